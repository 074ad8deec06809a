"""Tests of VA (view-angle gradient descent, thesis sec. 6.3)."""

import numpy as np
import pytest
from scipy.optimize import approx_fprime, least_squares

from ilocalg.photo import (
    ViewAngle,
    look_at,
    measured_view_angles_rad,
    project,
    va_cost,
    va_gradient,
    va_solve,
    va_solve_batch,
    view_angles_rad,
)

F = 1045.0
POIS = np.array([[-1.2, 0, 1.6], [-0.8, 0, 2.1], [-0.4, 0, 1.62], [0, 0, 1.58], [0.4, 0, 1.61], [0.8, 0, 1.59],
                 [1.2, 0, 1.1]])


def _photo(c):
    T = look_at(c, POIS.mean(axis=0), 0.02)
    return project(POIS, c, T, F)


def test_measured_angles_equal_true_angles_noise_free():
    c = np.array([0.3, 4.0, 1.4])
    U = _photo(c)
    np.testing.assert_allclose(measured_view_angles_rad(U, F), view_angles_rad(c[None], POIS[None])[0], atol=1e-12)


def test_gradient_matches_finite_differences():
    rng = np.random.default_rng(0)
    a = view_angles_rad(np.array([[0.2, 4.0, 1.4]]), POIS[None])[0] + rng.normal(0, 0.01, 21)
    c = np.array([0.8, 3.1, 1.2])
    num = approx_fprime(c, lambda x: va_cost(x[None], POIS[None], a[None])[0], 1e-7)
    np.testing.assert_allclose(va_gradient(c[None], POIS[None], a[None])[0], num, rtol=1e-4, atol=1e-7)


@pytest.mark.parametrize("c", [[0.0, 2.5, 1.45], [0.4, 5.5, 1.40], [-0.3, 8.5, 1.5]])
def test_exact_recovery_from_good_guess(c):
    c = np.asarray(c)
    U = _photo(c)
    res = va_solve(POIS, U, F, c + [0.5, -0.6, 0.1], free_z=True)
    assert res.converged
    np.testing.assert_allclose(res.c_m, c, atol=1e-4)
    assert res.cost < 1e-16


def test_exact_recovery_three_pois_and_two_d_search():
    c = np.array([0.2, 4.0, 1.45])
    U = _photo(c)
    idx = [0, 1, 6]
    res = va_solve(POIS[idx], U[idx], F, c + [0.3, 0.4, -0.1], max_iter=5000, free_z=True)
    np.testing.assert_allclose(res.c_m, c, atol=1e-4)
    res2 = va_solve(POIS, U, F, np.r_[c[:2] + [0.5, 0.5], c[2]], free_z=False)
    np.testing.assert_allclose(res2.c_m, c, atol=1e-4)


def test_agrees_with_scipy_least_squares_on_noisy_data():
    rng = np.random.default_rng(5)
    c = np.array([0.1, 4.0, 1.45])
    U = _photo(c) + rng.normal(0, 5, (7, 2))
    c0 = c + [0.4, 0.3, 0.0]
    a = measured_view_angles_rad(U, F)
    ref = least_squares(lambda x: view_angles_rad(x[None], POIS[None])[0] - a, c0, xtol=1e-14, ftol=1e-14).x
    ours = va_solve(POIS, U, F, c0, max_iter=20000, free_z=True).c_m
    np.testing.assert_allclose(ours, ref, atol=1e-3)


def test_two_pois_underdetermined_answer_depends_on_guess():
    c = np.array([0.0, 5.0, 1.45])
    U = _photo(c)
    idx = [2, 4]
    near = va_solve(POIS[idx], U[idx], F, c + [0.2, 0.2, 0.0]).c_m
    far = va_solve(POIS[idx], U[idx], F, [2.5, 1.0, 1.45]).c_m
    assert np.linalg.norm(near - c) < 0.3
    assert np.linalg.norm(far - c) > 1.0
    # both lie on the solution surface: the view angle matches
    for x in (near, far):
        assert view_angles_rad(x[None], POIS[idx][None])[0, 0] == pytest.approx(
            measured_view_angles_rad(U[idx], F)[0], abs=1e-6)


