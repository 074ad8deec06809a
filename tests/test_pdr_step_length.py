import numpy as np
import pytest

from ilocalg.pdr import step_length as sl
from ilocalg.pdr.signals import acc_from_log
from ilocalg.sim import gait


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
    rng = np.random.default_rng(4)
    ws = gait.make_walkers(4, 8)
    train = gait.fixed_length_features(gait.training_walks(ws, rng))
    test = gait.fixed_length_features(gait.training_walks(ws, rng))
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


def test_fit_luo_k_recovers_walk_length():
    rng = np.random.default_rng(0)
    # the assumed world: step amplitude an exact function of length, so Luo's model nearly holds
    walks = [sw for _, _, sw in gait.training_walks(gait.make_walkers(2, rng, world="assumed"), rng,
                                                     config=gait.gait_config("assumed"))]
    k, sig = sl.fit_luo_k([(*acc_from_log(sw.imu), sw.steps["length_m"]) for sw in walks])
    assert 0 < sig < 0.5
    tot_est = sum(sl.luo_steps(*acc_from_log(sw.imu), k)["length_m"].sum()
                  for sw in walks)
    tot_true = sum(sw.steps["length_m"].sum() for sw in walks)
    assert tot_est == pytest.approx(tot_true, rel=1e-9)


def test_fit_luo_k_without_steps_fails():
    t = np.arange(200) / 50.0
    still = np.tile([0.0, 0.0, 9.81], (200, 1))
    with pytest.raises(ValueError, match="no step detected"):
        sl.fit_luo_k([(still, t, np.full(3, 0.7))])


def test_k_from_distance_and_fit_scale():
    f = np.array([1.0, 2.0, 3.0])
    assert sl.k_from_distance(f, 12.0) == 2.0
    assert sl.fit_scale(f, 2.0 * f) == pytest.approx(2.0)
    with pytest.raises(ValueError, match="distance_m"):
        sl.k_from_distance(f, 0.0)
    with pytest.raises(ValueError, match="adds up to zero"):
        sl.k_from_distance([], 5.0)
    with pytest.raises(ValueError, match="zero model length"):
        sl.fit_scale([0.0, 0.0], [1.0, 1.0])


def test_fit_step_length_models_and_lengths_on_simulated_walks():
    rng = np.random.default_rng(3)
    ws = gait.make_walkers(3, 5)
    feats = gait.fixed_length_features(gait.training_walks(ws, rng))
    models, fits = sl.fit_step_length_models(feats)
    assert set(models) == {"SLM linear", "SLM quadratic", "Weinberg", sl.LUO_MODEL}
    assert list(fits["model"]) == ["SLM linear", "SLM quadratic"]
    assert fits["rmse_cm"].iloc[1] <= fits["rmse_cm"].iloc[0] + 1e-9   # nested models
    sw = gait.training_walks(ws[:1], rng, (0.6,))[0][2]
    acc, t = acc_from_log(sw.imu)
    from ilocalg.pdr.sam import detect_steps_sam, learn_feature_ranges
    st = detect_steps_sam(acc, t, learn_feature_ranges(feats, 0.01, 0.99))
    kim = sl.kim_mean_abs_mps2(acc, st)
    assert np.all(kim > 0)
    models["Kim"] = 0.5
    est = sl.step_lengths_m(acc, st, models)
    assert list(est.columns) == ["SLM linear", "SLM quadratic", "Weinberg", sl.LUO_MODEL, "Kim"]
    assert abs(est["SLM quadratic"].median() - 0.6) < 0.15
    with pytest.raises(ValueError, match="lack columns"):
        sl.fit_step_length_models(feats.drop(columns="X1"))
