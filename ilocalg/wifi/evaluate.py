"""Fit a registered Wi-Fi method on one fingerprint set and locate another (position, floor, building).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 3.
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Eq. (1)-(2).
"""

from __future__ import annotations

import time

import numpy as np

from ilocalg.io.schema import FingerprintSet
from ilocalg.wifi.hierarchical import HierarchicalLocator, locate_flat
from ilocalg.wifi.horus import SimplifiedHorus
from ilocalg.wifi.registry import DEFAULT_NOT_HEARD_DBM, ESTIMATORS, make_estimator

__all__ = ["EVALUATE_METHODS", "evaluate_method"]

#: Methods :func:`evaluate_method` accepts: every registered estimator, and ``"hierarchical"``.
EVALUATE_METHODS = (*ESTIMATORS, "hierarchical")


def evaluate_method(train: FingerprintSet, test: FingerprintSet, method: str, k: int | None = None,
                    metric: str = "euclidean", not_heard_dbm: float = DEFAULT_NOT_HEARD_DBM) -> dict:
    """Fit ``method`` on ``train`` and locate every scan of ``test``.

    Parameters
    ----------
    train, test : FingerprintSet
    method : str
        A key of :data:`ilocalg.wifi.registry.ESTIMATORS` (flat search; floor and building by the
        neighbours' vote, :func:`ilocalg.wifi.locate_flat`) or ``"hierarchical"`` (KNN building
        vote -> KNN floor vote inside the building -> KNN position inside the floor,
        :class:`ilocalg.wifi.HierarchicalLocator`).
    k, metric, not_heard_dbm
        Passed to :func:`ilocalg.wifi.registry.make_estimator`.

    Returns
    -------
    dict
        Arrays ``error_m`` (2-D error in the set's metres), ``floor``, ``building``, ``xy_m`` and the
        times ``fit_s``, ``predict_s`` (s); ``n_no_shared_ap``: test scans sharing no access point
        with the training set (their position, floor, building and error are NaN, the documented
        no-AP result of :mod:`ilocalg.wifi.preprocessing`).
    """
    t0 = time.perf_counter()
    if method == "hierarchical":
        clf = make_estimator("knn", k, metric, not_heard_dbm)
        loc = HierarchicalLocator(clf).fit(train.rssi_dbm, train.xy_m, train.floor, train.building)
        t1 = time.perf_counter()
        df = loc.predict(test.rssi_dbm)
        t2 = time.perf_counter()
    else:
        est = make_estimator(method, k, metric, not_heard_dbm)
        if isinstance(est, SimplifiedHorus):
            est.fit(train.rssi_dbm, np.column_stack([train.xy_m, train.floor, train.building]))
        else:
            est.fit(train.rssi_dbm, train.xy_m)
        t1 = time.perf_counter()
        df = locate_flat(est, test.rssi_dbm, train.floor, train.building)
        t2 = time.perf_counter()
    xy = df[["x_m", "y_m"]].to_numpy()
    return {
        "error_m": np.hypot(xy[:, 0] - test.x_m, xy[:, 1] - test.y_m),
        "floor": df["floor"].to_numpy(),
        "building": df["building"].to_numpy(),
        "xy_m": xy,
        "n_no_shared_ap": int(np.isnan(xy[:, 0]).sum()),
        "fit_s": t1 - t0,
        "predict_s": t2 - t1,
    }
