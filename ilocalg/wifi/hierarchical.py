"""Multi-building, multi-floor positioning: building -> floor -> position.

Two ways to add floor and building to a fingerprint estimator:

``locate_flat(est, X, floor, building)``
    *flat*: one search over the whole database; the position is the estimator's, floor and building
    are the (weighted) majority vote of the same neighbours (KNN, RADAR) or the labels of the most
    likely point (Horus).
:class:`HierarchicalLocator`
    *hierarchical*: the building is voted by the K nearest references of the whole database; the
    floor by the K nearest references inside the predicted building; the position by a position
    estimator fitted on the references of the predicted building and floor only.

Ties in the votes go to the nearest neighbour's label among the tied labels. A query that hears none
of the access points of its predicted building (or floor) keeps the whole-database vote for the floor
(and the whole-database neighbours' weighted position). A query sharing no
access point with the training set gets NaN position, floor and building (the documented no-AP
result of :mod:`ilocalg.wifi.preprocessing`); the labels are then float columns.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.base import clone

from ilocalg.io.schema import BUILDING, FLOOR, X_M, Y_M
from ilocalg.wifi.horus import SimplifiedHorus
from ilocalg.wifi.knn import KnnFingerprint, neighbour_weights, vote
from ilocalg.wifi.preprocessing import check_rssi, shares_no_ap
from ilocalg.wifi.radar import SimplifiedRadar

__all__ = ["locate_flat", "HierarchicalLocator"]


def _labels(v, n, name):
    if v is None:
        return None
    a = np.asarray(v)
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {a.shape}")
    return a


def _nbr_weights(est, dist):
    """The neighbour weights an estimator uses itself (RADAR: 1/d^2, eq. 2; KNN: its ``weights``)."""
    if isinstance(est, SimplifiedRadar):
        return neighbour_weights(dist, "distance", power=2.0)
    return neighbour_weights(dist, est.weights)


def _with_unlocated(locate, x: np.ndarray, miss: np.ndarray, columns) -> pd.DataFrame:
    """``locate(x[~miss])`` spread over all queries, NaN in the rows of ``miss`` (the located rows only
    when every query is located)."""
    if not miss.any():
        return locate(x)
    out = pd.DataFrame({c: np.full(miss.size, np.nan) for c in columns})
    if (~miss).any():
        df = locate(x[~miss])
        for c in df.columns:
            out.loc[~miss, c] = df[c].to_numpy(dtype=np.float64)
    return out


def locate_flat(est, X, floor=None, building=None) -> pd.DataFrame:
    """Position (and floor, building) of each query with a fitted flat estimator; NaN for a query sharing
    no access point with the training set (see :func:`_locate_flat`)."""
    if not isinstance(est, (KnnFingerprint, SimplifiedRadar, SimplifiedHorus)):
        raise ValueError(f"locate_flat() supports KnnFingerprint, SimplifiedRadar, SimplifiedHorus; "
                         f"got {type(est).__name__}")
    x = check_rssi(X, "X", n_aps=est.n_features_in_, owner=type(est).__name__, copy=False)
    cols = [X_M, Y_M] + [c for c, v in ((FLOOR, floor), (BUILDING, building)) if v is not None]
    return _with_unlocated(lambda xq: _locate_flat(est, xq, floor, building), x, shares_no_ap(x, est.heard_aps_),
                           cols)


def _locate_flat(est, X, floor=None, building=None) -> pd.DataFrame:
    """Position (and floor, building) of each query with a fitted flat estimator.

    Parameters
    ----------
    est : fitted KnnFingerprint, SimplifiedRadar or SimplifiedHorus
    X : ndarray (n_q, n_aps)
    floor, building : ndarray (n_ref,) or None
        Labels of the estimator's training rows.

    Returns
    -------
    DataFrame with ``x_m``, ``y_m`` and, when labels were given, ``floor``, ``building``.
    """
    n_ref = est.model_.point_of_row.size if isinstance(est, SimplifiedHorus) else est.y_.shape[0]
    floor = _labels(floor, n_ref, "floor")
    building = _labels(building, n_ref, "building")
    if isinstance(est, SimplifiedHorus):
        pt = est.predict_index(X)
        xy = est.model_.points_xy[pt]
        first_row = np.zeros(len(est.model_.n_scans), dtype=np.int64)
        pr = est.model_.point_of_row
        first_row[pr[::-1]] = np.arange(pr.size)[::-1]
        rows = first_row[pt]
        lab = {FLOOR: None if floor is None else floor[rows],
               BUILDING: None if building is None else building[rows]}
    elif isinstance(est, (KnnFingerprint, SimplifiedRadar)):
        dist, idx = est.kneighbors(X)
        w = _nbr_weights(est, dist)
        xy = np.einsum("qk,qkd->qd", w, est.y_[idx][:, :, :2])
        lab = {FLOOR: None if floor is None else vote(floor[idx], w),
               BUILDING: None if building is None else vote(building[idx], w)}
    else:
        raise ValueError(f"locate_flat() supports KnnFingerprint, SimplifiedRadar, SimplifiedHorus; "
                         f"got {type(est).__name__}")
    out = pd.DataFrame({X_M: xy[:, 0], Y_M: xy[:, 1]})
    for k, v in lab.items():
        if v is not None:
            out[k] = v
    return out


class HierarchicalLocator:
    """Building -> floor -> position with per-building and per-floor models.

    Parameters
    ----------
    classifier : KnnFingerprint or SimplifiedRadar
        Neighbour search used for the building and floor votes (weighted as the estimator weights
        its neighbours).
    position : estimator with fit/predict
        Position estimator, cloned and fitted once per (building, floor).

    Attributes (after fit)
    ----------------------
    building_clf_ : KnnFingerprint over all references
    floor_clf_ : dict building -> KnnFingerprint over that building's references
    pos_ : dict (building, floor) -> fitted position estimator
    """

    def __init__(self, classifier=None, position=None):
        self.classifier = classifier
        self.position = position

    def fit(self, X, xy, floor, building):
        """Fit on reference scans ``X`` (n, n_aps), positions ``xy`` (n, 2) and labels."""
        x = check_rssi(X, "X", copy=False)
        n = x.shape[0]
        xy = np.asarray(xy, dtype=np.float64)
        if xy.shape != (n, 2):
            raise ValueError(f"xy must have shape ({n}, 2), got {xy.shape}")
        floor = _labels(floor, n, "floor")
        building = _labels(building, n, "building")
        if floor is None or building is None:
            raise ValueError("HierarchicalLocator needs floor and building labels")
        clf = self.classifier if self.classifier is not None else KnnFingerprint(n_neighbors=5, p=2)
        pos = self.position if self.position is not None else clf
        self.building_clf_ = clone(clf).fit(x, xy)
        self._building = building
        self._floor = floor
        self.floor_clf_, self._floor_rows, self.pos_ = {}, {}, {}
        for b in np.unique(building):
            rb = np.flatnonzero(building == b)
            self.floor_clf_[b] = clone(clf).set_params(n_neighbors=min(clf.n_neighbors, rb.size)).fit(x[rb], xy[rb])
            self._floor_rows[b] = rb
            for f in np.unique(floor[rb]):
                rf = rb[floor[rb] == f]
                est = clone(pos)
                if "n_neighbors" in est.get_params():
                    est.set_params(n_neighbors=min(est.get_params()["n_neighbors"], rf.size))
                self.pos_[(b, f)] = est.fit(x[rf], xy[rf])
        self.n_features_in_ = x.shape[1]
        return self

    def predict(self, X) -> pd.DataFrame:
        """DataFrame with ``x_m``, ``y_m``, ``floor``, ``building`` per query (NaN for a query sharing no
        access point with the training set)."""
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, copy=False)
        return _with_unlocated(self._predict, x, shares_no_ap(x, self.building_clf_.heard_aps_),
                               [X_M, Y_M, FLOOR, BUILDING])

    def _predict(self, x) -> pd.DataFrame:
        n = x.shape[0]
        dist, idx = self.building_clf_.kneighbors(x)
        w = _nbr_weights(self.building_clf_, dist)
        b_hat = vote(self._building[idx], w)
        f_hat = np.empty(n, dtype=self._floor.dtype)
        xy = np.empty((n, 2))
        f_hat[:] = vote(self._floor[idx], w)                     # fallback: the whole-database vote
        for b in np.unique(b_hat):
            qb = np.flatnonzero(b_hat == b)
            clf = self.floor_clf_[b]
            qb = qb[~shares_no_ap(x[qb], clf.heard_aps_)]        # a query hearing none of b's APs keeps it
            if qb.size:
                d, i = clf.kneighbors(x[qb])
                f_hat[qb] = vote(self._floor[self._floor_rows[b]][i], _nbr_weights(clf, d))
        flat_xy = np.einsum("qk,qkd->qd", w, self.building_clf_.y_[idx][:, :, :2])
        for b, f in sorted({(bb, ff) for bb, ff in zip(b_hat.tolist(), f_hat.tolist(), strict=True)}):
            q = np.flatnonzero((b_hat == b) & (f_hat == f))
            xy[q] = np.asarray(self.pos_[(b, f)].predict(x[q]))[:, :2]
        miss = np.isnan(xy).any(axis=1)                            # hears none of the floor's APs
        xy[miss] = flat_xy[miss]
        return pd.DataFrame({X_M: xy[:, 0], Y_M: xy[:, 1], FLOOR: f_hat, BUILDING: b_hat})
