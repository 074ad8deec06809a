"""K-nearest-neighbour fingerprinting (KNN / WKNN) with Minkowski distances.

The maths is in pure functions over non-negative feature matrices (see
:func:`ilocalg.wifi.preprocessing.to_features`; "not heard" = 0); :class:`KnnFingerprint` is a
thin scikit-learn estimator around them.

Speed: the database is kept float32. Distances are computed for batches of queries with one of two
kernels, both exact for integer dBm (every partial sum is an integer below 2**24):

``"dense"``   Euclidean via ``|q|^2 + |r|^2 - 2 q.r`` with a float32 matrix product (BLAS);
              Manhattan via ``sum |q - r|`` chunk by chunk.
``"sparse"``  an inverted index over the APs: with features >= 0 and "not heard" = 0,
              ``|q - r| = q + r - 2 min(q, r)`` and ``q.r`` only involve the APs heard in both
              scans, so per AP only the (queries hearing it) x (references hearing it) block is
              touched. A scan hears ~18 of UJIIndoorLoc's 520 APs, so this does ~1/30 of the work.
              For Euclidean distances between integer features (plain dBm, the default) it takes
              the GEMM route instead, ``|r|^2 - 2 q.r`` as one float32 product per block of queries
              against the database stored as ``[-2 r, |r|^2]`` (exact: every value is an integer below
              2**24), which BLAS runs at the hardware's dense rate on every core.

Selecting the K smallest of each row first bounds the K-th smallest by that of a sample of the row (every
16th column), or, on the GEMM route, by the K-th smallest minimum of groups of 32 references taken while the
product, then sorts only the few values at or below it.

Ties in distance are broken by training order (the earlier reference wins), for both kernels.

Inside :func:`shared_searches` a search is done once: a cross-validation that fits the same fold for several
K, or an offset search whose shift grids overlap, gets the stored neighbours of the same database and queries
(compared by content) instead of searching again (see :func:`shared_searches` for why that is exact).

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Sec. 2.2, eq. (1) (Minkowski distance, a=1 Manhattan, a=2
Euclidean) and eq. (2) (mean of the K nearest positions; K=5, a=1 in the paper).
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.preprocessing import (
    RSSI_RANGE_DBM,
    RssiPositionTags,
    check_positions,
    check_rssi,
    check_shared_aps,
    checked_features,
    heard_aps,
    predict_located,
)

__all__ = [
    "InvertedIndex",
    "build_index",
    "pairwise_distances_batch",
    "smallest_k",
    "knn_search",
    "shared_searches",
    "neighbour_weights",
    "knn_predict",
    "vote",
    "KnnFingerprint",
]

_BATCH = 256
#: Distances per block of the Euclidean GEMM path (float32: 128 MB; UJIIndoorLoc's 1,111 queries in one block).
_BLOCK_VALUES = 1 << 25


class InvertedIndex:
    """Float32 feature database plus a per-AP inverted index (CSC layout).

    Attributes
    ----------
    features : ndarray (n_refs, n_aps) float32
    indptr, rows, values : the column-compressed non-zeros (AP j: ``rows[indptr[j]:indptr[j+1]]``)
    sq_norm, l1_norm : ndarray (n_refs,) float32
    """

    __slots__ = ("features", "indptr", "rows", "values", "sq_norm", "l1_norm", "int_top", "_gemm", "_digest")

    def __init__(self, features: np.ndarray):
        f = np.ascontiguousarray(features, dtype=np.float32)
        self.features = f
        r, c = np.nonzero(f)  # by reference row, then AP
        by_ap = np.argsort(c, kind="stable")  # by AP, then reference row
        counts = np.bincount(c, minlength=f.shape[1])
        self.indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        self.rows = r[by_ap].astype(np.int32)
        self.values = f[r, c][by_ap]
        self.sq_norm = np.einsum("ij,ij->i", f, f, dtype=np.float32)
        self.l1_norm = f.sum(axis=1, dtype=np.float32)
        #: the largest feature if all are integers, else None (see :func:`_exact_pair`); every other feature is 0
        v = self.values
        self.int_top = float(v.max(initial=0.0)) if bool(np.all(v == np.rint(v))) else None
        self._gemm = None  # built on the first Euclidean search (see _gemm_database)
        self._digest = None  # content hash of the features, taken on the first search in shared_searches()


#: Largest integer a float32 holds exactly (every partial sum of an exact distance stays below it).
_F32_EXACT = float(2**24)


def _exact_pair(q: np.ndarray, index: InvertedIndex) -> bool:
    """Whether queries and database hold integers small enough that every partial sum of
    ``|q|^2 + |r|^2 - 2 q.r`` is exact in float32, whatever the summation order."""
    if index.int_top is None or not bool(np.all(q == np.rint(q))):
        return False
    top = max(index.int_top, float(q.max(initial=0.0)))
    return 2.0 * q.shape[1] * top * top < _F32_EXACT


def build_index(features) -> InvertedIndex:
    """Build the float32 database + inverted index from a non-negative feature matrix."""
    f = np.asarray(features)
    if f.ndim != 2:
        raise ValueError(f"features must be 2-D, got shape {f.shape}")
    if (f < 0).any():
        raise ValueError("features must be >= 0 (use ilocalg.wifi.preprocessing.to_features)")
    memo = _MEMO.get()
    if memo is None:
        return InvertedIndex(f)
    return memo.index(f)


def _check_p(p) -> int:
    if p not in (1, 2):
        raise ValueError(f"p must be 1 (Manhattan) or 2 (Euclidean), got {p!r}")
    return int(p)


def pairwise_distances_batch(q_features, index: InvertedIndex, p: int = 1, kernel: str = "sparse") -> np.ndarray:
    """Distances (p=1) or squared distances (p=2) from each query to every reference.

    Parameters
    ----------
    q_features : ndarray (n_q, n_aps), >= 0, "not heard" = 0
    index : InvertedIndex
    p : {1, 2}
    kernel : {"sparse", "dense"}

    Returns
    -------
    ndarray (n_q, n_refs) float32
        Manhattan distance for p=1, **squared** Euclidean distance for p=2 (monotone in the
        distance; take the square root of what you keep).

    References
    ----------
    罗思奇 et al. 2017, eq. (1).
    """
    p = _check_p(p)
    q = np.ascontiguousarray(q_features, dtype=np.float32)
    db = index.features
    if q.shape[1] != db.shape[1]:
        raise ValueError(f"queries have {q.shape[1]} AP columns, the database has {db.shape[1]}")
    if kernel == "dense":
        if p == 2:
            d = q @ db.T
            d *= -2.0
            d += np.einsum("ij,ij->i", q, q, dtype=np.float32)[:, None]
            d += index.sq_norm[None, :]
            np.maximum(d, 0.0, out=d)  # rounding only; exact for integer features
            return d
        out = np.empty((q.shape[0], db.shape[0]), dtype=np.float32)
        step = max(1, 2_000_000 // max(1, db.shape[0] * 8))
        for s in range(0, q.shape[0], step):
            out[s:s + step] = np.abs(q[s:s + step, None, :] - db[None, :, :]).sum(axis=2)
        return out
    if kernel != "sparse":
        raise ValueError(f"kernel must be 'sparse' or 'dense', got {kernel!r}")
    acc = _sparse_partial(q, index, p)
    if p == 1:
        acc += q.sum(axis=1, dtype=np.float32)[:, None]
    else:
        acc += np.einsum("ij,ij->i", q, q, dtype=np.float32)[:, None]
    np.maximum(acc, 0.0, out=acc)
    return acc


def _sparse_partial(q: np.ndarray, index: InvertedIndex, p: int, out: np.ndarray | None = None) -> np.ndarray:
    """``norm(r) - 2 sum_j op(q_j, r_j)`` over the APs heard by both: the distance minus the
    query's own norm term (constant per row, so it does not change the ranking).

    ``out``, when given, is a C-contiguous float32 ``(n_q, n_cols)`` array with ``n_cols >= n_refs``: the
    references fill its first columns and the rest are set to :data:`_PAD` (see :func:`_manhattan_blocked`).
    Each cell adds its APs' terms in AP order, in float32, whatever the layout."""
    n_ref = index.features.shape[0]
    base = index.l1_norm if p == 1 else index.sq_norm
    acc = np.empty((q.shape[0], n_ref), dtype=np.float32) if out is None else out
    n_cols = acc.shape[1]
    acc[:, :n_ref] = base[None, :]
    acc[:, n_ref:] = _PAD
    acc_flat = acc.reshape(-1)  # a view (C-contiguous)
    itype = np.int32 if acc.size < 2**31 else np.int64  # half the index traffic when it fits
    qt = np.ascontiguousarray(q.T)  # one AP's queries contiguous
    for j in np.flatnonzero(qt.any(axis=1)):
        a, b = index.indptr[j], index.indptr[j + 1]
        if a == b:
            continue
        col = qt[j]
        qi = np.flatnonzero(col)
        qv = col[qi] * np.float32(-2.0)
        dv = index.values[a:b]
        blk = np.maximum.outer(qv, dv * np.float32(-2.0)) if p == 1 else np.multiply.outer(qv, dv)
        flat = np.add.outer(qi.astype(itype) * itype(n_cols), index.rows[a:b].astype(itype, copy=False))
        np.add.at(acc_flat, flat.ravel(), blk.ravel())  # no repeated index within one AP block
    return acc


