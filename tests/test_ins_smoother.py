import numpy as np
import pytest

from ilocalg import ins
from tests.test_ins_eskf import circle_run, nav_error


@pytest.fixture(scope="module")
def runs():
    return [circle_run(s, n=800) for s in range(4)]


def test_rts_never_worse_than_filtering(runs):
    for res, pos_t, vel_t, mat_t, _ in runs:
        sm = ins.eskf_rts_smooth(res)
        ef = nav_error(res.pos_n_m, res.vel_n_mps, res.mat_nb, pos_t, vel_t, mat_t)
        es = nav_error(sm.pos_n_m, sm.vel_n_mps, sm.mat_nb, pos_t, vel_t, mat_t)
        rms_f = np.sqrt(np.mean(ef**2, axis=0))
        rms_s = np.sqrt(np.mean(es**2, axis=0))
        assert np.all(rms_s[:6] <= rms_f[:6] * 1.02)
        assert np.linalg.norm(rms_s[:3]) < 0.8 * np.linalg.norm(rms_f[:3])


def test_smoothed_covariance_below_filtered_and_consistent(runs):
    nees = []
    for res, pos_t, vel_t, mat_t, _ in runs:
        sm = ins.eskf_rts_smooth(res)
        sd_f = np.sqrt(np.diagonal(res.P_plus, axis1=1, axis2=2))
        assert np.all(sm.sd <= sd_f + 1e-9)
        es = nav_error(sm.pos_n_m, sm.vel_n_mps, sm.mat_nb, pos_t, vel_t, mat_t)
        nees.append(np.mean((es[100:, :3] / sm.sd[100:, :3]) ** 2))
    assert 0.4 < np.mean(nees) < 2.0


def test_gain_formula_matches_definition(runs):
    res = runs[0][0]
    G = ins.rts_gains(res)
    k = 37
    ref = res.P_plus[k] @ res.Phi[k + 1].T @ np.linalg.inv(res.P_minus[k + 1])
    assert np.allclose(G[k], ref, atol=1e-8)


def test_window_ends_and_online_limits(runs):
    res = runs[0][0]
    t = res.t_s
    ends = ins.window_ends(t, 5.0)
    assert ends[-1] and ends.sum() == int(np.ceil((t[-1] - t[0] + 1e-9) / 5.0))
    full = ins.eskf_rts_smooth(res, with_cov=False)
    big = ins.online_window_smooth(res, 10 * t[-1])
    assert np.allclose(full.pos_n_m, big.pos_n_m)
    w5 = ins.online_window_smooth(res, 5.0)
    assert np.allclose(w5.pos_n_m[ends], res.pos_n_m[ends])  # window ends keep the filtered value
    assert w5.latency_s.max() <= 5.0 + 1e-9 and w5.latency_s.min() == 0.0
    with pytest.raises(ValueError, match="window_s"):
        ins.window_ends(t, -1.0)


def test_class_wrapper_agrees_with_functions():
    from tests.test_ins_eskf import CFG

    res, *_ = circle_run(5, n=300)
    # rebuild the same inputs through the class: run_eskf is deterministic given its inputs
    t = res.t_s
    est = ins.ErrorStateINS(ins.initial_covariance(), CFG)
    with pytest.raises(ValueError, match="fit"):
        est.smooth()
    rng = np.random.default_rng(0)
    gyr = np.tile([0.0, 0.0, 0.2], (t.size, 1)) + rng.normal(0, 0.001, (t.size, 3))
    acc = np.tile([0.0, 0.24, 9.81], (t.size, 1))
    fix = ins.PositionFix(t[::20], np.zeros((t[::20].size, 3)), np.full((t[::20].size, 3), 0.5))
    est.fit(t, gyr, acc, np.zeros(3), np.array([1.2, 0, 0]), np.eye(3), [fix])
    ref = ins.run_eskf(t, gyr, acc, np.zeros(3), np.array([1.2, 0, 0]), np.eye(3), ins.initial_covariance(),
                       [fix], CFG)
    assert np.array_equal(est.result_.pos_n_m, ref.pos_n_m)
    assert np.allclose(est.smooth(10.0).pos_n_m, ins.online_window_smooth(ref, 10.0).pos_n_m)


def test_smoothing_without_history_equals_smoothing_with_it():
    from ilocalg import ins
    from ilocalg.ins.pipeline import run_walk
    from ilocalg.sim import ins_walk

    w = ins_walk.simulate("iphone", "iphone_5s", seed=5)
    a = run_walk(w, "wvc")
    b = run_walk(w, "wvc", keep_covariance=False)
    for window in (None, 10.0):
        sa = ins.eskf_rts_smooth(a, window_s=window, with_cov=True)
        sb = ins.eskf_rts_smooth(b, window_s=window, with_cov=True)
        assert np.allclose(sa.xs, sb.xs, rtol=0, atol=1e-12)
        assert np.allclose(sa.sd, sb.sd, rtol=1e-12, atol=1e-15)


def test_window_grid_offset_shifts_the_window_ends():
    from ilocalg.ins.smoother import window_ends

    t = np.arange(0.0, 30.0, 0.5)
    e0 = window_ends(t, 10.0)
    e3 = window_ends(t, 10.0, offset_s=3.0)
    assert t[e0].tolist() == [9.5, 19.5, 29.5]
    assert t[e3].tolist() == [2.5, 12.5, 22.5, 29.5]
    with pytest.raises(ValueError, match="offset_s"):
        window_ends(t, 10.0, offset_s=10.0)


def _rts_mean_one_grid(res, ends):
    """Eq. (8) on one window grid, written out epoch by epoch (the reference of the stacked smoother)."""
    G = ins.rts_gains(res)
    xs = np.zeros((res.t_s.size, 21))
    x = np.zeros(21)
    for k in range(res.t_s.size - 2, -1, -1):
        x = np.zeros(21) if ends[k] else G[k] @ (x + res.dx[k + 1])
        xs[k] = x
    return xs


def test_grids_smoothed_together_equal_each_grid_alone_bit_for_bit(runs):
    from ilocalg.ins.smoother import eskf_rts_smooth_grids

    res = runs[1][0]
    span = res.t_s[-1] - res.t_s[0]
    grids = [(w, f * w) for f in (0.0, 0.25, 0.5) for w in (0.5, 2.0, 3.0, 2 * span)] + [(None, 0.0)]
    together = eskf_rts_smooth_grids(res, grids, gains=ins.rts_gains(res))
    assert len(together) == len(grids) and eskf_rts_smooth_grids(res, []) == []
    for (w, off), sm in zip(grids, together, strict=True):
        ends = ins.window_ends(res.t_s, w, off)
        assert np.array_equal(sm.xs, _rts_mean_one_grid(res, ends))
        alone = ins.eskf_rts_smooth(res, window_s=w, with_cov=False, offset_s=off)
        for f in ("pos_n_m", "vel_n_mps", "mat_nb", "sensor", "xs", "latency_s"):
            assert np.array_equal(getattr(sm, f), getattr(alone, f)), (w, off, f)
        assert np.isnan(sm.sd).all()
