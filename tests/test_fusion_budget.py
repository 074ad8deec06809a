"""ilocalg.fusion.budget: replacing error sources by the truth, the budget table, the steady-state weight."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.fusion.budget import (
    SOURCES,
    FusionInputs,
    error_budget,
    steady_state_weight,
    track_at,
    walk_errors,
    with_truth,
)
from ilocalg.pdr.dead_reckoning import dead_reckon


def _walk(seed=0):
    """A straight walk along x at 1.4 m/s, 0.7 m steps every 0.5 s; noisy detected steps and lagged fixes."""
    r = np.random.default_rng(seed)
    t = np.linspace(0.0, 30.0, 3001)
    xy = np.column_stack([1.4 * t, np.zeros_like(t)])
    true_end = np.arange(0.5, 30.0 + 1e-9, 0.5)
    det_t = np.sort(r.choice(true_end, size=50, replace=False))          # 10 steps missed
    fix_ref = np.arange(2.0, 29.0, 3.0)
    fix_t = fix_ref + 1.0                                                 # 1 s lag
    fix_xy = np.column_stack([1.4 * fix_ref, np.zeros_like(fix_ref)]) + r.normal(0, 3.0, (fix_ref.size, 2))
    return FusionInputs(
        t0_s=0.0, start_xy_m=np.array([-2.0, -1.0]), start_ref_t_s=0.0, step_t_s=det_t,
        step_m=0.7 + r.normal(0, 0.1, det_t.size), theta_rad=r.normal(0, 0.1, det_t.size),
        heading_t_s=t, heading_rad=np.full(t.size, 0.05), fix_t_s=fix_t, fix_ref_t_s=fix_ref, fix_xy_m=fix_xy,
        true_step_t_s=true_end, true_step_mid_t_s=true_end - 0.25, true_step_m=np.full(true_end.size, 0.7),
        truth_t_s=t, truth_xy_m=xy, truth_theta_rad=np.zeros_like(t), eval_t_s=np.arange(1.0, 30.0, 1.0))


def _pdr(inp):
    return dead_reckon(inp.step_m, inp.theta_rad, *inp.start_xy_m)[["x_m", "y_m"]].to_numpy()


def test_every_source_true_makes_dead_reckoning_exact():
    inp = with_truth(_walk(), SOURCES)
    assert inp.step_t_s.size == 60                                         # the true steps
    np.testing.assert_allclose(inp.step_m, 0.7)
    np.testing.assert_allclose(inp.theta_rad, 0.0, atol=1e-12)
    np.testing.assert_allclose(inp.fix_t_s, inp.fix_ref_t_s)               # no lag
    np.testing.assert_allclose(inp.fix_xy_m, inp.truth_at(inp.fix_ref_t_s))  # no fix error
    # states sit at step ends; at most one step (0.7 m) between a state and an evaluation time
    assert walk_errors(inp, _pdr).max() <= 0.7 + 1e-9


def test_each_replacement_touches_only_its_source():
    w = _walk()
    d = with_truth(w, ["step detection"])
    assert d.step_t_s.size == 60 and np.array_equal(d.fix_xy_m, w.fix_xy_m)
    assert set(np.round(d.step_m, 12)) <= set(np.round(w.step_m, 12))       # estimated lengths kept
    h = with_truth(w, ["heading"])
    assert np.array_equal(h.step_m, w.step_m) and np.allclose(h.theta_rad, 0.0)
    lag = with_truth(w, ["scan lag"])
    assert np.array_equal(lag.fix_xy_m, w.fix_xy_m) and np.array_equal(lag.fix_t_s, w.fix_ref_t_s)
    with pytest.raises(ValueError, match="unknown error source"):
        with_truth(w, ["magnetism"])


def test_budget_table_shares():
    walks = [_walk(s) for s in range(3)]
    b = error_budget(walks, {"PDR": _pdr})
    assert list(b["replaced_by_truth"]) == ["none (as simulated)", *SOURCES, "all of them"]
    base = b["mean_error_m"].iloc[0]
    np.testing.assert_allclose(b["error_removed_m"], base - b["mean_error_m"])
    np.testing.assert_allclose(b["share_of_error"], (base - b["mean_error_m"]) / base)
    s = b.set_index("replaced_by_truth")["share_of_error"]
    assert s["scan lag"] == 0.0                 # PDR alone reads no fix: lag carries nothing
    # a sixth of the steps missed (7 m by the end) outweighs zero-mean length and heading noise
    assert s["step detection"] > max(s["step length"], s["heading"], 0.1)
    assert s["Wi-Fi fix error"] > 0             # the start fix 2.2 m behind adds to the missed steps
    assert s["all of them"] > 0.9
    with pytest.raises(ValueError, match="no walks"):
        error_budget([], {"PDR": _pdr})


def test_track_at_takes_the_latest_state():
    np.testing.assert_array_equal(track_at([0.0, 1.0, 2.0], np.arange(6).reshape(3, 2), [-1.0, 0.5, 1.0, 9.0]),
                                  [[0, 1], [0, 1], [2, 3], [4, 5]])


def test_steady_state_weight_is_the_fixed_point_of_the_recursion():
    q, r = 0.6, 10.0
    p = 1.0
    for _ in range(2000):                       # scalar KF: predict (+q), update with gain p / (p + r)
        p = p + q
        k = p / (p + r)
        p = (1 - k) * p
    assert steady_state_weight(q, r) == pytest.approx(k, rel=1e-9)
    assert steady_state_weight(0.0, 1.0) == 0.0
    assert steady_state_weight(1e9, 1.0) == pytest.approx(1.0, abs=1e-6)
    with pytest.raises(ValueError):
        steady_state_weight(1.0, 0.0)


def test_inputs_refuse_a_fix_from_the_future():
    w = _walk()
    with pytest.raises(ValueError, match="after it is available"):
        FusionInputs(**{**w.__dict__, "fix_ref_t_s": w.fix_t_s + 1.0})


def test_input_diagnostics():
    from ilocalg.fusion.budget import input_diagnostics

    d = input_diagnostics([_walk()]).set_index("quantity")["value"]
    # a 1 s lag at 1.4 m/s puts every fix 1.4 m further behind the walker when it enters than where it was read
    assert (d["fix along-track offset from the position when it enters"]
            - d["fix along-track offset from the position it describes"]) == pytest.approx(-1.4)
    assert d["fix age when it enters"] == pytest.approx(1.0)
    assert d["detected / true steps"] == pytest.approx(50 / 60)
    assert 0.7 < d["PDR distance / true distance"] < 0.95


def test_inputs_from_a_walk_carry_its_truth_and_the_given_estimates():
    from types import SimpleNamespace

    t = np.arange(0.0, 4.0, 0.5)
    steps = pd.DataFrame({"t_strike_s": [0.5, 1.5], "duration_s": [1.0, 1.0], "t_mid_s": [1.0, 2.0],
                          "length_m": [0.7, 0.8]})
    walk = SimpleNamespace(imu=pd.DataFrame(index=t), steps=steps, truth_t_s=t,
                           truth_xy_m=np.column_stack([t, 0 * t]), truth=pd.DataFrame({"theta_rad": 0 * t}))
    fixes = pd.DataFrame({"t_ready_s": [2.0, 3.0], "t_ref_s": [1.0, 2.5], "fix_x_m": [1.0, np.nan],
                          "fix_y_m": [0.5, np.nan]})
    inp = FusionInputs.from_walk(walk, state_t_s=np.array([0.0, 2.5, 3.5]), step_m=np.array([0.7, 0.7]),
                                 theta_rad=np.zeros(2), heading_rad=0 * t, start_xy_m=np.zeros(2), start_ref_t_s=0.2,
                                 fixes=fixes, eval_t_s=np.array([3.0]))
    assert inp.t0_s == 0.0 and inp.start_ref_t_s == 0.2
    np.testing.assert_array_equal(inp.step_t_s, [2.5, 3.5])
    np.testing.assert_array_equal(inp.true_step_t_s, [1.5, 2.5])
    np.testing.assert_array_equal(inp.true_step_m, [0.7, 0.8])
    np.testing.assert_array_equal(inp.fix_xy_m[0], [1.0, 0.5])
    assert np.isnan(inp.fix_xy_m[1]).all() and inp.eval_xy_m is None
    np.testing.assert_allclose(inp.truth_at([3.0]), [[3.0, 0.0]])
