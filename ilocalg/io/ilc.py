"""Indoor Location Competition 2.0 (ILC 2020) traces, floor info and floor map.

An ILC trace is one walk of a site surveyor holding an Android phone flat in front of the body
(Microsoft Research / XYZ10 sample data, github.com/location-competition/indoor-location-competition-20).
Each non-comment line is tab-separated: column 1 Unix time in milliseconds (``SensorEvent.timestamp``
for sensors, system time for Wi-Fi and Bluetooth scans), column 2 the record type, then values:

=====================================  ==================================================  ==========
record type                            values                                              kept as
=====================================  ==================================================  ==========
``TYPE_WAYPOINT``                      x y (metres, floor-map frame)                       waypoints
``TYPE_ACCELEROMETER``                 x y z accuracy (m/s^2)                              imu acc_*
``TYPE_GYROSCOPE``                     x y z accuracy (rad/s)                              imu gyr_*
``TYPE_MAGNETIC_FIELD``                x y z accuracy (microtesla)                         imu mag_*
``TYPE_ROTATION_VECTOR``               x y z accuracy (unit quaternion vector part)        rotation_vector
``TYPE_WIFI``                          ssid bssid rssi(dBm) freq(MHz) last_seen(ms)        wifi
``*_UNCALIBRATED``                     6 values + accuracy                                 skipped, counted
``TYPE_BEACON``, ``TYPE_BLUE``, ...    (iBeacon / Bluetooth / others)                      skipped, counted
=====================================  ==================================================  ==========

The sensors' ``accuracy`` column is checked for presence but not kept. Besides the documented
types, the site2/F4 traces also hold ``TYPE_BLUE``, ``TYPE_BLU4``, ``TYPE_DIST1``, ``TYPE_DIST2``
and ``TYPE_SENSOR_MAGNETIC_FIELD_ACCURACY_CHANGED`` records: skipped and counted like any
unknown type (:attr:`IlcTrace.skipped`).

Lines starting with ``#`` carry the header: ``startTime``, site and floor ids and names, phone
brand/model/Android version, one line per sensor (type, name, vendor, resolution, range) and
``endTime`` at the end. Header key/value pairs are returned in :attr:`IlcTrace.header`.

Choices (documented here once)
------------------------------
Time
    ``t_s`` is Unix time in seconds (float64; millisecond resolution is exact to ~1e-7 s).
IMU time index
    One **common** index: accelerometer, gyroscope and magnetometer records must share their
    timestamps (they do in every trace of the site2/F4 sample: the recording app logs the three
    sensors together at ~50 Hz). A trace whose sensors are not aligned raises a ValueError naming
    the first mismatching line; nothing is interpolated.
Wi-Fi scans
    A scan is the set of ``TYPE_WIFI`` records sharing a timestamp; ``scan_id`` numbers scans
    0, 1, ... in time order. Extra columns ``ssid`` and ``last_seen_s`` (the AP's own last-seen
    time, often older than the scan: Android reports cached results) are kept.
Duplicate BSSIDs within one scan
    Found in 6 of the 19 site2/F4 traces (75 records): the same BSSID listed twice in one scan, once
    with its SSID and once with an empty SSID and an older ``last_seen`` (a hidden-SSID/cached
    duplicate). By default (``duplicate_bssid="error"``) the loader raises a ValueError naming the
    line; ``duplicate_bssid="keep_latest"`` keeps the record with the most recent last-seen time
    (ties: the first listed) and reports how many were dropped in
    :attr:`IlcTrace.n_duplicate_bssid_dropped` and in ``skipped["TYPE_WIFI duplicate bssid"]``.
Sensor timestamps
    Must be strictly increasing per sensor type (true in all 19 traces inspected); duplicates or
    decreasing times raise a ValueError naming the line. Waypoint times likewise.

Fingerprints from walks
-----------------------
:func:`ilc_fingerprints` positions every scan by linear interpolation of its walk's waypoints
in time (:func:`interpolate_waypoints`, no extrapolation: scans outside the waypoint span raise
or are left out and counted) and optionally leaves out stale AP readings (``max_age_s``).

Floor map
---------
``geojson_map.json`` stores polygons in longitude/latitude. Following the competition's own
plotting convention (the floor image spans ``floor_info.json``'s ``width`` x ``height`` metres),
the bounding box of the floor outline (feature 0) is mapped linearly onto ``[0, width] x
[0, height]`` metres. Walkable area = inside the outline (the union of its rings) and outside every
shop/obstacle polygon (features 1...). Polygons are returned as ``(n, 2)`` arrays;
:meth:`IlcFloorMap.walkable` tests points (:func:`points_in_polygon`, even-odd rule per ring) and
:meth:`ilocalg.fusion.particle_filter.OccupancyGrid.from_floor_map` rasterises the same area.

References
----------
Indoor Location Competition 2.0 sample data and format description, README of
github.com/location-competition/indoor-location-competition-20 (commit 8ab177cd).
"""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import (
    ArchiveReader,
    check_increasing,
    check_record_types,
    decode_text,
    fail,
    parse_record_log,
    read_bytes,
    read_records,
    split_by_type,
    to_float,
)
from ilocalg.io.scans import RELISTED_WIFI_POLICIES, relisted_readings, scan_matrix
from ilocalg.io.schema import (
    ACC_COLS,
    BSSID,
    FIELD_RANGES,
    FREQ_MHZ,
    GYR_COLS,
    MAG_COLS,
    RSSI_DBM,
    SCAN_ID,
    T_S,
    X_M,
    Y_M,
    FingerprintSet,
    check_imu,
    check_range,
    check_waypoints,
    check_wifi_scans,
)

__all__ = [
    "IlcTrace",
    "IlcFloorMap",
    "IlcFloor",
    "ROTVEC_COLS",
    "parse_ilc_trace",
    "load_ilc_trace",
    "list_ilc_traces",
    "load_ilc_floor",
    "load_ilc_floor_map",
    "points_in_polygon",
    "interpolate_waypoints",
    "IlcFingerprints",
    "ilc_fingerprints",
    "TRUNCATED_KEY",
    "require_walk",
]

