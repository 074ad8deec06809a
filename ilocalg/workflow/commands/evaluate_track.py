"""``python -m ilocalg evaluate track --trace PATH --fingerprints PATH... [--format auto|ilc|ipin] [--json]``.

Scores one walk (``--trace``) with a Wi-Fi fingerprint database, step-length factor, compass-to-map
heading offset and fix variance learned from *other* walks (``--fingerprints``, never the scored
one: giving it, under its name or another one with the same sensor content, raises). A PATH is a
walk file, an Indoor Location Competition 2.0 trace (``*.txt``) or an IPIN competition logfile,
the format taken from the content (``--format auto``) or given; or, for ILC, a trace id inside
``--floor`` (the floor's folder or ``.tar.xz`` archive; default: the shared ``ilc2020_site2_F4``
data set). ``--fingerprints all`` takes every trace of ``--floor`` except the scored one. IPIN
logfiles are pooled in one local frame through their latitude/longitude (see
:mod:`ilocalg.io.recording`).

Prints a summary table (one row per method: mean, median, 75th percentile of the error) and, with
``--json``, one JSON object instead (a public contract)::

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
``n_scans_no_shared_ap`` (hearing no access point of the database). Added keys (the old ones are
unchanged): ``lsq``, ``lsq_online`` (least squares, offline and online) and, with a map, ``lsq_map``,
``lsq_online_map``; ``warning`` when every method's mean error exceeds 20 m.

With ``--fingerprints all`` the floor's database and calibration rows are built once and saved in
``--cache-dir`` (:func:`ilocalg.track.cached_floor_model`); later walks of the same floor read them and
leave the scored walk out (:meth:`ilocalg.track.FloorModel.for_walk`). ``--floor-name`` picks one floor
of an archive holding several (``site1_F1`` in ``site1_F1_F2.tar.xz``). A walk sharing no access
point with the database, or in another floor's map frame, is refused naming its file; so is a
fingerprint file with the scored walk's sensor content under another name.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

NAME = "track"
HELP = "PDR, Wi-Fi, KF, KF+RTS, least squares (and map-constrained variants) on one ILC or IPIN walk"

from ilocalg.track._config import MAP_METHODS  # noqa: E402  (light: no heavy imports)

#: What each method key means (the --help text and the table's last column).
METHOD_HELP = {
    "pdr": "online: dead reckoning (steps x heading) from the first Wi-Fi fix",
    "wifi": "online: the latest Wi-Fi fix (WKNN on the fingerprint walks)",
    "kf": "online: step Kalman filter of PDR and Wi-Fi (Chiu 2013 eq. 20-26)",
    "kf_rts": "offline: kf smoothed backwards (Rauch-Tung-Striebel)",
    "aligned": "offline: the PDR track translated onto all fixes (Huber)",
    "aligned_rot": "offline: aligned, with a rotation fitted too",
    "aligned_kf_rts": "offline: kf_rts started at the aligned start",
    "pf": "online: particle filter inside the walkable map",
    "pf_smooth": "offline: the particle filter's ancestral paths",
    "map_align": "offline: whole-walk placement of the PDR track on the map",
    "map_align_kf_rts": "offline: kf_rts from the map_align placement",
    "lsq": "offline: one sparse least-squares system of fixes and steps",
    "lsq_map": "offline: lsq pulled onto the walkable map",
    "lsq_online": "online: lsq on the data so far",
    "lsq_online_map": "online: lsq_online moved onto the walkable map",
    "kf_gain": "online: Kalman filter with the walk's step scale and heading offset in its state",
    "kf_gain_map": "online: kf_gain moved onto the walkable map",
    "kf_gain_lag5s": "offline (5 s behind): kf_gain smoothed over a fixed 5 s lag",
    "kf_gain_map_lag5s": "offline (5 s behind): kf_gain_lag5s moved onto the walkable map",
    "kf_gain_map_start5s": "online after a delayed start: kf_gain_map, the states until 5 s after the first "
                           "fix smoothed then",
    "lsq_online_map_start5s": "online after a delayed start: lsq_online_map, the states until 5 s after the "
                              "first fix solved then",
    "lsq_paths": "offline: lsq pulled towards the database walks' paths (their waypoint segments)",
    "lsq_grid": "offline, at the waypoint times: lsq moved onto the database walks' waypoints (HMM)",
    "map_align_grid": "offline, at the waypoint times: map_align moved onto the database walks' waypoints",
    "lsq_online_map_grid": "online, at the waypoint times: lsq_online_map moved onto the database walks' waypoints",
    "kf_gain_map_grid": "online, at the waypoint times: kf_gain_map moved onto the database walks' waypoints",
}
#: Every method's mean error above this (m) prints a warning: the walk is probably not of this floor.
FAR_OFF_M = 20.0

EPILOG = ("methods (the table's rows, the keys of errors_m in --json):\n"
          + "\n".join(f"  {k:<17}{v}" for k, v in METHOD_HELP.items())
          + "\n\nexamples:\n"
          "  python -m ilocalg evaluate track --floor DATA/ilc2020_site1 --floor-name site1_F1 \\\n"
          "      --trace 5dd9e7aac5b77e0006b1732b --fingerprints all          # table; database cached\n"
          "  ... --json > result.json                                        # the JSON contract\n"
          "  ... --out-track track.csv --plot track.png                      # the track and a plan figure\n"
          "  python -m ilocalg evaluate track --format ipin --trace walk1.txt --fingerprints walk2.txt walk3.txt")


def add_arguments(parser) -> None:
    parser.add_argument("--trace", required=True, metavar="PATH", help="the walk to score: ILC trace file or trace id")
    parser.add_argument("--fingerprints", required=True, nargs="+", metavar="PATH",
                        help="walks that build the fingerprint database (trace files or ids; 'all' = every other "
                             "trace of --floor)")
    parser.add_argument("--format", default="auto", choices=("auto", "ilc", "ipin"),
                        help="walk file format (default: from the content)")
    parser.add_argument("--floor", default=None, metavar="PATH",
                        help="ILC floor folder or archive holding the trace ids (default: the shared ilc2020_site2_F4)")
    parser.add_argument("--floor-name", default=None, metavar="NAME",
                        help="the floor folder inside an archive holding several floors (e.g. site1_F1 in "
                             "site1_F1_F2.tar.xz)")
    parser.add_argument("--map", default=None, metavar="PATH",
                        help="floor folder or archive with floor_info.json and geojson_map.json (default: --floor)")
    parser.add_argument("--no-map", action="store_true", help="skip the map-constrained variants")
    parser.add_argument("--particles", type=int, default=1000, help="particle-filter size (default 1000)")
    parser.add_argument("--seed", type=int, default=0, help="particle-filter seed (default 0)")
    parser.add_argument("--out-track", default=None, metavar="CSV",
                        help="write every method's track (t_s, method, x_m, y_m, floor) to this CSV file")
    parser.add_argument("--plot", default=None, metavar="PNG",
                        help="draw the tracks on the floor plan (floor_image.png of --floor) into this image")
    parser.add_argument("--cache-dir", default=None, metavar="DIR",
                        help="where the floor's database is saved once built (default: ~/.cache/ilocalg/floors; "
                             "'none': do not cache)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter


def _default_floor() -> Path:
    from ilocalg.io.paths import data_dir

    return data_dir() / "ilc2020_site2_F4"


def _ids_in(floor, floor_name=None) -> list[str]:
    from ilocalg.io.ilc import list_ilc_traces

    return list_ilc_traces(floor, floor_name=floor_name)


POLICY = {"duplicate_bssid": "keep_latest", "relisted_wifi": "keep"}


def _load(paths, floor, fmt="auto", floor_name=None):
    """Walks for PATHs: files are read directly (format ``fmt`` or from the content), the rest are ILC
    trace ids inside ``floor`` (one archive pass)."""
    from ilocalg.io.ilc import IlcTrace, load_ilc_floor, load_ilc_trace, require_walk
    from ilocalg.io.recording import load_recording, require_recording_walk, sniff_format

    out, ids = {}, []
    for p in paths:
        if Path(p).is_file():
            f = sniff_format(p) if fmt == "auto" else fmt
            if f == "ilc":
                out[p] = load_ilc_trace(p, **POLICY)
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
        known = set(_ids_in(floor, floor_name))
        missing = [i for i in ids if i not in known]
        if missing:
            raise ValueError(f"trace {missing[0]!r} is neither a file nor a trace id in {floor}")
        fl = load_ilc_floor(floor, names=ids, floor_name=floor_name, **POLICY)
        for i in ids:
            out[i] = fl.traces[i]
    return {k: require_walk(v) if isinstance(v, IlcTrace) else require_recording_walk(v) for k, v in out.items()}


class _Stages:
    """A one-line progress bar over the command's stages (stderr, on a terminal only; off with --quiet): an
    error then stays the one line the command prints."""

    def __init__(self, quiet: bool, n: int):
        from tqdm import tqdm

        self.bar = tqdm(total=n, disable=True if quiet else None, file=sys.stderr,
                        bar_format="{desc:<38}{bar:20}| {elapsed}", leave=False)

    def __call__(self, desc: str):
        self.bar.set_description_str(desc)
        self.bar.update(1)

    def close(self):
        self.bar.close()


def _cache_dir(arg):
    if arg == "none":
        return None
    return Path(arg) if arg else Path.home() / ".cache" / "ilocalg" / "floors"


def run(args) -> dict:
    from ilocalg.io.ilc import load_ilc_floor_map
    from ilocalg.io.recording import as_recording
    from ilocalg.track import METHODS, RealWalkConfig, evaluate_track, evaluate_walk
    from ilocalg.track.floor import cached_floor_model

    floor = Path(args.floor) if args.floor else _default_floor()
    if args.particles < 10:
        raise ValueError(f"--particles must be >= 10, got {args.particles}")
    st = _Stages(getattr(args, "quiet", False), 5)
    try:
        return _run(args, floor, st, load_ilc_floor_map, as_recording, METHODS, RealWalkConfig, evaluate_track,
                    evaluate_walk, cached_floor_model)
    finally:
        st.close()


def _run(args, floor, st, load_ilc_floor_map, as_recording, METHODS, RealWalkConfig, evaluate_track, evaluate_walk,
         cached_floor_model):
    from ilocalg.fusion.particle_filter import OccupancyGrid

    st("loading the scored walk")
    fp_paths = list(args.fingerprints)
    fn = getattr(args, "floor_name", None)
    trace = _load([args.trace], floor, args.format, fn)[args.trace]
    use_floor_model = fp_paths == ["all"]
    if use_floor_model:
        if not floor.exists():
            raise ValueError(f"--fingerprints all needs an existing --floor, got {floor}")
        fp_paths = [i for i in _ids_in(floor, fn) if i != trace.name]
    if args.trace in fp_paths:
        raise ValueError(f"--fingerprints must not contain the scored trace {args.trace!r} (leave-one-walk-out)")
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
            fmap = load_ilc_floor_map(mp, floor_name=fn)
    methods = tuple(m for m in METHODS if fmap is not None or m not in MAP_METHODS)
    cfg = RealWalkConfig(n_particles=args.particles)
    rec = as_recording(trace)
    if use_floor_model:
        st("building or reading the floor database")
        files = [floor] if floor.is_file() else sorted((floor / "path_data_files").glob("*.txt")) or [floor]
        model, cached = cached_floor_model(files, lambda: _load(_ids_in(floor, fn), floor, args.format, fn),
                                           _cache_dir(args.cache_dir) or Path(_tmp_cache()), cfg, floor_name=fn,
                                           **POLICY)
        wm = model.for_walk(trace.name, cfg, content_id=rec.content_id)
        if wm.gain is None:                     # too few walks with waypoints to measure the gain spread
            from ilocalg.track._config import GAIN_METHODS

            methods = tuple(m for m in methods if m not in GAIN_METHODS)
        _check_same_site(rec, wm.db, args.trace)
        st("tracking the walk")
        grid = None if fmap is None else OccupancyGrid.from_floor_map(fmap, cfg.grid_cell_m)
        from ilocalg.track._config import GRID_METHODS

        # the marked points of the grid variants: the other walks' waypoints, kept with the floor model
        survey = None if model.walk_paths is None else model.walk_paths.without(trace.name)
        if survey is None or not len(survey.walk):
            methods = tuple(m for m in methods if m not in GRID_METHODS)
        r = evaluate_walk(rec, wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, grid=grid, rng=args.seed,
                          methods=methods, step_var_m2=wm.step_var_m2, gain=wm.gain, loo_fixes=wm.loo_fixes,
                          path_var_m2=wm.path_var_m2, survey=survey)
        r["info"]["wifi_config"] = wm.wifi_config
        r["info"]["database_from_cache"] = cached
        n_db = len(model.walks) - (trace.name in set(model.walks))
    else:
        st("loading the fingerprint walks")
        db = _load(fp_paths, floor, args.format, fn)
        for p, w in db.items():
            if as_recording(w).content_id == rec.content_id and len(rec.imu):
                raise ValueError(f"--fingerprints {p}: same sensor content as the scored walk {args.trace} (a copy "
                                 "under another name); leave it out (leave-one-walk-out)")
        st("building the database, tracking the walk")
        r = evaluate_track(trace, db, floor_map=fmap, cfg=cfg, rng=args.seed, methods=methods)
        n_db = len(db)
    st("scoring")
    e = r["errors"]
    info = {**r["info"], "n_scans_outside_walk": r["scans"]["n_scans_outside_walk"],
            "n_scans_no_shared_ap": r["scans"]["n_scans_no_shared_ap"]}
    info = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in info.items()}
    out = {
        "trace": trace.name,
        "n_waypoints": int(len(e)),
        "n_fingerprint_walks": n_db,
        "errors_m": {m: [float(x) for x in e[m]] for m in methods},
        "mean_m": {m: float(e[m].mean()) for m in methods},
        "info": info,
    }
    fl = r["floors"]
    if fl is not None and np.isfinite(fl["floor_true"].to_numpy()).all():
        out["floor_hit_rate"] = {m: float(np.mean(fl[m].to_numpy() == fl["floor_true"].to_numpy())) for m in methods}
        info["floor_source"] = r["scans"]["floor_source"]
    if min(out["mean_m"].values()) > FAR_OFF_M:
        out["warning"] = (f"every method is more than {FAR_OFF_M:.0f} m off on average (best "
                          f"{min(out['mean_m'].values()):.1f} m): is {args.trace} from this floor, and do the "
                          "fingerprint walks cover where it went?")
        print(f"warning: {out['warning']}", file=sys.stderr)
    if args.out_track:
        r["track"].to_csv(args.out_track, index=False, float_format="%.3f")
    if args.plot:
        _plot(args.plot, r, floor, rec, fn)
    return out


def _tmp_cache():
    import tempfile

    return Path(tempfile.gettempdir()) / "ilocalg-floors"


def _check_same_site(rec, db, path):
    """A walk sharing no access point with the database, or in another map frame, is from elsewhere."""
    if db.frame is not None and getattr(rec, "frame", None) is not None and rec.frame.name != db.frame.name \
            and not (rec.frame.geographic and db.frame.geographic):
        raise ValueError(f"{path}: its positions are in the map frame {rec.frame.name!r}, the fingerprint walks in "
                         f"{db.frame.name!r}: a walk of another floor or site")
    heard = set(rec.wifi["bssid"].astype(str)) if len(rec.wifi) else set()
    if not heard & set(db.ap_ids):
        raise ValueError(f"{path}: hears none of the {len(db.ap_ids)} access points of the fingerprint walks: a walk "
                         "of another floor or site")


def _plot(path, r, floor, rec, floor_name=None):
    """Tracks on the floor plan: ilocviz draws (imported only for --plot; ilocalg itself never draws)."""
    from ilocalg.io.ilc import _read_members, _resolve_root, load_ilc_floor_map
    from ilocviz.track import save_tracks_on_plan

    png = None
    root = _resolve_root(floor)
    if root.is_dir() and (root / "floor_image.png").is_file():
        png = (root / "floor_image.png").read_bytes()
    elif root.is_file():
        m = _read_members(root, lambda n: n.endswith("floor_image.png") and (floor_name is None or
                                                                            f"/{floor_name}/" in "/" + n))
        if len(m) == 1:
            png = next(iter(m.values()))
    fm = load_ilc_floor_map(floor, floor_name=floor_name)
    save_tracks_on_plan(path, r["track"], rec.truth[["x_m", "y_m"]].to_numpy(), png, (fm.width_m, fm.height_m),
                        title=f"{rec.name}: tracks on the floor plan")


def format_text(out: dict) -> str:
    """The default output: one row per method (mean, median, p75 of the error, metres) and its meaning."""
    rows = []
    for m, e in out["errors_m"].items():
        a = np.asarray(e, dtype=np.float64)
        rows.append((m, float(np.mean(a)), float(np.median(a)), float(np.quantile(a, 0.75)), METHOD_HELP.get(m, "")))
    rows.sort(key=lambda r: r[1])
    head = (f"walk {out['trace']}: {out['n_waypoints']} waypoints, {out['n_fingerprint_walks']} fingerprint walks "
            f"(Wi-Fi: {out['info'].get('wifi_config', '')})")
    lines = [head, f"{'method':<16}{'mean m':>8}{'median':>8}{'p75':>8}  what it is"]
    lines += [f"{m:<16}{a:>8.2f}{b:>8.2f}{c:>8.2f}  {h}" for m, a, b, c, h in rows]
    if "warning" in out:
        lines.append(f"warning: {out['warning']}")
    return "\n".join(lines)