def smallest_k(d: np.ndarray, k: int) -> np.ndarray:
    """Indices of the ``k`` smallest values per row, ordered by (value, column index).

    Ties are broken by column (training) order, also at the k-th boundary.
    """
    n = d.shape[1]
    k = int(k)
    if k >= n:
        return np.argsort(d, axis=1, kind="stable")[:, :k]
    if n >= 64 * k and d.shape[0]:
        got = _smallest_k_threshold(d, k)
        if got is not None:
            return got
    part = np.argpartition(d, k - 1, axis=1)[:, :k]
    dk = np.take_along_axis(d, part, axis=1)
    kth = dk.max(axis=1)
    n_le = (d <= kth[:, None]).sum(axis=1)
    order = np.lexsort((part, dk), axis=1)
    idx = np.take_along_axis(part, order, axis=1)
    tied = np.flatnonzero(n_le > k)
    if tied.size:  # boundary ties: the earliest references at the k-th value win
        dt = d[tied]
        kt = kth[tied][:, None]
        lt = dt < kt
        eq = dt == kt
        need = k - lt.sum(axis=1)
        sel = lt | (eq & (np.cumsum(eq, axis=1) <= need[:, None]))
        cols = np.nonzero(sel)[1].reshape(tied.size, k)
        dv = np.take_along_axis(dt, cols, axis=1)
        idx[tied] = np.take_along_axis(cols, np.lexsort((cols, dv), axis=1), axis=1)
    return idx


