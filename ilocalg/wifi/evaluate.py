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
import pandas as pd

from ilocalg.io.schema import FingerprintSet
from ilocalg.wifi.hierarchical import HierarchicalLocator, locate_flat
from ilocalg.wifi.horus import SimplifiedHorus
from ilocalg.wifi.registry import DEFAULT_NOT_HEARD_DBM, ESTIMATORS, make_estimator

__all__ = ["EVALUATE_METHODS", "evaluate_method", "nearest_same_floor", "error_budget"]

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
        neighbours' vote, :func:`ilocalg.wifi.locate_flat`; ``"toolkit"`` votes them itself,
        :func:`ilocalg.wifi.candidates.toolkit_estimator`) or ``"hierarchical"`` (KNN building
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
    elif method == "toolkit":  # a cascade-style regressor: fitted on, and predicting, [x, y, floor, building]
        est = make_estimator(method, k, metric, not_heard_dbm).fit(
            train.rssi_dbm, np.column_stack([train.xy_m, train.floor, train.building]).astype(np.float64))
        t1 = time.perf_counter()
        pr = est.predict(test.rssi_dbm)
        t2 = time.perf_counter()
        df = pd.DataFrame(pr, columns=["x_m", "y_m", "floor", "building"])
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


def nearest_same_floor(ref, query, k: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The ``k`` nearest ``ref`` positions of each ``query`` position on the same floor and building.

    ``ref`` (n_ref, 2 or 4) and ``query`` (n_q, 2 or 4): ``x_m, y_m`` and, where present, floor and building
    (columns 2-3). Returns the distances (m) and the rows of ``ref`` (n_q, k), nearest first; ``inf`` and ``-1``
    beyond the references of the query's floor (all of them on a floor without any).
    """
    from scipy.spatial import cKDTree

    ref, query = np.asarray(ref, dtype=np.float64), np.asarray(query, dtype=np.float64)
    key_r = ref[:, 2:4] if ref.shape[1] >= 4 else np.zeros((len(ref), 0))
    key_q = query[:, 2:4] if query.shape[1] >= 4 else np.zeros((len(query), 0))
    dist = np.full((len(query), k), np.inf)
    idx = np.full((len(query), k), -1, dtype=np.int64)
    for key in np.unique(key_q, axis=0):
        mq = (key_q == key).all(axis=1)
        rows = np.flatnonzero((key_r == key).all(axis=1))
        if rows.size:
            kk = min(k, rows.size)
            d, i = cKDTree(ref[rows, :2]).query(query[mq, :2], k=kk)
            dist[mq, :kk] = d.reshape(-1, kk)
            idx[mq, :kk] = rows[i.reshape(-1, kk)]
    return dist, idx


def error_budget(train: FingerprintSet, test: FingerprintSet, result: dict, far_m: float = 15.0) -> pd.DataFrame:
    """Where a result's 2-D error comes from: its mean error over groups of test scans (a diagnostic; it fits and
    chooses nothing).

    Groups: every located scan; floor hit / miss; the scan's phone seen or not in ``train`` (meta ``PHONEID``),
    also as the mean over building-floors of each group's mean weighted by the unseen scans of the floor (floors
    with both groups; the phones' areas differ); the distance from the scan's true position to the nearest
    reference position of ``train`` on its true building and floor (coverage: below 2 m, 2-5 m, 5 m or more);
    errors above ``far_m``. Beside them, two coverage bounds computed from positions alone: the error of the nearest
    reference position (the error of an estimator that always picks the right reference) and of the mean of the
    3 nearest (the error that averaging neighbours costs even when they are the right ones).

    ``result``: ``{"error_m", "floor", ...}`` per test scan (``error_m`` NaN: not located, left out). Returns one row
    per group: ``group``, ``n``, ``share_of_scans``, ``mean_error_m``, ``share_of_total_error`` (NaN for the
    bounds and the weighted rows).
    """
    e = np.asarray(result["error_m"], dtype=np.float64)
    ok = np.isfinite(e)
    ref = np.unique(np.column_stack([train.xy_m, train.floor, train.building]), axis=0)
    q = np.column_stack([test.xy_m, test.floor, test.building])
    tbf = test.building * 100 + test.floor
    dist, idx = nearest_same_floor(ref, q, 3)
    d1 = np.where(np.isfinite(dist[:, 0]), dist[:, 0], np.nan)      # NaN: no training reference on the floor
    used = idx >= 0
    mean_xy = (ref[np.maximum(idx, 0), :2] * used[..., None]).sum(axis=1) / np.maximum(used.sum(axis=1), 1)[:, None]
    d3 = np.where(used[:, 0], np.hypot(*(mean_xy - q[:, :2]).T), np.nan)
    total = e[ok].sum()
    rows = []

    def add(name, mask, weighted=None):
        m = mask & ok
        rows.append({"group": name, "n": int(m.sum()), "share_of_scans": m.sum() / ok.sum(),
                     "mean_error_m": float(e[m].mean()) if weighted is None else weighted,
                     "share_of_total_error": e[m].sum() / total if weighted is None else np.nan})

    add("all located scans", ok)
    hit = np.asarray(result["floor"]) == test.floor
    add("floor hit", hit)
    add("floor missed", ~hit)
    if test.meta is not None and train.meta is not None and "PHONEID" in test.meta and "PHONEID" in train.meta:
        seen = test.meta["PHONEID"].isin(set(train.meta["PHONEID"])).to_numpy()
        add("phone seen in training", seen)
        add("phone not seen in training", ~seen)
        d = pd.DataFrame({"e": e, "seen": seen, "bf": tbf})[ok]
        t = d.groupby(["bf", "seen"])["e"].agg(["mean", "size"]).unstack("seen")
        t = t.reindex(columns=pd.MultiIndex.from_product([["mean", "size"], [False, True]])).dropna()
        if len(t):
            w = t[("size", False)]
            both = np.isin(tbf, t.index.to_numpy())
            for flag, label in ((True, "seen"), (False, "not seen")):
                add(f"phone {label}, floor-weighted (floors with both)", both & (seen == flag),
                    float((t[("mean", flag)] * w).sum() / w.sum()))
    for lo, hi, label in ((0.0, 2.0, "< 2 m"), (2.0, 5.0, "2-5 m"), (5.0, np.inf, ">= 5 m")):
        add(f"nearest training reference {label}", (d1 >= lo) & (d1 < hi))
    add(f"error > {far_m:g} m", e > far_m)
    for name, v in (("bound: nearest training reference", d1), ("bound: mean of the 3 nearest references", d3)):
        rows.append({"group": name, "n": int(np.isfinite(v).sum()), "share_of_scans": np.isfinite(v).mean(),
                     "mean_error_m": float(np.nanmean(v)), "share_of_total_error": np.nan})
    return pd.DataFrame(rows)
