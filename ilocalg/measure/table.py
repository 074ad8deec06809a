"""The measured-parameter table ``data/measured_parameters.csv``: build it from the shared data.

One row per parameter: ``parameter, value, ci_low, ci_high, unit, dataset, method``. Every interval
is a seeded 95 % percentile bootstrap (:func:`ilocalg.measure.stats.bootstrap`), resampling walks,
APs or recordings as the ``method`` column says. ``python -m ilocalg measure`` (or ``make measured``)
rewrites the file; ``tests/test_measured_realdata.py`` recomputes it on a deterministic subsample
and fails when a value leaves its interval.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import REPO_ROOT
from ilocalg.measure import scans
from ilocalg.measure.stats import Estimate, bootstrap

__all__ = ["COLUMNS", "TABLE_PATH", "build_table", "write_table", "scan_rows", "ilc_walk_measures",
           "PARTS"]

COLUMNS = ("parameter", "value", "ci_low", "ci_high", "unit", "dataset", "method")
TABLE_PATH = REPO_ROOT / "data" / "measured_parameters.csv"
PARTS = ("scans", "radio", "gait", "heading")
_ILC = "ILC 2.0 site1 (F1+F2 walks)"


def _row(name: str, est: Estimate, unit: str, dataset: str, method: str) -> dict:
    return {"parameter": name, "value": est.value, "ci_low": est.ci_low, "ci_high": est.ci_high,
            "unit": unit, "dataset": dataset, "method": f"{method} [n={est.n}]"}


def _iqr(x):
    q = np.quantile(x, [0.25, 0.75])
    return float(q[1] - q[0])


def ilc_walk_measures(trace) -> dict:
    """Per-walk raw measurements of one ILC trace (arrays), the input of the ``*_rows`` builders."""
    out = {}
    w = trace.wifi
    if len(w):
        out["scan_interval_s"] = scans.scan_intervals_s(w)
        out["age_distinct_s"] = scans.reading_ages_s(w, distinct=True)
        out["age_listed_s"] = scans.reading_ages_s(w, distinct=False)
        out["n_listed"] = np.array([len(w)])
        out["n_distinct"] = np.array([out["age_distinct_s"].size])
    return out


def scan_rows(walks: list[dict], dataset: str = _ILC) -> list[dict]:
    """Scan interval and reading-age rows from per-walk measures (resampled by walk)."""
    iv = [m["scan_interval_s"] for m in walks if "scan_interval_s" in m and m["scan_interval_s"].size]
    ad = [m["age_distinct_s"] for m in walks if "age_distinct_s" in m]
    al = [m["age_listed_s"] for m in walks if "age_listed_s" in m]
    frac = [np.array([[m["n_distinct"][0], m["n_listed"][0]]]) for m in walks if "n_listed" in m]
    rows = [
        _row("wifi_scan_interval_s", bootstrap(iv, np.median), "s", dataset,
             "median time between consecutive scans while walking; bootstrap over walks"),
        _row("wifi_scan_interval_iqr_s", bootstrap(iv, _iqr), "s", dataset,
             "interquartile range of the scan interval; bootstrap over walks"),
        _row("wifi_scan_interval_p90_s", bootstrap(iv, lambda x: np.quantile(x, 0.9)), "s", dataset,
             "90th percentile of the scan interval; bootstrap over walks"),
        _row("wifi_reading_age_median_s", bootstrap(ad, np.median), "s", dataset,
             "median of t_scan - last_seen over distinct readings (re-listed cached readings: same AP, "
             "same RSSI, last_seen within 5 ms, dropped; age at first listing); bootstrap over walks"),
        _row("wifi_reading_age_iqr_s", bootstrap(ad, _iqr), "s", dataset,
             "interquartile range of the distinct readings' age; bootstrap over walks"),
        _row("wifi_reading_age_p90_s", bootstrap(ad, lambda x: np.quantile(x, 0.9)), "s", dataset,
             "90th percentile of the distinct readings' age; bootstrap over walks"),
        _row("wifi_listed_age_median_s", bootstrap(al, np.median), "s", dataset,
             "median of t_scan - last_seen over every listed row (re-listings included); bootstrap over walks"),
        _row("wifi_relisted_fraction", bootstrap(frac, lambda a: 1.0 - a[:, 0].sum() / a[:, 1].sum()), "1",
             dataset, "share of TYPE_WIFI rows that re-list an earlier reading; bootstrap over walks"),
    ]
    return rows


def build_table(root=None, every: int = 1, parts=PARTS) -> pd.DataFrame:
    """Measure every parameter from the shared data and return the table (columns :data:`COLUMNS`).

    Parameters
    ----------
    root : path, optional
        The data directory (default :func:`ilocalg.io.paths.data_dir`).
    every : int
        ILC site1 subsample (:func:`ilocalg.measure.sources.iter_ilc_site1`); 1 = all walks.
    parts : iterable of str
        Which groups of rows to measure (:data:`PARTS`).
    """
    from ilocalg.measure.sources import iter_ilc_site1

    parts = tuple(parts)
    bad = [p for p in parts if p not in PARTS]
    if bad:
        raise ValueError(f"unknown part(s) {bad}; known: {list(PARTS)}")
    base = Path(root) if root is not None else None
    rows: list[dict] = []
    if any(p in parts for p in ("scans", "heading", "gait")):
        walks = [ilc_walk_measures(tr) for _, _, tr in
                 iter_ilc_site1(None if base is None else base / "ilc2020_site1", every=every)]
        if "scans" in parts:
            rows += scan_rows(walks)
    df = pd.DataFrame(rows, columns=list(COLUMNS))
    if df["parameter"].duplicated().any():
        raise ValueError(f"duplicate parameters: {df.loc[df['parameter'].duplicated(), 'parameter'].tolist()}")
    return df


def write_table(df: pd.DataFrame, path=TABLE_PATH) -> Path:
    """Write the table as CSV (6 significant digits) and return the path."""
    path = Path(path)
    out = df.copy()
    for c in ("value", "ci_low", "ci_high"):
        out[c] = out[c].map(lambda v: float(f"{v:.6g}"))
    path.parent.mkdir(parents=True, exist_ok=True)
    out.to_csv(path, index=False)
    return path
