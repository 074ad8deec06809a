"""Read a Wi-Fi survey saved as a CSV in the layout the README offers for one's own data.

Layout: a header line, then one line per Wi-Fi scan: ``x_m``, ``y_m`` (where the scan was taken,
metres), optionally ``floor`` and ``building`` (whole numbers), then one column per access point
(RSSI in dBm, empty where the access point was not heard). Columns may come in any order; every
column that is not ``x_m``, ``y_m``, ``floor`` or ``building`` is an access point.

Bad content raises a ValueError naming the file, its line (as an editor counts it, the header is
line 1) and the column, e.g. ``survey.csv: line 7, column AP3: value 12 is outside [-110, 0] dBm``.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import byte_positions, count_per_line
from ilocalg.io.schema import RSSI_DBM, FingerprintSet, check_range

__all__ = ["SURVEY_POSITION_COLUMNS", "SURVEY_LABEL_COLUMNS", "read_survey_csv"]

#: Required position columns (metres).
SURVEY_POSITION_COLUMNS = ("x_m", "y_m")
#: Optional label columns (whole numbers).
SURVEY_LABEL_COLUMNS = ("floor", "building")


def _numeric(df: pd.DataFrame, col: str, source: str, allow_empty: bool) -> np.ndarray:
    """Column ``col`` as float64 (empty -> NaN), naming the first cell that is not a number."""
    v = pd.to_numeric(df[col], errors="coerce").to_numpy(dtype=np.float64)
    raw = df[col]
    bad = np.isnan(v) & raw.notna().to_numpy()
    if not allow_empty:
        bad |= raw.isna().to_numpy()
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        cell = raw.iloc[i]
        what = "is empty" if pd.isna(cell) else f"must be numeric, got {cell!r}"
        raise ValueError(f"{source}: line {i + 2}, column {col}: {what}")
    if not np.isfinite(v[~np.isnan(v)]).all():
        i = int(np.flatnonzero(~np.isfinite(v) & ~np.isnan(v))[0])
        raise ValueError(f"{source}: line {i + 2}, column {col}: must be a finite number, got {raw.iloc[i]!r}")
    return v


def _check_field_counts(data: bytes, source: str) -> None:
    """Refuse a line with another number of fields than the header (a cut or shortened line would otherwise read
    as access points not heard), naming the first. Blank lines are skipped, as the CSV reader does."""
    if not data.strip():
        return  # an empty file: the CSV reader names it
    if b'"' in data:  # quoted fields may hold commas: count with the csv module
        rows = csv.reader(io.StringIO(data.decode("utf-8-sig", errors="replace")))
        counts = [(i + 1, len(r)) for i, r in enumerate(rows) if r]
        lines, n = np.array([c[0] for c in counts]), np.array([c[1] for c in counts])
    else:
        arr = np.frombuffer(data, dtype=np.uint8)
        starts = np.concatenate([[0], byte_positions(arr, 10) + 1])
        starts = starts[starts < arr.size]
        n = count_per_line(arr, 44, starts) + 1
        ends = np.append(starts[1:] - 1, arr.size - (arr[-1] == 10))   # each line's end (its \n, or the file's)
        length = ends - starts - (arr[np.maximum(ends - 1, 0)] == 13)  # bytes before any \r\n
        keep = length > 0
        lines, n = np.arange(1, starts.size + 1)[keep], n[keep]
    if n.size == 0:
        return
    bad = np.flatnonzero(n != n[0])
    if bad.size:
        i = int(bad[0])
        what = "truncated line" if n[i] < n[0] else "too many fields"
        raise ValueError(f"{source}: line {int(lines[i])}: {what}: {int(n[i])} fields, expected {int(n[0])} "
                         "(the header's)")


def read_survey_csv(path) -> FingerprintSet:
    """Read a survey CSV (see the module docstring) as a :class:`ilocalg.io.schema.FingerprintSet`.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    FingerprintSet
        ``floor`` / ``building`` are None when the file has no such column.

    Raises
    ------
    ValueError
        Missing file, missing ``x_m``/``y_m`` column, no access-point column, no scan, a line with more or fewer
        fields than the header, a cell that is not a number, an empty position or label, an RSSI outside the schema
        range.
    """
    p = Path(path)
    source = str(path)
    if not p.is_file():
        raise ValueError(f"{source}: no such file")
    data = p.read_bytes()
    _check_field_counts(data, source)
    try:
        df = pd.read_csv(io.BytesIO(data), dtype=str, keep_default_na=False, na_values=[""])
    except pd.errors.EmptyDataError:
        raise ValueError(f"{source}: line 1: empty file, expected a header with x_m, y_m and access-point "
                         "columns") from None
    except (pd.errors.ParserError, UnicodeDecodeError) as e:
        raise ValueError(f"{source}: not a CSV file ({str(e).splitlines()[0]})") from None
    cols = [str(c).strip() for c in df.columns]
    df.columns = cols
    dup = sorted({c for c in cols if cols.count(c) > 1})
    if dup:
        raise ValueError(f"{source}: line 1: column {dup[0]} appears more than once")
    missing = [c for c in SURVEY_POSITION_COLUMNS if c not in cols]
    if missing:
        raise ValueError(f"{source}: line 1: no column {missing[0]!r}; the survey layout is x_m, y_m "
                         "[, floor, building], then one RSSI column (dBm) per access point")
    aps = [c for c in cols if c not in SURVEY_POSITION_COLUMNS + SURVEY_LABEL_COLUMNS]
    if not aps:
        raise ValueError(f"{source}: line 1: no access-point column (every column but x_m, y_m, floor, "
                         "building is an access point)")
    if len(df) == 0:
        raise ValueError(f"{source}: no scan after the header line")
    x = _numeric(df, "x_m", source, allow_empty=False)
    y = _numeric(df, "y_m", source, allow_empty=False)
    labels = {}
    for c in SURVEY_LABEL_COLUMNS:
        if c in cols:
            v = _numeric(df, c, source, allow_empty=False)
            if (v != np.round(v)).any():
                i = int(np.flatnonzero(v != np.round(v))[0])
                raise ValueError(f"{source}: line {i + 2}, column {c}: value {df[c].iloc[i]} is not a whole number")
            labels[c] = v.astype(np.int64)
    rssi = np.column_stack([_numeric(df, c, source, allow_empty=True) for c in aps])
    lines = np.arange(len(df)) + 2
    check_range(np.where(np.isnan(rssi), -50.0, rssi), RSSI_DBM, source=source, lines=lines, columns=aps)
    return FingerprintSet(rssi_dbm=rssi, ap_ids=tuple(aps), x_m=x, y_m=y, floor=labels.get("floor"),
                          building=labels.get("building"), source=source)
