import numpy as np
import pytest

from ilocalg.pdr import step_length as sl


def test_weinberg_formula_and_k_fit():
    rng = np.random.default_rng(1)
    hi = rng.uniform(2, 8, 200)
    lo = -rng.uniform(2, 8, 200)
    d = sl.weinberg_length_m(hi, lo, 0.5)
    np.testing.assert_allclose(d, 0.5 * (hi - lo) ** 0.25)
    assert sl.fit_weinberg_k(hi, lo, d) == pytest.approx(0.5)


def test_kim_and_luo():
    np.testing.assert_allclose(sl.kim_length_m([1.0, 8.0]), [0.98, 1.96])
    np.testing.assert_allclose(sl.luo_length_m([3.0], [2.0], 0.1), [0.1 * (3.5 + 1.0)])


def test_slm_recovers_coefficients_and_class_agrees():
    rng = np.random.default_rng(0)
    A = rng.uniform(4, 17, 300)
    X = rng.uniform(4, 38, 300)
    p = np.array([0.5, -0.004, 0.0075, -0.0002, 0.0015, -0.0001])
    y = sl.slm_design(A, X, "quadratic") @ p + rng.normal(0, 0.01, A.size)
    fit = sl.fit_slm(A, X, y, "quadratic")
    assert fit.rmse_m < 0.012
    np.testing.assert_allclose(fit.p, p, atol=5e-3)
    lin = sl.fit_slm(A, X, y, "linear")
    assert lin.rmse_m >= fit.rmse_m
    est = sl.SLM("quadratic").fit(A, X, y)
    np.testing.assert_allclose(est.predict(A, X), sl.slm_length_m(A, X, fit.p))


def test_bad_input():
    with pytest.raises(ValueError, match="a_max_mps2 must be >= a_min_mps2"):
        sl.weinberg_length_m([1.0], [2.0], 0.5)
    with pytest.raises(ValueError, match="a_min_mps2 must be finite"):
        sl.weinberg_length_m([1.0], [np.nan], 0.5)
    with pytest.raises(ValueError, match="kind must be"):
        sl.slm_design([1.0], [1.0], "cubic")
    with pytest.raises(ValueError, match="at least 6 steps"):
        sl.fit_slm([1, 2], [1, 2], [0.5, 0.6])
    with pytest.raises(ValueError, match="not fitted"):
        sl.SLM().predict([1.0], [1.0])


def test_models_on_simulated_fixed_length_walks():
    from ilocalg.experiments.pdr_step_features import fixed_length_features, training_walks
    from ilocalg.sim import gait

    rng = np.random.default_rng(4)
    ws = gait.make_walkers(4, 8)
    train = fixed_length_features(training_walks(ws, rng))
    test = fixed_length_features(training_walks(ws, rng))
    quad = sl.fit_slm(train["A"], train["X1"], train["length_m"], "quadratic")
    k = sl.fit_weinberg_k(train["a_max_mps2"], train["a_min_mps2"], train["length_m"])
    L = test["length_m"].to_numpy()
    err_slm = np.abs(sl.slm_length_m(test["A"], test["X1"], quad.p) - L) / L
    err_w = np.abs(sl.weinberg_length_m(test["a_max_mps2"], test["a_min_mps2"], k) - L) / L
    assert 0.3 < k < 0.6
    assert err_slm.mean() < 0.25 and err_w.mean() < 0.25
    # both beat a constant guess of the mean training length
    err_const = np.abs(train["length_m"].mean() - L) / L
    assert err_slm.mean() < err_const.mean() and err_w.mean() < err_const.mean()
