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

from ilocalg.io._text import (
    check_increasing,
    check_record_types,
    fail,
    parse_record_log,
    read_bytes,
    read_records,
    split_by_type,
    to_float,
)
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
    check_range,
    check_wifi_scans,
)

__all__ = ["IpinLog", "load_ipin_logfile", "parse_ipin_logfile", "EARTH_RADIUS_M", "TRUNCATED_KEY"]

#: Mean Earth radius (WGS-84 / IUGG), metres, for the local tangent-plane positions.
EARTH_RADIUS_M = 6371008.8

_IMU = {"ACCE": ("acc", ACC_COLS), "GYRO": ("gyr", GYR_COLS), "MAGN": ("mag", MAG_COLS)}
_N_FIELDS = {"ACCE": 6, "GYRO": 6, "MAGN": 6, "WIFI": 6, "POSI": 6}
_RANGE = {"ACCE": "acc_mps2", "GYRO": "gyr_radps", "MAGN": "mag_ut"}
#: Key of :attr:`IpinLog.skipped` that counts a last line dropped by ``truncated_last_line="drop"``.
TRUNCATED_KEY = "truncated last line"
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
        Record type -> number of lines kept / skipped; ``skipped["truncated last line"]`` counts a
        cut last line dropped by ``truncated_last_line="drop"``.
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


def _is_cut(line: str) -> str | None:
    """What a last line without a line end lacks, or None if it is a whole record."""
    parts = line.split(";")
    rtype = parts[0].strip()
    n = _N_FIELDS.get(rtype)
    if n is None:
        if len(parts) == 1 and any(k.startswith(rtype) for k in _N_FIELDS):
            return f"record type {rtype!r} is incomplete"
        return None
    if len(parts) - 1 != n:
        return f"{len(parts) - 1} of the {n} fields of {rtype}"
    return None


@dataclass(frozen=True)
class _Block:
    """One record type's records: file lines, numeric fields (float64) and text fields."""

    lines: np.ndarray
    num: np.ndarray
    ssid: list | None = None
    bssid: list | None = None


#: Numeric fields (0-based, after the type) converted per record type.
_NUMERIC = {"ACCE": (0, 1, 2, 3, 4), "GYRO": (0, 1, 2, 3, 4), "MAGN": (0, 1, 2, 3, 4), "WIFI": (0, 1, 4, 5),
            "POSI": (0, 1, 2, 3, 4, 5)}
_FIELDS = {"ACCE": _IMU_FIELDS, "GYRO": _IMU_FIELDS, "MAGN": _IMU_FIELDS, "WIFI": _WIFI_FIELDS, "POSI": _POSI_FIELDS}
def _blocks_fast(data: bytes, is_ascii: bool | None = None) -> tuple[dict, dict] | None:
    """Records grouped by type without a Python loop per line, or None (then :func:`_blocks_slow`)."""
    tl = split_by_type(data, b";", 0, _N_FIELDS, comment=b"%", is_ascii=is_ascii)  # n fields after type = n seps
    if tl is None:
        return None
    out = {}
    imu = [t for t in _IMU if t in tl.lines]  # one layout: read together
    groups = ([imu] if imu else []) + [[t] for t in ("WIFI", "POSI") if t in tl.lines]
    for types in groups:
        num = [j + 1 for j in _NUMERIC[types[0]]]  # fields after the type
        got = read_records(tl, types, ";", 6, num, strings=(3, 4) if types == ["WIFI"] else ())
        if got is None:
            return None
        for t, r in got.items():
            out[t] = _Block(tl.lines[t], r.num, *r.strings) if t == "WIFI" else _Block(tl.lines[t], r.num)
    return out, tl.counts


def _blocks_slow(lines: list[str], source) -> tuple[dict, dict]:
    """Records grouped by type, line by line; names the first malformed line."""
    recs: dict[str, tuple[list[int], list[list[str]]]] = {}
    counts: Counter = Counter()
    first_line: dict[str, int] = {}
    for lineno, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("%"):
            continue
        parts = line.split(";")
        rtype = parts[0].strip()
        if rtype not in counts:
            first_line[rtype] = lineno
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
    check_record_types(counts, first_line, _N_FIELDS, source, ";", "IPIN logfile")
    out = {}
    for rtype, (linenos, rows) in recs.items():
        v = _floats(rows, linenos, _NUMERIC[rtype], _FIELDS[rtype], source, rtype)
        if rtype == "WIFI":
            out[rtype] = _Block(np.asarray(linenos), v, [r[2] for r in rows], [r[3] for r in rows])
        else:
            out[rtype] = _Block(np.asarray(linenos), v)
    return out, dict(counts)


