"""Tests of the PoI-wall photo simulator."""

import numpy as np
import pytest

from ilocalg.photo import project
from ilocalg.sim import photo_poi


def test_same_seed_same_arrays_and_different_seed_differs():
    a = photo_poi.simulate(3, n_photos=2)
    b = photo_poi.simulate(3, n_photos=2)
    c = photo_poi.simulate(4, n_photos=2)
    for name in ("c_m", "T_true", "T_meas", "img_px", "c0_good_m", "c0_bad_m"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.img_px, c.img_px)


def test_layout_matches_the_thesis_description():
    shots = photo_poi.shots_frame()
    d = shots["dist_to_p4_m"].to_numpy()
    assert np.all(np.diff(d) > 0)  # t1 nearest to p4, t7 farthest
    np.testing.assert_allclose(np.diff(shots["y_m"]), 1.0)  # one metre apart
    z = photo_poi.POIS_M[:, 2]
    on_line = z[[0, 2, 3, 4, 5]]
    assert np.ptp(on_line) < 0.05  # p1, p3, p4, p5, p6 almost on one horizontal line
    assert abs(z[1] - on_line.mean()) > 0.3 and abs(z[6] - on_line.mean()) > 0.3


def test_noise_statistics_match_the_documented_inputs():
    s = photo_poi.simulate(0, n_photos=300)
    drag = (s.img_px - s.img_true_px).ravel()
    assert drag.std() == pytest.approx(photo_poi.DEFAULTS["drag_sd_px"], rel=0.05)
    # sensor error rotation: T_meas = T_true @ R_err
    R = np.swapaxes(s.T_true, 1, 2) @ s.T_meas
    yaw = np.degrees(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
    assert yaw.std() == pytest.approx(photo_poi.DEFAULTS["yaw_sd_deg"], rel=0.1)
    assert np.all(s.c0_good_m[:, 1] >= photo_poi.ROOM_M[2])
    good = np.hypot(*(s.c0_good_m[:, :2] - s.c_m[:, :2]).T).mean()
    bad = np.hypot(*(s.c0_bad_m[:, :2] - s.c_m[:, :2]).T).mean()
    assert good < bad


def test_true_screen_points_are_exact_projections_on_screen():
    s = photo_poi.simulate(1, n_photos=3)
    np.testing.assert_allclose(project(s.pois_m, s.c_m, s.T_true, s.f_px), s.img_true_px)
    assert np.all(np.abs(s.img_true_px[..., 0]) <= 640) and np.all(np.abs(s.img_true_px[..., 1]) <= 360)


def test_bad_parameters_raise():
    with pytest.raises(ValueError, match="unknown simulation parameters"):
        photo_poi.simulate(0, drag_px=3)
    with pytest.raises(ValueError, match="n_photos"):
        photo_poi.simulate(0, n_photos=0)
    with pytest.raises(ValueError, match="outside the screen"):
        photo_poi.simulate(0, n_photos=1, f_px=3000.0)


def test_changing_one_input_leaves_other_draws_unchanged():
    a = photo_poi.simulate(0, n_photos=3)
    b = photo_poi.simulate(0, n_photos=3, good_guess_sd_m=0.5, drag_sd_px=3.0)
    np.testing.assert_array_equal(a.c0_bad_m, b.c0_bad_m)
    np.testing.assert_array_equal(a.T_meas, b.T_meas)
    np.testing.assert_allclose((b.img_px - b.img_true_px) * 4.0, a.img_px - a.img_true_px)
