"""Column-name constants and validators for the toolkit's data types (see :mod:`ilocalg`).

Validators raise :class:`ValueError` naming the source, the column or row and what was expected;
they never drop, clip or fill anything.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

__all__ = [
    "T_S",
    "ACC_COLS",
    "GYR_COLS",
    "MAG_COLS",
    "IMU_COLS",
    "SCAN_ID",
    "BSSID",
    "RSSI_DBM",
    "FREQ_MHZ",
    "WIFI_COLS",
    "X_M",
    "Y_M",
    "FLOOR",
    "BUILDING",
    "WAYPOINT_COLS",
    "FingerprintSet",
    "check_time_index",
    "check_imu",
    "check_wifi_scans",
    "check_waypoints",
]

T_S = "t_s"
ACC_COLS = ("acc_x_mps2", "acc_y_mps2", "acc_z_mps2")
GYR_COLS = ("gyr_x_radps", "gyr_y_radps", "gyr_z_radps")
MAG_COLS = ("mag_x_ut", "mag_y_ut", "mag_z_ut")
IMU_COLS = ACC_COLS + GYR_COLS + MAG_COLS

SCAN_ID = "scan_id"
BSSID = "bssid"
RSSI_DBM = "rssi_dbm"
FREQ_MHZ = "freq_mhz"
WIFI_COLS = (T_S, SCAN_ID, BSSID, RSSI_DBM)

X_M = "x_m"
Y_M = "y_m"
FLOOR = "floor"
BUILDING = "building"
WAYPOINT_COLS = (T_S, X_M, Y_M)


def _where(source: str | None) -> str:
    return f"{source}: " if source else ""


def check_time_index(t_s, source: str | None = None, name: str = T_S) -> np.ndarray:
    """Check that times are finite and strictly increasing; return them as float64.

    Raises
    ------
    ValueError
        Naming the first offending row (NaN, duplicate or decreasing time).
    """
    t = np.asarray(t_s, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"{_where(source)}{name} must be one-dimensional, got shape {t.shape}")
    if t.size == 0:
        raise ValueError(f"{_where(source)}{name} is empty")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ValueError(f"{_where(source)}{name} is not finite at row {bad[0]} ({t[bad[0]]})")
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0)
    if bad.size:
        i = bad[0] + 1
        kind = "duplicate" if d[bad[0]] == 0 else "decreasing"
        raise ValueError(
            f"{_where(source)}{name} must be strictly increasing: {kind} timestamp at row {i} "
            f"({t[i]!r} after {t[i - 1]!r})"
        )
    return t


def check_imu(df: pd.DataFrame, source: str | None = None, required=()) -> pd.DataFrame:
    """Validate an IMU log: index ``t_s`` strictly increasing, known float columns, no NaN."""
    if df.index.name != T_S:
        raise ValueError(f"{_where(source)}IMU log must be indexed by {T_S!r}, got {df.index.name!r}")
    check_time_index(df.index.to_numpy(), source)
    unknown = [c for c in df.columns if c not in IMU_COLS]
    if unknown:
        raise ValueError(f"{_where(source)}unknown IMU columns {unknown}; expected a subset of {IMU_COLS}")
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise ValueError(f"{_where(source)}IMU log lacks required columns {missing}")
    for c in df.columns:
        v = df[c].to_numpy()
        if not np.issubdtype(v.dtype, np.floating):
            raise ValueError(f"{_where(source)}IMU column {c!r} must be float, got {v.dtype}")
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise ValueError(f"{_where(source)}IMU column {c!r} is not finite at row {bad[0]}")
    return df


def check_wifi_scans(df: pd.DataFrame, source: str | None = None) -> pd.DataFrame:
    """Validate a long Wi-Fi scan table (columns ``t_s, scan_id, bssid, rssi_dbm``)."""
    missing = [c for c in WIFI_COLS if c not in df.columns]
    if missing:
        raise ValueError(f"{_where(source)}Wi-Fi scans lack columns {missing}")
    for c in (T_S, RSSI_DBM):
        v = df[c].to_numpy(dtype=np.float64)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise ValueError(f"{_where(source)}Wi-Fi column {c!r} is not finite at row {bad[0]}")
    if df[T_S].is_monotonic_increasing is False:
        i = int(np.flatnonzero(np.diff(df[T_S].to_numpy()) < 0)[0]) + 1
        raise ValueError(f"{_where(source)}Wi-Fi scans are not sorted by {T_S}: row {i}")
    dup = df.duplicated(subset=[SCAN_ID, BSSID])
    if dup.any():
        i = int(np.flatnonzero(dup.to_numpy())[0])
        raise ValueError(f"{_where(source)}Wi-Fi scan {df[SCAN_ID].iloc[i]} lists bssid "
                         f"{df[BSSID].iloc[i]!r} twice (row {i})")
    return df


def check_waypoints(df: pd.DataFrame, source: str | None = None) -> pd.DataFrame:
    """Validate ground-truth waypoints (columns ``t_s, x_m, y_m``, times strictly increasing)."""
    missing = [c for c in WAYPOINT_COLS if c not in df.columns]
    if missing:
        raise ValueError(f"{_where(source)}waypoints lack columns {missing}")
    check_time_index(df[T_S].to_numpy(), source)
    for c in (X_M, Y_M):
        v = df[c].to_numpy(dtype=np.float64)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise ValueError(f"{_where(source)}waypoint column {c!r} is not finite at row {bad[0]}")
    return df


@dataclass(frozen=True)
class FingerprintSet:
    """A Wi-Fi fingerprint set.

    Attributes
    ----------
    rssi_dbm : ndarray, shape (n_samples, n_aps), float
        Received signal strength in dBm; ``NaN`` = access point not heard.
    ap_ids : tuple of str, length n_aps
        Access point identifiers (BSSID or the data set's column name).
    x_m, y_m : ndarray, shape (n_samples,)
        Sample positions in the set's planar frame, metres.
    floor, building : ndarray of int, shape (n_samples,), or None
    meta : DataFrame or None
        Any further per-sample columns (user, phone, timestamp ...), row-aligned.
    source : str or None
        Where the set came from (file path or simulator description).
    """

    rssi_dbm: np.ndarray
    ap_ids: tuple
    x_m: np.ndarray
    y_m: np.ndarray
    floor: np.ndarray | None = None
    building: np.ndarray | None = None
    meta: pd.DataFrame | None = field(default=None, compare=False)
    source: str | None = None

    def __post_init__(self):
        r = np.asarray(self.rssi_dbm)
        src = self.source
        if r.ndim != 2:
            raise ValueError(f"{_where(src)}rssi_dbm must be 2-D (n_samples, n_aps), got shape {r.shape}")
        n, m = r.shape
        if len(self.ap_ids) != m:
            raise ValueError(f"{_where(src)}{len(self.ap_ids)} ap_ids for {m} RSSI columns")
        if len(set(self.ap_ids)) != m:
            raise ValueError(f"{_where(src)}ap_ids are not unique")
        for name in ("x_m", "y_m", "floor", "building"):
            v = getattr(self, name)
            if v is None:
                continue
            if np.asarray(v).shape != (n,):
                raise ValueError(f"{_where(src)}{name} has shape {np.asarray(v).shape}, expected ({n},)")
        if self.meta is not None and len(self.meta) != n:
            raise ValueError(f"{_where(src)}meta has {len(self.meta)} rows, expected {n}")

    @property
    def n_samples(self) -> int:
        return int(np.asarray(self.rssi_dbm).shape[0])

    @property
    def n_aps(self) -> int:
        return int(np.asarray(self.rssi_dbm).shape[1])

    @property
    def xy_m(self) -> np.ndarray:
        """Positions as an (n_samples, 2) array."""
        return np.column_stack([self.x_m, self.y_m])

    def subset(self, rows) -> FingerprintSet:
        """Rows selected by a boolean mask or integer index (a new set; nothing is modified)."""
        rows = np.asarray(rows)
        return FingerprintSet(
            rssi_dbm=np.asarray(self.rssi_dbm)[rows],
            ap_ids=self.ap_ids,
            x_m=np.asarray(self.x_m)[rows],
            y_m=np.asarray(self.y_m)[rows],
            floor=None if self.floor is None else np.asarray(self.floor)[rows],
            building=None if self.building is None else np.asarray(self.building)[rows],
            meta=None if self.meta is None else self.meta.iloc[rows].reset_index(drop=True),
            source=self.source,
        )

    def to_frame(self) -> pd.DataFrame:
        """Wide DataFrame: one column per AP plus x_m, y_m (, floor, building)."""
        df = pd.DataFrame(np.asarray(self.rssi_dbm), columns=list(self.ap_ids))
        df[X_M] = self.x_m
        df[Y_M] = self.y_m
        if self.floor is not None:
            df[FLOOR] = self.floor
        if self.building is not None:
            df[BUILDING] = self.building
        return df