def parse_ipin_logfile(text: str | bytes, source: str = "<string>", time: str = "app",
                       truncated_last_line: str = "error") -> IpinLog:
    """Parse the text of an IPIN logfile (see :func:`load_ipin_logfile`)."""
    if time not in ("app", "sensor"):
        raise ValueError(f"time must be 'app' or 'sensor', got {time!r}")
    fast, n_cut = parse_record_log(text, source, truncated_last_line, _blocks_fast, _blocks_slow, _is_cut)
    recs, counts = fast

    imu = {}
    sensor_t = {}
    for rtype, (name, cols) in _IMU.items():
        if rtype not in recs:
            imu[name] = _empty_imu(cols)
            sensor_t[name] = np.array([], dtype=np.float64)
            continue
        linenos, v = recs[rtype].lines, recs[rtype].num
        t_app, t_sen = v[:, 0], v[:, 1]
        check_range(t_app, "elapsed_s", source, linenos, "2 (AppTimestamp)")
        check_range(t_sen - t_sen[0], "elapsed_s", source, linenos, "3 (SensorTimestamp, since the first record)")
        check_range(v[:, 2:5], _RANGE[rtype], source, linenos, ("4 (X)", "5 (Y)", "6 (Z)"))
        t_idx = t_app if time == "app" else t_sen
        other = "sensor" if time == "app" else "app"
        _increasing(t_idx, linenos, source, rtype,
                    hint=f" ({'App' if time == 'app' else 'Sensor'}Timestamp; try time={other!r})")
        df = pd.DataFrame(v[:, 2:5], columns=list(cols), index=pd.Index(t_idx, name=T_S), copy=False)
        imu[name] = check_imu(df, source)
        sensor_t[name] = t_sen

    if "WIFI" in recs:
        linenos, v, ssid, bssid = recs["WIFI"].lines, recs["WIFI"].num, recs["WIFI"].ssid, recs["WIFI"].bssid
        t = v[:, 0]
        check_range(t, "elapsed_s", source, linenos, "2 (AppTimestamp)")
        check_range(v[:, 2], FREQ_MHZ, source, linenos, "6 (Frequency)")
        check_range(v[:, 3], RSSI_DBM, source, linenos, "7 (RSS)")
        _increasing(t, linenos, source, "WIFI", strict=False)
        if not all(bssid):
            fail(source, linenos[next(i for i, b in enumerate(bssid) if not b)], "WIFI field 5 (MAC_BSSID) is empty")
        wifi = pd.DataFrame({
            T_S: t,
            SCAN_ID: np.concatenate([[0], np.cumsum(np.diff(t) > 0)]).astype(np.int64),
            BSSID: pd.array([b.lower() for b in bssid], dtype="string"),
            RSSI_DBM: v[:, 3],
            FREQ_MHZ: v[:, 2],
            "ssid": pd.array(ssid, dtype="string"),
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

    linenos, v = (recs["POSI"].lines, recs["POSI"].num) if "POSI" in recs else (np.zeros(0, np.int64),
                                                                               np.zeros((0, 6)))
    _increasing(v[:, 0], linenos, source, "POSI")
    check_range(v[:, 0], "elapsed_s", source, linenos, "2 (Timestamp)")
    check_range(v[:, 1], "count", source, linenos, "3 (Counter)")
    check_range(v[:, 2], "lat_deg", source, linenos, "4 (Latitude)")
    check_range(v[:, 3], "lon_deg", source, linenos, "5 (Longitude)")
    check_range(v[:, 4], FLOOR, source, linenos, "6 (floor_ID)")
    check_range(v[:, 5], BUILDING, source, linenos, "7 (Building_ID)")
    lat, lon = v[:, 2], v[:, 3]
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
    if n_cut:
        skipped[TRUNCATED_KEY] = n_cut
    return IpinLog(acc=imu["acc"], gyr=imu["gyr"], mag=imu["mag"], sensor_t_s=sensor_t, wifi=wifi,
                   positions=positions, kept=kept, skipped=skipped, source=source)


def load_ipin_logfile(path, time: str = "app", truncated_last_line: str = "error") -> IpinLog:
    """Load an IPIN competition smartphone logfile (plain, ``.gz`` or ``.xz``).

    Parameters
    ----------
    path : str or Path
        UTF-8 text (a byte-order mark is stripped, CRLF line ends and trailing blank lines are
        accepted); gzip or xz compressed files are read transparently.
    time : {"app", "sensor"}
        Which timestamp indexes the IMU logs (AppTimestamp by default, see module docstring).
    truncated_last_line : {"error", "drop"}
        A file cut while being written ends without a line end inside its last record: raise
        naming that line, or drop the line and count it in ``skipped["truncated last line"]``.

    Returns
    -------
    IpinLog

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    ValueError
        Naming the file and 1-based line (and column, for values): wrong field count (truncated
        line), non-numeric or non-finite value, a value outside its valid range
        (:data:`ilocalg.io.schema.FIELD_RANGES`), unsorted or duplicate timestamps, duplicate
        BSSID in a scan, lower-case or ``,``/tab-separated record types, a file in which no
        known record type occurs, a non-UTF-8 byte, or corrupt compressed data.

    References
    ----------
    IPIN competition Track 3 logfile format (see module docstring).
    """
    path = Path(path)
    return parse_ipin_logfile(read_bytes(path), str(path), time=time, truncated_last_line=truncated_last_line)
