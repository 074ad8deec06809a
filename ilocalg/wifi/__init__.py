"""Wi-Fi fingerprint positioning: Simplified-RADAR, Simplified-Horus, KNN / WKNN.

Inputs are RSSI matrices ``X`` of shape (n_samples, n_aps) in dBm with ``NaN`` = not heard (see
:mod:`ilocalg`); every estimator takes the RSSI it substitutes for "not heard" as a parameter
(``not_heard_dbm``). Estimators follow the scikit-learn contract (``fit(X, y)`` -> self,
``predict(X)``; ``y`` = positions in metres, shape (n, 2)).

Modules: :mod:`~ilocalg.wifi.preprocessing` (validation, representations), :mod:`~ilocalg.wifi.knn`
(KNN / WKNN, 罗思奇 et al. 2017 eq. 1-2), :mod:`~ilocalg.wifi.radar` (i-Loc thesis eq. 1-3),
:mod:`~ilocalg.wifi.horus` (i-Loc thesis eq. 5-7), :mod:`~ilocalg.wifi.hierarchical`
(building -> floor -> position), :mod:`~ilocalg.wifi.cascade` (the toolkit's building -> floor ->
position WKNN estimator), :mod:`~ilocalg.wifi.offset` (WKNN with a per-query device offset search),
:mod:`~ilocalg.wifi.ensemble` (AP selection, an averaging ensemble of estimators),
:mod:`~ilocalg.wifi.spots` (an estimator fitted on the per-spot mean fingerprints),
:mod:`~ilocalg.wifi.survey` (the README's survey CSV layout), :mod:`~ilocalg.wifi.candidates` (the toolkit's
candidate configurations and its UJIIndoorLoc headline estimator),
:mod:`~ilocalg.wifi.registry` (the one registry of estimator
factories, name -> factory, used by experiments and the command line), :mod:`~ilocalg.wifi.evaluate`
(fit a registered method on one fingerprint set, locate another), :mod:`~ilocalg.wifi.model_selection`
(scores, a selection-half search, GroupKFold CV on training only and the toolkit ladder).
"""

from ilocalg.wifi.cascade import CascadeFingerprint
from ilocalg.wifi.ensemble import ApSelector, FingerprintEnsemble, combine_predictions
from ilocalg.wifi.evaluate import evaluate_method
from ilocalg.wifi.hierarchical import HierarchicalLocator, locate_flat
from ilocalg.wifi.horus import SimplifiedHorus, fit_horus, horus_predict_index, horus_scores
from ilocalg.wifi.knn import KnnFingerprint, build_index, knn_predict, knn_search, neighbour_weights, vote
from ilocalg.wifi.offset import OffsetFingerprint, device_shift_choice, offset_search
from ilocalg.wifi.preprocessing import (
    REPRESENTATIONS,
    check_positions,
    check_rssi,
    fill_not_heard,
    strongest_ap_mask,
    to_features,
)
from ilocalg.wifi.radar import SimplifiedRadar, radar_predict, union_topk_sq_distances
from ilocalg.wifi.registry import ESTIMATORS, make_estimator, paper_estimators, register_estimator
from ilocalg.wifi.spots import SpotAveragedFingerprint, spot_fingerprints

__all__ = [
    "KnnFingerprint",
    "SimplifiedRadar",
    "SimplifiedHorus",
    "HierarchicalLocator",
    "CascadeFingerprint",
    "OffsetFingerprint",
    "offset_search",
    "device_shift_choice",
    "ApSelector",
    "FingerprintEnsemble",
    "combine_predictions",
    "SpotAveragedFingerprint",
    "spot_fingerprints",
    "locate_flat",
    "ESTIMATORS",
    "register_estimator",
    "make_estimator",
    "paper_estimators",
    "evaluate_method",
    "check_positions",
    "build_index",
    "knn_search",
    "knn_predict",
    "neighbour_weights",
    "vote",
    "radar_predict",
    "union_topk_sq_distances",
    "fit_horus",
    "horus_scores",
    "horus_predict_index",
    "REPRESENTATIONS",
    "check_rssi",
    "fill_not_heard",
    "strongest_ap_mask",
    "to_features",
]
