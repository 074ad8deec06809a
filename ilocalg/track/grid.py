"""The survey's marked points: a track moved, at the times it is asked about, onto the points other walks stood on.

The surveyors of a floor stand on a fixed set of marked points: on site1, 89 % of F1's waypoints (88 % on F2) lie
within 0.1 m of a waypoint of *another* walk. A track is scored at its waypoints' times, which is also the
protocol of the 2021 Indoor Location & Navigation competition on this data format (the times to locate are given),
whose top solutions moved each estimate onto the training waypoints ("snap to grid"). The ``*_grid`` variants of
:data:`ilocalg.track.GRID_METHODS` do that with what a deployment has: the database walks' distinct waypoints
(:func:`survey_points`, the scored walk's own waypoints never among them) and the times asked about (the query
times: in scoring, the waypoints' times; in the competition, the given times).

A discrete hidden Markov model over the marked points at the query times (:func:`grid_hmm`)
    Each query time ``k`` has as states the marked points within ``N_SD`` sd of the base estimate ``e_k`` plus one
    "no marked point" state (the walker is elsewhere; its position is ``e_k`` itself). Emissions: a marked point
    ``c``: ``(1 - pi) / n_k * N(e_k; c, s_e^2 I)`` (``n_k`` points in the disc); the off state: ``pi / a_k``
    (``a_k`` the disc's area: a position uniform in it), with ``pi`` the share of the database walks' waypoints
    that are not within ``tol`` of another database walk's waypoint (:func:`off_grid_share`, leave-one-walk-out
    inside the database) and ``s_e^2`` the base estimate's error variance: the per-axis variance of the walk's
    persistent Wi-Fi fix error (``var_b`` of :func:`ilocalg.track.fixes.fix_error_correlation`, measured on the
    database walks; the error the tracks keep, :mod:`ilocalg.track.error_sources`), or the mean fix variance
    without it. Transitions: the displacement between the states of consecutive query times against the PDR
    displacement between them, Gaussian with per-axis variance ``step_var * n_steps`` (the measured step variance,
    :func:`ilocalg.track.motion.calibrate_step_var`), plus ``s_e^2`` for each end in the off state. Offline: the
    Viterbi path; online (causal): at each query time the most probable state of the forward (filtered)
    distribution, which uses the base estimates and the PDR up to that time only.
What a walk off the marked points gets
    Where no marked point lies within ``N_SD`` sd of the estimate, or the off state is the more probable one, the
    base estimator's position: the variant is never further from the base than ``N_SD`` sd of ``s_e``.
What is drawn between query times (:func:`bend_track`)
    The base track's states moved by the query corrections: linear in time between query times (offline), the
    latest earlier query's correction held (online). The scored positions are the query positions themselves.

Measured on the development walks only (site1 F1 even, 50 walks, 379 waypoints, leave-one-walk-out with the
nested Wi-Fi selection, Wi-Fi only 5.73 m; 85.5 % of their waypoints lie on another walk's waypoint), ratio to Wi-Fi
only, base -> HMM with the settings above (``s_e^2 = var_b``, ``pi`` from the database): ``lsq`` 0.610 -> 0.329,
``lsq_map`` 0.567 -> 0.351, ``lsq_paths`` 0.582 -> 0.335, ``map_align`` 0.529 -> 0.330; causal ``lsq_online_map``
0.752 -> 0.594, ``kf_gain_map`` 0.766 -> 0.591. The nearest marked point within a radius ``r`` instead (1-8 m; no
radius): best ``map_align`` 0.417 (r 6 m), ``lsq`` 0.493 (8 m), ``lsq_online_map`` 0.670 (6 m), ``kf_gain_map``
0.687 (6 m). Sensitivity of the HMM (development walks, not used to choose): ``s_e^2`` from the base's own
development errors x0.5 / x1 / x2: ``lsq`` 0.380 / 0.356 / 0.330, ``kf_gain_map`` 0.627 / 0.590 / 0.547; ``pi`` 0.05
/ 0.3: ``lsq`` 0.319 / 0.353. Per walk the variant is not always better: worse than its base on 8 (``lsq_grid``),
10 (``map_align_grid``), 14 (``lsq_online_map_grid``) and 13 (``kf_gain_map_grid``) of the 50 development walks
(at most +3.3 to +5.0 m on a walk's mean): a base off by about the points' spacing (on F1 a marked point's nearest
other one is 2.7 m away, median) can be decoded onto a shifted route.

Held out, scored once after the method and its settings were fixed (base -> grid, ratio to Wi-Fi only; mean,
median, p75 of the grid variant): F1 odd (50 walks, 320 waypoints, Wi-Fi only 5.35 m) ``lsq`` 0.676 -> 0.411
(2.20, 0.00, 2.91 m), ``map_align`` 0.591 -> 0.340 (1.82, 0.00, 2.79 m), ``lsq_online_map`` 0.774 -> 0.580 (3.11,
2.05, 5.25 m), ``kf_gain_map`` 0.791 -> 0.581 (3.11, 2.13, 5.22 m); F2 every 2nd (49 walks, 362 waypoints, 5.57 m)
0.676 -> 0.384 (2.14, 0.00, 2.65 m), 0.620 -> 0.324 (1.80, 0.00, 2.12 m), 0.737 -> 0.578 (3.22, 0.00, 5.10 m),
0.733 -> 0.566 (3.15, 0.00, 4.76 m). CPU: about 25 ms per walk for the four variants (site1 F1, the off share
measured per scored walk over the other walks' waypoints).

References
----------
Kaggle Indoor Location & Navigation (2021), top solutions' "snap to grid" post-processing of the training
waypoints; Rabiner L. R., "A tutorial on hidden Markov models and selected applications in speech recognition",
Proc. IEEE 77(2) (1989), the forward algorithm and Viterbi decoding; Newson P., Krumm J., ACM SIGSPATIAL GIS (2009),
hidden Markov map matching (Gaussian emissions, transitions from the travelled distance).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

__all__ = ["survey_points", "off_grid_share", "grid_hmm", "bend_track", "grid_queries", "N_SD", "SAME_POINT_M"]

#: The disc (in sd of the base estimate's error) whose marked points are a query time's states.
N_SD = 3.0
#: Two waypoints closer than this (m) are the same marked point (:func:`off_grid_share`).
SAME_POINT_M = 0.1


def survey_points(paths) -> np.ndarray:
    """The distinct waypoints (k, 2) of a walked-path graph built from waypoints
    (:meth:`ilocalg.track.paths.WalkedPaths.from_recordings`): its segments' ends, each point once (two ends the
    same to 1 mm are one point; the first kept)."""
    pts = np.vstack([np.asarray(paths.a_m, dtype=np.float64).reshape(-1, 2),
                     np.asarray(paths.b_m, dtype=np.float64).reshape(-1, 2)])
    if pts.shape[0] == 0:
        raise ValueError("no surveyed point: the database walks have no waypoint segment")
    _, first = np.unique(np.round(pts, 3), axis=0, return_index=True)
    return pts[np.sort(first)]


def off_grid_share(paths, tol_m: float = SAME_POINT_M) -> float:
    """Share of the graph's walks' waypoints farther than ``tol_m`` from every waypoint of another of its walks
    (each walk against the others): the prior that a walker stands off the marked points. Kept with the graph."""
    memo = getattr(paths, "_memo", None)
    key = ("off_grid_share", tol_m)
    if memo is not None and key in memo:
        return memo[key]
    pts = np.vstack([paths.a_m, paths.b_m])
    walk = np.concatenate([paths.walk, paths.walk])
    names, wid = np.unique(walk, return_inverse=True)
    if len(names) < 2:
        raise ValueError("the share of waypoints off the marked points needs at least two walks")
    r = np.round(pts, 3)
    # A walk's point at a location is off when no other walk has a point within tol_m of it, i.e. when the walks at
    # the locations within tol_m (itself included) are that walk alone: a property of the location. So: the distinct
    # locations, the distinct walks at each, and the pairs of locations within tol_m (the candidates from a slightly
    # larger radius, then the distance as cKDTree.query computes it, compared as d <= tol_m).
    loc_xy, loc = np.unique(r, axis=0, return_inverse=True)
    lw = np.unique(np.column_stack([loc, wid]), axis=0)  # (location, walk), each once
    n_walks = np.bincount(lw[:, 0], minlength=loc_xy.shape[0])
    walk1 = np.full(loc_xy.shape[0], -1, dtype=np.int64)
    walk1[lw[:, 0]] = lw[:, 1]  # the walk of a one-walk location
    pairs = cKDTree(loc_xy).query_pairs(tol_m * (1.0 + 1e-6) + 1e-12, output_type="ndarray").reshape(-1, 2)
    pairs = pairs[np.sqrt(((loc_xy[pairs[:, 0]] - loc_xy[pairs[:, 1]]) ** 2).sum(axis=1)) <= tol_m]
    ia, ib = np.concatenate([pairs[:, 0], pairs[:, 1]]), np.concatenate([pairs[:, 1], pairs[:, 0]])
    shared = n_walks >= 2
    shared[ia[(n_walks[ib] >= 2) | (walk1[ib] != walk1[ia])]] = True
    n = int(n_walks.sum())
    n_off = int(n_walks[~shared].sum())
    out = float(n_off / n)
    if memo is not None:
        memo[key] = out
    return out


def grid_hmm(est_xy_m, pdr_xy_m, n_steps, points_m, est_var_m2: float, step_var_m2: float, off_share: float,
             causal: bool, n_sd: float = N_SD) -> tuple[np.ndarray, np.ndarray]:
    """The positions at the query times from the hidden Markov model over the marked points (module docstring).

    ``est_xy_m`` (q, 2): the base estimates at the query times (in time order); ``pdr_xy_m`` (q, 2): the PDR track
    (cumulative displacement, any origin) at the same times; ``n_steps`` (q,): the step count at each (fractional);
    ``points_m`` (k, 2): the marked points; ``est_var_m2``: the base estimate's per-axis error variance;
    ``step_var_m2``: one step's per-axis displacement variance; ``off_share``: the prior of the off state (1: no
    marked point is trusted, every query keeps its base estimate).
    ``causal``: the forward filter's most probable state at each query time (uses the times up to it only); else
    the Viterbi path. Returns ``(positions (q, 2), on_point (q,) bool)``.

    References
    ----------
    Rabiner (1989), eq. 19-20 (forward) and 32-35 (Viterbi).
    """
    est = np.asarray(est_xy_m, dtype=np.float64).reshape(-1, 2)
    pdr = np.asarray(pdr_xy_m, dtype=np.float64).reshape(-1, 2)
    ns = np.asarray(n_steps, dtype=np.float64).reshape(-1)
    P = np.asarray(points_m, dtype=np.float64).reshape(-1, 2)
    q = est.shape[0]
    if pdr.shape != est.shape or ns.shape != (q,):
        raise ValueError(f"grid_hmm: est_xy_m {est.shape}, pdr_xy_m {pdr.shape} and n_steps {ns.shape} must describe "
                         "the same query times")
    if not (est_var_m2 > 0 and step_var_m2 > 0 and 0.0 <= off_share <= 1.0):
        raise ValueError(f"grid_hmm: est_var_m2 and step_var_m2 must be > 0 and off_share in [0, 1], got "
                         f"{est_var_m2}, {step_var_m2}, {off_share}")
    if q == 0 or off_share >= 1.0:          # no walk stands where another stood: no marked point to trust
        return est.copy(), np.zeros(q, dtype=bool)
    off_share = max(off_share, 1e-9)        # every waypoint shared: the off state only where no point is near
    if not np.isfinite(est).all():
        raise ValueError("grid_hmm: the base estimates must be finite at every query time")
    tree = cKDTree(P) if P.shape[0] else None
    radius = n_sd * np.sqrt(est_var_m2)
    log_off = np.log(off_share / (np.pi * radius * radius))
    pos, off, log_e = [], [], []
    for k in range(q):
        idx = tree.query_ball_point(est[k], radius) if tree is not None else []
        c = P[np.sort(np.asarray(idx, dtype=np.int64))]
        d2 = ((c - est[k]) ** 2).sum(axis=1)
        le = (np.log((1.0 - off_share) / max(c.shape[0], 1)) - np.log(2.0 * np.pi * est_var_m2)
              - d2 / (2.0 * est_var_m2))
        pos.append(np.vstack([c, est[k][None]]))
        off.append(np.r_[np.zeros(c.shape[0]), 1.0])
        log_e.append(np.r_[le, log_off])
    dpdr = np.diff(pdr, axis=0)
    dn = np.maximum(np.diff(ns), 1.0)

    def log_t(k):          # from the states of query k to those of query k + 1
        v = step_var_m2 * dn[k] + est_var_m2 * (off[k][:, None] + off[k + 1][None, :])
        dd = pos[k + 1][None, :, :] - pos[k][:, None, :] - dpdr[k]
        return -np.log(2.0 * np.pi * v) - (dd ** 2).sum(axis=-1) / (2.0 * v)

    pick = np.empty(q, dtype=np.int64)
    if causal:
        la = log_e[0]
        pick[0] = int(np.argmax(la))
        for k in range(1, q):
            m = la[:, None] + log_t(k - 1)
            mx = m.max(axis=0)
            la = mx + np.log(np.exp(m - mx).sum(axis=0)) + log_e[k]
            la = la - la.max()
            pick[k] = int(np.argmax(la))
    else:
        delta, back = log_e[0], []
        for k in range(1, q):
            m = delta[:, None] + log_t(k - 1)
            back.append(np.argmax(m, axis=0))
            delta = m.max(axis=0) + log_e[k]
        pick[-1] = int(np.argmax(delta))
        for k in range(q - 1, 0, -1):
            pick[k - 1] = int(back[k - 1][pick[k]])
    xy = np.array([pos[k][pick[k]] for k in range(q)])
    on = np.array([off[k][pick[k]] == 0.0 for k in range(q)])
    return xy, on


def bend_track(state_t_s, states_xy_m, query_t_s, query_xy_m, causal: bool) -> np.ndarray:
    """The states moved by each query's correction (query position minus the states at its time): linear in time
    between query times and held outside them (offline), or the latest earlier query's held (``causal``; none
    before the first query time). Only what is drawn: the variants are scored at the query positions."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    x = np.asarray(states_xy_m, dtype=np.float64)
    tq = np.asarray(query_t_s, dtype=np.float64)
    if tq.size == 0:
        return x.copy()
    base_q = np.column_stack([np.interp(tq, ts, x[:, 0]), np.interp(tq, ts, x[:, 1])])
    corr = np.asarray(query_xy_m, dtype=np.float64) - base_q
    if causal:
        i = np.searchsorted(tq, ts, side="right") - 1
        c = np.where((i >= 0)[:, None], corr[np.maximum(i, 0)], 0.0)
    else:
        c = np.column_stack([np.interp(ts, tq, corr[:, 0]), np.interp(ts, tq, corr[:, 1])])
    return x + c


