import tarfile

import numpy as np
import pandas as pd
import pytest

from ilocalg.io import oxford


def _write_recording(folder, n=400, rate=100.0, feet=None, row_ns=400_000_000):
    folder.mkdir(parents=True)
    t_ns = (1_000_000_000 + np.arange(n) * 1e9 / rate).astype(np.int64)
    acc = np.column_stack([np.zeros(n), np.zeros(n), 9.8 + np.sin(np.arange(n) / 10.0)])
    with open(folder / "accelerometer.csv", "w") as fh:
        for k in range(n):
            fh.write(f"{t_ns[k]},3,{acc[k, 0]},{acc[k, 1]},{acc[k, 2]}\n")
    feet = feet if feet is not None else [(1, 1), (0, 1), (1, 1), (1, 0), (1, 1), (0, 1), (1, 1)]
    with open(folder / "stepcounter.csv", "w") as fh:
        for k, (left, right) in enumerate(feet):
            fh.write(f"{t_ns[0] + (k + 1) * row_ns},{left},{right}\n")
    return t_ns


def test_folder_layout(tmp_path):
    d = tmp_path / "Pixel_Jamie_Hard_InHand_1"
    t_ns = _write_recording(d)
    rec = oxford.load_oxford_step_counter(d)
    assert rec.name == d.name and rec.meta["position"] == "InHand" and rec.meta["phone"] == "Pixel"
    assert rec.imu.index.name == "t_s" and rec.imu.index[0] == 0.0
    assert list(rec.imu.columns) == ["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]
    # 0->1 transitions: left at rows 3, 7 (1-based 3rd, 7th), right at row 5
    assert rec.true_steps == 3
    np.testing.assert_allclose(rec.step_t_s, (np.array([3, 5, 7]) * 0.4e9 + t_ns[0] - t_ns[0]) / 1e9)
    assert rec.hardware_steps is None


def test_archive_layout(tmp_path):
    for name in ("Samsung_Dario_Hard_ArmBand_1", "Nexus_Jamie_Hard_InHand_2"):
        _write_recording(tmp_path / "data" / name)
    arc = tmp_path / "opt.tar.xz"
    with tarfile.open(arc, "w:xz") as tf:
        tf.add(tmp_path / "data", arcname="data")
    assert oxford.list_oxford_archive(arc) == ["Nexus_Jamie_Hard_InHand_2", "Samsung_Dario_Hard_ArmBand_1"]
    rec = oxford.load_oxford_step_counter(arc, "Samsung_Dario_Hard_ArmBand_1")
    assert rec.meta["position"] == "Armband" and rec.true_steps == 3
    assert len(oxford.load_oxford_archive(arc)) == 2
    held = oxford.load_oxford_archive(arc, select=lambda n: "_InHand_" in n)  # one pass, filtered by name
    named = oxford.load_oxford_archive(arc, ["Nexus_Jamie_Hard_InHand_2"])
    assert [r.name for r in held] == ["Nexus_Jamie_Hard_InHand_2"]
    pd.testing.assert_frame_equal(held[0].imu, named[0].imu)
    np.testing.assert_array_equal(held[0].step_t_s, named[0].step_t_s)
    with pytest.raises(ValueError, match="that the selection keeps"):
        oxford.load_oxford_archive(arc, select=lambda n: False)
    with pytest.raises(ValueError, match="names or select"):
        oxford.load_oxford_archive(arc, ["Nexus_Jamie_Hard_InHand_2"], select=bool)
    with pytest.raises(ValueError, match="pass member"):
        oxford.load_oxford_step_counter(arc)
    with pytest.raises(ValueError, match="no recording 'nope'"):
        oxford.load_oxford_step_counter(arc, "nope")


def test_validation_csv(tmp_path):
    n = 300
    t_ns = 5_000_000_000 + np.arange(n) * 10_000_000
    true = np.floor(np.arange(n) / 50).astype(int)           # a step every 0.5 s
    hw = 100 + np.floor(np.arange(n) / 51).astype(int)
    df = pd.DataFrame({"t": t_ns, "x": 0.1, "y": 0.2, "z": 9.8, "app": 0, "true": true, "hw": hw})
    p = tmp_path / "walk.csv"
    df.to_csv(p, header=False, index=False)
    rec = oxford.load_oxford_step_counter(p)
    assert rec.true_steps == true[-1] == 5
    np.testing.assert_allclose(rec.step_t_s, np.arange(1, 6) * 0.5)
    assert rec.hardware_steps == hw[-1] - hw[0]


def test_bad_input_names_file_line_column(tmp_path):
    d = tmp_path / "rec"
    _write_recording(d)
    acc = d / "accelerometer.csv"
    lines = acc.read_text().splitlines()
    lines[4] = lines[4].replace(",3,", ",3,abc,", 1).rsplit(",", 1)[0]
    acc.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"accelerometer.csv: line 5, column 3 \(ax_mps2\): not a number: 'abc'"):
        oxford.load_oxford_step_counter(d)
    lines = acc.read_text().splitlines()
    lines[4] = lines[3]
    acc.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"line 5, column 1 \(timestamp_ns\): duplicate timestamp"):
        oxford.load_oxford_step_counter(d)
    lines[4] = "1,3,0,0,9.8"
    acc.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="line 5, column 1.*decreasing"):
        oxford.load_oxford_step_counter(d)
    lines[4] = "1,3,0,0"
    acc.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="line 5 has 4 columns, expected 5"):
        oxford.load_oxford_step_counter(d)
    d2 = tmp_path / "rec2"
    _write_recording(d2, feet=[(0, 0), (2, 0)])
    with pytest.raises(ValueError, match=r"stepcounter.csv: line 2, column 2 \(left_foot\): foot state must be 0 or 1"):
        oxford.load_oxford_step_counter(d2)
    (d2 / "stepcounter.csv").unlink()
    with pytest.raises(ValueError, match="lacks stepcounter.csv"):
        oxford.load_oxford_step_counter(d2)
    with pytest.raises(ValueError, match="no such file"):
        oxford.load_oxford_step_counter(tmp_path / "missing")
    bad = tmp_path / "v.csv"
    bad.write_text("1,0,0,9.8,0,0,0\n2,0,0,9.8,0,1,0\n3,0,0,9.8,0,0,0\n")
    with pytest.raises(ValueError, match=r"line 3, column 6 \(true_count\): cumulative count decreases"):
        oxford.load_oxford_step_counter(bad)
    empty = tmp_path / "e.csv"
    empty.write_text("")
    with pytest.raises(ValueError, match="empty"):
        oxford.load_oxford_step_counter(empty)


