"""AP selection and an averaging ensemble of fingerprint estimators (toolkit steps, beyond the papers).

* :class:`ApSelector`: a transformer that keeps the access points heard in at least ``min_count``
  training scans (``min_count=1``: drop the APs never heard in training). A query reading of an AP the
  database never heard adds the same amount to the query's distance to every reference under Minkowski
  distances, but not under Sorensen (it enters numerator and denominator), so dropping it changes the
  ranking there. Pure function :func:`ap_keep_mask`.
* :class:`FingerprintEnsemble`: fits several fingerprint estimators on the same data and returns the mean
  of their positions and the majority vote of their floors and buildings (ties: the first member's
  label). Pure function :func:`combine_predictions`.

Both compose in a :class:`~sklearn.pipeline.Pipeline` (``[("aps", ApSelector()), ("est", ...)]``) and are
tuned with :class:`~sklearn.model_selection.GridSearchCV` and :func:`ilocalg.metrics.horizontal_error_scorer`.
The target layout is that of :class:`ilocalg.wifi.CascadeFingerprint`: ``[x_m, y_m, floor, building]``
(n, 4), or positions only.

References
----------
Torres-Sospedra, J. et al. (2015). Comprehensive analysis of distance and similarity measures for Wi-Fi
fingerprinting indoor positioning systems. Expert Systems with Applications 42, 9263-9278 (the distances
and representations of the members; APs not seen in the radio map).
Chen, Y., Yang, Q., Yin, J., Chai, X. (2006). Power-efficient access-point selection for indoor location
estimation. IEEE Transactions on Knowledge and Data Engineering 18(7), 877-888 (locating with a subset of
the APs).
Torres-Sospedra, J. et al. (2019). Ensembles of indoor positioning systems based on fingerprinting:
simplifying parameter selection and obtaining robust systems. IPIN 2019 (averaging the estimates of
fingerprinting models with different distances and representations).
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin, TransformerMixin, clone
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.preprocessing import RssiPositionTags, check_rssi

__all__ = ["ap_keep_mask", "ApSelector", "combine_predictions", "FingerprintEnsemble", "wants_devices"]


def ap_keep_mask(x_dbm: np.ndarray, min_count: int = 1) -> np.ndarray:
    """Boolean mask (n_aps,) of the APs heard (not NaN) in at least ``min_count`` rows of ``x_dbm``."""
    if int(min_count) != min_count or min_count < 1:
        raise ValueError(f"min_count must be a whole number >= 1, got {min_count!r}")
    return (~np.isnan(np.asarray(x_dbm, dtype=np.float64))).sum(axis=0) >= int(min_count)


class ApSelector(RssiPositionTags, TransformerMixin, BaseEstimator):
    """Keep the access points heard in at least ``min_count`` training scans.

    Parameters
    ----------
    min_count : int
        Training scans an AP must be heard in (1: drop only the APs never heard in training).

    Attributes
    ----------
    keep_ : ndarray of bool (n_aps,)
    n_features_in_ : int

    Raises
    ------
    ValueError
        At ``fit`` when no AP is heard ``min_count`` times (nothing would be left).
    """

    def __init__(self, min_count=1):
        self.min_count = min_count

    def fit(self, X, y=None):
        """Learn the kept APs from the training scans ``X`` (n, n_aps; dBm, NaN = not heard)."""
        x = check_rssi(X, "X", owner=type(self).__name__, valid_dbm=None, copy=False)
        keep = ap_keep_mask(x, self.min_count)
        if not keep.any():
            raise ValueError(f"ApSelector: no access point is heard in min_count={self.min_count} training scans")
        self.keep_ = keep
        self.n_features_in_ = x.shape[1]
        return self

    def transform(self, X):
        """The columns of the kept APs (n, keep_.sum())."""
        check_is_fitted(self, "keep_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=None, copy=False)
        return x[:, self.keep_]

    def get_feature_names_out(self, input_features=None):
        check_is_fitted(self, "keep_")
        names = (np.asarray(input_features, dtype=object) if input_features is not None
                 else np.array([f"x{i}" for i in range(self.n_features_in_)], dtype=object))
        return names[self.keep_]


def combine_predictions(preds) -> np.ndarray:
    """Mean position and majority labels of several estimators' predictions.

    Parameters
    ----------
    preds : sequence of ndarray (n, d)
        Each member's prediction; ``d == 4`` is ``[x_m, y_m, floor, building]`` (the last two are voted),
        any other ``d`` is positions only (averaged). NaN rows (a member that located nothing) are left
        out of the mean and the vote; a row NaN in every member stays NaN.

    Returns
    -------
    ndarray (n, d)
        Positions: mean over the members that located the row. Labels: the most frequent among those
        members, ties to the label of the earliest member holding a tied label.
    """
    p = np.stack([np.asarray(a, dtype=np.float64) for a in preds])   # (m, n, d)
    if p.ndim == 2:
        p = p[:, :, None]
    ok = np.isfinite(p).all(axis=2)                                   # (m, n)
    n_ok = ok.sum(axis=0)
    out = np.full(p.shape[1:], np.nan)
    n_pos = 2 if p.shape[2] == 4 else p.shape[2]
    s = np.where(ok[:, :, None], p[:, :, :n_pos], 0.0).sum(axis=0)
    has = n_ok > 0
    out[has, :n_pos] = s[has] / n_ok[has, None]
    if p.shape[2] == 4:
        for c in (2, 3):
            lab = p[:, :, c]                                          # (m, n)
            same = (lab[:, None, :] == lab[None, :, :]) & ok[:, None, :] & ok[None, :, :]
            count = same.sum(axis=1).astype(np.float64)               # (m, n): votes for member i's label
            count[~ok] = -1.0
            best = np.argmax(count, axis=0)                           # first member among the most voted
            out[has, c] = lab[best, np.arange(lab.shape[1])][has]
    return out[:, 0] if np.asarray(preds[0]).ndim == 1 else out


class FingerprintEnsemble(RssiPositionTags, RegressorMixin, BaseEstimator):
    """Mean position and majority floor / building of several fingerprint estimators.

    Parameters
    ----------
    estimators : sequence of (str, estimator)
        The members (cloned at ``fit``), each a regressor on the RSSI matrix whose target is the ensemble's
        ``y`` (e.g. :class:`ilocalg.wifi.OffsetFingerprint`, :class:`ilocalg.wifi.CascadeFingerprint`).
    n_neighbors : int or None
        Set on every member that has an ``n_neighbors`` parameter (None: leave the members' own).

    Attributes
    ----------
    estimators_ : list of fitted members
    n_features_in_ : int

    Notes
    -----
    ``score`` is R^2; tune with ``scoring=ilocalg.metrics.horizontal_error_scorer()`` for metres.
    """

    def __init__(self, estimators=(), n_neighbors=None):
        self.estimators = estimators
        self.n_neighbors = n_neighbors

    def fit(self, X, y):
        """Fit every member on ``X`` (n, n_aps; dBm, NaN = not heard) and ``y``."""
        members = list(self.estimators)
        if not members:
            raise ValueError("FingerprintEnsemble needs at least one (name, estimator) in estimators")
        for m in members:
            if not (isinstance(m, tuple) and len(m) == 2 and isinstance(m[0], str) and hasattr(m[1], "fit")):
                raise ValueError(f"estimators must be (name, estimator) pairs, got {m!r}")
        x = check_rssi(X, "X", owner=type(self).__name__, valid_dbm=None, copy=False)
        if y is None:
            raise ValueError("this estimator requires y to be passed, but the target y is None "
                             "([x_m, y_m, floor, building] per row, or positions)")
        fitted = []
        for _, est in members:
            e = clone(est)
            if self.n_neighbors is not None and "n_neighbors" in e.get_params():
                e.set_params(n_neighbors=self.n_neighbors)
            fitted.append(e.fit(x, y))
        self.estimators_ = fitted
        self.n_features_in_ = x.shape[1]
        return self

    def predict(self, X, devices=None, times=None) -> np.ndarray:
        """Combined predictions (:func:`combine_predictions`), the shape of the fitted ``y``. ``devices`` and
        ``times`` (each scan's phone and time) go to the members that calibrate per device
        (:func:`wants_devices`)."""
        check_is_fitted(self, "estimators_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=None, copy=False)
        meta = {"devices": devices, "times": times}
        return combine_predictions([e.predict(x, **meta) if wants_devices(e) else e.predict(x)
                                    for e in self.estimators_])


def wants_devices(est) -> bool:
    """Whether ``est`` (or an estimator inside it) calibrates per device (``device_calibration=True``, as
    :class:`ilocalg.wifi.OffsetFingerprint`): its ``predict`` then needs each scan's ``devices`` and ``times``."""
    params = est.get_params(deep=True)
    return any(params[k] is True for k in device_calibration_keys(est))


def device_calibration_keys(est) -> list[str]:
    """The ``device_calibration`` parameters of ``est`` and of the estimators inside it (``get_params`` keys)."""
    return [k for k in est.get_params(deep=True) if k.split("__")[-1] == "device_calibration"]
