"""The Hartmann IMU + video-tracker experiment (ilocalg.experiments.ins_hartmann)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import ins_hartmann
from ilocalg.ins.paper_values import HARTMANN_TABLE2_OVERALL


@pytest.fixture(scope="module")
def out():
    return ins_hartmann.run(seed=0, fast=True, n_sequences=1, duration_s=40.0, noise_scales=(0.5, 1.0, 4.0),
                            outage_factors=((2.0, 1.0),))


def test_mean_deviation_is_a_sensitivity_curve_of_the_tracker_noise(out):
    tn = out["tracker_noise"]
    assert list(tn["noise_scale"]) == [0.5, 1.0, 4.0]
    for a in "xyz":
        dev = tn[f"mean_dev_{a}_m"].to_numpy()
        assert np.all(np.diff(dev) > 0)               # more tracker noise, larger deviation to the tracker
        assert (tn[f"paper_mean_dev_{a}_m"] == HARTMANN_TABLE2_OVERALL[f"mean_dev_{a}_m"]).all()
    imp = out["tracker_noise_implied"].set_index("axis")
    for a in "xyz":
        sc = imp.loc[a, "implied_noise_scale"]
        dev = tn[f"mean_dev_{a}_m"].to_numpy()
        pv = HARTMANN_TABLE2_OVERALL[f"mean_dev_{a}_m"]
        if dev[0] <= pv <= dev[-1]:
            assert 0.5 <= sc <= 4.0
            assert np.interp(sc, tn["noise_scale"], dev) == pytest.approx(pv)
        else:
            assert np.isnan(sc)


def test_outage_inputs_are_labelled_and_swept(out):
    cmp = out["comparison"].set_index("quantity")
    for key in ("vt_rate_hz", "outage_max_s", "outages_over_1s"):
        assert cmp.loc[f"overall {key}", "note"].startswith("input, not a reproduction")
        assert cmp.loc[f"overall {key}", "row_class"] == "set by input"  # shown apart, never counted
    assert (cmp.loc[[q for q in cmp.index if "_dev_" in q], "row_class"] == "result").all()
    os_ = out["outage_sensitivity"]
    assert list(zip(os_["outage_rate_factor"], os_["outage_excess_factor"], strict=True)) == [(1.0, 1.0), (2.0, 1.0)]
    # twice the outage rate: at least as many outages over 1 s and a lower tracker rate
    assert os_["outages_over_1s"].iloc[1] >= os_["outages_over_1s"].iloc[0]
    assert os_["vt_rate_hz"].iloc[1] < os_["vt_rate_hz"].iloc[0]
    r = out["readings"]
    assert r["choice"].is_unique and (r["source"].str.len() > 0).all()


def test_assumed_tracker_noise_sets_the_main_sequences_and_the_readings():
    kw = {"seed": 0, "fast": True, "n_sequences": 1, "duration_s": 15.0, "noise_scales": (1.0,), "outage_factors": ()}
    base, noisy = ins_hartmann.run(**kw), ins_hartmann.run(vt_noise_scale=3.0, **kw)
    t0, t1 = base["table2"].iloc[-1], noisy["table2"].iloc[-1]
    assert t1["mean_dev_x_m"] > t0["mean_dev_x_m"]
    assert noisy["readings"].loc[2, "code_does"].startswith("sd 9 / 9 / 24 mm")
    # the sensitivity curve stays about the default noise
    assert noisy["tracker_noise"]["mean_dev_x_m"].iloc[0] == base["tracker_noise"]["mean_dev_x_m"].iloc[0]


def test_side_studies_skipped_leave_the_claimed_tables_unchanged():
    """Sweep tasks (the seed sweep, the claims' robustness samples) skip the tracker-noise and outage sweeps
    (manifest.SWEEP_KWARGS): the tables the sweep keeps must be the same as in a run with them."""
    from ilocalg.papers.claims import tables_to_long
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    lite = ins_hartmann.run(seed=0, fast=True, n_sequences=1, duration_s=20.0, **SWEEP_KWARGS["ins_hartmann"])
    full = ins_hartmann.run(seed=0, fast=True, n_sequences=1, duration_s=20.0, noise_scales=(1.0,),
                            outage_factors=((2.0, 1.0),))
    for name in ("comparison", "measures", "table2", "settling"):
        pd.testing.assert_frame_equal(lite[name], full[name])
    pd.testing.assert_frame_equal(tables_to_long(lite), tables_to_long(full), check_exact=True)
    assert lite["tracker_noise"].empty and lite["outage_sensitivity"].empty


def test_side_studies_reuse_the_main_runs_only_where_they_simulate_the_same_sequences():
    from ilocalg.ins.hartmann_eval import run_sequence, table2_row
    from ilocalg.sim import hartmann as sim

    kw = {"seed": 0, "fast": True, "n_sequences": 1, "duration_s": 15.0, "noise_scales": (1.0,),
          "outage_factors": ((2.0, 1.0),)}

    def fresh(**sim_kw):
        seq = sim.simulate(15.0, seed=0, **sim_kw)
        return table2_row("1", seq, run_sequence(seq))

    default, doubled = fresh(), fresh(outage_rate_per_s=2.0 * sim.OUTAGE_RATE_PER_S)
    for main_rate, rows in ((1.0, (default, default, doubled)), (2.0, (default, default, doubled))):
        out = ins_hartmann.run(outage_rate_factor=main_rate, **kw)
        got = (out["tracker_noise"].iloc[0], *(out["outage_sensitivity"].iloc[i] for i in (0, 1)))
        for g, want in zip(got, rows, strict=True):
            assert g["mean_dev_x_m"] == want["mean_dev_x_m"] and g["mean_dev_z_m"] == want["mean_dev_z_m"]
    assert out["table2"].iloc[0]["mean_dev_x_m"] == doubled["mean_dev_x_m"]  # the main run at twice the rate


def test_runs_together_give_each_runs_tables():
    """run_many (the seed sweep's and the robustness samples' path): runs of other seeds, durations and tracker
    settings filtered in one batch, each run's tables those of run alone."""
    runs = [{"seed": 1, "fast": True, "n_sequences": 1, "duration_s": 12.0, "noise_scales": (), "outage_factors": ()},
            {"seed": 0, "fast": True, "n_sequences": 2, "duration_s": 9.0, "noise_scales": (2.0,),
             "outage_factors": (), "vt_noise_scale": 1.5, "outage_rate_factor": 2.0},
            {"seed": 1, "fast": True, "n_sequences": 1, "duration_s": 12.0, "noise_scales": (1.0,),
             "outage_factors": ((2.0, 1.0),)}]
    together = ins_hartmann.run_many(runs)
    for r, got in zip(runs, together, strict=True):
        alone = ins_hartmann.run(**r)
        assert list(got) == list(alone)
        for name in alone:
            pd.testing.assert_frame_equal(got[name], alone[name], check_exact=True)