def test_heel_bounce_policy_counts_what_it_merges(tmp_path):
    # readings every 0.1 s: the left foot lands (row 2), lifts for one reading and lands again 0.2 s after its
    # landing (row 4: a bounce, < MIN_STRIDE_S), lifts and lands 0.8 s after (row 10: a step); the right foot
    # lands once
    feet = [(0, 0), (1, 0), (0, 0), (1, 0), (0, 0), (0, 1), (0, 1), (0, 0), (0, 0), (1, 0)]
    d = tmp_path / "Pixel_Jamie_Hard_Armband_1"
    _write_recording(d, feet=feet, row_ns=100_000_000)
    keep = oxford.load_oxford_step_counter(d)
    merge = oxford.load_oxford_step_counter(d, heel_bounces="merge")
    assert keep.true_steps == 4 and keep.n_heel_bounces == 1 and keep.n_heel_bounces_merged == 0
    assert merge.true_steps == 3 and merge.n_heel_bounces == 1 and merge.n_heel_bounces_merged == 1
    np.testing.assert_allclose(merge.step_t_s, np.setdiff1d(keep.step_t_s, [keep.step_t_s[1]]))
    # landings exactly min_stride_s apart are two steps; a bounce is timed from the last KEPT landing (0.7 s is 0.6 s
    # after the kept 0.1 s landing: a step, though only 0.2 s after the bounce at 0.5 s)
    t_ns = np.array([0.0, 0.1, 0.2, 0.6]) * 1e9
    assert not oxford.heel_bounces_mask(t_ns, np.array([[0, 0], [1, 0], [0, 0], [1, 0]]), min_stride_s=0.5).any()
    t_ns = np.arange(8) * 1e8
    m = oxford.heel_bounces_mask(t_ns, np.array([[0, 0], [1, 0], [0, 0], [1, 0], [0, 0], [1, 0], [0, 0], [1, 0]]))
    assert m[:, 0].tolist() == [False, False, True, False, True, False, False] and not m[:, 1].any()
    with pytest.raises(ValueError, match="heel_bounces must be one of"):
        oxford.load_oxford_step_counter(d, heel_bounces="drop")
    with pytest.raises(ValueError, match="min_stride_s"):
        oxford.heel_bounces_mask(np.arange(3.0), np.zeros((3, 2)), min_stride_s=0.0)


