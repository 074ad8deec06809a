"""Positioning error metrics: horizontal error, error CDF, summary tables, floor/building hits.

References
----------
IPIN / EvAAL competition rules: penalised error = 2-D error + 15 m per wrong floor + 50 m per
wrong building.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = [
    "horizontal_error_m",
    "error_cdf",
    "summary",
    "hit_rate",
    "penalised_error_m",
    "SUMMARY_COLUMNS",
    "summarise_by_method",
    "mean_horizontal_error_m",
    "horizontal_error_scorer",
]

SUMMARY_COLUMNS = ("n", "mean_m", "median_m", "p75_m", "p80_m", "p95_m", "rms_m", "std_m", "max_m")


def _as_xy(a, name: str) -> np.ndarray:
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim == 1 and arr.shape[0] == 2:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] < 2:
        raise ValueError(f"{name} must have shape (n, 2) (x_m, y_m), got {arr.shape}")
    return arr[:, :2]


def horizontal_error_m(est_xy, true_xy) -> np.ndarray:
    """Euclidean 2-D error per sample.

    Parameters
    ----------
    est_xy, true_xy : array_like, shape (n, 2)
        Estimated and true positions, metres.

    Returns
    -------
    ndarray, shape (n,)
        Error in metres; NaN where an estimate is NaN (a missing fix stays visible).
    """
    est = _as_xy(est_xy, "est_xy")
    true = _as_xy(true_xy, "true_xy")
    if est.shape != true.shape:
        raise ValueError(f"est_xy has shape {est.shape} but true_xy has shape {true.shape}")
    if np.isnan(true).any():
        raise ValueError("true_xy contains NaN: ground truth must be complete")
    return np.hypot(est[:, 0] - true[:, 0], est[:, 1] - true[:, 1])


def error_cdf(err_m) -> pd.DataFrame:
    """Empirical CDF of errors: columns ``error_m`` (sorted) and ``fraction`` in (0, 1]."""
    e = np.asarray(err_m, dtype=np.float64).ravel()
    if np.isnan(e).any():
        raise ValueError("error_cdf got NaN errors; drop or count missing fixes explicitly first")
    if e.size == 0:
        raise ValueError("error_cdf got no errors")
    e = np.sort(e)
    return pd.DataFrame({"error_m": e, "fraction": np.arange(1, e.size + 1) / e.size})


def summary(err_m, name: str | None = None) -> pd.Series:
    """Mean, median, p75, p80, p95, RMS, STD (population) and max of errors in metres.

    NaN errors raise: decide explicitly how missing estimates are counted.
    """
    e = np.asarray(err_m, dtype=np.float64).ravel()
    if e.size == 0:
        raise ValueError("summary got no errors")
    if np.isnan(e).any():
        raise ValueError(f"summary got {int(np.isnan(e).sum())} NaN errors of {e.size}")
    vals = [
        e.size,
        e.mean(),
        np.median(e),
        np.percentile(e, 75),
        np.percentile(e, 80),
        np.percentile(e, 95),
        np.sqrt(np.mean(e**2)),
        e.std(),
        e.max(),
    ]
    return pd.Series(vals, index=list(SUMMARY_COLUMNS), name=name, dtype=np.float64)


def hit_rate(pred, true) -> float:
    """Fraction of samples whose predicted label (floor, building) equals the true one."""
    p = np.asarray(pred)
    t = np.asarray(true)
    if p.shape != t.shape:
        raise ValueError(f"pred has shape {p.shape} but true has shape {t.shape}")
    if p.size == 0:
        raise ValueError("hit_rate got no samples")
    return float(np.mean(p == t))


def penalised_error_m(est_xy, true_xy, floor_pred=None, floor_true=None, building_pred=None,
                      building_true=None, floor_penalty_m: float = 15.0,
                      building_penalty_m: float = 50.0) -> np.ndarray:
    """IPIN-style error: 2-D error + ``floor_penalty_m`` per wrong floor + ``building_penalty_m``
    per wrong building (floor difference counted in floors, as in the EvAAL rules)."""
    e = horizontal_error_m(est_xy, true_xy)
    if floor_pred is not None:
        e = e + floor_penalty_m * np.abs(np.asarray(floor_pred) - np.asarray(floor_true))
    if building_pred is not None:
        e = e + building_penalty_m * (np.asarray(building_pred) != np.asarray(building_true))
    return e


def summarise_by_method(points: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per-method mean / median / p90 / max error and the error CDFs of a scored-points table.

    Parameters
    ----------
    points : DataFrame
        One row per scored point, columns ``method`` and ``error_m``.

    Returns
    -------
    summary : DataFrame
        ``method``, ``mean_error_m``, ``median_error_m``, ``p90_error_m``, ``max_error_m``, ``n``
        (methods in order of appearance).
    cdf : DataFrame
        :func:`error_cdf` of each method, with a ``method`` column.
    """
    for c in ("method", "error_m"):
        if c not in points.columns:
            raise ValueError(f"points lack column {c!r}")
    g = points.groupby("method", sort=False)["error_m"]
    summ = pd.DataFrame({"mean_error_m": g.mean(), "median_error_m": g.median(),
                         "p90_error_m": g.quantile(0.9), "max_error_m": g.max(), "n": g.size()}).reset_index()
    cdf = pd.concat([error_cdf(e["error_m"].to_numpy()).assign(method=m)
                     for m, e in points.groupby("method", sort=False)], ignore_index=True)
    return summ, cdf


def mean_horizontal_error_m(y_true, y_pred, missing_error_m: float | None = None) -> float:
    """Mean 2-D error (metres) of predicted positions, with a stated cost for "not located".

    A NaN prediction (the fingerprint estimators' documented result for a scan sharing no access
    point with the training set, :mod:`ilocalg.wifi.preprocessing`) counts as ``missing_error_m``;
    by default the diagonal of the bounding box of ``y_true``, which is at least the distance
    between any two true positions: no answer never scores better than the worst answer inside the
    evaluated area.

    Parameters
    ----------
    y_true, y_pred : array_like, shape (n, >=2)
        True and predicted positions (the first two columns are x, y in metres).
    missing_error_m : float, optional

    Returns
    -------
    float
    """
    t = _as_xy(y_true, "y_true")
    p = _as_xy(y_pred, "y_pred")
    if t.shape != p.shape:
        raise ValueError(f"y_pred has shape {p.shape} but y_true has shape {t.shape}")
    miss = np.isnan(p).any(axis=1)
    e = horizontal_error_m(np.where(miss[:, None], t, p), t)
    if miss.any():
        if missing_error_m is None:
            missing_error_m = float(np.hypot(*(t.max(axis=0) - t.min(axis=0))))
        e[miss] = float(missing_error_m)
    return float(e.mean())


def horizontal_error_scorer(missing_error_m: float | None = None):
    """A scikit-learn scorer: minus :func:`mean_horizontal_error_m` (greater is better), e.g.
    ``GridSearchCV(KnnFingerprint(), {"n_neighbors": [1, 3, 5]}, scoring=horizontal_error_scorer())``.

    Never NaN for a fold holding scans that share no access point with its training part: those count
    as ``missing_error_m`` (see :func:`mean_horizontal_error_m`).
    """
    from sklearn.metrics import make_scorer

    return make_scorer(mean_horizontal_error_m, greater_is_better=False, missing_error_m=missing_error_m)
