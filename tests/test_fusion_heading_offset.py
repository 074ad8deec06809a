"""Heading offset and start from fixes: rigid 2-D fit, robust IRLS, circular mean."""

import numpy as np
import pytest

from ilocalg.fusion.heading_offset import (
    circular_mean_rad,
    fit_rigid_2d,
    fit_track_to_fixes,
    fit_translation_2d,
    rotate_xy,
)


def test_rigid_fit_recovers_exact_transform():
    rng = np.random.default_rng(1)
    src = rng.uniform(-20, 20, (30, 2))
    dst = rotate_xy(src, 0.7) + [5.0, -3.0]
    a, t = fit_rigid_2d(src, dst)
    assert a == pytest.approx(0.7, abs=1e-12)
    np.testing.assert_allclose(t, [5.0, -3.0], atol=1e-10)


def test_rigid_fit_matches_brute_force_on_noisy_points():
    rng = np.random.default_rng(2)
    src = rng.uniform(-20, 20, (25, 2))
    dst = rotate_xy(src, -1.2) + [1.0, 2.0] + rng.normal(0, 2.0, (25, 2))
    a, t = fit_rigid_2d(src, dst)
    grid = np.linspace(-np.pi, np.pi, 20001)

    def cost(ang):
        q = rotate_xy(src, ang)
        return np.sum((q + (dst - q).mean(0) - dst) ** 2)

    best = grid[np.argmin([cost(g) for g in grid])]
    assert a == pytest.approx(best, abs=1e-3)
    assert cost(a) <= cost(best) + 1e-9


def test_huber_fit_resists_outliers_where_least_squares_does_not():
    rng = np.random.default_rng(3)
    src = np.column_stack([np.linspace(0, 60, 40), 5 * np.sin(np.linspace(0, 6, 40))])
    dst = rotate_xy(src, 0.3) + [10.0, 20.0] + rng.normal(0, 1.0, (40, 2))
    dst[::5] += 80.0                             # 8 gross outliers
    ls = fit_track_to_fixes(src, dst, huber_m=None)
    rb = fit_track_to_fixes(src, dst, huber_m=3.0)
    assert abs(rb.angle_rad - 0.3) < 0.03 and np.hypot(*(rb.t_m - [10, 20])) < 1.5
    assert np.hypot(*(ls.t_m - [10, 20])) > 10 * np.hypot(*(rb.t_m - [10, 20]))
    assert rb.weights[::5].max() < 0.1 and rb.weights.max() == 1.0


def test_translation_only_fit_is_the_huber_m_estimate():
    """rotation=False: the same IRLS with the heading held; it reaches the Huber minimum (checked by a
    direct minimiser) and ignores gross outliers."""
    from scipy.optimize import minimize

    rng = np.random.default_rng(5)
    src = np.column_stack([np.linspace(0, 50, 30), 4 * np.cos(np.linspace(0, 5, 30))])
    dst = src + [-7.0, 12.0] + rng.normal(0, 3.0, (30, 2))
    dst[::6] += [60.0, -40.0]
    h = 5.0
    fit = fit_track_to_fixes(src, dst, huber_m=h, rotation=False)
    assert fit.angle_rad == 0.0

    def huber(t):
        d = np.hypot(*(dst - src - t).T)
        return np.where(d <= h, 0.5 * d**2, h * d - 0.5 * h**2).sum()

    ref = minimize(huber, np.median(dst - src, axis=0), method="Nelder-Mead",
                   options={"xatol": 1e-9, "fatol": 1e-12, "maxiter": 10000}).x
    assert np.hypot(*(fit.t_m - ref)) < 1e-3
    assert np.hypot(*(fit.t_m - [-7, 12])) < 2.5
    ls = fit_track_to_fixes(src, dst, huber_m=None, rotation=False)
    np.testing.assert_allclose(ls.t_m, (dst - src).mean(axis=0), atol=1e-12)
    np.testing.assert_allclose(fit_translation_2d(src, dst, np.r_[np.ones(29), 0.0]), (dst - src)[:29].mean(0),
                               atol=1e-12)


def test_circular_mean_wraps():
    assert circular_mean_rad([np.pi - 0.1, -np.pi + 0.1]) == pytest.approx(-np.pi, abs=1e-9) or \
        circular_mean_rad([np.pi - 0.1, -np.pi + 0.1]) == pytest.approx(np.pi, abs=1e-9)
    assert circular_mean_rad([0.1, 0.3], [1, 3]) == pytest.approx(np.arctan2(np.sin(0.1) + 3 * np.sin(0.3),
                                                                              np.cos(0.1) + 3 * np.cos(0.3)))


@pytest.mark.parametrize("src,dst,w,match", [
    (np.zeros((1, 2)), np.zeros((1, 2)), None, "at least 2"),
    (np.zeros((3, 2)), np.zeros((3, 3)), None, "shape"),
    (np.zeros((3, 2)), np.full((3, 2), np.nan), None, "finite"),
    (np.zeros((3, 2)), np.zeros((3, 2)), [1, -1, 1], "weights"),
])
def test_bad_input(src, dst, w, match):
    with pytest.raises(ValueError, match=match):
        fit_rigid_2d(src, dst, w)
    with pytest.raises(ValueError, match="huber_m"):
        fit_track_to_fixes(np.zeros((3, 2)), np.ones((3, 2)), huber_m=-1.0)
    with pytest.raises(ValueError, match="angles_rad"):
        circular_mean_rad([])
