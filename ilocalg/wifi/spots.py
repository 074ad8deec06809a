"""Fingerprints averaged per reference spot: one denoised fingerprint per surveyed place (a toolkit step).

Beyond the papers (a "toolkit" method, not a reproduction). A survey such as UJIIndoorLoc records several scans at
each reference spot (19 937 training scans at 933 distinct ``[x_m, y_m, floor, building]`` targets; the set's
BUILDINGID, FLOOR, SPACEID, RELATIVEPOSITION name 905 spots). :class:`SpotAveragedFingerprint` fits any fingerprint
estimator on the mean fingerprint of each spot (:func:`ilocalg.wifi.preprocessing.mean_fingerprints`: the mean of
the readings where an AP was heard, an AP kept where it was heard in at least ``min_heard_fraction`` of the spot's
scans), so that a query meets one denoised fingerprint per place instead of a crowd of noisy scans from the place
best covered. A spot is a distinct row of the target ``y``: no meta column is needed, and the estimator composes in
a :class:`~sklearn.pipeline.Pipeline` and a :class:`ilocalg.wifi.FingerprintEnsemble` (beside a member fitted on
the raw scans: "raw + averaged").

The wrapper has no ``n_neighbors`` parameter of its own (the inner estimator's is ``estimator__n_neighbors``), so
a :class:`~ilocalg.wifi.FingerprintEnsemble` that sets one K on its members leaves the averaged member's K alone:
a spot stands for several scans, so its K is chosen separately.

References
----------
Bahl, P., Padmanabhan, V. N. (2000). RADAR: an in-building RF-based user location and tracking system. IEEE
INFOCOM 2000 (the radio map holds the mean signal strength per reference point).
Torres-Sospedra, J. et al. (2014). UJIIndoorLoc: a new multi-building and multi-floor database for WLAN
fingerprint-based indoor localization problems. IPIN 2014 (reference spots: SPACEID, RELATIVEPOSITION).
"""

from __future__ import annotations

import hashlib

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin, clone
from sklearn.utils.validation import check_is_fitted

from ilocalg.wifi.preprocessing import RssiPositionTags, check_positions, check_rssi, mean_fingerprints

__all__ = ["spot_fingerprints", "SpotAveragedFingerprint"]


