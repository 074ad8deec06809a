"""Tests of ST (similar triangles, thesis eq. 29-30)."""

import warnings

import numpy as np
import pytest

from ilocalg.photo import (
    IllConditionedWarning,
    RankDeficientError,
    SimilarTriangles,
    look_at,
    project,
    small_rotation,
    st_error_propagation,
    st_solve,
    st_solve_batch,
)

F = 1045.0
POIS = np.array([[-1.2, 0, 1.6], [-0.8, 0, 2.1], [-0.4, 0, 1.62], [0, 0, 1.58], [0.4, 0, 1.61], [0.8, 0, 1.59],
                 [1.2, 0, 1.1]])


def _photo(c, roll=0.03):
    T = look_at(c, POIS.mean(axis=0), roll)
    return T, project(POIS, c, T, F)


@pytest.mark.parametrize("idx", [[0, 1], [2, 3], [0, 2, 3], [4, 5], list(range(7))])
def test_exact_recovery_noise_free(idx):
    c = np.array([0.3, 4.5, 1.42])
    T, U = _photo(c)
    res = st_solve(POIS[idx], U[idx], F, T)
    np.testing.assert_allclose(res.c_m, c, atol=1e-9)
    assert res.rank == 3
    np.testing.assert_allclose(res.residual_m, 0.0, atol=1e-9)


def test_collinear_pois_off_the_camera_line_are_still_full_rank():
    # three exactly collinear PoIs: with a known orientation each ray fixes c to a line,
    # so the system is full rank unless the camera is on the PoIs' line
    P = np.array([[-1.0, 0, 1.5], [0.0, 0, 1.5], [1.0, 0, 1.5]])
    c = np.array([0.2, 4.0, 1.4])
    T = look_at(c, [0, 0, 1.5])
    res = st_solve(P, project(P, c, T, F), F, T)
    np.testing.assert_allclose(res.c_m, c, atol=1e-9)


def test_rank_deficient_when_camera_on_line_of_collinear_pois_raises():
    P = np.array([[0.0, 0.0, 1.5], [0.0, 1.0, 1.5], [0.0, 2.0, 1.5]])
    c = np.array([0.0, 5.0, 1.5])
    T = look_at(c, [0.05, 0.0, 1.45])
    U = project(P, c, T, F)
    with pytest.raises(RankDeficientError, match="rank 2"):
        st_solve(P, U, F, T)
    assert issubclass(RankDeficientError, ValueError)
    out = st_solve_batch(P, U[None], F, T[None])
    assert out["rank"][0] == 2 and np.isnan(out["c_m"]).all() and np.isinf(out["cond"][0])


def test_near_parallel_rays_warn():
    P = np.array([[0.0, 0.0, 1.5], [0.0, 1.0, 1.5]])
    c = np.array([0.001, 5.0, 1.5])
    T = look_at(c, [0.0, 0.0, 1.45])
    U = project(P, c, T, F)
    with pytest.warns(IllConditionedWarning, match="ill-conditioned"):
        res = st_solve(P, U, F, T)
    assert res.cond > 100


def test_well_conditioned_does_not_warn():
    c = np.array([0.0, 3.0, 1.4])
    T, U = _photo(c)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st_solve(POIS, U, F, T)


def test_least_squares_matches_numpy_lstsq_on_noisy_data():
    rng = np.random.default_rng(3)
    c = np.array([0.1, 6.0, 1.45])
    T, U = _photo(c)
    U = U + rng.normal(0, 10, U.shape)
    res = st_solve(POIS, U, F, T)
    A = []
    b = []
    for p, (u, v) in zip(POIS, U, strict=True):
        for row in (T[0] - u / F * T[2], T[1] - v / F * T[2]):
            A.append(row)
            b.append(row @ p)
    ref = np.linalg.lstsq(np.array(A), np.array(b), rcond=None)[0]
    np.testing.assert_allclose(res.c_m, ref, atol=1e-10)


def test_class_agrees_with_function():
    c = np.array([0.3, 5.0, 1.4])
    T, U = _photo(c)
    U = U + 3.0
    np.testing.assert_allclose(SimilarTriangles(F).locate(POIS, U, T).c_m, st_solve(POIS, U, F, T).c_m)


def test_bad_input_raises():
    c = np.array([0.3, 5.0, 1.4])
    T, U = _photo(c)
    with pytest.raises(ValueError, match="at least 2"):
        st_solve(POIS[:1], U[:1], F, T)
    with pytest.raises(ValueError, match="img_px"):
        st_solve(POIS, U[:3], F, T)
    with pytest.raises(ValueError, match="rotation"):
        st_solve(POIS, U, F, 2 * T)
    with pytest.raises(ValueError, match="NaN"):
        st_solve(POIS, np.where(np.arange(14).reshape(7, 2) == 3, np.nan, U), F, T)


def test_error_propagation_matches_monte_carlo():
    rng = np.random.default_rng(7)
    c = np.array([0.2, 6.5, 1.45])
    T, U = _photo(c)
    tilt, yaw, drag = np.deg2rad(1.0), np.deg2rad(5.0), 12.0
    pred = st_error_propagation(POIS, U[None], F, T[None], tilt, yaw, drag)
    n = 4000
    Tm = T @ small_rotation(tilt * rng.standard_normal(n), tilt * rng.standard_normal(n), yaw * rng.standard_normal(n))
    Um = U + drag * rng.standard_normal((n, 7, 2))
    est = st_solve_batch(POIS, Um, F, Tm)["c_m"]
    cov_mc = np.cov((est - c).T)
    assert np.sqrt(np.trace(cov_mc)) == pytest.approx(pred["rms_m"][0], rel=0.1)
    # the heading error dominates at this range
    assert np.trace(pred["cov_orientation_m2"][0]) > np.trace(pred["cov_drag_m2"][0])
