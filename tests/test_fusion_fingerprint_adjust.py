"""Tests of ilocalg.fusion.fingerprint_adjust (Luo et al. 2017's Wi-Fi start + fingerprint adjustment)."""

import numpy as np
import pytest

from ilocalg.fusion.fingerprint_adjust import fingerprint_adjusted_track, principled_weight
from ilocalg.pdr.dead_reckoning import dead_reckon


def test_hand_worked_walk():
    # four 1 m steps east; a fix at state 2 at (2, 1) and at state 4 at (3, 0)
    th = np.zeros(4)
    d = np.ones(4)
    z = np.full((5, 2), np.nan)
    z[2] = [2.0, 1.0]
    z[4] = [3.0, 0.0]
    x = fingerprint_adjusted_track([0.0, 0.0], th, d, z, 0.5)
    expected = np.array([[0, 0], [1, 0], [2, 0.5], [3, 0.5], [3.5, 0.25]])
    np.testing.assert_allclose(x, expected)


def test_weight_limits_are_pdr_and_reset():
    rng = np.random.default_rng(0)
    th = rng.uniform(-np.pi, np.pi, 30)
    d = rng.uniform(0.5, 0.8, 30)
    z = np.full((31, 2), np.nan)
    z[::5] = rng.normal(0, 3, (7, 2))
    pdr = fingerprint_adjusted_track([1.0, 2.0], th, d, z, 0.0)
    ref = dead_reckon(d, th, 1.0, 2.0)[["x_m", "y_m"]].to_numpy()
    np.testing.assert_allclose(pdr, ref, atol=1e-12)
    reset = fingerprint_adjusted_track([1.0, 2.0], th, d, z, 1.0)
    has = np.all(np.isfinite(z), axis=1)
    np.testing.assert_allclose(reset[has], z[has])


def test_bad_input():
    with pytest.raises(ValueError, match="weight"):
        fingerprint_adjusted_track([0, 0], [0.0], [1.0], np.full((2, 2), np.nan), 1.5)
    with pytest.raises(ValueError, match="z_m must have shape"):
        fingerprint_adjusted_track([0, 0], [0.0], [1.0], np.full((3, 2), np.nan), 0.5)
    z = np.full((2, 2), np.nan)
    z[1, 0] = 1.0
    with pytest.raises(ValueError, match="row 1"):
        fingerprint_adjusted_track([0, 0], [0.0], [1.0], z, 0.5)


def test_principled_weight_grows_with_pdr_noise_and_shrinks_with_wifi_noise():
    w1, q1 = principled_weight(0.1, 0.1, 0.7, 0.55, 3.0, 4.0)
    w2, q2 = principled_weight(0.3, 0.1, 0.7, 0.55, 3.0, 4.0)
    w3, _ = principled_weight(0.1, 0.1, 0.7, 0.55, 3.0, 16.0)
    assert q2 > q1 and w2 > w1 and w3 < w1 and 0 < w3 < w1 < w2 < 1
