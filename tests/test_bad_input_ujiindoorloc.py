"""Bad and unusual input for the UJIIndoorLoc loader: the common text policy, value ranges (no
integer overflow), compression errors; every error names the file's line and column."""

from __future__ import annotations

import lzma
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ilocalg.io.ujiindoorloc import META_COLUMNS, POSITION_COLUMNS, WAP_COLUMNS, load_ujiindoorloc

COLUMNS = WAP_COLUMNS + POSITION_COLUMNS + META_COLUMNS
HEADER = ",".join(COLUMNS)


def _row(k=0):
    r = [100] * 520
    r[k % 520], r[(k + 7) % 520] = -60 - k, -90
    return ",".join(str(v) for v in r) + f",{-7541.26 + k},{4864921.0 + k},{k % 4},{k % 3},106,2,2,23,{1371713733 + k}"


ROWS = [_row(k) for k in range(4)]
GOOD = HEADER + "\n" + "\n".join(ROWS) + "\n"


def _write(tmp_path, data, name="trainingData.csv"):
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode("utf-8"))
    return p


def _same(a, b):
    np.testing.assert_array_equal(a.rssi_dbm, b.rssi_dbm)
    np.testing.assert_array_equal(a.building, b.building)
    assert a.meta.equals(b.meta)


def test_bom_crlf_and_trailing_blank_lines_are_accepted(tmp_path):
    ref = load_ujiindoorloc(_write(tmp_path, GOOD))
    odd = b"\xef\xbb\xbf" + GOOD.replace("\n", "\r\n").encode() + b"\r\n\r\n"
    _same(load_ujiindoorloc(_write(tmp_path, odd, "odd.csv")), ref)


def test_non_utf8_byte_names_line(tmp_path):
    data = GOOD.encode().replace(b",106,2,2,23,1371713735", b",106,2,2,\xe923,1371713735")
    with pytest.raises(ValueError, match=r"latin\.csv: line 4: byte 0xE9 .* is not UTF-8"):
        load_ujiindoorloc(_write(tmp_path, data, "latin.csv"))


def test_xz_is_read_and_corrupt_xz_named(tmp_path):
    ref = load_ujiindoorloc(_write(tmp_path, GOOD))
    _same(load_ujiindoorloc(_write(tmp_path, lzma.compress(GOOD.encode()), "t.csv.xz")), ref)
    with pytest.raises(ValueError, match=r"cut\.csv\.xz: corrupt or truncated xz data"):
        load_ujiindoorloc(_write(tmp_path, lzma.compress(GOOD.encode())[:60], "cut.csv.xz"))


@pytest.mark.parametrize("column, value, match", [
    ("WAP001", "50", r"line 2, column WAP001: value 50 is outside \[-110, 0\] dBm"),
    ("WAP009", "-200", r"line 2, column WAP009: value -200 is outside \[-110, 0\] dBm"),
    ("BUILDINGID", "1e20", r"line 2, column BUILDINGID: value 1e\+20 is outside \[0, 1000000\]"),
    ("FLOOR", "-9223372036854775809", r"line 2, column FLOOR: value -9.22337203685478e\+18 is outside \[-20, 200\]"),
    ("LATITUDE", "nan", r"line 2, column LATITUDE: expected a number, got 'nan'"),
    ("LONGITUDE", "1e30", r"line 2, column LONGITUDE: value 1e\+30 is outside \[-20037508, 20037508\] m"),
    ("TIMESTAMP", "-5", r"line 2, column TIMESTAMP: value -5 is outside \[0, 4102444800\] s"),
    ("USERID", "2.5", r"line 2, column USERID: value 2.5 is not a whole number"),
])
def test_values_outside_their_range_name_line_and_column(tmp_path, column, value, match):
    cells = ROWS[0].split(",")
    cells[COLUMNS.index(column)] = value
    text = HEADER + "\n" + ",".join(cells) + "\n" + "\n".join(ROWS[1:]) + "\n"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an overflow is an error, never a numpy RuntimeWarning
        with pytest.raises(ValueError, match=r"range\.csv: " + match):
            load_ujiindoorloc(_write(tmp_path, text, "range.csv"))


def test_blank_line_inside_the_data_names_its_line(tmp_path):
    text = HEADER + "\n" + ROWS[0] + "\n\n" + "\n".join(ROWS[1:]) + "\n"
    with pytest.raises(ValueError, match=r"gap\.csv: line 3: truncated line: 1 fields, expected 529"):
        load_ujiindoorloc(_write(tmp_path, text, "gap.csv"))


@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(row=st.integers(0, 3), column=st.sampled_from(["WAP001", "WAP300", "LONGITUDE", "FLOOR", "BUILDINGID",
                                                      "PHONEID", "TIMESTAMP"]),
       value=st.one_of(st.sampled_from(["", "abc", "nan", "1e400", "100"]),
                       st.integers(-10**25, 10**25).map(str),
                       st.floats(allow_nan=False, allow_infinity=False, width=64).map(repr)))
def test_one_corrupted_cell_loads_or_names_file_line_and_column(tmp_path, row, column, value):
    rows = list(ROWS)
    cells = rows[row].split(",")
    cells[COLUMNS.index(column)] = value
    rows[row] = ",".join(cells)
    p = _write(tmp_path, HEADER + "\n" + "\n".join(rows) + "\n", "prop.csv")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            fs = load_ujiindoorloc(p)
        except ValueError as e:
            assert str(e).startswith(f"{p}: line {row + 2}, column {column}: "), str(e)
            return
    got = {"LONGITUDE": fs.x_m, "FLOOR": fs.floor, "BUILDINGID": fs.building}.get(column)
    if got is not None:
        assert got[row] == float(value)
