"""IPIN competition smartphone logfiles (Track 3, "smartphone-based, off-site").

A logfile is plain text, one record per line, fields separated by ``;``; lines starting with
``%`` are comments. The records read here:

=====  ============================================================================  ============
type   fields after the type                                                         kept as
=====  ============================================================================  ============
ACCE   AppTimestamp(s); SensorTimestamp(s); Acc_X; Acc_Y; Acc_Z (m/s^2); Accuracy    ``acc``
GYRO   AppTimestamp(s); SensorTimestamp(s); Gyr_X; Gyr_Y; Gyr_Z (rad/s); Accuracy    ``gyr``
MAGN   AppTimestamp(s); SensorTimestamp(s); Mag_X; Mag_Y; Mag_Z (uT); Accuracy       ``mag``
WIFI   AppTimestamp(s); SensorTimeStamp(s); Name_SSID; MAC_BSSID; Frequency; RSS     ``wifi``
POSI   Timestamp(s); Counter; Latitude(deg); Longitude(deg); floor_ID; Building_ID   ``positions``
=====  ============================================================================  ============

Every other record type (AHRS, PRES, LIGH, PROX, GNSS, BLE4, SOUN, ...) is skipped and counted in
:attr:`IpinLog.skipped`; its fields are not checked.

Choices
-------
Time
    ``t_s`` is the AppTimestamp (seconds since the app started), the one clock shared by every
    record type (POSI only has it). The sensor's own timestamp is kept as ``sensor_t_s`` in
    :attr:`IpinLog.sensor_t_s`. IPIN sensors are not sampled together, so the IMU is returned as
    three per-sensor logs (``acc``, ``gyr``, ``mag``), each an IMU log in the sense of
    :mod:`ilocalg` (a subset of the IMU columns, its own strictly increasing ``t_s`` index).
    ``time="sensor"`` indexes the IMU logs by SensorTimestamp instead.
Wi-Fi scans
    A scan = consecutive WIFI records sharing one AppTimestamp. The frequency column is kept as
    ``freq_mhz``.
Positions
    ``lat_deg, lon_deg, floor, building`` plus ``x_m, y_m`` on a local tangent plane (equirectangular,
    WGS-84 mean radius 6371008.8 m) with its origin at the first POSI record, x east, y north.

References
----------
IPIN competition Track 3 logfile format (the "LogFiles" description distributed with the
competition data, e.g. IPIN 2016-2020 Track 3 technical annex).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import check_increasing, fail, to_float
from ilocalg.io.schema import (
    ACC_COLS,
    BSSID,
    BUILDING,
    FLOOR,
    FREQ_MHZ,
    GYR_COLS,
    MAG_COLS,
    RSSI_DBM,
    SCAN_ID,
    T_S,
    X_M,
    Y_M,
    check_imu,
    check_wifi_scans,
)

__all__ = ["IpinLog", "load_ipin_logfile", "parse_ipin_logfile", "EARTH_RADIUS_M"]

#: Mean Earth radius (WGS-84 / IUGG), metres, for the local tangent-plane positions.
EARTH_RADIUS_M = 6371008.8

_IMU = {"ACCE": ("acc", ACC_COLS), "GYRO": ("gyr", GYR_COLS), "MAGN": ("mag", MAG_COLS)}
_N_FIELDS = {"ACCE": 6, "GYRO": 6, "MAGN": 6, "WIFI": 6, "POSI": 6}
_IMU_FIELDS = ("AppTimestamp", "SensorTimestamp", "X", "Y", "Z", "Accuracy")
_WIFI_FIELDS = ("AppTimestamp", "SensorTimeStamp", "Name_SSID", "MAC_BSSID", "Frequency", "RSS")
_POSI_FIELDS = ("Timestamp", "Counter", "Latitude", "Longitude", "floor_ID", "Building_ID")


@dataclass(frozen=True)
class IpinLog:
    """One IPIN smartphone logfile.

    Attributes
    ----------
    acc, gyr, mag : DataFrame
        IMU logs indexed by ``t_s`` with ``acc_*_mps2`` / ``gyr_*_radps`` / ``mag_*_ut`` columns
        (empty frames when the file has none).
    sensor_t_s : dict[str, ndarray]
        ``"acc" | "gyr" | "mag"`` -> SensorTimestamp (s) row-aligned with the IMU logs.
    wifi : DataFrame
        ``t_s, scan_id, bssid, rssi_dbm, freq_mhz, ssid, sensor_t_s``.
    positions : DataFrame
        ``t_s, counter, lat_deg, lon_deg, floor, building, x_m, y_m`` (ground-truth POSI records).
    kept, skipped : dict
        Record type -> number of lines kept / skipped.
    source : str
    """

    acc: pd.DataFrame
    gyr: pd.DataFrame
    mag: pd.DataFrame
    sensor_t_s: dict = field(compare=False)
    wifi: pd.DataFrame
    positions: pd.DataFrame
    kept: dict = field(compare=False)
    skipped: dict = field(compare=False)
    source: str | None = None


def _floats(rows, linenos, cols, names, source, rtype) -> np.ndarray:
    """Columns ``cols`` of ``rows`` as float64, naming line and column of the first bad value."""
    sub = [[r[c] for c in cols] for r in rows]
    return to_float(sub, linenos, source, lambda j: f"{rtype} field {cols[j] + 2} ({names[cols[j]]})", len(cols),
                    finite=True)


def _increasing(t, linenos, source, rtype, strict=True, hint=""):
    need = "strictly increasing" if strict else "non-decreasing"
    check_increasing(t, linenos, source, lambda i, kind: f"{kind} {rtype} timestamp {float(t[i])!r} after "
                                                         f"{float(t[i - 1])!r}; timestamps must be {need}{hint}",
                     strict=strict)


def _empty_imu(cols):
    return pd.DataFrame({c: np.array([], dtype=np.float64) for c in cols},
                        index=pd.Index([], dtype=np.float64, name=T_S))


def parse_ipin_logfile(text: str, source: str = "<string>", time: str = "app") -> IpinLog:
    """Parse the text of an IPIN logfile (see :func:`load_ipin_logfile`)."""
    if time not in ("app", "sensor"):
        raise ValueError(f"time must be 'app' or 'sensor', got {time!r}")
    recs: dict[str, tuple[list[int], list[list[str]]]] = {}
    counts: Counter = Counter()
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("%"):
            continue
        parts = line.split(";")
        rtype = parts[0].strip()
        counts[rtype] += 1
        n = _N_FIELDS.get(rtype)
        if n is None:
            continue
        vals = [p.strip() for p in parts[1:]]
        if len(vals) != n:
            fail(source, lineno, f"{rtype} expects {n} fields after the type, got {len(vals)} "
                                  f"(truncated or malformed line: {line[:60]!r})")
        lst = recs.setdefault(rtype, ([], []))
        lst[0].append(lineno)
        lst[1].append(vals)
    if not counts:
        raise ValueError(f"{source}: no records (empty file or comments only)")

    imu = {}
    sensor_t = {}
    for rtype, (name, cols) in _IMU.items():
        linenos, rows = recs.get(rtype, ([], []))
        if not rows:
            imu[name] = _empty_imu(cols)
            sensor_t[name] = np.array([], dtype=np.float64)
            continue
        v = _floats(rows, linenos, (0, 1, 2, 3, 4), _IMU_FIELDS, source, rtype)
        t_app, t_sen = v[:, 0], v[:, 1]
        t_idx = t_app if time == "app" else t_sen
        other = "sensor" if time == "app" else "app"
        _increasing(t_idx, linenos, source, rtype,
                    hint=f" ({'App' if time == 'app' else 'Sensor'}Timestamp; try time={other!r})")
        df = pd.DataFrame(v[:, 2:5], columns=list(cols), index=pd.Index(t_idx, name=T_S))
        imu[name] = check_imu(df, source)
        sensor_t[name] = t_sen

    linenos, rows = recs.get("WIFI", ([], []))
    if rows:
        v = _floats(rows, linenos, (0, 1, 4, 5), _WIFI_FIELDS, source, "WIFI")
        t = v[:, 0]
        _increasing(t, linenos, source, "WIFI", strict=False)
        for ln, r in zip(linenos, rows, strict=True):
            if not r[3]:
                fail(source, ln, "WIFI field 5 (MAC_BSSID) is empty")
        wifi = pd.DataFrame({
            T_S: t,
            SCAN_ID: np.concatenate([[0], np.cumsum(np.diff(t) > 0)]).astype(np.int64),
            BSSID: pd.array([r[3].lower() for r in rows], dtype="string"),
            RSSI_DBM: v[:, 3],
            FREQ_MHZ: v[:, 2],
            "ssid": pd.array([r[2] for r in rows], dtype="string"),
            "sensor_t_s": v[:, 1],
        })
        dup = wifi.duplicated(subset=[SCAN_ID, BSSID]).to_numpy()
        if dup.any():
            i = int(np.flatnonzero(dup)[0])
            fail(source, linenos[i], f"WIFI bssid {wifi[BSSID].iloc[i]!r} appears twice in the scan at "
                                      f"AppTimestamp {float(t[i])!r}")
        check_wifi_scans(wifi, source)
    else:
        wifi = pd.DataFrame({T_S: np.array([], dtype=np.float64), SCAN_ID: np.array([], dtype=np.int64),
                             BSSID: pd.array([], dtype="string"), RSSI_DBM: np.array([], dtype=np.float64),
                             FREQ_MHZ: np.array([], dtype=np.float64), "ssid": pd.array([], dtype="string"),
                             "sensor_t_s": np.array([], dtype=np.float64)})

    linenos, rows = recs.get("POSI", ([], []))
    v = _floats(rows, linenos, (0, 1, 2, 3, 4, 5), _POSI_FIELDS, source, "POSI") if rows else np.zeros((0, 6))
    _increasing(v[:, 0], linenos, source, "POSI")
    for j, name in ((4, "floor_ID"), (5, "Building_ID")):
        nonint = np.flatnonzero(v[:, j] != np.round(v[:, j]))
        if nonint.size:
            fail(source, linenos[nonint[0]], f"POSI field {j + 2} ({name}) must be an integer, got {v[nonint[0], j]}")
    lat, lon = v[:, 2], v[:, 3]
    bad = np.flatnonzero((np.abs(lat) > 90) | (np.abs(lon) > 180))
    if bad.size:
        fail(source, linenos[bad[0]], f"POSI latitude/longitude out of range: {lat[bad[0]]}, {lon[bad[0]]}")
    if lat.size:
        lat0, lon0 = np.deg2rad(lat[0]), np.deg2rad(lon[0])
        x = EARTH_RADIUS_M * (np.deg2rad(lon) - lon0) * np.cos(lat0)
        y = EARTH_RADIUS_M * (np.deg2rad(lat) - lat0)
    else:
        x = y = np.array([], dtype=np.float64)
    positions = pd.DataFrame({T_S: v[:, 0], "counter": v[:, 1].astype(np.int64), "lat_deg": lat, "lon_deg": lon,
                              FLOOR: v[:, 4].astype(np.int64), BUILDING: v[:, 5].astype(np.int64), X_M: x, Y_M: y})

    kept = {k: n for k, n in counts.items() if k in _N_FIELDS}
    skipped = {k: n for k, n in counts.items() if k not in _N_FIELDS}
    return IpinLog(acc=imu["acc"], gyr=imu["gyr"], mag=imu["mag"], sensor_t_s=sensor_t, wifi=wifi,
                   positions=positions, kept=kept, skipped=skipped, source=source)


def load_ipin_logfile(path, time: str = "app") -> IpinLog:
    """Load an IPIN competition smartphone logfile.

    Parameters
    ----------
    path : str or Path
    time : {"app", "sensor"}
        Which timestamp indexes the IMU logs (AppTimestamp by default, see module docstring).

    Returns
    -------
    IpinLog

    Raises
    ------
    ValueError
        Naming the file and 1-based line: wrong field count (truncated line), non-numeric or
        non-finite value (with its field number and name), unsorted or duplicate timestamps,
        duplicate BSSID in a scan, non-integer floor/building, or a file without records.

    References
    ----------
    IPIN competition Track 3 logfile format (see module docstring).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except UnicodeDecodeError:
        text = path.read_text(encoding="latin-1")
    return parse_ipin_logfile(text, str(path), time=time)
