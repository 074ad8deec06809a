"""Tests of ilocalg.experiments.pso_k_factor."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import pso_k_factor as E
from ilocalg.pdr import k_factor as K
from ilocalg.pdr import k_walks as KW
from ilocalg.sim.pso_walks import simulate_pso_walks


def test_bad_prefilter_and_gps_gap():
    with pytest.raises(ValueError, match="prefilter"):
        E.run(prefilter="sg", real=False)
    w = simulate_pso_walks(0)["1"][1]
    gappy = w.gps.drop(index=range(20, 30))
    from ilocalg.gnss import gps_track_length_m
    with pytest.raises(ValueError, match="GPS gap"):
        gps_track_length_m(gappy)


def test_dr_recovers_distance_with_true_like_k():
    w = simulate_pso_walks(0)["1"][0]
    st = KW.detect_walk_steps(w.imu)
    d_true = w.route_m
    k = d_true / K.step_factors(st).sum()
    tr = KW.dr_track(w.imu, w.gps, st, k, w.origin_deg)
    from ilocalg.gnss import path_length_m
    assert path_length_m(tr.lat_deg.to_numpy(), tr.lon_deg.to_numpy()) == pytest.approx(d_true, rel=1e-6)
    # the loop closes to within a few metres (compass noise and bias only)
    assert np.hypot(tr.x_m.iloc[-1] - tr.x_m.iloc[0], tr.y_m.iloc[-1] - tr.y_m.iloc[0]) < 0.1 * d_true


def test_compass_filter_study_ma_beats_sg():
    c = E.compass_filter_study(seed=0, n_logs=30)
    raw, ma, sg = c["rms_deg_mean"]
    assert ma < sg < raw


@pytest.fixture(scope="module")
def fast_run():
    return E.run(seed=0, fast=True, real=False)


def test_run_tables_and_findings(fast_run):
    out = fast_run
    t = out["table_5_2"]
    assert list(t["walker"]) == list(E.PAPER_TABLE_5_2)
    # Table 5-2's accuracy: 1 - |GPS - PSO| / GPS on the learning walk itself (thesis L927-935)
    p1 = out["phase1"]
    np.testing.assert_allclose(t["acc_pct"], 100 * (1 - (p1["gps_m"] - p1["pso_m"]).abs() / p1["gps_m"]))
    # the PSO stops anywhere in the interval where the fitness is below minFitness: its k lies there
    sr = out["stop_rule"]
    stopped = sr["pso_stopped_by"] == "minFitness"
    assert ((sr.loc[stopped, "k_pso"] >= sr.loc[stopped, "k_stop_lo"])
            & (sr.loc[stopped, "k_pso"] <= sr.loc[stopped, "k_stop_hi"])).all()
    assert (sr["k_stop_lo"] <= sr["k_closed"]).all() and (sr["k_closed"] <= sr["k_stop_hi"]).all()
    # closure in % of DR distance does not depend on k
    np.testing.assert_allclose(out["phase2"]["pso_closure_pct"], out["phase2"]["tar_closure_pct"], rtol=1e-3)
    cmp = out["comparison"]
    assert {"paper", "item", "quantity", "paper_value", "reproduced_value"} <= set(cmp.columns)
    assert out["ilc_status"]["ran"].iloc[0] == False  # noqa: E712
    assert list(out["readings"].columns) == ["choice", "paper_line", "text_says", "code_does", "source"]
    # the default row of the sensitivity table is the default run's Table 5-2
    sens = out["sensitivity"].iloc[0]
    assert sens["k_pso_mean"] == pytest.approx(t["k_pso"].mean())
    assert sens["det_over_true_steps"] == pytest.approx(t["det_steps"].sum() / t["true_steps"].sum())


def test_text_reading_is_the_default_and_no_ma_the_labelled_alternative(fast_run):
    # thesis L692/L718: MA before the step detector is the default; no MA is the alternative reading
    assert fast_run["sensitivity"]["prefilter"].iloc[0] == "ma2"
    cmp = fast_run["comparison"]
    alt = cmp[cmp["item"].str.contains(r"\(none, static band")]
    assert len(alt) and alt["note"].str.startswith("alternative reading").all()
    default = cmp[cmp["item"].str.contains(r"\(ma2, static band")]
    assert len(default) and not default["note"].str.contains("alternative reading").any()
    # the MA shrinks the step amplitudes, so the learned k rises (the same walks, the same GPS distance)
    assert (fast_run["table_5_2"]["k_pso"].mean() > fast_run["table_5_2_no_ma"]["k_pso"].mean())


def test_sensitivity_sweeps_band_scatter_and_gps():
    sens = E.sensitivity(0, variants=[v for v in E.SENSITIVITY_VARIANTS
                                      if v[0].startswith(("default", "band 0", "accelerometer", "GPS tau"))])
    by = sens.set_index("variant")
    # the band follows the accelerometer noise of the static log
    assert (by.loc["accelerometer noise 0.05 m/s^2 (band follows)", "band_mps2"]
            < by.loc["default (text reading)", "band_mps2"]
            < by.loc["accelerometer noise 0.20 m/s^2 (band follows)", "band_mps2"])
    assert by.loc["band 0 (no rejection)", "band_mps2"] == 0.0
    # a band of 0 rejects nothing: at least as many steps as with the static band
    assert by.loc["band 0 (no rejection)", "det_over_true_steps"] >= by.loc["default (text reading)",
                                                                            "det_over_true_steps"]
    # the 1 Hz GPS track's length bias shrinks as its error becomes more correlated (smoother track)
    g = [by.loc[f"GPS tau {t} s", "gps_over_true_mean"] for t in (5, 60, 300)]
    assert g[0] > g[1] > g[2] >= 0.99


def test_static_band_is_the_static_log_rms():
    b = E.static_band_mps2(0, "none")
    assert 0.05 < b < 0.2                           # the simulated sensor noise, 0.10 m/s^2, plus quantisation
    assert E.static_band_mps2(0, "ma2") < b         # the moving average lowers the static RMS
    w = simulate_pso_walks(0)["1"][0]
    wide = KW.detect_walk_steps(w.imu, "none", band_mps2=10.0)
    assert len(wide) == 0                           # a band wider than the signal rejects every extremum
    with pytest.raises(ValueError, match="prefilter"):
        KW.detect_walk_steps(w.imu, "ma")
    with pytest.raises(ValueError, match="walk A1/x: no GPS fix"):
        KW.dr_track(w.imu, w.gps.iloc[:0], wide, 0.5, w.origin_deg, "A1/x")


def test_readings_follow_the_runs_assumed_values():
    default = E.readings().set_index("choice")
    changed = E.readings(acc_noise_mps2=0.2, gps_open_tau_s=60.0, step_amp_cv=0.27, route_scale=1.05)
    changed = changed.set_index("choice")
    assert "0.10 m/s^2 assumed" in default.loc["+-RMS band of Fig 3.9", "source"]
    assert "0.20 m/s^2 assumed" in changed.loc["+-RMS band of Fig 3.9", "source"]
    assert "tau 20 s" in default.loc["GPS error", "code_does"] and "tau 60 s" in changed.loc["GPS error", "code_does"]
    assert "CV 0.27 per step" in changed.loc["step-to-step scatter", "code_does"]
    assert changed.loc["true route length", "code_does"].endswith("route_scale 1.05")
    assert E.readings(band="0.3").loc[1, "code_does"] == "fixed 0.3 m/s^2"


def test_run_is_deterministic(fast_run):
    again = E.run(seed=0, fast=True, real=False)
    for k in ("table_5_2", "phase2", "pso_repeat", "compass"):
        pd.testing.assert_frame_equal(fast_run[k], again[k])


def test_sweep_runs_without_side_studies_give_the_same_results(fast_run):
    """The seed sweep and the claims' samples run without the side studies (manifest.SWEEP_KWARGS): every table
    they return, and so the long results the sweep keeps, must be those of the run with them."""
    from ilocalg.papers.claims import tables_to_long
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    lite = E.run(seed=0, fast=True, real=False, **SWEEP_KWARGS["pso_k_factor"])
    assert not {"pso_repeat", "sensitivity", "fitness_variants", "ilc_status"} & set(lite)
    assert list(lite) == [name for name in fast_run if name in lite]
    for name, df in lite.items():
        pd.testing.assert_frame_equal(df, fast_run[name], check_exact=True)
    pd.testing.assert_frame_equal(tables_to_long(lite), tables_to_long(fast_run), check_exact=True)


def test_ilc_k_study_on_real_data(shared_data):
    p = shared_data("ilc2020_site2_F4")
    res = KW.ilc_k_study(p, seed=0)
    s = res["summary"].iloc[0]
    assert s["n_learn_walks"] >= 5 and s["n_test_walks"] >= 5
    assert 0.3 < s["k_pso"] < 1.0
    assert s["k_pso"] == pytest.approx(s["k_closed"], abs=0.01)
