"""Tests of ilocalg.pdr.sign_change (PSO thesis Fig. 3.9)."""

import numpy as np
import pytest

from ilocalg.pdr.filters import moving_average
from ilocalg.pdr.sign_change import STEP_COLUMNS, detect_steps_sign_change, slope_sign_extrema, static_rms_mps2


def _walk(n_steps=60, f_hz=1.0, fs_hz=8.0, amp=2.5, noise=0.2, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(0, n_steps / f_hz, 1 / fs_hz)
    a = 9.81 + amp * np.sin(2 * np.pi * f_hz * t) + rng.normal(0, noise, t.size)
    return t, a


def test_extrema_by_sign_change():
    g = np.array([0, 1, 2, 1, 0, 1, 1, 1, 0, -1, 0.0])
    i_max, i_min = slope_sign_extrema(g)
    np.testing.assert_array_equal(i_max, [2, 5])  # the plateau 5..7 counts once, at its start
    np.testing.assert_array_equal(i_min, [4, 9])


@pytest.mark.parametrize("f_hz,smooth", [(1.0, True), (1.2, True), (1.8, False), (2.0, False)])
def test_counts_steps_of_a_sinusoidal_walk_at_8hz(f_hz, smooth):
    t, a = _walk(n_steps=60, f_hz=f_hz)
    steps = detect_steps_sign_change(a, t, smooth=smooth)
    assert tuple(steps.columns[:6]) == STEP_COLUMNS
    # edge samples (first / last step) and 8 Hz sampling of the peaks cost up to 3 steps
    assert 57 <= len(steps) <= 60
    # amplitude recovered within the smoothing/aliasing loss, gravity kept in the values
    assert np.all(steps.a_max_mps2 > 9.81) and np.all(steps.a_min_mps2 < 9.81)
    assert np.all(steps.i_valley > steps.i_peak)
    assert np.all(np.diff(steps.t_s) > 0)


def test_rms_band_rejects_small_wiggles():
    t, a = _walk(n_steps=30, noise=0.0)
    # add small ripples during a standing phase: no steps there
    t2 = np.arange(t[-1] + 0.125, t[-1] + 20, 0.125)
    a2 = 9.81 + 0.05 * np.sin(2 * np.pi * 0.6 * t2)
    steps = detect_steps_sign_change(np.r_[a, a2], np.r_[t, t2], smooth=True)
    assert abs(len(steps) - 30) <= 1
    assert steps.t_s.max() < t[-1] + 0.5
    # without the band (rms 0) the ripples are counted too
    assert len(detect_steps_sign_change(np.r_[a, a2], np.r_[t, t2], rms_mps2=0.0, smooth=True)) > 38


def test_ma_2_2_at_8hz_nulls_a_1_6hz_cadence():
    # the thesis's MA(nL=nR=2) at 8 Hz has its first zero at fs/5 = 1.6 Hz: a step signal there vanishes
    t, a = _walk(n_steps=60, f_hz=1.6, noise=0.0)
    assert len(detect_steps_sign_change(a, t, smooth=False)) >= 58
    assert np.ptp(moving_average(a, 2, 2)[2:-2]) < 1e-9


def test_standing_still_gives_empty_table():
    t = np.arange(0, 10, 0.125)
    steps = detect_steps_sign_change(np.full(t.size, 9.81), t)
    assert len(steps) == 0 and tuple(steps.columns) == STEP_COLUMNS


def test_bad_input():
    t, a = _walk(n_steps=5)
    with pytest.raises(ValueError, match="t_s must have the shape"):
        detect_steps_sign_change(a, t[:-1])
    with pytest.raises(ValueError, match="strictly increasing"):
        detect_steps_sign_change(a, t[::-1])
    a = a.copy()
    a[3] = np.nan
    with pytest.raises(ValueError, match="acc_mps2 must be finite"):
        detect_steps_sign_change(a, t)
    with pytest.raises(ValueError, match="rms_mps2"):
        detect_steps_sign_change(np.ones(10), np.arange(10.0), rms_mps2=-1.0)


def test_default_is_no_moving_average_and_static_rms_band():
    t, a = _walk(n_steps=40, f_hz=1.8, noise=0.0)
    np.testing.assert_array_equal(detect_steps_sign_change(a, t), detect_steps_sign_change(a, t, smooth=False))
    rng = np.random.default_rng(0)
    static = 9.81 + rng.normal(0, 0.1, 480)
    band = static_rms_mps2(static)
    assert band == pytest.approx(np.std(static))
    # the moving average lowers the static RMS about by sqrt(5) for white noise
    assert static_rms_mps2(static, smooth=True) == pytest.approx(band / np.sqrt(5), rel=0.15)
    with pytest.raises(ValueError, match="static_acc_mps2"):
        static_rms_mps2(np.ones((3, 3)))
