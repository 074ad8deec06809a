"""Trajectory estimators of one walk behind one interface: a :class:`TrackProblem` in, states out.

A :class:`TrackProblem` holds what every estimator may use: the step states' times, each step's PDR
displacement in the map frame (step length x heading, floor offset applied) with its per-axis
variance, the Wi-Fi fixes with their variance, and optionally the walkable raster. An estimator is a
function ``problem -> (n+1, 2)`` positions of the states, registered in :data:`ESTIMATORS` with
whether it is causal (the state at time t uses the data up to t only: the online case) or uses the
whole walk (offline). Each runs alone: ``ESTIMATORS["lsq"].fn(problem)``.

Least squares (:func:`lsq_track`)
    One sparse linear system per walk (the core of the 2021 Indoor Location & Navigation winners):
    the unknowns are the states' positions; each step gives ``p[i+1] - p[i] = d[i]`` with weight
    ``1 / step_var``, each fix ``(1 - a) p[j] + a p[j+1] = z`` (the fix time between states j and
    j+1) with weight ``1 / fix_var``; x and y share the matrix. Fixes far off the track are
    down-weighted by iteratively re-weighted least squares with Huber's weights (c = 1.345 sd,
    Huber 1981). Optionally (``rotate=True``) the whole walk's PDR heading is first rotated onto the
    fixes (one angle per walk, Huber-robust; :func:`ilocalg.fusion.heading_offset.fit_track_to_fixes`):
    off by default, since on site1 F1 (10 walks, leave-one-walk-out) it raised the mean error from
    2.83 m to 3.23 m (the floor offset learned from the other walks is the better heading).
Causal least squares (:func:`lsq_causal_track`)
    The same system solved at every fix with the data so far (rotation: fitted on the fixes so far
    once there are three); between fixes the last solved state is dead-reckoned; before the first fix
    is known, the PDR track passes through the first fix at that fix's time. For a linear
    Gaussian model the last state of the batch solution is the Kalman filter's estimate; the
    robust weights and the per-walk rotation are what it adds.
Start-up with a declared latency (not causal; each its own variant)
    Every online variant (and the Wi-Fi-only track) reports a time before the first fix is known only
    once it is (the PDR track placed through that fix: backward PDR). Beyond that, two variants wait on
    purpose: a delayed start (``kf_gain_map_start5s``, ``lsq_online_map_start5s``: the states until
    :data:`STARTUP_DELAY_S` after the first fix is known are re-estimated from the data known then, the
    Kalman filter's by a fixed-interval RTS pass, the least squares by one solve; every later state is the
    causal variant's) and a fixed lag (``kf_gain_map_lag5s``: every state from the data up to 5 s after it,
    then moved onto the map). Their latencies are in :data:`ilocalg.track.LATENCY_METHODS`.
Map step (:func:`snap_to_map`, ``*_map``)
    States off the walkable raster are pulled to the nearest walkable cell: those cells become
    extra absolute constraints (variance ``cell_m^2``) and the system is solved again (three
    rounds), then any state still off the map is moved onto it.

References
----------
Huber P. J., Robust Statistics, Wiley (1981), the Huber weights; Kaggle Indoor Location & Navigation
(2021), winning solutions' "cost minimisation" of Wi-Fi fixes and relative PDR displacements;
Rauch, Tung, Striebel, AIAA J. 3(8) (1965), batch least squares and smoothing.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.ndimage import distance_transform_edt
from scipy.sparse.linalg import splu

from ilocalg.fusion.heading_offset import fit_track_to_fixes, rotate_xy

__all__ = ["TrackProblem", "Estimator", "ESTIMATORS", "lsq_solve", "lsq_track", "lsq_causal_track", "snap_to_map",
           "map_snapper", "kf_gain_track", "kf_gain_map_track", "kf_gain_lag_track", "KF_GAIN_LAG_S", "HUBER_C",
           "kf_gain_map_lag_track", "kf_gain_map_start_track", "lsq_online_map_start_track", "startup_until_s",
           "STARTUP_DELAY_S", "lsq_paths_track", "lsq_gain_solve", "PATH_ROUNDS", "STATES_USED_METHODS"]

#: The estimators that honour :attr:`TrackProblem.states_used` (the causal least squares and its map variants).
STATES_USED_METHODS = ("lsq_online", "lsq_online_map", "lsq_online_map_start5s")

#: Huber's constant (in standard deviations): 95 % efficiency under Gaussian errors (Huber 1981).
HUBER_C = 1.345


@dataclass(frozen=True)
class TrackProblem:
    """Inputs of a trajectory estimator (frames: the database's map frame, metres).

    state_t_s : (n+1,) state times (log start, then each step), increasing.
    disp_m : (n, 2) PDR displacement of each step (floor heading offset applied).
    step_var_m2 : per-axis variance of one step's displacement error.
    fix_t_s, fix_xy_m : (m,), (m, 2) Wi-Fi fixes.
    fix_var_m2 : per-axis variance of a fix's error: one for all fixes, or (m,) one per fix (its own
        measured quality, :class:`ilocalg.track.fixes.FixVarModel`).
    grid : walkable raster (:class:`ilocalg.fusion.particle_filter.OccupancyGrid`) or None.
    fix_avail_t_s : (m,) when each fix becomes known (the scan time; default ``fix_t_s``), in increasing
        order; ``fix_t_s`` is the time it describes (its readings' time), at or before it. The causal
        estimators use a fix from its availability on, for the state of its readings' time.
    gain : :class:`ilocalg.track.motion.GainStats` or None: the spread of a walk's own step scale and
        heading offset, measured on the other walks; needed by the ``kf_gain*`` estimators.
    map_start : the online map variants (``lsq_online_map``, ``kf_gain_map``) start from the first fix's
        walkable posterior (:func:`map_first_fix`) rather than the fix itself.
    fix_corr : ``(c0, rho, var_b_m2)``: the share of a fix's error correlated from fix to fix, its correlation
        and its per-axis variance
        (:func:`ilocalg.track.fixes.fix_error_correlation`, measured on the database walks); the ``kf_gain*``
        estimators carry it as a state, the least-squares ones as unknowns. None: fix errors independent.
    paths : the walked-path graph of the database walks (:class:`ilocalg.track.paths.WalkedPaths`, never
        holding the scored walk) or None; needed by the ``lsq_paths*`` estimators.
    path_var_m2 : per-axis variance of a position constrained to ``paths`` (default:
        :meth:`~ilocalg.track.paths.WalkedPaths.spread_var_m2`, measured leave-one-walk-out on its walks).
    states_used : indices of the states whose estimates are used (e.g. those around the times a walk is scored
        at), or None (every state). The causal least squares (``lsq_online*``) then solves only at the fixes
        those states depend on and leaves the other states NaN; every state it returns is the same number as
        without it. The other estimators ignore it.
    """

    state_t_s: np.ndarray
    disp_m: np.ndarray
    step_var_m2: float
    fix_t_s: np.ndarray
    fix_xy_m: np.ndarray
    fix_var_m2: float | np.ndarray
    grid: object | None = None
    fix_avail_t_s: np.ndarray | None = None
    gain: object | None = None
    map_start: bool = False
    fix_corr: tuple | None = None
    paths: object | None = None
    path_var_m2: float | None = None
    states_used: np.ndarray | None = None

    def fix_var_at(self, sel=slice(None)) -> np.ndarray:
        """Per-axis variance of the fixes ``sel`` (an index, slice or mask of the fixes), one per fix."""
        fv = np.asarray(self.fix_var_m2, dtype=np.float64)
        return np.broadcast_to(fv, np.asarray(self.fix_t_s).shape)[sel]

    def __post_init__(self):
        n = np.asarray(self.state_t_s).size
        if np.asarray(self.disp_m).shape != (n - 1, 2):
            raise ValueError(f"disp_m must have shape ({n - 1}, 2) for {n} states, got {np.shape(self.disp_m)}")
        if np.asarray(self.fix_xy_m).shape != (np.asarray(self.fix_t_s).size, 2):
            raise ValueError("fix_xy_m must have shape (len(fix_t_s), 2)")
        fv = np.asarray(self.fix_var_m2, dtype=np.float64)
        if fv.ndim > 1 or (fv.ndim == 1 and fv.size != np.asarray(self.fix_t_s).size):
            raise ValueError(f"fix_var_m2 must be a scalar or have shape (len(fix_t_s),), got {fv.shape}")
        if not (self.step_var_m2 > 0 and np.all(fv > 0)):
            raise ValueError(f"step_var_m2 and fix_var_m2 must be > 0, got {self.step_var_m2}, {self.fix_var_m2}")
        if np.asarray(self.fix_t_s).size < 1:
            raise ValueError("a track needs at least one Wi-Fi fix")
        if self.fix_avail_t_s is not None and np.shape(self.fix_avail_t_s) != np.shape(self.fix_t_s):
            raise ValueError("fix_avail_t_s must have the shape of fix_t_s")
        if self.states_used is not None:
            u = np.asarray(self.states_used)
            if u.ndim != 1 or u.dtype.kind not in "iu" or (u.size and (u.min() < 0 or u.max() >= n)):
                raise ValueError(f"states_used must be indices of the {n} states, got {self.states_used!r}")


def _interp_rows(state_t_s, t_s):
    """Index j and weight a of each time between states j and j+1 (clamped to the span)."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    t = np.clip(np.asarray(t_s, dtype=np.float64), ts[0], ts[-1])
    j = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, max(ts.size - 2, 0))
    if ts.size < 2:
        return j, np.zeros(t.size)
    a = (t - ts[j]) / np.maximum(ts[j + 1] - ts[j], 1e-12)
    return j, np.clip(a, 0.0, 1.0)