ROTVEC_COLS = ("rv_x", "rv_y", "rv_z")

_SENSORS = {
    "TYPE_ACCELEROMETER": ACC_COLS,
    "TYPE_GYROSCOPE": GYR_COLS,
    "TYPE_MAGNETIC_FIELD": MAG_COLS,
    "TYPE_ROTATION_VECTOR": ROTVEC_COLS,
}
#: number of value columns (after time and type) of every record type the loader checks
_N_VALUES = {
    "TYPE_WAYPOINT": 2,
    "TYPE_ACCELEROMETER": 4,
    "TYPE_GYROSCOPE": 4,
    "TYPE_MAGNETIC_FIELD": 4,
    "TYPE_ROTATION_VECTOR": 4,
    "TYPE_WIFI": 5,
}
_DUPLICATE_POLICIES = ("error", "keep_latest")
_RANGE = {"TYPE_ACCELEROMETER": "acc_mps2", "TYPE_GYROSCOPE": "gyr_radps", "TYPE_MAGNETIC_FIELD": "mag_ut",
          "TYPE_ROTATION_VECTOR": "rotvec"}
#: Key of :attr:`IlcTrace.skipped` that counts a last line dropped by ``truncated_last_line="drop"``.
TRUNCATED_KEY = "truncated last line"


@dataclass(frozen=True)
class IlcTrace:
    """One ILC 2.0 trace (a surveyor's walk).

    Attributes
    ----------
    imu : DataFrame
        Index ``t_s`` (Unix s, strictly increasing); columns ``acc_*_mps2``, ``gyr_*_radps``,
        ``mag_*_ut`` (Android sensor frame and units, calibrated values). Empty if the trace has no
        sensor records.
    rotation_vector : DataFrame
        Index ``t_s``; columns ``rv_x, rv_y, rv_z`` (Android ``TYPE_ROTATION_VECTOR``).
    wifi : DataFrame
        Long scan table: ``t_s, scan_id, bssid, rssi_dbm, freq_mhz, ssid, last_seen_s``.
    waypoints : DataFrame
        ``t_s, x_m, y_m`` in the floor-map frame (metres).
    header : dict
        Header key/values (``SiteID``, ``FloorName``, ``Model``, ``startTime`` ...); ``sensors`` is a
        tuple of dicts, one per ``# type:`` line.
    kept, skipped : dict
        Record type -> number of lines kept / skipped (unknown types are skipped and counted;
        ``skipped["truncated last line"]`` counts a cut last line dropped by
        ``truncated_last_line="drop"``).
    n_duplicate_bssid_dropped : int
        Wi-Fi records dropped by the ``keep_latest`` duplicate-BSSID policy (0 under ``error``).
    source : str
    """

    imu: pd.DataFrame
    rotation_vector: pd.DataFrame
    wifi: pd.DataFrame
    waypoints: pd.DataFrame
    header: dict = field(compare=False)
    kept: dict = field(compare=False)
    skipped: dict = field(compare=False)
    n_duplicate_bssid_dropped: int = 0
    source: str | None = None

    @property
    def name(self) -> str:
        """Trace id (file stem)."""
        return Path(self.source).stem if self.source else ""

    @property
    def n_scans(self) -> int:
        return int(self.wifi[SCAN_ID].nunique()) if len(self.wifi) else 0


def _parse_header(lines: list[str]) -> dict:
    header: dict = {}
    sensors = []
    for ln in lines:
        parts = [p for p in ln.lstrip("#").strip().split("\t") if p]
        kv = {}
        for p in parts:
            k, sep, v = p.partition(":")
            if sep:
                kv[k.strip()] = v.strip()
        if "type" in kv and "name" in kv:
            sensors.append(kv)
        else:
            header.update(kv)
    header["sensors"] = tuple(sensors)
    return header


def _check_increasing(t_ms: np.ndarray, linenos: list[int], source: str, rtype: str, strict: bool = True):
    def message(i, kind):
        if strict:
            return (f"{kind} {rtype} timestamp {int(t_ms[i])} after {int(t_ms[i - 1])}; "
                    "timestamps must be strictly increasing per record type")
        return f"{rtype} timestamp {int(t_ms[i])} before {int(t_ms[i - 1])}; Wi-Fi scans must be in time order"

    check_increasing(t_ms, linenos, source, message, strict=strict)


def _is_cut(line: str) -> str | None:
    """What a last line without a line end lacks, or None if it is a whole record."""
    if line.startswith("#"):
        return None
    parts = line.split("\t")
    if len(parts) < 2:
        return "only the time column"
    rtype = parts[1]
    n = _N_VALUES.get(rtype)
    if n is None:
        if any(k.startswith(rtype) for k in _N_VALUES):
            return f"record type {rtype!r} is incomplete"
        return None
    if len(parts) - 2 != n:
        return f"{len(parts) - 2} of the {n} values of {rtype}"
    return None


def _times_ms(t_ms, linenos, source) -> np.ndarray:
    """Column 1 as int64 after its range check (a huge integer is an error, not an overflow)."""
    check_range(np.asarray(t_ms, dtype=np.float64), "unix_time_ms", source, linenos, "1 (Unix time)")
    return np.asarray(t_ms, dtype=np.int64)


@dataclass(frozen=True)
class _Block:
    """One record type's records: file lines, times (ms), numeric values and, for Wi-Fi, texts."""

    lines: np.ndarray
    t_ms: list | np.ndarray
    num: np.ndarray
    ssid: list | None = None
    bssid: list | None = None
    block: np.ndarray | None = None  # records read in turns with other types: the array ``num`` is columns of
    col: int = 0                     # (from column ``col`` on), see :func:`ilocalg.io._text.read_records`


#: Values (0-based, after time and type) converted per record type, and their names.
_NUMERIC = {**{k: ((0, 1, 2), ("x", "y", "z")) for k in _SENSORS}, "TYPE_WAYPOINT": ((0, 1), ("x", "y")),
            "TYPE_WIFI": ((2, 3, 4), ("rssi", "frequency", "last seen timestamp"))}


