"""ilocalg.fusion.iloc_kf: the i-Loc KF variants on one walk, the R of a fix, the budget methods."""

import numpy as np

from ilocalg.fusion.iloc_kf import nearest_point_variance, run_filters


def test_filter_starts_where_it_is_told_and_a_scan_without_fix_is_skipped():
    pdr = {"state_t_s": np.array([0.0, 1.0, 2.0]), "step_m": np.array([0.7, 0.7]), "theta_rad": np.zeros(2)}
    fix = np.array([[0.7, 0.0], [np.nan, np.nan]])
    tracks, info = run_filters(np.array([0.0, 0.0]), pdr, np.array([1.0, 2.0]), fix,
                             {"R": np.array([1.0, 1.0])}, P0_var_m2=1.0)
    np.testing.assert_allclose(tracks["PTS"][0], [0.0, 0.0])
    np.testing.assert_allclose(tracks["PTS"][-1], [1.4, 0.0])
    assert info["n_fixes"] == 1


def test_a_fix_gets_the_variance_of_the_nearest_calibrated_point():
    r_of = nearest_point_variance(np.array([[0.0, 0.0], [4.0, 0.0]]), np.array([1.0, 9.0]))
    np.testing.assert_array_equal(r_of(np.array([[0.5, 1.0], [3.0, -1.0], [np.nan, np.nan]])), [1.0, 9.0, np.nan])
    assert r_of(np.array([2.5, 0.0]))[0] == 9.0