def _smallest_k_threshold(d: np.ndarray, k: int, stride: int = 16) -> np.ndarray | None:
    """:func:`smallest_k` by a threshold: the ``k``-th smallest of every ``stride``-th column bounds each row's
    ``k``-th smallest from above, so the ``k`` smallest are among the values at or below it (every tie
    included); only those few are sorted, by (value, column). ``None`` when too many values pass
    (many ties) or a value is NaN: the caller then partitions the whole rows."""
    sample = d[:, ::stride]
    tau = np.partition(sample, k - 1, axis=1)[:, k - 1]
    if not np.isfinite(tau).all():
        return None
    r, c = np.nonzero(d <= tau[:, None])
    if r.size > d.size // 8:
        return None
    v = d[r, c]
    o = np.lexsort((c, v, r))
    starts = np.searchsorted(r, np.arange(d.shape[0]))  # r is sorted (row-major nonzero)
    return c[o][starts[:, None] + np.arange(k)].astype(np.intp)


def knn_search(q_features, index: InvertedIndex, k: int, p: int = 1, kernel: str = "sparse",
               batch: int = _BATCH, metric: str = "minkowski") -> tuple[np.ndarray, np.ndarray]:
    """The ``k`` nearest references of each query.

    Parameters
    ----------
    q_features : ndarray (n_q, n_aps), >= 0
    index : InvertedIndex
    k : int
    p : {1, 2}, Minkowski exponent (metric="minkowski")
    kernel : {"sparse", "dense"}
    batch : int, queries per distance block
    metric : {"minkowski", "sorensen"}
        "sorensen" (Bray-Curtis) is ``sum|q - r| / sum(q + r)`` (Torres-Sospedra et al. 2015).

    Returns
    -------
    dist : ndarray (n_q, k) float64
        Distances (not squared), ascending.
    idx : ndarray (n_q, k) int64
        Reference row indices (ties: training order).
    """
    if metric not in ("minkowski", "sorensen"):
        raise ValueError(f"metric must be 'minkowski' or 'sorensen', got {metric!r}")
    p = 1 if metric == "sorensen" else _check_p(p)
    q = np.ascontiguousarray(q_features, dtype=np.float32)
    n_ref = index.features.shape[0]
    if not 1 <= int(k) <= n_ref:
        raise ValueError(f"n_neighbors must be in [1, {n_ref}] (the number of references), got {k}")
    if kernel not in ("sparse", "dense"):
        raise ValueError(f"kernel must be 'sparse' or 'dense', got {kernel!r}")
    memo = _MEMO.get()
    if memo is None:
        return _knn_search(q, index, int(k), p, kernel, batch, metric)
    return memo.search(q, index, int(k), p, kernel, batch, metric)


#: Neighbours a search inside :func:`shared_searches` keeps at least (the largest K of the toolkit grids), so
#: that the same search at a smaller K is a prefix of it.
_SHARED_K = 12


