"""Experiment fusion_knn_pdr: KNN + PDR (notebook 08)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import fusion_knn_pdr


def test_fast_run_is_deterministic_and_structured():
    a = fusion_knn_pdr.run(seed=0, fast=True)
    b = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False)
    for name in ("test_points", "summary", "per_point", "calibration", "comparison", "adjust_sweep"):
        pd.testing.assert_frame_equal(a[name], b[name])
    m = a["summary"].set_index("method")["mean_error_m"]
    assert {fusion_knn_pdr.COMBINED, fusion_knn_pdr.KF_ALT, "PDR only", "Wi-Fi only (KNN)"} <= set(m.index)
    # the default combination is the adjust_sweep row of the default weight
    aw = a["adjust_sweep"].set_index("weight")["mean_error_m"]
    assert aw[0.5] == pytest.approx(m[fusion_knn_pdr.COMBINED], rel=1e-12)  # same track, summed in another order
    assert list(a["readings"].columns) == ["choice", "paper_line", "text_says", "code_does", "source"]
    assert not any("sec. 3.1" in str(q) and "KF" in str(q) for q in a["comparison"]["quantity"])
    pp = a["per_point"]
    ex = a["track_example"]
    start_pdr = ex[ex["method"] == "PDR only"].iloc[0][["x_m", "y_m"]].to_numpy(float)
    start_true = ex[ex["method"] == "truth"].iloc[0][["x_m", "y_m"]].to_numpy(float)
    assert np.allclose(start_pdr, start_true)             # PDR starts at the true start (paper, L235)
    assert pp["PDR only"].iloc[-1] > pp["PDR only"].iloc[1]   # and drifts
    assert "Combined" in fusion_knn_pdr.findings(a)


def test_crossover_point():
    assert fusion_knn_pdr.crossover_point([0, 1, 2, 5, 6], [3, 3, 3, 3, 3]) == 3
    assert fusion_knn_pdr.crossover_point([4, 4], [3, 3]) == 0
