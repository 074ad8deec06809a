"""Tests of ilocalg.io.ilc (real ILC 2.0 site2/F4 archive + crafted bad inputs) and ilocalg.io.summaries."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from ilocalg.io import ilc, summaries
from ilocalg.io.schema import ACC_COLS, IMU_COLS, MAG_COLS

HEADER = (
    "#\tstartTime:1574149352216\n"
    "#\tSiteID:site\tSiteName:mall\tFloorId:fl\tFloorName:F4\n"
    "#\tBrand:OPPO\tModel:PBCM10\tAndroidName:8.1.0\tAPILevel:27\t\n"
    "#\ttype:1\tname:BMI160 Accelerometer\tvendor:BOSCH\n"
)


def _good_lines():
    lines = ["1000\tTYPE_WAYPOINT\t10.0\t20.0"]
    for k in range(5):
        t = 1000 + 20 * k
        lines += [f"{t}\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t2",
                  f"{t}\tTYPE_MAGNETIC_FIELD\t20.0\t-5.0\t-30.0\t3",
                  f"{t}\tTYPE_GYROSCOPE\t0.01\t0.02\t0.03\t3",
                  f"{t}\tTYPE_ROTATION_VECTOR\t0.1\t0.0\t0.5\t3",
                  f"{t}\tTYPE_GYROSCOPE_UNCALIBRATED\t1\t2\t3\t4\t5\t6\t3"]
    lines += ["1050\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:01\t-50\t2412\t1040",
              "1050\tTYPE_WIFI\t\taa:bb:cc:dd:ee:02\t-70\t5180\t1045",
              "1090\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:01\t-52\t2412\t1085",
              "1060\tTYPE_BEACON\tUUID\t1\t2\t-65\t-82\t5.5\t6B:11:4C:D1:29:F2\t1060",
              "1070\tTYPE_SOMETHING_NEW\t1",
              "1100\tTYPE_WAYPOINT\t13.0\t24.0"]
    return lines


def _write(tmp_path, lines, name="t.txt", header=HEADER):
    p = tmp_path / name
    p.write_text(header + "\n".join(lines) + "\n", encoding="utf-8")
    return p


# ---------------------------------------------------------------------------- crafted good file

def test_crafted_trace_parses_every_kept_record(tmp_path):
    tr = ilc.load_ilc_trace(_write(tmp_path, _good_lines()))
    assert set(tr.imu.columns) == set(IMU_COLS)
    assert tr.imu.index.name == "t_s"
    np.testing.assert_allclose(tr.imu.index.to_numpy(), 1.0 + 0.02 * np.arange(5))
    np.testing.assert_allclose(tr.imu["mag_z_ut"].to_numpy(), -30.0)
    assert tr.rotation_vector.shape == (5, 3)
    assert tr.wifi["scan_id"].tolist() == [0, 0, 1]
    assert tr.wifi["rssi_dbm"].tolist() == [-50.0, -70.0, -52.0]
    assert tr.wifi["freq_mhz"].tolist() == [2412.0, 5180.0, 2412.0]
    assert tr.n_scans == 2
    np.testing.assert_allclose(tr.waypoints[["t_s", "x_m", "y_m"]].to_numpy(), [[1.0, 10, 20], [1.1, 13, 24]])
    assert tr.kept == {"TYPE_WAYPOINT": 2, "TYPE_ACCELEROMETER": 5, "TYPE_MAGNETIC_FIELD": 5,
                       "TYPE_GYROSCOPE": 5, "TYPE_ROTATION_VECTOR": 5, "TYPE_WIFI": 3}
    assert tr.skipped == {"TYPE_GYROSCOPE_UNCALIBRATED": 5, "TYPE_BEACON": 1, "TYPE_SOMETHING_NEW": 1}
    assert tr.header["Model"] == "PBCM10" and tr.header["FloorName"] == "F4"
    assert tr.header["sensors"][0]["vendor"] == "BOSCH"


def test_summaries_on_crafted_trace(tmp_path):
    tr = ilc.load_ilc_trace(_write(tmp_path, _good_lines()))
    s = summaries.trace_summary(tr)
    assert s["imu_rate_hz"] == pytest.approx(50.0)
    assert s["walk_length_m"] == pytest.approx(5.0)
    assert s["mean_speed_mps"] == pytest.approx(50.0)
    assert s["aps_per_scan_median"] == pytest.approx(1.5) and s["aps_per_scan_max"] == 2
    assert s["n_bssids"] == 2 and s["n_skipped"] == 7


# ---------------------------------------------------------------------------- crafted bad files

@pytest.mark.parametrize("mutate, match", [
    (lambda L: L[:1] + ["1000\tTYPE_ACCELEROMETER\t0.1\t0.2"] + L[1:], r"line 6: TYPE_ACCELEROMETER expects 4 values"),
    (lambda L: L[:1] + ["1000\tTYPE_ACCELEROMETER\t0.1\tabc\t9.8\t2"] + L[1:],
     r"line 6: TYPE_ACCELEROMETER column 4 \(y\) must be numeric, got 'abc'"),
    (lambda L: ["10x0\tTYPE_WAYPOINT\t1\t2"] + L, r"line 5: column 1 \(Unix time, ms\) must be an integer"),
    (lambda L: ["1000"] + L, r"line 5: expected at least 2 tab-separated columns"),
    (lambda L: L + ["1100\tTYPE_WAYPOINT\t1\t2"], r"duplicate TYPE_WAYPOINT timestamp 1100"),
    (lambda L: L + ["1000\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:03\t-50\t2412\t1040"],
     r"TYPE_WIFI timestamp 1000 before 1090"),
    (lambda L: L + ["1090\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:01\t-50\t2412\t1040"],
     r"bssid 'aa:bb:cc:dd:ee:01' appears twice.*keep_latest"),
    (lambda L: L + ["1090\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:09\t-50\t2412"], r"TYPE_WIFI expects 5 values"),
])
def test_bad_lines_raise_naming_file_and_line(tmp_path, mutate, match):
    p = _write(tmp_path, mutate(_good_lines()), name="bad.txt")
    with pytest.raises(ValueError, match=match) as e:
        ilc.load_ilc_trace(p)
    assert "bad.txt" in str(e.value)


def test_unsorted_and_duplicate_sensor_timestamps_raise(tmp_path):
    lines = _good_lines()
    i = lines.index("1040\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t2")
    lines[i] = "1020\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t2"
    with pytest.raises(ValueError, match=r"line \d+: duplicate TYPE_ACCELEROMETER timestamp 1020"):
        ilc.load_ilc_trace(_write(tmp_path, lines))
    lines[i] = "1010\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t2"
    with pytest.raises(ValueError, match=r"decreasing TYPE_ACCELEROMETER timestamp 1010 after 1020"):
        ilc.load_ilc_trace(_write(tmp_path, lines))


def test_misaligned_imu_sensors_raise(tmp_path):
    lines = [ln for ln in _good_lines() if not ln.startswith("1080\tTYPE_GYROSCOPE\t")]
    with pytest.raises(ValueError, match="TYPE_GYROSCOPE timestamps differ from TYPE_ACCELEROMETER.*does not interp"):
        ilc.load_ilc_trace(_write(tmp_path, lines))


def test_empty_and_header_only_files_raise(tmp_path):
    p = tmp_path / "empty.txt"
    p.write_text("", encoding="utf-8")
    with pytest.raises(ValueError, match="empty.txt: no data records"):
        ilc.load_ilc_trace(p)
    with pytest.raises(ValueError, match="no data records"):
        ilc.load_ilc_trace(_write(tmp_path, [], name="h.txt"))


def test_duplicate_bssid_keep_latest_is_counted(tmp_path):
    lines = _good_lines() + ["1090\tTYPE_WIFI\t\taa:bb:cc:dd:ee:01\t-60\t2412\t1000"]
    tr = ilc.load_ilc_trace(_write(tmp_path, lines), duplicate_bssid="keep_latest")
    assert tr.n_duplicate_bssid_dropped == 1
    assert tr.skipped["TYPE_WIFI duplicate bssid"] == 1 and tr.kept["TYPE_WIFI"] == 3
    last = tr.wifi[tr.wifi.scan_id == 1]
    assert last["rssi_dbm"].tolist() == [-52.0]  # the record with the latest last-seen time
    with pytest.raises(ValueError, match="duplicate_bssid must be one of"):
        ilc.load_ilc_trace(_write(tmp_path, lines), duplicate_bssid="drop")


def test_points_in_polygon_and_bad_ring():
    sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    assert ilc.points_in_polygon([1, 3, 1.9], [1, 1, 0.1], sq).tolist() == [True, False, True]
    with pytest.raises(ValueError, match="ring must have shape"):
        ilc.points_in_polygon(0, 0, sq[:2])


# ---------------------------------------------------------------------------- the real archive

@functools.lru_cache(maxsize=1)
def _floor(root):
    return ilc.load_ilc_floor(root, duplicate_bssid="keep_latest", relisted_wifi="keep")


def test_real_archive_all_19_traces_load(shared_data):
    root = shared_data("ilc2020_site2_F4")
    names = ilc.list_ilc_traces(root)
    assert len(names) == 19
    floor = _floor(str(root))
    assert floor.names == names
    assert sum(len(t.waypoints) for t in floor.traces.values()) == 125
    for tr in floor.traces.values():
        assert 2 <= len(tr.waypoints) <= 18
        assert tr.header["Model"] == "PBCM10" and tr.header["FloorName"] == "F4"
        assert summaries.sample_rate_hz(tr.imu.index) == pytest.approx(50.0, rel=0.02)
        assert set(tr.imu.columns) == set(IMU_COLS)
        # gravity magnitude of a phone held flat, and Earth field strength in microtesla
        g = np.linalg.norm(tr.imu[list(ACC_COLS)].to_numpy(), axis=1)
        assert 9.0 < np.mean(g) < 11.0
        b = np.linalg.norm(tr.imu[list(MAG_COLS)].to_numpy(), axis=1)
        assert 20.0 < np.median(b) < 80.0
        assert tr.wifi["rssi_dbm"].between(-100, -10).all()
        assert tr.skipped.get("TYPE_ACCELEROMETER_UNCALIBRATED", 0) == len(tr.imu)
    # the duplicate-BSSID policy was needed: 75 records in 6 traces, all counted
    dropped = {k: t.n_duplicate_bssid_dropped for k, t in floor.traces.items() if t.n_duplicate_bssid_dropped}
    assert len(dropped) == 6 and sum(dropped.values()) == 75


def test_real_archive_default_policy_refuses_duplicates(shared_data):
    root = shared_data("ilc2020_site2_F4")
    with pytest.raises(ValueError, match=r"5dd3ac5f44333f00067aa66a.txt: line \d+: TYPE_WIFI bssid"):
        ilc.load_ilc_floor(root, names=["5dd3ac5f44333f00067aa66a"])
    tr = ilc.load_ilc_floor(root, names=["5dd3a32544333f00067aa5ab"], relisted_wifi="keep").traces[
        "5dd3a32544333f00067aa5ab"]
    assert tr.n_duplicate_bssid_dropped == 0 and len(tr.waypoints) == 14


def test_real_floor_map_contains_every_waypoint(shared_data):
    root = shared_data("ilc2020_site2_F4")
    floor = _floor(str(root))
    fm = floor.floor_map
    assert fm.width_m == pytest.approx(236.71181214) and fm.height_m == pytest.approx(219.7467648)
    assert len(fm.obstacles) == 328
    xy = np.concatenate([t.waypoints[["x_m", "y_m"]].to_numpy() for t in floor.traces.values()])
    assert fm.walkable(xy[:, 0], xy[:, 1]).all()
    # a point outside the floor rectangle, and obstacle centroids inside their obstacle, are not walkable
    assert not fm.walkable(-5.0, -5.0)
    cents = np.array([ob[:-1].mean(axis=0) for ob in fm.obstacles])
    own = np.array([ilc.points_in_polygon(c[0], c[1], ob) for c, ob in zip(cents, fm.obstacles, strict=True)])
    assert own.sum() > 100
    assert not fm.walkable(cents[own, 0], cents[own, 1]).any()


def test_real_floor_summary(shared_data):
    floor = _floor(str(shared_data("ilc2020_site2_F4")))
    df = summaries.floor_summary(floor.traces)
    assert len(df) == 20 and df["trace"].iloc[-1] == "total"
    tot = df.iloc[-1]
    assert tot["n_waypoints"] == 125
    assert tot["imu_rate_hz"] == pytest.approx(50.0, rel=0.01)
    assert 50 < tot["aps_per_scan_median"] < 400
    assert 1.5 < tot["scan_interval_s"] < 6.0
    assert 0.5 < tot["mean_speed_mps"] < 2.0  # walking speed
    assert tot["n_bssids"] < df["n_bssids"].iloc[:-1].sum()


def test_folder_missing_raises(tmp_path):
    with pytest.raises(ValueError, match="no such ILC folder"):
        ilc.load_ilc_floor(tmp_path / "nope")
    with pytest.raises(ValueError, match="expected path_data_files/ or exactly one"):
        ilc.list_ilc_traces(tmp_path)


# ---------------------------------------------------------------------------- waypoint interpolation, fingerprints

def test_interpolate_waypoints(tmp_path):
    tr = ilc.load_ilc_trace(_write(tmp_path, _good_lines()))
    xy = ilc.interpolate_waypoints(tr.waypoints, [1.0, 1.05, 1.1])
    np.testing.assert_allclose(xy, [[10, 20], [11.5, 22], [13, 24]])
    with pytest.raises(ValueError, match=r"t_s\[1\] = 1.2 is outside the waypoint time span"):
        ilc.interpolate_waypoints(tr.waypoints, [1.05, 1.2])
    assert np.isnan(ilc.interpolate_waypoints(tr.waypoints, [0.9], outside="nan")).all()


def test_fingerprints_from_crafted_trace(tmp_path):
    tr = ilc.load_ilc_trace(_write(tmp_path, _good_lines()))
    fp = ilc.ilc_fingerprints([tr])
    f = fp.fingerprints
    assert f.n_samples == 2 and f.ap_ids == ("aa:bb:cc:dd:ee:01", "aa:bb:cc:dd:ee:02")
    np.testing.assert_allclose(f.rssi_dbm, [[-50, -70], [-52, np.nan]])
    np.testing.assert_allclose(f.xy_m, [[11.5, 22.0], [12.7, 23.6]])
    # AP 02 was last seen 5 ms before its scan, AP 01 10 ms and 5 ms before
    old = ilc.ilc_fingerprints([tr], max_age_s=0.007)
    assert old.n_stale_dropped == 1
    assert np.isnan(old.fingerprints.rssi_dbm[0, 0]) and old.fingerprints.rssi_dbm[0, 1] == -70


def test_fingerprints_outside_policy_on_real_walks(shared_data):
    floor = _floor(str(shared_data("ilc2020_site2_F4")))
    with pytest.raises(ValueError, match="outside the waypoint time span.*outside='drop'"):
        ilc.ilc_fingerprints(floor.traces)
    fp = ilc.ilc_fingerprints(floor.traces, outside="drop")
    assert len(fp.scans) == 268 and fp.n_outside == 9
    assert fp.fingerprints.n_samples == 268 - 9 == fp.scans["used"].sum()
    assert floor.floor_map.walkable(fp.fingerprints.x_m, fp.fingerprints.y_m).mean() > 0.9
    heard = np.isfinite(fp.fingerprints.rssi_dbm).sum(axis=1)
    assert (heard >= 1).all() and np.median(heard) > 50


def test_walkable_is_the_union_of_outline_rings_minus_obstacles():
    """The rule of the walkable raster (OccupancyGrid.from_polygons): overlapping outline rings add up."""
    a = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    b = a + [5.0, 0.0]
    hole = np.array([[12, 2], [14, 2], [14, 4], [12, 4]], float)
    fm = ilc.IlcFloorMap(width_m=15.0, height_m=10.0, outline=(a, b), obstacles=(hole,), lonlat_bbox=(0, 0, 1, 1))
    assert fm.walkable([2, 7, 12, 13, 16], [5, 5, 5, 3, 5]).tolist() == [True, True, True, False, False]
