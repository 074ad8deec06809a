"""The robust step detector on the 48 real Oxford recordings: per-recording bounds under both truths, and
invariance to the phone's orientation. Real data: must fail, not skip, under CI=true (``shared_data``)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from ilocalg.io.oxford import load_oxford_archive
from ilocalg.pdr.robust import ROBUST_DEFAULTS, detect_steps_robust
from ilocalg.pdr.step_evaluate import (
    ONSET_GRID,
    error_causes,
    is_development,
    prepare,
    step_diagnosis,
    walk_gate_sweep,
)

_CACHE: dict = {}


@pytest.fixture
def diag(shared_data):
    p = shared_data("oxford_step_counter") / "optimisation_data.tar.xz"
    if p not in _CACHE:
        recs = load_oxford_archive(p)
        prep = [prepare(r) for r in recs]
        _CACHE[p] = (prep, step_diagnosis(prep, recs))
        _CACHE["recordings"] = recs
    return _CACHE[p]


def test_every_recording_within_its_measured_bound(diag):
    # bounds a little below what the detector at its defaults gives today (worst 92.61 % published, 95.33 % with
    # the heel bounces merged; means 98.88 % and 99.29 %): a regression in any one recording fails
    _, d = diag
    assert len(d) == 48
    assert d["accuracy"].min() >= 0.92 and d["accuracy_bounces_merged"].min() >= 0.95
    assert d["accuracy"].mean() >= 0.987 and d["accuracy_bounces_merged"].mean() >= 0.991
    # the heel bounces are the swinging-arm shortfall: every such recording scores higher without them
    arm = d[d["position"] == "SwingingArm"]
    assert len(arm) == 2 and (arm["accuracy_bounces_merged"] > arm["accuracy"] + 0.03).all()
    assert (d["true_steps_published"] - d["n_heel_bounces"] == d["true_steps_bounces_merged"]).all()
    assert d["recording"].map(is_development).sum() == 24


def test_walk_detection_default_is_the_development_folds_choice(diag):
    # swept on the development half only: the default is the value leave-one-recording-out chooses against the
    # bounce-merged truth, and it counts better than the detector without walk detection against both truths
    prep, _ = diag
    g = walk_gate_sweep(prep, _CACHE["recordings"]).set_index("min_stride_nac")
    assert (g["n_recordings"] == 24).all()
    assert g["loro_chosen_bounces_merged"].idxmax() == ROBUST_DEFAULTS["min_stride_nac"]
    on = g.loc[ROBUST_DEFAULTS["min_stride_nac"]]
    for truth in ("published", "bounces_merged"):
        assert on[f"mean_accuracy_{truth}"] > g.loc["off", f"mean_accuracy_{truth}"]


def test_gait_onset_default_is_the_development_folds_choice_and_costs_no_true_step(diag):
    # swept on the development half only, like the stride threshold: the default ratio is the value
    # leave-one-recording-out chooses against both truths, and against "off" it removes handling detections
    # before the walk without missing any more true steps (the detector's own errors, by cause)
    prep, _ = diag
    g = walk_gate_sweep(prep, _CACHE["recordings"], ONSET_GRID, "min_onset_ratio").set_index("min_onset_ratio")
    default = ROBUST_DEFAULTS["min_onset_ratio"]
    assert g["loro_chosen_bounces_merged"].idxmax() == default == g["loro_chosen_published"].idxmax()
    on, off = g.loc[default], g.loc["off"]
    assert on["own_extra_before_walk"] < off["own_extra_before_walk"]
    for c in ("own_missed_walk_end", "own_missed_inside_walk", "own_extra_after_walk", "own_extra_pause"):
        assert on[c] == off[c], c
    assert on["own_errors"] < off["own_errors"]


def test_extra_detections_in_the_truths_gaps_are_the_landings_the_heel_sensors_missed(diag):
    # the detections in gaps of the bounce-merged truth (classified from step times alone) against the loader's
    # unpaired landings (from the foot states alone): two independent counts of the same missing landings
    prep, _ = diag
    recs = _CACHE["recordings"]
    assert all(r.step_is_heel_bounce.sum() == r.n_heel_bounces for r in recs)
    _, c = error_causes(prep, recs)
    extra = c[[f"extra_{k}" for k in ("timing", "truth_gap", "pause", "before_walk", "after_walk", "inside_walk")]]
    missed = c[[f"missed_{k}" for k in ("timing", "walk_end", "inside_walk")]]
    assert len(c) == 48 and (c["counted"] - c["true_steps_bounces_merged"]
                             == extra.sum(axis=1) - missed.sum(axis=1)).all()
    # today: at most 2 apart in any recording, 55 beside 60 over the 48
    assert (c["truth_gap"] - c["n_unpaired_landings"]).abs().max() <= 3
    assert abs(int(c["truth_gap"].sum()) - int(c["n_unpaired_landings"].sum())) <= 8
    # a paired "timing" error leaves the count alone
    assert (c["missed_timing"] == c["extra_timing"]).all()


def test_rotating_the_phone_frame_does_not_change_the_steps(diag):
    prep, _ = diag
    rot = Rotation.random(3, random_state=7)
    for p, r in zip([prep[0], prep[6], prep[20]], rot, strict=True):
        a = detect_steps_robust(p.acc_mps2, p.t_s)
        b = detect_steps_robust(p.acc_mps2 @ r.as_matrix().T, p.t_s)
        assert len(a) == len(b) > 200
        np.testing.assert_allclose(a["t_s"], b["t_s"], atol=1e-9)


def test_bad_input_is_one_clear_error():
    t = np.arange(100) / 100.0
    with pytest.raises(ValueError, match=r"shape \(n, 3\) or \(n,\)"):
        detect_steps_robust(np.zeros((100, 2)), t)
    with pytest.raises(ValueError, match="not finite"):
        detect_steps_robust(np.r_[np.full(50, 9.8), np.nan, np.full(49, 9.8)], t)
    with pytest.raises(ValueError, match="strictly increasing"):
        detect_steps_robust(np.full(100, 9.8), t[::-1])
