"""Per-query device offset search: WKNN on the RSSI shift that brings a scan closest to the database.

Beyond the papers (a "toolkit" method, not a reproduction). Phones report the same signal a few dB
apart (UJIIndoorLoc: per-phone offset sd 4.24 dB, ``data/measured_parameters.csv``), and the
validation campaign of UJIIndoorLoc used phones the training survey never saw. A calibration that
needs no labelled data from the new phone: shift every heard reading of a query by each ``delta``
of a small grid (``shifts_db``), search the database at each shift, and keep the shift whose
``n_neighbors`` nearest references lie closest on average (the query's own best fit; nothing is
learned from the queries). This is the "offset search" form of the unsupervised device calibration
of Tsui et al. (2009): the offset is the one that minimises the fingerprint distance.

With ``device_calibration=True`` the offset is the phone's, not the scan's: the shift whose criterion
summed over the same device's scans up to and including the query (time order) is smallest
(:func:`device_shift_choice`). The first scan of a phone gets the per-query search; every later scan
pools what the phone has heard so far, as a phone calibrating itself in use would (Tsui et al. 2009
learn the mapping from the device's own unlabelled scans over time). Causal: no later scan and no
position is used. Needs each query's device and time at ``predict`` (UJIIndoorLoc: PHONEID,
TIMESTAMP).

Maths in :func:`offset_search` (pure, over a fitted :class:`~ilocalg.wifi.knn.InvertedIndex`);
:class:`OffsetFingerprint` is the scikit-learn regressor around it. Target layout as
:class:`ilocalg.wifi.CascadeFingerprint`: ``[x_m, y_m, floor, building]`` (n, 4), floor and building
by the neighbours' distance-weighted vote, or positions only (n, 2).

References
----------
Tsui, A. W., Chuang, Y.-H., Chu, H.-H. (2009). Unsupervised learning for solving RSS hardware
variance problem in WiFi localization. Mobile Networks and Applications 14, 677-691.
Torres-Sospedra, J. et al. (2015). Comprehensive analysis of distance and similarity measures for
Wi-Fi fingerprinting indoor positioning systems. Expert Systems with Applications 42, 9263-9278
(powed / exponential representations, Sorensen distance).
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.cascade import split_target
from ilocalg.wifi.knn import InvertedIndex, build_index, knn_predict, knn_search, neighbour_weights, vote
from ilocalg.wifi.preprocessing import (
    RSSI_RANGE_DBM,
    RssiPositionTags,
    check_rssi,
    checked_features,
    heard_aps,
    predict_located,
    shares_no_ap,
    to_features,
)

__all__ = ["offset_search", "device_shift_choice", "OffsetFingerprint"]


def device_shift_choice(criterion: np.ndarray, devices, times) -> np.ndarray:
    """Per query, the index of the shift a self-calibrating phone uses (causal per-device calibration).

    ``criterion`` (n_q, n_shifts): each query's offset-search criterion at each shift (mean distance to its K
    nearest references). For each device, queries are taken in time order (ties: row order); a query's choice is
    the shift minimising the criterion summed over its device's queries up to and including itself (ties: the
    earlier shift). A device's first query therefore gets its own best shift (:func:`offset_search`).
    """
    c = np.asarray(criterion, dtype=np.float64)
    dev = np.asarray(devices).ravel()
    t = np.asarray(times, dtype=np.float64).ravel()
    if c.ndim != 2 or dev.size != c.shape[0] or t.size != c.shape[0]:
        raise ValueError(f"devices and times need one entry per query ({c.shape[0]}), got {dev.size} and {t.size}")
    if not np.isfinite(t).all():
        bad = int(np.flatnonzero(~np.isfinite(t))[0])
        raise ValueError(f"times must be finite, got {t[bad]} at query {bad}")
    order = np.lexsort((np.arange(t.size), t))
    _, inv = np.unique(dev[order], return_inverse=True)
    out = np.empty(c.shape[0], dtype=np.int64)
    for g in range(int(inv.max()) + 1 if inv.size else 0):
        rows = order[inv.reshape(-1) == g]
        out[rows] = np.cumsum(c[rows], axis=0).argmin(axis=1)
    return out


def offset_search(x_dbm: np.ndarray, index: InvertedIndex, k: int, shifts_db, not_heard_dbm: float = -104.0,
                  representation: str = "powed", metric: str = "sorensen", p: int = 2,
                  ceiling_dbm: float = 0.0, devices=None, times=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nearest references of each query at its best RSSI shift.

    Parameters
    ----------
    x_dbm : ndarray (n_q, n_aps)
        Query scans, dBm, NaN = not heard (each hearing at least one AP of the database).
    index : InvertedIndex
        The database in ``representation`` (:func:`ilocalg.wifi.knn.build_index` of :func:`to_features`).
    k : int
        Neighbours per query.
    shifts_db : sequence of float
        Candidate offsets, dB, added to every heard reading of a query; a shifted reading is held in
        ``[not_heard_dbm, ceiling_dbm]`` (a reading pushed to the floor counts as "not heard").
    not_heard_dbm, representation, metric, p
        As :class:`ilocalg.wifi.KnnFingerprint`.
    devices, times : array_like (n_q,), optional
        Each query's device and time: the shift is then the device's (:func:`device_shift_choice`), not the
        query's own.

    Returns
    -------
    dist, idx : ndarray (n_q, k)
        Distances and database rows at the chosen shift, nearest first.
    shift_db : ndarray (n_q,)
        The chosen shift (the one with the smallest mean distance to its ``k`` neighbours; ties to
        the earlier entry of ``shifts_db``).
    """
    shifts = np.asarray(list(shifts_db), dtype=np.float64).ravel()
    if shifts.size == 0 or not np.isfinite(shifts).all():
        raise ValueError(f"shifts_db must be a non-empty sequence of finite dB values, got {shifts_db!r}")
    if devices is not None:
        crit, ds, js = [], [], []
        for s in shifts:
            f = to_features(np.clip(x_dbm + s, not_heard_dbm, ceiling_dbm), not_heard_dbm, representation)
            d, i = knn_search(f, index, k, p=p, metric=metric)
            crit.append(d.mean(axis=1))
            ds.append(d)
            js.append(i)
        ch = device_shift_choice(np.column_stack(crit), devices, times)
        rows = np.arange(ch.size)
        return np.stack(ds)[ch, rows], np.stack(js)[ch, rows], shifts[ch]
    best = None
    for s in shifts:
        xs = np.clip(x_dbm + s, not_heard_dbm, ceiling_dbm)
        f = to_features(xs, not_heard_dbm, representation)
        d, i = knn_search(f, index, k, p=p, metric=metric)
        crit = d.mean(axis=1)
        if best is None:
            best = [crit, d, i, np.full(crit.size, s)]
            continue
        m = crit < best[0]
        best[0][m], best[1][m], best[2][m], best[3][m] = crit[m], d[m], i[m], s
    return best[1], best[2], best[3]


