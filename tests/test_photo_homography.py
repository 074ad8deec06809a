"""Tests of plane-to-plane homography ranging (survey 002 eq. 3-5)."""

import numpy as np
import pytest

from ilocalg.photo import homography_dlt, homography_locate, homography_pose, intrinsics, look_at, project

F = 1045.0


def _marker_photo(c, side_m=0.2):
    # square marker on the wall y = 0 centred at (0, 0, 1.5): plane axes x and z
    h = side_m / 2
    XY = np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
    world = np.c_[XY[:, 0], np.zeros(4), 1.5 + XY[:, 1]]
    T = look_at(c, [0.0, 0.0, 1.5], 0.05)
    return XY, world, T, project(world, c, T, F)


def test_dlt_matches_opencv_find_homography():
    cv2 = pytest.importorskip("cv2")
    rng = np.random.default_rng(2)
    XY = rng.uniform(-1, 1, (8, 2))
    H_true = np.array([[800.0, 30.0, 5.0], [-20.0, 790.0, 12.0], [0.05, 0.02, 1.0]])
    x = np.c_[XY, np.ones(8)] @ H_true.T
    x = x[:, :2] / x[:, 2:]
    ours = homography_dlt(XY, x)
    np.testing.assert_allclose(ours / ours[2, 2], H_true, rtol=1e-9, atol=1e-9)
    # with noise OpenCV refines the DLT by reprojection error (LM): close, not identical
    xn = x + rng.normal(0, 0.5, (8, 2))
    ref, _ = cv2.findHomography(XY, xn, 0)
    ours = homography_dlt(XY, xn)
    np.testing.assert_allclose(ours / ours[2, 2], ref / ref[2, 2], rtol=5e-3, atol=1e-3)


@pytest.mark.parametrize("dist", [1.0, 2.5, 4.0])
def test_marker_distance_exact_noise_free(dist):
    c = np.array([0.3, dist, 1.4])
    XY, world, T, U = _marker_photo(c)
    pose = homography_pose(homography_dlt(XY, U), F)
    origin = np.array([0.0, 0.0, 1.5])
    assert pose.distance_m == pytest.approx(np.linalg.norm(c - origin), rel=1e-9)
    # H = K [r1 r2 t]: r1, r2 are the world x and z axes seen from the camera
    np.testing.assert_allclose(pose.R[:, 0], T[:, 0], atol=1e-9)
    np.testing.assert_allclose(pose.R[:, 1], T[:, 2], atol=1e-9)
    H = intrinsics(F) @ np.c_[pose.R[:, 0], pose.R[:, 1], pose.t_m]
    Hd = homography_dlt(XY, U)
    np.testing.assert_allclose(H / H[2, 2], Hd / Hd[2, 2], rtol=1e-8, atol=1e-9)


def test_locate_from_wall_pois_exact():
    P = np.array([[-1.2, 0, 1.6], [-0.8, 0, 2.1], [0, 0, 1.58], [1.2, 0, 1.1], [0.4, 0, 1.61]])
    c = np.array([0.2, 5.0, 1.45])
    U = project(P, c, look_at(c, P.mean(axis=0)), F)
    est = homography_locate(P, U, F, [0, 0, 0], [1, 0, 0], [0, 0, 1])
    np.testing.assert_allclose(est, c, atol=1e-8)


def test_bad_input_raises():
    with pytest.raises(ValueError, match="at least 4"):
        homography_dlt(np.zeros((3, 2)), np.zeros((3, 2)))
    line = np.c_[np.arange(5.0), np.zeros(5)]
    with pytest.raises(ValueError, match="degenerate"):
        homography_dlt(line, line * 100)
    with pytest.raises(ValueError, match="not on the plane"):
        homography_locate(np.array([[0, 0.5, 0], [1, 0, 0], [0, 0, 1], [1, 0, 1.0]]), np.zeros((4, 2)), F,
                          [0, 0, 0], [1, 0, 0], [0, 0, 1])


def test_square_marker_pose_ippe_agrees_noise_free():
    pytest.importorskip("cv2")
    from ilocalg.photo import square_marker_pose

    c = np.array([0.4, 3.0, 1.35])
    XY, world, T, U = _marker_photo(c)
    ippe = square_marker_pose(U, 0.2, F)
    hom = homography_pose(homography_dlt(XY, U), F)
    assert ippe.distance_m == pytest.approx(hom.distance_m, rel=1e-7)
    np.testing.assert_allclose(ippe.c_plane_m, hom.c_plane_m, atol=1e-6)
    with pytest.raises(ValueError, match="side_m"):
        square_marker_pose(U, -1.0, F)


@pytest.mark.parametrize("n", [4, 5, 7, 9])
def test_batch_gives_each_item_its_result_alone(n):
    # a batch of views (shared target points, and one target per view) has, item by item, the bits of the
    # one-view functions: every step is per item (a sum over the batch axis would move last bits)
    from ilocalg.photo import homography_dlt_batch, homography_pose_batch

    rng = np.random.default_rng(n)
    B = 37
    XY = rng.uniform(-1, 1, (B, n, 2)) * rng.uniform(0.05, 3, (B, 1, 1))
    img = rng.uniform(-600, 600, (B, n, 2))
    for plane in (XY[0], XY):
        H = homography_dlt_batch(plane, img)
        pose = homography_pose_batch(H, F, 3.0, -2.0)
        assert H.shape == (B, 3, 3) and pose.distance_m.shape == (B,)
        for b in range(B):
            Hb = homography_dlt(plane if plane.ndim == 2 else plane[b], img[b])
            pb = homography_pose(Hb, F, 3.0, -2.0)
            assert np.array_equal(H[b], Hb)
            assert np.array_equal(pose.R[b], pb.R) and np.array_equal(pose.t_m[b], pb.t_m)
            assert np.array_equal(pose.c_plane_m[b], pb.c_plane_m) and pose.distance_m[b] == pb.distance_m
        assert np.array_equal(homography_dlt_batch(plane[::-1] if plane.ndim == 3 else plane, img[::-1]), H[::-1])


def test_batch_bad_input_raises():
    from ilocalg.photo import homography_dlt_batch, homography_pose_batch

    line = np.c_[np.arange(5.0), np.zeros(5)]
    ok = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.2]])
    with pytest.raises(ValueError, match="degenerate"):
        homography_dlt_batch(np.stack([ok, line]), np.stack([ok * 100, line * 100]))
    with pytest.raises(ValueError, match=r"\(B, n, 2\)"):
        homography_dlt_batch(ok, ok)
    with pytest.raises(ValueError, match="plane_xy must have shape"):
        homography_dlt_batch(np.zeros((2, 5, 2)), np.zeros((3, 5, 2)))
    with pytest.raises(ValueError, match="finite"):
        homography_pose_batch(np.full((2, 3, 3), np.nan), F)
