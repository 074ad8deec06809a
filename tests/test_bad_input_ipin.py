"""Bad and unusual input for the IPIN logfile loader: every case fails naming file and line, or is
accepted by the common text policy or an explicit, counted policy."""

from __future__ import annotations

import gzip
import lzma
import re
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ilocalg.io import ipin

GOOD = """\
% crafted logfile
POSI;0.100;1;39.000000;-3.000000;0;0
ACCE;0.110;1000.010;0.1;0.2;9.8;3
GYRO;0.112;1000.012;0.01;0.02;0.03;3
MAGN;0.115;1000.015;20.0;-5.0;-30.0;3
ACCE;0.130;1000.030;0.2;0.3;9.7;3
AHRS;0.131;1000.031;1.0;2.0;3.0;0.1;0.2;0.3
ACCE;0.150;1000.050;0.3;0.4;9.6;3
WIFI;0.500;1000.400;eduroam;00:0b:86:27:36:c1;2412;-65
WIFI;0.500;1000.450;;00:0b:86:27:36:c2;5180;-80
POSI;2.100;2;39.000100;-3.000000;1;0
"""
LINES = GOOD.splitlines()


def _write(tmp_path, data, name="log.txt"):
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode("utf-8"))
    return p


def _same(a: ipin.IpinLog, b: ipin.IpinLog):
    for k in ("acc", "gyr", "mag"):
        np.testing.assert_array_equal(getattr(a, k).to_numpy(), getattr(b, k).to_numpy())
    assert a.wifi.equals(b.wifi) and a.positions.equals(b.positions) and a.kept == b.kept


# ------------------------------------------------------------------------------------ text policy

def test_bom_crlf_and_trailing_blank_lines_are_accepted(tmp_path):
    ref = ipin.load_ipin_logfile(_write(tmp_path, GOOD))
    odd = b"\xef\xbb\xbf" + GOOD.replace("\n", "\r\n").encode() + b"\r\n\r\n  \n"
    log = ipin.load_ipin_logfile(_write(tmp_path, odd, "odd.txt"))
    _same(log, ref)
    assert log.kept["POSI"] == 2  # the BOM no longer hides the first record


def test_non_utf8_byte_is_an_error_naming_file_and_line(tmp_path):
    data = GOOD.replace("eduroam", "caf\u00e9").encode("latin-1")
    with pytest.raises(ValueError, match=r"latin\.txt: line 9: byte 0xE9 .* is not UTF-8"):
        ipin.load_ipin_logfile(_write(tmp_path, data, "latin.txt"))


@pytest.mark.parametrize("suffix, pack", [(".gz", gzip.compress), (".xz", lzma.compress)])
def test_compressed_files_are_read_transparently(tmp_path, suffix, pack):
    ref = ipin.load_ipin_logfile(_write(tmp_path, GOOD))
    _same(ipin.load_ipin_logfile(_write(tmp_path, pack(GOOD.encode()), "log.txt" + suffix)), ref)


@pytest.mark.parametrize("suffix, pack, kind", [(".gz", gzip.compress, "gzip"), (".xz", lzma.compress, "xz")])
def test_corrupt_compressed_file_names_the_file(tmp_path, suffix, pack, kind):
    p = _write(tmp_path, pack(GOOD.encode())[:40], "cut.txt" + suffix)
    with pytest.raises(ValueError, match=rf"cut\.txt\{suffix}: corrupt or truncated {kind} data"):
        ipin.load_ipin_logfile(p)
    p = _write(tmp_path, GOOD, "plain.txt" + suffix)
    with pytest.raises(ValueError, match=rf"plain\.txt\{suffix}: not {kind} data although the name ends in"):
        ipin.load_ipin_logfile(p)


# ------------------------------------------------------------------------------ record types

@pytest.mark.parametrize("sep", [",", "\t"])
def test_other_delimiters_are_an_error_not_an_empty_log(tmp_path, sep):
    p = _write(tmp_path, GOOD.replace(";", sep), "delim.txt")
    msg = r"delim\.txt: line 2: fields are separated by " + re.escape(repr(sep)) + "; .* by ';'"
    with pytest.raises(ValueError, match=msg):
        ipin.load_ipin_logfile(p)


