"""A walk's scan sequence aligned to the database walks' scan sequences (issue 26; a diagnostic, no method).

The hypothesis: a walk's persistent Wi-Fi fix error comes from matching against a database walk recorded under
similar radio conditions, at the wrong place along it (per walk, median, 53 % of the scans' five nearest rows come
from one database walk; :mod:`ilocalg.track.surface`). Aligning the walk's whole scan sequence to each database
walk's scan sequence, in order, would then put each scan at the right place along that walk. Here each database
walk whose rows pass within ``radius_m`` of at least ``min_frac`` of the walk's ``lsq`` positions (at its scan
times) is a candidate, in both directions; :func:`subsequence_dtw` aligns the walk's scans (RSSI vectors, the
Euclidean distance of :func:`ilocalg.track.fixes.dense_wknn`, optionally plus ``lam_dbm_per_m`` times the distance
of the row to the ``lsq`` position, i.e. the ``lsq`` track shape matched to that walk's path too) to a stretch of
the candidate's rows; a scan's aligned position is the mean position of the rows it is matched to. Kept per scan:
the alignment of the cheapest candidate (cost per path step), the candidates' positions weighted by
``exp(-(cost - cost_min) / h_dbm)``, and the oracle (the candidate whose alignment is nearest the truth; a
diagnostic). The question first asked (before any estimator): are the aligned positions closer to the truth than
the WKNN fixes?

What it measured (issue 26; development walks only: site1 F1 even, 50 walks, leave-one-walk-out with the nested
Wi-Fi selection; scan-weighted mean error at the walks' scan times, truth interpolated between waypoints; the
walk's mean error vector's length is its persistent part):

``python -m ilocalg`` has no command for it; the numbers come from :func:`align_table` (``scan_summary``)::

    from ilocalg.experiments.fusion_real_walks import FLOOR_CACHE
    from ilocalg.track import RealWalkConfig
    from ilocalg.track.floor import cached_floor_model
    from ilocalg.track.lowo import floor_files, load_floor
    from ilocalg.track.walk_align import align_table, scan_summary
    ds = "ilc2020_site1/site1_F1"; fl = load_floor(None, ds, "keep"); cfg = RealWalkConfig()
    model, _ = cached_floor_model(floor_files(None, ds), lambda: fl.traces, FLOOR_CACHE, cfg, dataset=ds,
                                  relisted_wifi="keep")
    SETTINGS = ((3, 0.5, 0), (5, 0.5, 0), (8, 0.3, 0), (12, 0.2, 0), (5, 0.5, 2), (8, 0.3, 5), (8, 0.3, 20))
    t = align_table(fl.traces, model, fl.names[::2], cfg, settings=SETTINGS)
    print(scan_summary(t))

Mean error per scan (m; the walks with a candidate: 45 at 3 m, 49 at 5 m, else 50) and, in brackets, the mean over
walks of the walk's mean error vector's length; ``walks nearer``: walks whose aligned scans (cheapest / weighted,
``h_dbm`` 5) are nearer the truth on average than their fixes:

====================  ============  ============  ============  ============  ============  =============
radius, frac, lam     fixes       lsq         cheapest    weighted    oracle      walks nearer
====================  ============  ============  ============  ============  ============  =============
3 m, 0.5, 0           5.18 (3.44)  3.42 (3.30)  6.39 (4.64)  6.24 (4.55)  6.15 (4.17)  12, 13 of 45
5 m, 0.5, 0           5.28 (3.38)  3.42 (3.26)  6.68 (4.67)  6.48 (4.51)  6.09 (3.81)  12, 15 of 49
8 m, 0.3, 0           5.28 (3.39)  3.40 (3.25)  7.85 (5.35)  7.76 (5.20)  6.49 (3.85)  11, 15 of 50
12 m, 0.2, 0          5.28 (3.39)  3.40 (3.25)  8.04 (5.50)  7.84 (5.19)  6.48 (3.80)  11, 16 of 50
5 m, 0.5, 2 dB/m      5.28 (3.38)  3.42 (3.26)  6.33 (4.42)  6.13 (4.22)  5.74 (3.50)  15, 20 of 49
8 m, 0.3, 5 dB/m      5.28 (3.39)  3.40 (3.25)  6.24 (4.08)  6.11 (3.75)  5.70 (3.37)  23, 28 of 50
8 m, 0.3, 20 dB/m     5.28 (3.39)  3.40 (3.25)  5.68 (3.79)  5.52 (3.64)  5.20 (3.24)  26, 29 of 50
====================  ============  ============  ============  ============  ============  =============

Candidates per walk (median): 1 / 3 / 4.5 / 7.5 at radius 3 / 5 / 8 / 12 m. The radius spans the ``lsq`` track's
own error at the scan times (3.4 m mean) to a few times it. CPU (the alignments of one walk, ``cpu_s``): median
0.01-0.02 s per setting (50 walks, loaded machine); the whole table 57 CPU-s, mostly the ``lsq`` tracks.

Why it fails: the aligned positions are *farther* from the truth than the WKNN fixes they would correct in every
setting, and so is their persistent part (the walk's mean error vector); without the track in the cost even the
candidate chosen with the truth (oracle) is farther (6.09-6.49 m against 5.18-5.28 m). So a walk's persistent fix
error is not the wrong place along one well-matched database walk that an ordered alignment puts right: matched in
order, the scans land no nearer than matched one by one. Adding the ``lsq`` shape to the cost (``lam_dbm_per_m``
> 0, the track matched to the walk's path too) brings the aligned positions toward the fixes' error only by pulling
them onto the ``lsq`` track, and at 20 dB/m they are still 5.5 m off where ``lsq`` itself is 3.4 m off at the same
scans: as extra ``lsq`` observations they would pull the track toward worse positions, so that step (and an
estimator key) was not taken and nothing was scored on held-out walks.

References
----------
Sakoe H., Chiba S., IEEE Trans. ASSP 26(1) (1978), dynamic time warping; Mueller M., Fundamentals of Music
Processing, Springer (2015), Sec. 7.2.3 (subsequence DTW: open begin and end on the database sequence);
Luo et al. (2017), eq. 1 (the RSSI distance of KNN fingerprinting).
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ilocalg.io.recording import as_recording
from ilocalg.io.schema import T_S, X_M, Y_M
from ilocalg.track._config import DEFAULT_CONFIG, RealWalkConfig
from ilocalg.track.database import WifiDatabase
from ilocalg.track.fixes import db_matrix
from ilocalg.track.motion import _track_at
from ilocalg.track.surface import walk_queries

__all__ = ["subsequence_dtw", "rssi_distances", "align_to_walks", "align_table", "scan_summary"]


def subsequence_dtw(C) -> tuple[float, np.ndarray]:
    """Subsequence DTW of a query (rows of the cost matrix ``C``, (m, n)) against a stretch of a reference
    (columns): steps (1, 1), (1, 0), (0, 1), open begin and end on the reference (Mueller 2015, Sec. 7.2.3).

    Returns ``(cost, path)``: the accumulated cost of the optimal warping path and the path (L, 2) of (query,
    reference) index pairs, first to last, every query index at least once."""
    C = np.asarray(C, dtype=np.float64)
    if C.ndim != 2 or 0 in C.shape or not np.isfinite(C).all():
        raise ValueError(f"subsequence_dtw: C must be a finite (m, n) matrix with m, n >= 1, got shape {C.shape}")
    m, n = C.shape
    D = np.empty((m, n))
    D[0] = C[0]
    for i in range(1, m):
        D[i, 0] = D[i - 1, 0] + C[i, 0]
        up = D[i - 1]
        diag = np.minimum(up[1:], up[:-1])                 # min(D[i-1, j], D[i-1, j-1]) for j >= 1
        row = D[i]
        for j in range(1, n):
            row[j] = C[i, j] + min(diag[j - 1], row[j - 1])
    i, j = m - 1, int(np.argmin(D[-1]))
    cost = float(D[i, j])
    path = [(i, j)]
    while i > 0:
        if j == 0:
            i -= 1
        else:
            k = int(np.argmin((D[i - 1, j - 1], D[i - 1, j], D[i, j - 1])))
            i, j = (i - 1, j - 1) if k == 0 else (i - 1, j) if k == 1 else (i, j - 1)
        path.append((i, j))
    return cost, np.array(path[::-1])


def rssi_distances(db: WifiDatabase, X, cfg: RealWalkConfig = DEFAULT_CONFIG) -> np.ndarray:
    """Euclidean RSSI distances (m, n) of queries ``X`` (m, n_aps in ``db.ap_ids`` order; NaN not heard) to every
    database row (readings older than ``cfg.max_age_s`` not heard; not heard = ``cfg.not_heard_dbm``), as
    :func:`ilocalg.track.fixes.dense_wknn` measures them."""
    A = np.nan_to_num(db_matrix(db, cfg), nan=cfg.not_heard_dbm) - cfg.not_heard_dbm
    Q = np.nan_to_num(np.asarray(X, dtype=np.float64), nan=cfg.not_heard_dbm) - cfg.not_heard_dbm
    return np.sqrt(np.maximum((Q * Q).sum(1)[:, None] + (A * A).sum(1)[None] - 2.0 * Q @ A.T, 0.0))


def align_to_walks(db: WifiDatabase, dist, shape_xy_m, radius_m: float = 5.0, min_frac: float = 0.5,
                   lam_dbm_per_m: float = 0.0) -> list[tuple[float, str, bool, np.ndarray]]:
    """The walk's scans aligned to each candidate database walk (rows in their stored, time, order; both
    directions). ``dist`` (m, n): :func:`rssi_distances`; ``shape_xy_m`` (m, 2): the walk's track at its scans.
    A candidate passes within ``radius_m`` of at least ``min_frac`` of ``shape_xy_m``; the alignment's cost adds
    ``lam_dbm_per_m`` times each row's distance to the track. Returns ``[(cost per path step, walk, reversed,
    positions (m, 2))]``, cheapest first."""
    if not (radius_m > 0 and 0 <= min_frac <= 1 and lam_dbm_per_m >= 0):
        raise ValueError(f"align_to_walks: radius_m must be > 0, min_frac in [0, 1], lam_dbm_per_m >= 0; got "
                         f"{radius_m}, {min_frac}, {lam_dbm_per_m}")
    s = np.asarray(shape_xy_m, dtype=np.float64)
    m = len(s)
    out = []
    for w in dict.fromkeys(db.walk):
        idx = np.flatnonzero(db.walk == w)
        gap = np.hypot(*(s[:, None] - db.xy_m[idx][None]).transpose(2, 0, 1))       # m, n_w
        if (gap.min(axis=1) <= radius_m).mean() < min_frac:
            continue
        for rev in (False, True):
            o = slice(None, None, -1) if rev else slice(None)
            ii = idx[o]
            cost, path = subsequence_dtw(dist[:, ii] + lam_dbm_per_m * gap[:, o])
            pos = np.zeros((m, 2))
            np.add.at(pos, path[:, 0], db.xy_m[ii[path[:, 1]]])
            pos /= np.bincount(path[:, 0], minlength=m)[:, None]
            out.append((cost / len(path), w, rev, pos))
    return sorted(out, key=lambda r: r[0])


def align_table(traces: dict, model, names, cfg: RealWalkConfig = DEFAULT_CONFIG,
                settings=((5.0, 0.5, 0.0),), h_dbm: float = 5.0, select: bool = True) -> pd.DataFrame:
    """The development table behind the module docstring: for each walk of ``names`` (leave-one-walk-out against
    ``model``, a :class:`ilocalg.track.floor.FloorModel` of ``traces``, with its nested Wi-Fi selection when
    ``select``), its ``lsq`` track and WKNN fixes, and per ``(radius_m, min_frac, lam_dbm_per_m)`` of ``settings``
    the scans aligned by :func:`align_to_walks`.

    Returns a DataFrame, one row per scan inside the walk's waypoints and setting: ``walk, radius_m, min_frac,
    lam_dbm_per_m, n_candidates``, the error vectors (m) ``fix_dx, fix_dy`` (WKNN fix), ``lsq_dx, lsq_dy``,
    ``best_dx, best_dy`` (cheapest candidate), ``weighted_dx, weighted_dy`` (weights ``exp(-(cost - min) /
    h_dbm)``), ``oracle_dx, oracle_dy`` (the candidate nearest the truth on average; diagnostic), NaN without a
    candidate; ``cpu_s`` (the walk's alignment)."""
    from ilocalg.track.evaluation import evaluate_walk

    if select:
        model.select_wifi(list(names), cfg)
    rows = []
    for name in names:
        wm = model.for_walk(name, cfg, select=select)
        r = evaluate_walk(traces[name], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, methods=("lsq",),
                          step_var_m2=wm.step_var_m2, gain=wm.gain,
                          loo_fixes=model.loo_fixes([name], cfg, select=select)[name])
        fx = r["fixes"]
        shape = _track_at(r["state_t_s"], r["tracks"]["lsq"], fx.t_s)
        wp = as_recording(traces[name]).in_frame(wm.db.frame).truth
        tw = wp[T_S].to_numpy()
        inside = (fx.t_s >= tw[0]) & (fx.t_s <= tw[-1])
        true = np.column_stack([np.interp(fx.t_s, tw, wp[c].to_numpy()) for c in (X_M, Y_M)])
        dist = rssi_distances(wm.db, walk_queries(traces[name], wm.db, fx.t_s, wm.cfg), wm.cfg)
        for radius, frac, lam in settings:
            c0 = time.process_time()
            res = align_to_walks(wm.db, dist, shape, radius, frac, lam)
            cpu = time.process_time() - c0
            est = {"fix": fx.xy_m, "lsq": shape}
            if res:
                cs = np.array([c for c, *_ in res])
                w = np.exp(-(cs - cs[0]) / h_dbm)
                est["best"] = res[0][3]
                est["weighted"] = np.tensordot(w / w.sum(), np.stack([p for *_, p in res]), axes=1)
                est["oracle"] = min((p for *_, p in res), key=lambda p: np.hypot(*(p - true)[inside].T).mean())
            d = {"walk": name, "radius_m": radius, "min_frac": frac, "lam_dbm_per_m": lam,
                 "n_candidates": len(res) // 2, "cpu_s": cpu}
            for k in ("fix", "lsq", "best", "weighted", "oracle"):
                e = est[k] - true if k in est else np.full_like(true, np.nan)
                d[f"{k}_dx"], d[f"{k}_dy"] = e[inside, 0], e[inside, 1]
            rows.append(pd.DataFrame(d))
    return pd.concat(rows, ignore_index=True)


def scan_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per setting of :func:`align_table`'s ``table`` (walks with a candidate only): the mean error per scan (m)
    and the mean over walks of the walk's mean error vector's length (``*_bias_m``, the persistent part) of the
    fixes, ``lsq`` and the aligned positions, the walks whose aligned (``best`` / ``weighted``) scans are nearer
    the truth on average than their fixes, and the median CPU per walk."""
    t = table.dropna(subset=["best_dx"])
    out = []
    for key, g in t.groupby(["radius_m", "min_frac", "lam_dbm_per_m"]):
        row = dict(zip(["radius_m", "min_frac", "lam_dbm_per_m"], key, strict=True))
        err = {k: np.hypot(g[f"{k}_dx"], g[f"{k}_dy"]) for k in ("fix", "lsq", "best", "weighted", "oracle")}
        per_walk = pd.DataFrame(err).assign(walk=g["walk"]).groupby("walk").mean()
        bias = g.groupby("walk")[[c for c in g.columns if c.endswith(("_dx", "_dy"))]].mean()
        row["walks"] = len(per_walk)
        row["median_candidates"] = float(g.groupby("walk")["n_candidates"].first().median())
        for k, e in err.items():
            row[f"{k}_m"] = float(e.mean())
        for k in err:
            row[f"{k}_bias_m"] = float(np.hypot(bias[f"{k}_dx"], bias[f"{k}_dy"]).mean())
        row["walks_best_nearer"] = int((per_walk["best"] < per_walk["fix"]).sum())
        row["walks_weighted_nearer"] = int((per_walk["weighted"] < per_walk["fix"]).sum())
        row["median_cpu_s"] = float(g.groupby("walk")["cpu_s"].first().median())
        out.append(row)
    return pd.DataFrame(out)
