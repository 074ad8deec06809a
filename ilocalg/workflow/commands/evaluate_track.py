"""``python -m ilocalg evaluate track --trace PATH --fingerprints PATH... --json``: PDR + Wi-Fi on one walk.

Scores one Indoor Location Competition 2.0 walk (``--trace``) with a Wi-Fi fingerprint database,
step-length factor, compass-to-map heading offset and fix variance learned from *other* walks
(``--fingerprints``, never the scored one: giving it raises). A PATH is either an ILC trace file
(``*.txt``, your own recordings in the ILC format) or a trace id inside ``--floor`` (the floor's
folder or ``.tar.xz`` archive; default: the shared ``ilc2020_site2_F4`` data set).
``--fingerprints all`` takes every trace of ``--floor`` except the scored one.

Prints one JSON object (a public contract)::

    {"trace": id, "n_waypoints": n, "errors_m": {"pdr": [...], "wifi": [...], "kf": [...],
     "kf_rts": [...], ...}, "mean_m": {"pdr": ..., ...}, "info": {...}}

``errors_m`` lists the error (metres) at every waypoint of the trace, in waypoint order, per method:
``pdr`` (dead reckoning from the first Wi-Fi fix), ``wifi`` (latest fix), ``kf``, ``kf_rts`` (the step
Kalman filter and its RTS smoothing), ``aligned``, ``aligned_rot``, ``aligned_kf_rts`` (the track fitted
onto the walk's fixes) and, when a floor map is available (``--map``, default ``--floor`` when it
holds ``geojson_map.json``), ``pf``, ``pf_smooth`` (map-constrained particle filter) and
``map_align``, ``map_align_kf_rts`` (whole-walk map matching). The waypoints are used for the errors only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

NAME = "track"
HELP = "PDR, Wi-Fi, KF, KF+RTS (and map-constrained variants) on one ILC walk, errors at its waypoints"

MAP_METHODS = ("pf", "pf_smooth", "map_align", "map_align_kf_rts")


def add_arguments(parser) -> None:
    parser.add_argument("--trace", required=True, metavar="PATH", help="the walk to score: ILC trace file or trace id")
    parser.add_argument("--fingerprints", required=True, nargs="+", metavar="PATH",
                        help="walks that build the fingerprint database (trace files or ids; 'all' = every other "
                             "trace of --floor)")
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


def _load(paths, floor):
    """Traces for PATHs: files are read directly, the rest are ids inside ``floor`` (one archive pass)."""
    from ilocalg.io.ilc import load_ilc_floor, load_ilc_trace, require_walk

    out, ids = {}, []
    for p in paths:
        if Path(p).is_file():
            out[p] = load_ilc_trace(p, duplicate_bssid="keep_latest")
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
    return {k: require_walk(v) for k, v in out.items()}


def run(args) -> dict:
    from ilocalg.io.ilc import load_ilc_floor_map
    from ilocalg.track import METHODS, RealWalkConfig, evaluate_track

    floor = Path(args.floor) if args.floor else _default_floor()
    if args.particles < 10:
        raise ValueError(f"--particles must be >= 10, got {args.particles}")
    fp_paths = list(args.fingerprints)
    trace = _load([args.trace], floor)[args.trace]
    if fp_paths == ["all"]:
        if not floor.exists():
            raise ValueError(f"--fingerprints all needs an existing --floor, got {floor}")
        fp_paths = [i for i in _ids_in(floor) if i != trace.name]
    if args.trace in fp_paths or any(Path(p).stem == trace.name for p in fp_paths):
        raise ValueError(f"--fingerprints must not contain the scored trace {trace.name!r} (leave-one-walk-out)")
    db = _load(fp_paths, floor)
    fmap = None
    if not args.no_map:
        mp = Path(args.map) if args.map else floor
        if args.map and not mp.exists():
            raise ValueError(f"--map {mp}: no such folder or archive")
        if mp.exists():
            fmap = load_ilc_floor_map(mp)
    methods = tuple(m for m in METHODS if fmap is not None or m not in MAP_METHODS)
    cfg = RealWalkConfig(n_particles=args.particles)
    r = evaluate_track(trace, db, floor_map=fmap, cfg=cfg, rng=args.seed, methods=methods)
    e = r["errors"]
    info = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in r["info"].items()}
    return {
        "trace": trace.name,
        "n_waypoints": int(len(e)),
        "n_fingerprint_walks": len(db),
        "errors_m": {m: [float(x) for x in e[m]] for m in methods},
        "mean_m": {m: float(e[m].mean()) for m in methods},
        "info": info,
    }