def test_lower_case_types_are_an_error(tmp_path):
    p = _write(tmp_path, GOOD.replace("ACCE;0.130", "acce;0.130"), "lower.txt")
    with pytest.raises(ValueError, match=r"lower\.txt: line 6: record type 'acce' must be upper case"):
        ipin.load_ipin_logfile(p)


def test_no_known_record_type_is_an_error(tmp_path):
    p = _write(tmp_path, "AHRS;0.1;1.0;1;2;3;0.1;0.2;0.3\nPRES;0.2;1.1;1013;3\n", "other.txt")
    with pytest.raises(ValueError, match=r"other\.txt: no known record type found .*first on line 1: 'AHRS'"):
        ipin.load_ipin_logfile(p)


# --------------------------------------------------------------------------- cut last line

@pytest.mark.parametrize("cut", ["POSI;2.100;2;39.0001", "PO", "ACC"])
def test_cut_last_line_is_an_error_or_dropped_and_counted(tmp_path, cut):
    text = "\n".join(LINES[:-1]) + "\n" + cut  # no line end: the recording stopped mid-line
    p = _write(tmp_path, text, "cut.txt")
    with pytest.raises(ValueError, match=r"cut\.txt: line 11: the file ends inside this record.*"
                                         r"truncated_last_line='drop'"):
        ipin.load_ipin_logfile(p)
    log = ipin.load_ipin_logfile(p, truncated_last_line="drop")
    assert log.skipped[ipin.TRUNCATED_KEY] == 1
    assert len(log.positions) == 1 and log.kept["ACCE"] == 3
    with pytest.raises(ValueError, match="truncated_last_line must be one of"):
        ipin.load_ipin_logfile(p, truncated_last_line="keep")


def test_whole_last_line_without_line_end_is_not_cut(tmp_path):
    log = ipin.load_ipin_logfile(_write(tmp_path, GOOD.rstrip("\n")))
    assert len(log.positions) == 2 and ipin.TRUNCATED_KEY not in log.skipped


# ----------------------------------------------------------------------------- value ranges

@pytest.mark.parametrize("old, new, match", [
    ("00:0b:86:27:36:c1;2412;-65", "00:0b:86:27:36:c1;2412;50",
     r"line 9, column 7 \(RSS\): value 50 is outside \[-110, 0\] dBm"),
    ("00:0b:86:27:36:c1;2412;-65", "00:0b:86:27:36:c1;-2412;-65",
     r"line 9, column 6 \(Frequency\): value -2412 is outside \[2400, 7125\] MHz"),
    ("0.2;0.3;9.7;3", "0.2;0.3;1e9;3", r"line 6, column 6 \(Z\): value 1000000000 is outside \[-400, 400\] m/s\^2"),
    ("1;0\n", "1;1e20\n", r"line 11, column 7 \(Building_ID\): value 1e\+20 is outside \[0, 1000000\]"),
    ("-3.000000;1;0", "-3.000000;1.5;0", r"line 11, column 6 \(floor_ID\): value 1.5 is not a whole number"),
    ("POSI;2.100;2;", "POSI;1e17;2;", r"line 11, column 2 \(Timestamp\): value 1e\+17 is outside \[0, 86400\] s"),
])
def test_values_outside_their_range_name_line_column_and_value(tmp_path, old, new, match):
    p = _write(tmp_path, GOOD.replace(old, new), "range.txt")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an overflow is an error, never a numpy warning
        with pytest.raises(ValueError, match=r"range\.txt: " + match):
            ipin.load_ipin_logfile(p)


# Value fields (line index in LINES, field index after ';'-split) whose corruption must be reported
# on exactly that line.
_VALUE_FIELDS = [(2, 3), (2, 5), (3, 4), (4, 3), (8, 5), (8, 6), (10, 3), (10, 4), (10, 5), (10, 6)]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.sampled_from(_VALUE_FIELDS),
       value=st.one_of(st.sampled_from(["", "abc", "nan", "inf", "-inf", "1e400", "0x10", "--1"]),
                       st.floats(allow_nan=False, allow_infinity=False, width=64).map(repr)))
