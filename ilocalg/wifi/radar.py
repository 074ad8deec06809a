"""Simplified-RADAR: nearest neighbours in signal space over the union of the strongest APs.

For a query ``s`` and a reference ``s'`` the distance is taken over the union of the ``k`` strongest
APs of each (eq. 1); the ``N`` nearest references are weighted by ``1/d^2`` normalised (eq. 2) and
their positions averaged (eq. 3). When a scan hears fewer than ``k`` APs, ``k`` decreases to the
number heard (the thesis: "if fewer than k, decrease in turn"). Not-heard APs inside the union take
``not_heard_dbm``.

Database (thesis L283, L287): the database keeps every scan of every training point and the query
is compared with each stored vector; the N nearest *training points* are kept. With
``point_distance="min"`` (the default) references sharing a position form one training point whose
distance is the smallest over its stored scans; ``point_distance=None`` treats every reference row
as its own neighbour. Fitting a per-point mean map (one row per point,
:func:`ilocalg.wifi.preprocessing.mean_fingerprints`) gives the same result either way: that is the
labelled alternative to the text's database.

Vectorisation: with masks ``A`` (query's top-k) and ``B`` (reference's top-k), the union mask is
``A + B - AB`` and eq. (1) squared expands into one matrix product of stacked features, computed in
chunks of references: float32 for integer dBm (every partial sum is an integer below 2**24, so it is
exact), float64 for anything else. A fitted estimator stacks the reference factor once when it is small
(:data:`_STACK_CACHE_BYTES`), so a predict call costs the product, not the stacking of the database.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
sec. 3.1, eq. (1)-(4).
Bahl P., Padmanabhan V. N., "RADAR: an in-building RF-based user location
and tracking system", IEEE INFOCOM 2000 (NNSS, N = 3).
"""

from __future__ import annotations

import threading

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.knn import knn_predict, neighbour_weights, smallest_k
from ilocalg.wifi.preprocessing import (
    RSSI_RANGE_DBM,
    RssiPositionTags,
    check_positions,
    check_rssi,
    check_shared_aps,
    checked_features,
    heard_aps,
    predict_located,
    strongest_ap_mask,
    to_features,
)

__all__ = ["union_topk_sq_distances", "radar_predict", "SimplifiedRadar"]

_REF_CHUNK = 4096
_Q_BATCH = 512
#: A fitted SimplifiedRadar keeps eq. (1)'s stacked reference factor (float64: n_ref x (5 n_aps + 2) x 8 bytes) when
#: it is at most this large (the i-Loc floor: 18 900 scans x 19 APs, 15 MB), so a predict call, down to one query,
#: does not stack the whole database again; a larger database (UJIIndoorLoc: 415 MB) is stacked per call, slab by slab.
_STACK_CACHE_BYTES = 64 * 2**20
#: :meth:`SimplifiedRadar.kneighbors` writes each batch's n_q x n_ref distances into one buffer per thread, kept
#: between calls when at most this large (the i-Loc floor: 512 x 18 900 float64, 74 MB): a fresh array of that size
#: is a new memory mapping per batch, whose page faults cost about as much as a fifth of the product itself.
_SCRATCH_BYTES = 96 * 2**20
_scratch = threading.local()


def _scratch_out(shape: tuple, dtype) -> np.ndarray | None:
    """A C-contiguous array of ``shape`` and ``dtype`` on this thread's kept buffer (None when too large)."""
    n = int(np.prod(shape)) * np.dtype(dtype).itemsize
    if n > _SCRATCH_BYTES:
        return None
    buf = getattr(_scratch, "buf", None)
    if buf is None or buf.size < n:
        buf = _scratch.buf = np.empty(n, dtype=np.uint8)
    return buf[:n].view(dtype).reshape(shape)


