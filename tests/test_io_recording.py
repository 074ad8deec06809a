"""ilocalg.io.recording (the Recording type, frames, loading by content), ipin_write and ilc_write."""

import dataclasses

import numpy as np
import pandas as pd
import pytest
from pyproj import Geod

from ilocalg.io import LocalFrame, Recording, as_recording, load_recording, write_ilc_trace, write_ipin_logfile
from ilocalg.io.ipin_write import ipin_logfile_text
from ilocalg.io.recording import common_frame, recording_fingerprints, sniff_format, truth_at
from ilocalg.sim import walk_recordings as wr


@pytest.fixture(scope="module")
def walks():
    return wr.simulate_recordings(3, seed=7, n_floors=2, n_nodes=25, floor_changes=True)[1]


def test_ipin_round_trip_is_exact(walks, tmp_path):
    r = walks[1]                                   # climbs a floor half-way: floors 0 and 1 in the truth
    back = load_recording(write_ipin_logfile(r, tmp_path / "walk.txt"))
    assert back.meta["format"] == "ipin" and back.name == "walk"
    np.testing.assert_array_equal(back.imu.index.to_numpy(), r.imu.index.to_numpy())
    np.testing.assert_array_equal(back.imu[list(r.imu.columns)].to_numpy(), r.imu.to_numpy())
    pd.testing.assert_frame_equal(back.pressure, r.pressure)
    for c in ("t_s", "scan_id", "rssi_dbm", "freq_mhz"):
        np.testing.assert_array_equal(back.wifi[c].to_numpy(), r.wifi[c].to_numpy())
    assert back.wifi["bssid"].tolist() == r.wifi["bssid"].tolist()
    assert set(back.truth["floor"]) == {0.0, 1.0}
    np.testing.assert_array_equal(back.truth["floor"].to_numpy(), r.truth["floor"].to_numpy())
    # the logfile's own frame starts at its first point; moved into the simulator's frame it is the truth
    assert back.truth[["x_m", "y_m"]].iloc[0].abs().max() < 1e-9 and back.frame != r.frame
    np.testing.assert_allclose(back.in_frame(r.frame).truth[["x_m", "y_m"]].to_numpy(),
                               r.truth[["x_m", "y_m"]].to_numpy(), atol=1e-6)
    assert back.content_id == r.content_id
    assert "PRES" not in back.meta["skipped"]


def test_ilc_round_trip_keeps_values_and_content(walks, tmp_path):
    r = walks[0]
    back = load_recording(write_ilc_trace(r, tmp_path / "walk.txt"))
    assert back.meta["format"] == "ilc" and not back.frame.geographic
    np.testing.assert_array_equal(back.imu.to_numpy(), r.imu[list(back.imu.columns)].to_numpy())
    # ILC times are Unix ms: the same walk re-based, identical relative times to the millisecond
    dt = back.imu.index.to_numpy() - back.imu.index[0]
    np.testing.assert_allclose(dt, r.imu.index.to_numpy() - r.imu.index[0], atol=5e-7)
    np.testing.assert_array_equal(back.truth[["x_m", "y_m"]].to_numpy(), r.truth[["x_m", "y_m"]].to_numpy())
    assert np.isnan(back.truth["floor"]).all()            # the ILC format has no floor per waypoint
    assert back.content_id == r.content_id