def lsq_solve(n_states: int, disp_m, step_var_m2: float, fix_j, fix_a, fix_xy_m, fix_var_m2,
              anchor_idx=(), anchor_xy_m=None, anchor_var_m2: float = 1.0, n_iter: int = 5,
              fix_corr=None) -> np.ndarray:
    """Solve the walk's sparse least-squares system (see the module docstring); returns (n_states, 2).

    ``fix_var_m2`` may be a scalar or one value per fix; ``anchor_*``: extra absolute constraints on
    states (the map step). Huber re-weighting of the fixes over ``n_iter`` rounds (1: plain weighted LS),
    on each fix's whole error in its whole sd.
    ``fix_corr`` ``(c0, rho, var_b_m2)``: the fixes' correlated error as unknowns ``b_i`` appended after the
    states (fix rows ``... + b_i = z_i`` with the white variance ``(1 - c0) fix_var``; ``b_0 = 0`` with
    ``var_b_m2``, ``b_i - rho b_{i-1} = 0`` with ``var_b_m2 (1 - rho^2)``; Bryson & Henrikson 1968), as the
    ``kf_gain`` filter carries them. None (or no fix): no such unknowns, every fix error white.
    """
    n, m = n_states, len(fix_j)
    corr = fix_corr is not None and m > 0
    c0, rho, var_b = (float(v) for v in fix_corr) if corr else (0.0, 0.0, 0.0)
    nb = m if corr else 0                                   # the bias unknowns, after the states
    d = np.asarray(disp_m, dtype=np.float64).reshape(-1, 2)
    k = d.shape[0]
    anchor_idx = np.asarray(anchor_idx, dtype=np.int64)
    na = anchor_idx.size
    fj = np.asarray(fix_j)
    fa = np.asarray(fix_a, dtype=np.float64)
    # rows: steps, fixes, anchors, then (correlated errors) the bias chain
    fix_cols = [fj, np.minimum(fj + 1, n - 1)] + ([n + np.arange(m)] if corr else [])
    fix_vals = [1.0 - fa, fa] + ([np.ones(m)] if corr else [])
    rows = [np.repeat(np.arange(k), 2), k + np.repeat(np.arange(m), len(fix_cols)), k + m + np.arange(na)]
    cols = [np.column_stack([np.arange(k), np.arange(k) + 1]).ravel(), np.column_stack(fix_cols).ravel(), anchor_idx]
    vals = [np.tile([-1.0, 1.0], k), np.column_stack(fix_vals).ravel(), np.ones(na)]
    if corr:
        rows += [k + m + na + np.array([0]), k + m + na + np.repeat(np.arange(1, m), 2)]
        cols += [np.array([n]), np.column_stack([n + np.arange(m - 1), n + np.arange(1, m)]).ravel()]
        vals += [np.ones(1), np.tile([-rho, 1.0], m - 1)]
    A = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(k + m + na + nb, n + nb))
    b = np.concatenate([d, np.asarray(fix_xy_m, dtype=np.float64).reshape(-1, 2),
                        np.zeros((0, 2)) if na == 0 else np.asarray(anchor_xy_m, dtype=np.float64).reshape(-1, 2),
                        np.zeros((nb, 2))])
    white = (1.0 - c0) * np.broadcast_to(np.asarray(fix_var_m2, dtype=np.float64), (m,))
    if corr:
        var_b = max(var_b, 1e-9)
        w_chain = np.concatenate([[1.0 / var_b], np.full(m - 1, 1.0 / (var_b * max(1.0 - rho ** 2, 1e-9)))])
    else:
        w_chain = np.zeros(0)
    # the fix weights and sds rounded as the two former solvers did, so both cases stay bit-identical to them
    w0 = 1.0 / white
    sd_fix = np.sqrt(white + var_b) if corr else np.sqrt(1.0 / w0)
    hub = np.ones(m)
    x = None
    ridge = sp.identity(n + nb, format="csc") * 1e-9
    A_fix, At = A[k:k + m, :n], A.T
    for _ in range(max(n_iter, 1)):
        w_fix = hub / white if corr else w0 * hub
        w = np.concatenate([np.full(k, 1.0 / step_var_m2), w_fix, np.full(na, 1.0 / anchor_var_m2), w_chain])
        AtW = At.multiply(w).tocsr()
        # one factorisation for both axes: the same SuperLU factors and triangular solves as a spsolve per axis
        lu = splu((AtW @ A).tocsc() + ridge)
        x = np.column_stack([lu.solve(AtW @ b[:, 0]), lu.solve(AtW @ b[:, 1])])
        if m == 0:
            break
        res = np.hypot(*((A_fix @ x[:n]) - b[k:k + m]).T) / sd_fix
        new = np.minimum(1.0, HUBER_C / np.maximum(res, 1e-12))
        if np.allclose(new, hub, atol=1e-3):
            break
        hub = new
    return x[:n]


