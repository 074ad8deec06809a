import numpy as np
import pytest

from ilocalg.pdr import signals as sg


def test_sliding_extrema_match_brute_force():
    x = np.random.default_rng(0).normal(size=60)
    for left, right in [(0, 0), (2, 3), (3, 2), (4, 4), (0, 5)]:
        ref = np.array([x[max(i - left, 0): i + right + 1].max() for i in range(x.size)])
        np.testing.assert_array_equal(sg.sliding_max(x, left, right), ref)


def test_moving_mean_and_resample():
    x = np.arange(10.0)
    np.testing.assert_allclose(sg.moving_mean(x, 2)[2:-2], x[2:-2])
    t = np.array([0.0, 0.3, 1.0])
    xu, tu = sg.resample_uniform(2 * t, t, 10.0)
    np.testing.assert_allclose(tu, np.arange(11) / 10.0)
    np.testing.assert_allclose(xu, 2 * tu)
    assert sg.sample_rate_hz(np.arange(5) / 50.0) == pytest.approx(50.0)


def test_bad_times_and_samples():
    with pytest.raises(ValueError, match="row 2"):
        sg.check_times([0.0, 1.0, 0.5])
    with pytest.raises(ValueError, match="not finite at row 1"):
        sg.check_times([0.0, np.nan, 0.5])
    with pytest.raises(ValueError, match="irregularly"):
        sg.check_times([0.0, 0.1, 0.2, 0.9])
    sg.check_times([0.0, 0.1, 0.2, 0.9], regular=False)
    with pytest.raises(ValueError, match="too short"):
        sg.check_acc(np.zeros((1, 3)))
    with pytest.raises(ValueError, match="shape"):
        sg.check_acc(np.zeros((5, 2)))
    with pytest.raises(ValueError, match="row 3"):
        sg.check_acc(np.r_[np.zeros((3, 3)), [[0, np.inf, 0]]])


def test_moving_mean_time_matches_brute_force_on_irregular_samples():
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.005, 0.03, 300))
    x = rng.normal(size=300)
    w = 0.1
    ref = np.array([x[np.abs(t - ti) <= w / 2].mean() for ti in t])
    np.testing.assert_allclose(sg.moving_mean_time(x, t, w), ref, rtol=1e-12, atol=1e-12)
    # on a uniform grid it is the sample-count moving mean
    tu = np.arange(100) / 100.0
    np.testing.assert_allclose(sg.moving_mean_time(x[:100], tu, 0.0501), sg.moving_mean(x[:100], 2), atol=1e-12)
    with pytest.raises(ValueError, match="window_s"):
        sg.moving_mean_time(x, t, -0.1)


def test_gravity_lowpass_and_projection():
    rng = np.random.default_rng(2)
    n = 400
    # a tilted phone at rest with noise: gravity is recovered and the projection is |g|
    g = np.array([1.0, 3.0, 9.2])
    acc = g + rng.normal(0, 0.05, (n, 3))
    gl = sg.gravity_lowpass_mps2(acc, 50)
    np.testing.assert_allclose(gl[200], g, atol=0.05)
    v = sg.along_gravity_mps2(acc, gl)
    assert abs(np.median(v) - np.linalg.norm(g)) < 0.02
    # one vector or one per sample give the same projection
    np.testing.assert_allclose(sg.along_gravity_mps2(acc, g), sg.along_gravity_mps2(acc, np.tile(g, (n, 1))))
    with pytest.raises(ValueError, match="non-zero"):
        sg.along_gravity_mps2(acc, np.zeros(3))
    with pytest.raises(ValueError, match="half_width"):
        sg.gravity_lowpass_mps2(acc, -1)


def test_acc_from_log_reads_the_documented_columns():
    import pandas as pd

    imu = pd.DataFrame({"acc_x_mps2": [0.0, 1.0], "acc_y_mps2": [0.0, 2.0], "acc_z_mps2": [9.8, 9.7]},
                       index=pd.Index([0.0, 0.02], name="t_s"))
    acc, t = sg.acc_from_log(imu)
    np.testing.assert_array_equal(acc, [[0.0, 0.0, 9.8], [1.0, 2.0, 9.7]])
    np.testing.assert_array_equal(t, [0.0, 0.02])
    with pytest.raises(ValueError, match="acc_z_mps2"):
        sg.acc_from_log(imu.drop(columns="acc_z_mps2"))