class _SearchMemo:
    """The neighbours of the searches done inside one :func:`shared_searches` block, by content key."""

    def __init__(self, max_entries: int, max_index_bytes: int):
        self.max_entries = int(max_entries)
        self.max_index_bytes = int(max_index_bytes)
        self.indexes: dict = {}
        self.store: dict = {}
        self.hits = 0
        self.misses = 0

    def index(self, f: np.ndarray) -> InvertedIndex:
        """The database of features ``f``: the one built before for the same features, else a new one."""
        f = np.ascontiguousarray(f, dtype=np.float32)
        key = _digest(f)
        got = self.indexes.get(key)
        if got is None:
            got = InvertedIndex(f)
            got._digest = key
            self.indexes[key] = got
            while sum(i.features.nbytes for i in self.indexes.values()) > self.max_index_bytes:
                self.indexes.pop(next(iter(self.indexes)))  # least recently used first
        else:
            self.indexes[key] = self.indexes.pop(key)
        return got

    def search(self, q, index, k, p, kernel, batch, metric):
        if index._digest is None:
            index._digest = _digest(index.features)
        key = (index._digest, _digest(q), p, kernel, metric, int(batch))
        got = self.store.get(key)
        if got is not None and got[0].shape[1] >= k:
            self.hits += 1
            self.store[key] = self.store.pop(key)  # most recently used last
            return np.ascontiguousarray(got[0][:, :k]), np.ascontiguousarray(got[1][:, :k])
        self.misses += 1
        kk = min(max(k, _SHARED_K), index.features.shape[0])
        dist, idx = _knn_search(q, index, kk, p, kernel, batch, metric)
        self.store.pop(key, None)
        self.store[key] = (dist, idx)
        while len(self.store) > self.max_entries:
            self.store.pop(next(iter(self.store)))
        return np.ascontiguousarray(dist[:, :k]), np.ascontiguousarray(idx[:, :k])


def _digest(a: np.ndarray) -> tuple:
    """Content key of a C-contiguous array: dtype, shape and a BLAKE2b hash of its bytes."""
    a = np.ascontiguousarray(a)
    return a.dtype.str, a.shape, hashlib.blake2b(a.data, digest_size=20).digest()


_MEMO: contextvars.ContextVar = contextvars.ContextVar("ilocalg_knn_search_memo", default=None)


@contextlib.contextmanager
def shared_searches(max_entries: int = 1024, max_index_bytes: int = 256 * 2**20):
    """Inside the block, :func:`knn_search` does each search once and returns the stored result when asked again,
    and :func:`build_index` builds each database once.

    Two searches are the same when the database features, the query features (compared by a BLAKE2b hash of
    their bytes), ``p``, ``metric``, ``kernel`` and ``batch`` are: a cross-validation that fits the same fold for
    several K (a fresh :class:`KnnFingerprint` per candidate builds the same database again), or an offset search
    whose shift grids overlap (:func:`ilocalg.wifi.offset.offset_search`). Each search keeps at least
    :data:`_SHARED_K` neighbours and a smaller ``k`` gets their first ``k``: the neighbours are ordered by
    (distance, training order), a total order, so the ``k`` nearest are the first ``k`` of any larger set, with
    the same distances (each is computed per query and reference, whatever ``k``). The results are the bits
    :func:`knn_search` returns outside the block (a test checks it); only the time changes.

    Parameters
    ----------
    max_entries : int
        Searches kept (least recently used dropped first); each holds ``n_q x max(k, 12)`` distances and
        indices (UJIIndoorLoc's 1,111 validation scans: 213 kB).
    max_index_bytes : int
        Feature bytes of the databases kept (least recently used dropped first; UJIIndoorLoc's training set is
        41 MB). Nested blocks share the outer block's store.

    Yields
    ------
    dict
        ``{"hits": ..., "misses": ...}`` of the searches, filled at exit.
    """
    outer = _MEMO.get()
    memo = outer if outer is not None else _SearchMemo(max_entries, max_index_bytes)
    token = _MEMO.set(memo)
    counts: dict = {}
    try:
        yield counts
    finally:
        _MEMO.reset(token)
        counts.update(hits=memo.hits, misses=memo.misses)


