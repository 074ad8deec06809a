"""Bad and unusual input for the ILC 2.0 loaders (trace, floor map, floor archive): every case fails
naming file and line (or JSON place, or archive member), or is accepted by the common text policy or
an explicit, counted policy."""

from __future__ import annotations

import io
import json
import lzma
import tarfile
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ilocalg.io import ilc

HEADER = "#\tstartTime:1574149352216\n#\tSiteID:site\tFloorName:F4\n"
BODY = [
    "1000\tTYPE_WAYPOINT\t10.0\t20.0",                              # line 3
    "1000\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t2",
    "1000\tTYPE_GYROSCOPE\t0.01\t0.02\t0.03\t3",
    "1000\tTYPE_MAGNETIC_FIELD\t20.0\t-5.0\t-30.0\t3",
    "1020\tTYPE_ACCELEROMETER\t0.2\t0.3\t9.7\t2",                  # line 7
    "1020\tTYPE_GYROSCOPE\t0.02\t0.03\t0.04\t3",
    "1020\tTYPE_MAGNETIC_FIELD\t21.0\t-6.0\t-31.0\t3",
    "1020\tTYPE_ROTATION_VECTOR\t0.1\t0.0\t0.5\t3",
    "1050\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:01\t-50\t2412\t1040",    # line 11
    "1060\tTYPE_BEACON\tUUID\t1\t2\t-65\t-82\t5.5\t6B:11:4C:D1:29:F2\t1060",
    "1100\tTYPE_WAYPOINT\t13.0\t24.0",                              # line 13
]
GOOD = HEADER + "\n".join(BODY) + "\n"


def _write(tmp_path, data, name="t.txt"):
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode("utf-8"))
    return p


def _same(a: ilc.IlcTrace, b: ilc.IlcTrace):
    assert a.imu.equals(b.imu) and a.wifi.equals(b.wifi) and a.waypoints.equals(b.waypoints)
    assert a.kept == b.kept


# ------------------------------------------------------------------------------------ text policy

def test_bom_crlf_and_trailing_blank_lines_are_accepted(tmp_path):
    ref = ilc.load_ilc_trace(_write(tmp_path, GOOD))
    odd = b"\xef\xbb\xbf" + GOOD.replace("\n", "\r\n").encode() + b"\r\n\r\n"
    tr = ilc.load_ilc_trace(_write(tmp_path, odd, "odd.txt"))
    _same(tr, ref)
    assert tr.header["startTime"] == "1574149352216"


def test_non_utf8_byte_is_an_error_naming_file_and_line(tmp_path):
    data = GOOD.replace("\tnet\t", "\tcaf\u00e9\t").encode("latin-1")
    with pytest.raises(ValueError, match=r"latin\.txt: line 11: byte 0xE9 .* is not UTF-8"):
        ilc.load_ilc_trace(_write(tmp_path, data, "latin.txt"))


def test_xz_trace_is_read_and_a_corrupt_one_named(tmp_path):
    ref = ilc.load_ilc_trace(_write(tmp_path, GOOD))
    _same(ilc.load_ilc_trace(_write(tmp_path, lzma.compress(GOOD.encode()), "t.txt.xz")), ref)
    with pytest.raises(ValueError, match=r"cut\.txt\.xz: corrupt or truncated xz data"):
        ilc.load_ilc_trace(_write(tmp_path, lzma.compress(GOOD.encode())[:50], "cut.txt.xz"))


# ------------------------------------------------------------------------------ record types

def test_lower_case_types_are_an_error(tmp_path):
    p = _write(tmp_path, GOOD.replace("TYPE_", "type_"), "lower.txt")
    with pytest.raises(ValueError, match=r"lower\.txt: line 3: record type 'type_WAYPOINT' must be upper case"):
        ilc.load_ilc_trace(p)


def test_no_known_record_type_is_an_error(tmp_path):
    p = _write(tmp_path, HEADER + "1060\tTYPE_BEACON\tUUID\t1\t2\t-65\n", "beacons.txt")
    with pytest.raises(ValueError, match=r"beacons\.txt: no known record type found .*line 3: 'TYPE_BEACON'"):
        ilc.load_ilc_trace(p)


@pytest.mark.parametrize("cut, why", [("1100\tTYPE_WAYPOINT\t13.0", "1 of the 2 values"),
                                      ("1100\tTYPE_WAY", "record type 'TYPE_WAY' is incomplete"),
                                      ("1100", "only the time column")])
