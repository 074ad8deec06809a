"""Experiment fusion_iloc_kf: the i-Loc KF on the simulated floor (notebook 07)."""

import numpy as np
import pandas as pd

from ilocalg.experiments import fusion_iloc_kf
from ilocalg.papers import comparison_table


def test_fast_run_is_deterministic_and_kf_beats_both_inputs():
    a = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=())
    b = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=())
    for name in ("test_points", "summary", "cdf", "r_table", "gating", "comparison", "track_example"):
        pd.testing.assert_frame_equal(a[name], b[name])
    m = a["summary"].set_index("method")["mean_error_m"]
    kf = m["KF (R per point, calibrated)"]
    assert kf < m["PTS"] and kf < m["Wi-Fi only"]
    assert m["KF (R per point, calibrated) + RTS"] < kf           # smoothing helps on a whole walk
    assert (a["summary"]["n"] == 2 * 28).all()
    g = a["gating"]
    assert (g["gated_out"] <= g["fixes"]).all() and (g["fixes"] == 28).all()
    comp = comparison_table(a["comparison"].to_dict("records"))
    assert {"paper_value", "reproduced_value"} <= set(comp.columns)
    assert "KF" in fusion_iloc_kf.findings(a)
    assert (a["r_table"]["calibrated_var_m2"] >= 4.0 / 12.0 - 1e-12).all()


def test_score_points_wifi_is_the_fix():
    true = np.array([[0.0, 0.0], [1.0, 0.0]])
    fix = np.array([[3.0, 4.0], [1.0, 0.0]])
    tracks = {"A": np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]])}
    tp = fusion_iloc_kf.score_points(tracks, np.array([0, 2]), true, fix)
    e = tp.set_index(["method", "point"])["error_m"]
    assert e[("Wi-Fi only", 1)] == 5.0 and e[("Wi-Fi only", 2)] == 0.0
    assert e[("A", 1)] == 0.0 and e[("A", 2)] == 1.0