def _blocks_fast(data: bytes, is_ascii: bool | None = None) -> tuple[dict, dict, list] | None:
    """Records grouped by type without a Python loop per line, or None (then :func:`_blocks_slow`)."""
    tl = split_by_type(data, b"\t", 1, {k: n + 1 for k, n in _N_VALUES.items()}, header=b"#", spaces_ok=True,
                       is_ascii=is_ascii)
    if tl is None:
        return None
    out = {}
    sensors = [t for t in _SENSORS if t in tl.lines]  # one layout: read together
    groups = ([sensors] if sensors else []) + [[t] for t in ("TYPE_WAYPOINT", "TYPE_WIFI") if t in tl.lines]
    for types in groups:
        sel, _ = _NUMERIC[types[0]]
        wifi = types == ["TYPE_WIFI"]
        got = read_records(tl, types, "\t", _N_VALUES[types[0]] + 1, [j + 2 for j in sel], ints=(0,),
                           strings=(2, 3) if wifi else ())
        if got is None:
            return None
        for t, r in got.items():
            out[t] = _Block(tl.lines[t], r.ints[0], r.num, *r.strings, block=r.block, col=r.col)
    return out, tl.counts, tl.header


def _blocks_slow(lines: list[str], source) -> tuple[dict, dict, list]:
    """Records grouped by type, line by line; names the first malformed line."""
    header_lines: list[str] = []
    by_type: dict[str, tuple[list[int], list[int], list[list[str]]]] = {}
    counts: Counter = Counter()
    first_line: dict[str, int] = {}
    for lineno, raw in enumerate(lines, start=1):
        line = raw.rstrip("\r")
        if not line.strip():
            continue
        if line.startswith("#"):
            header_lines.append(line)
            continue
        parts = line.split("\t")
        if len(parts) < 2:
            fail(source, lineno, f"expected at least 2 tab-separated columns (time ms, record type), "
                                 f"got {len(parts)}: {line[:60]!r}")
        try:
            t_ms = int(parts[0])
        except ValueError:
            fail(source, lineno, f"column 1 (Unix time, ms) must be an integer, got {parts[0]!r}")
        rtype = parts[1]
        if rtype not in counts:
            first_line[rtype] = lineno
        counts[rtype] += 1
        nval = _N_VALUES.get(rtype)
        if nval is None:
            continue
        vals = parts[2:]
        if len(vals) != nval:
            fail(source, lineno, f"{rtype} expects {nval} values after time and type "
                                 f"({2 + nval} columns), got {len(vals)} ({len(parts)} columns)")
        lst = by_type.setdefault(rtype, ([], [], []))
        lst[0].append(lineno)
        lst[1].append(t_ms)
        lst[2].append(vals)
    if not counts:
        raise ValueError(f"{source}: no data records (empty file or header only)")
    check_record_types(counts, first_line, _N_VALUES, source, "\t", "ILC trace")
    out = {}
    for rtype, (linenos, t_ms, rows) in by_type.items():
        sel, names = _NUMERIC[rtype]
        v = to_float([[r[j] for j in sel] for r in rows], linenos, source,
                     lambda j, rtype=rtype, sel=sel, names=names: f"{rtype} column {sel[j] + 3} ({names[j]})",
                     len(sel))
        if rtype == "TYPE_WIFI":
            out[rtype] = _Block(np.asarray(linenos), t_ms, v, [r[0] for r in rows], [r[1] for r in rows])
        else:
            out[rtype] = _Block(np.asarray(linenos), t_ms, v)
    return out, dict(counts), header_lines


