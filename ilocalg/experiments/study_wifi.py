"""Study: Simplified-RADAR / Simplified-Horus / KNN error vs AP count k, training-point spacing, scans
per point and each radio parameter of the floor's test session (day-to-day drift, body shadowing,
device offset, path-loss exponent, heavy-wall loss), on the simulated i-Loc floor (extends i-Loc
thesis sec. 3, Figs 3 and 5).

One ``run(seed, ...)`` simulates the floor (:mod:`ilocalg.sim.iloc_floor`) with ``scans_per_point``
training scans per point and the radio parameters given (the rest at the defaults of
:data:`ilocalg.sim.iloc_floor.PARAMS`, each from a published measurement), thins the 2 m training
grid to ``spacing_m`` (:func:`thin_points`), builds the radio maps exactly as
:mod:`ilocalg.experiments.wifi_iloc` does (RADAR and Horus on every stored scan, thesis L283-287 and
Fig 4; KNN on the per-point mean fingerprints; estimators from
:func:`ilocalg.wifi.paper_estimators`) and scores the three methods on new scans at
the thesis' 28 test-route points. The test route stays the thesis' one, so with a coarser grid
some test points are no longer training points (which is what coarser surveys cost).

For a given seed the floor itself (APs, walls, shadowing) is the same whatever the parameters: the
simulator draws it before the scans, so the curves compare the same building.

Returns ``{"sweep_wifi": ...}``: quantities ``mean error``, ``median error``, ``80th-percentile
error`` (m) per ``method`` (in ``item``), ``training points`` (count) and ``test scans hearing no
AP (not scored)``: a test scan in which the simulated phone heard no AP at all (rare: fading and
missed detections) cannot be positioned by any of the methods, so it is left out of every method's
score and counted here. The swept values live in the task parameters ``k_aps``, ``spacing_m``,
``scans_per_point``.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 3, Figs 3 and 5.
"""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd

from ilocalg.metrics import horizontal_error_m, summary
from ilocalg.sim import iloc_floor
from ilocalg.wifi import paper_estimators
from ilocalg.wifi.preprocessing import mean_fingerprints
from ilocalg.workflow.studies import study_row, study_tasks

__all__ = ["run", "thin_points", "GRIDS", "tasks", "findings", "BASE"]

EXPERIMENT = "study_wifi"
STATS = (("mean error", "mean_m"), ("median error", "median_m"), ("80th-percentile error", "p80_m"))

#: Radio parameters of the floor swept here (defaults: :data:`ilocalg.sim.iloc_floor.PARAMS`).
RADIO = ("drift_sd_db", "body_loss_db", "device_offset_db", "path_loss_exponent", "heavy_wall_db")
_P = iloc_floor.PARAMS
#: The base point of the one-factor grids (the thesis' survey: k = 5, 2 m grid, 300 scans; fast: 60 scans;
#: the radio parameters at the simulator's published defaults).
BASE = {"k_aps": 5, "spacing_m": 2.0, "scans_per_point": 300, **{k: _P[k] for k in RADIO}}
BASE_FAST = {**BASE, "scans_per_point": 60}

#: One-factor grids: full and fast.
GRIDS = {
    False: {"k_aps": [1, 2, 3, 4, 5, 6, 8, 10, 14, 20],
            "spacing_m": [2.0, 4.0, 6.0, 8.0, 12.0],
            "scans_per_point": [2, 5, 10, 30, 100, 300],
            "drift_sd_db": [0.0, 1.5, 3.0, 4.5, 6.0],
            "body_loss_db": [0.0, 2.5, 5.0, 7.5, 10.0],
            "device_offset_db": [-10.0, -5.0, 0.0, 5.0, 10.0],
            "path_loss_exponent": [1.6, 2.0, 2.5, 3.0, 3.5],
            "heavy_wall_db": [3.4, 6.9, 10.0, 13.0]},
    True: {"k_aps": [1, 3, 5, 10],
           "spacing_m": [2.0, 6.0],
           "scans_per_point": [5, 60],
           "drift_sd_db": [0.0, 3.0, 6.0],
           "body_loss_db": [0.0, 5.0],
           "device_offset_db": [-10.0, 0.0],
           "path_loss_exponent": [2.0, 3.0],
           "heavy_wall_db": [3.4, 6.9]},
}