def spot_fingerprints(rssi_dbm, y, min_heard_fraction: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The mean fingerprint of each reference spot (a distinct row of ``y``) and the spot's target.

    Parameters
    ----------
    rssi_dbm : ndarray (n, n_aps)
        Training scans, dBm, NaN = not heard.
    y : ndarray (n,) or (n, d)
        Targets (e.g. ``[x_m, y_m, floor, building]``); identical rows are one spot.
    min_heard_fraction : float in [0, 1]
        An AP enters a spot's fingerprint only where heard in at least this fraction of the spot's scans
        (0: wherever heard at least once).

    Returns
    -------
    fp : ndarray (n_spots, n_aps)
        Mean dBm over the scans that heard the AP, NaN = not heard (in order of first appearance).
    y_spot : ndarray (n_spots,) or (n_spots, d)
        The spots' targets, in ``y``'s layout.
    """
    x = check_rssi(rssi_dbm, "X", copy=False)
    yy = check_positions(y, x.shape[0])
    key = (_digest(x), _digest(yy), float(min_heard_fraction))
    hit = _SPOTS_MEMO.get(key)
    if hit is None:
        fp, pts, _ = mean_fingerprints(x, yy, min_heard_fraction)
        hit = (fp, pts[:, 0] if yy.ndim == 1 else pts)
        for a in hit:
            a.setflags(write=False)
        _SPOTS_MEMO[key] = hit
        while len(_SPOTS_MEMO) > _SPOTS_MEMO_SIZE:
            _SPOTS_MEMO.pop(next(iter(_SPOTS_MEMO)))
    return hit[0].copy(), hit[1].copy()


#: The last few :func:`spot_fingerprints` results by content (a CV fits several spot members on one fold's
#: training part: the per-spot means are computed once per fold); read-only arrays, the same values.
_SPOTS_MEMO: dict = {}
_SPOTS_MEMO_SIZE = 4


def _digest(a: np.ndarray) -> tuple:
    """Shape, dtype and a BLAKE2b hash of ``a``'s bytes (a content key)."""
    a = np.ascontiguousarray(a)
    return a.shape, a.dtype.str, hashlib.blake2b(a.view(np.uint8), digest_size=16).hexdigest()


class SpotAveragedFingerprint(RssiPositionTags, RegressorMixin, BaseEstimator):
    """Fit a fingerprint estimator on the per-spot mean fingerprints (:func:`spot_fingerprints`).

    Parameters
    ----------
    estimator : estimator or None
        The fingerprint estimator fitted on the spots (cloned); None: :class:`ilocalg.wifi.OffsetFingerprint`
        with its defaults.
    min_heard_fraction : float in [0, 1]
        As :func:`spot_fingerprints`.

    Attributes
    ----------
    estimator_ : the fitted inner estimator
    n_spots_ : int, distinct targets (spots) in the training set
    n_features_in_ : int

    Notes
    -----
    ``score`` is R^2; tune with ``scoring=ilocalg.metrics.horizontal_error_scorer()`` for metres. The inner
    estimator's K must not exceed the number of spots (its own ``fit`` says so when it does).
    """

    def __init__(self, estimator=None, min_heard_fraction=0.0):
        self.estimator = estimator
        self.min_heard_fraction = min_heard_fraction

    def fit(self, X, y):
        """Average ``X`` (n, n_aps; dBm, NaN = not heard) per distinct row of ``y`` and fit the inner estimator."""
        x = check_rssi(X, "X", owner=type(self).__name__, valid_dbm=None, copy=False)
        if y is None:
            raise ValueError("this estimator requires y to be passed, but the target y is None "
                             "([x_m, y_m, floor, building] per row, or positions)")
        return self._fit_spots(*spot_fingerprints(x, y, self.min_heard_fraction), x.shape[1])

    def _fit_spots(self, fp: np.ndarray, y_spot: np.ndarray, n_features: int):
        """:meth:`fit` from the spots' fingerprints and targets (:func:`spot_fingerprints` of the training scans,
        ``n_features`` AP columns): members that share the training scans share the averaging
        (:func:`ilocalg.wifi.model_selection.fit_members`)."""
        from ilocalg.wifi.offset import OffsetFingerprint

        est = OffsetFingerprint() if self.estimator is None else self.estimator
        if not hasattr(est, "fit"):
            raise ValueError(f"estimator must be a fingerprint estimator with fit/predict, got {est!r}")
        self.estimator_ = clone(est).fit(fp, y_spot)
        self.n_spots_ = int(fp.shape[0])
        self.n_features_in_ = int(n_features)
        return self

    def predict(self, X, **meta) -> np.ndarray:
        """The inner estimator's prediction (the layout of the fitted ``y``); ``meta`` (each scan's ``devices`` and
        ``times``, for a device-calibrated inner estimator) is passed on."""
        check_is_fitted(self, "estimator_")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=None, copy=False)
        return self.estimator_.predict(x, **meta)

    def predict_weight_powers(self, X, powers, **meta) -> list[np.ndarray]:
        """The inner estimator's ``predict_weight_powers`` (one neighbour search for several exponents); a
        ValueError when the inner estimator has none."""
        check_is_fitted(self, "estimator_")
        if not hasattr(self.estimator_, "predict_weight_powers"):
            raise ValueError(f"{type(self.estimator_).__name__} has no predict_weight_powers")
        x = check_rssi(X, "X", n_aps=self.n_features_in_, owner=type(self).__name__, valid_dbm=None, copy=False)
        return self.estimator_.predict_weight_powers(x, powers, **meta)