def _rotation(problem: TrackProblem, upto: int | None = None) -> float:
    """Angle (rad) rotating the PDR track onto the fixes (Huber-robust, translation free); 0 with < 3 fixes."""
    ft, fxy = problem.fix_t_s[:upto], problem.fix_xy_m[:upto]
    if ft.size < 3:
        return 0.0
    rel = np.vstack([[0.0, 0.0], np.cumsum(problem.disp_m, axis=0)])
    j, a = _interp_rows(problem.state_t_s, ft)
    at = rel[j] * (1 - a)[:, None] + rel[np.minimum(j + 1, rel.shape[0] - 1)] * a[:, None]
    return float(fit_track_to_fixes(at, fxy, huber_m=2.0 * np.sqrt(np.median(problem.fix_var_at(slice(upto)))))
                 .angle_rad)


def lsq_track(problem: TrackProblem, rotate: bool = False, n_iter: int = 5) -> np.ndarray:
    """Whole-walk (offline) least-squares track of :class:`TrackProblem` (module docstring)."""
    disp = rotate_xy(problem.disp_m, _rotation(problem)) if rotate else problem.disp_m
    j, a = _interp_rows(problem.state_t_s, problem.fix_t_s)
    return lsq_solve(problem.state_t_s.size, disp, problem.step_var_m2, j, a, problem.fix_xy_m, problem.fix_var_m2,
                     n_iter=n_iter, fix_corr=problem.fix_corr)


def lsq_causal_track(problem: TrackProblem, rotate: bool = False, n_iter: int = 5) -> np.ndarray:
    """Online least-squares track: each state from the data up to its time only (module docstring).

    Solved once per problem (:func:`_shared`): ``lsq_online_map`` and ``lsq_online_map_start5s`` start from the same
    map-started problem, and without the map at start-up ``lsq_online`` too."""
    return _shared(problem, ("lsq_causal", bool(rotate), int(n_iter)),
                   lambda: _lsq_causal_track(problem, rotate, n_iter)).copy()