def _knn_search(q: np.ndarray, index: InvertedIndex, k: int, p: int, kernel: str, batch: int,
                metric: str) -> tuple[np.ndarray, np.ndarray]:
    """:func:`knn_search` on checked arguments (``q`` float32, C-contiguous)."""
    dist = np.empty((q.shape[0], k), dtype=np.float64)
    idx = np.empty((q.shape[0], k), dtype=np.int64)
    if kernel == "sparse" and metric == "minkowski" and p == 2 and q.shape[1] == index.features.shape[1] \
            and _exact_pair(q, index):
        d2, idx = _euclidean_blocked(q, index, int(k), max(int(batch), 1))
        return np.sqrt(d2), idx
    if kernel == "sparse" and metric == "minkowski" and p == 1 and q.shape[1] == index.features.shape[1]:
        return _manhattan_blocked(q, index, int(k), max(int(batch), 1))
    for s in range(0, q.shape[0], batch):
        qb = q[s:s + batch]
        if kernel == "sparse":  # rank on the partial sums, add the query's norm to the k kept
            d = _sparse_partial(qb, index, p)
            own = qb.sum(axis=1) if p == 1 else np.einsum("ij,ij->i", qb, qb)
        else:
            d = pairwise_distances_batch(qb, index, p=p, kernel=kernel)
            own = np.zeros(qb.shape[0], dtype=np.float32)
        if metric == "sorensen":
            l1q = qb.sum(axis=1, dtype=np.float32)
            d = d + own[:, None]  # the full Manhattan distance (own = 0 for the dense kernel)
            den = l1q[:, None] + index.l1_norm[None, :]
            d = np.divide(d, den, out=np.zeros_like(d), where=den > 0)
            own = np.zeros(qb.shape[0], dtype=np.float32)
        ii = smallest_k(d, k)
        dd = np.take_along_axis(d, ii, axis=1).astype(np.float64) + own.astype(np.float64)[:, None]
        dd = np.maximum(dd, 0.0)
        dist[s:s + batch] = np.sqrt(dd) if p == 2 else dd
        idx[s:s + batch] = ii
    return dist, idx


#: References per group whose minimum bounds the selection (see _euclidean_blocked).
_GROUP = 32
#: The distance of a padding row: above every exact distance (integers below 2**24), finite in float32.
_PAD = np.float32(2.0**100)