def test_unpaired_landings_are_counted_not_added(tmp_path):
    # the left foot lands at 0.8 s and again at 1.6 s with no right landing between (a stride apart: not a
    # bounce): one right landing went unregistered; the truth keeps the 3 landings it has
    d = tmp_path / "Pixel_Jamie_Hard_InHand_1"
    _write_recording(d, feet=[(0, 0), (1, 0), (0, 0), (1, 0), (0, 0), (0, 1)])
    for policy in ("keep", "merge"):
        rec = oxford.load_oxford_step_counter(d, heel_bounces=policy)
        assert rec.true_steps == 3 and rec.n_unpaired_landings == 1 and rec.n_heel_bounces == 0


_CACHE = {}


@pytest.fixture
def real_recordings(shared_data):
    p = shared_data("oxford_step_counter")
    if p not in _CACHE:            # load the archive once for the tests below
        _CACHE[p] = oxford.load_oxford_archive(p / "optimisation_data.tar.xz")
    return p, _CACHE[p]


def test_real_archive_matches_its_stats(real_recordings):
    p, recs = real_recordings
    stats = pd.read_csv(p / "optimisation_stats.csv", skipinitialspace=True)
    stats.columns = [c.strip("# ").strip() for c in stats.columns]
    want = dict(zip(stats["dir"].str.strip(), stats["steps"], strict=True))
    assert len(recs) == 48
    assert {r.name: r.true_steps for r in recs} == want
    for r in recs:
        assert r.imu.index.is_monotonic_increasing and len(r.step_t_s) == r.true_steps
        assert 0 <= r.step_t_s[0] and r.step_t_s[-1] <= r.imu.index[-1] + 1.0


def test_real_heel_bounces_counted_both_ways(real_recordings):
    p, recs = real_recordings
    assert sum(r.n_heel_bounces for r in recs) == 107 and sum(r.n_heel_bounces > 0 for r in recs) == 21
    assert all(r.n_heel_bounces_merged == 0 for r in recs)          # the default keeps the published truth
    assert sum(r.n_unpaired_landings for r in recs) == 60 and sum(r.n_unpaired_landings > 0 for r in recs) == 20
    names = ["Pixel_Jamie_Hard_Armband_1", "Pixel_Jamie_Hard_SwingingArm_1", "Samsung_Dario_Hard_InHand_1"]
    merged = oxford.load_oxford_archive(p / "optimisation_data.tar.xz", names, heel_bounces="merge")
    kept = {r.name: r for r in recs}
    for m in merged:
        k = kept[m.name]
        assert m.n_heel_bounces == m.n_heel_bounces_merged == k.n_heel_bounces
        assert m.true_steps == k.true_steps - k.n_heel_bounces == len(m.step_t_s)
        assert set(np.round(m.step_t_s, 9)) <= set(np.round(k.step_t_s, 9))
    assert [m.n_heel_bounces for m in merged] == [13, 20, 0]


def test_real_robust_detector_accuracy(real_recordings):
    from ilocalg.workflow.commands.evaluate_steps import count

    _, recs = real_recordings
    acc = np.array([1 - abs(count(r, "robust") - r.true_steps) / r.true_steps for r in recs[::4]])
    assert acc.mean() > 0.975 and acc.min() > 0.9
