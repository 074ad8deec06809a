"""Tests of ilocalg.pdr.k_factor (Weinberg k learned by PSO against a reference distance)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.pdr import k_factor as K
from ilocalg.pdr.step_length import k_from_distance, weinberg_length_m


def _steps(q):
    # steps whose (Amax - Amin)^(1/4) equals q
    return pd.DataFrame({"a_max_mps2": 9.8 + np.asarray(q) ** 4, "a_min_mps2": np.full(len(q), 9.8)})


def test_step_factors_are_weinberg_with_k1():
    st = _steps([1.2, 1.5, 1.3])
    np.testing.assert_allclose(K.step_factors(st), weinberg_length_m(st.a_max_mps2, st.a_min_mps2, 1.0))
    np.testing.assert_allclose(K.step_factors(st), [1.2, 1.5, 1.3])


@pytest.mark.parametrize("fitness", ["total", "per_step"])
def test_pso_agrees_with_closed_form_and_scipy(fitness):
    rng = np.random.default_rng(0)
    q = rng.uniform(1.3, 1.7, 150)
    d = 0.47 * q.sum() * 1.02
    summ, res = K.learn_k(_steps(q), d, fitness, rng=1, pso_settings={"min_fitness": -np.inf})
    assert summ["k_scipy"] == pytest.approx(summ["k_closed"], abs=1e-4)
    assert summ["k_pso"] == pytest.approx(summ["k_closed"], abs=1e-3)
    if fitness == "total":
        assert summ["k_closed"] == pytest.approx(d / q.sum())


def test_thesis_settings_stop_below_min_fitness():
    q = np.full(200, 1.5)
    summ, res = K.learn_k(_steps(q), 150.0, "total", rng=0)
    assert res.converged and summ["fitness_pso_m"] < 0.1
    assert abs(summ["k_pso"] * q.sum() - 150.0) < 0.1
    assert summ["iters"] < 100


def test_per_step_closed_form_is_the_minimiser():
    q = np.random.default_rng(2).uniform(1.2, 1.8, 77)
    d = 60.0
    k = K.closed_form_k(q, d, "per_step")["k_min"]
    grid = np.linspace(k - 0.05, k + 0.05, 2001)
    assert K.per_step_fitness(k, q, d)[0] <= K.per_step_fitness(grid, q, d).min() + 1e-12


def test_bad_input_no_steps_and_gps():
    with pytest.raises(ValueError, match="no steps detected"):
        K.learn_k(_steps([]), 100.0)
    with pytest.raises(ValueError, match="d_gps_m"):
        K.learn_k(_steps([1.0, 1.1]), 0.0)
    with pytest.raises(ValueError, match="fitness"):
        K.learn_k(_steps([1.0, 1.1]), 10.0, fitness="median")


def test_total_closed_form_is_k_from_distance():
    q = np.random.default_rng(5).uniform(1.2, 1.8, 40)
    assert K.closed_form_k(q, 30.0, "total")["k_min"] == k_from_distance(q, 30.0) == 30.0 / q.sum()


def test_per_step_fitness_on_a_hand_worked_walk():
    """Eq. 4.4 per step (the default reading): three steps, GPS distance 3 m (1 m per step).

    q = 1.0, 1.25, 2.0; k = 0.8 gives Weinberg steps 0.8, 1.0, 1.6 m, so |1 - s_j| = 0.2, 0, 0.6 and the
    fitness is their mean, 0.8 / 3 m. The walk-total reading is |3 - 0.8 * 4.25| = 0.4 m.
    """
    q = np.array([1.0, 1.25, 2.0])
    assert K.per_step_fitness(0.8, q, 3.0)[0] == pytest.approx(0.8 / 3)
    assert K.distance_fitness(0.8, q, 3.0) == pytest.approx(0.4)
    # weighted median of (D/N)/q_j = 1, 0.8, 0.5 with weights q: cumulative weights from the smallest ratio
    # 2.0 (0.5), 3.25 (0.8) reach half of 4.25 at 0.8
    assert K.closed_form_k(q, 3.0)["k_min"] == pytest.approx(0.8)
    assert K.FITNESSES[0] == "per_step"


def test_stop_interval_brackets_where_the_pso_stops():
    rng = np.random.default_rng(3)
    q = rng.uniform(1.3, 1.7, 120)
    d = 0.47 * q.sum()
    lo, hi = K.stop_interval(q, d)
    k0 = K.closed_form_k(q, d)["k_min"]
    assert lo < k0 < hi
    assert K.per_step_fitness([lo, hi], q, d) == pytest.approx([0.1, 0.1])
    for r in range(5):
        s, _ = K.learn_k(_steps(q), d, rng=r)
        if s["iters"] < K.PSO_SETTINGS_PAPER["max_iters"]:
            assert lo <= s["k_pso"] <= hi
    # a walk whose best fitness is above minFitness has no stop interval
    assert np.isnan(K.stop_interval(q, d, min_fitness=1e-6)[0])


@pytest.mark.parametrize("fitness", ["total", "per_step"])
def test_learn_k_repeats_gives_each_seeds_learn_k_bit_for_bit(fitness):
    q = np.random.default_rng(3).uniform(1.3, 1.7, 60)
    st, d = _steps(q), 0.47 * q.sum() * 1.05
    summ, runs = K.learn_k_repeats(st, d, fitness, [np.random.default_rng([7, r]) for r in range(6)])
    for r, res in enumerate(runs):
        one, one_res = K.learn_k(st, d, fitness, rng=np.random.default_rng([7, r]))
        assert float(res.x_best[0]) == one["k_pso"] and res.n_iters == one["iters"]
        np.testing.assert_array_equal(res.positions, one_res.positions)
        assert {k: one[k] for k in summ} == summ
    assert len({res.n_iters for res in runs} | {float(res.x_best[0]) for res in runs}) > 2  # the seeds differ
    with pytest.raises(ValueError, match="positive distance"):
        K.learn_k_repeats(st, -1.0, fitness, [0])