def test_class_agrees_with_function_and_batch():
    c = np.array([0.3, 6.0, 1.4])
    U = _photo(c) + 4.0
    c0 = c + [1.0, 1.0, 0.0]
    r1 = ViewAngle(F).locate(POIS, U, c0)
    r2 = va_solve(POIS, U, F, c0)
    r3 = va_solve_batch(POIS, measured_view_angles_rad(U, F)[None], c0[None])
    np.testing.assert_allclose(r1.c_m, r2.c_m)
    np.testing.assert_allclose(r3["c_m"][0], r2.c_m)


def test_bad_input_raises():
    U = _photo(np.array([0.0, 4.0, 1.4]))
    with pytest.raises(ValueError, match="at least 2"):
        va_solve(POIS[:1], U[:1], F, [0, 4, 1.4])
    with pytest.raises(ValueError, match="c0_m"):
        va_solve(POIS, U, F, [0, 4])
    with pytest.raises(ValueError, match="angles_rad"):
        va_solve_batch(POIS, np.zeros((1, 5)), np.zeros((1, 3)))


def test_default_search_is_on_the_floor_plane():
    c = np.array([0.2, 4.0, 1.45])
    U = _photo(c) + 3.0
    c0 = np.array([0.9, 3.2, 1.30])
    res = va_solve(POIS, U, F, c0)
    assert res.c_m[2] == c0[2]                      # height kept: the camera height is known
    assert va_solve(POIS, U, F, c0, free_z=True).c_m[2] != c0[2]


@pytest.mark.parametrize("layout", ["A", "D", "G"])
def test_va_from_the_truth_converges_on_noise_free_photos(layout):
    """Started at (or near) the true centre with the true height, VA on noise-free photos ends at the truth."""
    from ilocalg.sim import photo_poi

    lay = photo_poi.LAYOUTS[layout]
    P = lay.pois_m
    C = np.c_[lay.shots_xy_m, np.full(7, 1.45)]
    U = project(P, C, look_at(C, P.mean(axis=0), 0.02), F)
    a = measured_view_angles_rad(U, F)
    at = va_solve_batch(P, a, C)
    np.testing.assert_allclose(at["c_m"], C, atol=1e-9)
    assert np.all(at["cost"] < 1e-20)
    near = va_solve_batch(P, a, C + [0.3, -0.4, 0.0], max_iter=5000)
    assert near["converged"].all()
    np.testing.assert_allclose(near["c_m"], C, atol=1e-4)


def test_batch_gives_each_photo_its_result_alone_bit_for_bit():
    # 7 PoIs (21 pairs: a sum over pairs long enough for numpy to add a contiguous axis in blocks), noisy angles, starts
    # up to 3 m off; each photo's descent depends on its own numbers only, whatever the batch (and its size 1)
    rng = np.random.default_rng(11)
    c = np.column_stack([rng.uniform(-2, 2, 12), rng.uniform(2, 6, 12), np.full(12, 1.5)])
    ang = view_angles_rad(c, np.broadcast_to(POIS, (12, 7, 3))) + rng.normal(0, 0.01, (12, 21))
    c0 = c + np.column_stack([rng.uniform(-3, 3, (12, 2)), np.zeros(12)])
    for free_z in (False, True):
        batch = va_solve_batch(POIS, ang, c0, max_iter=300, free_z=free_z)
        assert np.unique(batch["n_iter"]).size > 3                 # photos leave the batch at different iterations
        for b in range(12):
            one = va_solve_batch(POIS, ang[b:b + 1], c0[b:b + 1], max_iter=300, free_z=free_z)
            for key in ("c_m", "cost", "n_iter", "converged"):
                assert np.array_equal(one[key][0], batch[key][b]), (free_z, b, key)
        np.testing.assert_array_equal(va_cost(c0, POIS, ang), [va_cost(c0[b], POIS, ang[b])[0] for b in range(12)])
