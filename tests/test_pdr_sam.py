import numpy as np
import pandas as pd
import pytest

from ilocalg.pdr import sam
from ilocalg.sim import gait


@pytest.fixture(scope="module")
def walks():
    # the detector's mechanics on walkers with one fixed waveform each (the assumed world): with the measured
    # step-to-step scatter, a walker's own min/max ranges no longer cover its next walk (notebook 03 shows it)
    ws = gait.make_walkers(4, 11, world="assumed")
    rng = np.random.default_rng(5)
    cfg = gait.gait_config("assumed")
    train = [gait.simulate_walk(gait.straight_route(80.0), w, rng, cfg, n_steps=100) for w in ws]
    test = [gait.simulate_walk(gait.straight_route(80.0), w, rng, cfg, n_steps=100) for w in ws]
    return train, test


def _acc(sw):
    return sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy(), sw.imu.index.to_numpy()


def test_vertical_component_of_pure_vertical_motion():
    t = np.arange(200) / 50.0
    up = 2.0 * np.sin(2 * np.pi * 2 * t)
    g0 = np.array([0.0, 6.0, 7.0])
    u = g0 / np.linalg.norm(g0)
    acc = (np.linalg.norm(g0) + up)[:, None] * u[None, :]
    v, h = sam.vertical_horizontal_mps2(acc, g0)
    np.testing.assert_allclose(v, -up, atol=1e-12)
    np.testing.assert_allclose(h, 0.0, atol=1e-12)


def test_features_of_a_synthetic_wave():
    rate = 50.0
    t = np.arange(500) / rate
    # a_perp = -a_up: a clean 2 Hz cosine of amplitude 3 -> A1 = A2 = 6, T1 = T2 = 0.25 s
    up = -3.0 * np.cos(2 * np.pi * 2.0 * t)
    acc = np.column_stack([np.zeros_like(t), np.zeros_like(t), 9.8 + up])
    w = sam.sam_waves(acc, t, g0_mps2=[0.0, 0.0, 9.8])
    mid = w.iloc[2:-2]
    np.testing.assert_allclose(mid["A1"], 6.0, atol=0.05)
    np.testing.assert_allclose(mid["A"], 12.0, atol=0.1)
    np.testing.assert_allclose(mid["T1"], 0.24, atol=0.021)
    np.testing.assert_allclose(mid["T"], 0.5, atol=0.021)
    np.testing.assert_allclose(mid["I"], 0.0, atol=1e-9)
    # X1: DFT of 2N+1 = 23 samples of 3 cos at ~0.92 cycles per window, |sum| close to 23 * 3 / 2
    assert 25 < mid["X1"].iloc[0] < 40
    assert np.allclose(np.diff(mid["t_s"]), 0.5, atol=0.021)


def test_ranges_and_step_count_on_simulated_walkers(walks):
    train, test = walks
    logs = [(*_acc(sw), sw.steps["t_mid_s"]) for sw in train]
    wide = sam.SAMDetector(q_low=0.0, q_high=1.0).fit(logs)
    paper = sam.SAMDetector().fit(logs)
    r = wide.ranges_
    assert list(r.index) == list(sam.SAM_FEATURES)
    assert (r["min"] < r["max"]).all()
    assert (paper.ranges_["min"] >= r["min"]).all() and (paper.ranges_["max"] <= r["max"]).all()
    for sw in test:
        steps = wide.detect(*_acc(sw))
        err = abs(len(steps) - len(sw.steps)) / len(sw.steps)
        assert err < 0.08
        # narrower [5 %, 95 %] ranges reject more waves, never fewer
        assert len(paper.detect(*_acc(sw))) <= len(steps)
        assert {"i_peak", "t_s", "a_max_mps2", "a_min_mps2"} <= set(steps.columns)
        np.testing.assert_allclose(steps["t_s"], sw.imu.index.to_numpy()[steps["i_peak"]])
        # detected steps lie near true mid-step times
        d = np.abs(steps["t_s"].to_numpy()[:, None] - sw.steps["t_mid_s"].to_numpy()[None, :]).min(axis=1)
        assert np.median(d) < 0.05
        # class and function agree
        direct = sam.detect_steps_sam(*_acc(sw), ranges=r)
        pd.testing.assert_frame_equal(steps, direct)


