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
