"""Long Wi-Fi scan table -> RSSI matrix (one row per scan, one column per access point).

The long scan table and the fingerprint matrix are the data types documented in :mod:`ilocalg`;
this is the one conversion between them, used by the fingerprint databases built from walks
(:func:`ilocalg.io.ilc.ilc_fingerprints`) and by the queries of the track pipeline
(:func:`ilocalg.track.wifi_fixes`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.io.schema import BSSID, RSSI_DBM, SCAN_ID, T_S

__all__ = ["scan_matrix"]


def scan_matrix(scans: pd.DataFrame, ap_ids, keep=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """RSSI matrix of a long scan table over the access points ``ap_ids``.

    Parameters
    ----------
    scans : DataFrame
        Long scan table (``t_s, scan_id, bssid, rssi_dbm``), one row per access point heard in a
        scan; a BSSID appears at most once per scan.
    ap_ids : sequence of str
        The matrix columns, in order. Readings of other access points are not in the matrix.
    keep : array_like of bool, shape (len(scans),), optional
        Readings to put in the matrix (e.g. not stale); the others leave NaN. Every scan keeps its
        row, even when none of its readings is kept.

    Returns
    -------
    scan_ids : ndarray of int, shape (m,)
        Every scan id of ``scans``, increasing.
    t_s : ndarray, shape (m,)
        Time of each scan (its first row's ``t_s``), seconds.
    rssi_dbm : ndarray, shape (m, len(ap_ids))
        ``NaN`` where the access point was not heard (or its reading not kept).
    """
    missing = [c for c in (T_S, SCAN_ID, BSSID, RSSI_DBM) if c not in scans.columns]
    if missing:
        raise ValueError(f"scans lacks the column(s) {missing}")
    sids = np.sort(scans[SCAN_ID].unique())
    t = scans.groupby(SCAN_ID)[T_S].first().loc[sids].to_numpy()
    col = {a: j for j, a in enumerate(ap_ids)}
    rowof = {s: i for i, s in enumerate(sids)}
    X = np.full((sids.size, len(col)), np.nan)
    j = scans[BSSID].map(col)
    ok = j.notna().to_numpy()
    if keep is not None:
        keep = np.asarray(keep, dtype=bool)
        if keep.shape != (len(scans),):
            raise ValueError(f"keep must have shape ({len(scans)},), got {keep.shape}")
        ok = ok & keep
    X[scans[SCAN_ID].map(rowof).to_numpy()[ok], j.to_numpy()[ok].astype(np.int64)] = \
        scans[RSSI_DBM].to_numpy(dtype=np.float64)[ok]
    return sids, t, X