def test_cut_last_line_is_an_error_or_dropped_and_counted(tmp_path, cut, why):
    p = _write(tmp_path, HEADER + "\n".join(BODY[:-1] + [cut]), "cut.txt")
    with pytest.raises(ValueError, match=rf"cut\.txt: line 13: the file ends inside this record \({why}"):
        ilc.load_ilc_trace(p)
    tr = ilc.load_ilc_trace(p, truncated_last_line="drop")
    assert tr.skipped[ilc.TRUNCATED_KEY] == 1 and len(tr.waypoints) == 1


# ----------------------------------------------------------------------------- value ranges

@pytest.mark.parametrize("old, new, match", [
    ("\t-50\t2412", "\t50\t2412", r"line 11, column 5 \(rssi\): value 50 is outside \[-110, 0\] dBm"),
    ("\t-50\t2412", "\t-50\t-2412", r"line 11, column 6 \(frequency\): value -2412 is outside \[2400, 7125\] MHz"),
    ("\t0.2\t0.3\t9.7\t2", "\t0.2\t0.3\t1e9\t2", r"line 7, column 5 \(z\): value 1000000000 is outside"),
    ("\t0.1\t0.0\t0.5\t3", "\t0.1\t0.0\t5\t3", r"line 10, column 5 \(z\): value 5 is outside \[-1, 1\]"),
    ("1100\tTYPE_WAYPOINT\t13.0", "1100\tTYPE_WAYPOINT\tnan", r"line 13, column 3 \(x\): value nan is outside"),
    ("1100\tTYPE_WAYPOINT", "100000000000000000000\tTYPE_WAYPOINT",
     r"line 13, column 1 \(Unix time\): value 1e\+20 is outside \[0, 4102444800000\] ms"),
])
def test_values_outside_their_range_name_line_column_and_value(tmp_path, old, new, match):
    p = _write(tmp_path, GOOD.replace(old, new), "range.txt")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"range\.txt: " + match):
            ilc.load_ilc_trace(p)


# (line index in BODY, tab-field index) of value fields
_VALUE_FIELDS = [(0, 2), (0, 3), (1, 2), (1, 4), (2, 3), (3, 4), (7, 3), (8, 4), (8, 5)]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.sampled_from(_VALUE_FIELDS),
       value=st.one_of(st.sampled_from(["", "abc", "nan", "inf", "1e400", "0x10"]),
                       st.floats(allow_nan=False, allow_infinity=False, width=64).map(repr)))
def test_one_corrupted_field_loads_or_names_file_and_line(tmp_path, where, value):
    i, j = where
    body = list(BODY)
    parts = body[i].split("\t")
    parts[j] = value
    body[i] = "\t".join(parts)
    p = _write(tmp_path, HEADER + "\n".join(body) + "\n", "prop.txt")
    try:
        tr = ilc.load_ilc_trace(p)
    except ValueError as e:
        assert str(e).startswith(f"{p}: line {i + 3}"), str(e)
        return
    assert np.isfinite(float(value)) and len(tr.imu) == 2


# ------------------------------------------------------------------------------------ floor map

INFO = {"map_info": {"width": 200.0, "height": 100.0}}
SQUARE = [[0.0, 0.0], [0.001, 0.0], [0.001, 0.001], [0.0, 0.001], [0.0, 0.0]]


def _geo(outline=SQUARE, obstacles=()):
    feats = [{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [outline]}}]
    feats += [{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [o]}} for o in obstacles]
    return {"type": "FeatureCollection", "features": feats}


def _floor(tmp_path, info=INFO, geo=None, name="F4"):
    d = tmp_path / name
    (d / "path_data_files").mkdir(parents=True)
    (d / "floor_info.json").write_text(info if isinstance(info, str) else json.dumps(info))
    (d / "geojson_map.json").write_text(json.dumps(geo if geo is not None else _geo()))
    return d


def test_good_floor_map(tmp_path):
    m = ilc.load_ilc_floor_map(_floor(tmp_path))
    assert m.width_m == 200.0 and m.walkable([100.0], [50.0]).tolist() == [True]


