"""``python -m ilocalg evaluate track --trace PATH --fingerprints PATH... [--format auto|ilc|ipin] --json``.

Scores one walk (``--trace``) with a Wi-Fi fingerprint database, step-length factor, compass-to-map
heading offset and fix variance learned from *other* walks (``--fingerprints``, never the scored
one: giving it, under its name or another one with the same sensor content, raises). A PATH is a
walk file, an Indoor Location Competition 2.0 trace (``*.txt``) or an IPIN competition logfile,
the format taken from the content (``--format auto``) or given; or, for ILC, a trace id inside
``--floor`` (the floor's folder or ``.tar.xz`` archive; default: the shared ``ilc2020_site2_F4``
data set). ``--fingerprints all`` takes every trace of ``--floor`` except the scored one. IPIN
logfiles are pooled in one local frame through their latitude/longitude (see
:mod:`ilocalg.io.recording`).

Prints one JSON object (a public contract)::

    {"trace": id, "n_waypoints": n, "errors_m": {"pdr": [...], "wifi": [...], "kf": [...],
     "kf_rts": [...], ...}, "mean_m": {"pdr": ..., ...}, "info": {...}}

``errors_m`` lists the error (metres) at every waypoint of the trace, in waypoint order, per method:
``pdr`` (dead reckoning from the first Wi-Fi fix), ``wifi`` (latest fix), ``kf``, ``kf_rts`` (the step
Kalman filter and its RTS smoothing), ``aligned``, ``aligned_rot``, ``aligned_kf_rts`` (the track fitted
onto the walk's fixes) and, when a floor map is available (``--map``, default ``--floor`` when it
holds ``geojson_map.json``), ``pf``, ``pf_smooth`` (map-constrained particle filter) and
``map_align``, ``map_align_kf_rts`` (whole-walk map matching). The waypoints are used for the errors only.
When the walks have floor numbers (IPIN logfiles), ``floor_hit_rate`` gives per method the fraction of
ground-truth points whose estimated floor is right (see :func:`ilocalg.track.estimate_floors`).
``info`` counts the scans left out: ``n_scans_outside_walk`` (outside the walk's IMU time span) and
``n_scans_no_shared_ap`` (hearing no access point of the database).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

NAME = "track"
HELP = "PDR, Wi-Fi, KF, KF+RTS (and map-constrained variants) on one ILC or IPIN walk, errors at its ground truth"

MAP_METHODS = ("pf", "pf_smooth", "map_align", "map_align_kf_rts")


def add_arguments(parser) -> None:
    parser.add_argument("--trace", required=True, metavar="PATH", help="the walk to score: ILC trace file or trace id")
    parser.add_argument("--fingerprints", required=True, nargs="+", metavar="PATH",
                        help="walks that build the fingerprint database (trace files or ids; 'all' = every other "
                             "trace of --floor)")
    parser.add_argument("--format", default="auto", choices=("auto", "ilc", "ipin"),
                        help="walk file format (default: from the content)")
    parser.add_argument("--floor", default=None, metavar="PATH",
                        help="ILC floor folder or archive holding the trace ids (default: the shared ilc2020_site2_F4)")
    parser.add_argument("--map", default=None, metavar="PATH",
                        help="floor folder or archive with floor_info.json and geojson_map.json (default: --floor)")
    parser.add_argument("--no-map", action="store_true", help="skip the map-constrained variants")
    parser.add_argument("--particles", type=int, default=1000, help="particle-filter size (default 1000)")
    parser.add_argument("--seed", type=int, default=0, help="particle-filter seed (default 0)")


def _default_floor() -> Path:
    from ilocalg.io.paths import data_dir

    return data_dir() / "ilc2020_site2_F4"


def _ids_in(floor) -> list[str]:
    from ilocalg.io.ilc import list_ilc_traces

    return list_ilc_traces(floor)


def _load(paths, floor, fmt="auto"):
    """Walks for PATHs: files are read directly (format ``fmt`` or from the content), the rest are ILC
    trace ids inside ``floor`` (one archive pass)."""
    from ilocalg.io.ilc import IlcTrace, load_ilc_floor, load_ilc_trace, require_walk
    from ilocalg.io.recording import load_recording, require_recording_walk, sniff_format

    out, ids = {}, []
    for p in paths:
        if Path(p).is_file():
            f = sniff_format(p) if fmt == "auto" else fmt
            if f == "ilc":
                out[p] = load_ilc_trace(p, duplicate_bssid="keep_latest")
            elif f == "ipin":
                out[p] = load_recording(p, format="ipin")
            else:
                raise ValueError(f"{p}: {f} recordings have no Wi-Fi or positions; evaluate track takes ILC traces "
                                 "and IPIN logfiles")
        else:
            ids.append(p)
    if ids:
        if floor is None or not Path(floor).exists():
            raise ValueError(f"{ids[0]!r} is neither a trace file nor a trace id of an existing --floor ({floor})")
        known = set(_ids_in(floor))
        missing = [i for i in ids if i not in known]
        if missing:
            raise ValueError(f"trace {missing[0]!r} is neither a file nor a trace id in {floor}")
        fl = load_ilc_floor(floor, names=ids, duplicate_bssid="keep_latest")
        for i in ids:
            out[i] = fl.traces[i]
    return {k: require_walk(v) if isinstance(v, IlcTrace) else require_recording_walk(v) for k, v in out.items()}


def run(args) -> dict:
    from ilocalg.io.ilc import load_ilc_floor_map
    from ilocalg.track import METHODS, RealWalkConfig, evaluate_track

    floor = Path(args.floor) if args.floor else _default_floor()
    if args.particles < 10:
        raise ValueError(f"--particles must be >= 10, got {args.particles}")
    fp_paths = list(args.fingerprints)
    trace = _load([args.trace], floor, args.format)[args.trace]
    if fp_paths == ["all"]:
        if not floor.exists():
            raise ValueError(f"--fingerprints all needs an existing --floor, got {floor}")
        fp_paths = [i for i in _ids_in(floor) if i != trace.name]
    if args.trace in fp_paths or any(Path(p).stem == trace.name for p in fp_paths):
        raise ValueError(f"--fingerprints must not contain the scored trace {trace.name!r} (leave-one-walk-out)")
    db = _load(fp_paths, floor, args.format)
    fmap = None
    geo = getattr(trace, "frame", None) is not None and trace.frame.geographic
    if geo and args.map:
        raise ValueError(f"--map {args.map}: an ILC floor map is in its own map frame; the walks are in a geographic "
                         "frame (latitude/longitude), pass --no-map")
    if not args.no_map and not geo:
        mp = Path(args.map) if args.map else floor
        if args.map and not mp.exists():
            raise ValueError(f"--map {mp}: no such folder or archive")
        if mp.exists():
            fmap = load_ilc_floor_map(mp)
    methods = tuple(m for m in METHODS if fmap is not None or m not in MAP_METHODS)
    cfg = RealWalkConfig(n_particles=args.particles)
    r = evaluate_track(trace, db, floor_map=fmap, cfg=cfg, rng=args.seed, methods=methods)
    e = r["errors"]
    info = {**r["info"], "n_scans_outside_walk": r["scans"]["n_scans_outside_walk"],
            "n_scans_no_shared_ap": r["scans"]["n_scans_no_shared_ap"]}
    info = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in info.items()}
    out = {
        "trace": trace.name,
        "n_waypoints": int(len(e)),
        "n_fingerprint_walks": len(db),
        "errors_m": {m: [float(x) for x in e[m]] for m in methods},
        "mean_m": {m: float(e[m].mean()) for m in methods},
        "info": info,
    }
    fl = r["floors"]
    if fl is not None and np.isfinite(fl["floor_true"].to_numpy()).all():
        out["floor_hit_rate"] = {m: float(np.mean(fl[m].to_numpy() == fl["floor_true"].to_numpy())) for m in methods}
        info["floor_source"] = r["scans"]["floor_source"]
    return out