def thin_points(points_xy_m, spacing_m: float) -> np.ndarray:
    """Indices of a sub-grid of training points at least ``spacing_m`` apart (greedy, in survey order).

    Walking the points in the order the survey lists them (corridor by corridor), a point is kept
    when it is at least ``spacing_m`` (minus 1 mm) from every point kept so far. On the 2 m grid,
    4 m keeps every other point of a corridor, 6 m every third, and so on.

    Parameters
    ----------
    points_xy_m : array_like (n, 2)
    spacing_m : float, > 0

    Returns
    -------
    ndarray of int, sorted
    """
    pts = np.asarray(points_xy_m, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) == 0:
        raise ValueError(f"points_xy_m must have shape (n, 2) with n >= 1, got {pts.shape}")
    if not np.isfinite(spacing_m) or spacing_m <= 0:
        raise ValueError(f"spacing_m must be a positive distance in metres, got {spacing_m!r}")
    kept = [0]
    for i in range(1, len(pts)):
        d = np.hypot(*(pts[kept] - pts[i]).T)
        if d.min() >= spacing_m - 1e-3:
            kept.append(i)
    return np.asarray(kept, dtype=np.int64)


#: Device offsets whose test sessions every simulated survey draws at once (both grids' values): the offset
#: changes only what the test phone reads (:func:`ilocalg.sim.iloc_floor.simulate_device_offsets`), so the
#: device-offset points of a seed share one survey, its fits and its per-point fingerprints.
_OFFSETS = tuple(sorted(set(GRIDS[False]["device_offset_db"]) | set(GRIDS[True]["device_offset_db"])))


def _split(radio: tuple) -> tuple[tuple, float]:
    """``radio`` (sorted (name, value) pairs) -> (the survey's pairs, without the device offset; the offset)."""
    r = dict(radio)
    off = r.pop("device_offset_db") if "device_offset_db" in r else iloc_floor.world_params()["device_offset_db"]
    return tuple(sorted(r.items())), off


@functools.lru_cache(maxsize=12)
def _floors(seed: int, spp: int, spt: int, survey_radio: tuple, offsets: tuple) -> dict:
    """The simulated floors of a survey, one per device offset (read only here): the AP-count, spacing and
    device-offset points of a seed share them, so a worker process that runs several of them (the seeds
    interleave in the task list) simulates the survey once; 12 surveys of 3.7 MB at most."""
    sims = iloc_floor.simulate_device_offsets(offsets, seed, scans_per_point=spp, scans_per_test_point=spt,
                                              **dict(survey_radio))
    return dict(zip(offsets, sims, strict=True))


def _floor(seed: int, spp: int, spt: int, radio: tuple) -> iloc_floor.IlocFloor:
    """The simulated floor of a task (:func:`_floors`; the same arrays as ``iloc_floor.simulate``)."""
    survey_radio, off = _split(radio)
    return _floors(seed, spp, spt, survey_radio, tuple(sorted({*_OFFSETS, off})))[off]


@functools.lru_cache(maxsize=12)
def _training(seed: int, spp: int, spt: int, survey_radio: tuple, spacing_m: float) -> tuple:
    """The training side of a task (read only): the floor, the kept points, the training scans and positions kept
    and their per-point mean fingerprints. The AP-count and device-offset points of a survey share it (12 entries,
    as :func:`_floors`; the scans kept are at most 3 MB per survey)."""
    sim = next(iter(_floors(seed, spp, spt, survey_radio, _OFFSETS).values()))  # every offset's floor has its survey
    keep = thin_points(sim.points_xy_m, spacing_m)
    rows_kept = np.isin(sim.train.meta["point"].to_numpy(), keep)
    X, xy = sim.train.rssi_dbm[rows_kept], sim.train.xy_m[rows_kept]
    fp, pts, _ = mean_fingerprints(X, xy, min_heard_fraction=0.5)
    return sim, keep, X, xy, fp, pts


