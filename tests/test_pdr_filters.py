"""Tests of ilocalg.pdr.filters (PSO thesis eq. 3.4-3.6, Table 3-2)."""

import numpy as np
import pytest
from scipy.signal import savgol_coeffs, savgol_filter

from ilocalg.pdr.filters import moving_average, rms, savitzky_golay, savitzky_golay_coeffs, smoother_gain

# Table 3-2 of the PSO thesis (Numerical Recipes' table); the thesis prints the (m=2, nL=4, nR=0) row
# as "0.886 -0.143 -0.886 0.257 0.886", a typo of Numerical Recipes' 0.086 -0.143 -0.086 0.257 0.886.
TABLE_3_2_PAPER = {
    (2, 2, 2): [-0.086, 0.343, 0.486, 0.343, -0.086],
    (2, 4, 0): [0.086, -0.143, -0.086, 0.257, 0.886],
    (2, 5, 5): [-0.084, 0.021, 0.103, 0.161, 0.196, 0.207, 0.196, 0.161, 0.103, 0.021, -0.084],
    (4, 4, 4): [0.035, -0.128, 0.070, 0.315, 0.417, 0.315, 0.070, -0.128, 0.035],
    (4, 5, 5): [0.042, -0.105, -0.023, 0.140, 0.280, 0.333, 0.280, 0.140, -0.023, -0.105, 0.042],
}


@pytest.mark.parametrize("key", sorted(TABLE_3_2_PAPER))
def test_sg_coeffs_match_table_3_2(key):
    m, nl, nr = key
    c = savitzky_golay_coeffs(nl, nr, m)
    np.testing.assert_allclose(c, TABLE_3_2_PAPER[key], atol=6e-4)
    assert c.sum() == pytest.approx(1.0)


@pytest.mark.parametrize("nl,nr,m", [(2, 2, 2), (5, 5, 2), (4, 4, 4), (4, 0, 2), (3, 1, 1)])
def test_sg_coeffs_match_scipy(nl, nr, m):
    # scipy returns the convolution order; pos = index of the smoothed sample in the window
    ref = savgol_coeffs(nl + nr + 1, m, pos=nl, use="dot")
    np.testing.assert_allclose(savitzky_golay_coeffs(nl, nr, m), ref, atol=1e-12)


def test_sg_matches_scipy_filter_including_edges():
    x = np.random.default_rng(1).normal(size=50).cumsum()
    np.testing.assert_allclose(savitzky_golay(x, 2, 2, 2), savgol_filter(x, 5, 2, mode="interp"), atol=1e-10)


def test_sg_preserves_polynomials_up_to_order():
    t = np.arange(30.0)
    quad = 0.3 * t**2 - 2 * t + 1
    np.testing.assert_allclose(savitzky_golay(quad, 2, 2, 2), quad, atol=1e-9)
    np.testing.assert_allclose(savitzky_golay(quad, 4, 0, 2), quad, atol=1e-9)


def test_moving_average_is_window_mean():
    x = np.random.default_rng(2).normal(size=40)
    ma = moving_average(x, 2, 2)
    np.testing.assert_allclose(ma[2:-2], np.convolve(x, np.ones(5) / 5, mode="valid"), atol=1e-12)
    assert ma[0] == pytest.approx(x[:5].mean()) and ma[-1] == pytest.approx(x[-5:].mean())
    assert ma.shape == x.shape


def test_filters_reduce_white_noise_rms_as_expected():
    x = np.random.default_rng(3).normal(size=200_000)
    # white noise: MA(5) keeps sqrt(1/5) of the sd, SG(2,2,2) sqrt(sum c^2) = sqrt(17/35)
    assert rms(moving_average(x)) / rms(x) == pytest.approx(np.sqrt(1 / 5), rel=0.02)
    assert rms(savitzky_golay(x)) / rms(x) == pytest.approx(np.sqrt(17 / 35), rel=0.02)


def test_rms_is_population_sd():
    x = np.array([1.0, 2.0, 3.0, 6.0])
    assert rms(x) == pytest.approx(np.std(x))


def test_bad_input():
    with pytest.raises(ValueError, match="fewer than the window"):
        moving_average(np.ones(3))
    with pytest.raises(ValueError, match="finite"):
        savitzky_golay(np.array([1, 2, np.nan, 4, 5, 6.0]))
    with pytest.raises(ValueError, match="order"):
        savitzky_golay_coeffs(1, 1, 3)
    with pytest.raises(ValueError, match="n_left"):
        moving_average(np.ones(10), n_left=-1)
    with pytest.raises(ValueError, match="1-D"):
        moving_average(np.ones((5, 5)))


def test_moving_average_frequency_response():
    rate = 8.0
    # MA(2,2) at 8 Hz: first zero at rate / 5 = 1.6 Hz (inside the walking step-rate band), DC gain 1
    assert smoother_gain(1.6, rate, 2, 2) == pytest.approx(0.0, abs=1e-12)
    assert smoother_gain(0.0, rate, 2, 2) == pytest.approx(1.0)
    # MA(1,1): first zero at 8 / 3 Hz
    assert smoother_gain(rate / 3, rate, 1, 1) == pytest.approx(0.0, abs=1e-12)
    # closed form |sin(pi f N / fs) / (N sin(pi f / fs))|
    f = np.linspace(0.05, 3.95, 40)
    for n in (1, 2, 3):
        N = 2 * n + 1
        ref = np.abs(np.sin(np.pi * f * N / rate) / (N * np.sin(np.pi * f / rate)))
        np.testing.assert_allclose(smoother_gain(f, rate, n, n), ref, atol=1e-12)
    # and the filter itself: a 1.6 Hz sine sampled at 8 Hz vanishes in the interior
    t = np.arange(200) / rate
    y = moving_average(np.sin(2 * np.pi * 1.6 * t + 0.3), 2, 2)
    assert np.max(np.abs(y[2:-2])) < 1e-12
    with pytest.raises(ValueError, match="rate_hz"):
        smoother_gain(1.0, 0.0)
