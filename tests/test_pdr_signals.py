import numpy as np
import pytest

from ilocalg.pdr import signals as sg


def test_sliding_extrema_match_brute_force():
    x = np.random.default_rng(0).normal(size=60)
    for left, right in [(0, 0), (2, 3), (3, 2), (4, 4), (0, 5)]:
        ref = np.array([x[max(i - left, 0): i + right + 1].max() for i in range(x.size)])
        np.testing.assert_array_equal(sg.sliding_max(x, left, right), ref)
        ref = np.array([x[max(i - left, 0): i + right + 1].min() for i in range(x.size)])
        np.testing.assert_array_equal(sg.sliding_min(x, left, right), ref)


def test_moving_mean_and_resample():
    x = np.arange(10.0)
    np.testing.assert_allclose(sg.moving_mean(x, 2)[2:-2], x[2:-2])
    t = np.array([0.0, 0.3, 1.0])
    tu, xu = sg.resample_uniform(t, 2 * t, 10.0)
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
