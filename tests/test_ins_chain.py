"""Tests of ilocalg.ins.chain (Liao et al.'s chain on a walk: scoring and layout helpers)."""

from types import SimpleNamespace

import numpy as np
import pytest

from ilocalg.ins.chain import METHODS, gcp_fix_delay_s, indoor_errors, stats_rows, trajectory_frame


def _walk(n=50):
    t = np.arange(n, dtype=float)
    pos = np.c_[t, np.zeros(n), np.zeros(n)]  # 1 m/s along E
    return SimpleNamespace(t_s=t, t_true_s=t, pos_true_n_m=pos, mat_true_nb=np.repeat(np.eye(3)[None], n, 0),
                           t_indoor_s=10.0, gcp_t_s=np.array([27.0]), gcp_id=np.array([0]))


def test_indoor_errors_score_the_indoor_part_only():
    w = _walk()
    pos = w.pos_true_n_m + np.where(w.t_s[:, None] < 10, 100.0, 1.0) * np.array([0.0, 1.0, 0.0])
    err = indoor_errors(w, pos, w.mat_true_nb)
    assert len(err) == 40 and np.allclose(err["N"], 1.0)
    rows = stats_rows("p", METHODS[0], 3, err)
    assert [r["stat"] for r in rows] == ["max", "rms", "std"] and rows[1]["N"] == pytest.approx(1.0)


def test_gcp_fix_delay_is_the_time_since_the_closest_approach():
    w = _walk()
    assert gcp_fix_delay_s(w, np.array([[25.0, 0.0, 0.0]])) == pytest.approx(2.0)
    w.gcp_t_s, w.gcp_id = np.array([]), np.array([], dtype=int)
    assert np.isnan(gcp_fix_delay_s(w, np.array([[25.0, 0.0, 0.0]])))


def test_trajectory_frame_layouts():
    w = _walk(5)
    sol = {"m": (w.pos_true_n_m + 1.0, w.mat_true_nb)}
    h = trajectory_frame("p", w, sol, w.t_s >= 2)
    assert list(h["method"].unique()) == ["Truth", "m"] and "heading_deg" in h and len(h) == 10
    e = trajectory_frame("p", w, sol, w.t_s >= 2, attitude="errors")
    assert (e[["roll_err_deg", "pitch_err_deg", "heading_err_deg"]].abs().to_numpy() < 1e-9).all()
    assert np.allclose(e.loc[e["method"] == "m", "E"] - e.loc[e["method"] == "Truth", "E"].to_numpy(), 1.0)
    with pytest.raises(ValueError, match="attitude"):
        trajectory_frame("p", w, sol, w.t_s >= 2, attitude="euler")


def test_run_methods_reuses_a_given_nhc_solution_exactly():
    from ilocalg.ins.chain import run_methods
    from ilocalg.sim import ins_walk

    walk = ins_walk.simulate("iphone", "iphone_5s", seed=1)
    ref, r_ref = run_methods(walk, "truth", "downweight")
    got, r_got = run_methods(walk, "truth", "downweight", nhc=ref[METHODS[0]])
    assert got[METHODS[0]] is ref[METHODS[0]]
    for m in METHODS:
        assert all(np.array_equal(a, b) for a, b in zip(got[m], ref[m], strict=True))
    assert np.array_equal(r_got.pos_n_m, r_ref.pos_n_m)


def test_run_methods_many_gives_each_walk_the_bits_of_run_methods():
    from ilocalg.ins.chain import run_methods, run_methods_many
    from ilocalg.ins.eskf import same_run
    from ilocalg.sim import ins_walk

    walks = [ins_walk.simulate("iphone", "iphone_5s", seed=1), ins_walk.simulate("samsung", "samsung_s5", seed=2)]
    for walk, (sol, r) in zip(walks, run_methods_many(walks, "truth", "downweight"), strict=True):
        ref, r_ref = run_methods(walk, "truth", "downweight")
        for m in METHODS:
            assert all(np.array_equal(a, b) for a, b in zip(sol[m], ref[m], strict=True)), m
        assert same_run(r_ref, r) and np.array_equal(r.P_plus, r_ref.P_plus)


def test_smoothing_with_shared_gains_has_the_bits_of_a_fresh_smoothing():
    from ilocalg.ins.chain import run_methods, run_methods_many, smooth_gcp
    from ilocalg.ins.smoother import eskf_rts_smooth, rts_gains, rts_gains_shared
    from ilocalg.sim import ins_walk

    walks = [ins_walk.simulate("samsung", "samsung_s5", seed=3)]
    (sol, r), = run_methods_many(walks, smooth=False)
    (sol_s, _), = run_methods_many(walks)
    assert list(sol) == list(METHODS[:3])
    G = smooth_gcp(sol, r)
    assert list(sol) == list(METHODS) and np.array_equal(G, rts_gains(r))
    assert all(np.array_equal(a, b) for a, b in zip(sol[METHODS[3]], sol_s[METHODS[3]], strict=True))
    # another stair handling resumes from the default filter: the shared beginning's gains are reused
    ref, _ = run_methods(walks[0], "truth", "drop")
    got, r_got = run_methods(walks[0], "truth", "drop", nhc=sol[METHODS[0]], prefix=(r,), gains_of=(r, G))
    for m in METHODS:
        assert all(np.array_equal(a, b) for a, b in zip(got[m], ref[m], strict=True)), m
    fresh = rts_gains(r_got)
    shared = rts_gains_shared(r_got, r, G)
    assert np.array_equal(shared, fresh)
    same = int(np.argmin((r_got.P_plus == r.P_plus).reshape(len(G), -1).all(axis=1)))
    assert 100 < same < len(G) - 100  # a real shared beginning, and a real difference after it
    # a run sharing nothing (another walk) and the run itself
    other = run_methods(ins_walk.simulate("samsung", "samsung_s5", seed=4))[1]
    assert np.array_equal(rts_gains_shared(other, r, G), rts_gains(other))
    assert np.array_equal(rts_gains_shared(r, r, G), G)
    sm = eskf_rts_smooth(r_got, with_cov=False, gains=shared)
    assert np.array_equal(sm.pos_n_m, got[METHODS[3]][0])
    with pytest.raises(ValueError, match="ref_gains"):
        rts_gains_shared(r_got, r, G[:-1])
