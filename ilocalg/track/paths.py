"""The walked-path graph of a floor: where the surveyed walks went, as line segments.

Every database walk's ground truth is a polyline through its waypoints; the segments between
consecutive waypoints of all the floor's walks form the graph (:class:`WalkedPaths`), built once per
floor. The database walks' own waypoints are legitimate data (the fingerprint database is built from
them); a scored walk's own waypoints are its truth and must never enter its estimate, so the graph of a
scored walk is :meth:`WalkedPaths.without` that walk (and :func:`ilocalg.track.evaluate_walk` refuses a
graph that contains it).

:meth:`WalkedPaths.project` moves points to the nearest point of the nearest segment (exact, brute
force over the segments in blocks: a site 1 floor has about 600 segments). :meth:`WalkedPaths.spread_var_m2`
measures how far a walk strays from the paths of the *other* walks (leave-one-walk-out: every walk's
polyline sampled every metre, its distance to the graph of the others), the variance of a position
constrained to the graph.

Without the walks themselves (a floor model read from its cache keeps the database only),
:meth:`WalkedPaths.from_database` builds the graph from the database scans' positions instead (each
walk's scans in time order; they lie on its waypoint polyline, except that a turn between two scans is
cut short).

Measured (development walks: site1 F1 even, leave-one-walk-out, 379 waypoints, Wi-Fi only 5.73 m): a walk's
per-axis spread around the other walks' paths is about 1.3 m sd (F1, all walks); ``lsq_paths`` 0.582 x Wi-Fi only
against ``lsq`` 0.610, but not better than the walkable-raster map step ``lsq_map`` (0.567); the map step after
``lsq_paths`` 0.582. A hidden Markov model over the graph's nodes (PDR transitions, Wi-Fi emissions, the posterior
mean per fix fed to the least squares) was tried and left out: 0.700 (0.913 with the emissions tempered by the
measured fix-error correlation); so was a global placement (the least-squares track translated, by a grid search
within 12 m, to where its states' Huber distance to the graph plus the fixes' common-error prior is least, then
the projection round): 0.918 with every state one observation, 0.587 with the walk one observation. On this
dense graph (about 100 walks) some path lies near any translated track, so the graph does not place a walk.

References
----------
Kaggle Indoor Location & Navigation (2021), winning solutions: snapping the optimised trajectory to the
graph of the training waypoints ("snap to grid" of the training paths); White C. E., Bernstein D.,
Kornhauser A. L., "Some map matching algorithms for personal navigation assistants", Transportation
Research C 8 (2000), point-to-curve projection; Newson P., Krumm J., ACM SIGSPATIAL GIS (2009), hidden
Markov map matching (the variant left out).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ilocalg.io.recording import as_recording
from ilocalg.io.schema import T_S, X_M, Y_M

__all__ = ["WalkedPaths", "SPREAD_STEP_M", "PATH_ROUNDS", "lsq_paths_track", "lsq_gain_solve"]

#: The spacing (m) at which :meth:`WalkedPaths.spread_var_m2` samples each walk's polyline.
SPREAD_STEP_M = 1.0
#: Points x segments per block of :meth:`WalkedPaths.project` (memory bound: ~8 arrays of this many floats).
_BLOCK = 1 << 20


@dataclass(frozen=True)
class WalkedPaths:
    """Segments ``a_m[i] -> b_m[i]`` (map frame, metres) of the walks ``walk[i]`` (module docstring)."""

    a_m: np.ndarray
    b_m: np.ndarray
    walk: np.ndarray
    _memo: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):
        a, b = np.asarray(self.a_m), np.asarray(self.b_m)
        if a.ndim != 2 or a.shape[1:] != (2,) or b.shape != a.shape or np.shape(self.walk) != (a.shape[0],):
            raise ValueError(f"WalkedPaths: a_m, b_m must be (n, 2) and walk (n,), got {a.shape}, {b.shape}, "
                             f"{np.shape(self.walk)}")

    @classmethod
    def from_polylines(cls, polylines: dict) -> WalkedPaths:
        """The graph of ``{walk name: (k, 2) points in walking order}`` (a polyline of < 2 points adds nothing)."""
        a, b, w = [], [], []
        for name, p in polylines.items():
            p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
            p = p[np.isfinite(p).all(axis=1)]
            if p.shape[0] >= 2:
                a.append(p[:-1])
                b.append(p[1:])
                w.append(np.full(p.shape[0] - 1, name, dtype=object))
        if not a:
            return cls(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0, dtype=object))
        return cls(np.concatenate(a), np.concatenate(b), np.concatenate(w))

    @classmethod
    def from_recordings(cls, recordings, frame=None) -> WalkedPaths:
        """The graph of walks with ground truth (their waypoints in time order), in ``frame`` (default: each
        walk's own; pass the database's :attr:`~ilocalg.track.WifiDatabase.frame`)."""
        polys = {}
        for r in (recordings.values() if isinstance(recordings, dict) else recordings):
            r = as_recording(r)
            if frame is not None and len(r.truth):
                r = r.in_frame(frame)
            tr = r.truth.sort_values(T_S, kind="stable")
            polys[r.name] = tr[[X_M, Y_M]].to_numpy(dtype=np.float64)
        return cls.from_polylines(polys)

    @classmethod
    def from_database(cls, db) -> WalkedPaths:
        """The graph of a :class:`~ilocalg.track.WifiDatabase`'s scan positions, walk by walk in row (time) order."""
        walk = np.asarray(db.walk, dtype=object)
        return cls.from_polylines({w: db.xy_m[walk == w] for w in dict.fromkeys(walk)})

    @property
    def walks(self) -> list:
        return list(dict.fromkeys(self.walk))

    def without(self, *names) -> WalkedPaths:
        """The graph without the segments of the walks ``names``."""
        keep = ~np.isin(self.walk, np.asarray(names, dtype=object))
        return WalkedPaths(self.a_m[keep], self.b_m[keep], self.walk[keep])

    def project(self, xy_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Nearest point of the graph to every point: ``(projected (n, 2), distance (n,), segment index (n,))``."""
        xy = np.asarray(xy_m, dtype=np.float64).reshape(-1, 2)
        if self.a_m.shape[0] == 0:
            raise ValueError("the walked-path graph has no segment (no database walk with two waypoints)")
        a, ab = self.a_m, self.b_m - self.a_m
        ab2 = np.maximum((ab ** 2).sum(axis=1), 1e-12)
        out = np.empty_like(xy)
        dist = np.empty(xy.shape[0])
        seg = np.empty(xy.shape[0], dtype=np.int64)
        step = max(1, _BLOCK // a.shape[0])
        for s in range(0, xy.shape[0], step):
            p = xy[s:s + step]
            ap_x = p[:, 0, None] - a[None, :, 0]
            ap_y = p[:, 1, None] - a[None, :, 1]
            t = np.clip((ap_x * ab[None, :, 0] + ap_y * ab[None, :, 1]) / ab2[None, :], 0.0, 1.0)
            dx, dy = ap_x - t * ab[None, :, 0], ap_y - t * ab[None, :, 1]
            d2 = dx * dx + dy * dy
            k = np.argmin(d2, axis=1)
            r = np.arange(p.shape[0])
            seg[s:s + step] = k
            dist[s:s + step] = np.sqrt(d2[r, k])
            out[s:s + step] = a[k] + t[r, k, None] * ab[k]
        return out, dist, seg

    def samples(self, step_m: float = SPREAD_STEP_M) -> tuple[np.ndarray, np.ndarray]:
        """Points every ``step_m`` along each segment (its start included, its end from the next segment or
        added at a walk's last segment): ``(xy (n, 2), walk (n,))``."""
        L = np.hypot(*(self.b_m - self.a_m).T)
        n = np.maximum(np.ceil(L / step_m).astype(np.int64), 1)
        i = np.repeat(np.arange(L.size), n)
        f = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / n[i]
        xy = self.a_m[i] + f[:, None] * (self.b_m - self.a_m)[i]
        return xy, self.walk[i]

    def spread_var_m2(self, step_m: float = SPREAD_STEP_M) -> float:
        """Per-axis variance (m^2) of a walk's distance to the other walks' paths: every walk's polyline sampled
        every ``step_m``, each sample's distance to :meth:`without` its walk; ``mean(d^2) / 2`` (kept once
        computed). Raises with fewer than two walks."""
        key = ("spread", step_m)
        if key not in self._memo:
            names = self.walks
            if len(names) < 2:
                raise ValueError("the spread of the walked paths needs at least two walks")
            xy, w = self.samples(step_m)
            d2 = np.concatenate([self.without(n).project(xy[w == n])[1] ** 2 for n in names])
            self._memo[key] = float(d2.mean() / 2.0)
        return self._memo[key]


#: Rounds of :func:`lsq_paths_track` (solve, project, re-solve); it stops earlier once no state moves by more than
#: :data:`PATH_TOL_M`. One: on the development walks (site1 F1 even, leave-one-walk-out, 379 waypoints, Wi-Fi only
#: 5.73 m) one round gave 0.582 x Wi-Fi only, two 0.585, five 0.591 (plain ``lsq`` 0.610).
PATH_ROUNDS = 1
PATH_TOL_M = 0.05


def lsq_paths_track(problem, rounds: int = PATH_ROUNDS, var_scale: float = 1.0, robust: bool = True,
                    snap: bool = False, gain: bool = False, map_step: bool = False) -> np.ndarray:
    """Offline least squares with the walked-path graph as a soft constraint (``lsq_paths``).

    The whole-walk least squares of :func:`ilocalg.track.estimators.lsq_track` (Wi-Fi fixes, PDR steps,
    correlated fix errors), then ``rounds`` times: every state projected onto the nearest segment of
    ``problem.paths`` (:meth:`WalkedPaths.project`), the system solved again with each projection as an
    absolute observation of its state with variance ``var_scale * problem.path_var_m2`` (measured: a walk's
    distance to the other walks' paths, :meth:`WalkedPaths.spread_var_m2`). The projection moves a state
    across the path only, so the observation pulls it onto the path without holding it along it.
    ``robust``: a state far from every path (an area one walk crossed) gets Huber's weight
    (c = 1.345 sd, Huber 1981) on its distance (on: a priori; off changed nothing measurable on the development
    walks). ``snap``: the states finally moved onto the graph (hard).
    ``gain``: the walk's own step scale and heading bias solved with the track (:func:`lsq_gain_solve`, needs
    ``problem.gain``: its spread measured on the other walks); off: on the development walks (site1 F1 even,
    leave-one-walk-out) it raised the error (``lsq`` 0.610 -> 0.626 x Wi-Fi only, ``lsq_paths`` with five
    rounds 0.591 -> 0.627), as did ``snap`` (0.591 -> 0.596). ``map_step``: then the map step of
    ``lsq_map`` (:func:`ilocalg.track.estimators.lsq_map_track`: states off the walkable raster pulled onto it,
    the path observations kept).
    """
    from ilocalg.track.estimators import HUBER_C, _interp_rows, lsq_solve

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
        from ilocalg.track.estimators import _with_map

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
    :func:`ilocalg.track.estimators.lsq_solve`. Returns ``((n, 2) states, g)``.
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import spsolve

    from ilocalg.track.estimators import HUBER_C, _interp_rows

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