def test_format_is_taken_from_the_content(walks, tmp_path):
    a = write_ipin_logfile(walks[0], tmp_path / "a.log")
    b = write_ilc_trace(walks[0], tmp_path / "b.dat")
    assert sniff_format(a) == "ipin" and sniff_format(b) == "ilc"
    ox = tmp_path / "oxford.csv"
    t = np.arange(200) * 10_000_000
    ox.write_text("\n".join(f"{ti},0.1,9.8,0.2,0,{i // 50},{i // 50}" for i, ti in enumerate(t)) + "\n")
    rec = load_recording(ox)
    assert rec.meta["format"] == "oxford" and rec.meta["true_steps"] == 3 and rec.step_t_s.size == 3
    assert len(rec.truth) == 0 and list(rec.imu.columns) == ["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]
    dup = tmp_path / "dup.csv"
    rows = ox.read_text().splitlines()
    dup.write_text("\n".join(rows[:10] + [rows[9]] + rows[10:]) + "\n")       # a repeated timestamp
    with pytest.raises(ValueError, match="duplicate"):
        load_recording(dup)
    kept = load_recording(dup, duplicate_timestamps="drop")      # the loader's policy, passed through
    assert kept.meta["skipped"] == {"duplicate timestamps": 1} and len(kept.imu) == 200
    junk = tmp_path / "junk.txt"
    junk.write_text("hello\nworld\n")
    with pytest.raises(ValueError, match="junk.txt: cannot tell the format.*pass format="):
        load_recording(junk)
    with pytest.raises(ValueError, match="format must be one of"):
        load_recording(a, format="csv")


def test_geographic_frame_agrees_with_geodesic_distances():
    f = LocalFrame.at(48.137, 11.575)
    rng = np.random.default_rng(0)
    lat = 48.137 + rng.uniform(-0.005, 0.005, 50)
    lon = 11.575 + rng.uniform(-0.005, 0.005, 50)
    xy = f.to_xy(lat, lon)
    _, _, dist = Geod(ellps="WGS84").inv(np.full(50, 11.575), np.full(50, 48.137), lon, lat)
    np.testing.assert_allclose(np.hypot(*xy.T), dist, rtol=1e-9)      # azimuthal equidistant: exact from the origin
    np.testing.assert_allclose(f.to_latlon(*xy.T), np.column_stack([lat, lon]), atol=1e-11)
    with pytest.raises(ValueError, match="latitude in"):
        LocalFrame.at(91.0, 0.0)


def test_walks_of_several_logfiles_share_one_frame(walks, tmp_path):
    """Each IPIN logfile starts x/y at its own first point; pooled, they agree with the simulator's frame."""
    recs = [load_recording(write_ipin_logfile(r, tmp_path / f"{r.name}.txt")) for r in walks]
    starts = {(round(float(w.truth["x_m"].iloc[0]), 6), round(float(w.truth["y_m"].iloc[0]), 6)) for w in walks}
    assert len({r.frame for r in recs}) == len(starts) >= 2    # one frame per distinct first point
    frame = common_frame(recs)
    rf = recording_fingerprints(recs)
    assert rf.frame == frame == recs[0].frame
    ref = recording_fingerprints(walks)                       # the simulator's own frame
    moved = frame.to_latlon(*rf.fingerprints.xy_m.T)
    np.testing.assert_allclose(walks[0].frame.to_xy(*moved.T), ref.fingerprints.xy_m, atol=1e-6)
    np.testing.assert_array_equal(rf.fingerprints.floor, ref.fingerprints.floor)
    ilc = load_recording(write_ilc_trace(walks[0], tmp_path / "x.ilc"))
    with pytest.raises(ValueError, match="do not convert"):
        common_frame([recs[0], ilc])


def test_fingerprints_are_the_interpolated_truth(walks):
    r = walks[1]
    rf = recording_fingerprints([r])
    fp = rf.fingerprints
    xy, fl = truth_at(r.truth, fp.meta["t_s"].to_numpy())
    np.testing.assert_array_equal(fp.xy_m, xy)
    np.testing.assert_array_equal(fp.floor, fl)
    n_scans = r.wifi["scan_id"].nunique()
    assert fp.n_samples == n_scans and rf.n_outside == 0
    late = dataclasses.replace(r, truth=r.truth.iloc[2:].reset_index(drop=True))     # truth starts later
    rl = recording_fingerprints([late])
    n_before = int((r.wifi.groupby("scan_id")["t_s"].first() < late.truth["t_s"].iloc[0]).sum())
    assert n_before >= 1 and rl.n_outside == n_before and rl.fingerprints.n_samples == n_scans - n_before
    with pytest.raises(ValueError, match="outside the ground-truth time span.*outside='drop'"):
        recording_fingerprints([late], outside="error")
    # floor between two points: the earlier point's
    tr = pd.DataFrame({"t_s": [0.0, 10.0], "x_m": [0.0, 10.0], "y_m": [0.0, 0.0], "floor": [0.0, 1.0]})
    xy, fl = truth_at(tr, [5.0, 10.0, 11.0])
    np.testing.assert_array_equal(fl[:2], [0.0, 1.0]) and np.testing.assert_array_equal(xy[0], [5.0, 0.0])
    assert np.isnan(xy[2]).all() and np.isnan(fl[2])
    with pytest.raises(ValueError, match="outside the ground-truth time span"):
        truth_at(tr, [11.0], outside="error")


def test_writer_refuses_what_the_format_cannot_hold(walks):
    r = walks[0]
    mapped = dataclasses.replace(r, frame=LocalFrame("floor plan"),
                                 truth=r.truth.drop(columns=["lat_deg", "lon_deg"]))
    with pytest.raises(ValueError, match=r"pass origin=\(lat_deg, lon_deg\)"):
        ipin_logfile_text(mapped)
    text = ipin_logfile_text(mapped, origin=(24.0, 121.0))
    assert text.count("\nPOSI;") == len(r.truth)
    nofloor = dataclasses.replace(r, truth=r.truth.assign(floor=np.nan))
    with pytest.raises(ValueError, match="floor_if_unknown"):
        ipin_logfile_text(nofloor)
    with pytest.raises(ValueError, match="need the frequency; the Wi-Fi scans lack 'freq_mhz'"):
        ipin_logfile_text(dataclasses.replace(r, wifi=r.wifi.drop(columns=["freq_mhz"])))


def test_recording_checks_its_parts(walks):
    r = walks[0]
    with pytest.raises(ValueError, match="ground truth lacks the column"):
        dataclasses.replace(r, truth=r.truth.drop(columns=["floor"]))
    with pytest.raises(ValueError, match="strictly increasing"):
        dataclasses.replace(r, truth=r.truth.iloc[::-1].reset_index(drop=True))
    with pytest.raises(ValueError, match="not a walk recording"):
        as_recording(object())
    assert as_recording(r) is r and isinstance(r, Recording)
    assert r.has_floors and not dataclasses.replace(r, truth=r.truth.assign(floor=np.nan)).has_floors


def test_pressure_records_are_read_and_checked(walks, tmp_path):
    p = write_ipin_logfile(walks[1], tmp_path / "w.txt")
    lines = p.read_text().splitlines()
    i = next(k for k, ln in enumerate(lines) if ln.startswith("PRES;"))
    lines[i] = "PRES;1.0;1.0;abc;3"
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=rf"w.txt: line {i + 1}: PRES expects"):
        load_recording(p)
