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

__all__ = ["EVALUATE_METHODS", "evaluate_method", "error_budget"]

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
    from scipy.spatial import cKDTree

    e = np.asarray(result["error_m"], dtype=np.float64)
    ok = np.isfinite(e)
    ref = pd.DataFrame({"x": train.x_m, "y": train.y_m, "bf": train.building * 100 + train.floor}).drop_duplicates()
    tbf = test.building * 100 + test.floor
    d1 = np.full(test.n_samples, np.nan)
    d3 = np.full(test.n_samples, np.nan)
    for bf, g in ref.groupby("bf"):
        m = tbf == bf
        if not m.any():
            continue
        pts = g[["x", "y"]].to_numpy()
        q = np.column_stack([test.x_m[m], test.y_m[m]])
        dd, ii = cKDTree(pts).query(q, min(3, len(pts)))
        dd, ii = np.atleast_2d(dd.T).T, np.atleast_2d(ii.T).T
        d1[m] = dd[:, 0]
        d3[m] = np.hypot(*(pts[ii].mean(axis=1) - q).T)
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
