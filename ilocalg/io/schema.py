"""Column-name constants, valid ranges and validators for the toolkit's data types (see :mod:`ilocalg`).

Validators raise :class:`ValueError` naming the source, the column or row and what was expected;
they never drop, clip or fill anything.

Valid ranges
------------
:data:`FIELD_RANGES` declares, once, the physically possible range of every field a loader reads
(field -> minimum, maximum, unit, integer or not, where the bound comes from). Every loader checks
its values with :func:`check_range` right after parsing, so an error names the file's line and
column: ``trainingData.csv: line 1203, column WAP017: value 50 is outside [-110, 0] dBm``.
Integers are checked before they are cast, so a value that would overflow int64 (``1e20``) is an
error, not a numpy warning. NaN is outside every range. The bounds are deliberately wide (what a
phone can physically report, not what a walk usually shows): they catch corrupt values, not
unusual walks. A plain table and one vectorised check are enough here; a schema library
(pandera) would add a dependency for the same comparison and could not name a file's line.
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
    "FieldRange",
    "FIELD_RANGES",
    "MAX_RECORDING_S",
    "check_range",
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


@dataclass(frozen=True)
class FieldRange:
    """Valid range of one field: ``lo <= value <= hi`` (in ``unit``), whole numbers if ``integer``."""

    lo: float
    hi: float
    unit: str
    integer: bool = False
    why: str = ""


#: Longest recording a loader accepts, s (one day). Bounds the memory of any resampling that
#: follows (50 Hz x 3 axes x 1 day = 100 MB) and catches a corrupt timestamp far in the future.
MAX_RECORDING_S = 86400.0

#: The valid range of every field read by a loader (one place; see the module docstring).
FIELD_RANGES: dict[str, FieldRange] = {
    RSSI_DBM: FieldRange(-110.0, 0.0, "dBm", why="received power of a Wi-Fi beacon at a phone; the weakest "
                                                 "readings in UJIIndoorLoc (Torres-Sospedra 2014) are -104 dBm"),
    FREQ_MHZ: FieldRange(2400.0, 7125.0, "MHz", why="IEEE 802.11 2.4, 5 and 6 GHz bands"),
    "acc_mps2": FieldRange(-400.0, 400.0, "m/s^2", why="above any phone accelerometer's full scale (+-16 g or "
                                                       "+-32 g = 314 m/s^2)"),
    "gyr_radps": FieldRange(-70.0, 70.0, "rad/s", why="+-4000 deg/s, twice the largest phone gyroscope range"),
    "mag_ut": FieldRange(-5000.0, 5000.0, "uT", why="phone magnetometer full scale (+-4912 uT, AK09916)"),
    "rotvec": FieldRange(-1.0, 1.0, "", why="vector part of a unit quaternion"),
    "lat_deg": FieldRange(-90.0, 90.0, "deg"),
    "lon_deg": FieldRange(-180.0, 180.0, "deg"),
    "xy_m": FieldRange(-2.0037508e7, 2.0037508e7, "m", why="half the Web-Mercator world width; holds every local "
                                                          "and projected frame the loaders return"),
    "map_size_m": FieldRange(1.0, 1.0e4, "m", why="a floor map between 1 m and 10 km wide"),
    FLOOR: FieldRange(-20.0, 200.0, "", integer=True, why="floor numbers of existing buildings"),
    BUILDING: FieldRange(0.0, 1.0e6, "", integer=True),
    "id": FieldRange(0.0, 1.0e9, "", integer=True, why="small non-negative identifiers (space, user, phone)"),
    "count": FieldRange(0.0, 1.0e9, "", integer=True, why="cumulative step or record counters"),
    "foot_state": FieldRange(0.0, 1.0, "", integer=True, why="heel sensor: 0 = foot up, 1 = foot down"),
    "unix_time_s": FieldRange(0.0, 4.102444800e9, "s", why="1970 to 2100"),
    "unix_time_ms": FieldRange(0.0, 4.102444800e12, "ms", why="1970 to 2100"),
    "elapsed_s": FieldRange(0.0, MAX_RECORDING_S, "s", why="time since the recording's first sample"),
}


def _fmt(v) -> str:
    v = float(v)
    return f"{v:.15g}" if np.isfinite(v) else str(v)


def check_range(values, field_name: str, source=None, lines=None, columns=None) -> np.ndarray:
    """Check values against :data:`FIELD_RANGES` (vectorised); return them as float64.

    Parameters
    ----------
    values : array_like, shape (n,) or (n, k)
    field_name : str
        Key of :data:`FIELD_RANGES`.
    source : str, optional
        File name for the message.
    lines : sequence of int or str, length n, optional
        The file line of each row (or, for files without lines such as JSON, a str naming the
        row's place); without it the message names the row (0-based).
    columns : str or sequence of str, optional
        Column name(s) for the message (one per column of a 2-D ``values``); default
        ``field_name``; ``""`` names no column.

    Raises
    ------
    ValueError
        ``SOURCE: line N, column COL: value V is outside [LO, HI] UNIT`` for the first bad value
        (row-major order), or ``... value V is not a whole number`` for an integer field.
    """
    spec = FIELD_RANGES[field_name]
    v = np.asarray(values, dtype=np.float64)
    if v.size == 0:
        return v
    if not spec.integer and spec.lo <= v.min() and v.max() <= spec.hi:  # False for a NaN: then found below
        return v
    v2 = v.reshape(v.shape[0], -1) if v.ndim else v.reshape(1, 1)
    ok = (v2 >= spec.lo) & (v2 <= spec.hi)
    whole = True
    if spec.integer:
        with np.errstate(invalid="ignore"):
            frac = ok & (v2 != np.floor(v2))
        whole = not frac.any()
    if ok.all() and whole:
        return v
    bad = np.argwhere(~ok) if not ok.all() else np.argwhere(frac)
    i, j = (int(x) for x in bad[0])
    if columns is None:
        col = field_name
    elif isinstance(columns, str):
        col = columns
    else:
        col = columns[j]
    if lines is None:
        where = f"row {i}"
    elif isinstance(lines[i], str):
        where = lines[i]
    else:
        where = f"line {int(lines[i])}"
    where += f", column {col}" if col else ""
    unit = f" {spec.unit}" if spec.unit else ""
    if not ok[i, j]:
        what = f"value {_fmt(v2[i, j])} is outside [{_fmt(spec.lo)}, {_fmt(spec.hi)}]{unit}"
    else:
        what = f"value {_fmt(v2[i, j])} is not a whole number"
    raise ValueError(f"{_where(source)}{where}: {what}")


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
    if not np.isfinite(t).all():
        bad = np.flatnonzero(~np.isfinite(t))
        raise ValueError(f"{_where(source)}{name} is not finite at row {bad[0]} ({t[bad[0]]})")
    d = np.diff(t)
    if not (d > 0).all():
        bad = np.flatnonzero(d <= 0)
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
        if not np.isfinite(v).all():
            bad = np.flatnonzero(~np.isfinite(v))
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