def grid_queries(problem, base_states_xy_m, query_t_s, points_m, off_share: float, causal: bool):
    """:func:`grid_hmm` on top of a base track of ``problem`` (:class:`~ilocalg.track.estimators.TrackProblem`):
    the base states at ``query_t_s`` (linear between states), the PDR of ``problem.disp_m`` and its step count at
    the same times, ``problem.step_var_m2``, and the base's error variance from ``problem.fix_corr`` (``var_b``,
    the persistent fix error) or else the mean fix variance. ``query_t_s`` must increase. Returns
    ``(positions (q, 2), on_point (q,))``."""
    ts = np.asarray(problem.state_t_s, dtype=np.float64)
    tq = np.asarray(query_t_s, dtype=np.float64)
    if tq.size > 1 and np.any(np.diff(tq) < 0):
        raise ValueError("grid_queries: the query times must not decrease")
    x = np.asarray(base_states_xy_m, dtype=np.float64)
    est = np.column_stack([np.interp(tq, ts, x[:, 0]), np.interp(tq, ts, x[:, 1])])
    cum = np.vstack([[0.0, 0.0], np.cumsum(problem.disp_m, axis=0)])
    pdr = np.column_stack([np.interp(tq, ts, cum[:, 0]), np.interp(tq, ts, cum[:, 1])])
    n = np.interp(tq, ts, np.arange(ts.size, dtype=np.float64))
    fc = problem.fix_corr
    var = float(fc[2]) if fc is not None and float(fc[2]) > 0 else float(np.mean(problem.fix_var_at()))
    return grid_hmm(est, pdr, n, points_m, var, problem.step_var_m2, off_share, causal)
