"""Tests of ilocalg.experiments.pso_k_factor."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import pso_k_factor as E
from ilocalg.pdr.step_length import weinberg_length_m
from ilocalg.sim.pso_walks import simulate_pso_walks


def _steps(q):
    # steps whose (Amax - Amin)^(1/4) equals q
    return pd.DataFrame({"a_max_mps2": 9.8 + np.asarray(q) ** 4, "a_min_mps2": np.full(len(q), 9.8)})


def test_step_factors_are_weinberg_with_k1():
    st = _steps([1.2, 1.5, 1.3])
    np.testing.assert_allclose(E.step_factors(st), weinberg_length_m(st.a_max_mps2, st.a_min_mps2, 1.0))
    np.testing.assert_allclose(E.step_factors(st), [1.2, 1.5, 1.3])


@pytest.mark.parametrize("fitness", ["total", "per_step"])
def test_pso_agrees_with_closed_form_and_scipy(fitness):
    rng = np.random.default_rng(0)
    q = rng.uniform(1.3, 1.7, 150)
    d = 0.47 * q.sum() * 1.02
    summ, res = E.learn_k(_steps(q), d, fitness, rng=1, pso_settings={"min_fitness": -np.inf})
    assert summ["k_scipy"] == pytest.approx(summ["k_closed"], abs=1e-4)
    assert summ["k_pso"] == pytest.approx(summ["k_closed"], abs=1e-3)
    if fitness == "total":
        assert summ["k_closed"] == pytest.approx(d / q.sum())


def test_thesis_settings_stop_below_min_fitness():
    q = np.full(200, 1.5)
    summ, res = E.learn_k(_steps(q), 150.0, "total", rng=0)
    assert res.converged and summ["fitness_pso_m"] < 0.1
    assert abs(summ["k_pso"] * q.sum() - 150.0) < 0.1
    assert summ["iters"] < 100


def test_per_step_closed_form_is_the_minimiser():
    q = np.random.default_rng(2).uniform(1.2, 1.8, 77)
    d = 60.0
    k = E.closed_form_k(q, d, "per_step")["k_min"]
    grid = np.linspace(k - 0.05, k + 0.05, 2001)
    assert E.per_step_fitness(k, q, d)[0] <= E.per_step_fitness(grid, q, d).min() + 1e-12


def test_bad_input_no_steps_and_gps():
    with pytest.raises(ValueError, match="no steps detected"):
        E.learn_k(_steps([]), 100.0)
    with pytest.raises(ValueError, match="d_gps_m"):
        E.learn_k(_steps([1.0, 1.1]), 0.0)
    with pytest.raises(ValueError, match="fitness"):
        E.learn_k(_steps([1.0, 1.1]), 10.0, fitness="median")
    with pytest.raises(ValueError, match="prefilter"):
        E.run(prefilter="sg", real=False)
    w = simulate_pso_walks(0)["1"][1]
    gappy = w.gps.drop(index=range(20, 30))
    from ilocalg.gnss import gps_track_length_m
    with pytest.raises(ValueError, match="GPS gap"):
        gps_track_length_m(gappy)


def test_dr_recovers_distance_with_true_like_k():
    w = simulate_pso_walks(0)["1"][0]
    st = E.detect_walk_steps(w, "none")
    d_true = w.route_m
    k = d_true / E.step_factors(st).sum()
    tr = E.dr_track(w, st, k)
    from ilocalg.gnss import path_length_m
    assert path_length_m(tr.lat_deg.to_numpy(), tr.lon_deg.to_numpy()) == pytest.approx(d_true, rel=1e-6)
    # the loop closes to within a few metres (compass noise and bias only)
    assert np.hypot(tr.x_m.iloc[-1] - tr.x_m.iloc[0], tr.y_m.iloc[-1] - tr.y_m.iloc[0]) < 0.1 * d_true


def test_compass_filter_study_ma_beats_sg():
    c = E.compass_filter_study(seed=0, n_logs=30)
    raw, ma, sg = c["rms_deg_mean"]
    assert ma < sg < raw


@pytest.fixture(scope="module")
def fast_run():
    return E.run(seed=0, fast=True, real=False)


def test_run_tables_and_findings(fast_run):
    out = fast_run
    t = out["table_5_2"]
    assert list(t["walker"]) == list(E.PAPER_TABLE_5_2)
    # walk-total fitness: PSO distance equals the GPS distance to within minFitness (plus DR haversine sums)
    assert np.all(np.abs(out["phase1"]["gps_m"] - out["phase1"]["pso_m"]) < 0.2)
    # the thesis's MA(2,2) at 8 Hz loses many steps; without it most are found
    assert out["table_5_2"]["det_steps"].sum() < 0.8 * t["true_steps"].sum()
    assert out["table_5_2_alt"]["det_steps"].sum() > 0.85 * t["true_steps"].sum()
    # closure in % of DR distance does not depend on k
    np.testing.assert_allclose(out["phase2"]["pso_closure_pct"], out["phase2"]["tar_closure_pct"], rtol=1e-3)
    cmp = out["comparison"]
    assert {"paper", "item", "quantity", "paper_value", "reproduced_value"} <= set(cmp.columns)
    assert out["ilc_status"]["ran"].iloc[0] == False  # noqa: E712


def test_run_is_deterministic(fast_run):
    again = E.run(seed=0, fast=True, real=False)
    for k in ("table_5_2", "phase2", "pso_repeat", "compass"):
        pd.testing.assert_frame_equal(fast_run[k], again[k])


def test_ilc_k_study_on_real_data(shared_data):
    p = shared_data("ilc2020_site2_F4")
    res = E.ilc_k_study(p, seed=0)
    s = res["summary"].iloc[0]
    assert s["n_learn_walks"] >= 5 and s["n_test_walks"] >= 5
    assert 0.3 < s["k_pso"] < 1.0
    assert s["k_pso"] == pytest.approx(s["k_closed"], abs=0.01)
