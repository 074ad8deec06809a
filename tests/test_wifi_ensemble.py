"""ApSelector and FingerprintEnsemble: AP selection and an averaging ensemble of fingerprint estimators."""

import numpy as np
import pytest
from sklearn.pipeline import Pipeline

from ilocalg.wifi import (
    ApSelector,
    CascadeFingerprint,
    FingerprintEnsemble,
    KnnFingerprint,
    OffsetFingerprint,
    combine_predictions,
)


def _radio(rng, n=150, n_aps=12):
    """Positions on a 30 m square, log-distance RSSI (dBm, whole numbers), NaN below -95 dBm."""
    xy = rng.uniform(0, 30, (n, 2))
    ap = rng.uniform(0, 30, (n_aps, 2))
    d = np.maximum(np.hypot(xy[:, None, 0] - ap[None, :, 0], xy[:, None, 1] - ap[None, :, 1]), 1.0)
    x = np.round(-35.0 - 30.0 * np.log10(d) + rng.normal(0, 2.0, d.shape))
    x[x < -95] = np.nan
    return x, xy


def test_ap_selector_keeps_the_aps_heard_often_enough():
    x = np.array([[-50, np.nan, np.nan, -70], [-60, np.nan, -80, np.nan], [-55, np.nan, -81, np.nan]])
    np.testing.assert_array_equal(ApSelector().fit(x).keep_, [True, False, True, True])
    sel = ApSelector(min_count=2).fit(x)
    np.testing.assert_array_equal(sel.keep_, [True, False, True, False])
    np.testing.assert_array_equal(sel.transform(x), x[:, [0, 2]])
    np.testing.assert_array_equal(sel.get_feature_names_out(["a", "b", "c", "d"]), ["a", "c"])
    with pytest.raises(ValueError, match="min_count must be a whole number"):
        ApSelector(min_count=0).fit(x)
    with pytest.raises(ValueError, match="no access point is heard in min_count=4"):
        ApSelector(min_count=4).fit(x)
    with pytest.raises(ValueError, match="X has 3 features, but ApSelector is expecting 4"):
        sel.transform(x[:, :3])


def test_ap_selection_leaves_minkowski_results_unchanged():
    # an AP never heard in training adds the same amount to a query's (squared) distance to every reference:
    # the same neighbours, hence the same unweighted KNN position
    rng = np.random.default_rng(0)
    x, xy = _radio(rng)
    x[:, 3] = np.nan                                              # never heard in training
    q, _ = _radio(np.random.default_rng(0), n=40)
    q[:, 3] = -60.0
    plain = KnnFingerprint(n_neighbors=3, p=2).fit(x, xy).predict(q)
    piped = Pipeline([("aps", ApSelector()), ("est", KnnFingerprint(n_neighbors=3, p=2))]).fit(x, xy).predict(q)
    np.testing.assert_allclose(piped, plain, rtol=0, atol=1e-9)


def test_combine_predictions_means_positions_and_votes_labels():
    a = np.array([[0.0, 0.0, 1, 0], [np.nan] * 4, [2.0, 2.0, 3, 1]])
    b = np.array([[2.0, 4.0, 2, 0], [5.0, 5.0, 1, 1], [np.nan] * 4])
    c = np.array([[4.0, 2.0, 2, 1], [7.0, 7.0, 2, 1], [np.nan] * 4])
    out = combine_predictions([a, b, c])
    np.testing.assert_allclose(out[:, :2], [[2.0, 2.0], [6.0, 6.0], [2.0, 2.0]])
    np.testing.assert_array_equal(out[:, 2], [2, 1, 3])                   # majority; tie -> earliest member (b)
    np.testing.assert_array_equal(out[:, 3], [0, 1, 1])
    assert np.isnan(combine_predictions([a[1:2], a[1:2]])).all()          # NaN in every member stays NaN
    np.testing.assert_allclose(combine_predictions([np.array([1.0, 2.0]), np.array([3.0, 6.0])]), [2.0, 4.0])


