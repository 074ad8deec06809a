"""Tests of ilocalg.photo.camera (pinhole projection, eq. 29-30)."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ilocalg.photo.camera import intrinsics, look_at, project, ray_angle_rad, small_rotation


def test_look_at_is_rotation_and_centres_target():
    c = np.array([0.3, 4.0, 1.4])
    target = np.array([0.0, 0.0, 1.6])
    T = look_at(c, target, roll_rad=0.1)
    np.testing.assert_allclose(T @ T.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(T) == pytest.approx(1.0)
    np.testing.assert_allclose(project(target[None], c, T, 1000.0), [[0.0, 0.0]], atol=1e-9)


def test_project_matches_opencv():
    cv2 = pytest.importorskip("cv2")
    rng = np.random.default_rng(1)
    P = rng.uniform([-2, -0.5, 0.5], [2, 0.5, 2.5], (6, 3))
    c = np.array([0.5, 5.0, 1.3])
    T = look_at(c, [0, 0, 1.5], 0.05)
    f = 900.0
    rvec, _ = cv2.Rodrigues(T)
    ref, _ = cv2.projectPoints(P, rvec, -T @ c, intrinsics(f), None)
    np.testing.assert_allclose(project(P, c, T, f), ref.reshape(-1, 2), atol=1e-8)


def test_project_rejects_points_behind_camera():
    c = np.array([0.0, 5.0, 1.5])
    T = look_at(c, [0, 0, 1.5])
    with pytest.raises(ValueError, match="behind"):
        project(np.array([[0.0, 8.0, 1.5]]), c, T, 1000.0)


def test_ray_angle_matches_world_angle():
    c = np.array([0.2, 3.0, 1.4])
    T = look_at(c, [0, 0, 1.5])
    P = np.array([[-1.0, 0, 1.2], [0.8, 0, 1.9]])
    U = project(P, c, T, 800.0)
    u, v = P[0] - c, P[1] - c
    ref = np.arccos(u @ v / np.linalg.norm(u) / np.linalg.norm(v))
    assert ray_angle_rad(U[0], U[1], 800.0) == pytest.approx(ref, abs=1e-12)


def test_small_rotation_zero_is_identity_and_intrinsics_validates():
    np.testing.assert_allclose(small_rotation(0.0, 0.0, 0.0), np.eye(3))
    with pytest.raises(ValueError, match="f_px"):
        intrinsics(-1.0)


def test_thin_lens_law_and_pinhole_approximation():
    from ilocalg.photo import thin_lens_image_distance_m

    f = 3.7e-3
    d_i = thin_lens_image_distance_m(np.array([0.1, 2.5, 8.5]), f)
    np.testing.assert_allclose(1 / np.array([0.1, 2.5, 8.5]) + 1 / d_i, 1 / f, rtol=1e-12)  # eq. (27)
    assert d_i[1] / f - 1 < 2e-3  # d_o >> f: d_i ~ f, eq. (28)
    with pytest.raises(ValueError, match="larger than the focal length"):
        thin_lens_image_distance_m(0.001, f)


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-2, 2), y=st.floats(1.5, 9), z=st.floats(1.0, 2.0), roll=st.floats(-0.3, 0.3),
       k=st.integers(2, 7))
def test_st_recovers_any_camera_exactly(x, y, z, roll, k):
    from ilocalg.photo import st_solve

    P = np.array([[-1.2, 0, 1.6], [-0.8, 0, 2.1], [-0.4, 0, 1.62], [0, 0, 1.58], [0.4, 0, 1.61], [0.8, 0, 1.59],
                  [1.2, 0, 1.1]])[:k]
    c = np.array([x, y, z])
    T = look_at(c, P.mean(axis=0), roll)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = st_solve(P, project(P, c, T, 1045.0), 1045.0, T)
    np.testing.assert_allclose(res.c_m, c, atol=1e-6)