def test_learned_ranges_are_quantiles():
    f = pd.DataFrame({k: np.arange(101, dtype=float) for k in sam.SAM_FEATURES})
    r = sam.learn_feature_ranges(f)
    np.testing.assert_allclose(r["min"], 5.0)
    np.testing.assert_allclose(r["max"], 95.0)


def test_vote_relaxes_the_all_tests_rule():
    waves = pd.DataFrame({f: [1.0, 5.0, 5.0] for f in sam.SAM_FEATURES})
    waves.loc[1, "A"] = 50.0                                   # fails one test
    waves.loc[2, ["A", "X1"]] = 50.0                           # fails two
    r = pd.DataFrame({"min": 0.0, "max": 10.0}, index=pd.Index(sam.SAM_FEATURES, name="feature"))
    np.testing.assert_array_equal(sam.in_ranges(waves, r), [True, False, False])
    np.testing.assert_array_equal(sam.in_ranges(waves, r, min_pass=6), [True, True, False])
    with pytest.raises(ValueError, match="min_pass"):
        sam.in_ranges(waves, r, min_pass=8)


def test_bad_input():
    t = np.arange(100) / 50.0
    acc = np.tile([0.0, 0.0, 9.8], (100, 1))
    with pytest.raises(ValueError, match="too short"):
        sam.sam_waves(acc[:10], t[:10])
    bad = acc.copy()
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match="row 7"):
        sam.sam_waves(bad, t)
    t2 = t.copy()
    t2[50] = t2[49]
    with pytest.raises(ValueError, match="strictly increasing"):
        sam.sam_waves(acc, t2)
    t3 = t.copy()
    t3[60:] += 0.5
    with pytest.raises(ValueError, match="irregularly sampled"):
        sam.sam_waves(acc, t3)
    with pytest.raises(ValueError, match="shape"):
        sam.sam_waves(acc[:, :2], t)
    with pytest.raises(ValueError, match="not fitted"):
        sam.SAMDetector().detect(acc, t)
    with pytest.raises(ValueError, match="lack columns"):
        sam.learn_feature_ranges(pd.DataFrame({"A": [1.0, 2.0]}))


def test_windows_in_samples_agree_at_rates_a_clock_jitter_apart():
    from ilocalg.pdr.sam import _window_sizes, seconds_to_samples

    for w_valley in (0.25, 0.5):  # the literal W_wave / 2 (L357) and the default 0.5 s
        a = _window_sizes(49.99999, 0.25, 0.5, w_valley)
        b = _window_sizes(50.000001, 0.25, 0.5, w_valley)
        assert a == b
    assert _window_sizes(50.0, 0.25, 0.5, 0.5) == (6, 25, 11)  # N = floor(0.5 W_wave f) - 1 = 11 (L357)
    assert seconds_to_samples(0.25, 49.99999) == seconds_to_samples(0.25, 50.000001) == 13  # 12.5 half up
    assert seconds_to_samples(0.25, 47.99999, "floor") == seconds_to_samples(0.25, 48.00001, "floor") == 12
    with pytest.raises(ValueError, match="rate_hz"):
        seconds_to_samples(0.5, 0.0)


def test_same_waves_at_rates_a_clock_jitter_apart():
    w = gait.make_walkers(1, rng=3)[0]
    sw = gait.simulate_walk(gait.straight_route(10.0), w, rng=3)
    acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
    n = len(acc)
    wa = sam.sam_waves(acc, np.arange(n) / 49.99999, valley_s=0.25)
    wb = sam.sam_waves(acc, np.arange(n) / 50.000001, valley_s=0.25)
    np.testing.assert_array_equal(wa["i_peak"], wb["i_peak"])
    np.testing.assert_array_equal(wa["i_left"], wb["i_left"])
    np.testing.assert_array_equal(wa["i_right"], wb["i_right"])
