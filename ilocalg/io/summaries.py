"""Summaries of loaded Indoor Location Competition 2.0 traces and of the real data sets (for the data tour).

All numbers are computed from the loaded data: sample rates from the median sampling interval,
Wi-Fi scan statistics from the long scan table, walk length as the polyline length through the
surveyor's waypoints (a lower bound of the distance walked: the surveyor walks straight between
waypoints only approximately).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import DATASETS
from ilocalg.io.paths import data_dir as default_data_dir
from ilocalg.io.schema import BSSID, SCAN_ID, T_S, X_M, Y_M

__all__ = ["sample_rate_hz", "aps_per_scan", "walk_length_m", "trace_summary", "floor_summary",
           "dataset_availability", "real_dataset_summaries"]


def sample_rate_hz(t_s) -> float:
    """Sample rate as 1 / median interval (NaN for fewer than 2 samples)."""
    t = np.asarray(t_s, dtype=np.float64)
    if t.size < 2:
        return float("nan")
    return float(1.0 / np.median(np.diff(t)))


def aps_per_scan(wifi: pd.DataFrame) -> pd.Series:
    """Number of access points heard in each scan (index ``scan_id``)."""
    if not len(wifi):
        return pd.Series([], dtype=np.int64, name="n_aps")
    return wifi.groupby(SCAN_ID)[BSSID].nunique().rename("n_aps")


def walk_length_m(waypoints: pd.DataFrame) -> float:
    """Length (m) of the polyline through the waypoints in time order (0 for fewer than 2)."""
    xy = waypoints[[X_M, Y_M]].to_numpy(dtype=np.float64)
    if len(xy) < 2:
        return 0.0
    return float(np.hypot(*np.diff(xy, axis=0).T).sum())


def trace_summary(trace) -> dict:
    """One row of numbers describing an :class:`ilocalg.io.ilc.IlcTrace`.

    Keys: ``trace``, ``duration_s`` (IMU span), ``imu_rate_hz``, ``n_imu``, ``n_scans``,
    ``scan_interval_s`` (median), ``aps_per_scan_median``, ``aps_per_scan_max``, ``n_bssids``,
    ``rssi_median_dbm``, ``ap_age_median_s`` (scan time minus the AP's last-seen time: Android
    reports cached readings), ``n_waypoints``, ``walk_length_m``, ``mean_speed_mps`` (walk length over the
    waypoint time span), ``n_skipped`` (records skipped), ``n_duplicate_bssid_dropped``.
    """
    imu_t = trace.imu.index.to_numpy(dtype=np.float64)
    wifi = trace.wifi
    aps = aps_per_scan(wifi)
    scan_t = wifi.groupby(SCAN_ID)[T_S].first().to_numpy() if len(wifi) else np.array([])
    wp = trace.waypoints
    length = walk_length_m(wp)
    span = float(wp[T_S].iloc[-1] - wp[T_S].iloc[0]) if len(wp) > 1 else float("nan")
    return {
        "trace": trace.name,
        "duration_s": float(imu_t[-1] - imu_t[0]) if imu_t.size > 1 else float("nan"),
        "imu_rate_hz": sample_rate_hz(imu_t),
        "n_imu": int(imu_t.size),
        "n_scans": int(aps.size),
        "scan_interval_s": float(np.median(np.diff(scan_t))) if scan_t.size > 1 else float("nan"),
        "aps_per_scan_median": float(aps.median()) if aps.size else float("nan"),
        "aps_per_scan_max": int(aps.max()) if aps.size else 0,
        "n_bssids": int(wifi[BSSID].nunique()) if len(wifi) else 0,
        "rssi_median_dbm": float(wifi["rssi_dbm"].median()) if len(wifi) else float("nan"),
        "ap_age_median_s": (float((wifi[T_S] - wifi["last_seen_s"]).median())
                            if len(wifi) and "last_seen_s" in wifi else float("nan")),
        "n_waypoints": int(len(wp)),
        "walk_length_m": length,
        "mean_speed_mps": length / span if span and np.isfinite(span) and span > 0 else float("nan"),
        "n_skipped": int(sum(trace.skipped.values())),
        "n_duplicate_bssid_dropped": int(trace.n_duplicate_bssid_dropped),
    }


def floor_summary(traces) -> pd.DataFrame:
    """:func:`trace_summary` of every trace (a dict or iterable of traces), one row each, plus a total row.

    The ``total`` row sums counts, durations and lengths (``n_bssids``: distinct BSSIDs over all
    traces) and takes medians of rates and per-scan statistics.
    """
    items = list(traces.values() if isinstance(traces, dict) else traces)
    df = pd.DataFrame([trace_summary(t) for t in items])
    if df.empty:
        raise ValueError("floor_summary: no traces given")
    tot = {"trace": "total"}
    for c in df.columns[1:]:
        if c.startswith(("n_", "walk_length", "duration")):
            tot[c] = df[c].sum()
        else:
            tot[c] = df[c].median()
    tot["n_bssids"] = int(pd.concat([t.wifi[BSSID] for t in items]).nunique())
    all_df = pd.concat([df, pd.DataFrame([tot])], ignore_index=True)
    return all_df


def dataset_availability(data_dir: str | Path | None = None) -> pd.DataFrame:
    """Which real data sets are present under ``data_dir`` (default :func:`ilocalg.io.paths.data_dir`)."""
    root = Path(data_dir) if data_dir else default_data_dir()
    rows = []
    for name, where in DATASETS.items():
        p = root / name
        rows.append({"dataset": name, "present": p.is_dir(), "download": where})
    return pd.DataFrame(rows)


def real_dataset_summaries(data_dir: str | Path | None = None, fast: bool = False) -> dict[str, pd.DataFrame]:
    """Summaries of the real sets present under ``data_dir`` (absent sets are simply left out): UJIIndoorLoc
    files (rows, APs, APs heard per scan, buildings, floors), the Oxford in-hand archive's recordings (rate,
    duration, true steps) and the ILC 2.0 site2 F4 traces (:func:`floor_summary`); ``fast`` reads 3 of each."""
    root = Path(data_dir) if data_dir else default_data_dir()
    out = {}
    uji = root / "ujiindoorloc"
    if uji.is_dir():
        from ilocalg.io.ujiindoorloc import load_ujiindoorloc

        rows = []
        for stem in ("trainingData", "validationData"):
            f = next((p for p in (uji / f"{stem}.csv.gz", uji / f"{stem}.csv") if p.exists()), None)
            if f is None:
                continue
            fs = load_ujiindoorloc(f)
            heard = np.sum(~np.isnan(fs.rssi_dbm), axis=1)
            rows.append({"file": f.name, "rows": fs.n_samples, "aps": fs.n_aps,
                         "aps_heard_per_scan_median": float(np.median(heard)),
                         "buildings": int(np.unique(fs.building).size), "floors": int(np.unique(fs.floor).size)})
        out["ujiindoorloc"] = pd.DataFrame(rows)
    ox = root / "oxford_step_counter" / "optimisation_data.tar.xz"
    if ox.exists():
        from ilocalg.io.oxford import list_oxford_archive, load_oxford_archive

        # the full run reads every recording in one pass over the xz archive (listing it first is a second pass)
        recs = load_oxford_archive(ox, list_oxford_archive(ox)[:3]) if fast else load_oxford_archive(ox)
        rows = []
        for r in recs:
            t = r.imu.index.to_numpy()
            rows.append({"recording": r.name, "rate_hz": sample_rate_hz(t), "duration_s": float(t[-1] - t[0]),
                         "true_steps": int(r.true_steps)})
        out["oxford_step_counter"] = pd.DataFrame(rows)
    ilc = root / "ilc2020_site2_F4"
    if ilc.is_dir():
        from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor

        names = list_ilc_traces(ilc)
        floor = load_ilc_floor(ilc, names=names[:3] if fast else None, duplicate_bssid="keep_latest",
                           relisted_wifi="keep")
        out["ilc2020_site2_F4"] = floor_summary(floor.traces)
    return out