def _gemm_database(index: InvertedIndex) -> np.ndarray:
    """The references as columns ``[-2 r, |r|^2]`` of a ``(n_aps + 1, n_pad)`` float32 array (training order),
    padded with columns of distance :data:`_PAD` to a multiple of :data:`_GROUP`; built once per index, so that
    ``[q, 1] . column = |r|^2 - 2 q.r`` (the squared distance less ``|q|^2``) is one GEMM with its transpose.
    Stored by AP (each AP's values contiguous), so that the APs a search needs are gathered as whole rows."""
    got = getattr(index, "_gemm", None)
    if got is None:
        n, m = index.features.shape
        n_pad = -(-n // _GROUP) * _GROUP
        db = np.zeros((m + 1, n_pad), dtype=np.float32)
        np.multiply(index.features.T, np.float32(-2.0), out=db[:m, :n])
        db[m, :n] = index.sq_norm
        db[m, n:] = _PAD
        got = index._gemm = db
    return got


#: Fewest queries for which :func:`_euclidean_blocked` gathers the shared columns of the database (the copy
#: costs about as much as a product with this many queries over the columns it saves).
_MIN_QUERIES_TO_GATHER = 32


def _shared_columns(q: np.ndarray, index: InvertedIndex) -> np.ndarray | None:
    """The AP columns heard by some query and some reference, when they are at most 90 % of the columns and
    there are enough queries to pay for gathering them (else ``None``: the whole product)."""
    if q.shape[0] < _MIN_QUERIES_TO_GATHER:
        return None
    cols = np.flatnonzero((np.diff(index.indptr) > 0) & q.any(axis=0))
    return cols if len(cols) <= 0.9 * q.shape[1] else None


def _group_select(d_flat: np.ndarray, q_stride: int, ref_stride: int, gmin: np.ndarray, k: int,
                  strided: bool = False) -> tuple[np.ndarray, np.ndarray] | None:
    """The ``k`` smallest distances of each query and their references, ordered by (value, training order),
    from a block of distances and the minima of its groups of :data:`_GROUP` references.

    ``d_flat[q * q_stride + r * ref_stride]`` is query ``q``'s distance to reference ``r``; ``gmin`` is
    ``(n_q, n_groups)``, the minima of groups of consecutive references (group ``g``: ``g * _GROUP + i``), or
    with ``strided`` of every ``n_groups``-th reference (group ``g``: ``g + i * n_groups``). The ``k``-th
    smallest group minimum bounds each query's ``k``-th smallest distance from above (``k`` groups hold a value
    at or below it), so only the groups whose minimum is at or below it can hold a neighbour: their values at or
    below the bound (every tie included) are sorted. ``None`` when those groups are more than an eighth of the
    block (very many ties): the caller then sorts whole rows."""
    n_q = gmin.shape[0]
    tau = np.partition(gmin, k - 1, axis=1)[:, k - 1]
    qi, gi = np.nonzero(gmin <= tau[:, None])  # by query, then group (training order)
    if qi.size * _GROUP > d_flat.size // 8:
        return None
    if strided:
        c = (gi[:, None] + np.arange(_GROUP) * gmin.shape[1]).ravel()
    else:
        c = (gi[:, None] * _GROUP + np.arange(_GROUP)).ravel()
    r = np.repeat(qi, _GROUP)
    v = d_flat.take(c * ref_stride + r * q_stride)
    keep = v <= tau.take(r)
    c, r, v = c[keep], r[keep], v[keep]
    o = np.lexsort((c, v, r))
    pick = np.searchsorted(r[o], np.arange(n_q))[:, None] + np.arange(k)
    return c[o][pick], v[o][pick]


def _manhattan_blocked(q: np.ndarray, index: InvertedIndex, k: int, batch: int) -> tuple[np.ndarray, np.ndarray]:
    """Manhattan distances (float64) and indices of the ``k`` nearest references, sparse kernel.

    The same sums as :func:`knn_search`'s batch loop (:func:`_sparse_partial`, then the query's own norm added
    to the ``k`` kept), in large blocks of queries (about :data:`_BLOCK_VALUES` distances) whose rows are padded
    with :data:`_PAD` to a multiple of :data:`_GROUP` references, so that the ``k`` nearest are picked from the
    minima of groups of every ``n_pad / _GROUP``-th reference (:func:`_group_select`; an element-wise minimum of
    :data:`_GROUP` contiguous slices of a row, about 7x cheaper than minima over 32 consecutive values)."""
    n_q = q.shape[0]
    n_ref = index.features.shape[0]
    n_pad = -(-n_ref // _GROUP) * _GROUP
    n_grp = n_pad // _GROUP
    batch = max(batch, _BLOCK_VALUES // max(n_pad, 1))
    buf = np.empty(min(batch, n_q) * n_pad, dtype=np.float32)
    dist = np.empty((n_q, k), dtype=np.float64)
    idx = np.empty((n_q, k), dtype=np.int64)
    for s in range(0, n_q, batch):
        qb = q[s:s + batch]
        b = qb.shape[0]
        d = _sparse_partial(qb, index, 1, out=buf[:b * n_pad].reshape(b, n_pad))
        got = None
        if n_grp >= k:
            gmin = np.minimum.reduce(d.reshape(b, _GROUP, n_grp), axis=1)
            got = _group_select(buf[:b * n_pad], n_pad, 1, gmin, k, strided=True)
        if got is None:  # a tiny database, or very many ties: whole rows
            ii = smallest_k(d[:, :n_ref], k)
            dv = np.take_along_axis(d, ii, axis=1)
        else:
            ii, dv = got
        idx[s:s + b] = ii
        dist[s:s + b] = np.maximum(dv.astype(np.float64) + qb.sum(axis=1).astype(np.float64)[:, None], 0.0)
    return dist, idx


def _euclidean_blocked(q: np.ndarray, index: InvertedIndex, k: int, batch: int) -> tuple[np.ndarray, np.ndarray]:
    """Squared Euclidean distances (float64) and indices of the ``k`` nearest references, for integer features.

    One float32 GEMM per block of queries (at least ``batch``, about 64 MB of distances) gives
    ``|r|^2 - 2 q.r`` for every reference (see :func:`_gemm_database`); one pass keeps the minimum of each
    group of :data:`_GROUP` consecutive references. The ``k``-th smallest group minimum
    bounds each query's ``k``-th smallest distance from above (``k`` groups hold a value at or below it), so
    only the few groups whose minimum is at or below it can hold a neighbour: their values at or below the
    bound (every tie included) are sorted by (value, training order). Every value is an integer below
    2**24, hence exact in any summation order: the same distances, neighbours and ties (training order) as
    the other kernels. The product runs over the AP columns heard by some query and some reference only
    (:func:`_shared_columns`; on UJIIndoorLoc's validation set 312 of 520): every other column adds an exact 0
    to ``q.r`` (``|q|^2`` is taken over all columns).
    """
    n_q, m = q.shape
    n_ref = index.features.shape[0]
    db_t = _gemm_database(index)
    qn = np.einsum("ij,ij->i", q, q, dtype=np.float32).astype(np.float64)  # every column (before the next line)
    cols = _shared_columns(q, index)
    if cols is not None:  # q.r over the columns heard on both sides only: the others add exact zeros
        db_t = db_t[np.append(cols, m)]
        q = q[:, cols]
        m = len(cols)
    db = db_t.T  # (n_pad, m + 1)
    n_pad = db.shape[0]
    n_grp = n_pad // _GROUP
    dist = np.empty((n_q, k), dtype=np.float64)
    idx = np.empty((n_q, k), dtype=np.int64)
    batch = max(batch, _BLOCK_VALUES // max(n_pad, 1))  # large blocks: BLAS packs the database once per block
    qa = np.empty((min(batch, n_q), m + 1), dtype=np.float32)
    qa[:, m] = 1.0
    d_buf = np.empty(n_pad * qa.shape[0], dtype=np.float32)
    g_buf = np.empty(n_grp * qa.shape[0], dtype=np.float32)
    for s in range(0, n_q, batch):
        e = min(s + batch, n_q)
        b = e - s
        qb = qa[:b]
        qb[:, :m] = q[s:e]
        qt = qb.T
        d = d_buf[:n_pad * b].reshape(n_pad, b)  # |r|^2 - 2 q.r, references by row (the long side)
        gmin = g_buf[:n_grp * b].reshape(n_grp, b)
        np.matmul(db, qt, out=d)  # one product per block: split into slabs, BLAS re-packs and re-syncs per call
        np.minimum.reduce(d.reshape(n_grp, _GROUP, b), axis=1, out=gmin)
        got = _group_select(d.reshape(-1), 1, b, np.ascontiguousarray(gmin.T), k) if n_grp >= k else None
        if got is None:  # a tiny database, or very many ties: whole rows
            dq = np.ascontiguousarray(d[:n_ref].T)
            ii = smallest_k(dq, k)
            dv = np.take_along_axis(dq, ii, axis=1)
        else:
            ii, dv = got
        idx[s:e] = ii
        dist[s:e] = np.maximum(dv.astype(np.float64) + qn[s:e, None], 0.0)
    return dist, idx


def neighbour_weights(dist: np.ndarray, weights: str = "uniform", power: float = 1.0) -> np.ndarray:
    """Row-normalised neighbour weights.

    ``"uniform"``: 1/K (eq. 2 of 罗思奇 et al.). ``"distance"``: 1/d**power (WKNN; power=1 as in
    scikit-learn, power=2 is the i-Loc thesis eq. (2)); when some neighbours are at distance 0
    only those share the weight.
    """
    dist = np.asarray(dist, dtype=np.float64)
    if weights == "uniform":
        return np.full(dist.shape, 1.0 / dist.shape[1])
    if weights != "distance":
        raise ValueError(f"weights must be 'uniform' or 'distance', got {weights!r}")
    zero = dist == 0
    with np.errstate(divide="ignore"):
        w = 1.0 / dist**power
    anyzero = zero.any(axis=1)
    w[anyzero] = zero[anyzero].astype(np.float64)
    return w / w.sum(axis=1, keepdims=True)


def knn_predict(y_ref, idx, w) -> np.ndarray:
    """Weighted mean of the neighbours' targets: ``sum_k w_k y[idx_k]`` (eq. 2)."""
    y = np.asarray(y_ref, dtype=np.float64)
    yk = y[idx]  # (n_q, k) or (n_q, k, d)
    if yk.ndim == 2:
        return np.sum(w * yk, axis=1)
    return np.einsum("qk,qkd->qd", w, yk)


def vote(labels_nbr, w=None, tie: str = "smallest") -> np.ndarray:
    """Majority (or weight-majority) label per row of ``labels_nbr`` (n_q, k).

    Parameters
    ----------
    labels_nbr : ndarray (n_q, k), the neighbours' labels, nearest first
    w : ndarray (n_q, k), optional neighbour weights (default: one vote each)
    tie : {"smallest", "nearest"}
        Among labels tied for the most votes: the smallest label (as ``scipy.stats.mode``, the
        convention of the published UJIIndoorLoc re-measurements) or the nearest neighbour's.
    """
    lab = np.asarray(labels_nbr)
    if tie not in ("smallest", "nearest"):
        raise ValueError(f"tie must be 'smallest' or 'nearest', got {tie!r}")
    if w is None:
        w = np.ones(lab.shape)
    same = lab[:, :, None] == lab[:, None, :]
    score = np.einsum("qij,qj->qi", same, np.asarray(w, dtype=np.float64))
    top = score >= score.max(axis=1, keepdims=True) - 1e-12
    if tie == "nearest":
        best = np.argmax(top, axis=1)
    else:
        key = np.where(top, lab, np.iinfo(np.int64).max if np.issubdtype(lab.dtype, np.integer) else np.inf)
        best = np.argmin(key, axis=1)
    return lab[np.arange(lab.shape[0]), best]


def _checked_features(x: np.ndarray, not_heard_dbm, representation: str) -> np.ndarray:
    """:func:`~ilocalg.wifi.preprocessing.to_features` of an RSSI matrix that :func:`check_rssi` has already
    returned (float64), without checking ``x`` a second time (:func:`~ilocalg.wifi.preprocessing.checked_features`:
    the same values and messages)."""
    return checked_features(x, not_heard_dbm, representation, name="X")


class KnnFingerprint(RssiPositionTags, RegressorMixin, BaseEstimator):
    """KNN / WKNN fingerprint positioning (scikit-learn regressor).

    Parameters
    ----------
    n_neighbors : int
        K (5 in 罗思奇 et al. 2017).
    p : {1, 2}
        Minkowski exponent a of eq. (1): 1 Manhattan (the paper), 2 Euclidean.
    weights : {"uniform", "distance"}
        "uniform" is eq. (2); "distance" (1/d) gives WKNN.
    not_heard_dbm : float
        RSSI substituted for NaN (not heard).
    rssi_range_dbm : (float, float) or None
        Physical range of a heard reading, dBm (default :data:`ilocalg.wifi.preprocessing.RSSI_RANGE_DBM`,
        the loaders' range); a value outside it raises a ValueError naming its row and column. ``None``
        accepts any finite value (e.g. for scikit-learn's estimator checks on random data).
    representation : {"positive", "exponential", "powed", "rank"}
        Feature representation (``positive`` = plain dBm with NaN filled; distance-equivalent).
    kernel : {"sparse", "dense"}
        Distance kernel (same result; see the module docstring).
    metric : {"minkowski", "sorensen"}
        "sorensen" replaces eq. (1) by the Sorensen (Bray-Curtis) distance (``p`` ignored).

    Attributes
    ----------
    index_ : InvertedIndex
    y_ : ndarray, the training targets (positions)
    heard_aps_ : ndarray of bool (n_aps,), the access points heard in the training set
    n_features_in_ : int

    A query sharing no access point with the training set gets a NaN position from ``predict`` (see
    :mod:`ilocalg.wifi.preprocessing`, "No shared access point"); ``kneighbors`` raises for it.

    References
    ----------
    罗思奇 et al. 2017, sec. 2.2, eq. (1)-(2).
    """

    def __init__(self, n_neighbors=5, p=1, weights="uniform", not_heard_dbm=-104.0, representation="positive",
                 kernel="sparse", metric="minkowski", rssi_range_dbm=RSSI_RANGE_DBM):
        self.n_neighbors = n_neighbors
        self.p = p
        self.weights = weights
        self.not_heard_dbm = not_heard_dbm
        self.representation = representation
        self.kernel = kernel
        self.metric = metric
        self.rssi_range_dbm = rssi_range_dbm

    def _features(self, X, name="X", n_aps=None, allow_empty_rows=True):
        x = check_rssi(X, name, n_aps=n_aps, allow_empty_rows=allow_empty_rows, owner=type(self).__name__,
                       valid_dbm=self.rssi_range_dbm, copy=False)
        return checked_features(x, self.not_heard_dbm, self.representation, name=name)

    def fit(self, X, y):
        """Store the reference fingerprints ``X`` (n_refs, n_aps, dBm/NaN) and positions ``y``."""
        if self.metric not in ("minkowski", "sorensen"):
            raise ValueError(f"metric must be 'minkowski' or 'sorensen', got {self.metric!r}")
        if self.metric == "minkowski":
            _check_p(self.p)
        if self.weights not in ("uniform", "distance"):
            raise ValueError(f"weights must be 'uniform' or 'distance', got {self.weights!r}")
        x = check_rssi(X, "X", owner=type(self).__name__, valid_dbm=self.rssi_range_dbm, copy=False)
        f = checked_features(x, self.not_heard_dbm, self.representation, name="X")
        heard = heard_aps(x, type(self).__name__)
        y = check_positions(y, f.shape[0])
        if not 1 <= int(self.n_neighbors) <= f.shape[0]:
            raise ValueError(f"n_neighbors={self.n_neighbors} must be in [1, n_samples={f.shape[0]}]")
        self.index_ = build_index(f)
        self.y_ = y
        self.heard_aps_ = heard
        self.n_features_in_ = f.shape[1]
        return self

    def kneighbors(self, X, n_neighbors=None):
        """(dist, idx) of the nearest references, ascending; ties by training order."""
        check_is_fitted(self, "index_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, allow_empty_rows=False, owner=type(self).__name__,
                       valid_dbm=self.rssi_range_dbm, copy=False)
        check_shared_aps(x, self.heard_aps_, type(self).__name__)
        f = _checked_features(x, self.not_heard_dbm, self.representation)
        k = int(self.n_neighbors if n_neighbors is None else n_neighbors)
        return knn_search(f, self.index_, k, p=self.p, kernel=self.kernel, metric=self.metric)

    def predict(self, X):
        """Positions (n_q, 2) (or the shape of the fitted ``y``) of the queries ``X``; NaN for a query
        sharing no access point with the training set."""
        check_is_fitted(self, "index_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=self.rssi_range_dbm,
                       copy=False)

        def located(xq):
            dist, idx = self.kneighbors(xq)
            return knn_predict(self.y_, idx, neighbour_weights(dist, self.weights))
        return predict_located(x, self.heard_aps_, located, self.y_.shape[1:])