def parse_ilc_trace(text: str | bytes, source: str = "<string>", duplicate_bssid: str = "error",
                    truncated_last_line: str = "error", relisted_wifi: str = "refuse") -> IlcTrace:
    """Parse the text of one ILC trace file (see :func:`load_ilc_trace`)."""
    if duplicate_bssid not in _DUPLICATE_POLICIES:
        raise ValueError(f"duplicate_bssid must be one of {_DUPLICATE_POLICIES}, got {duplicate_bssid!r}")
    if relisted_wifi not in RELISTED_WIFI_POLICIES:
        raise ValueError(f"relisted_wifi must be one of {RELISTED_WIFI_POLICIES}, got {relisted_wifi!r}")
    fast, n_cut = parse_record_log(text, source, truncated_last_line, _blocks_fast, _blocks_slow, _is_cut)
    by_type, counts, header_lines = fast
    empty = _Block(np.zeros(0, dtype=np.int64), [], np.zeros((0, 3)), [], [])

    def sensor(rtype, checked_t=None):
        blk = by_type.get(rtype, empty)
        linenos, v = blk.lines, blk.num
        if (checked_t is not None and isinstance(blk.t_ms, np.ndarray) and blk.t_ms.dtype == np.int64
                and np.array_equal(blk.t_ms, checked_t)):
            t = blk.t_ms  # the times another sensor's records passed: the same checks would pass again
            check_range(v, _RANGE[rtype], source, linenos, ("3 (x)", "4 (y)", "5 (z)"))
            return linenos, t, v.reshape(-1, 3)
        t = _times_ms(blk.t_ms, linenos, source)
        _check_increasing(t, linenos, source, rtype)
        check_range(v, _RANGE[rtype], source, linenos, ("3 (x)", "4 (y)", "5 (z)"))
        span = FIELD_RANGES["elapsed_s"]  # times increase (checked above): the first is 0, the last the largest
        if t.size and not span.lo <= 0.0 <= (t[-1] - t[0]) * 1e-3 <= span.hi:
            check_range((t - t[0]) * 1e-3, "elapsed_s", source, linenos, "1 (Unix time, since the first record)")
        return linenos, t, v.reshape(-1, 3)

    # IMU on one common time index
    imu_parts = {}
    ref = None
    for rtype in ("TYPE_ACCELEROMETER", "TYPE_GYROSCOPE", "TYPE_MAGNETIC_FIELD"):
        if rtype not in by_type:
            continue
        linenos, t, v = sensor(rtype, None if ref is None else ref[1])
        if ref is None:
            ref = (rtype, t)
        elif t.size != ref[1].size or not np.array_equal(t, ref[1]):
            n = min(t.size, ref[1].size)
            mism = np.flatnonzero(t[:n] != ref[1][:n])
            i = int(mism[0]) if mism.size else n
            where = f"line {linenos[i]}" if i < len(linenos) else f"after line {linenos[-1]}"
            raise ValueError(f"{source}: {where}: {rtype} timestamps differ from {ref[0]} ones "
                             f"({t.size} vs {ref[1].size} records, first difference at record {i}); "
                             "the loader needs a common IMU time index and does not interpolate")
        imu_parts[rtype] = v
    if ref is None:
        imu = pd.DataFrame({}, index=pd.Index([], dtype=np.float64, name=T_S))
    else:
        cols = [c for rtype in imu_parts for c in _SENSORS[rtype]]
        index = pd.Index(ref[1] * 1e-3, name=T_S)
        blks = [by_type[rtype] for rtype in imu_parts]
        c0 = blks[0].col
        if blks[0].block is not None and all(b.block is blks[0].block and b.col == c0 + 3 * k
                                             for k, b in enumerate(blks)):
            # the sensors were read in turns into adjacent columns of one array: a view, not a copy
            imu = pd.DataFrame(blks[0].block[:, c0:c0 + 3 * len(blks)], columns=cols, index=index, copy=False)
        else:
            data = {}
            for rtype, v in imu_parts.items():
                for j, c in enumerate(_SENSORS[rtype]):
                    data[c] = v[:, j]
            imu = pd.DataFrame(data, index=index)
        check_imu(imu, source)

    if "TYPE_ROTATION_VECTOR" in by_type:
        _, t, v = sensor("TYPE_ROTATION_VECTOR", None if ref is None else ref[1])
        rotvec = pd.DataFrame(v, columns=list(ROTVEC_COLS), index=pd.Index(t * 1e-3, name=T_S), copy=False)
    else:
        rotvec = pd.DataFrame({c: np.array([], dtype=np.float64) for c in ROTVEC_COLS},
                              index=pd.Index([], dtype=np.float64, name=T_S))

    # waypoints
    blk = by_type.get("TYPE_WAYPOINT", empty)
    linenos = blk.lines
    t = _times_ms(blk.t_ms, linenos, source)
    _check_increasing(t, linenos, source, "TYPE_WAYPOINT")
    v = blk.num.reshape(-1, blk.num.shape[1] if blk.num.size else 2)[:, :2]
    check_range(v, "xy_m", source, linenos, ("3 (x)", "4 (y)"))
    waypoints = pd.DataFrame({T_S: t * 1e-3, X_M: v[:, 0], Y_M: v[:, 1]})
    if len(waypoints):
        check_waypoints(waypoints, source)

    # Wi-Fi
    skipped = {k: n for k, n in counts.items() if k not in _N_VALUES}
    blk = by_type.get("TYPE_WIFI", empty)
    linenos = blk.lines
    t = _times_ms(blk.t_ms, linenos, source)
    _check_increasing(t, linenos, source, "TYPE_WIFI", strict=False)
    num = blk.num.reshape(-1, 3)
    check_range(num[:, 0], RSSI_DBM, source, linenos, "5 (rssi)")
    check_range(num[:, 1], FREQ_MHZ, source, linenos, "6 (frequency)")
    check_range(num[:, 2], "unix_time_ms", source, linenos, "7 (last seen timestamp)")
    bssid = blk.bssid
    if not all(bssid):
        fail(source, linenos[next(i for i, b in enumerate(bssid) if not b)], "TYPE_WIFI column 4 (bssid) is empty")
    scan_id = np.concatenate([[0], np.cumsum(np.diff(t) > 0)]).astype(np.int64) if t.size else t
    wifi = pd.DataFrame({
        T_S: t * 1e-3,
        SCAN_ID: scan_id,
        BSSID: pd.array(bssid, dtype="string"),
        RSSI_DBM: num[:, 0],
        FREQ_MHZ: num[:, 1],
        "ssid": pd.array(blk.ssid, dtype="string"),
        "last_seen_s": num[:, 2] * 1e-3,
    })
    keep = np.ones(len(wifi), dtype=bool)
    if len(wifi):
        dup = wifi.duplicated(subset=[SCAN_ID, BSSID], keep=False).to_numpy()
        if dup.any():
            if duplicate_bssid == "error":
                i = int(np.flatnonzero(wifi.duplicated(subset=[SCAN_ID, BSSID]).to_numpy())[0])
                fail(source, linenos[i], f"TYPE_WIFI bssid {bssid[i]!r} appears twice in the scan at "
                                          f"{int(t[i])} ms; pass duplicate_bssid='keep_latest' to keep the "
                                          "record with the most recent last-seen time (counted)")
            # keep_latest: stable sort by last_seen descending within each (scan, bssid) group
            order = np.lexsort((np.arange(len(wifi)), -num[:, 2], wifi[BSSID].to_numpy(dtype=object),
                                scan_id))
            first = ~wifi.iloc[order].duplicated(subset=[SCAN_ID, BSSID]).to_numpy()
            keep = np.zeros(len(wifi), dtype=bool)
            keep[order[first]] = True
    n_dropped = int((~keep).sum())
    if n_dropped:
        wifi = wifi[keep].reset_index(drop=True)
    n_relisted = 0
    if len(wifi) and relisted_wifi != "keep":          # re-listed cached readings (ilocalg.io.scans)
        rel = relisted_readings(wifi)
        if rel.any() and relisted_wifi == "refuse":
            i = int(np.flatnonzero(rel)[0])
            fail(source, np.asarray(linenos)[keep][i], f"TYPE_WIFI bssid {wifi[BSSID].iloc[i]!r} re-lists its reading "
                 f"of the previous scan (same RSSI, last seen within 1 ms; {int(rel.sum())} such lines); pass "
                 "relisted_wifi='merge' to merge them into their first listing (counted) or 'keep' to take them as "
                 "new readings")
        n_relisted = int(rel.sum())  # merge_relisted_wifi(wifi), with the re-listings found above
        if n_relisted:
            wifi = wifi[~rel].reset_index(drop=True)
    if len(wifi):
        check_wifi_scans(wifi, source)

    kept = {k: n for k, n in counts.items() if k in _N_VALUES}
    if n_cut:
        skipped[TRUNCATED_KEY] = n_cut
    if n_dropped:
        kept["TYPE_WIFI"] -= n_dropped
        skipped["TYPE_WIFI duplicate bssid"] = n_dropped
    if n_relisted:
        kept["TYPE_WIFI"] -= n_relisted
        skipped["TYPE_WIFI relisted reading"] = n_relisted
    return IlcTrace(imu=imu, rotation_vector=rotvec, wifi=wifi, waypoints=waypoints,
                    header=_parse_header(header_lines), kept=kept, skipped=skipped,
                    n_duplicate_bssid_dropped=n_dropped, source=source)


