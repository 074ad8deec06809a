"""The i-Loc floor simulator: determinism, geometry from the thesis, calibrated inputs."""

import numpy as np
import pytest

from ilocalg.sim import iloc_floor


def test_same_seed_same_arrays_and_different_seed_differs():
    a = iloc_floor.simulate(3, scans_per_point=20, scans_per_test_point=2)
    b = iloc_floor.simulate(3, scans_per_point=20, scans_per_test_point=2)
    np.testing.assert_array_equal(a.train.rssi_dbm, b.train.rssi_dbm)
    np.testing.assert_array_equal(a.test.rssi_dbm, b.test.rssi_dbm)
    np.testing.assert_array_equal(a.ap_xy_m, b.ap_xy_m)
    c = iloc_floor.simulate(4, scans_per_point=20, scans_per_test_point=2)
    assert not np.array_equal(np.nan_to_num(a.train.rssi_dbm), np.nan_to_num(c.train.rssi_dbm))


def test_geometry_follows_the_thesis():
    pts = iloc_floor.training_points()
    assert pts.shape == (iloc_floor.N_TRAIN_POINTS, 2) and len(np.unique(pts, axis=0)) == len(pts)
    assert (pts >= 0).all() and (pts[:, 0] <= iloc_floor.FLOOR_W_M).all() and (pts[:, 1] <= iloc_floor.FLOOR_H_M).all()
    # every point has a neighbour 2 m away
    d = np.hypot(pts[:, None, 0] - pts[None, :, 0], pts[:, None, 1] - pts[None, :, 1])
    np.fill_diagonal(d, np.inf)
    np.testing.assert_allclose(d.min(axis=1), 2.0)
    route = iloc_floor.test_route_index()
    assert route.size == iloc_floor.N_TEST_POINTS
    np.testing.assert_allclose(np.hypot(*np.diff(pts[route], axis=0).T), 2.0)  # a walk


def test_calibrated_inputs():
    sim = iloc_floor.simulate(0, scans_per_point=100, scans_per_test_point=2)
    s = iloc_floor.summary(sim).set_index("quantity")["value"]
    # thesis: 4-18 APs per scan -> the bulk of the scans (5th-95th percentile) lies in that range
    assert 4 <= s["APs heard per scan, 5th percentile"] and s["APs heard per scan, 95th percentile"] <= 18
    assert 2.0 <= s["RSSI sd at a point per AP, median [dB]"] <= 6.0
    # integer dBm above the detection threshold, NaN otherwise
    x = sim.train.rssi_dbm
    assert np.nanmin(x) >= sim.detect_dbm and np.array_equal(x[~np.isnan(x)], np.round(x[~np.isnan(x)]))
    # points near windows / the junction drift more (Fig 2)
    assert sim.fade_sd_db.max() > sim.fade_sd_db.min()


def test_unknown_parameter_raises():
    with pytest.raises(ValueError, match="unknown simulator parameters"):
        iloc_floor.simulate(0, path_loss=3)


def test_floor_fixes_shapes_and_variance_floor():
    ff = iloc_floor.floor_fixes(0, n_walkers=2, n_cal=3, method="KNN (Manhattan, K=5)", scans_per_point=20)
    n_pts = ff.route_xy_m.shape[0]
    assert ff.fix_xy_m.shape == (n_pts, 5, 2) and ff.cal_var_m2.shape == (n_pts,)
    assert (ff.cal_var_m2 >= iloc_floor.SPACING_M**2 / 12.0 - 1e-12).all()
    assert np.median(np.hypot(*(ff.fix_xy_m[:, 0] - ff.route_xy_m).T)) < 15.0
    with pytest.raises(ValueError, match="method must be one of"):
        iloc_floor.floor_fixes(0, 1, 2, method="SVM", scans_per_point=5)
    with pytest.raises(ValueError, match="n_cal"):
        iloc_floor.floor_fixes(0, 1, 1, scans_per_point=5)
