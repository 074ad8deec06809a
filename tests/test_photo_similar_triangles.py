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
    st_system,
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


def _svd_reference(P, U, f, T, rank_rtol=1e-9):
    """st_solve_batch as it was before the closed form: the SVD of st_system's matrix, every photo."""
    A, b = st_system(P, U, f, T)
    Uu, s, Vt = np.linalg.svd(A, full_matrices=False)
    rank = np.sum(s > rank_rtol * s[:, :1], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_s = np.where(s > rank_rtol * s[:, :1], 1.0 / s, 0.0)
        ub = np.matmul(b[:, None, :], Uu)[:, 0, :] * inv_s
        c = np.matmul(Vt.transpose(0, 2, 1), ub[..., None])[..., 0]
        cond = np.where(rank == 3, s[:, 0] / s[:, -1], np.inf)
    c[rank < 3] = np.nan
    return {"c_m": c, "rank": rank, "cond": cond, "singular_values": s}


def _random_photos(rng, B, n, spread_m, noise_px):
    """B photos of n PoIs scattered by up to spread_m around a point 3-8 m in front of cameras with random roll."""
    centre = np.c_[rng.uniform(-1, 1, B), np.zeros(B), rng.uniform(1.0, 2.0, B)]
    P = centre[:, None, :] + spread_m[:, None, None] * rng.uniform(-1, 1, (B, n, 3))
    c = np.c_[rng.uniform(-2, 2, B), rng.uniform(4, 8, B), rng.uniform(1.2, 1.7, B)]
    T = look_at(c, centre, rng.uniform(-0.5, 0.5, B))
    return P, project(P, c, T, F) + rng.normal(0, noise_px, (B, n, 2)), T


@pytest.mark.parametrize("n", [2, 3, 7, 12])
def test_batch_matches_lstsq_and_svd_on_random_photos(n):
    rng = np.random.default_rng(n)
    B = 300
    P, U, T = _random_photos(rng, B, n, rng.uniform(0.05, 1.0, B), 3.0)
    out = st_solve_batch(P, U, F, T)
    ref = _svd_reference(P, U, F, T)
    assert (out["rank"] == 3).all()
    A, b = st_system(P, U, F, T)
    lstsq = np.array([np.linalg.lstsq(A[i], b[i], rcond=None)[0] for i in range(B)])
    # rounding level: both are backward stable, so they differ by a few eps * cond relative to |c|
    err = np.linalg.norm(out["c_m"] - lstsq, axis=1) / (np.linalg.norm(lstsq, axis=1) * ref["cond"])
    assert err.max() < 1e-14
    np.testing.assert_allclose(out["singular_values"], ref["singular_values"], rtol=1e-13)
    np.testing.assert_allclose(out["cond"], ref["cond"], rtol=1e-13)


def test_batch_near_degenerate_rows_take_the_svd_unchanged():
    # PoIs spread from 1 m down to 1e-9 m around one point (cond from ~3 to beyond the rank threshold), noise-free
    # and noisy, mixed with exactly rank-deficient photos (camera on the PoIs' line) in one batch
    rng = np.random.default_rng(11)
    B = 400
    spread = 10.0 ** rng.uniform(-9, 0, B)
    P, U, T = _random_photos(rng, B, 4, spread, 0.0)
    U[::2] += rng.normal(0, 1.0, U[::2].shape)
    Pl = np.array([[0.0, 0.0, 1.5], [0.0, 1.0, 1.5], [0.0, 2.0, 1.5], [0.0, 3.0, 1.5]])
    cl = np.array([0.0, 5.0, 1.5])
    Tl = look_at(cl, [0.05, 0.0, 1.45])
    P[:20], U[:20], T[:20] = Pl, project(Pl, cl, Tl, F), Tl
    out = st_solve_batch(P, U, F, T)
    ref = _svd_reference(P, U, F, T)
    np.testing.assert_array_equal(out["rank"], ref["rank"])
    assert (out["rank"][:20] == 2).all() and np.isnan(out["c_m"][:20]).all() and np.isinf(out["cond"][:20]).all()
    assert (ref["rank"] < 3).sum() > 20 and (ref["cond"] > 100).sum() > 100  # the batch does reach degeneracy
    slow = ref["cond"] > 100
    for key in ("c_m", "rank", "cond", "singular_values"):  # ill-conditioned and rank-deficient: bit for bit
        np.testing.assert_array_equal(out[key][slow], ref[key][slow])
    fast = ~slow
    np.testing.assert_allclose(out["singular_values"][fast], ref["singular_values"][fast], rtol=1e-12)
    err = np.linalg.norm(out["c_m"][fast] - ref["c_m"][fast], axis=1)
    assert (err <= 1e-13 * np.linalg.norm(ref["c_m"][fast], axis=1) * ref["cond"][fast]).all()


def test_batch_non_rotation_or_nan_takes_the_svd():
    rng = np.random.default_rng(5)
    P, U, T = _random_photos(rng, 50, 5, np.full(50, 0.8), 2.0)
    Ts = T.copy()
    Ts[::3] *= 1 + 1e-9  # not a rotation: the closed form's singular values would be off by 1e-9
    out = st_solve_batch(P, U, F, Ts)
    ref = _svd_reference(P, U, F, Ts)
    for key in ("c_m", "cond", "singular_values"):
        np.testing.assert_array_equal(out[key][::3], ref[key][::3])
    U[7, 1, 0] = np.nan
    with pytest.raises(np.linalg.LinAlgError):  # as before: NaN never gives a silent answer
        st_solve_batch(P, U, F, T)


def test_batch_rank_rtol_is_honoured():
    rng = np.random.default_rng(8)
    P, U, T = _random_photos(rng, 100, 3, 10.0 ** rng.uniform(-2, 0, 100), 1.0)  # cond 7 to 1600
    for rtol in (1e-9, 0.02, 0.1):  # a coarse tolerance makes some well-conditioned (cond < 100) photos rank 2
        out = st_solve_batch(P, U, F, T, rank_rtol=rtol)
        ref = _svd_reference(P, U, F, T, rank_rtol=rtol)
        np.testing.assert_array_equal(out["rank"], ref["rank"])
        np.testing.assert_array_equal(np.isnan(out["c_m"]).all(axis=1), ref["rank"] < 3)
        assert (ref["rank"] == 3).any()
    assert (ref["rank"] < 3).sum() > 10
