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

__all__ = ["scan_matrix", "relisted_readings", "merge_relisted_wifi", "RELISTED_WIFI_POLICIES",
           "RELISTED_TOLERANCE_S"]


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
    sid = scans[SCAN_ID].to_numpy()
    sids = np.sort(scans[SCAN_ID].unique())
    t = scans.groupby(SCAN_ID)[T_S].first().loc[sids].to_numpy()
    cols = pd.Index(list(ap_ids))
    if cols.is_unique:      # one hash lookup per reading (not a Python call per reading)
        j = cols.get_indexer(scans[BSSID])
    else:                   # a repeated id: its last column, as a dict {id: column} gives
        col = {a: k for k, a in enumerate(ap_ids)}
        j = scans[BSSID].map(col).fillna(-1).to_numpy().astype(np.int64)
    X = np.full((sids.size, len(cols)), np.nan)
    ok = j >= 0
    if keep is not None:
        keep = np.asarray(keep, dtype=bool)
        if keep.shape != (len(scans),):
            raise ValueError(f"keep must have shape ({len(scans)},), got {keep.shape}")
        ok = ok & keep
    # the row of each reading: its scan's place among the sorted scan ids (every id is there)
    X[np.searchsorted(sids, sid)[ok], j[ok]] = scans[RSSI_DBM].to_numpy(dtype=np.float64)[ok]
    return sids, t, X


#: Policies for Wi-Fi readings that re-list an earlier reading (:func:`relisted_readings`).
RELISTED_WIFI_POLICIES = ("refuse", "merge", "keep")
#: Largest ``last_seen`` shift (s) of a re-listing: measured on the ILC 2020 site1 F1/F2 and site2 F4 walks,
#: the shift between a reading and the same access point's previous one (same RSSI) is 0 or +-1 ms in
#: 99.99 % of the near-equal cases and never 2 ms with the same RSSI; genuine new readings differ by the
#: scan interval (about 2 s).
RELISTED_TOLERANCE_S = 0.001


def relisted_readings(scans: pd.DataFrame, tolerance_s: float = RELISTED_TOLERANCE_S) -> np.ndarray:
    """Which readings re-list the same access point's previous reading (a cached value, not a new one).

    The rule, found on the ILC 2020 walks (about half of their ``TYPE_WIFI`` lines): a reading whose
    access point was heard in an earlier scan with the **same RSSI** and a ``last_seen`` within
    ``tolerance_s`` (0 or +-1 ms: Android re-reports a cached scan result with its timestamp re-rounded)
    is that earlier reading listed again. The comparison is with the access point's previous listing,
    so a reading listed in ten consecutive scans counts once (chains are followed).

    Parameters
    ----------
    scans : DataFrame
        Long scan table (``t_s, scan_id, bssid, rssi_dbm, last_seen_s``), as the ILC loader makes it.

    Returns
    -------
    ndarray of bool, shape (len(scans),)
        True for a re-listing (the first listing is never marked).
    """
    missing = [c for c in (SCAN_ID, BSSID, RSSI_DBM, "last_seen_s") if c not in scans.columns]
    if missing:
        raise ValueError(f"scans lacks the column(s) {missing}")
    n = len(scans)
    if n == 0:
        return np.zeros(0, dtype=bool)
    b = pd.factorize(scans[BSSID])[0]
    sid = scans[SCAN_ID].to_numpy()
    order = np.lexsort((sid, b))                       # by access point, then scan (stable)
    bo, so = b[order], sid[order]
    r = scans[RSSI_DBM].to_numpy(dtype=np.float64)[order]
    ls = scans["last_seen_s"].to_numpy(dtype=np.float64)[order]
    same_ap = np.concatenate([[False], (bo[1:] == bo[:-1]) & (so[1:] > so[:-1])])
    prev_r, prev_ls = np.roll(r, 1), np.roll(ls, 1)
    rel = same_ap & (r == prev_r) & (np.abs(ls - prev_ls) <= tolerance_s + 1e-6)
    out = np.zeros(n, dtype=bool)
    out[order] = rel
    return out


def merge_relisted_wifi(scans: pd.DataFrame, tolerance_s: float = RELISTED_TOLERANCE_S) -> tuple[pd.DataFrame, int]:
    """The scan table with every re-listing (:func:`relisted_readings`) merged into its first listing.

    A re-listed reading stays once, in the scan that first listed it; its re-listings are removed (a
    scan left empty disappears). Returns the table (index reset) and the number of readings merged.
    """
    rel = relisted_readings(scans, tolerance_s)
    return scans[~rel].reset_index(drop=True), int(rel.sum())
