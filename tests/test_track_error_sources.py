"""Oracle ablations of an online track's error (ilocalg.track.error_sources): each removes its planted error."""

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from ilocalg.track import error_sources as es
from ilocalg.track.estimators import TrackProblem, kf_gain_track
from ilocalg.track.motion import GainStats
from ilocalg.track.online_kf import gain_kf
from tests.track_sim import gained_walk


def _walk(seed=0, n=160, fix_sd=3.0, scale=1.1, bias_rad=0.15, fix_every=4, fix_bias=(4.0, -3.0)):
    """A winding walk: PDR steps off by a gain, fixes with a persistent bias; waypoints every 20 steps."""
    rng = np.random.default_rng(seed)
    truth, g, pdr = gained_walk(rng, n, scale, bias_rad)
    ts = np.arange(n + 1) * 0.5
    fi = np.arange(1, n + 1, fix_every)
    fixes = truth[fi] + rng.normal(0, fix_sd, (fi.size, 2)) + np.asarray(fix_bias)
    gs = GainStats(gain_var=0.02, gain_walk_var=1e-6, step_var_m2=0.01, n_walks=10)
    p = TrackProblem(ts, np.column_stack([pdr.real, pdr.imag]), 0.01, ts[fi], fixes, fix_sd ** 2, gain=gs)
    wi = np.arange(0, n + 1, 20)
    return p, {"problem": p, "truth_t_s": ts[wi], "truth_xy_m": truth[wi], "fix_true_xy_m": truth[fi]}, g, truth


def test_own_gain_recovers_the_planted_gain_and_makes_the_steps_true():
    p, w, g, truth = _walk()
    assert abs(complex(es.own_gain(p, w["truth_t_s"], w["truth_xy_m"])) - g) < 1e-9
    q = es.with_own_gain(p, w["truth_t_s"], w["truth_xy_m"])
    np.testing.assert_allclose(q.disp_m, np.diff(truth, axis=0), atol=1e-9)
    gi = es.own_gain(p, w["truth_t_s"], w["truth_xy_m"], per_interval=True)
    np.testing.assert_allclose(gi, g, atol=1e-9)
    assert q.gain.gain_var < 1e-6 and q.gain.gain_walk_var == 0


def test_without_outlier_fixes_drops_a_planted_50_m_fix_only():
    p, w, _, _ = _walk(1, fix_bias=(0.0, 0.0))
    xy = p.fix_xy_m.copy()
    xy[10] += [50.0, 0.0]
    p = TrackProblem(p.state_t_s, p.disp_m, p.step_var_m2, p.fix_t_s, xy, p.fix_var_m2, gain=p.gain)
    q = es.without_outlier_fixes(p, w["fix_true_xy_m"])
    assert p.fix_t_s[10] not in q.fix_t_s
    # the others: about 1 % of honest fixes exceed the 99 % quantile
    assert q.fix_t_s.size >= p.fix_t_s.size - 1 - 2


def test_oracles_remove_their_error_sources():
    p, w, _, truth = _walk(2)
    assert p.fix_t_s[0] == 0.5 and w["truth_t_s"][1] == 10.0
    base = es._errors(kf_gain_track, p, w).mean()
    nob = es._errors(kf_gain_track, es.without_fix_bias(p, w["fix_true_xy_m"]), w).mean()
    start = es.with_true_start(p, w["truth_t_s"], w["truth_xy_m"])
    assert start.fix_var_at()[0] == pytest.approx(0.25)
    # fix 0 (state 1's time, 0.5 s) at the truth between the first two waypoints (0 s and 10 s)
    np.testing.assert_allclose(start.fix_xy_m[0], truth[0] + 0.05 * (truth[20] - truth[0]))
    assert not start.map_start and np.array_equal(start.fix_xy_m[1:], p.fix_xy_m[1:])
    assert nob < 0.5 * base          # a 5 m fix bias dominates this walk's error
    t = es.oracle_table({"w": w}, kf_gain_track, wifi_mean_m=5.0)
    assert list(t["condition"])[0] == "as is" and t["mean_m"].iloc[0] == pytest.approx(base)
    assert t.set_index("condition").loc["walk's mean fix error removed", "mean_m"] == pytest.approx(nob)
    assert np.allclose(t["ratio_to_wifi"], t["mean_m"] / 5.0)


def test_nees_of_a_consistent_filter_is_about_two():
    """Linear Gaussian walks without bias, no Huber: the filter's NEES at the waypoints averages 2."""
    v = []
    for seed in range(30):
        p, w, _, _ = _walk(seed, fix_bias=(0.0, 0.0), scale=1.0, bias_rad=0.0)
        rng = np.random.default_rng(100 + seed)
        # steps with exactly the filter's step noise
        p = TrackProblem(p.state_t_s, p.disp_m + rng.normal(0, 0.1, p.disp_m.shape), 0.01, p.fix_t_s, p.fix_xy_m,
                         p.fix_var_m2, gain=p.gain)
        r = gain_kf(p.state_t_s, p.disp_m, p.fix_t_s, p.fix_xy_m, p.fix_var_m2, 0.01, 1e-8, 0.0, huber_c=None)
        v.append(es.nees(r.xy_m, r.P, p.state_t_s, w["truth_t_s"][1:], w["truth_xy_m"][1:]))
    assert 1.5 < np.concatenate(v).mean() < 2.6


def test_error_by_time_since_first_fix_bins_and_shares():
    p, w, _, _ = _walk(3)
    e = {"w": np.arange(w["truth_t_s"].size, dtype=float) + 1.0}
    t = es.error_by_time_since_first_fix(e, {"w": w}, edges_s=(-np.inf, 0.0, 20.0, np.inf))
    assert t["n"].sum() == w["truth_t_s"].size and t["share"].sum() == pytest.approx(1.0)
    assert t["n"].iloc[0] == 1        # the first waypoint (t = 0) is before the first fix (t = 0.5)


def test_walk_record_from_an_evaluate_walk_result():
    p, w, _, _ = _walk(4)
    res = {"problem": p, "errors": pd.DataFrame({"t_s": w["truth_t_s"], "wifi": np.ones(w["truth_t_s"].size)}),
           "fixes": SimpleNamespace(true_xy_m=w["fix_true_xy_m"])}
    rec = es.walk_record(res, w["truth_xy_m"])
    assert rec["problem"] is p and np.array_equal(rec["truth_xy_m"], w["truth_xy_m"])
    with pytest.raises(ValueError, match="waypoint positions"):
        es.walk_record(res, w["truth_xy_m"][:-1])
    with pytest.raises(ValueError, match="problem"):
        es.walk_record({**res, "problem": None}, w["truth_xy_m"])