def test_ensemble_agrees_with_scikit_learn_voting_regressor():
    from sklearn.ensemble import VotingRegressor
    from sklearn.neighbors import KNeighborsRegressor

    rng = np.random.default_rng(1)
    x = rng.uniform(-90, -30, (120, 6))                              # continuous: no distance ties
    y = rng.uniform(0, 30, 120)
    q = rng.uniform(-90, -30, (30, 6))
    ours = FingerprintEnsemble([("k3", KnnFingerprint(3, p=2)), ("k7", KnnFingerprint(7, p=2))]).fit(x, y)
    ref = VotingRegressor([("k3", KNeighborsRegressor(3)), ("k7", KNeighborsRegressor(7))]).fit(x, y)
    np.testing.assert_allclose(ours.predict(q), ref.predict(q), rtol=1e-9)


def test_ensemble_class_equals_the_function_and_sets_k():
    rng = np.random.default_rng(2)
    x, xy = _radio(rng)
    y = np.column_stack([xy, (xy[:, 0] > 15).astype(float), np.zeros(len(xy))])
    q = x[::5]
    members = [("off", OffsetFingerprint(shifts_db=(-2.0, 0.0, 2.0))), ("cas", CascadeFingerprint(metric="sorensen"))]
    ens = FingerprintEnsemble(members, n_neighbors=4).fit(x, y)
    assert all(e.n_neighbors == 4 for e in ens.estimators_)
    assert members[0][1].n_neighbors == 8                               # the given members are not changed
    by_hand = [type(e)(**{**e.get_params(), "n_neighbors": 4}).fit(x, y).predict(q) for _, e in members]
    np.testing.assert_allclose(ens.predict(q), combine_predictions(by_hand), rtol=0, atol=1e-12)


def test_ensemble_bad_input():
    x, xy = _radio(np.random.default_rng(3))
    with pytest.raises(ValueError, match="at least one"):
        FingerprintEnsemble().fit(x, xy)
    with pytest.raises(ValueError, match=r"\(name, estimator\) pairs"):
        FingerprintEnsemble([KnnFingerprint()]).fit(x, xy)
    with pytest.raises(ValueError, match="target y is None"):
        FingerprintEnsemble([("k", KnnFingerprint())]).fit(x, None)
    ens = FingerprintEnsemble([("k", KnnFingerprint())]).fit(x, xy)
    with pytest.raises(ValueError, match="expecting 12 features"):
        ens.predict(x[:, :5])


def test_check_estimator():
    from sklearn.utils.estimator_checks import check_estimator

    from tests.test_wifi_knn import EXPECTED_FAILED

    check_estimator(ApSelector(), expected_failed_checks=EXPECTED_FAILED)
    members = [("knn", KnnFingerprint(n_neighbors=3, not_heard_dbm=-100.0, rssi_range_dbm=None)),
               ("off", OffsetFingerprint(n_neighbors=3, shifts_db=(0.0,), representation="positive",
                                         metric="minkowski", not_heard_dbm=-100.0, rssi_range_dbm=None))]
    check_estimator(FingerprintEnsemble(members), expected_failed_checks=EXPECTED_FAILED)


@pytest.mark.realdata
def test_ensemble_on_ujiindoorloc(shared_data):
    """The K=5 ensemble row on the official split: an upper bound on the mean error and lower bounds on the hit
    rates, a little looser than the 6.28 m, 95.6 % floor and 100 % building measured on 2026-11-27."""
    from ilocalg.experiments.wifi_ujiindoorloc import load
    from ilocalg.wifi.model_selection import ensemble_pipeline

    train, test = load(shared_data("ujiindoorloc").parent)
    y = np.column_stack([train.xy_m, train.floor, train.building])
    pr = ensemble_pipeline(5).fit(train.rssi_dbm, y).predict(test.rssi_dbm)
    e = np.hypot(pr[:, 0] - test.x_m, pr[:, 1] - test.y_m)
    assert np.isfinite(e).all()
    assert e.mean() < 6.5
    assert np.mean(pr[:, 2] == test.floor) >= 0.95
    assert np.mean(pr[:, 3] == test.building) == 1.0