def _stack_query(q: np.ndarray, a: np.ndarray, dtype) -> np.ndarray:
    """Left factor of :func:`_union_sq`: five blocks of n_aps columns, then the query's constant and a 1."""
    na = 1.0 - a
    const_q = np.sum(a * q * q, axis=1, keepdims=True)
    ones = np.ones_like(const_q)
    return np.concatenate([-2.0 * a * q, a, na * q * q, -2.0 * na * q, -a, const_q, ones], axis=1).astype(dtype)


def _stack_ref(r: np.ndarray, b: np.ndarray, dtype, out: np.ndarray | None = None) -> np.ndarray:
    """Right factor of :func:`_union_sq`: the blocks matching :func:`_stack_query`, a 1 and the reference's
    constant (written into ``out``, float64, when given)."""
    br = b * r
    const_r = np.sum(br * r, axis=1, keepdims=True)
    ones = np.ones_like(const_r)
    if out is not None:
        return np.concatenate([r, r * r, b, br, br * r, ones, const_r], axis=1, out=out)
    return np.concatenate([r, r * r, b, br, br * r, ones, const_r], axis=1).astype(dtype, copy=False)


def _stack_ref_all(r: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`_stack_ref` of every reference in float64, built in slabs of 1 024 rows (they stay in cache)."""
    out = np.empty((r.shape[0], 5 * r.shape[1] + 2))
    for s in range(0, r.shape[0], 1024):
        _stack_ref(r[s:s + 1024], b[s:s + 1024], np.float64, out=out[s:s + 1024])
    return out


def _exact_dtype(q, ref: _References, k: int) -> type:
    """float32 when it is exact, else float64.

    Every term of the stacked product involves one of the <= k masked APs of the query or of the
    reference (or is one of the two constants, each a sum over <= k masked APs), so the absolute sum of
    the terms is below ``7 blocks * 2k APs * 2 M^2`` for features <= M. With integer features (integer dBm
    above the floor) and that bound below 2**24 every partial sum is an integer float32 represents
    exactly (UJIIndoorLoc: M = 104, k = 5), whatever the order of the additions.
    """
    m = max(float(q.max(initial=0.0)), ref.max)
    integer = ref.integer and not np.any(q != np.round(q))
    bound = 7.0 * (2.0 * max(k, 1)) * (2.0 * m * m)
    return np.float32 if integer and bound < 2.0**24 else np.float64


class _References:
    """The reference side of eq. (1): features ``r``, strongest-AP masks ``b``, what :func:`_exact_dtype` needs of
    them, and the right factor of :func:`_union_sq`.

    With ``cache_bytes`` at least the float64 right factor's size, the factor is stacked once, here (its
    float32 cast on first use), and every call slices it; otherwise each call stacks its slab of references
    anew. Both give the same bits: the factor is built row by row (element-wise products and per-row sums),
    and the float32 factor is the float64 one cast, as :func:`_stack_ref` casts it.
    """

    def __init__(self, r: np.ndarray, b: np.ndarray, cache_bytes: int = 0):
        self.r, self.b = r, b
        self.k = int(b.sum(axis=1).max(initial=0))
        self.max = float(r.max(initial=0.0))
        self.integer = not np.any(r != np.round(r))
        self.cached = r.shape[0] * (5 * r.shape[1] + 2) * 8 <= cache_bytes
        self._stacks = {np.float64: _stack_ref_all(r, b)} if self.cached else {}

    def right(self, start: int, stop: int, dtype) -> np.ndarray:
        """Rows ``start:stop`` of the right factor, in ``dtype``."""
        if not self.cached:
            return _stack_ref(self.r[start:stop], self.b[start:stop], dtype)
        st = self._stacks.get(dtype)
        if st is None:
            st = self._stacks[dtype] = self._stacks[np.float64].astype(dtype)
        return st[start:stop]


def union_topk_sq_distances(q_rssi_dbm, ref_rssi_dbm, k_aps: int = 5, not_heard_dbm: float = -100.0) -> np.ndarray:
    """Squared eq. (1) distances between every query and every reference.

    Parameters
    ----------
    q_rssi_dbm : ndarray (n_q, n_aps), dBm, NaN = not heard
    ref_rssi_dbm : ndarray (n_ref, n_aps)
    k_aps : int
        k, the number of strongest APs of each scan (5 is best in the thesis, Fig 3).
    not_heard_dbm : float
        RSSI used for an AP of the union that the other scan did not hear.

    Returns
    -------
    ndarray (n_q, n_ref), float32 for integer dBm (exact), float64 otherwise
        ``sum_{i in SAP_k(s) U SAP_k(s')} (s_i - s'_i)^2``.

    References
    ----------
    i-Loc thesis, sec. 3.1, eq. (1).
    """
    q = to_features(q_rssi_dbm, not_heard_dbm, "positive", dtype=np.float64, name="X")
    r = to_features(ref_rssi_dbm, not_heard_dbm, "positive", dtype=np.float64, name="reference X")
    a = strongest_ap_mask(q_rssi_dbm, k_aps).astype(np.float64)
    b = strongest_ap_mask(ref_rssi_dbm, k_aps).astype(np.float64)
    return _union_sq(q, a, _References(r, b))


def _union_sq(q, a, ref: _References, clamp: bool = True, scratch: bool = False) -> np.ndarray:
    """Squared eq. (1) distances as one matrix product per slab of references.

    With ``a``, ``b`` the strongest-AP masks of query and reference, the union's indicator is
    ``a + b - ab``, so ``d = sum_i (a_i + b_i - a_i b_i)(q_i - r_i)^2`` expands into five products of a
    query term and a reference term (grouped by the reference term: ``r``, ``r^2``, ``b``, ``br``,
    ``br^2``) plus a constant of each side, all in one GEMM. A float64 product may round a true 0 below 0:
    ``clamp`` sets such values to 0 here (a pass over the whole matrix); with ``clamp=False`` the caller does,
    where needed (:meth:`SimplifiedRadar.kneighbors` checks the per-point minima first, which are all >= 0 but
    for a rare exact match). ``scratch``: the result is written into this thread's kept buffer
    (:func:`_scratch_out`) when it fits, valid until the next such call: for a caller that drops it before.
    """
    k = int(max(a.sum(axis=1).max(initial=0), ref.k))
    dt = _exact_dtype(q, ref, k)
    left = _stack_query(q, a, dt)
    n_ref = ref.r.shape[0]
    out = _scratch_out((q.shape[0], n_ref), dt) if scratch else None
    out = np.empty((q.shape[0], n_ref), dtype=dt) if out is None else out
    if ref.cached and q.shape[0] > 1:  # the whole factor at hand: one product straight into out (no slab copies;
        np.matmul(left, ref.right(0, n_ref, dt).T, out=out)  # one query keeps the slabs: BLAS's threaded gemv
        # over all references would round differently from the slabs' with 2 threads; the same bits otherwise)
    else:
        for s in range(0, n_ref, _REF_CHUNK):
            right = ref.right(s, s + _REF_CHUNK, dt)
            out[:, s:s + _REF_CHUNK] = left @ right.T  # (into a slice directly, matmul would not call BLAS)
    if clamp and dt is not np.float32:  # float32 here is exact (an integer sum of integers): never below 0
        np.maximum(out, 0.0, out=out)
    return out


def radar_predict(q_rssi_dbm, ref_rssi_dbm, ref_xy, k_aps: int = 5, n_neighbors: int = 3,
                  not_heard_dbm: float = -100.0) -> np.ndarray:
    """Simplified-RADAR positions of the queries (eq. 1-3).

    Returns
    -------
    ndarray (n_q, d)
        Weighted means of the ``n_neighbors`` nearest references' positions, weights
        ``1/d^2`` normalised (eq. 2); references at distance 0 share all the weight.

    References
    ----------
    i-Loc thesis, sec. 3.1, eq. (1)-(3).
    """
    q = np.asarray(q_rssi_dbm, dtype=np.float64)
    d2 = union_topk_sq_distances(q, ref_rssi_dbm, k_aps, not_heard_dbm)
    idx = smallest_k(d2, n_neighbors)
    dist = np.sqrt(np.take_along_axis(d2, idx, axis=1).astype(np.float64))
    return knn_predict(ref_xy, idx, neighbour_weights(dist, "distance", power=2.0))


class SimplifiedRadar(RssiPositionTags, RegressorMixin, BaseEstimator):
    """Simplified-RADAR (i-Loc thesis sec. 3.1) as a scikit-learn regressor.

    Parameters
    ----------
    k_aps : int
        Strongest APs per scan in the union distance (eq. 1); thesis best k = 5.
    n_neighbors : int
        N nearest training points (N = 3, after RADAR; thesis L287).
    not_heard_dbm : float
        RSSI substituted for a union AP that a scan did not hear.
    point_distance : {"min", None}
        ``"min"``: references at the same position are one training point, at the smallest
        distance over its scans (thesis L283, L287: every stored scan is compared); ``None``:
        every reference row is a neighbour of its own.
    rssi_range_dbm : (float, float) or None
        Physical range of a heard reading, dBm (default :data:`ilocalg.wifi.preprocessing.RSSI_RANGE_DBM`,
        the loaders' range); a value outside it raises a ValueError naming its row and column. ``None``
        accepts any finite value (e.g. for scikit-learn's estimator checks on random data).

    Attributes
    ----------
    ref_rssi_dbm_ : ndarray (n_ref, n_aps)
    y_ : ndarray, reference positions
    points_ : ndarray, the training points' positions (unique rows of ``y_`` with
        ``point_distance="min"``, else ``y_``)
    n_features_in_ : int

    References
    ----------
    i-Loc thesis, sec. 3.1, eq. (1)-(3).
    """

    def __init__(self, k_aps=5, n_neighbors=3, not_heard_dbm=-100.0, point_distance="min",
                 rssi_range_dbm=RSSI_RANGE_DBM):
        self.k_aps = k_aps
        self.n_neighbors = n_neighbors
        self.not_heard_dbm = not_heard_dbm
        self.point_distance = point_distance
        self.rssi_range_dbm = rssi_range_dbm

    def fit(self, X, y):
        """Store the reference scans ``X`` (dBm, NaN = not heard) and positions ``y``."""
        x = check_rssi(X, "X", valid_dbm=self.rssi_range_dbm)
        r = checked_features(x, self.not_heard_dbm, dtype=np.float64, name="X")  # checks readings against the floor
        if int(self.k_aps) < 1:
            raise ValueError(f"k_aps must be >= 1, got {self.k_aps}")
        heard = heard_aps(x, type(self).__name__)
        if self.point_distance not in ("min", None):
            raise ValueError(f"point_distance must be 'min' or None, got {self.point_distance!r}")
        yy = check_positions(y, x.shape[0])
        if self.point_distance == "min":
            # the rows grouped by position, positions in lexicographic order (np.unique(axis=0)'s), each group's
            # rows in their original order: one stable lexsort (column 0 first)
            pos = yy.reshape(yy.shape[0], -1)
            order = np.lexsort(pos.T[::-1])
            srt = pos[order]
            self._starts = np.flatnonzero(np.r_[True, np.any(srt[1:] != srt[:-1], axis=1)])
            self._order = order
            self.points_ = srt[self._starts]
            if yy.ndim == 1:
                self.points_ = self.points_[:, 0]
        else:
            order = self._order = np.arange(x.shape[0])
            self.points_ = yy
            self._starts = None
        n_nb = len(self.points_)
        if not 1 <= int(self.n_neighbors) <= n_nb:
            raise ValueError(f"n_neighbors={self.n_neighbors} must be in [1, number of training points={n_nb}] "
                             f"(n_samples={x.shape[0]}, point_distance={self.point_distance!r})")
        self.y_ = yy
        self.heard_aps_ = heard
        self.ref_rssi_dbm_ = x
        self._refs = _References(r[order], strongest_ap_mask(x[order], self.k_aps).astype(np.float64),
                                 _STACK_CACHE_BYTES)
        self.n_features_in_ = x.shape[1]
        return self

    def kneighbors(self, X, n_neighbors=None):
        """(dist, idx): eq. (1) distances (ascending) and reference rows of the nearest neighbours.

        With ``point_distance="min"`` the neighbours are the N nearest training points and ``idx``
        holds, for each, the row of its nearest stored scan (so ``y_[idx]`` are the points' positions
        and row labels such as floor or building follow); with ``None``, the N nearest rows.
        """
        check_is_fitted(self, "ref_rssi_dbm_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, allow_empty_rows=False,
                       owner=type(self).__name__, valid_dbm=self.rssi_range_dbm)
        check_shared_aps(x, self.heard_aps_, type(self).__name__)
        k = int(self.n_neighbors if n_neighbors is None else n_neighbors)
        dist = np.empty((x.shape[0], k))
        idx = np.empty((x.shape[0], k), dtype=np.int64)
        for s in range(0, x.shape[0], _Q_BATCH):
            xb = x[s:s + _Q_BATCH]
            q = checked_features(xb, self.not_heard_dbm, dtype=np.float64)
            a = strongest_ap_mask(xb, self.k_aps).astype(np.float64)
            if self._starts is not None:  # one distance per training point: its nearest stored scan
                d2 = _union_sq(q, a, self._refs, clamp=False, scratch=True)
                gmin = np.minimum.reduceat(d2, self._starts, axis=1)
                if gmin.size and gmin.min() < 0:  # a float64 product rounded a 0 below 0: as _union_sq's clamp
                    np.maximum(d2, 0.0, out=d2)  # (every column is in one point's run, so otherwise none is < 0)
                    gmin = np.minimum.reduceat(d2, self._starts, axis=1)
                gi = smallest_k(gmin, k)
                dd = np.take_along_axis(gmin, gi, axis=1)
                rows = self._order[self._nearest_scan(d2, gi)]
            else:
                d2 = _union_sq(q, a, self._refs, scratch=True)
                rows = smallest_k(d2, k)
                dd = np.take_along_axis(d2, rows, axis=1)
            idx[s:s + _Q_BATCH] = rows
            dist[s:s + _Q_BATCH] = np.sqrt(dd.astype(np.float64))
        return dist, idx

    def _nearest_scan(self, d2: np.ndarray, gi: np.ndarray) -> np.ndarray:
        """Column of ``d2`` (n_q, n_ref: references ordered by point) holding the first nearest stored scan of
        each selected training point ``gi`` (n_q, k): the point's scans are one run of columns, so only the k
        selected runs of each query are searched (``argmin`` gives the first of equal minima)."""
        counts = np.diff(np.r_[self._starts, d2.shape[1]])
        width = int(counts[gi].max(initial=1))
        offs = np.arange(width, dtype=np.int64)
        cols = self._starts[gi][..., None] + offs                            # (n_q, k, width)
        inside = offs < counts[gi][..., None]
        vals = np.take_along_axis(d2, np.where(inside, cols, 0).reshape(d2.shape[0], -1), axis=1)
        vals = np.where(inside, vals.reshape(cols.shape), np.inf)
        return self._starts[gi] + np.argmin(vals, axis=2)

    def predict(self, X):
        """Positions of the query scans ``X`` (n_q, n_aps): eq. (2)-(3) over the N nearest; NaN for a query
        sharing no access point with the training set (:mod:`ilocalg.wifi.preprocessing`)."""
        check_is_fitted(self, "ref_rssi_dbm_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=self.rssi_range_dbm)

        def located(xq):
            dist, idx = self.kneighbors(xq)
            return knn_predict(self.y_, idx, neighbour_weights(dist, "distance", power=2.0))
        return predict_located(x, self.heard_aps_, located, self.y_.shape[1:])
