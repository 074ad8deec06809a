import numpy as np
import pytest

from ilocalg import metrics


def test_horizontal_error_is_euclidean():
    e = metrics.horizontal_error_m([[3.0, 4.0], [0.0, 0.0]], [[0.0, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(e, [5.0, 0.0])


def test_horizontal_error_rejects_shape_mismatch_and_nan_truth():
    with pytest.raises(ValueError, match="shape"):
        metrics.horizontal_error_m(np.zeros((3, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="NaN"):
        metrics.horizontal_error_m(np.zeros((1, 2)), [[np.nan, 0.0]])


def test_summary_matches_numpy_definitions():
    rng = np.random.default_rng(0)
    e = rng.gamma(2.0, 2.0, 1001)
    s = metrics.summary(e)
    assert s["n"] == 1001
    assert s["mean_m"] == pytest.approx(e.mean())
    assert s["median_m"] == pytest.approx(np.median(e))
    assert s["p80_m"] == pytest.approx(np.percentile(e, 80))
    assert s["rms_m"] == pytest.approx(np.sqrt((e**2).mean()))
    assert s["max_m"] == e.max()
    assert s["median_m"] <= s["p75_m"] <= s["p80_m"] <= s["p95_m"] <= s["max_m"]


def test_summary_refuses_nan_and_empty():
    with pytest.raises(ValueError, match="NaN"):
        metrics.summary([1.0, np.nan])
    with pytest.raises(ValueError, match="no errors"):
        metrics.summary([])


def test_error_cdf_is_monotone_and_ends_at_one():
    cdf = metrics.error_cdf([3.0, 1.0, 2.0])
    assert list(cdf["error_m"]) == [1.0, 2.0, 3.0]
    assert cdf["fraction"].iloc[-1] == 1.0
    assert np.all(np.diff(cdf["fraction"]) > 0)


def test_hit_rate_and_penalised_error():
    assert metrics.hit_rate([0, 1, 2, 2], [0, 1, 1, 2]) == 0.75
    e = metrics.penalised_error_m([[0, 0], [0, 0]], [[3, 4], [0, 0]], floor_pred=[1, 3], floor_true=[1, 1],
                                  building_pred=[0, 1], building_true=[0, 0])
    np.testing.assert_allclose(e, [5.0, 2 * 15.0 + 50.0])


def test_summarise_by_method_keeps_order_and_matches_numpy():
    import pandas as pd

    from ilocalg.metrics import summarise_by_method

    rng = np.random.default_rng(0)
    e = {"B": rng.uniform(0, 5, 50), "A": rng.uniform(0, 9, 40)}
    pts = pd.concat([pd.DataFrame({"method": m, "error_m": v}) for m, v in e.items()], ignore_index=True)
    summ, cdf = summarise_by_method(pts)
    assert list(summ["method"]) == ["B", "A"]
    for m, v in e.items():
        r = summ.set_index("method").loc[m]
        assert r["mean_error_m"] == pytest.approx(v.mean()) and r["max_error_m"] == v.max()
        assert r["p90_error_m"] == pytest.approx(np.quantile(v, 0.9)) and r["n"] == v.size
    assert set(cdf["method"]) == {"A", "B"}
    with pytest.raises(ValueError, match="error_m"):
        summarise_by_method(pts.drop(columns="error_m"))


def test_mean_horizontal_error_counts_missing_positions():
    from ilocalg.metrics import mean_horizontal_error_m

    t = np.array([[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]])
    p = np.array([[0.0, 1.0], [np.nan, np.nan], [6.0, 8.0]])
    # the missing row costs the diagonal of the truth's bounding box (10 m) by default
    assert mean_horizontal_error_m(t, p) == pytest.approx((1.0 + 10.0 + 0.0) / 3)
    assert mean_horizontal_error_m(t, p, missing_error_m=50.0) == pytest.approx(51.0 / 3)
    assert mean_horizontal_error_m(t, t) == 0.0
    with pytest.raises(ValueError, match="y_pred has shape"):
        mean_horizontal_error_m(t, p[:2])


def test_scorer_keeps_grid_search_finite_with_unlocatable_scans():
    """Folds whose test scans hear only APs unknown to their training part still get a finite score."""
    from sklearn.model_selection import GridSearchCV, KFold

    from ilocalg.metrics import horizontal_error_scorer
    from ilocalg.wifi import KnnFingerprint

    rng = np.random.default_rng(0)
    n = 60
    xy = rng.uniform(0, 30, (n, 2))
    ap = np.array([[0.0, 0.0], [30.0, 0.0], [0.0, 30.0], [30.0, 30.0]])
    X = -40 - 30 * np.log10(1 + np.hypot(*(xy[:, None, :] - ap[None]).transpose(2, 0, 1))) + rng.normal(0, 2, (n, 4))
    X = np.column_stack([X, np.full(n, np.nan)])
    X[-5:, :4] = np.nan                 # the last fold's scans hear only AP 4, never heard in training
    X[-5:, 4] = -60.0
    gs = GridSearchCV(KnnFingerprint(not_heard_dbm=-110.0), {"n_neighbors": [1, 3]},
                      scoring=horizontal_error_scorer(), cv=KFold(12), error_score="raise").fit(X, xy)
    scores = gs.cv_results_["split11_test_score"]
    assert np.isfinite(gs.cv_results_["mean_test_score"]).all() and np.isfinite(scores).all()
    diag = np.hypot(*(xy[-5:].max(axis=0) - xy[-5:].min(axis=0)))
    np.testing.assert_allclose(scores, -diag)           # every scan of that fold unlocated: the stated cost