def _survey(seed: int, spp: int, spt: int, radio: tuple, spacing_m: float) -> tuple:
    """What a task scores on (read only): the floor, the kept points, the training scans and positions kept,
    their per-point mean fingerprints (:func:`_training`), and the test scans hearing some AP with their true
    positions."""
    sim = _floor(seed, spp, spt, radio)
    keep, X, xy, fp, pts = _training(seed, spp, spt, _split(radio)[0], spacing_m)[1:]
    heard = ~np.all(np.isnan(sim.test.rssi_dbm), axis=1)  # a scan hearing no AP cannot be positioned
    return sim, keep, X, xy, fp, pts, heard, sim.test.xy_m[heard], sim.test.rssi_dbm[heard]


def _paper_estimator(name: str, sim) -> object:
    return paper_estimators(sim.detect_dbm, BASE["k_aps"])[name]


@functools.lru_cache(maxsize=12)
def _horus_fit(*training) -> object:
    """Simplified-Horus fitted on every stored scan of a survey (Fig 4): its per-point histograms do not read
    ``k_aps`` nor the test phone (read only; :func:`_use_fit` copies what ``predict`` needs)."""
    sim, _, X, xy, *_ = _training(*training)
    return _paper_estimator("Simplified-Horus", sim).fit(X, xy)


@functools.lru_cache(maxsize=1)
def _radar_fit(k_aps: int, *training) -> object:
    """Simplified-RADAR with ``k_aps`` fitted on every stored scan of a survey (L283, L287; read only): the
    device-offset points (consecutive tasks of a seed) share it."""
    sim, _, X, xy, *_ = _training(*training)
    return paper_estimators(sim.detect_dbm, k_aps)["Simplified-RADAR"].fit(X, xy)


def _use_fit(est, fitted) -> None:
    """Give ``est`` the fitted attributes of ``fitted``, an estimator of the same parameters but ``k_aps``."""
    a, b = est.get_params(), fitted.get_params()
    if {k: v for k, v in a.items() if k != "k_aps"} != {k: v for k, v in b.items() if k != "k_aps"}:
        raise ValueError(f"fitted estimator has other parameters: {b} vs {a}")
    for attr in ("model_", "heard_aps_", "n_features_in_"):
        setattr(est, attr, getattr(fitted, attr))


@functools.lru_cache(maxsize=12)
def _knn_summary(*survey) -> dict:
    """Error summary of the KNN (Manhattan, K=5) on a survey's per-point mean fingerprints: it uses every AP,
    so the AP-count points of a survey share it."""
    sim, _, _, _, fp, pts, _, true, Xq = _survey(*survey)
    return summary(horizontal_error_m(_paper_estimator("KNN (Manhattan, K=5)", sim).fit(fp, pts).predict(Xq), true))


def run(seed: int = 0, fast: bool = False, k_aps: int = 5, spacing_m: float = 2.0,
        scans_per_point: int | None = None, scans_per_test_point: int | None = None,
        **radio) -> dict[str, pd.DataFrame]:
    """Errors of the three Wi-Fi methods for one survey configuration (see the module docstring).

    Parameters
    ----------
    seed : int
    fast : bool
        Default scans: 60 per training point and 5 per test point instead of 300 and 20.
    k_aps : int
        Strongest APs used by RADAR and Horus (KNN uses every AP: its rows do not depend on k).
    spacing_m : float
        Training-point spacing (2 m = the thesis' full grid).
    scans_per_point : int, optional
        Training scans per point (thesis: 300).
    scans_per_test_point : int, optional
        New scans at each test point (thesis: 20).
    **radio
        Radio parameters of :data:`RADIO` (floor simulator overrides).
    """
    unknown = set(radio) - set(RADIO)
    if unknown:
        raise ValueError(f"unknown radio parameters {sorted(unknown)}; swept here: {list(RADIO)}")
    if int(k_aps) != k_aps or k_aps < 1:
        raise ValueError(f"k_aps must be an integer >= 1, got {k_aps!r}")
    spp = int(scans_per_point or (60 if fast else iloc_floor.SCANS_PER_POINT))
    spt = int(scans_per_test_point or (5 if fast else 20))
    survey = (int(seed), spp, spt, tuple(sorted(radio.items())), float(spacing_m))
    training = (int(seed), spp, spt, _split(survey[3])[0], float(spacing_m))
    sim, keep, X, xy, fp, pts, heard, true, Xq = _survey(*survey)
    rows = [study_row("training points", len(keep), "points"),
            study_row("test scans hearing no AP (not scored)", np.sum(~heard), "scans")]
    for name, est in paper_estimators(sim.detect_dbm, int(k_aps)).items():
        if name == "KNN (Manhattan, K=5)":  # every AP, whatever k: the same errors at every k of a survey
            s = _knn_summary(*survey)
        else:
            if name == "Simplified-Horus":  # the histograms do not depend on k (only the query's APs do)
                _use_fit(est, _horus_fit(*training))
            else:  # every stored scan: RADAR's database (L283, L287)
                est = _radar_fit(int(k_aps), *training)
            s = summary(horizontal_error_m(est.predict(Xq), true))
        rows += [study_row(q, s[col], "m", method=name) for q, col in STATS]
    return {"sweep_wifi": pd.DataFrame(rows)}


