import numpy as np
import pandas as pd
import pytest

from ilocalg.pdr.norm_peaks import detect_steps_norm_peaks
from ilocalg.pdr.signals import moving_mean, moving_mean_time


def _gait(seed=0, f_step=1.9, n=1200):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.05, 0.07, n))  # irregular 14-20 Hz, like a phone
    t -= t[0]
    acc = np.column_stack([0.2 * rng.normal(size=t.size), 0.2 * rng.normal(size=t.size),
                           9.81 + 2.5 * np.cos(2 * np.pi * f_step * t)])
    return t, acc


def test_counts_the_steps_of_an_irregularly_sampled_gait():
    t, acc = _gait()
    steps = detect_steps_norm_peaks(acc, t)
    assert isinstance(steps, pd.DataFrame)
    assert {"i_peak", "t_s", "a_max_mps2", "a_min_mps2"} <= set(steps.columns)
    assert abs(len(steps) - 1.9 * t[-1]) <= 3
    assert np.array_equal(steps["t_s"].to_numpy(), t[steps["i_peak"].to_numpy()])
    assert np.all(steps["a_max_mps2"] - steps["a_min_mps2"] >= 0.8 - 1e-12)  # prominence bound
    assert np.median(np.diff(steps["t_s"])) == pytest.approx(1 / 1.9, rel=0.05)
    # the norm alone gives the same steps
    pd.testing.assert_frame_equal(detect_steps_norm_peaks(np.linalg.norm(acc, axis=1), t), steps)


def test_no_steps_when_standing():
    t = np.arange(300) * 0.06
    steps = detect_steps_norm_peaks(np.tile([0.0, 0.0, 9.81], (300, 1)), t)
    assert len(steps) == 0 and list(steps.columns)[:4] == ["i_peak", "t_s", "a_max_mps2", "a_min_mps2"]


def test_time_window_mean_generalises_the_sample_count_mean():
    rng = np.random.default_rng(1)
    x = rng.normal(size=200)
    dt = 0.01
    t = np.arange(200) * dt
    for n in (1, 3, 7):
        # uniform samples: a window of (2n + 0.5) dt holds n samples either side
        assert np.array_equal(moving_mean_time(x, t, (2 * n + 0.5) * dt), moving_mean(x, n))
    assert np.allclose(moving_mean_time(x, t, 0.0), x, rtol=0, atol=1e-12)  # the sample itself


def test_bad_input_is_a_clear_error():
    t, acc = _gait(n=50)
    with pytest.raises(ValueError, match="t_s"):
        detect_steps_norm_peaks(acc, t[::-1])
    with pytest.raises(ValueError, match="acc_mps2"):
        detect_steps_norm_peaks(acc[:, :2], t)
    with pytest.raises(ValueError, match="min_interval_s"):
        detect_steps_norm_peaks(acc, t, min_interval_s=0.0)
    with pytest.raises(ValueError, match="window_s"):
        moving_mean_time(acc[:, 2], t, -1.0)
