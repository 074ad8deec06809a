"""Study of PSO convergence vs swarm size and inertia schedule (ilocalg.experiments.study_pso)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import study_pso
from ilocalg.experiments.pso_k_factor import PSO_SETTINGS_PAPER


def _q(seed=0, **p):
    df = study_pso.run(seed=seed, fast=True, **p)["sweep_pso"]
    return dict(zip(df["quantity"], df["value"], strict=True))


def test_same_seed_same_table():
    a = study_pso.run(seed=2, fast=True, n_particles=5, schedule="const0.7")["sweep_pso"]
    b = study_pso.run(seed=2, fast=True, n_particles=5, schedule="const0.7")["sweep_pso"]
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert study_pso.SCHEDULES["paper"] == (PSO_SETTINGS_PAPER["w_init"], PSO_SETTINGS_PAPER["w_final"])


def test_quantities_are_consistent_and_more_particles_help():
    small = [_q(s, n_particles=2) for s in (0, 1)]
    big = [_q(s, n_particles=30) for s in (0, 1)]
    for q in small + big:
        assert 0.0 <= q["success rate"] <= 100.0
        assert q["iterations"] <= PSO_SETTINGS_PAPER["max_iters"]
        if q["success rate"] > 0:
            # failed runs count as maxIters, so the all-runs mean is never below the successful runs' mean
            assert q["iterations to minFitness"] <= q["iterations"] + 1e-9
            assert q["fitness evaluations per success"] >= q["iterations to minFitness"]
    assert np.mean([q["success rate"] for q in big]) > np.mean([q["success rate"] for q in small])
    assert np.mean([q["final |k - k*|"] for q in big]) < np.mean([q["final |k - k*|"] for q in small])


def test_all_runs_converge_means_iterations_equal():
    q = _q(0, n_particles=30, schedule="const0.7")
    assert q["success rate"] == 100.0
    assert q["iterations"] == pytest.approx(q["iterations to minFitness"])


def test_bad_parameters_are_clear_errors():
    with pytest.raises(ValueError, match="schedule"):
        study_pso.run(schedule="linear")
    with pytest.raises(ValueError, match="n_particles"):
        study_pso.run(n_particles=0)