def load_ilc_trace(path, duplicate_bssid: str = "error", truncated_last_line: str = "error",
                   relisted_wifi: str = "refuse") -> IlcTrace:
    """Load one ILC 2.0 trace file.

    Parameters
    ----------
    path : str or Path
        A ``*.txt`` trace (UTF-8, tab-separated; a byte-order mark is stripped, CRLF line ends
        and trailing blank lines are accepted), plain or ``.gz`` / ``.xz`` compressed.
    duplicate_bssid : {"error", "keep_latest"}
        What to do when a scan lists a BSSID twice (see the module docstring). Six of the 19
        site2/F4 traces need ``"keep_latest"``.
    truncated_last_line : {"error", "drop"}
        A file cut while being written ends without a line end inside its last record: raise
        naming that line, or drop the line and count it in ``skipped["truncated last line"]``.
    relisted_wifi : {"refuse", "merge", "keep"}
        A reading that re-lists the same access point's reading of an earlier scan (same RSSI, last seen
        within 1 ms: :func:`ilocalg.io.scans.relisted_readings`; about half the Wi-Fi lines of the ILC
        2020 walks): raise naming the line, merge it into its first listing (counted in
        ``skipped["TYPE_WIFI relisted reading"]``) or keep it as a new reading.

    Returns
    -------
    IlcTrace

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    ValueError
        Naming the file and 1-based line (and column, for values): wrong number of columns,
        non-numeric value, a value outside its valid range (:data:`ilocalg.io.schema.FIELD_RANGES`),
        unsorted or duplicate sensor/waypoint timestamps, misaligned IMU sensors, duplicate BSSID
        (policy ``"error"``), lower-case record types, a file without any known record type, a
        non-UTF-8 byte or corrupt compressed data.

    References
    ----------
    Indoor Location Competition 2.0, trace file format (README of the competition repository).
    """
    path = Path(path)
    return parse_ilc_trace(read_bytes(path), str(path), duplicate_bssid=duplicate_bssid,
                           truncated_last_line=truncated_last_line, relisted_wifi=relisted_wifi)


def require_walk(trace: IlcTrace, min_imu: int = 50, min_waypoints: int = 2, min_scans: int = 1) -> IlcTrace:
    """Refuse, with a sentence, a trace too small to be scored or used as a fingerprint walk.

    A walk needs IMU records (steps and headings), at least two waypoints (positions between them
    are interpolated in time) and a Wi-Fi scan. Returns ``trace`` unchanged.

    Raises
    ------
    ValueError
        ``FILE: the walk has 1 waypoint (TYPE_WAYPOINT records); at least 2 are needed ...``.
    """
    src = trace.source or "<trace>"
    n_wp, n_imu, n_scans = len(trace.waypoints), len(trace.imu), trace.n_scans
    if n_imu < min_imu:
        raise ValueError(f"{src}: the walk has {n_imu} IMU samples (TYPE_ACCELEROMETER/GYROSCOPE/MAGNETIC_FIELD "
                         f"records); at least {min_imu} (1 s at 50 Hz) are needed to detect steps and headings")
    if n_wp < min_waypoints:
        raise ValueError(f"{src}: the walk has {n_wp} waypoint{'s' if n_wp != 1 else ''} (TYPE_WAYPOINT records); "
                         f"at least {min_waypoints} are needed to place it in time (positions are interpolated "
                         "between waypoints)")
    if n_scans < min_scans:
        raise ValueError(f"{src}: the walk has no Wi-Fi scan (TYPE_WIFI records); fingerprints and Wi-Fi fixes "
                         "need at least one")
    return trace


# ----------------------------------------------------------------------------------------------
# floor: folder or archive
# ----------------------------------------------------------------------------------------------

def _resolve_root(root) -> Path:
    """A folder with path_data_files/, a folder holding ``*.tar.xz``, or the archive itself."""
    p = Path(root)
    if p.is_file():
        return p
    if not p.is_dir():
        raise ValueError(f"{p}: no such ILC folder or archive")
    if (p / "path_data_files").is_dir():
        return p
    subs = [d for d in p.iterdir() if d.is_dir() and (d / "path_data_files").is_dir()]
    if len(subs) == 1:
        return subs[0]
    archives = sorted(p.glob("*.tar.xz")) + sorted(p.glob("*.tar.gz")) + sorted(p.glob("*.tar"))
    if len(archives) == 1:
        return archives[0]
    raise ValueError(f"{p}: expected path_data_files/ or exactly one .tar.xz archive, found "
                     f"{len(archives)} archives")


def _read_members(archive: Path, want) -> dict[str, bytes]:
    """Read the archive members whose name passes ``want(name)`` in one sequential pass."""
    out = {}
    with ArchiveReader(archive) as ar:
        for m in ar.tar:
            if m.isfile() and want(m.name):
                ar.member = m.name
                out[m.name] = ar.tar.extractfile(m).read()
                ar.member = None
    return out