def tasks(seeds, fast: bool = False) -> list:
    """Sweep tasks of the three one-factor curves (k, spacing, scans per point) around :data:`BASE`."""
    base = BASE_FAST if fast else BASE
    grids = [{**{k: [v] for k, v in base.items()}, name: vals} for name, vals in GRIDS[fast].items()]
    return study_tasks(EXPERIMENT, grids, seeds, fast=fast)


def findings(cv: pd.DataFrame, fast: bool = False) -> str:
    """Sentences computed from :func:`ilocalg.workflow.studies.curves` output of this study."""
    from ilocalg.workflow.studies import select

    base = BASE_FAST if fast else BASE
    out = []

    def curve(method, vary):
        fixed = {k: v for k, v in base.items() if k != vary}
        c = select(cv, "mean error", method=method, **fixed).sort_values(vary)
        return c

    for m in ("Simplified-RADAR", "Simplified-Horus"):
        c = curve(m, "k_aps")
        b = c.loc[c["mean"].idxmin()]
        last = "" if int(b["k_aps"]) == int(c["k_aps"].iloc[-1]) else (
            f", {c['mean'].iloc[-1]:.2f} m at k={int(c['k_aps'].iloc[-1])}")
        out.append(f"{m}: mean error {c['mean'].iloc[0]:.2f} m at k={int(c['k_aps'].iloc[0])}, lowest "
                   f"{b['mean']:.2f} m [95 % CI {b['ci95_low']:.2f}-{b['ci95_high']:.2f}] at k={int(b['k_aps'])}"
                   f"{last} (N={int(b['n'])} seeds).")
    for m in ("Simplified-RADAR", "Simplified-Horus"):
        parts = []
        for p in RADIO:
            c = curve(m, p)
            if len(c) < 2:
                continue
            parts.append(f"{p} {c[p].iloc[0]:g} -> {c[p].iloc[-1]:g}: {c['mean'].iloc[0]:.2f} -> "
                         f"{c['mean'].iloc[-1]:.2f} m")
        if parts:
            out.append(f"{m}, mean error over each radio parameter (others at their defaults): " + "; ".join(parts)
                       + ".")
    for m in ("Simplified-RADAR", "Simplified-Horus", "KNN (Manhattan, K=5)"):
        c = curve(m, "spacing_m")
        s = curve(m, "scans_per_point")
        out.append(f"{m}: {c['mean'].iloc[0]:.2f} m on the {c['spacing_m'].iloc[0]:g} m grid vs "
                   f"{c['mean'].iloc[-1]:.2f} m at {c['spacing_m'].iloc[-1]:g} m spacing; "
                   f"{s['mean'].iloc[0]:.2f} m with {int(s['scans_per_point'].iloc[0])} scans per point vs "
                   f"{s['mean'].iloc[-1]:.2f} m with {int(s['scans_per_point'].iloc[-1])}.")
    return "\n".join(out)
