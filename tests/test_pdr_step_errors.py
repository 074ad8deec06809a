"""Causes of a detector's missed and extra steps (ilocalg.pdr.step_errors), on hand-made step times."""

from __future__ import annotations

import numpy as np
import pytest

from ilocalg.pdr.step_errors import CAUSES, classify_step_errors, count_causes

WALK = 10.0 + 0.5 * np.arange(40)          # a regular walk, 0.5 s steps


def _causes(true, det):
    e = classify_step_errors(true, det)
    return list(zip(e["kind"], e["cause"], strict=True)), e


def test_a_perfect_count_has_no_errors():
    e = classify_step_errors(WALK, WALK + 0.1)
    assert e.empty and list(e.columns) == ["kind", "t_s", "cause", "gap_intervals"]
    n = count_causes(e)
    assert n["detector_net"] == 0 and n["truth_gap"] == 0 and set(n) >= {f"{k}_{c}" for k, c in CAUSES}


def test_a_step_found_beyond_the_tolerance_is_timing():
    det = WALK.copy()
    det[7] += 0.3
    got, _ = _causes(WALK, det)
    assert got == [("missed", "timing"), ("extra", "timing")]
    assert count_causes(classify_step_errors(WALK, det))["detector_net"] == 0


def test_a_landing_missing_from_the_truth_is_a_truth_gap():
    true = np.delete(WALK, [12, 25])
    got, e = _causes(true, WALK)
    assert got == [("extra", "truth_gap")] * 2
    assert np.allclose(e["gap_intervals"], 2.0) and np.allclose(e["t_s"], WALK[[12, 25]])
    n = count_causes(e)
    assert n["truth_gap"] == 2 and n["detector_net"] == 0


def test_the_detectors_own_errors():
    true = np.r_[WALK, WALK[-1] + 4.0 + 0.5 * np.arange(10)]    # a 4 s stop, then 10 more steps
    det = np.r_[5.0, np.delete(true, [0, 20]), WALK[-1] + 2.0, WALK[30] + 0.25 + 1e-3, true[-1] + 3.0]
    got, e = _causes(true, np.sort(det))
    assert sorted(got) == sorted([("extra", "before_walk"), ("missed", "walk_end"), ("missed", "inside_walk"),
                                  ("extra", "inside_walk"), ("extra", "pause"), ("extra", "after_walk")])
    assert np.all(np.diff(e["t_s"]) >= 0)
    n = count_causes(e)
    assert n["detector_net"] == 4 - 2 and n["truth_gap"] == 0


@pytest.mark.parametrize("kw", [{"tol_s": 0.6}, {"tol_s": 0.0}, {"gap_factor": 1.0}, {"pause_factor": 1.2},
                                {"n_local": 0}])
def test_bad_parameters(kw):
    with pytest.raises(ValueError):
        classify_step_errors(WALK, WALK, **kw)
