"""Simplified-Horus: per-point empirical RSSI distributions, product likelihood, argmax.

Training (Fig 4): the training scans are grouped by reference point (identical positions); for
each point and each AP heard there the histogram of its RSSI values (bins of ``bin_width_db``)
normalised by the number of scans in which the AP was heard gives ``Pr(s_i | P_j)``.

Positioning: the query's APs are sorted strongest first; APs never heard anywhere in training are
ignored (thesis: "ignore new APs that are not in the AP set"). The ``k`` strongest remaining APs
are matched (eq. 5-6, logs summed); the candidate points are those whose model holds all ``k``
APs, and when no point holds them all ``k`` decreases (the weakest is dropped) until some do
(thesis: "if fewer than k, decrease in turn"; this also resolves the case "s lacks an AP of the
database": only the query's own strongest APs that exist in the database are compared). The
estimate is the candidate with the largest likelihood (eq. 7; ties: first point in training order).

Zero probabilities: an RSSI value that a point's model never saw for an AP (or a value outside the
trained range) would make the product zero; it gets the documented floor ``prob_floor`` instead
(default 1e-3, i.e. about one scan in a thousand) -- the thesis' other remedy, "add training data",
is not available to an estimator.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 3.2, eq. (5)-(7), Fig 4; Youssef M., Agrawala A.,
"The Horus WLAN location determination system", MobiSys 2005.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.preprocessing import (
    RSSI_RANGE_DBM,
    RssiPositionTags,
    check_positions,
    check_rssi,
    check_shared_aps,
    heard_aps,
    predict_located,
)

__all__ = ["HorusModel", "fit_horus", "horus_scores", "horus_predict_index", "SimplifiedHorus"]


class HorusModel:
    """Per-point RSSI histograms (compact: only the (point, AP) pairs heard in training).

    Attributes
    ----------
    points_xy : ndarray (n_points, d) reference point positions (training order of first scan)
    point_of_row : ndarray (n_train,) point index of each training scan
    pair : ndarray (n_points, n_aps) int32, row of ``log_prob`` or -1 (AP never heard there)
    log_prob : ndarray (n_pairs + 1, n_bins) float32, log Pr(bin | point, AP), floored; the last row
        is all ``log(prob_floor)`` (used for unseen pairs, then masked out of the candidates)
    lo_dbm, bin_width_db : float, bin edges ``lo_dbm + i * bin_width_db``
    ap_known : ndarray (n_aps,) bool, AP heard somewhere in training
    """

    __slots__ = ("points_xy", "point_of_row", "pair", "log_prob", "lo_dbm", "bin_width_db", "ap_known",
                 "n_scans")

    def __init__(self, **kw):
        for k, v in kw.items():
            setattr(self, k, v)


def fit_horus(rssi_dbm, xy, bin_width_db: float = 1.0, prob_floor: float = 1e-3) -> HorusModel:
    """Build the per-point histogram model from training scans.

    Parameters
    ----------
    rssi_dbm : ndarray (n, n_aps), dBm, NaN = not heard
    xy : ndarray (n,) or (n, d), positions; identical rows form one reference point
    bin_width_db : float
        Histogram bin width (1 dB = integer RSSI as phones report it).
    prob_floor : float
        Probability given to an RSSI bin never seen at a point (0 < floor < 1).

    References
    ----------
    i-Loc thesis, sec. 3.2, Fig 4 (per-point CDF / histogram of each AP).
    """
    x = check_rssi(rssi_dbm, "X")
    if not 0 < prob_floor < 1:
        raise ValueError(f"prob_floor must be in (0, 1), got {prob_floor}")
    if not bin_width_db > 0:
        raise ValueError(f"bin_width_db must be > 0, got {bin_width_db}")
    y = np.asarray(xy, dtype=np.float64)
    y2 = y.reshape(y.shape[0], -1)
    _, first, inv = np.unique(y2, axis=0, return_index=True, return_inverse=True)
    # renumber points in training order of their first scan
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    point_of_row = rank[inv.ravel()]
    points_xy = y[first[order]]
    n_pts, n_aps = order.size, x.shape[1]
    heard = ~np.isnan(x)
    if not heard.any():
        raise ValueError("X hears no access point at all (every value is NaN)")
    lo = np.floor(np.nanmin(x) / bin_width_db) * bin_width_db
    hi = np.nanmax(x)
    n_bins = int(np.floor((hi - lo) / bin_width_db)) + 1
    r, c = np.nonzero(heard)
    b = np.floor((x[r, c] - lo) / bin_width_db).astype(np.int64)
    p = point_of_row[r]
    key = p * n_aps + c
    # the (point, AP) pairs heard, ascending (np.unique's order), by a table over all pairs instead of a sort
    seen = np.zeros(n_pts * n_aps, dtype=bool)
    seen[key] = True
    pair_keys = np.flatnonzero(seen)
    pair_of_key = np.zeros(n_pts * n_aps, dtype=np.int64)
    pair_of_key[pair_keys] = np.arange(pair_keys.size)
    pair_id = pair_of_key[key]
    # scans per (pair, bin): whole numbers, the same float64 values as adding 1.0 per scan
    counts = np.bincount(pair_id * n_bins + b, minlength=pair_keys.size * n_bins).reshape(pair_keys.size, n_bins)
    counts = counts.astype(np.float64)
    prob = counts / counts.sum(axis=1, keepdims=True)
    log_prob = np.log(np.maximum(prob, prob_floor)).astype(np.float32)
    log_prob = np.vstack([log_prob, np.full((1, n_bins), np.log(prob_floor), dtype=np.float32)])
    pair = np.full((n_pts, n_aps), -1, dtype=np.int32)
    pair.ravel()[pair_keys] = np.arange(pair_keys.size, dtype=np.int32)
    return HorusModel(points_xy=points_xy, point_of_row=point_of_row, pair=pair, log_prob=log_prob,
                      lo_dbm=float(lo), bin_width_db=float(bin_width_db), ap_known=heard.any(axis=0),
                      n_scans=np.bincount(point_of_row, minlength=n_pts))


def _points_by_ap(model: HorusModel) -> tuple[np.ndarray, np.ndarray]:
    """``(indptr, points)``: the points whose model holds AP ``a`` are ``points[indptr[a]:indptr[a+1]]``
    (ascending, i.e. training order)."""
    ap, pt = np.nonzero(model.pair.T >= 0)
    indptr = np.zeros(model.pair.shape[1] + 1, dtype=np.int64)
    np.cumsum(np.bincount(ap, minlength=model.pair.shape[1]), out=indptr[1:])
    return indptr, pt


def _candidates(model: HorusModel, q: np.ndarray, k_aps: int, by_ap=None):
    """The candidate (query, point) pairs of eq. (7) and their log-likelihoods (eq. 5-6).

    Returns ``(qi, pi, score, k_eff)``: pairs sorted by query then point (training order), the float32 sum of
    the first ``k_eff[qi]`` log-probabilities (added in the query's order, as a cumulative sum), and the number
    of APs compared per query. Sparse: the candidates of the strongest AP come from an inverted index (AP ->
    points) and each further AP only filters them, so the work scales with the candidates, not with
    queries x points.
    """
    if int(k_aps) < 1:
        raise ValueError(f"k_aps must be >= 1, got {k_aps}")
    known = ~np.isnan(q) & model.ap_known[None, :]
    n_known = known.sum(axis=1)
    if (n_known == 0).any():
        i = int(np.flatnonzero(n_known == 0)[0])
        raise ValueError(f"X row {i} hears no access point known to the training data "
                         "(all NaN or only unknown APs)")
    n_q = q.shape[0]
    k = min(int(k_aps), q.shape[1])
    # the k strongest known APs of each query, strongest first (ties: the lower column), from the heard ones
    r, c = np.nonzero(known)
    o = np.lexsort((c, -q[r, c], r))
    rank = np.arange(r.size) - np.repeat(np.cumsum(n_known) - n_known, n_known)
    top = rank < k
    aps = np.zeros((n_q, k), dtype=np.int64)  # beyond a query's n_valid known APs: unused
    aps[r[top], rank[top]] = c[o][top]
    n_valid = np.minimum(n_known, k)  # the first n_valid of aps are known APs
    indptr, points = _points_by_ap(model) if by_ap is None else by_ap
    # candidates of the strongest AP (every known AP is held by some point)
    a0 = aps[:, 0]
    counts = indptr[a0 + 1] - indptr[a0]
    qi = np.repeat(np.arange(n_q), counts)
    offs = np.arange(qi.size) - np.repeat(np.cumsum(counts) - counts, counts)
    pi = points[np.repeat(indptr[a0], counts) + offs]
    # k' = the largest prefix of the query's APs that some point holds (thesis: decrease k until some do)
    n_aps = model.pair.shape[1]
    pair_flat = model.pair.reshape(-1)  # flat takes: much faster than 2-D fancy indexing
    at_pt = pi * n_aps
    k_eff = np.ones(n_q, dtype=np.int64)
    going = np.ones(n_q, dtype=bool)
    for j in range(1, k):
        going &= n_valid > j
        if not going.any():
            break
        hold = pair_flat.take(at_pt + aps[:, j].take(qi)) >= 0
        hold_q = np.zeros(n_q, dtype=bool)
        hold_q[qi[hold & going[qi]]] = True
        going &= hold_q
        k_eff[going] = j + 1
        keep = hold | ~going[qi]
        qi, pi, at_pt = qi[keep], pi[keep], at_pt[keep]
    nb = model.log_prob.shape[1]
    vals = np.take_along_axis(q, aps, axis=1)
    bins = np.floor((np.nan_to_num(vals, nan=model.lo_dbm) - model.lo_dbm) / model.bin_width_db).astype(np.int64)
    outside = (bins < 0) | (bins >= nb)
    floor_lp = model.log_prob[-1, 0]
    lp_flat = model.log_prob.reshape(-1)
    np.clip(bins, 0, nb - 1, out=bins)
    score = np.zeros(qi.size, dtype=np.float32)
    kq = k_eff.take(qi)
    for j in range(int(k_eff.max())):
        use = kq > j
        qj = qi[use]
        lp = lp_flat.take(pair_flat.take(at_pt[use] + aps[:, j].take(qj)) * nb + bins[:, j].take(qj))
        lp[outside[:, j].take(qj)] = floor_lp
        score[use] += lp
    return qi, pi, score, k_eff


def horus_scores(model: HorusModel, q_rssi_dbm, k_aps: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Log-likelihoods ``sum log Pr(s_i | P_j)`` over the query's used APs (eq. 5-6).

    Returns
    -------
    score : ndarray (n_q, n_points) float32, ``-inf`` for non-candidate points
    k_used : ndarray (n_q,) int, the number of APs finally compared (<= k_aps)

    References
    ----------
    i-Loc thesis, sec. 3.2, eq. (5)-(6).
    """
    q = np.asarray(q_rssi_dbm, dtype=np.float64)
    qi, pi, s, k_eff = _candidates(model, q, k_aps)
    score = np.full((q.shape[0], model.pair.shape[0]), -np.inf, dtype=np.float32)
    score[qi, pi] = s
    return score, k_eff


def horus_predict_index(model: HorusModel, q_rssi_dbm, k_aps: int = 5, batch: int = 1024) -> np.ndarray:
    """Index of the maximum-likelihood reference point of each query (eq. 7)."""
    q = np.asarray(q_rssi_dbm, dtype=np.float64)
    out = np.empty(q.shape[0], dtype=np.int64)
    by_ap = _points_by_ap(model)
    for s in range(0, q.shape[0], batch):
        qb = q[s:s + batch]
        qi, pi, sc, _ = _candidates(model, qb, k_aps, by_ap)
        o = np.lexsort((pi, -sc, qi))  # per query: the largest likelihood, ties to the first point
        out[s:s + batch] = pi[o[np.searchsorted(qi[o], np.arange(qb.shape[0]))]]
    return out


class SimplifiedHorus(RssiPositionTags, RegressorMixin, BaseEstimator):
    """Simplified-Horus (i-Loc thesis sec. 3.2) as a scikit-learn regressor.

    Parameters
    ----------
    k_aps : int
        Number of the query's strongest (known) APs whose probabilities are multiplied.
    bin_width_db : float
        Histogram bin width in dB.
    prob_floor : float
        Smoothing floor for an RSSI value never seen at a point (see the module docstring).
    not_heard_dbm : float
        Accepted for a uniform interface; Horus models only heard readings, so "not heard" is
        never substituted (an AP missing from the query is simply not compared).
    rssi_range_dbm : (float, float) or None
        Physical range of a heard reading, dBm (default :data:`ilocalg.wifi.preprocessing.RSSI_RANGE_DBM`,
        the loaders' range); a value outside it raises a ValueError naming its row and column. ``None``
        accepts any finite value (e.g. for scikit-learn's estimator checks on random data).

    Attributes
    ----------
    model_ : HorusModel
    n_features_in_ : int

    References
    ----------
    i-Loc thesis, sec. 3.2, eq. (5)-(7).
    """

    def __init__(self, k_aps=5, bin_width_db=1.0, prob_floor=1e-3, not_heard_dbm=-104.0,
                 rssi_range_dbm=RSSI_RANGE_DBM):
        self.k_aps = k_aps
        self.bin_width_db = bin_width_db
        self.prob_floor = prob_floor
        self.not_heard_dbm = not_heard_dbm
        self.rssi_range_dbm = rssi_range_dbm

    def fit(self, X, y):
        """Build the per-point histograms from training scans ``X`` at positions ``y``."""
        x = check_rssi(X, "X", valid_dbm=self.rssi_range_dbm)
        heard = heard_aps(x, type(self).__name__)
        yy = check_positions(y, x.shape[0])
        if int(self.k_aps) < 1:
            raise ValueError(f"k_aps must be >= 1, got {self.k_aps}")
        self.model_ = fit_horus(x, yy, self.bin_width_db, self.prob_floor)
        self.heard_aps_ = heard
        self.n_features_in_ = x.shape[1]
        return self

    def predict_index(self, X):
        """Index into ``model_.points_xy`` of the most likely point per query."""
        check_is_fitted(self, "model_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, allow_empty_rows=False,
                       owner=type(self).__name__, valid_dbm=self.rssi_range_dbm)
        check_shared_aps(x, self.heard_aps_, type(self).__name__)
        return horus_predict_index(self.model_, x, self.k_aps)

    def _predict_index_checked(self, x):
        """:meth:`predict_index` on rows that :meth:`predict` has already checked and located."""
        return horus_predict_index(self.model_, x, self.k_aps)

    def predict(self, X):
        """Positions of the most likely reference points (eq. 7); NaN for a query sharing no access point
        with the training set (:mod:`ilocalg.wifi.preprocessing`)."""
        check_is_fitted(self, "model_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=self.rssi_range_dbm)
        pts = self.model_.points_xy
        return predict_located(x, self.heard_aps_, lambda xq: pts[self._predict_index_checked(xq)], pts.shape[1:])
