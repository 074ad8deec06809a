"""Loader for UJIIndoorLoc (trainingData.csv / validationData.csv, plain or gzip-compressed).

Format (UCI dataset 310): a header line and 529 comma-separated columns per row:
``WAP001`` ... ``WAP520`` (RSSI in dBm, integers -104..0, **100 = not detected**), ``LONGITUDE``,
``LATITUDE``, ``FLOOR``, ``BUILDINGID``, ``SPACEID``, ``RELATIVEPOSITION``, ``USERID``, ``PHONEID``,
``TIMESTAMP``.

Positions: despite their names, LONGITUDE and LATITUDE are **metres in a projected frame (Web
Mercator, EPSG:3857)**, not degrees. They are returned unchanged as ``x_m`` (= LONGITUDE) and
``y_m`` (= LATITUDE): errors computed from them are in projected metres, the unit the published
results on this set use. Web-Mercator metres are stretched by ``1/cos(latitude)``; at the Jaume I
campus (about 39.99 deg N) one projected metre is about 0.766 ground metres, see
:func:`ground_scale`.

References
----------
Torres-Sospedra J. et al., "UJIIndoorLoc: A new multi-building and multi-floor database for WLAN
fingerprint-based indoor localization problems", IPIN 2014, doi:10.1109/IPIN.2014.7275492.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import byte_positions, count_per_line, decode_text, read_bytes
from ilocalg.io.schema import BUILDING, FIELD_RANGES, FLOOR, RSSI_DBM, FingerprintSet, check_range

__all__ = [
    "N_WAPS",
    "WAP_COLUMNS",
    "POSITION_COLUMNS",
    "META_COLUMNS",
    "NOT_DETECTED",
    "WEAKEST_DBM",
    "load_ujiindoorloc",
    "ground_scale",
]

N_WAPS = 520
WAP_COLUMNS = tuple(f"WAP{i:03d}" for i in range(1, N_WAPS + 1))
POSITION_COLUMNS = ("LONGITUDE", "LATITUDE", "FLOOR", "BUILDINGID")
META_COLUMNS = ("SPACEID", "RELATIVEPOSITION", "USERID", "PHONEID", "TIMESTAMP")
#: The RSSI code for "access point not detected".
NOT_DETECTED = 100
#: The weakest reading the data set documents, the usual substitute for "not detected".
WEAKEST_DBM = -104.0

_EARTH_RADIUS_M = 6378137.0


def ground_scale(y_m) -> np.ndarray:
    """Ground metres per projected (Web Mercator) metre at northing ``y_m``: ``cos(latitude)``."""
    lat = 2.0 * np.arctan(np.exp(np.asarray(y_m, dtype=np.float64) / _EARTH_RADIUS_M)) - np.pi / 2.0
    return np.cos(lat)


def _read_integer_rssi(data: bytes, header: list, n_rows: int):
    """``(wap, cols)``: the WAP columns as int16 (n, 520) and every other column as float64, or ``(None, None)``
    when a WAP cell is not an integer code within int16 or another cell is not a finite number (the float64
    path then reads the file and names the cell)."""
    wanted = set(WAP_COLUMNS)
    try:
        with np.errstate(invalid="ignore", over="ignore"):  # a cell pandas cannot cast: the float64 path names it
            df = pd.read_csv(io.BytesIO(data), header=0, names=header, nrows=n_rows, engine="c", na_filter=False,
                             dtype={c: (np.int16 if c in wanted else np.float64) for c in header})
    except (ValueError, TypeError, OverflowError, pd.errors.ParserError):
        return None, None
    cols = {c: df[c].to_numpy(dtype=np.float64) for c in header if c not in wanted}
    if not all(np.isfinite(v).all() for v in cols.values()):
        return None, None
    wap = df[list(WAP_COLUMNS)].to_numpy(dtype=np.int16)
    return wap, cols


def _read_float_table(data: bytes, path, header: list, n_rows: int, letters: bool):
    """``(wap, cols)`` as float64 (every cell parsed as a number); raises naming the first cell that is not a
    finite number (file line, column)."""
    arr = None
    try:
        df = pd.read_csv(io.BytesIO(data), header=0, names=header, nrows=n_rows, dtype=np.float64,
                         keep_default_na=False, na_values=[], engine="c")
        arr = df.to_numpy(dtype=np.float64)
        del df
        if not np.isfinite(arr).all() or (letters and np.any((arr == 0.0) | (arr == 1.0))):
            arr = None  # (pandas reads True/False as 1/0: such a cell is named below)
    except (ValueError, pd.errors.ParserError):
        arr = None
    if arr is None:  # locate the first cell that is not a finite number
        df = pd.read_csv(io.BytesIO(data), header=0, names=header, nrows=n_rows, keep_default_na=False,
                         na_values=[], skip_blank_lines=False, dtype=str)
        for col in header:
            s = df[col]
            v = pd.to_numeric(s.str.strip(), errors="coerce").to_numpy(dtype=np.float64)
            bad = np.flatnonzero(~np.isfinite(v))
            if bad.size:
                r = int(bad[0])
                raise ValueError(f"{path}: line {r + 2}, column {col}: expected a number, got {s.iloc[r]!r}")
        raise ValueError(f"{path}: could not parse as {len(header)} numeric columns")  # pragma: no cover
    pos = {c: j for j, c in enumerate(header)}
    cols = {c: arr[:, j] for c, j in pos.items() if c not in set(WAP_COLUMNS)}
    return arr[:, [pos[c] for c in WAP_COLUMNS]], cols


def load_ujiindoorloc(path) -> FingerprintSet:
    """Load a UJIIndoorLoc CSV (``trainingData.csv`` or ``validationData.csv``, optionally ``.gz``).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    FingerprintSet
        ``rssi_dbm`` (n, 520) float64 with 100 replaced by NaN (not heard); ``ap_ids`` the WAP
        column names; ``x_m`` = LONGITUDE, ``y_m`` = LATITUDE (projected Web-Mercator metres, see the
        module docstring); ``floor`` = FLOOR, ``building`` = BUILDINGID (int64); ``meta`` with
        SPACEID, RELATIVEPOSITION, USERID, PHONEID, TIMESTAMP (int64).

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    ValueError
        Empty file, missing or unknown columns, a line with too few or too many fields, a
        non-numeric value, a value outside its valid range (:data:`ilocalg.io.schema.FIELD_RANGES`;
        RSSI other than 100 outside [-110, 0] dBm, an integer column that would overflow), a
        non-UTF-8 byte or a corrupt ``.gz``/``.xz`` file; the message names the file, the line
        (1 = header) and the column. Under the common text policy a byte-order mark is stripped,
        CRLF line ends and trailing blank lines are accepted.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    data = read_bytes(path)
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    if not data.isascii():
        decode_text(data, path)  # a non-UTF-8 byte is an error naming its line
    end = len(data)
    while end and data[end - 1] in b"\r\n \t":  # trailing blank lines are accepted
        end -= 1
    if end == 0:
        raise ValueError(f"{path}: empty file (expected a header and data rows)")
    if data.find(b"\r", 0, end) >= 0 and data.count(b"\r", 0, end) != data.count(b"\r\n", 0, end):
        k = data.find(b"\r", 0, end)
        while data[k + 1:k + 2] == b"\n":
            k = data.find(b"\r", k + 1, end)
        line = data.count(b"\n", 0, k) + 1
        raise ValueError(f"{path}: line {line}: a carriage return without a line feed "
                         "(old Mac line ends); re-save the file with LF or CRLF line ends")
    nl = data.find(b"\n", 0, end)
    header = [h.strip().strip('"') for h in data[:nl if nl >= 0 else end].decode("utf-8").rstrip("\r").split(",")]
    expected = list(WAP_COLUMNS) + list(POSITION_COLUMNS) + list(META_COLUMNS)
    missing = [c for c in expected if c not in header]
    if missing:
        raise ValueError(f"{path}: line 1 (header) lacks columns {missing[:5]}"
                         f"{' ...' if len(missing) > 5 else ''} ({len(missing)} missing)")
    extra = [c for c in header if c not in expected]
    if extra:
        raise ValueError(f"{path}: line 1 (header) has unknown columns {extra[:5]}")
    if len(set(header)) != len(header):
        raise ValueError(f"{path}: line 1 (header) repeats a column name")
    if nl < 0:
        raise ValueError(f"{path}: no data rows after the header")
    n_fields = len(header)
    # fields per data line (commas + 1), vectorised: the first line with another count is named
    body = np.frombuffer(data, dtype=np.uint8, count=end - nl - 1, offset=nl + 1)
    starts = np.concatenate([[0], byte_positions(body, 10) + 1])
    n_per_line = count_per_line(body, 44, starts) + 1
    bad = np.flatnonzero(n_per_line != n_fields)
    if bad.size:
        i, c = int(bad[0]), int(n_per_line[bad[0]])
        what = "truncated line" if c < n_fields else "too many fields"
        raise ValueError(f"{path}: line {i + 2}: {what}: {c} fields, expected {n_fields}")
    n_rows = len(starts)  # lines of the body (it ends without a line end)
    del body, starts, n_per_line
    letters = any(data.find(c, nl) >= 0 for c in (b"r", b"R", b"l", b"L"))  # (True/False: see below)
    # RSSI codes are integers in real files: parsed as int16 (a quarter of float64's memory), then widened
    # once; any cell that is not such an integer sends the file down the float64 path below, unchanged
    wap, cols = (None, None) if letters else _read_integer_rssi(data, header, n_rows)
    if wap is None:
        wap, cols = _read_float_table(data, path, header, n_rows, letters)
    del data
    lines_no = np.arange(2, wap.shape[0] + 2)
    # 100 = not detected; every other reading must be a received power
    spec = FIELD_RANGES[RSSI_DBM]
    not_heard = wap == NOT_DETECTED
    if wap.dtype == np.int16 and np.all(not_heard | ((wap >= spec.lo) & (wap <= spec.hi))):  # whole numbers
        rssi = wap.astype(np.float64, order="F")  # (column-major, as pandas' blocks are)
        del wap
    else:  # the range check on float64 names the first value outside (row-major)
        rssi = wap.astype(np.float64, order="F")
        del wap
        rssi[not_heard] = 0.0
        check_range(rssi, RSSI_DBM, path, lines_no, WAP_COLUMNS)
    np.copyto(rssi, np.nan, where=not_heard)
    del not_heard
    for c in ("LONGITUDE", "LATITUDE"):
        check_range(cols[c], "xy_m", path, lines_no, c)
    kinds = {"FLOOR": FLOOR, "BUILDINGID": BUILDING, "SPACEID": "id", "RELATIVEPOSITION": "id", "USERID": "id",
             "PHONEID": "id", "TIMESTAMP": "unix_time_s"}
    ints = {}
    for c in ("FLOOR", "BUILDINGID") + META_COLUMNS:
        v = check_range(cols[c], kinds[c], path, lines_no, c)  # before the cast: no int64 overflow
        nonint = np.flatnonzero(v != np.round(v))
        if nonint.size:
            r = int(nonint[0])
            raise ValueError(f"{path}: line {r + 2}, column {c}: expected an integer, got {v[r]:g}")
        ints[c] = v.astype(np.int64)
    meta = pd.DataFrame({c: ints[c] for c in META_COLUMNS})
    return FingerprintSet(
        rssi_dbm=rssi,
        ap_ids=WAP_COLUMNS,
        x_m=np.array(cols["LONGITUDE"]),
        y_m=np.array(cols["LATITUDE"]),
        floor=ints["FLOOR"],
        building=ints["BUILDINGID"],
        meta=meta,
        source=str(path),
    )
