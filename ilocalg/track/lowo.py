"""Leave-one-walk-out over a floor's walks: pooling the scored waypoints, the Wi-Fi ablation, the floor's files.

A floor's leave-one-walk-out (each walk tracked with everything learned from the *other* walks,
:meth:`ilocalg.track.FloorModel.for_walk` and :func:`ilocalg.track.evaluate_walk`) is scored waypoint
by waypoint; split into shards, a sweep's long ``sweep_waypoints`` rows (``quantity`` = method, ``value``
= error in metres, ``item`` = ``"<floor>/<walk>#<waypoint>"``) are pooled per floor and over all floors
by :func:`sweep_summary`, and :func:`lowo_findings` states the result in sentences.
:func:`wifi_ablation` scores each Wi-Fi configuration of :data:`ilocalg.track.WIFI_CANDIDATES` on the
floor's database scans (each walk against the others). :func:`floor_files` (the floor model's cache key)
and :func:`floor_image` find a data set's floor in the data folder, :func:`load_floor` reads it (once per
process): ``dataset`` is a data set folder (``"ilc2020_site2_F4"``) or ``"folder/floor"`` for one floor of a
several-floor archive. :data:`PLAIN_WKNN` is the plain Wi-Fi reference of the real-walk experiments.

References
----------
Indoor Location Competition 2.0 sample data (Microsoft Research / XYZ10, 2020); the EvAAL p75 error:
Torres-Sospedra J. et al., Sensors 18(2) (2018).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import ArchiveReader
from ilocalg.io.ilc import _read_members, _resolve_root, load_ilc_floor
from ilocalg.io.paths import data_dir as default_data_dir
from ilocalg.io.scans import merge_relisted_wifi
from ilocalg.track._config import CAUSAL_METHODS, GRID_METHODS, LATENCY_METHODS, METHODS, RealWalkConfig, latency_of
from ilocalg.track.database import WifiDatabase
from ilocalg.track.fixes import WIFI_CANDIDATES, loo_fix_features_shared

__all__ = ["sweep_summary", "lowo_findings", "wifi_ablation", "floor_files", "floor_image", "load_floor",
           "DATASET", "PLAIN_WKNN"]


#: The real-walk experiments' default floor (site 2's fourth floor, 19 walks).
DATASET = "ilc2020_site2_F4"
#: The plain Wi-Fi reference the Wi-Fi-only row must be at least as accurate as (issue 26).
PLAIN_WKNN = {"k_neighbors": 5, "p": 2, "weights": "distance", "max_age_s": 2.0, "metric": "minkowski"}


def load_floor(data_dir=None, dataset: str = DATASET, relisted_wifi: str = "keep", names=None):
    """A floor (traces and map) from ``data_dir`` (None: the toolkit's data folder). ``dataset`` is a data
    set folder (``"ilc2020_site2_F4"``) or ``"folder/floor"`` for one floor of a several-floor archive
    (``"ilc2020_site1/site1_F1"``); ``relisted_wifi``: the loader's re-listing policy
    (:func:`ilocalg.io.scans.relisted_readings`); ``names``: only these walks (None: every walk), or the whole
    floor when it is already read.

    Read once per process for the same files (their paths, sizes and modification times), policy and walks: a
    notebook's own run and its leave-one-walk-out share one reading (a site 1 floor takes about 10 CPU-s).
    The floor returned is shared, so treat it as read-only (the experiment only reads it).
    """
    p = Path(default_data_dir() if data_dir is None else data_dir)
    folder, _, floor_name = dataset.partition("/")
    if (p / folder).exists():
        p = p / folder
    files = floor_files(data_dir, dataset)
    stamp = tuple((str(f.resolve()), f.stat().st_size, f.stat().st_mtime_ns) for f in files if f.exists())
    key = (str(p), floor_name or None, relisted_wifi, stamp)
    if names is not None:
        names = tuple(sorted(set(names)))
        if (*key, None) in _FLOORS:
            names = None                                # the whole floor is read already: it holds them
    key = (*key, names)
    fl = _FLOORS.pop(key, None)
    if fl is None:
        fl = load_ilc_floor(Path(key[0]), names=names, duplicate_bssid="keep_latest", relisted_wifi=relisted_wifi,
                            floor_name=key[1])
        while len(_FLOORS) >= 2:
            _FLOORS.pop(next(iter(_FLOORS)))
    _FLOORS[key] = fl                                   # the most recently used, kept longest
    return fl


#: The floors :func:`load_floor` read last in this process ((folder, floor, policy, file stamps, walks or None) ->
#: floor), least recently used first; two, as a notebook's floor and the other floor of its leave-one-walk-out.
_FLOORS: dict = {}


def sweep_summary(results: pd.DataFrame) -> dict[str, pd.DataFrame]:
    """Pool the ``sweep_waypoints`` rows of a sweep of the real-walk experiment's ``run``
    (``fusion_real_walks``; any shards, floors, sites).

    Returns ``summary``: one row per floor and method plus the ``pooled`` rows (every waypoint of every
    floor): ``n_waypoints, n_walks, mean_m, median_m, p75_m`` (EvAAL), ``ratio_to_wifi`` (mean over
    Wi-Fi only's mean), ``online``, ``latency`` (``none``, a :data:`LATENCY_METHODS` text, or ``whole walk``),
    ``goal`` (0.5 offline, 0.7 online, with or without a declared latency), ``meets_goal``; and ``waypoints``
    (``floor, walk, waypoint`` and one error column per method).
    """
    r = results[results["table"] == "sweep_waypoints"]
    if r.empty:
        raise ValueError("no sweep_waypoints rows: not a sweep of fusion_real_walks.run")
    item = r["item"].str.rsplit("#", n=1, expand=True)
    fw = item[0].str.rsplit("/", n=1, expand=True)
    long = pd.DataFrame({"floor": fw[0].to_numpy(), "walk": fw[1].to_numpy(),
                         "waypoint": item[1].astype(int).to_numpy(), "method": r["quantity"].to_numpy(),
                         "error_m": r["value"].to_numpy()})
    wide = long.pivot_table(index=["floor", "walk", "waypoint"], columns="method", values="error_m",
                            aggfunc="first").reset_index()
    wide.columns.name = None
    methods = [m for m in (*METHODS, "wifi_plain_knn") if m in wide.columns]
    rows = []
    for fl_name, g in [*wide.groupby("floor", sort=True), ("pooled", wide)]:
        w = float(g["wifi"].mean())
        for m in methods:
            e = g[m].to_numpy(dtype=np.float64)
            online = m in CAUSAL_METHODS or m == "wifi_plain_knn"
            goal = 0.7 if online or m in LATENCY_METHODS else 0.5     # a declared latency: judged as online
            ratio = float(np.mean(e)) / w
            rows.append({"floor": fl_name, "method": m, "online": online,
                         "latency": "none" if online else latency_of(m),
                         "n_waypoints": int(e.size),
                         "n_walks": int(g["walk"].nunique()), "mean_m": float(np.mean(e)),
                         "median_m": float(np.median(e)), "p75_m": float(np.quantile(e, 0.75)),
                         "ratio_to_wifi": ratio, "goal": goal if m not in ("wifi", "wifi_plain_knn") else np.nan,
                         "meets_goal": bool(ratio <= goal) if m not in ("wifi", "wifi_plain_knn") else None})
    return {"summary": pd.DataFrame(rows), "waypoints": wide}


def lowo_findings(summary: pd.DataFrame) -> str:
    """Sentences computed from :func:`sweep_summary`'s table: per floor and pooled, Wi-Fi only against the
    plain reference, the best offline and online estimators and their ratios to Wi-Fi only."""
    out = []
    for fl_name, g in summary.groupby("floor", sort=False):
        g = g.set_index("method")
        w, pk = g.loc["wifi"], g.loc["wifi_plain_knn"] if "wifi_plain_knn" in g.index else None
        s = (f"{fl_name}: {int(w['n_walks'])} walks, {int(w['n_waypoints'])} waypoints; Wi-Fi only mean "
             f"{w['mean_m']:.2f} m (p75 {w['p75_m']:.2f} m)")
        if pk is not None:
            s += (f", plain WKNN K = 5 <= 2 s {pk['mean_m']:.2f} m "
                  f"({'no worse' if w['mean_m'] <= pk['mean_m'] + 1e-9 else 'WORSE: the baseline is not fair'})")
        out.append(s + ".")
        lat = g.index.isin(list(LATENCY_METHODS))
        for label, sel in (("offline", ~g["online"] & ~lat), ("online", g["online"]),
                           ("online with a declared latency (not causal)", lat)):
            p = g[sel & ~g.index.isin(["wifi", "wifi_plain_knn"])]
            tracks_only = p[~p.index.isin(list(GRID_METHODS))]
            best = None
            for lab, q in ((label, p), (f"{label} track estimator (no query times, no marked points)", tracks_only)):
                if not len(q) or (q is tracks_only and q["mean_m"].idxmin() == best):
                    continue
                b = best = q["mean_m"].idxmin()
                r = q.loc[b]
                grid = " (at the query times, on the survey's marked points)" if b in GRID_METHODS else ""
                out.append(f"  best {lab}: {b}{grid}, mean {r['mean_m']:.2f} m, median {r['median_m']:.2f} m, p75 "
                           f"{r['p75_m']:.2f} m, {r['ratio_to_wifi']:.2f} x Wi-Fi only (goal <= {r['goal']} x: "
                           f"{'met' if r['meets_goal'] else 'missed'}).")
    return "\n".join(out)


def wifi_ablation(floor, cfg: RealWalkConfig | None = None, db: WifiDatabase | None = None) -> pd.DataFrame:
    """What each Wi-Fi piece buys: leave-one-walk-out fix error of every database scan (each walk located
    against the others) for every Wi-Fi configuration of :data:`ilocalg.track.WIFI_CANDIDATES` (the first
    one is the plain reference: WKNN, K = 5, readings older than 2 s dropped) with the re-listed readings
    kept and merged (:func:`ilocalg.io.scans.merge_relisted_wifi`, the loader's ``relisted_wifi`` rule).
    ``floor`` must be loaded with ``relisted_wifi="keep"``. ``db``: its database with the readings kept when
    already built from the same walks (``WifiDatabase.from_traces(floor.traces)``, e.g. the floor model's
    :attr:`~ilocalg.track.FloorModel.db`); None: built here. Columns: ``relisted_wifi, wifi_config, n, mean_m,
    median_m, p75_m, merged_readings``.
    """
    cfg = cfg or RealWalkConfig()
    rows = []
    for policy in ("keep", "merge"):
        n_merged = 0
        trs = {}
        for k, t in floor.traces.items():
            if policy == "merge":
                w, n = merge_relisted_wifi(t.wifi)
                n_merged += n
                t = dataclasses.replace(t, wifi=w)
            trs[k] = t
        db_p = db if policy == "keep" and db is not None else WifiDatabase.from_traces(trs)
        # every candidate's leave-one-walk-out fixes, one distance product per reading-age limit (the same fixes
        # as loo_fix_errors of each)
        loo = loo_fix_features_shared(db_p, [(None, dataclasses.replace(cfg, **kw))
                                             for kw in WIFI_CANDIDATES.values()])
        for label, (err, _) in zip(WIFI_CANDIDATES, loo, strict=True):
            e = np.hypot(*err.T)
            e = e[np.isfinite(e)]
            rows.append({"relisted_wifi": policy, "wifi_config": label, "n": int(e.size), "mean_m": float(e.mean()),
                         "median_m": float(np.median(e)), "p75_m": float(np.quantile(e, 0.75)),
                         "merged_readings": n_merged})
    return pd.DataFrame(rows)


def floor_image(data_dir, dataset: str) -> bytes | None:
    """The floor plan image (``floor_image.png``) of a data set's floor, or None when absent (``data_dir``
    None: the toolkit's data folder). In an archive: the first ``floor_image.png`` of the floor's folder for
    ``"folder/floor"`` (the archive is read only up to it), else the archive's one image (None when several)."""
    p = Path(default_data_dir() if data_dir is None else data_dir)
    folder, _, floor_name = dataset.partition("/")
    root = _resolve_root(p / folder if (p / folder).exists() else p)
    if root.is_dir():
        f = root / "floor_image.png"
        return f.read_bytes() if f.is_file() else None
    if floor_name:          # the floor folder's image: read up to it, not through the rest of the archive
        with ArchiveReader(root) as ar:
            for m in ar.tar:
                if m.isfile() and m.name.endswith("floor_image.png") and f"/{floor_name}/" in "/" + m.name:
                    ar.member = m.name
                    return ar.tar.extractfile(m).read()
        return None
    m = _read_members(root, lambda n: n.endswith("floor_image.png"))
    return next(iter(m.values())) if len(m) == 1 else None


def floor_files(data_dir, dataset: str) -> list[Path]:
    """The files a floor is read from (its archive, or its walk files): the floor model's cache key
    (:func:`ilocalg.track.cached_floor_model`); ``data_dir`` None: the toolkit's data folder."""
    p = Path(default_data_dir() if data_dir is None else data_dir)
    folder = dataset.partition("/")[0]
    root = _resolve_root(p / folder if (p / folder).exists() else p)
    return [root] if root.is_file() else sorted((root / "path_data_files").glob("*.txt"))