@pytest.mark.parametrize("info, match", [
    ({"map_info": {"width": float("nan"), "height": 100}}, r"map_info.width: value nan is outside \[1, 10000\] m"),
    ({"map_info": {"width": 200, "height": -5}}, r"map_info.height: value -5 is outside \[1, 10000\] m"),
    ({"map_info": {"height": 5}}, r"lacks numeric map_info.width/height"),
    ('{"map_info": {"width": 200,\n "height": }}', r"line 2, column 12: not valid JSON"),
])
def test_bad_floor_info_names_the_file_and_place(tmp_path, info, match):
    with pytest.raises(ValueError, match=r"floor_info\.json: " + match):
        ilc.load_ilc_floor_map(_floor(tmp_path, info=info))


@pytest.mark.parametrize("geo, match", [
    (_geo(outline=[[0.0, 0.0]] * 4), r"features\[0\] \(the floor outline\) spans no area"),
    (_geo(outline=[[0.0, 0.0], [float("nan"), 0.0], [0.001, 0.001], [0.0, 0.001]]),
     r"features\[0\]\.geometry\.coordinates\[0\]\[1\], column 0 \(longitude\): value nan is outside \[-180, 180\]"),
    (_geo(obstacles=[[[0.0, 0.0], [0.0, 95.0], [0.001, 0.0]]]),
     r"features\[1\]\.geometry\.coordinates\[0\]\[1\], column 1 \(latitude\): value 95 is outside \[-90, 90\] deg"),
    (_geo(outline=[[0.0, 0.0], [1.0, 1.0]]),
     r"features\[0\]\.geometry\.coordinates\[0\]: a ring needs at least 3 \[lon, lat\] points"),
    ({"features": [{"geometry": {"type": "Point", "coordinates": [0, 0]}}]},
     r"features\[0\]\.geometry: unsupported geometry type 'Point'"),
])
def test_bad_geojson_names_the_file_and_place(tmp_path, geo, match):
    with pytest.raises(ValueError, match=r"geojson_map\.json: " + match):
        ilc.load_ilc_floor_map(_floor(tmp_path, geo=geo))


# ------------------------------------------------------------------------------- floor archive

def _tar_xz(tmp_path, members: dict, name="site_F4.tar.xz") -> bytes:
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w:xz") as tf:
        for k, v in members.items():
            ti = tarfile.TarInfo(k)
            ti.size = len(v)
            tf.addfile(ti, io.BytesIO(v))
    return buf.getvalue()


