import numpy as np
import pytest

from ilocalg import units


def test_as_rng_same_seed_same_stream_and_passthrough():
    a = units.as_rng(7).normal(size=5)
    b = units.as_rng(7).normal(size=5)
    assert a.tobytes() == b.tobytes()
    g = np.random.default_rng(1)
    assert units.as_rng(g) is g
    with pytest.raises(ValueError, match="rng"):
        units.as_rng("seed")


def test_angle_conventions_round_trip():
    psi = np.deg2rad([0.0, 90.0, 180.0, -45.0])
    theta = units.yaw_to_theta(psi)
    # north -> +y (90 deg from east), east -> 0
    np.testing.assert_allclose(np.rad2deg(theta[:2]), [90.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(units.wrap_angle_rad(units.theta_to_yaw(theta) - psi), 0.0, atol=1e-12)
    w = units.wrap_angle_rad(np.array([np.pi, -np.pi, 3 * np.pi + 0.1]))
    assert np.all(w >= -np.pi) and np.all(w < np.pi)