def _in_floor(name: str, floor_name: str | None) -> bool:
    """Whether an archive member belongs to the floor folder ``floor_name`` (None: any)."""
    return floor_name is None or f"/{floor_name}/" in "/" + name


def list_ilc_traces(root, floor_name: str | None = None) -> list[str]:
    """Trace ids (file stems, sorted) under a floor folder or inside its archive (only the floor folder
    ``floor_name`` of a several-floor archive)."""
    r = _resolve_root(root)
    if r.is_dir():
        return sorted(f.stem for f in (r / "path_data_files").glob("*.txt"))
    with ArchiveReader(r) as ar:
        names = [m.name for m in ar.tar if m.isfile() and "/path_data_files/" in "/" + m.name
                 and m.name.endswith(".txt") and _in_floor(m.name, floor_name)]
    return sorted(Path(n).stem for n in names)


@dataclass(frozen=True)
class IlcFloorMap:
    """A floor's size and walkable area in the floor-map frame (metres).

    Attributes
    ----------
    width_m, height_m : float
        Map size from ``floor_info.json``.
    outline : tuple of ndarray (n, 2)
        Exterior rings of the floor outline (feature 0 of ``geojson_map.json``).
    obstacles : tuple of ndarray (n, 2)
        Exterior rings of the shop/obstacle polygons (not walkable).
    lonlat_bbox : tuple (lon_min, lat_min, lon_max, lat_max)
        The outline's bounding box that maps onto ``[0, width] x [0, height]``.
    """

    width_m: float
    height_m: float
    outline: tuple
    obstacles: tuple
    lonlat_bbox: tuple
    source: str | None = None

    def walkable(self, x_m, y_m) -> np.ndarray:
        """True where ``(x_m, y_m)`` lies inside an outline ring and outside every obstacle.

        The exact point test; the filters use the same area as a raster
        (:meth:`ilocalg.fusion.particle_filter.OccupancyGrid.from_floor_map`, same rule: union of the
        outline rings minus the obstacles).
        """
        x = np.asarray(x_m, dtype=np.float64)
        y = np.asarray(y_m, dtype=np.float64)
        inside = np.zeros(np.broadcast(x, y).shape, dtype=bool)
        for ring in self.outline:
            inside |= points_in_polygon(x, y, ring)
        blocked = np.zeros_like(inside)
        for ring in self.obstacles:
            blocked |= points_in_polygon(x, y, ring)
        return inside & ~blocked