def test_corrupt_floor_archive_names_archive(tmp_path):
    members = {"F4/path_data_files/a.txt": GOOD.encode(), "F4/floor_info.json": json.dumps(INFO).encode(),
               "F4/geojson_map.json": json.dumps(_geo()).encode()}
    data = _tar_xz(tmp_path, members)
    ok = _write(tmp_path, data, "ok.tar.xz")
    assert ilc.load_ilc_floor(ok).names == ["a"]
    cut = _write(tmp_path, data[: len(data) // 2], "cut.tar.xz")
    with pytest.raises(ValueError, match=r"cut\.tar\.xz(:F4/\S+)?: corrupt or truncated archive"):
        ilc.load_ilc_floor(cut)
    with pytest.raises(ValueError, match=r"junk\.tar\.xz: corrupt or truncated archive"):
        ilc.list_ilc_traces(_write(tmp_path, b"not an archive at all", "junk.tar.xz"))


def test_bad_trace_inside_archive_names_archive_member_and_line(tmp_path):
    members = {"F4/path_data_files/a.txt": GOOD.replace("\t-50\t", "\t50\t").encode(),
               "F4/floor_info.json": json.dumps(INFO).encode(), "F4/geojson_map.json": json.dumps(_geo()).encode()}
    p = _write(tmp_path, _tar_xz(tmp_path, members), "f.tar.xz")
    with pytest.raises(ValueError, match=r"f\.tar\.xz:F4/path_data_files/a\.txt: line 11, column 5 \(rssi\)"):
        ilc.load_ilc_floor(p)


# ------------------------------------------------------------------------------ degenerate walks

@pytest.mark.parametrize("drop, match", [
    ("TYPE_WAYPOINT", r"the walk has 0 waypoints"),
    ("1100\tTYPE_WAYPOINT", r"the walk has 1 waypoint \(TYPE_WAYPOINT records\); at least 2"),
    ("TYPE_WIFI", r"the walk has no Wi-Fi scan"),
])
def test_require_walk_gives_a_sentence(tmp_path, drop, match):
    body = [b for b in BODY if drop not in b]
    tr = ilc.load_ilc_trace(_write(tmp_path, HEADER + "\n".join(body) + "\n", "small.txt"))
    with pytest.raises(ValueError, match=r"small\.txt: " + match):
        ilc.require_walk(tr, min_imu=2)
    with pytest.raises(ValueError, match=r"the walk has 2 IMU samples .* at least 50"):
        ilc.require_walk(ilc.load_ilc_trace(_write(tmp_path, GOOD, "g.txt")))


# ------------------------------------------------------------------ fast path == line by line

def _agree(data: bytes):
    fast = ilc._blocks_fast(data)
    assert fast is not None
    slow = ilc._blocks_slow(data.decode("utf-8").splitlines(), "x")
    assert fast[1] == slow[1] and list(fast[1]) == list(slow[1]) and fast[2] == slow[2]
    assert set(fast[0]) == set(slow[0])
    for k, b in slow[0].items():
        a = fast[0][k]
        np.testing.assert_array_equal(a.lines, b.lines)
        np.testing.assert_array_equal(np.asarray(a.t_ms), np.asarray(b.t_ms))
        np.testing.assert_array_equal(a.num, b.num)
        assert a.ssid == b.ssid and a.bssid == b.bssid


def test_fast_path_and_line_by_line_parser_agree_on_crafted_files():
    _agree(GOOD.encode())
    _agree(GOOD.replace("\n", "\r\n").replace("\tnet\t", "\t caf\u00e9 net\t").encode())
    big = [HEADER.rstrip("\n")]
    for i in range(25000):
        t = 1574149352216 + 20 * i
        big += [f"{t}\tTYPE_ACCELEROMETER\t{np.sin(i):.5f}\t0.2\t9.8\t2",
                f"{t}\tTYPE_GYROSCOPE_UNCALIBRATED\t1\t2\t3\t4\t5\t6\t3"]
        if i % 300 == 0:
            big.append(f"{t}\tTYPE_WIFI\tnet {i}\taa:bb:cc:dd:ee:{i % 256:02x}\t-{40 + i % 50}\t2412\t{t - 100}")
    _agree(("\n".join(big) + "\n").encode())


@pytest.mark.parametrize("old, new", [("\t0.1\t0.2\t9.8\t2", "\t0.1\tTRUE\t9.8\t2"),
                                      ("1020\tTYPE_GYRO", "1020 \tTYPE_GYRO"), ("1100\t", "11000\t"),
                                      ("\t24.0", "\t24.0\t")])
def test_odd_files_leave_the_fast_path(old, new):
    assert ilc._blocks_fast(GOOD.replace(old, new, 1).encode()) is None


def test_every_real_trace_takes_the_fast_path_and_agrees(shared_data):
    root = shared_data("ilc2020_site2_F4")
    archive = sorted(root.glob("*.tar.xz"))[0]
    with tarfile.open(archive) as tf:
        members = [m for m in tf if m.isfile() and "path_data_files" in m.name and m.name.endswith(".txt")]
        assert len(members) == 19
        for m in members:
            _agree(tf.extractfile(m).read())


@pytest.mark.parametrize("bad", ["1e03", "10.0", "1O20", "0x10"])
def test_a_time_that_is_not_digits_is_refused_even_at_the_common_width(bad):
    # pandas would read "1e03" or "10.0" in an int64 column through float; int() refuses them
    data = GOOD.replace("1020\t", bad + "\t")
    assert ilc._blocks_fast(data.encode()) is None
    with pytest.raises(ValueError, match=r"x: line 7: column 1 \(Unix time, ms\) must be an integer, got '"
                                         + bad + "'"):
        ilc.parse_ilc_trace(data, "x")


def test_a_column_of_only_true_false_words_is_refused_not_read_as_ones():
    body = [("\t".join(b.split("\t")[:4] + ["true"] + b.split("\t")[5:]) if "TYPE_WAYPOINT" not in b
             and len(b.split("\t")) == 6 else b) for b in BODY]
    data = HEADER + "\n".join(body) + "\n"
    assert ilc._blocks_fast(data.encode()) is None
    with pytest.raises(ValueError, match=r"x: line 4: TYPE_ACCELEROMETER column 5 \(z\) must be numeric, got 'true'"):
        ilc.parse_ilc_trace(data, "x")
