"""The smartphone INS constraints experiment (ilocalg.experiments.ins_constraints)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import ins_constraints


@pytest.fixture(scope="module")
def tables():
    return ins_constraints.run(seed=0, fast=True, reference_grade=False)


def test_stair_handling_table_compares_off_barometer_and_truth(tables):
    st = tables["stair_handling"]
    assert {"N (none)", "N (baro)", "N (truth)"} <= set(st.columns)
    rms = st[st.stat == "rms"].set_index(["phone", "method"])
    # NHC has no WVC: stair handling cannot change it
    nhc = rms.loc[("Samsung", "Filtering + NHC/ZUPT")]
    assert nhc["N (none)"] == nhc["N (baro)"] == nhc["N (truth)"]
    # the iPhone 5S has no barometer: 'baro' is no handling
    ip = rms.loc[("iPhone", "Filtering + WVC/ZUPT")]
    assert ip["N (none)"] == ip["N (baro)"]
    # the default rows process both phones alike (Liao et al. 2016, L202): no stair handling on either
    e = tables["errors"].set_index(["phone", "method", "stat"])
    for phone in ("Samsung", "iPhone"):
        assert e.loc[(phone, "Filtering + WVC/ZUPT", "rms"), "N"] == pytest.approx(
            rms.loc[(phone, "Filtering + WVC/ZUPT"), "N (none)"])


def test_inputs_and_readings_are_reported(tables):
    ws = tables["walk_stats"]
    assert np.all((ws["walker_speed_mps"] > 0.8) & (ws["walker_speed_mps"] < 2.0))
    # the fix comes at the end of a 1 s ranging cycle after the phone gets near the beacon (look-back window 3 s)
    assert np.all((ws["gcp_delay_mean_s"] >= 0) & (ws["gcp_delay_mean_s"] <= 3.0))
    g = tables["gcp_grade"]
    assert set(g["control points"]) == {ins_constraints.GCP_RSSI_LABEL, "Bluetooth RSSI, packet scatter 2 dB",
                                        "Bluetooth RSSI, packet scatter 8 dB",
                                        "Bluetooth (surveyed point, delay, offset)", "ideal (true position + 5 cm)"}
    # the default control-point model is the walk the experiment scores
    e = tables["errors"].set_index(["phone", "method", "stat"])
    d = g[(g["control points"] == ins_constraints.GCP_RSSI_LABEL)].set_index(["phone", "method"])
    assert d.loc[("Samsung", "Filtering + WVC/ZUPT + GCP"), "N"] == pytest.approx(
        e.loc[("Samsung", "Filtering + WVC/ZUPT + GCP", "rms"), "N"])
    assert (g["n_fixes"] >= 1).all() and (g["fix_horizontal_error_mean_m"] >= 0).all()
    r = tables["readings"]
    assert list(r.columns) == ["choice", "paper_line", "text_says", "code_does", "source"]
    assert r["choice"].is_unique and (r["source"].str.len() > 0).all()
    with pytest.raises(ValueError, match="stairs"):
        ins_constraints.run(fast=True, stairs="lidar")


def test_sensor_sensitivity_sweeps_bias_instability_and_jitter(tables):
    ss = tables["sensor_sensitivity"]
    # fast mode: one value at a time (each factor at 10 ms, each jitter at x1, each noise factor at both)
    n = (len(ins_constraints.BIAS_INSTABILITY_FACTORS) + len(ins_constraints.TIME_JITTERS_S) - 1
         + len(ins_constraints.NOISE_FACTORS) - 1)
    assert len(ss) == 2 * n and set(ss["phone"]) == {"Samsung", "iPhone"} and (ss["n_seeds"] == 1).all()
    assert set(ss["noise_factor"]) == set(ins_constraints.NOISE_FACTORS)
    assert (ss.loc[ss.time_jitter_sd_ms == 0, "tag_error_sd_ms"] == 0).all()
    big = ss[ss.time_jitter_sd_ms == 30]
    assert ((big["tag_error_sd_ms"] > 24) & (big["tag_error_sd_ms"] <= 30)).all()
    # the default cell (x1, 10 ms) is the experiment's own Filtering + WVC/ZUPT + GCP row
    e = tables["errors"].set_index(["phone", "method", "stat"])
    cell = ss[(ss.bias_instability_factor == 1.0) & (ss.time_jitter_sd_ms == 10.0)
              & (ss.noise_factor == 3.0)].set_index("phone")
    for phone in ("Samsung", "iPhone"):
        for ax in ("N", "E", "H"):
            assert cell.loc[phone, ax] == pytest.approx(e.loc[(phone, "Filtering + WVC/ZUPT + GCP", "rms"), ax])
    assert np.isfinite(ss[["N", "E", "H", "Heading"]].to_numpy()).all()
    with pytest.raises(ValueError, match="seeds"):
        ins_constraints.sensor_sensitivity([])


def test_gait_sensitivity_moves_each_published_mean_by_one_sd(tables):
    g = tables["gait_sensitivity"].set_index(["phone", "walker"])
    assert len(g) == 2 * len(ins_constraints.GAIT_VARIANTS)
    for phone in ("Samsung", "iPhone"):
        # the walker's draws are paired: the level speed moves by exactly one between-walker sd
        dv = g.loc[(phone, "level speed mean + 1 sd"), "speed_mps"] - g.loc[(phone, "published"), "speed_mps"]
        assert dv == pytest.approx(0.16)
        # a walk ratio one sd lower means a higher cadence at the same speed
        assert g.loc[(phone, "walk ratio - 1 sd"), "cadence_hz"] > g.loc[(phone, "published"), "cadence_hz"]
    e = tables["errors"].set_index(["phone", "method", "stat"])
    assert g.loc[("Samsung", "published"), "N"] == pytest.approx(
        e.loc[("Samsung", "Filtering + WVC/ZUPT + GCP", "rms"), "N"])


def test_error_budget_changes_one_source_at_a_time(tables):
    b = tables["error_budget"]
    assert set(b["table"]) >= {"gcp_grade", "sensor_grade", "stair_handling", "sensor_sensitivity",
                               "gait_sensitivity"}
    np.testing.assert_allclose(b["delta_horizontal_m"], b["horizontal"] - b["baseline_horizontal"])
    np.testing.assert_allclose(b["horizontal"], np.hypot(b["N"], b["E"]))
    # the control-point rows are measured against the default walk's own errors
    e = tables["errors"].set_index(["phone", "method", "stat"])
    for r in b[b["table"] == "gcp_grade"].itertuples():
        assert r.baseline_N == pytest.approx(e.loc[(r.phone, r.method, "rms"), "N"])
    # the paper's values ride along as labelled references (Table 4: Samsung GCP filter N 1.23 m)
    s = b[(b.phone == "Samsung") & (b.method == "Filtering + WVC/ZUPT + GCP")]
    assert (s["paper_N"] == 1.23).all()


def test_sweep_runs_without_side_studies_give_the_same_results(tables):
    """The seed sweep and the claims' samples run without the side studies (manifest.SWEEP_KWARGS): every table
    they return, and so the long results the sweep keeps, must be those of the run with them."""
    from ilocalg.papers.claims import tables_to_long
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    lite = ins_constraints.run(seed=0, fast=True, reference_grade=False, **SWEEP_KWARGS["ins_constraints"])
    assert "gcp_grade" not in lite and "error_budget" not in lite
    for name, df in lite.items():
        pd.testing.assert_frame_equal(df, tables[name], check_exact=True)
    pd.testing.assert_frame_equal(tables_to_long(lite), tables_to_long(tables), check_exact=True)