def points_in_polygon(x_m, y_m, ring: np.ndarray) -> np.ndarray:
    """Even-odd point-in-polygon test (vectorised over points).

    Parameters
    ----------
    x_m, y_m : array_like, broadcastable
    ring : ndarray, shape (n, 2)
        Polygon vertices (closed or not).
    """
    ring = np.asarray(ring, dtype=np.float64)
    if ring.ndim != 2 or ring.shape[1] != 2 or ring.shape[0] < 3:
        raise ValueError(f"ring must have shape (n>=3, 2), got {ring.shape}")
    x = np.asarray(x_m, dtype=np.float64)[..., None]
    y = np.asarray(y_m, dtype=np.float64)[..., None]
    x0, y0 = ring[:, 0], ring[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    cond = (y0 > y) != (y1 > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    return (np.count_nonzero(cond & (x < xc), axis=-1) % 2) == 1


def _exteriors(geom, where: str) -> list[np.ndarray]:
    try:
        kind, coords = geom["type"], geom["coordinates"]
        if kind == "Polygon":
            rings = [(f"{where}.coordinates[0]", coords[0])]
        elif kind == "MultiPolygon":
            rings = [(f"{where}.coordinates[{i}][0]", p[0]) for i, p in enumerate(coords)]
        else:
            raise ValueError(f"{where}: unsupported geometry type {kind!r}; expected Polygon or MultiPolygon")
        out = []
        for w, r in rings:
            a = np.asarray(r, dtype=np.float64)
            if a.ndim != 2 or a.shape[1] < 2 or a.shape[0] < 3:
                raise ValueError(f"{w}: a ring needs at least 3 [lon, lat] points, got shape {a.shape}")
            at = [f"{w}[{k}]" for k in range(a.shape[0])]
            check_range(a[:, 0], "lon_deg", None, at, "0 (longitude)")
            check_range(a[:, 1], "lat_deg", None, at, "1 (latitude)")
            out.append(a[:, :2])
        return out
    except (KeyError, TypeError, IndexError) as e:
        raise ValueError(f"{where}: not a GeoJSON Polygon/MultiPolygon geometry ({type(e).__name__}: {e})") from None


def _json(data: bytes, source: str):
    text = decode_text(data, source)
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise ValueError(f"{source}: line {e.lineno}, column {e.colno}: not valid JSON ({e.msg})") from None


def _floor_map(info_bytes: bytes, geo_bytes: bytes, source: str) -> IlcFloorMap:
    info_src, geo_src = f"{source}/floor_info.json", f"{source}/geojson_map.json"
    info = _json(info_bytes, info_src)
    try:
        w = float(info["map_info"]["width"])
        h = float(info["map_info"]["height"])
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"{info_src}: lacks numeric map_info.width/height ({type(e).__name__}: {e})") from e
    check_range([w, h], "map_size_m", info_src, ["map_info.width", "map_info.height"], "")
    geo = _json(geo_bytes, geo_src)
    feats = geo.get("features") if isinstance(geo, dict) else None
    if not feats:
        raise ValueError(f"{geo_src}: geojson_map.json has no features")
    try:
        outline_ll = _exteriors(feats[0]["geometry"], "features[0].geometry")
        obstacles_ll = [r for i, f in enumerate(feats[1:], start=1)
                        for r in _exteriors(f["geometry"], f"features[{i}].geometry")]
    except (KeyError, TypeError) as e:
        raise ValueError(f"{geo_src}: a feature lacks its geometry ({type(e).__name__}: {e})") from None
    except ValueError as e:
        raise ValueError(f"{geo_src}: {e}") from None
    allpts = np.concatenate(outline_ll)
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    if not (hi[0] > lo[0] and hi[1] > lo[1]):
        raise ValueError(f"{geo_src}: features[0] (the floor outline) spans no area: longitudes "
                         f"[{lo[0]!r}, {hi[0]!r}], latitudes [{lo[1]!r}, {hi[1]!r}]")

    def to_m(r):
        return np.column_stack([(r[:, 0] - lo[0]) / (hi[0] - lo[0]) * w, (r[:, 1] - lo[1]) / (hi[1] - lo[1]) * h])

    obstacles = [to_m(r) for r in obstacles_ll]
    return IlcFloorMap(width_m=w, height_m=h, outline=tuple(to_m(r) for r in outline_ll),
                       obstacles=tuple(obstacles), lonlat_bbox=(lo[0], lo[1], hi[0], hi[1]), source=source)


def load_ilc_floor_map(root, floor_name: str | None = None) -> IlcFloorMap:
    """Floor size and walkable polygons from a floor folder or its archive (see module docstring;
    ``floor_name`` as in :func:`load_ilc_floor`)."""
    r = _resolve_root(root)
    if r.is_dir():
        return _floor_map(read_bytes(r / "floor_info.json"), read_bytes(r / "geojson_map.json"), str(r))
    m = _read_members(r, lambda n: n.endswith(("floor_info.json", "geojson_map.json")) and _in_floor(n, floor_name))
    info = [v for k, v in m.items() if k.endswith("floor_info.json")]
    geo = [v for k, v in m.items() if k.endswith("geojson_map.json")]
    if len(info) != 1 or len(geo) != 1:
        found = sorted(Path(k).parent.name for k in m if k.endswith("floor_info.json"))
        raise ValueError(f"{r}: expected one floor_info.json and one geojson_map.json in the archive; found "
                         f"{len(found)} floors ({', '.join(found) or 'none'}); pick one with floor_name="
                         f"{found[0] if found else 'NAME'!r} (command line: --floor-name)")
    return _floor_map(info[0], geo[0], str(r))


@dataclass(frozen=True)
class IlcFloor:
    """All traces of one floor plus its map.

    Attributes
    ----------
    traces : dict[str, IlcTrace]
        Trace id -> trace, sorted by id.
    floor_map : IlcFloorMap
    source : str
    """

    traces: dict
    floor_map: IlcFloorMap
    source: str

    @property
    def names(self) -> list[str]:
        return list(self.traces)


def load_ilc_floor(root, names=None, duplicate_bssid: str = "error", truncated_last_line: str = "error",
                   relisted_wifi: str = "refuse", floor_name: str | None = None) -> IlcFloor:
    """Load a floor's traces (all, or ``names``) and map from a folder or directly from its archive.

    ``root`` may be the extracted floor folder (``.../site2_F4`` with ``path_data_files/``), the
    data-set folder holding the ``.tar.xz`` or the archive itself; archive members are read in
    memory with :mod:`tarfile` (nothing is extracted); a corrupt or truncated archive raises a
    ValueError naming it (and the member being read). ``duplicate_bssid``, ``relisted_wifi`` and
    ``truncated_last_line`` are passed to :func:`parse_ilc_trace` for every trace. ``floor_name``
    picks one floor folder of an archive holding several (e.g. ``"site1_F1"`` in ``site1_F1_F2.tar.xz``).
    """
    r = _resolve_root(root)
    want = None if names is None else set(names)
    texts: dict[str, tuple[str, str]] = {}
    if r.is_dir():
        for f in sorted((r / "path_data_files").glob("*.txt")):
            if want is None or f.stem in want:
                texts[f.stem] = (read_bytes(f), str(f))
        fmap = load_ilc_floor_map(r)
    else:
        m = _read_members(r, lambda n: n.endswith((".txt", "floor_info.json", "geojson_map.json"))
                          and _in_floor(n, floor_name))
        for k, v in sorted(m.items()):
            if "path_data_files/" in k and k.endswith(".txt") and (want is None or Path(k).stem in want):
                texts[Path(k).stem] = (v, f"{r}:{k}")
        info = [v for k, v in m.items() if k.endswith("floor_info.json")]
        geo = [v for k, v in m.items() if k.endswith("geojson_map.json")]
        if len(info) != 1 or len(geo) != 1:
            found = sorted(Path(k).parent.name for k in m if k.endswith("floor_info.json"))
            raise ValueError(f"{r}: expected one floor_info.json and one geojson_map.json in the archive; found "
                             f"{len(found)} floors ({', '.join(found) or 'none'}); pick one with floor_name="
                             f"{found[0] if found else 'NAME'!r} (command line: --floor-name), or extract "
                             "the archive and pass that floor's folder")
        fmap = _floor_map(info[0], geo[0], str(r))
    if want is not None and set(texts) != want:
        raise ValueError(f"{r}: traces not found: {sorted(want - set(texts))}")
    if not texts:
        raise ValueError(f"{r}: no trace files (path_data_files/*.txt)")
    traces = {k: parse_ilc_trace(t, src, duplicate_bssid=duplicate_bssid, truncated_last_line=truncated_last_line,
                                 relisted_wifi=relisted_wifi) for k, (t, src) in sorted(texts.items())}
    return IlcFloor(traces=traces, floor_map=fmap, source=str(r))


# ----------------------------------------------------------------------------------------------
# positions at arbitrary times, fingerprints from walks
# ----------------------------------------------------------------------------------------------

def interpolate_waypoints(waypoints: pd.DataFrame, t_s, outside: str = "error",
                          span_name: str = "waypoint") -> np.ndarray:
    """Positions at times ``t_s`` by linear interpolation between the surveyor's waypoints.

    Parameters
    ----------
    waypoints : DataFrame
        ``t_s, x_m, y_m`` (strictly increasing times, at least 2 rows).
    t_s : array_like, shape (n,)
    outside : {"error", "nan"}
        Times before the first or after the last waypoint raise (``"error"``) or give NaN rows
        (``"nan"``); nothing is extrapolated.
    span_name : str
        What the points are, in the error message (``"waypoint"``, ``"ground-truth"``).

    Returns
    -------
    ndarray, shape (n, 2), metres
    """
    if outside not in ("error", "nan"):
        raise ValueError(f"outside must be 'error' or 'nan', got {outside!r}")
    check_waypoints(waypoints, "waypoints")
    if len(waypoints) < 2:
        raise ValueError(f"need at least 2 waypoints to interpolate, got {len(waypoints)}")
    tw = waypoints[T_S].to_numpy(dtype=np.float64)
    t = np.asarray(t_s, dtype=np.float64)
    out = (t < tw[0]) | (t > tw[-1]) | ~np.isfinite(t)
    if outside == "error" and out.any():
        i = int(np.flatnonzero(out)[0])
        raise ValueError(f"t_s[{i}] = {float(t[i])!r} is outside the {span_name} time span "
                         f"[{float(tw[0])!r}, {float(tw[-1])!r}] "
                         "(pass outside='nan' to get NaN there)")
    xy = np.column_stack([np.interp(t, tw, waypoints[X_M].to_numpy(dtype=np.float64)),
                          np.interp(t, tw, waypoints[Y_M].to_numpy(dtype=np.float64))])
    xy[out] = np.nan
    return xy


@dataclass(frozen=True)
class IlcFingerprints:
    """Wi-Fi fingerprints made from ILC walks.

    Attributes
    ----------
    fingerprints : FingerprintSet
        One sample per used scan; ``meta`` has ``trace, scan_id, t_s``.
    scans : DataFrame
        Every scan of the given traces: ``trace, scan_id, t_s, x_m, y_m, n_aps, n_stale, used`` and
        ``reason`` (``""``, ``"outside waypoint span"`` or ``"no AP left"``).
    n_outside, n_stale_dropped : int
        Scans left out for lying outside their walk's waypoint span; AP readings left out for being
        older than ``max_age_s``.
    """

    fingerprints: FingerprintSet
    scans: pd.DataFrame
    n_outside: int
    n_stale_dropped: int


def ilc_fingerprints(traces, outside: str = "error", max_age_s: float | None = None) -> IlcFingerprints:
    """Build a fingerprint set from ILC walks: each scan positioned by interpolating its walk's waypoints.

    Parameters
    ----------
    traces : dict[str, IlcTrace] or iterable of IlcTrace
    outside : {"error", "drop"}
        Scans before the first / after the last waypoint of their walk raise, or are left out
        and counted (``n_outside``). In the 19 site2/F4 traces 9 of 268 scans lie after the
        last waypoint.
    max_age_s : float or None
        Leave out (and count) AP readings whose last-seen time is more than this before the
        scan (Android reports cached results, often tens of seconds old); ``None`` keeps all.

    Returns
    -------
    IlcFingerprints
    """
    if outside not in ("error", "drop"):
        raise ValueError(f"outside must be 'error' or 'drop', got {outside!r}")
    if max_age_s is not None and not max_age_s >= 0:
        raise ValueError(f"max_age_s must be >= 0 or None, got {max_age_s!r}")
    items = list(traces.values() if isinstance(traces, dict) else traces)
    if not items:
        raise ValueError("ilc_fingerprints: no traces given")
    scan_rows, samples, used_rows = [], [], []
    n_stale_total = 0
    for tr in items:
        w = tr.wifi
        if not len(w):
            continue
        st = w.groupby(SCAN_ID, sort=True)[T_S].first()
        xy = interpolate_waypoints(tr.waypoints, st.to_numpy(), outside="nan")
        if outside == "error" and np.isnan(xy[:, 0]).any():
            i = int(np.flatnonzero(np.isnan(xy[:, 0]))[0])
            raise ValueError(f"{tr.source}: scan {int(st.index[i])} at t_s={float(st.iloc[i])!r} lies outside the "
                             "waypoint time span (pass outside='drop' to leave such scans out, counted)")
        stale = np.zeros(len(w), dtype=bool)
        if max_age_s is not None:
            stale = (w[T_S] - w["last_seen_s"]).to_numpy() > max_age_s
        used = np.zeros(len(w), dtype=bool)
        for i, (sid, t) in enumerate(st.items()):
            rows = (w[SCAN_ID] == sid).to_numpy()
            n_st = int((rows & stale).sum())
            keep = rows & ~stale
            reason = ""
            if np.isnan(xy[i, 0]):
                reason = "outside waypoint span"
            elif not keep.any():
                reason = "no AP left"
            else:
                n_stale_total += n_st
                used |= keep
                samples.append((tr.name, int(sid), float(t), xy[i]))
            scan_rows.append({"trace": tr.name, SCAN_ID: int(sid), T_S: float(t), X_M: xy[i, 0], Y_M: xy[i, 1],
                              "n_aps": int(rows.sum()), "n_stale": n_st, "used": reason == "", "reason": reason})
        if used.any():
            used_rows.append(w[used])
    scans = pd.DataFrame(scan_rows)
    if not samples:
        raise ValueError("ilc_fingerprints: no usable scan in the given traces")
    ap_ids = sorted({b for w in used_rows for b in w[BSSID].tolist()})
    # one row per used scan, in trace then scan order (as ``samples``)
    rssi = np.concatenate([scan_matrix(w, ap_ids)[2] for w in used_rows])
    meta = pd.DataFrame({"trace": [s[0] for s in samples], SCAN_ID: [s[1] for s in samples],
                         T_S: [s[2] for s in samples]})
    xy = np.array([s[3] for s in samples])
    fps = FingerprintSet(rssi_dbm=rssi, ap_ids=tuple(ap_ids), x_m=xy[:, 0], y_m=xy[:, 1], meta=meta,
                         source=f"ILC walks ({len(items)} traces)")
    n_out = int((scans["reason"] == "outside waypoint span").sum())
    return IlcFingerprints(fingerprints=fps, scans=scans, n_outside=n_out, n_stale_dropped=n_stale_total)
