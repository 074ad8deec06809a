"""Experiment fusion_knn_pdr: KNN + PDR (notebook 08)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import fusion_knn_pdr
from ilocalg.sim import gait, iloc_floor, measured


@pytest.fixture(scope="module")
def fast_runs():
    """A fast run with every table, and the same run as the seed sweep runs it (manifest.SWEEP_KWARGS)."""
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    return (fusion_knn_pdr.run(seed=0, fast=True),
            fusion_knn_pdr.run(seed=0, fast=True, **SWEEP_KWARGS["fusion_knn_pdr"]))


def test_sweep_runs_without_the_sweeps_give_the_same_results(fast_runs):
    """The seed sweep and the claims' samples run without the survey, detector and latency sweeps: every table
    they return, and so the long results the sweep keeps, must be those of the run with them."""
    from ilocalg.papers.claims import tables_to_long

    a, b = fast_runs
    assert "survey_sweep" in a and "survey_sweep" not in b
    assert list(b) == [name for name in a if name in b]
    for name, df in b.items():
        pd.testing.assert_frame_equal(df, a[name], check_exact=True)
    pd.testing.assert_frame_equal(tables_to_long(b), tables_to_long(a), check_exact=True)


def test_fast_run_is_deterministic_and_structured(fast_runs):
    a, _ = fast_runs
    m = a["summary"].set_index("method")["mean_error_m"]
    assert {fusion_knn_pdr.COMBINED, fusion_knn_pdr.KF_ALT, "PDR only", "Wi-Fi only (KNN)"} <= set(m.index)
    # the default combination is the adjust_sweep row of the default weight, the inverse-variance weight
    aw = a["adjust_sweep"]
    assert aw["default"].sum() == 1
    assert aw.loc[aw["default"], "mean_error_m"].iloc[0] == pytest.approx(m[fusion_knn_pdr.COMBINED], rel=1e-12)
    cal = a["calibration"].set_index("quantity")["value"]
    assert cal["adjustment weight used"] == pytest.approx(cal["adjustment weight, inverse variances (training data)"],
                                                          abs=1e-3)
    assert 0.0 < cal["adjustment weight used"] < 1.0
    # a given weight is used as given
    c = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False, budget=False, adjust_weight=0.5)
    assert c["calibration"].set_index("quantity")["value"]["adjustment weight used"] == 0.5
    assert list(a["readings"].columns) == ["choice", "paper_line", "text_says", "code_does", "source"]
    assert not any("sec. 3.1" in str(q) and "KF" in str(q) for q in a["comparison"]["quantity"])
    pp = a["per_point"]
    ex = a["track_example"]
    start_pdr = ex[ex["method"] == "PDR only"].iloc[0][["x_m", "y_m"]].to_numpy(float)
    start_true = ex[ex["method"] == "truth"].iloc[0][["x_m", "y_m"]].to_numpy(float)
    assert np.allclose(start_pdr, start_true)             # PDR starts at the true start (paper, L235)
    assert pp["PDR only"].iloc[-1] > pp["PDR only"].iloc[1]   # and drifts
    assert "Combined" in fusion_knn_pdr.findings(a)



def test_test_positions_are_walking_positions_off_the_reference_grid(fast_runs):
    a = fast_runs[1]
    tp = a["test_points"]
    xy = tp[["x_true_m", "y_true_m"]].to_numpy()
    grid = iloc_floor.training_points()
    d = np.hypot(xy[:, None, 0] - grid[None, :, 0], xy[:, None, 1] - grid[None, :, 1]).min(axis=1)
    assert d.min() > 1e-3                                  # no test position is a reference point
    assert (tp["t_s"] > gait.GaitConfig().stand_s).all()   # fixes available while walking, not at the start
    pdr = tp[tp["method"] == "PDR only"].sort_values(["walker", "point"])
    iv = a["calibration"].set_index("quantity")["value"]["scan interval = time between test positions [s]"]
    assert iv == pytest.approx(measured.param("wifi_scan_interval_s"))
    for _, g in pdr.groupby("walker"):
        dt = np.diff(g["t_s"].to_numpy())
        np.testing.assert_allclose(dt, iv)                 # periodic scans, scored when each fix is stamped
        step = np.hypot(*np.diff(g[["x_true_m", "y_true_m"]].to_numpy(), axis=0).T)
        assert step.min() > 1.0                            # the walker moved between scans
    # every walk has as many test positions as its walking time allows, for every method
    n = tp.groupby(["walker", "method"]).size().unstack()
    assert (n.nunique(axis=1) == 1).all()
    assert not a["readings"]["source"].str.contains("limitation").any()


def test_test_scans_are_walking_scans_from_their_own_sessions(monkeypatch):
    calls, drifts = [], []
    real_scans, real_drift = iloc_floor.walking_scans, iloc_floor.session_drift_db

    def spy_drift(sim, rng=None):
        d = real_drift(sim, rng)
        drifts.append(d)
        return d

    def spy_scans(sim, t, xy, starts, lat, rng, drift, **kw):
        calls.append((sim, np.asarray(starts), kw.get("read_age_s"), drift))
        return real_scans(sim, t, xy, starts, lat, rng, drift, **kw)

    monkeypatch.setattr(iloc_floor, "session_drift_db", spy_drift)
    monkeypatch.setattr(iloc_floor, "walking_scans", spy_scans)
    fusion_knn_pdr.run(seed=0, fast=True, sweeps=False, budget=False)
    assert len(calls) == len(drifts) == 2                  # one walking session per walker
    for (sim, starts, age, drift), new in zip(calls, drifts, strict=True):
        assert drift is new                                # a new session's per-AP drift ...
        assert not np.allclose(drift, sim.test_drift_db)   # ... not the standing calibration session's
        assert starts.size > 20 and age.shape == (starts.size, sim.ap_xy_m.shape[0])  # aged readings
    assert not np.allclose(drifts[0], drifts[1])           # each walk is its own session


def test_fixes_enter_only_after_their_scan_ends(fast_runs):
    a = fast_runs[1]
    tp = a["test_points"]
    w = tp[tp["method"] == "Wi-Fi only (KNN)"].set_index(["walker", "point"])
    c = tp[tp["method"] == fusion_knn_pdr.COMBINED].set_index(["walker", "point"])
    # the combined track at a fix's availability time has moved towards that fix (the state then includes it)
    assert (w["t_s"] == c.loc[w.index, "t_s"]).all()
    b = a["budget"]
    base = b[b["replaced_by_truth"] == "none (as simulated)"].set_index("method")["mean_error_m"]
    m = a["summary"].set_index("method")["mean_error_m"]
    assert base[fusion_knn_pdr.COMBINED] == pytest.approx(m[fusion_knn_pdr.COMBINED], rel=1e-9)
    assert base["PDR only"] == pytest.approx(m["PDR only"], rel=1e-9)
    allt = b[b["replaced_by_truth"] == "all of them"].set_index("method")["mean_error_m"]
    assert (allt < 0.5 * base).all()                       # with every source true, little error is left
    meas = a["measures"]
    assert {"quantity", "value", "unit"} <= set(meas.columns)
    assert {"adjustment weight used", "mean error", "detected / true steps"} <= set(meas["quantity"])
    # a measure never repeats a comparison row's quantity (a claim naming it would match two rows)
    assert not set(meas["quantity"]) & set(a["comparison"]["quantity"])
    assert not meas.duplicated(["quantity", "item"]).any()



def test_survey_sweep_keeps_the_walks():
    a = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False, budget=False)
    b = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False, budget=False, scans_per_point=20)
    # PDR only at the same instants: the same walkers and walks whatever the survey size and scan latency
    pa = a["test_points"].query("method == 'PDR only'").set_index(["walker", "t_s"])["error_m"]
    pb = b["test_points"].query("method == 'PDR only'").set_index(["walker", "t_s"])["error_m"]
    common = pa.index.intersection(pb.index)
    assert len(common) > 10
    np.testing.assert_array_equal(pa[common].to_numpy(), pb[common].to_numpy())


def test_shared_computations_give_what_each_call_computes_on_its_own():
    """run() lets its _walk_tracks calls share fits, fixes, training and PDR (_Shared): a call given what an earlier
    call with the default detector computed (the detector's defaults spelled out are the same detector) returns the
    same tables as the call on its own, and cached arrays cannot be changed in place."""
    scn = fusion_knn_pdr._scenario(0, True, 2, 3, 5, None, None, fusion_knn_pdr.SCAN_LATENCY_S)
    variant0 = dict(fusion_knn_pdr.DETECTOR_VARIANTS[0][1])
    assert fusion_knn_pdr._detector_key(None) == fusion_knn_pdr._detector_key(variant0)
    assert fusion_knn_pdr._detector_key(None) != fusion_knn_pdr._detector_key({"threshold_mps2": 0.5})
    with pytest.raises(ValueError, match="window_m"):
        fusion_knn_pdr._detector_key({"window_m": 1.0})
    shared = fusion_knn_pdr._Shared()
    fusion_knn_pdr._walk_tracks(scn, None, 0.2, (0.5,), principled=True, shared=shared)
    for det in (variant0, {"threshold_mps2": 2.0}):
        alone = fusion_knn_pdr._walk_tracks(scn, det, 0.2, (0.5,), principled=False)
        with_shared = fusion_knn_pdr._walk_tracks(scn, det, 0.2, (0.5,), principled=False, shared=shared)
        pd.testing.assert_frame_equal(with_shared[0], alone[0], check_exact=True)
        assert {k: v for k, v in with_shared[2].items() if k != "inputs"} == \
            {k: v for k, v in alone[2].items() if k != "inputs"}
    pdr = next(v for k, v in shared._values.items() if k[1][0] == "pdr")
    with pytest.raises(ValueError, match="read-only"):
        pdr["step_m"][0] = 0.0


def test_seed_table_reads_the_runs_it_is_given(monkeypatch):
    """seed_table(runs=) takes a seed from the tables given instead of running it again: same table either way."""
    runs = {0: fusion_knn_pdr.run(seed=0, fast=True)}
    per, head = fusion_knn_pdr.seed_table(range(2), fast=True)
    calls = []
    orig = fusion_knn_pdr.run
    monkeypatch.setattr(fusion_knn_pdr, "run", lambda **kw: calls.append(kw["seed"]) or orig(**kw))
    per2, head2 = fusion_knn_pdr.seed_table(range(2), fast=True, runs=runs)
    assert calls == [1]
    pd.testing.assert_frame_equal(per2, per, check_exact=True)
    pd.testing.assert_frame_equal(head2, head, check_exact=True)


def test_run_without_the_claim_measures_gives_the_same_other_tables(fast_runs):
    """claim_measures=False (seed_table's runs) leaves out only the extra walkers' rows of ``measures``: every other
    table, and the rows of ``measures`` computed from the run itself, are the same bytes."""
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    _, b = fast_runs
    c = fusion_knn_pdr.run(seed=0, fast=True, claim_measures=False, **SWEEP_KWARGS["fusion_knn_pdr"])
    assert list(c) == list(b)
    for name in b:
        if name != "measures":
            pd.testing.assert_frame_equal(c[name], b[name], check_exact=True)
    kept = b["measures"]["quantity"].isin(set(c["measures"]["quantity"]))
    assert 0 < kept.sum() < len(b["measures"])
    pd.testing.assert_frame_equal(c["measures"], b["measures"][kept].reset_index(drop=True), check_exact=True)