def _lsq_causal_track(problem: TrackProblem, rotate: bool, n_iter: int) -> np.ndarray:
    ts = problem.state_t_s
    n = ts.size
    out = np.full((n, 2), np.nan)
    ft = problem.fix_t_s
    known_t = ft if problem.fix_avail_t_s is None else problem.fix_avail_t_s
    # the state index at or after which each fix is known (a fix known at t is used from the first state >= t)
    avail = np.searchsorted(ts, known_t, side="left")
    cum = np.vstack([[0.0, 0.0], np.cumsum(problem.disp_m, axis=0)])
    # before the first solve: the PDR track placed so that it passes through the first fix at that fix's
    # time (the first fix moved back along the steps), the start every online variant shares
    last_i, last_disp = 0, problem.disp_m
    last_xy = problem.fix_xy_m[0] - (_track_at_cum(ts, cum, ft[:1])[0] - cum[0])
    out[0] = last_xy
    solve_at = np.zeros(n, dtype=bool)             # a new fix arrived at state i: solve on 0..i
    q = 0
    for i in range(n):
        while q < ft.size and avail[q] <= i:
            q += 1
        solve_at[i] = bool(q) and (i == 0 or avail[q - 1] == i)
    used = needed = None
    if problem.states_used is not None:     # only the solves the used states rest on (the last one at or before each)
        used = np.zeros(n, dtype=bool)
        used[np.asarray(problem.states_used, dtype=np.int64)] = True
        last_solve = np.maximum.accumulate(np.where(solve_at, np.arange(n), -1))[used]
        needed = np.zeros(n, dtype=bool)
        needed[last_solve[last_solve >= 0]] = True
    rel = None
    q = 0
    for i in range(n):
        while q < ft.size and avail[q] <= i:
            q += 1
        if solve_at[i]:
            if needed is not None and not needed[i]:
                continue                                  # no used state rests on this solve
            disp = rotate_xy(problem.disp_m, _rotation(problem, q)) if rotate else problem.disp_m
            j, a = _interp_rows(ts[:i + 1], ft[:q])
            if i == 0:
                wq = 1.0 / problem.fix_var_at(slice(q))          # the fixes' weighted mean (plain mean: one var)
                x = (wq[:, None] * problem.fix_xy_m[:q]).sum(axis=0, keepdims=True) / wq.sum()
            else:
                x = lsq_solve(i + 1, disp[:i], problem.step_var_m2, j, a, problem.fix_xy_m[:q],
                              problem.fix_var_at(slice(q)), n_iter=n_iter, fix_corr=problem.fix_corr)
            last_i, last_xy, last_disp, rel = i, x[-1], disp, None
            out[i] = last_xy
        elif used is None or used[i]:                     # dead-reckon from the last solved state
            if rel is None:                               # the steps of the last solve, summed once per solve
                rel = np.vstack([[0.0, 0.0], np.cumsum(last_disp, axis=0)])
            out[i] = last_xy + rel[i] - rel[last_i]
    if used is not None:
        out[~used] = np.nan
    return out


def _track_at_cum(state_t_s, cum, t_s):
    """Cumulative PDR displacement at times ``t_s`` (linear between states, held outside)."""
    return np.column_stack([np.interp(t_s, state_t_s, cum[:, 0]), np.interp(t_s, state_t_s, cum[:, 1])])


def map_snapper(grid) -> Callable:
    """``snap(xy_m) -> (snapped (n, 2), moved (n,) bool)``: the nearest walkable cell centre of every point off
    the walkable raster (points on it unchanged; points outside the raster's extent clamped to it first),
    the raster's distance transform computed once."""
    mask = grid.walkable_mask
    if not mask.any():
        raise ValueError("the walkable raster has no walkable cell")
    _, (ii, jj) = distance_transform_edt(~mask, return_indices=True)
    c = grid.cell_m

    def snap(xy_m):
        xy = np.asarray(xy_m, dtype=np.float64).reshape(-1, 2)
        col = np.clip(np.floor((xy[:, 0] - grid.x0_m) / c).astype(np.int64), 0, mask.shape[1] - 1)
        row = np.clip(np.floor((xy[:, 1] - grid.y0_m) / c).astype(np.int64), 0, mask.shape[0] - 1)
        inside_extent = ((xy[:, 0] >= grid.x0_m) & (xy[:, 0] < grid.x0_m + c * mask.shape[1])
                         & (xy[:, 1] >= grid.y0_m) & (xy[:, 1] < grid.y0_m + c * mask.shape[0]))
        moved = ~(mask[row, col] & inside_extent)
        out = xy.copy()
        r2, c2 = ii[row[moved], col[moved]], jj[row[moved], col[moved]]
        out[moved] = np.column_stack([grid.x0_m + (c2 + 0.5) * c, grid.y0_m + (r2 + 0.5) * c])
        return out, moved

    return snap


#: The snappers of the latest rasters (id -> (raster, snapper)): a floor's distance transform is computed once
#: for all its walks and map steps. The raster is kept with its snapper, so its id stays its own.
_SNAPPERS: dict = {}


#: What the estimators of the latest problems share (id -> (problem, its fingerprint, {step: result})): the causal
#: least squares, the gain filter and the map-started problem, each computed once per problem (:func:`_shared`).
_SHARED: dict = {}
#: How many problems :data:`_SHARED` keeps (a walk has two: its own and the map-started one).
_SHARED_KEPT = 4


def _fingerprint(problem: TrackProblem) -> bytes:
    """A digest of the problem's array contents (its other fields count by identity): a problem whose arrays were
    changed in place after a shared step is not served that step's stale result."""
    h = hashlib.blake2b(digest_size=16)
    for f in dataclasses.fields(problem):
        v = getattr(problem, f.name)
        if v is None or isinstance(v, (bool, int, float, np.ndarray, tuple, list)):
            a = np.asarray(v if v is not None else np.nan, dtype=np.float64)
            h.update(f.name.encode() + str(a.shape).encode() + np.ascontiguousarray(a).tobytes())
        else:
            h.update(f"{f.name}:{id(v)}".encode())
    return h.digest()


def _shared(problem: TrackProblem, key, make: Callable):
    """``make()``, computed once per problem and ``key`` and kept for the latest :data:`_SHARED_KEPT` problems (the
    problem kept with it, so its id stays its own); the result is shared: callers must not change it."""
    fp = _fingerprint(problem)
    hit = _SHARED.get(id(problem))
    if hit is None or hit[0] is not problem or hit[1] != fp:
        _SHARED.pop(id(problem), None)
        while len(_SHARED) >= _SHARED_KEPT:
            _SHARED.pop(next(iter(_SHARED)))
        hit = _SHARED[id(problem)] = (problem, fp, {})
    memo = hit[2]
    if key not in memo:
        memo[key] = make()
    return memo[key]


def snap_to_map(xy_m, grid) -> tuple[np.ndarray, np.ndarray]:
    """Nearest walkable cell centre of every point off the walkable raster (points on it are unchanged).

    Returns ``(snapped (n, 2), moved (n,) bool)``; points outside the raster's extent are clamped to it
    first (:func:`map_snapper`, kept for the latest few rasters).
    """
    hit = _SNAPPERS.get(id(grid))
    if hit is None or hit[0] is not grid:
        if len(_SNAPPERS) >= 4:
            _SNAPPERS.pop(next(iter(_SNAPPERS)))
        hit = _SNAPPERS[id(grid)] = (grid, map_snapper(grid))
    return hit[1](xy_m)


