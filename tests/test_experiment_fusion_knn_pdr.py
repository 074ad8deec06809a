"""Experiment fusion_knn_pdr: KNN + PDR (notebook 08)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import fusion_knn_pdr
from ilocalg.sim import gait, iloc_floor


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


def test_test_positions_are_walking_positions_off_the_reference_grid():
    a = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False)
    tp = a["test_points"]
    xy = tp[["x_true_m", "y_true_m"]].to_numpy()
    grid = iloc_floor.training_points()
    d = np.hypot(xy[:, None, 0] - grid[None, :, 0], xy[:, None, 1] - grid[None, :, 1]).min(axis=1)
    assert d.min() > 1e-3                                  # no test position is a reference point
    assert (tp["t_s"] > gait.GaitConfig().stand_s).all()   # scans started while walking, not at the start
    pdr = tp[tp["method"] == "PDR only"].sort_values(["walker", "point"])
    for _, g in pdr.groupby("walker"):
        dt = np.diff(g["t_s"].to_numpy())
        np.testing.assert_allclose(dt, 2.0)                # back-to-back 2 s scans
        step = np.hypot(*np.diff(g[["x_true_m", "y_true_m"]].to_numpy(), axis=0).T)
        assert step.min() > 1.0                            # the walker moved between scans
    # every walk has as many test positions as its walking time allows, for every method
    n = tp.groupby(["walker", "method"]).size().unstack()
    assert (n.nunique(axis=1) == 1).all()
    assert not a["readings"]["source"].str.contains("limitation").any()


def test_test_scans_are_walking_scans_from_their_own_sessions(monkeypatch):
    calls, drifts = [], []
    real_fixes, real_drift = iloc_floor.walking_fixes, iloc_floor.session_drift_db

    def spy_drift(sim, rng=None):
        d = real_drift(sim, rng)
        drifts.append(d)
        return d

    def spy_fixes(sim, est, t, xy, starts, lat, rng, drift):
        calls.append((sim, np.asarray(starts), lat, drift))
        return real_fixes(sim, est, t, xy, starts, lat, rng, drift)

    monkeypatch.setattr(iloc_floor, "session_drift_db", spy_drift)
    monkeypatch.setattr(iloc_floor, "walking_fixes", spy_fixes)
    fusion_knn_pdr.run(seed=0, fast=True, sweeps=False)
    assert len(calls) == len(drifts) == 2                  # one walking session per walker
    for (sim, starts, lat, drift), new in zip(calls, drifts, strict=True):
        assert drift is new                                # a new session's per-AP drift ...
        assert not np.allclose(drift, sim.test_drift_db)   # ... not the standing calibration session's
        assert lat == 2.0 and starts.size > 20             # walking scans with latency along the walk
    assert not np.allclose(drifts[0], drifts[1])           # each walk is its own session


def test_survey_and_latency_sweeps_keep_the_walks():
    a = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False)
    b = fusion_knn_pdr.run(seed=0, fast=True, sweeps=False, scans_per_point=20, scan_latency_s=3.0)
    # PDR only at the same instants: the same walkers and walks whatever the survey size and scan latency
    pa = a["test_points"].query("method == 'PDR only'").set_index(["walker", "t_s"])["error_m"]
    pb = b["test_points"].query("method == 'PDR only'").set_index(["walker", "t_s"])["error_m"]
    common = pa.index.intersection(pb.index)
    assert len(common) > 10
    np.testing.assert_array_equal(pa[common].to_numpy(), pb[common].to_numpy())
