"""Wi-Fi scans while walking: scan interval and the age of each reading at its scan's timestamp.

An Android scan result carries, per AP, the time it was last heard (``last_seen``, from
``ScanResult.timestamp``); the scan is stamped when the results are delivered. The age
``t_s - last_seen_s`` is the lag between where a reading was taken and where the scan is stamped.

Re-listed readings
------------------
Android also lists cached results: an AP not heard in the latest sweep reappears with the value
and ``last_seen`` of an earlier sweep. In the ILC 2.0 site1 walks about half of the ``TYPE_WIFI``
lines are such re-listings, with ``last_seen`` moved by about 1 ms. :func:`distinct_readings` keeps
one row per physical reading: for each AP, a row starts a new reading unless its RSSI equals that
of the AP's previous row and its ``last_seen`` lies within ``tol_s`` (default 5 ms) of it; the kept
row is the first scan that lists the reading, so its age is the lag with which that reading first
became available. :func:`reading_ages` with ``distinct=False`` returns the ages of every listed row
(what a consumer that trusts every listed value sees).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["scan_times_s", "scan_intervals_s", "distinct_readings", "reading_ages_s", "RELIST_TOL_S"]

#: two rows of one AP with equal RSSI and last-seen times closer than this are the same reading
RELIST_TOL_S = 0.005


def _need(df: pd.DataFrame, cols, what: str):
    missing = [c for c in cols if c not in df.columns]
    if missing:
        raise ValueError(f"{what}: missing column(s) {missing}; have {list(df.columns)}")


def scan_times_s(wifi: pd.DataFrame) -> np.ndarray:
    """Timestamps (s) of the distinct scans of one walk, sorted."""
    _need(wifi, ["t_s"], "wifi scans")
    return np.unique(wifi["t_s"].to_numpy(dtype=np.float64))


def scan_intervals_s(wifi: pd.DataFrame) -> np.ndarray:
    """Time between consecutive scans of one walk (s), shape (n_scans - 1,)."""
    return np.diff(scan_times_s(wifi))


def distinct_readings(wifi: pd.DataFrame, tol_s: float = RELIST_TOL_S) -> pd.DataFrame:
    """The rows of ``wifi`` that carry a new reading (re-listed cached readings removed).

    Parameters
    ----------
    wifi : DataFrame
        One walk's scans with ``t_s``, ``bssid``, ``rssi_dbm``, ``last_seen_s``.
    tol_s : float
        Two consecutive rows of one AP are the same reading when their RSSI is equal and their
        ``last_seen_s`` differ by at most ``tol_s``.

    Returns
    -------
    DataFrame
        The kept rows, in the input's order, with the input's columns.
    """
    _need(wifi, ["t_s", "bssid", "rssi_dbm", "last_seen_s"], "wifi scans")
    if tol_s < 0:
        raise ValueError(f"tol_s must be >= 0, got {tol_s}")
    w = wifi.reset_index(drop=True)
    order = np.lexsort((w["t_s"].to_numpy(), w["bssid"].to_numpy()))
    s = w.iloc[order]
    same_ap = s["bssid"].to_numpy()[1:] == s["bssid"].to_numpy()[:-1]
    same_rssi = s["rssi_dbm"].to_numpy()[1:] == s["rssi_dbm"].to_numpy()[:-1]
    ls = s["last_seen_s"].to_numpy(dtype=np.float64)
    close = np.abs(np.diff(ls)) <= tol_s + 1e-9
    repeat = np.concatenate([[False], same_ap & same_rssi & close])
    keep = np.zeros(len(w), dtype=bool)
    keep[order[~repeat]] = True
    return w[keep]


def reading_ages_s(wifi: pd.DataFrame, distinct: bool = True, tol_s: float = RELIST_TOL_S) -> np.ndarray:
    """Age of each reading at its scan's timestamp, ``t_s - last_seen_s`` (s).

    With ``distinct=True`` (default) one age per physical reading, taken at the first scan that lists
    it (:func:`distinct_readings`); with ``distinct=False`` one per listed row.
    """
    _need(wifi, ["t_s", "last_seen_s"], "wifi scans")
    w = distinct_readings(wifi, tol_s) if distinct else wifi
    return (w["t_s"].to_numpy(dtype=np.float64) - w["last_seen_s"].to_numpy(dtype=np.float64))