def _snap_finite(xy_m, grid) -> np.ndarray:
    """:func:`snap_to_map` of the finite states (a state snaps alone); the NaN states a problem's ``states_used``
    left out stay NaN."""
    xy = np.asarray(xy_m, dtype=np.float64)
    ok = np.isfinite(xy).all(axis=1)
    if ok.all():
        return snap_to_map(xy, grid)[0]
    out = xy.copy()
    out[ok] = snap_to_map(xy[ok], grid)[0]
    return out


def walkable_posterior(mean_m, cov_m2, grid, n_sd: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
    """Mean (2,) and covariance (2, 2) of a position known as ``N(mean_m, cov_m2)`` and known to lie on the
    walkable raster (a uniform prior over its walkable cells): the Gaussian's weights on the walkable cell
    centres within ``n_sd`` standard deviations, normalised (Bayes' rule on the cells; the covariance gets
    a cell's own ``cell_m^2 / 12`` per axis). Without a walkable cell there: the nearest walkable cell
    (:func:`snap_to_map`) with ``cov_m2``.

    References
    ----------
    Thrun S., Burgard W., Fox D., Probabilistic Robotics, MIT Press (2005), sec. 8.3.3 (a map as a prior on
    the pose: poses off free space have zero probability).
    """
    m = np.asarray(mean_m, dtype=np.float64).reshape(2)
    C = np.asarray(cov_m2, dtype=np.float64).reshape(2, 2)
    mask, c = grid.walkable_mask, grid.cell_m
    half = n_sd * np.sqrt(np.diag(C))
    i0 = max(int(np.floor((m[0] - half[0] - grid.x0_m) / c)), 0)
    i1 = min(int(np.ceil((m[0] + half[0] - grid.x0_m) / c)) + 1, mask.shape[1])
    j0 = max(int(np.floor((m[1] - half[1] - grid.y0_m) / c)), 0)
    j1 = min(int(np.ceil((m[1] + half[1] - grid.y0_m) / c)) + 1, mask.shape[0])
    if i1 > i0 and j1 > j0:
        jj, ii = np.nonzero(mask[j0:j1, i0:i1])
        xy = np.column_stack([grid.x0_m + (ii + i0 + 0.5) * c, grid.y0_m + (jj + j0 + 0.5) * c])
        r = xy - m
        d2 = np.einsum("ni,ij,nj->n", r, np.linalg.inv(C), r)
        inside = d2 <= n_sd ** 2
        if inside.any():
            w = np.exp(-0.5 * d2[inside])
            w /= w.sum()
            mu = w @ xy[inside]
            dv = xy[inside] - mu
            return mu, (w[:, None] * dv).T @ dv + np.eye(2) * c ** 2 / 12.0
    return snap_to_map(m, grid)[0][0], C


def _with_map(problem: TrackProblem, xy: np.ndarray, solve_anchored: Callable, rounds: int = 3) -> np.ndarray:
    if problem.grid is None:
        raise ValueError("the map step needs the floor's walkable raster (TrackProblem.grid)")
    anchors = {}
    for _ in range(rounds):
        snapped, moved = snap_to_map(xy, problem.grid)
        if not moved.any():
            return xy
        for i in np.flatnonzero(moved):
            anchors[int(i)] = snapped[i]
        idx = np.array(sorted(anchors))
        xy = solve_anchored(idx, np.array([anchors[i] for i in idx]))
    return snap_to_map(xy, problem.grid)[0]


def lsq_map_track(problem: TrackProblem) -> np.ndarray:
    """:func:`lsq_track` then the map step (offline)."""
    disp = problem.disp_m
    j, a = _interp_rows(problem.state_t_s, problem.fix_t_s)

    def solve(idx, anc):
        return lsq_solve(problem.state_t_s.size, disp, problem.step_var_m2, j, a, problem.fix_xy_m,
                         problem.fix_var_m2, anchor_idx=idx, anchor_xy_m=anc,
                         anchor_var_m2=problem.grid.cell_m ** 2, fix_corr=problem.fix_corr)

    return _with_map(problem, solve(np.zeros(0, dtype=np.int64), None), solve)


def map_first_fix(problem: TrackProblem) -> TrackProblem:
    """The problem with its first fix replaced by that fix's walkable posterior (:func:`walkable_posterior`:
    the fix and its variance, the walkable raster as the prior), its variance the posterior's mean per-axis
    variance: the map at start-up, when the track rests on that one fix (causal: it uses that fix only)."""
    if problem.grid is None:
        raise ValueError("the map step needs the floor's walkable raster (TrackProblem.grid)")
    # the same object for the same problem (:func:`_shared`), so the estimators started from it share their steps
    return _shared(problem, "map_first_fix", lambda: _map_first_fix(problem))


def _map_first_fix(problem: TrackProblem) -> TrackProblem:
    fv = np.array(problem.fix_var_at(), dtype=np.float64)
    mu, S = walkable_posterior(problem.fix_xy_m[0], np.eye(2) * fv[0], problem.grid)
    xy = np.array(problem.fix_xy_m, dtype=np.float64)
    xy[0] = mu
    fv[0] = max(float(np.trace(S)) / 2.0, problem.grid.cell_m ** 2 / 12.0)
    return dataclasses.replace(problem, fix_xy_m=xy, fix_var_m2=fv)


def lsq_causal_map_track(problem: TrackProblem, map_start: bool | None = None) -> np.ndarray:
    """:func:`lsq_causal_track`, each state then moved onto the walkable raster (causal: a state's snap uses
    only that state); with ``map_start`` (default ``problem.map_start``) the first fix first replaced by its
    walkable posterior (:func:`map_first_fix`)."""
    if problem.grid is None:
        raise ValueError("the map step needs the floor's walkable raster (TrackProblem.grid)")
    if problem.map_start if map_start is None else map_start:
        problem = map_first_fix(problem)
    return _snap_finite(lsq_causal_track(problem), problem.grid)


def _gain_kf_result(problem: TrackProblem):
    """:func:`ilocalg.track.online_kf.gain_kf` of the problem, run once per problem (:func:`_shared`: the
    ``kf_gain*`` variants of one walk share two filters, with and without the map at start-up); read-only."""
    g = problem.gain
    if g is None:
        raise ValueError("the kf_gain estimators need the measured gain spread (TrackProblem.gain, "
                         "ilocalg.track.motion.gain_stats on the other walks)")
    return _shared(problem, "gain_kf", lambda: _gain_kf_run(problem))


def _gain_kf_run(problem: TrackProblem):
    from ilocalg.track.online_kf import gain_kf

    g = problem.gain
    return gain_kf(problem.state_t_s, problem.disp_m, problem.fix_t_s, problem.fix_xy_m, problem.fix_var_m2,
                   g.step_var_m2, g.gain_var, g.gain_walk_var, fix_avail_t_s=problem.fix_avail_t_s,
                   fix_corr=problem.fix_corr)


def kf_gain_track(problem: TrackProblem) -> np.ndarray:
    """The gain-augmented Kalman filter (:func:`ilocalg.track.online_kf.gain_kf`), causal."""
    return _gain_kf_result(problem).xy_m.copy()


def kf_gain_map_track(problem: TrackProblem, map_start: bool | None = None) -> np.ndarray:
    """:func:`kf_gain_track`, each state then moved onto the walkable raster (causal); with ``map_start``
    (default ``problem.map_start``) the filter started from the first fix's walkable posterior
    (:func:`map_first_fix`)."""
    if problem.grid is None:
        raise ValueError("the map step needs the floor's walkable raster (TrackProblem.grid)")
    if problem.map_start if map_start is None else map_start:
        problem = map_first_fix(problem)
    return snap_to_map(kf_gain_track(problem), problem.grid)[0]


#: The lag of the fixed-lag smoothed variant ``kf_gain_lag5s`` (seconds): a display that trails the walker by
#: 5 s. Liao et al. (2016), L481, advise online smoothing windows "larger than 5 s but not beyond 20 s"; the
#: shortest is taken. Not causal; reported as its own variant beside the strictly causal ``kf_gain``.
KF_GAIN_LAG_S = 5.0


def kf_gain_lag_track(problem: TrackProblem, lag_s: float = KF_GAIN_LAG_S) -> np.ndarray:
    """:func:`kf_gain_track` smoothed over a fixed lag (:func:`ilocalg.track.online_kf.gain_kf_lag`): each state
    from the data up to ``lag_s`` after it (not causal)."""
    from ilocalg.track.online_kf import gain_kf_lag

    return gain_kf_lag(_gain_kf_result(problem), problem.state_t_s, lag_s)


def kf_gain_map_lag_track(problem: TrackProblem, lag_s: float = KF_GAIN_LAG_S) -> np.ndarray:
    """:func:`kf_gain_lag_track` (started as :func:`kf_gain_map_track`), each state then moved onto the walkable
    raster: each state from the data up to ``lag_s`` after it (online with that declared latency; not causal)."""
    from ilocalg.track.online_kf import gain_kf_lag

    problem = _map_started(problem)
    return snap_to_map(gain_kf_lag(_gain_kf_result(problem), problem.state_t_s, lag_s), problem.grid)[0]


#: The delayed start of the ``*_start5s`` variants (seconds after the first fix is known): the start-up is
#: reported once this much data follows the first fix, every later state as the causal variant has it. The same
#: 5 s as :data:`KF_GAIN_LAG_S` (Liao et al. 2016, L481), not chosen on any result.
STARTUP_DELAY_S = 5.0


def startup_until_s(problem: TrackProblem, delay_s: float = STARTUP_DELAY_S) -> float:
    """When a delayed start reports the start-up: ``delay_s`` after the first fix is known (its availability)."""
    known = problem.fix_t_s if problem.fix_avail_t_s is None else problem.fix_avail_t_s
    return float(np.min(known)) + delay_s


def kf_gain_map_start_track(problem: TrackProblem, delay_s: float = STARTUP_DELAY_S) -> np.ndarray:
    """:func:`kf_gain_map_track` with a delayed start (:func:`ilocalg.track.online_kf.gain_kf_delayed_start`): the
    states up to :func:`startup_until_s` smoothed on the data up to then, each later state the causal filter's.
    Online with a declared latency at the start-up only (a state at ``t`` before then waits until then)."""
    from ilocalg.track.online_kf import gain_kf_delayed_start

    problem = _map_started(problem)
    xy = gain_kf_delayed_start(_gain_kf_result(problem), problem.state_t_s, startup_until_s(problem, delay_s))
    return snap_to_map(xy, problem.grid)[0]


def lsq_online_map_start_track(problem: TrackProblem, delay_s: float = STARTUP_DELAY_S) -> np.ndarray:
    """:func:`lsq_causal_map_track` with a delayed start: the states up to :func:`startup_until_s` from the least
    squares on the data known by then (:func:`lsq_solve`), each later state the causal variant's; then each
    state moved onto the walkable raster. Online with a declared latency at the start-up only."""
    problem = _map_started(problem)
    out = lsq_causal_track(problem)
    ts = problem.state_t_s
    until = startup_until_s(problem, delay_s)
    j = int(np.searchsorted(ts, until, side="right")) - 1
    known = problem.fix_t_s if problem.fix_avail_t_s is None else problem.fix_avail_t_s
    # the fixes known by state j (a fix is used from the first state at or after it is known)
    q = np.searchsorted(ts, known, side="left") <= j
    if j >= 1 and q.any():
        jj, a = _interp_rows(ts[:j + 1], problem.fix_t_s[q])
        out[:j + 1] = lsq_solve(j + 1, problem.disp_m[:j], problem.step_var_m2, jj, a, problem.fix_xy_m[q],
                                problem.fix_var_at(q), fix_corr=problem.fix_corr)
    return _snap_finite(out, problem.grid)


def _map_started(problem: TrackProblem) -> TrackProblem:
    """``problem`` with the map at start-up (:func:`map_first_fix`) when ``problem.map_start``; the raster needed."""
    if problem.grid is None:
        raise ValueError("the map step needs the floor's walkable raster (TrackProblem.grid)")
    return map_first_fix(problem) if problem.map_start else problem


#: Rounds of :func:`lsq_paths_track` (solve, project, re-solve); it stops earlier once no state moves by more than
#: :data:`PATH_TOL_M`. One: on the development walks (site1 F1 even, leave-one-walk-out, 379 waypoints, Wi-Fi only
#: 5.73 m) one round gave 0.582 x Wi-Fi only, two 0.585, five 0.591 (plain ``lsq`` 0.610).
PATH_ROUNDS = 1
PATH_TOL_M = 0.05


def lsq_paths_track(problem, rounds: int = PATH_ROUNDS, var_scale: float = 1.0, robust: bool = True,
                    snap: bool = False, gain: bool = False, map_step: bool = False) -> np.ndarray:
    """Offline least squares with the walked-path graph as a soft constraint (``lsq_paths``).

    The whole-walk least squares of :func:`lsq_track` (Wi-Fi fixes, PDR steps, correlated fix errors), then
    ``rounds`` times: every state projected onto the nearest segment of ``problem.paths``
    (:meth:`ilocalg.track.paths.WalkedPaths.project`), the system solved again with each projection as an
    absolute observation of its state with variance ``var_scale * problem.path_var_m2`` (measured: a walk's
    distance to the other walks' paths, :meth:`ilocalg.track.paths.WalkedPaths.spread_var_m2`). The projection
    moves a state across the path only, so the observation pulls it onto the path without holding it along it.
    ``robust``: a state far from every path (an area one walk crossed) gets Huber's weight
    (c = 1.345 sd, Huber 1981) on its distance (on: a priori; off changed nothing measurable on the development
    walks). ``snap``: the states finally moved onto the graph (hard).
    ``gain``: the walk's own step scale and heading bias solved with the track (:func:`lsq_gain_solve`, needs
    ``problem.gain``: its spread measured on the other walks); off: on the development walks (site1 F1 even,
    leave-one-walk-out) it raised the error (``lsq`` 0.610 -> 0.626 x Wi-Fi only, ``lsq_paths`` with five
    rounds 0.591 -> 0.627), as did ``snap`` (0.591 -> 0.596). ``map_step``: then the map step of
    ``lsq_map`` (:func:`lsq_map_track`: states off the walkable raster pulled onto it,
    the path observations kept).
    """
    paths = problem.paths
    if paths is None:
        raise ValueError("lsq_paths needs the walked-path graph of the database walks (TrackProblem.paths)")
    var = (paths.spread_var_m2() if problem.path_var_m2 is None else float(problem.path_var_m2)) * var_scale
    n = problem.state_t_s.size
    j, a = _interp_rows(problem.state_t_s, problem.fix_t_s)

    if gain and problem.gain is None:
        raise ValueError("lsq_paths with gain needs the measured gain spread (TrackProblem.gain)")

    def solve(idx=None, anc=None, anc_var=1.0):
        if gain:
            return lsq_gain_solve(problem, problem.gain.gain_var, anchor_idx=() if idx is None else idx,
                                  anchor_xy_m=anc, anchor_var_m2=anc_var)[0]
        return lsq_solve(n, problem.disp_m, problem.step_var_m2, j, a, problem.fix_xy_m, problem.fix_var_m2,
                         anchor_idx=() if idx is None else idx, anchor_xy_m=anc, anchor_var_m2=anc_var,
                         fix_corr=problem.fix_corr)

    x = solve()
    idx = np.arange(n)
    for _ in range(max(rounds, 0)):
        proj, dist, _ = paths.project(x)
        w = np.minimum(1.0, HUBER_C * np.sqrt(var) / np.maximum(dist, 1e-12)) if robust else np.ones(n)
        new = solve(idx, proj, var / w)
        done = np.max(np.hypot(*(new - x).T)) < PATH_TOL_M
        x = new
        if done:
            break
    if map_step:
        if problem.grid is None:
            raise ValueError("the map step needs the floor's walkable raster (TrackProblem.grid)")
        proj, dist, _ = paths.project(x)
        w = np.minimum(1.0, HUBER_C * np.sqrt(var) / np.maximum(dist, 1e-12)) if robust else np.ones(n)
        cell2 = problem.grid.cell_m ** 2

        def solve_map(mi, manc):
            return solve(np.concatenate([idx, mi]), np.vstack([proj, manc]),
                         np.concatenate([var / w, np.full(mi.size, cell2)]))

        x = _with_map(problem, x, solve_map)
    return paths.project(x)[0] if snap else x


def lsq_gain_solve(problem, gain_var: float, anchor_idx=(), anchor_xy_m=None, anchor_var_m2=1.0,
                   n_iter: int = 5) -> tuple[np.ndarray, complex]:
    """The whole-walk least squares with the walk's own PDR gain as an unknown: every step's displacement is
    ``g d_i`` with one complex ``g = s exp(i b)`` per walk (step scale ``s``, heading bias ``b`` beyond the
    floor calibration; linear in ``g``, so the system stays linear), ``g`` observed as 1 with per-component
    variance ``gain_var`` (:attr:`ilocalg.track.motion.GainStats.gain_var`, measured on the other walks).
    Fixes (with ``problem.fix_corr``'s correlated errors as unknowns), anchors and Huber re-weighting as in
    :func:`lsq_solve`. Returns ``((n, 2) states, g)``.
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import spsolve

    n = problem.state_t_s.size
    d = np.asarray(problem.disp_m, dtype=np.float64)
    k = d.shape[0]
    fj, fa = _interp_rows(problem.state_t_s, problem.fix_t_s)
    m = fj.size
    corr = problem.fix_corr is not None and m > 0
    c0, rho, var_b = (float(v) for v in problem.fix_corr) if corr else (0.0, 0.0, 0.0)
    ai = np.asarray(anchor_idx, dtype=np.int64)
    na = ai.size
    # unknowns: X (n), Y (n), ga, gb, then (correlated errors) Bx (m), By (m)
    G = 2 * n
    nu = 2 * n + 2 + (2 * m if corr else 0)
    r, c, v, rhs, wt = [], [], [], [], []
    row = 0
    ii = np.arange(k)
    for axis, (ca, cb) in enumerate(((-d[:, 0], d[:, 1]), (-d[:, 1], -d[:, 0]))):
        base = axis * n
        r += [row + ii] * 4
        c += [base + ii + 1, base + ii, np.full(k, G), np.full(k, G + 1)]
        v += [np.ones(k), -np.ones(k), ca, cb]
        rhs.append(np.zeros(k))
        wt.append(np.full(k, 1.0 / problem.step_var_m2))
        row += k
    r += [np.array([row]), np.array([row + 1])]
    c += [np.array([G]), np.array([G + 1])]
    v += [np.ones(1), np.ones(1)]
    rhs.append(np.array([1.0, 0.0]))
    wt.append(np.full(2, 1.0 / gain_var))
    row += 2
    fix_rows = []
    fi = np.arange(m)
    for axis in range(2):
        base = axis * n
        fix_rows.append(row + fi)
        r += [row + fi, row + fi]
        c += [base + fj, base + np.minimum(fj + 1, n - 1)]
        v += [1.0 - fa, fa]
        if corr:
            r.append(row + fi)
            c.append(G + 2 + axis * m + fi)
            v.append(np.ones(m))
        rhs.append(problem.fix_xy_m[:, axis])
        wt.append(np.zeros(m))                       # set per Huber round
        row += m
    for axis in range(2):
        r.append(row + np.arange(na))
        c.append(axis * n + ai)
        v.append(np.ones(na))
        rhs.append(np.zeros(na) if na == 0 else np.asarray(anchor_xy_m, dtype=np.float64)[:, axis])
        wt.append(np.broadcast_to(1.0 / np.asarray(anchor_var_m2, dtype=np.float64), (na,)).copy())
        row += na
    if corr:
        var_b = max(var_b, 1e-9)
        for axis in range(2):
            b0 = G + 2 + axis * m
            r += [np.array([row]), row + np.repeat(np.arange(1, m), 2)]
            c += [np.array([b0]), np.column_stack([b0 + np.arange(m - 1), b0 + np.arange(1, m)]).ravel()]
            v += [np.ones(1), np.tile([-rho, 1.0], m - 1)]
            rhs.append(np.zeros(m))
            wt.append(np.concatenate([[1.0 / var_b], np.full(m - 1, 1.0 / (var_b * max(1.0 - rho ** 2, 1e-9)))]))
            row += m
    A = sp.csr_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))), shape=(row, nu))
    b = np.concatenate(rhs)
    w = np.concatenate(wt)
    white = (1.0 - c0) * problem.fix_var_at()
    sd_fix = np.sqrt(white + var_b)
    hub = np.ones(m)
    u = None
    for _ in range(max(n_iter, 1)):
        w[fix_rows[0]] = w[fix_rows[1]] = hub / white
        AtW = A.T.multiply(w).tocsr()
        u = spsolve((AtW @ A).tocsc() + sp.identity(nu, format="csc") * 1e-9, AtW @ b)
        xy = np.column_stack([u[:n], u[n:G]])
        at = xy[fj] * (1 - fa)[:, None] + xy[np.minimum(fj + 1, n - 1)] * fa[:, None]
        res = np.hypot(*(at - problem.fix_xy_m).T) / sd_fix
        new = np.minimum(1.0, HUBER_C / np.maximum(res, 1e-12))
        if np.allclose(new, hub, atol=1e-3):
            break
        hub = new
    return np.column_stack([u[:n], u[n:G]]), complex(u[G], u[G + 1])


@dataclass(frozen=True)
class Estimator:
    """A registered trajectory estimator: ``fn(problem) -> (n+1, 2)``; ``causal``: online; ``needs_map``."""

    name: str
    fn: Callable
    causal: bool
    needs_map: bool
    doc: str


#: The least-squares estimators (name -> :class:`Estimator`); the ``evaluate track`` method keys.
ESTIMATORS = {e.name: e for e in (
    Estimator("lsq", lsq_track, False, False, "whole-walk least squares of Wi-Fi fixes and PDR steps"),
    Estimator("lsq_map", lsq_map_track, False, True, "lsq, then pulled onto the walkable map"),
    Estimator("lsq_online", lsq_causal_track, True, False, "least squares on the data so far (online)"),
    Estimator("lsq_online_map", lsq_causal_map_track, True, True, "lsq_online, each state moved onto the map"),
    Estimator("kf_gain", kf_gain_track, True, False,
              "Kalman filter with the walk's step scale and heading offset as states (online)"),
    Estimator("kf_gain_map", kf_gain_map_track, True, True, "kf_gain, each state moved onto the map (online)"),
    Estimator("kf_gain_lag5s", kf_gain_lag_track, False, False,
              "kf_gain smoothed over a fixed 5 s lag (online with 5 s delay; not causal)"),
    Estimator("kf_gain_map_lag5s", kf_gain_map_lag_track, False, True,
              "kf_gain_lag5s, each state moved onto the map (online with 5 s delay; not causal)"),
    Estimator("kf_gain_map_start5s", kf_gain_map_start_track, False, True,
              "kf_gain_map, the states until 5 s after the first fix smoothed on the data until then "
              "(online with a delayed start; not causal)"),
    Estimator("lsq_online_map_start5s", lsq_online_map_start_track, False, True,
              "lsq_online_map, the states until 5 s after the first fix solved on the data until then "
              "(online with a delayed start; not causal)"),
    Estimator("lsq_paths", lsq_paths_track, False, False,
              "lsq, iterated with each state pulled towards the database walks' paths (offline)"),
)}
