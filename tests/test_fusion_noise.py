"""Tests of ilocalg.fusion.noise and ilocalg.fusion.synthetic."""

from __future__ import annotations

import numpy as np
import pytest

from ilocalg import fusion as fu


def test_spread_covariance_matches_numpy_weighted_cov():
    rng = np.random.default_rng(0)
    xy = rng.normal(size=(6, 5, 2)) * [3.0, 1.0]
    w = rng.uniform(0.1, 1.0, size=(6, 5))
    R = fu.fix_covariance_from_spread(xy, w, min_var_m2=0.5, scale=2.0)
    for i in range(6):
        C = np.cov(xy[i].T, aweights=w[i], bias=True)
        np.testing.assert_allclose(R[i], 2.0 * C + 0.5 * np.eye(2), atol=1e-12)
    assert (np.linalg.eigvalsh(R) > 0).all()
    same = fu.fix_covariance_from_spread(np.ones((1, 4, 2)), min_var_m2=1.5)
    np.testing.assert_allclose(same[0], 1.5 * np.eye(2))


def test_spread_covariance_bad_input():
    with pytest.raises(ValueError, match="shape \\(n, K>=1, 2\\)"):
        fu.fix_covariance_from_spread(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="weights of fix 1 sum to zero"):
        fu.fix_covariance_from_spread(np.zeros((2, 3, 2)), np.array([[1, 1, 1], [0, 0, 0]]))
    with pytest.raises(ValueError, match="min_var_m2 and scale must be > 0"):
        fu.fix_covariance_from_spread(np.zeros((2, 3, 2)), min_var_m2=0.0)


def test_spread_noise_tracks_true_error_in_the_filter():
    """Fixes whose neighbours scatter more are worse: R from the spread beats a fixed R of the same mean."""
    rng = np.random.default_rng(1)
    e_spread, e_fixed = [], []
    for seed in range(8):
        w = fu.straight_walk(200, rng=seed, fix_every=2, sigma_rf_m=0.0)
        n1 = len(w.z_m)
        sd = rng.choice([0.7, 6.0], size=n1)  # per-fix true error sd, metres
        nb = w.truth_xy_m[:, None, :] + sd[:, None, None] * rng.standard_normal((n1, 5, 2))
        z = nb.mean(axis=1)
        z[np.isnan(w.z_m[:, 0])] = np.nan
        R = fu.fix_covariance_from_spread(nb, min_var_m2=0.1, scale=1.0 / 5)  # variance of a 5-point mean
        r_var = np.trace(R, axis1=1, axis2=2) / 2
        x0 = w.truth_xy_m[0]
        a = fu.filter_walk(x0, np.eye(2), w.theta_rad, w.step_m, 0.2, z, R_m2=R)
        b = fu.filter_walk(x0, np.eye(2), w.theta_rad, w.step_m, 0.2, z, r_var_m2=np.nanmean(r_var))
        e_spread.append(np.linalg.norm(a.x - w.truth_xy_m, axis=1).mean())
        e_fixed.append(np.linalg.norm(b.x - w.truth_xy_m, axis=1).mean())
    assert np.mean(e_spread) < 0.9 * np.mean(e_fixed)


def test_synthetic_walk_is_deterministic():
    a = fu.straight_walk(50, rng=3, outlier_fraction=0.2)
    b = fu.straight_walk(50, rng=3, outlier_fraction=0.2)
    for name in ("truth_xy_m", "theta_rad", "step_m", "z_m", "is_outlier"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.z_m, fu.straight_walk(50, rng=4).z_m)
    assert np.isnan(a.z_m[1]).all() and not np.isnan(a.z_m[3]).any()