def test_one_corrupted_field_loads_or_names_file_and_line(tmp_path, where, value):
    i, j = where
    lines = list(LINES)
    parts = lines[i].split(";")
    parts[j] = value
    lines[i] = ";".join(parts)
    p = _write(tmp_path, "\n".join(lines) + "\n", "prop.txt")
    try:
        log = ipin.load_ipin_logfile(p)
    except ValueError as e:
        assert str(e).startswith(f"{p}: line {i + 1}"), str(e)
        return
    got = {2: log.acc.iloc[0].to_numpy(), 3: log.gyr.iloc[0].to_numpy(), 4: log.mag.iloc[0].to_numpy()}
    if i in got:
        assert got[i][j - 3] == float(value)
    elif i == 8:
        assert log.wifi.iloc[0][{5: "freq_mhz", 6: "rssi_dbm"}[j]] == float(value)
    else:
        assert log.positions.iloc[1][{3: "lat_deg", 4: "lon_deg", 5: "floor", 6: "building"}[j]] == float(value)


# ------------------------------------------------------------------ fast path == line by line

def _big(n_epochs: int) -> str:
    out = ["% generated"]
    for i in range(n_epochs):
        t = 0.01 * i
        out.append(f"ACCE;{t:.3f};{t + 5:.3f};{np.sin(i):.5f};0.{i % 97};9.8;3")
        out.append(f"AHRS;{t:.3f};{t + 5:.3f};1;2;3;0.1;0.2;0.3")
        if i % 7 == 0:
            out.append(f"PRES;{t:.3f};{t + 5:.3f};1013.{i % 10};3")
        if i % 500 == 3:
            out.append(f"WIFI;{t:.3f};{t + 5:.3f};my net {i};00:0b:86:27:36:{i % 256:02x};2412;-{40 + i % 50}")
        if i % 1000 == 0:
            out.append(f"POSI;{t + 0.001:.3f};{i};39.{i:06d};-3.0;{i % 3};0")
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("text", [GOOD, GOOD.replace("\n", "\r\n"), _big(30000)], ids=["small", "crlf", "big"])
def test_fast_path_and_line_by_line_parser_agree(text):
    data = text.encode()
    fast = ipin._blocks_fast(data)
    assert fast is not None  # these files take the fast path
    slow = ipin._blocks_slow(text.splitlines(), "x")
    assert fast[1] == slow[1] and list(fast[1]) == list(slow[1])  # counts, in order of first occurrence
    assert set(fast[0]) == set(slow[0])
    for k, b in slow[0].items():
        a = fast[0][k]
        np.testing.assert_array_equal(a.lines, b.lines)
        np.testing.assert_array_equal(a.num, b.num)
        assert a.ssid == b.ssid and a.bssid == b.bssid


def test_unknown_record_types_of_every_length_are_counted_like_the_line_parser():
    # the fast path reads unknown types through a 16-byte window, then a 64-byte one, then line by line
    names = ["XYZ", "A" * 15, "B" * 16, "C" * 17, "D" * 63, "E" * 64, "F" * 70]
    lines = GOOD.splitlines()
    out = lines[:4]
    for i, name in enumerate(names * 3):
        out.append(f"{name};{i};1;2" if i % 2 else name)  # with fields, and a type alone on its line
        out.append(lines[3 + i % 8])
    text = "\n".join(out + lines[4:]) + "\n"
    fast = ipin._blocks_fast(text.encode())
    assert fast is not None
    slow = ipin._blocks_slow(text.splitlines(), "x")
    assert fast[1] == slow[1] and list(fast[1]) == list(slow[1])  # counts, in order of first occurrence
    assert all(fast[1][n] == 3 for n in names)


@pytest.mark.parametrize("old, new", [(";3\n", "; 3\n"), ("0.2;9.8;3", "0.2;TRUE;3"), ("\n", "\n\x0c"),
                                      (";-65", ";-65;"), ("%", " %")])
def test_odd_files_leave_the_fast_path(old, new):
    assert ipin._blocks_fast(GOOD.replace(old, new, 1).encode()) is None


def test_ssid_true_stays_text():
    fast = ipin._blocks_fast(GOOD.replace("eduroam", "TRUE").encode())
    assert fast[0]["WIFI"].ssid[0] == "TRUE"


