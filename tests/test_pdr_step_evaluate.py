"""Leave-one-recording-out tuning of the step detectors (ilocalg.pdr.step_evaluate)."""

import numpy as np
import pytest

from ilocalg.pdr import step_evaluate as prs


def test_loro_cv_never_uses_the_held_out_recording():
    # grid row 0 is best on recordings 1-3; row 1 is better only on recording 0
    s = np.array([[0.90, 0.99, 0.99, 0.99],
                  [0.93, 0.95, 0.95, 0.95]])
    held, choice = prs.loro_cv(s)
    np.testing.assert_array_equal(choice, [0, 0, 0, 0])
    np.testing.assert_allclose(held, [0.90, 0.99, 0.99, 0.99])
    # a row that is perfect on one recording and bad elsewhere is never chosen for that recording
    s2 = np.array([[1.0, 0.5, 0.5], [0.8, 0.9, 0.9]])
    held2, choice2 = prs.loro_cv(s2)
    assert choice2[0] == 1 and held2[0] == 0.8
    with pytest.raises(ValueError, match="n_recordings >= 2"):
        prs.loro_cv(np.ones((3, 1)))


def test_accuracy():
    np.testing.assert_allclose(prs.accuracy([90, 110, 100], [100, 100, 100]), [0.9, 0.9, 1.0])


def test_grid_detectors_only():
    with pytest.raises(ValueError, match="unknown grid detector 'sam'"):
        prs.count_steps(None, "sam", {})
    assert prs.detector_params("sign_change", {"n": 5}) == {"n_left": 5, "n_right": 5, "smooth": True}
    assert all(len(full) >= len(fast) for full, fast in prs.DETECTORS.values())


def test_truth_artefacts_counts_double_triggers():
    from types import SimpleNamespace

    r = SimpleNamespace(name="r", true_steps=5, step_t_s=np.array([0.0, 0.5, 0.6, 1.1, 1.15]))
    t = prs.truth_artefacts([r]).iloc[0]
    assert t["intervals_below_0.25s"] == 2 and t["share_of_steps"] == 0.4


def test_walk_gate_sweep_names_a_robust_parameter_and_needs_development_recordings():
    from ilocalg.pdr.step_errors import CAUSES, TRUTH_LIMITED

    with pytest.raises(ValueError, match="unknown robust detector parameter 'min_onset'"):
        prs.walk_gate_sweep([], [], prs.ONSET_GRID, "min_onset")
    with pytest.raises(ValueError, match="at least 2 development recordings"):
        prs.walk_gate_sweep([], [], prs.ONSET_GRID, "min_onset_ratio")
    # the sweep's own-error columns are exactly the detector's causes (every cause not limited by the truth)
    assert set(prs.OWN_CAUSES) == {f"{k}_{c}" for k, c in CAUSES if c not in TRUTH_LIMITED}
    assert prs.ONSET_GRID[0] is None and prs.NAC_GRID[0] is None
