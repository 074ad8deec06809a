"""The toolkit's multi-building estimator: building -> floor -> position, each level its own KNN.

Beyond the papers (a "toolkit" method, not a reproduction). :class:`CascadeFingerprint` is a
scikit-learn regressor whose target is the (n, 4) array ``[x_m, y_m, floor, building]`` (the
layout :class:`ilocalg.wifi.SimplifiedHorus` also accepts) and whose ``predict`` returns the same
layout, so it composes in a :class:`~sklearn.pipeline.Pipeline` and is tuned with
:class:`~sklearn.model_selection.GridSearchCV` with
:func:`ilocalg.metrics.horizontal_error_scorer` (minus the mean 2-D error in metres).
The levels reuse :class:`ilocalg.wifi.HierarchicalLocator` and :class:`ilocalg.wifi.KnnFingerprint`
(its vectorised batch search: no Python loop per query,
one loop per predicted building/floor).

Ways in, each a parameter (Torres-Sospedra et al. 2015 for the representations and distances):

* ``representation``: ``positive`` (dBm above "not heard"), ``exponential`` or ``powed``
  (``((rssi - min)/-min)^e``, which weighs strong readings up);
* ``p`` / ``metric``: Manhattan, Euclidean or Sorensen distance;
* ``n_neighbors_class`` (building and floor votes, distance-weighted) and ``n_neighbors``
  (position, distance-weighted inside the predicted floor).

References
----------
Torres-Sospedra, J. et al. (2015). Comprehensive analysis of distance and similarity measures for
Wi-Fi fingerprinting indoor positioning systems. Expert Systems with Applications 42, 9263-9278.
Torres-Sospedra, J. et al. (2014). UJIIndoorLoc: a new multi-building and multi-floor database for
WLAN fingerprint-based indoor localization problems. IPIN 2014.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.hierarchical import HierarchicalLocator
from ilocalg.wifi.knn import KnnFingerprint
from ilocalg.wifi.preprocessing import RSSI_RANGE_DBM, RssiPositionTags, check_rssi

__all__ = ["CascadeFingerprint", "split_target"]


def split_target(y) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """``(xy (n, 2), floor, building)`` from an (n, 4) target; ``(y, None, None)`` for any other shape
    (positions only, as :class:`ilocalg.wifi.KnnFingerprint` takes them)."""
    a = np.asarray(y, dtype=np.float64)
    if a.ndim == 0:
        raise ValueError(f"y must be an array of positions (n, 2) or (n, 4) [x_m, y_m, floor, building], got {a!r}")
    if not np.isfinite(a).all():
        raise ValueError(f"y is not finite at row {np.argwhere(~np.isfinite(a))[0][0]}")
    if a.ndim == 2 and a.shape[1] == 4:
        return a[:, :2], a[:, 2], a[:, 3]
    return a, None, None


class CascadeFingerprint(RssiPositionTags, RegressorMixin, BaseEstimator):
    """Building -> floor -> position fingerprinting with distance-weighted KNN at every level.

    Parameters
    ----------
    n_neighbors : int
        K of the position WKNN inside the predicted building and floor.
    n_neighbors_class : int
        K of the building and floor votes (weighted 1/d).
    p : {1, 2}
        Minkowski exponent (ignored for ``metric="sorensen"``).
    metric : {"minkowski", "sorensen"}
    representation : {"positive", "exponential", "powed", "rank"}
    not_heard_dbm : float
        RSSI substituted for "not heard".
    rssi_range_dbm : (float, float) or None
        Range of a heard reading (``None``: any finite value, for scikit-learn's checks).

    Attributes
    ----------
    locator_ : HierarchicalLocator (with floor and building labels) or KnnFingerprint (2-column y)
    n_features_in_ : int
    n_outputs_ : int, 4 with labels, else the number of position columns

    Notes
    -----
    ``score`` is scikit-learn's R^2 (as :class:`ilocalg.wifi.KnnFingerprint`); tune with
    ``scoring=ilocalg.metrics.horizontal_error_scorer()`` for metres.

    ``fit(X, y)``: ``y`` is (n, 4) ``[x_m, y_m, floor, building]`` (whole-number labels) or (n, 2)
    positions only, any number of columns (then one flat WKNN). ``predict(X)`` returns the same
    number of columns; a query
    sharing no access point with the training set gets NaN everywhere.
    """

    def __init__(self, n_neighbors=5, n_neighbors_class=5, p=2, metric="minkowski", representation="powed",
                 not_heard_dbm=-104.0, rssi_range_dbm=RSSI_RANGE_DBM):
        self.n_neighbors = n_neighbors
        self.n_neighbors_class = n_neighbors_class
        self.p = p
        self.metric = metric
        self.representation = representation
        self.not_heard_dbm = not_heard_dbm
        self.rssi_range_dbm = rssi_range_dbm

    def _knn(self, k):
        return KnnFingerprint(n_neighbors=k, p=self.p, weights="distance", not_heard_dbm=self.not_heard_dbm,
                              representation=self.representation, metric=self.metric,
                              rssi_range_dbm=self.rssi_range_dbm)

    def fit(self, X, y):
        """Fit on reference scans ``X`` (n, n_aps; dBm, NaN = not heard) and targets ``y`` (n, 4) or (n, 2)."""
        x = check_rssi(X, "X", owner=type(self).__name__, valid_dbm=self.rssi_range_dbm, copy=False)
        if y is None:
            raise ValueError("this estimator requires y to be passed, but the target y is None "
                             "([x_m, y_m, floor, building] per row)")
        xy, floor, building = split_target(y)
        if xy.shape[0] != x.shape[0]:
            raise ValueError(f"X has {x.shape[0]} rows but y has {xy.shape[0]}")
        for name, v in (("n_neighbors", self.n_neighbors), ("n_neighbors_class", self.n_neighbors_class)):
            if not 1 <= int(v) <= x.shape[0]:
                raise ValueError(f"{name}={v} must be in [1, n_samples={x.shape[0]}]")
        if floor is None:
            self.locator_ = self._knn(self.n_neighbors).fit(x, xy)
        else:
            for name, v in (("floor", floor), ("building", building)):
                if (v != np.round(v)).any():
                    raise ValueError(f"y column {name} must hold whole numbers, got {v[v != np.round(v)][0]}")
            self.locator_ = HierarchicalLocator(self._knn(self.n_neighbors_class), self._knn(self.n_neighbors)).fit(
                x, xy, floor.astype(np.int64), building.astype(np.int64))
        self.n_outputs_ = 4 if floor is not None else (1 if xy.ndim == 1 else xy.shape[1])
        self.n_features_in_ = x.shape[1]
        return self

    def _at_n_neighbors(self, k: int):
        """This fitted estimator with the position K set to ``k``, without refitting: a shallow copy whose position
        models (:class:`ilocalg.wifi.KnnFingerprint`, each floor's clamped to its references as ``fit`` clamps them)
        search ``k`` neighbours. The building and floor classifiers and every database are shared, none depends on
        K, so the copy predicts what ``clone(self).set_params(n_neighbors=k).fit(...)`` would (a CV over K fits
        once per fold, :func:`ilocalg.wifi.model_selection.toolkit_cv`). ``k`` must be valid for the fitted set."""
        import copy

        check_is_fitted(self, "locator_")
        out = copy.copy(self)
        out.n_neighbors = k
        loc = self.locator_
        if isinstance(loc, KnnFingerprint):
            out.locator_ = copy.copy(loc).set_params(n_neighbors=k)
        else:
            out.locator_ = copy.copy(loc)
            out.locator_.pos_ = {bf: copy.copy(e).set_params(n_neighbors=min(k, e.y_.shape[0]))
                                 for bf, e in loc.pos_.items()}
        return out

    def predict(self, X) -> np.ndarray:
        """(n_q, 4) ``[x_m, y_m, floor, building]`` (or the positions' shape when fitted on positions only)."""
        check_is_fitted(self, "locator_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=self.rssi_range_dbm,
                       copy=False)
        if self.n_outputs_ != 4:
            return np.asarray(self.locator_.predict(x), dtype=np.float64)
        df = self.locator_.predict(x)
        return df[["x_m", "y_m", "floor", "building"]].to_numpy(dtype=np.float64)
