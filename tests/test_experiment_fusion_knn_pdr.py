"""Experiment fusion_knn_pdr: KNN + PDR (notebook 08)."""

import pandas as pd

from ilocalg.experiments import fusion_knn_pdr


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


def test_crossover_point():
    assert fusion_knn_pdr.crossover_point([0, 1, 2, 5, 6], [3, 3, 3, 3, 3]) == 3
    assert fusion_knn_pdr.crossover_point([4, 4], [3, 3]) == 0
