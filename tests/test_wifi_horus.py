"""Simplified-Horus: histograms, argmax likelihood, the two zero-probability cases, bad input."""

import numpy as np
import pytest

from ilocalg.sim import iloc_floor
from ilocalg.wifi import SimplifiedHorus, fit_horus, horus_predict_index, horus_scores


def _toy():
    # point A (0,0): AP0 ~ -50, AP1 ~ -70; point B (10,0): AP0 ~ -70, AP1 ~ -50, AP2 only at B
    X = np.array([[-50, -70, np.nan], [-51, -70, np.nan], [-50, -71, np.nan],
                  [-70, -50, -60], [-71, -51, -60], [-70, -50, -61]], dtype=float)
    y = np.array([[0, 0]] * 3 + [[10, 0]] * 3, dtype=float)
    return X, y


def test_histograms_and_argmax():
    X, y = _toy()
    m = fit_horus(X, y, bin_width_db=1.0, prob_floor=1e-3)
    np.testing.assert_array_equal(m.points_xy, [[0, 0], [10, 0]])
    # Pr(AP0 = -50 | A) = 2/3
    row = m.pair[0, 0]
    np.testing.assert_allclose(np.exp(m.log_prob[row, int(-50 - m.lo_dbm)]), 2 / 3, rtol=1e-6)
    est = SimplifiedHorus(k_aps=2).fit(X, y)
    np.testing.assert_array_equal(est.predict(np.array([[-50, -70, np.nan], [-70, -50, np.nan]])), [[0, 0], [10, 0]])
    # the class and the functions agree
    np.testing.assert_array_equal(est.predict_index(X), horus_predict_index(m, X, 2))


def test_unseen_value_gets_the_floor_not_zero():
    X, y = _toy()
    m = fit_horus(X, y, prob_floor=1e-3)
    s, k = horus_scores(m, np.array([[-55.0, -70.0, np.nan]]), k_aps=2)  # -55 never seen for AP0
    assert np.isfinite(s[0, 0])
    np.testing.assert_allclose(s[0, 0], np.log(1e-3) + np.log(2 / 3), rtol=1e-5)
    assert k[0] == 2


def test_k_decreases_when_no_point_holds_all_aps():
    X, y = _toy()
    m = fit_horus(X, y)
    # strongest AP2 (only at B), then AP0: no point holds both AP2 and AP0? B holds both -> k=2.
    s, k = horus_scores(m, np.array([[-70.0, np.nan, -60.0]]), k_aps=2)
    assert k[0] == 2 and np.isneginf(s[0, 0]) and np.isfinite(s[0, 1])
    # unknown AP (never heard in training) is ignored; the query lacks database APs -> fewer compared
    X2 = np.hstack([X, np.full((6, 1), np.nan)])
    est = SimplifiedHorus(k_aps=3).fit(X2, y)
    np.testing.assert_array_equal(est.predict(np.array([[-50.0, np.nan, np.nan, -30.0]])), [[0, 0]])


def test_only_unknown_aps_raise():
    X, y = _toy()
    X2 = np.hstack([X, np.full((6, 1), np.nan)])
    est = SimplifiedHorus().fit(X2, y)
    with pytest.raises(ValueError, match="shares no access point with the training set"):
        est.predict_index(np.array([[np.nan, np.nan, np.nan, -40.0]]))
    with pytest.raises(ValueError, match="hears no access point"):
        est.predict_index(np.full((1, 4), np.nan))
    # predict: the documented no-AP result, a NaN position
    assert np.isnan(est.predict(np.array([[np.nan, np.nan, np.nan, -40.0]]))).all()
    assert np.isnan(est.predict(np.full((1, 4), np.nan))).all()
    with pytest.raises(ValueError, match="features"):
        est.predict(np.full((1, 3), -50.0))
    with pytest.raises(ValueError, match="prob_floor"):
        SimplifiedHorus(prob_floor=0).fit(X, y)


def test_accuracy_on_simulated_floor():
    # test scans under the survey's own conditions (no drift, body or device difference)
    # the assumed world's radio (the measured one's shadowing and dropout make every method coarser; notebook 01)
    sim = iloc_floor.simulate(0, scans_per_point=60, scans_per_test_point=3, drift_sd_db=0.0, body_loss_db=0.0,
                              world="assumed")
    xy = SimplifiedHorus(5).fit(sim.train.rssi_dbm, sim.train.xy_m).predict(sim.test.rssi_dbm)
    e = np.hypot(*(xy - sim.test.xy_m).T)
    assert np.median(e) <= 2.0 and np.percentile(e, 80) < 6.0


def test_check_estimator():
    from sklearn.utils.estimator_checks import check_estimator

    from tests.test_wifi_knn import EXPECTED_FAILED

    check_estimator(SimplifiedHorus(k_aps=3, bin_width_db=0.5, rssi_range_dbm=None),
                    expected_failed_checks=EXPECTED_FAILED)