class OffsetFingerprint(RssiPositionTags, RegressorMixin, BaseEstimator):
    """Distance-weighted KNN with a per-query RSSI offset search (see :func:`offset_search`).

    Parameters
    ----------
    n_neighbors : int
        K of the WKNN (1/d weights) and of the floor / building votes.
    shifts_db : tuple of float
        Candidate offsets, dB (``(0,)``: plain WKNN).
    representation : {"positive", "exponential", "powed", "rank"}
    metric : {"minkowski", "sorensen"}
    p : {1, 2}
        Minkowski exponent (ignored for Sorensen).
    not_heard_dbm : float
    rssi_range_dbm : (float, float) or None
        Range of a heard reading (``None``: any finite value, for scikit-learn's checks).
    weight_power : float
        Exponent of the neighbour weights 1/d**weight_power (1: scikit-learn's "distance"; 2: the i-Loc
        thesis eq. (2)); the floor and building votes use the same weights.
    device_calibration : bool
        The shift of each query is its phone's, pooled over the phone's scans so far
        (:func:`device_shift_choice`); ``predict`` then needs ``devices`` and ``times``.

    Attributes
    ----------
    index_ : InvertedIndex
    y_ : ndarray, the training targets
    heard_aps_ : ndarray of bool (n_aps,)
    n_features_in_ : int
    n_outputs_ : int

    Notes
    -----
    ``score`` is R^2; tune with ``scoring=ilocalg.metrics.horizontal_error_scorer()`` for metres. A query
    sharing no access point with the training set gets NaN everywhere.
    """

    def __init__(self, n_neighbors=8, shifts_db=(-4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0),
                 representation="powed", metric="sorensen", p=2, not_heard_dbm=-104.0,
                 rssi_range_dbm=RSSI_RANGE_DBM, weight_power=1.0, device_calibration=False):
        self.n_neighbors = n_neighbors
        self.shifts_db = shifts_db
        self.representation = representation
        self.metric = metric
        self.p = p
        self.not_heard_dbm = not_heard_dbm
        self.rssi_range_dbm = rssi_range_dbm
        self.weight_power = weight_power
        self.device_calibration = device_calibration

    def _ceiling(self):
        return np.inf if self.rssi_range_dbm is None else float(self.rssi_range_dbm[1])

    def fit(self, X, y):
        """Fit on reference scans ``X`` (n, n_aps; dBm, NaN = not heard) and ``y`` (n, 4) or (n, 2)."""
        owner = type(self).__name__
        x = check_rssi(X, "X", owner=owner, valid_dbm=self.rssi_range_dbm, copy=False)
        if y is None:
            raise ValueError("this estimator requires y to be passed, but the target y is None "
                             "([x_m, y_m, floor, building] per row, or positions)")
        xy, floor, building = split_target(y)
        if xy.shape[0] != x.shape[0]:
            raise ValueError(f"X has {x.shape[0]} rows but y has {xy.shape[0]}")
        if not 1 <= int(self.n_neighbors) <= x.shape[0]:
            raise ValueError(f"n_neighbors={self.n_neighbors} must be in [1, n_samples={x.shape[0]}]")
        if self.metric not in ("minkowski", "sorensen"):
            raise ValueError(f"metric must be 'minkowski' or 'sorensen', got {self.metric!r}")
        _check_power(self.weight_power)
        shifts = np.asarray(list(self.shifts_db), dtype=np.float64)
        if shifts.size == 0 or not np.isfinite(shifts).all():
            raise ValueError(f"shifts_db must be a non-empty sequence of finite dB values, got {self.shifts_db!r}")
        for name, v in (("floor", floor), ("building", building)):
            if v is not None and (v != np.round(v)).any():
                raise ValueError(f"y column {name} must hold whole numbers, got {v[v != np.round(v)][0]}")
        self.heard_aps_ = heard_aps(x, owner)
        self.index_ = build_index(checked_features(x, self.not_heard_dbm, self.representation))
        self.y_ = np.asarray(y, dtype=np.float64)
        self.n_outputs_ = 4 if floor is not None else (1 if xy.ndim == 1 else xy.shape[1])
        self.n_features_in_ = x.shape[1]
        return self

    def _at_n_neighbors(self, k: int):
        """This fitted estimator with ``n_neighbors=k``, without refitting (a shallow copy sharing the database: the
        fit does not depend on K), so a CV over K fits once per fold (:func:`ilocalg.wifi.model_selection.toolkit_cv`).
        ``k`` must be valid for the fitted set."""
        import copy

        check_is_fitted(self, "index_")
        return copy.copy(self).set_params(n_neighbors=k)

    def predict(self, X, devices=None, times=None) -> np.ndarray:
        """``[x_m, y_m, floor, building]`` (n_q, 4), or the positions' shape when fitted on positions.

        ``devices`` and ``times`` (one per row of ``X``): each scan's phone and time, required with
        ``device_calibration`` and ignored without it."""
        return self.predict_weight_powers(X, (self.weight_power,), devices, times)[0]

    def predict_weight_powers(self, X, powers, devices=None, times=None) -> list[np.ndarray]:
        """:meth:`predict` at each neighbour-weight exponent of ``powers``, from one offset search: the same values
        as ``set_params(weight_power=a).predict(X)`` for each ``a`` (a CV over the exponent shares the search)."""
        check_is_fitted(self, "index_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=self.rssi_range_dbm,
                       copy=False)
        pw = [_check_power(a) for a in powers]
        width = self.y_[0].size
        meta = {}
        if self.device_calibration:
            if devices is None or times is None:
                raise ValueError(f"{type(self).__name__}(device_calibration=True) needs each scan's devices= and "
                                 "times= at predict")
            dev, tm = np.asarray(devices).ravel(), np.asarray(times, dtype=np.float64).ravel()
            if dev.size != x.shape[0] or tm.size != x.shape[0]:
                raise ValueError(f"devices and times need one entry per row of X ({x.shape[0]}), got {dev.size} "
                                 f"and {tm.size}")
            ok = ~shares_no_ap(x, self.heard_aps_)
            meta = {"devices": dev[ok], "times": tm[ok]}

        def located(xq):
            d, i, s = offset_search(xq, self.index_, int(self.n_neighbors), self.shifts_db, self.not_heard_dbm,
                                    self.representation, self.metric, self.p, self._ceiling(), **meta)
            cols = []
            for a in pw:
                w = neighbour_weights(d, "distance", a)
                if self.n_outputs_ != 4:
                    cols.append(knn_predict(self.y_, i, w).reshape(len(xq), -1))
                else:
                    cols += [knn_predict(self.y_[:, :2], i, w), vote(self.y_[:, 2][i], w), vote(self.y_[:, 3][i], w)]
            return np.column_stack([*cols, s])
        out = np.asarray(predict_located(x, self.heard_aps_, located, (width * len(pw) + 1,)), dtype=np.float64)
        preds = [out[:, j * width:(j + 1) * width] for j in range(len(pw))]
        return [p[:, 0] if self.y_.ndim == 1 else p for p in preds]


def _check_power(a) -> float:
    """``a`` as a float exponent of the neighbour weights, or a ValueError."""
    if isinstance(a, (str, bytes, bool)) or not (np.isscalar(a) and np.isfinite(a) and a > 0):
        raise ValueError(f"weight_power must be a finite number > 0, got {a!r}")
    return float(a)
