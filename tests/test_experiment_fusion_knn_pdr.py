"""Experiment fusion_knn_pdr: KNN + PDR (notebook 08)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import fusion_knn_pdr
from ilocalg.experiments.pdr_step_features import training_walks
from ilocalg.sim import gait


def test_fast_run_is_deterministic_and_combined_beats_pdr_only():
    a = fusion_knn_pdr.run(seed=0, fast=True)
    b = fusion_knn_pdr.run(seed=0, fast=True)
    for name in ("test_points", "summary", "per_point", "calibration", "comparison"):
        pd.testing.assert_frame_equal(a[name], b[name])
    m = a["summary"].set_index("method")["mean_error_m"]
    assert m["combined (KF)"] < m["PDR only"]
    pp = a["per_point"]
    assert pp["PDR only"].iloc[0] == 0.0                  # PDR starts at the true start (paper)
    assert pp["PDR only"].iloc[-1] > pp["PDR only"].iloc[1]   # and drifts
    assert "Combined" in fusion_knn_pdr.findings(a)


def test_fit_luo_k_recovers_walk_length():
    rng = np.random.default_rng(0)
    walks = [sw for _, _, sw in training_walks(gait.make_walkers(2, rng), rng)]
    k, sig = fusion_knn_pdr.fit_luo_k(walks)
    assert 0 < sig < 0.5
    tot_est = sum(fusion_knn_pdr.pdr_004(sw.imu.iloc[:, :3].to_numpy(), sw.imu.index.to_numpy(), k)["length_m"].sum()
                  for sw in walks)
    tot_true = sum(sw.steps["length_m"].sum() for sw in walks)
    assert tot_est == pytest.approx(tot_true, rel=1e-9)


def test_crossover_point():
    assert fusion_knn_pdr.crossover_point([0, 1, 2, 5, 6], [3, 3, 3, 3, 3]) == 3
    assert fusion_knn_pdr.crossover_point([4, 4], [3, 3]) == 0
