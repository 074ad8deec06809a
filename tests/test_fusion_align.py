"""Tests of ilocalg.fusion.align."""

from __future__ import annotations

import numpy as np
import pytest

from ilocalg import fusion as fu

STATES = np.array([0.0, 0.5, 1.0, 1.5, 2.0])


def test_fixes_go_to_latest_state_at_or_before():
    R = np.eye(2)[None] * np.array([1.0, 2.0, 3.0])[:, None, None]
    a = fu.fixes_at_states(STATES, [0.0, 0.7, 1.99], [[1, 1], [2, 2], [3, 3]], fix_R_m2=R)
    np.testing.assert_array_equal(a.state_index, [0, 1, 3])
    np.testing.assert_array_equal(a.z_m[[0, 1, 3]], [[1, 1], [2, 2], [3, 3]])
    assert np.isnan(a.z_m[[2, 4]]).all() and np.isnan(a.R_m2[2]).all()
    assert a.R_m2[3, 0, 0] == 3 and a.n_before_start == 0 and a.n_superseded == 0


def test_policies_are_explicit_and_counted():
    with pytest.raises(ValueError, match="fix 0 at t=-0.1 s precedes the first state"):
        fu.fixes_at_states(STATES, [-0.1, 0.6], [[0, 0], [1, 1]])
    a = fu.fixes_at_states(STATES, [-0.1, 0.6], [[0, 0], [1, 1]], before_start="drop")
    assert a.n_before_start == 1 and a.state_index[0] == -1 and not a.used[0]
    with pytest.raises(ValueError, match="fixes 0 and 1 both fall on state 1"):
        fu.fixes_at_states(STATES, [0.6, 0.8], [[0, 0], [1, 1]])
    b = fu.fixes_at_states(STATES, [0.6, 0.8, 0.9], [[0, 0], [1, 1], [2, 2]], same_state="last")
    assert b.n_superseded == 2 and b.used.tolist() == [False, False, True]
    np.testing.assert_array_equal(b.z_m[1], [2, 2])


def test_bad_inputs():
    with pytest.raises(ValueError, match="state_t_s must be"):
        fu.fixes_at_states([0.0, 0.0], [0.1], [[0, 0]])
    with pytest.raises(ValueError, match="fix_t_s must be"):
        fu.fixes_at_states(STATES, [0.5, 0.1], [[0, 0], [1, 1]])
    with pytest.raises(ValueError, match="fix_xy_m must be finite with shape"):
        fu.fixes_at_states(STATES, [0.5], [[0, np.nan]])
