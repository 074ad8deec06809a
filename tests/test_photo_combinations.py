"""Tests of ilocalg.photo.combinations (every method on photos of one PoI combination)."""

import numpy as np
import pytest

from ilocalg.photo.combinations import combo_label, horizontal_error_cm, locate_methods, on_end_wall
from ilocalg.sim import photo_poi


def test_labels_errors_and_the_end_wall():
    assert combo_label((0, 2, 6)) == "{1,3,7}"
    assert horizontal_error_cm(np.array([[3.0, 4.0, 9.0]]), np.zeros((1, 3)))[0] == pytest.approx(500.0)
    P = np.zeros((2, 4, 3))
    P[1, 0, 1] = 0.5
    assert list(on_end_wall(P)) == [True, False]


def test_noise_free_photos_are_located_exactly_by_st_and_pnp():
    s = photo_poi.simulate(0, n_photos=1, drag_sd_px=0.0, tilt_sd_deg=0.0, yaw_sd_deg=0.0)
    idx = np.array([[0, 2, 4, 6]])
    n = s.c_m.shape[0]
    P = np.broadcast_to(s.pois_m[idx], (n, 4, 3))
    U = s.img_px[:, idx[0]]
    est, st, conv = locate_methods(P, U, s.f_px, s.T_meas, s.T_true, {"VA_truth": s.c_m}, va_max_iter=50)
    assert set(est) == {"ST", "ST_true_orientation", "VA_truth", "PnP_SQPnP", "homography"}
    for m in ("ST", "PnP_SQPnP", "VA_truth"):
        assert horizontal_error_cm(est[m], s.c_m).max() < 0.1, m
    assert conv[0]["method"] == "VA_truth" and 0 <= conv[0]["converged_share"] <= 1
    # the thesis's methods only: the same estimates of ST and VA
    own, _, _ = locate_methods(P, U, s.f_px, s.T_meas, s.T_true, {"VA_truth": s.c_m}, va_max_iter=50, others=False)
    assert set(own) == {"ST", "VA_truth"}
    for m in own:
        np.testing.assert_array_equal(own[m], est[m])
