"""Experiment fusion_iloc_kf: the i-Loc KF on the simulated floor (notebook 07)."""

import numpy as np
import pandas as pd

from ilocalg.experiments import fusion_iloc_kf
from ilocalg.papers import comparison_table


def test_fast_run_is_deterministic_and_reports_every_reading():
    a = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=())
    b = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=())
    for name in ("test_points", "summary", "cdf", "r_table", "gating", "comparison", "track_example", "readings"):
        pd.testing.assert_frame_equal(a[name], b[name])
    m = a["summary"].set_index("method")["mean_error_m"]
    # Wi-Fi only, PDR only (from the Wi-Fi start and the true start), and the KF with each R reading and
    # the other Table 4 reading
    assert {"Wi-Fi only", "PTS (Wi-Fi start)", "PTS (true start)", "KF (R calibrated)", "KF (R = thesis Table 5)",
            "KF (R constant)", "KF (R calibrated, Table 4 read as m2)"} <= set(m.index)
    assert (a["summary"]["n"] == 2 * 28).all()  # 2 walkers x 28 test points
    g = a["gating"]
    assert (g["gated_out"] <= g["fixes"]).all() and (g["fixes"] <= 28).all()
    comp = comparison_table(a["comparison"].to_dict("records"))
    assert {"paper_value", "reproduced_value"} <= set(comp.columns)
    assert "KF" in fusion_iloc_kf.findings(a)
    assert (a["r_table"]["calibrated_var_m2"] >= 4.0 / 12.0 - 1e-12).all()
    assert {"R", "Q", "start", "Wi-Fi fix"} <= set(a["readings"]["choice"])
    assert list(a["latency_sweep"]["scan_latency_s"]) == [0.0, 1.0, 2.0, 3.0]
    c = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=(), latencies_s=())
    pd.testing.assert_frame_equal(a["summary"], c["summary"])  # the sweep draws after the main tables


def test_filter_starts_where_it_is_told_and_a_scan_without_fix_is_skipped():
    pdr = {"state_t_s": np.array([0.0, 1.0, 2.0]), "step_m": np.array([0.7, 0.7]), "theta_rad": np.zeros(2)}
    fix = np.array([[0.7, 0.0], [np.nan, np.nan]])
    tracks, info = fusion_iloc_kf.run_filters(np.array([0.0, 0.0]), pdr, np.array([1.0, 2.0]), fix,
                                              {"R": np.array([1.0, 1.0])}, P0_var_m2=1.0)
    np.testing.assert_allclose(tracks["PTS"][0], [0.0, 0.0])
    np.testing.assert_allclose(tracks["PTS"][-1], [1.4, 0.0])
    assert info["n_fixes"] == 1


def test_score_points_wifi_is_the_fix():
    true = np.array([[0.0, 0.0], [1.0, 0.0]])
    fix = np.array([[3.0, 4.0], [1.0, 0.0]])
    tracks = {"A": np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]])}
    tp = fusion_iloc_kf.score_points(tracks, np.array([0, 2]), true, fix)
    e = tp.set_index(["method", "point"])["error_m"]
    assert e[("Wi-Fi only", 1)] == 5.0 and e[("Wi-Fi only", 2)] == 0.0
    assert e[("A", 1)] == 0.0 and e[("A", 2)] == 1.0
