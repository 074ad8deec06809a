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

The estimator that uses the graph, ``lsq_paths``, is :func:`ilocalg.track.estimators.lsq_paths_track`.

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

__all__ = ["WalkedPaths", "SPREAD_STEP_M"]

#: The spacing (m) at which :meth:`WalkedPaths.spread_var_m2` samples each walk's polyline.
SPREAD_STEP_M = 1.0
#: Points x segments per block of :meth:`WalkedPaths.project` (memory bound: ~8 arrays of this many floats).
_BLOCK = 1 << 20


def _segment_d2(p, a, ab, ab2):
    """Each point of ``p`` (n, 2) against each segment ``a + t ab`` (m): the clipped parameter ``t`` (n, m) of its
    nearest point and the squared distance ``d2`` (n, m) to it (``ab2``: the segments' squared lengths)."""
    ap_x = p[:, 0, None] - a[None, :, 0]
    ap_y = p[:, 1, None] - a[None, :, 1]
    t = np.clip((ap_x * ab[None, :, 0] + ap_y * ab[None, :, 1]) / ab2[None, :], 0.0, 1.0)
    dx, dy = ap_x - t * ab[None, :, 0], ap_y - t * ab[None, :, 1]
    return t, dx * dx + dy * dy


@dataclass(frozen=True)
class WalkedPaths:
    """Segments ``a_m[i] -> b_m[i]`` (map frame, metres) of the walks ``walk[i]`` (module docstring)."""

    a_m: np.ndarray
    b_m: np.ndarray
    walk: np.ndarray
    _memo: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)
    #: ``(graph, names)`` when this graph is :meth:`without` ``names`` of another, else None
    _parent: tuple | None = dataclasses.field(init=False, default=None, compare=False, repr=False)

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
        out = WalkedPaths(self.a_m[keep], self.b_m[keep], self.walk[keep])
        object.__setattr__(out, "_parent", (self, frozenset(names)))
        return out

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
            t, d2 = _segment_d2(p, a, ab, ab2)
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
            if self._parent is not None:        # from the whole graph's distances to each walk's paths
                parent, removed = self._parent
                d2 = parent._spread_d2(step_m, removed, names)
            else:
                xy, w = self.samples(step_m)
                d2 = np.concatenate([self.without(n).project(xy[w == n])[1] ** 2 for n in names])
            self._memo[key] = float(d2.mean() / 2.0)
        return self._memo[key]

    def _walk_min_d2(self, step_m: float):
        """Every sample of :meth:`samples`' squared distance to each walk's segments (the least over them, as
        :meth:`project` computes it): ``(M (n_samples, n_walks), sample walk (n_samples,), walks)``; kept."""
        key = ("walk_min_d2", step_m)
        if key not in self._memo:
            xy, sw = self.samples(step_m)
            walks = self.walks
            a, ab = self.a_m, self.b_m - self.a_m
            ab2 = np.maximum((ab ** 2).sum(axis=1), 1e-12)
            segs = [np.flatnonzero(self.walk == w) for w in walks]
            M = np.empty((xy.shape[0], len(walks)))
            step = max(1, _BLOCK // max(a.shape[0], 1))
            for s in range(0, xy.shape[0], step):
                p = xy[s:s + step]
                _, d2 = _segment_d2(p, a, ab, ab2)
                for j, g in enumerate(segs):
                    M[s:s + step, j] = d2[:, g].min(axis=1)
            self._memo[key] = (M, sw, walks)
        return self._memo[key]

    def _two_nearest_walks(self, step_m: float):
        """Every sample's nearest other walk (index into :attr:`walks`, -1: none), its squared distance, the
        second nearest other walk's (inf: none), from :meth:`_walk_min_d2`, and each walk's samples (walk -> rows);
        kept."""
        key = ("two_nearest", step_m)
        if key not in self._memo:
            M, sw, walks = self._walk_min_d2(step_m)
            pos = {w: i for i, w in enumerate(walks)}
            own = np.array([pos[w] for w in sw], dtype=np.int64).reshape(-1)
            D = M.copy()
            D[np.arange(D.shape[0]), own] = np.inf
            if D.shape[1] >= 2:
                part = np.argpartition(D, 1, axis=1)[:, :2]
                v = np.take_along_axis(D, part, axis=1)
                first = np.argmin(v, axis=1)
                b1 = part[np.arange(D.shape[0]), first]
                v1, v2 = v[np.arange(D.shape[0]), first], v[np.arange(D.shape[0]), 1 - first]
            else:
                b1, v1, v2 = np.zeros(D.shape[0], dtype=np.int64), D[:, 0], np.full(D.shape[0], np.inf)
            b1 = np.where(np.isfinite(v1), b1, -1)
            self._memo[key] = (b1, v1, v2, {w: np.flatnonzero(own == i) for i, w in enumerate(walks)})
        return self._memo[key]

    def _spread_d2(self, step_m: float, removed, names) -> np.ndarray:
        """The squared distances :meth:`spread_var_m2` of ``self.without(*removed)`` averages (walks ``names``, in
        order): each of a walk's samples to the nearest segment of the walks other than it and ``removed``, the
        least of this graph's per-walk distances (:meth:`_walk_min_d2`; the same numbers as projecting)."""
        M, sw, walks = self._walk_min_d2(step_m)
        if len(removed) == 1:                   # one walk left out (a scored walk): from each sample's two nearest
            (r,) = removed
            b1, v1, v2, rows = self._two_nearest_walks(step_m)
            ri = walks.index(r) if r in walks else -1
            at = np.concatenate([rows[n] for n in names])       # each walk's samples, in the order of names
            d = np.where(b1[at] == ri, v2[at], v1[at])  # the least over the walks but its own and r: the same value
            if not np.isfinite(d).all():
                raise ValueError("the walked-path graph has no segment (no database walk with two waypoints)")
            return np.sqrt(d) ** 2
        out = []
        for n in names:
            allowed = np.array([w != n and w not in removed for w in walks])
            if not allowed.any():
                raise ValueError("the walked-path graph has no segment (no database walk with two waypoints)")
            out.append(np.sqrt(M[sw == n][:, allowed].min(axis=1)) ** 2)
        return np.concatenate(out)
