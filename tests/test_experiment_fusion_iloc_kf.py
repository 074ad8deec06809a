"""Experiment fusion_iloc_kf: the i-Loc KF on the simulated floor (notebook 07)."""

import pandas as pd
import pytest

from ilocalg.experiments import fusion_iloc_kf
from ilocalg.papers import comparison_table


@pytest.fixture(scope="module")
def fast_runs():
    """A fast run with every table, and the same run as the seed sweep runs it (manifest.SWEEP_KWARGS)."""
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    return (fusion_iloc_kf.run(seed=0, fast=True),
            fusion_iloc_kf.run(seed=0, fast=True, **SWEEP_KWARGS["fusion_iloc_kf"]))


def test_sweep_runs_without_the_side_sweeps_give_the_same_results(fast_runs):
    """The seed sweep and the claims' samples run without the Wi-Fi estimator and scan-latency sweeps: those two
    tables are empty, every other table, and so the long results the sweep keeps, must be those of the full run."""
    from ilocalg.papers.claims import tables_to_long

    a, lite = fast_runs
    assert list(lite) == list(a)
    skipped = {"by_wifi_method", "latency_sweep"}
    assert all(lite[name].empty and not a[name].empty for name in skipped)
    for name, df in lite.items():
        if name not in skipped:
            pd.testing.assert_frame_equal(df, a[name], check_exact=True)
    pd.testing.assert_frame_equal(tables_to_long(lite), tables_to_long(a), check_exact=True)
    # the run's own estimator in the estimator sweep is the run's result
    row = a["by_wifi_method"].set_index("wifi_method").loc["Simplified-Horus"]
    m = a["summary"].set_index("method")["mean_error_m"]
    assert row["kf_mean_m"] == pytest.approx(m[fusion_iloc_kf.MAIN], rel=1e-12)
    assert row["wifi_only_mean_m"] == pytest.approx(m["Wi-Fi only"], rel=1e-12)


def test_fast_run_is_deterministic_and_reports_every_reading(fast_runs):
    a, c = fast_runs
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
    pd.testing.assert_frame_equal(a["summary"], c["summary"])  # the sweeps draw after the main tables