def test_a_column_of_only_true_false_words_is_refused_not_read_as_ones():
    # pandas reads a column made only of true/false words as 1/0; the fast path checks such columns,
    # and the line parser names the first word
    lines = [ln if not ln.startswith(("ACCE", "GYRO", "MAGN")) else
             ";".join(ln.split(";")[:5] + [("TRUE", "False")[i % 2], ln.split(";")[6]])
             for i, ln in enumerate(LINES)]
    data = "\n".join(lines) + "\n"
    assert ipin._blocks_fast(data.encode()) is None
    with pytest.raises(ValueError, match=r"x: line 3: ACCE field 6 \(Z\) must be a finite number, got 'TRUE'"):
        ipin.parse_ipin_logfile(data, "x")


@pytest.mark.parametrize("n_epochs", [1, 7, 20001])
def test_fast_path_reads_any_number_of_records_in_pieces(n_epochs):
    # records of one layout are read by pandas a few megabytes at a time; a piece may end anywhere
    from ilocalg.io import _text
    text = _big(n_epochs)
    old = _text._PIECE
    try:
        _text._PIECE = 997  # many small pieces, cut inside runs of lines
        fast = ipin._blocks_fast(text.encode())
    finally:
        _text._PIECE = old
    slow = ipin._blocks_slow(text.splitlines(), "x")
    assert fast is not None and set(fast[0]) == set(slow[0])
    for k, b in slow[0].items():
        np.testing.assert_array_equal(fast[0][k].num, b.num)
        np.testing.assert_array_equal(fast[0][k].lines, b.lines)
        assert fast[0][k].ssid == b.ssid


@pytest.mark.parametrize("turns", [True, False], ids=["types-take-turns", "irregular"])
def test_fast_path_reads_interleaved_imu_types_like_the_line_parser(turns):
    """ACCE, GYRO and MAGN read together: in turns (each type every third line, no reordering) or irregularly."""
    out = ["% interleaved"]
    for i in range(3000):
        t = 0.01 * i
        for k, rt in enumerate(("GYRO", "ACCE", "MAGN")):
            if turns or (i + k) % 4:
                out.append(f"{rt};{t + 0.001 * k:.3f};{t + 5:.3f};{np.sin(i + k):.5f};0.{i % 97};{9 + k}.8;3")
        if i % 50 == 0:
            out.append(f"AHRS;{t:.3f};{t + 5:.3f};1;2;3;0.1;0.2;0.3")
    text = "\n".join(out) + "\n"
    fast = ipin._blocks_fast(text.encode())
    assert fast is not None
    slow = ipin._blocks_slow(text.splitlines(), "x")
    assert fast[1] == slow[1] and list(fast[1]) == list(slow[1])
    for k, b in slow[0].items():
        np.testing.assert_array_equal(fast[0][k].lines, b.lines)
        np.testing.assert_array_equal(fast[0][k].num, b.num)


@pytest.mark.parametrize("chunk", [7, 64, 1 << 21])
def test_line_scan_matches_a_plain_count(chunk):
    """The scan behind both fast paths (line ends, separators per line, bytes up to 32) equals a count line by
    line, including lines that cross a chunk border, chunks without a line end and lines of 256+ separators."""
    from ilocalg.io import _text

    rng = np.random.default_rng(3)
    old = _text._CHUNK
    try:
        _text._CHUNK = chunk
        for _ in range(40):
            body = rng.choice(np.frombuffer(b"ab;;\t\n\r\x0b 1", dtype=np.uint8), rng.integers(1, 400)).tobytes()
            data = body + b";" * int(rng.integers(0, 2) * 300) + b"\t" * int(rng.integers(0, 2) * 70) + b"\n"
            arr = np.frombuffer(data, dtype=np.uint8)
            for sep in (b";", b"\t"):
                ends, n_sep, n_le32 = _text._scan_lines(arr, sep[0])
                lines = data.split(b"\n")[:-1]
                assert ends.tolist() == [i for i, b in enumerate(data) if b == 10]
                assert n_sep.tolist() == [ln.count(sep) for ln in lines]
                assert n_le32 == sum(b <= 32 for b in data)  # controls and spaces
    finally:
        _text._CHUNK = old
