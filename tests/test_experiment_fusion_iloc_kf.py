"""Experiment fusion_iloc_kf: the i-Loc KF on the simulated floor (notebook 07)."""

import pandas as pd
import pytest

from ilocalg.experiments import fusion_iloc_kf
from ilocalg.papers import comparison_table


def test_fast_run_is_deterministic_and_reports_every_reading():
    a = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=())
    b = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=(), budget=False)
    for name in ("test_points", "summary", "cdf", "r_table", "gating", "comparison", "track_example", "readings"):
        pd.testing.assert_frame_equal(a[name], b[name])
    m = a["summary"].set_index("method")["mean_error_m"]
    # Wi-Fi only, PDR only (from the Wi-Fi start and the true start), and the KF with each R reading and
    # the other Table 4 reading
    assert {"Wi-Fi only", "PTS (Wi-Fi start)", "PTS (true start)", "KF (R calibrated)", "KF (R = thesis Table 5)",
            "KF (R constant)", "KF (R calibrated, Table 4 read as m2)"} <= set(m.index)
    assert (a["summary"]["n"] == 2 * 28).all()  # 2 walkers x 28 test points
    g = a["gating"]
    assert (g["gated_out"] <= g["fixes"]).all() and (g["fixes"] >= 10).all()
    # a fix enters after its scan has ended: its RSSI values are older than 0 s and younger than the latency
    assert ((g["mean_fix_age_at_entry_s"] > 0) & (g["mean_fix_age_at_entry_s"] < 2.0)).all()
    comp = comparison_table(a["comparison"].to_dict("records"))
    assert {"paper_value", "reproduced_value"} <= set(comp.columns)
    assert "KF" in fusion_iloc_kf.findings(a)
    assert (a["r_table"]["calibrated_var_m2"] >= 4.0 / 12.0 - 1e-12).all()
    assert {"R", "Q", "start", "Wi-Fi fix", "scoring", "error budget"} <= set(a["readings"]["choice"])
    assert "L777" in a["readings"].set_index("choice").loc["Wi-Fi fix", "paper_line"]
    # the budget's baseline is the main result, and with every source true little error is left
    bud = a["budget"]
    base = bud[bud["replaced_by_truth"] == "none (as simulated)"].set_index("method")["mean_error_m"]
    assert base[fusion_iloc_kf.MAIN] == pytest.approx(m[fusion_iloc_kf.MAIN], rel=1e-9)
    assert base["PTS (Wi-Fi start)"] == pytest.approx(m["PTS (Wi-Fi start)"], rel=1e-9)
    allt = bud[bud["replaced_by_truth"] == "all of them"].set_index("method")["mean_error_m"]
    assert (allt < 0.2 * base).all()
    meas = a["measures"]
    assert "KF mean / Wi-Fi only mean" in set(meas["quantity"])
    assert not set(meas["quantity"]) & set(a["comparison"]["quantity"])
    assert not meas.duplicated(["quantity", "item"]).any()
    assert list(a["latency_sweep"]["scan_latency_s"]) == [0.0, 1.0, 2.0, 3.0]
    c = fusion_iloc_kf.run(seed=0, fast=True, wifi_methods=(), latencies_s=())
    pd.testing.assert_frame_equal(a["summary"], c["summary"])  # the sweep draws after the main tables
