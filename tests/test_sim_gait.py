import numpy as np
import pandas as pd
import pytest

from ilocalg.pdr.sam import match_waves_to_steps, sam_waves
from ilocalg.sim import gait


def _walk(seed, **kw):
    w = gait.make_walkers(2, seed)[1]
    return gait.simulate_walk(gait.straight_route(30.0, 0.3), w, seed, **kw)


def test_same_seed_same_bytes():
    a, b = _walk(7), _walk(7)
    assert a.imu.equals(b.imu) and a.steps.equals(b.steps)
    c = _walk(8)
    assert not np.array_equal(a.imu.to_numpy()[:100], c.imu.to_numpy()[:100])


def test_truth_is_consistent():
    sw = _walk(1)
    st = sw.steps
    assert st["length_m"].sum() == pytest.approx(30.0, abs=1e-9)
    end = st[["x_m", "y_m"]].to_numpy()[-1]
    np.testing.assert_allclose(end, [30 * np.cos(0.3), 30 * np.sin(0.3)], atol=1e-9)
    np.testing.assert_allclose(st["theta_rad"], 0.3, atol=1e-9)
    cad = 1.0 / st["duration_s"].mean()
    assert 1.6 < cad < 2.5                        # about two steps per second
    # at rest the accelerometer reads 1 g
    rest = sw.imu.loc[sw.imu.index < 0.9, ["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
    assert np.linalg.norm(rest.mean(0)) == pytest.approx(9.80665, abs=0.05)


def test_fixed_length_and_n_steps():
    sw = _walk(2, step_length_m=0.5, n_steps=15)
    assert len(sw.steps) == 15
    assert abs(sw.steps["length_m"].mean() - 0.5) < 0.03
    with pytest.raises(ValueError, match="exceed the route"):
        _walk(2, step_length_m=0.8, n_steps=100)


def test_features_span_table1_magnitudes():
    ws = gait.make_walkers(4, 3)
    rng = np.random.default_rng(0)
    feats = []
    for w in ws:
        for L in (0.4, 0.6, 0.8):
            sw = gait.simulate_walk(gait.straight_route(20.0), w, rng, step_length_m=L, n_steps=15)
            acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
            m = match_waves_to_steps(sam_waves(acc, sw.imu.index.to_numpy()), sw.steps["t_mid_s"], 0.15)
            feats.append(m.assign(L=L))
    f = pd.concat(feats)
    assert len(f) >= 0.95 * 4 * 3 * 15
    med = f.median()
    assert 0.4 < med["T"] < 0.65 and 4.0 < med["A"] < 17.0 and 0.5 < med["I"] < 1.9
    # longer steps give larger waves (amplitude grows with step length)
    assert np.corrcoef(f["A"], f["L"])[0, 1] > 0.3


def test_loop_route():
    r = gait.loop_route()
    assert r.shape == (29, 2)
    np.testing.assert_allclose(np.hypot(*np.diff(r, axis=0).T), 4.11)
    np.testing.assert_allclose(r[0], r[-1])
    with pytest.raises(ValueError, match="even"):
        gait.loop_route(27)


def test_bad_input():
    w = gait.make_walkers(1, 0)[0]
    with pytest.raises(ValueError, match="route_xy_m"):
        gait.simulate_walk([[0, 0]], w, 0)
    with pytest.raises(ValueError, match="step_length_m"):
        gait.simulate_walk(gait.straight_route(5), w, 0, step_length_m=-1)
    with pytest.raises(ValueError, match="n must be"):
        gait.make_walkers(0)


def test_step_length_and_cadence_follow_dynamic_similarity():
    """Alexander's stride / leg = 2.3 Fr^0.3, both ways, and the walkers' natural steps on it."""
    leg = np.array([0.82, 0.9, 1.0])
    L, f, v = gait.alexander_step(leg, speed_mps=1.4)
    np.testing.assert_allclose(2 * L / leg, 2.3 * (1.4**2 / (9.80665 * leg)) ** 0.3)
    np.testing.assert_allclose(L * f, 1.4)
    L2, f2, v2 = gait.alexander_step(leg, step_length_m=L)
    np.testing.assert_allclose(v2, 1.4)
    np.testing.assert_allclose(f2, f)
    for w in gait.make_walkers(5, 2):
        Lw, fw, _ = gait.alexander_step(w.leg_m, speed_mps=w.speed_mps)
        assert w.step_length_m == pytest.approx(float(Lw)) and w.cadence_hz == pytest.approx(float(fw))
        assert w.leg_m == pytest.approx(0.53 * w.height_m)
    with pytest.raises(ValueError, match="exactly one"):
        gait.alexander_step(0.9)


def test_pendulum_amplitude_and_step_variability():
    # the inverted pendulum: larger and faster steps bounce more
    a = gait.pendulum_amplitude_mps2([0.4, 0.6, 0.8], 2.0, 0.9)
    assert np.all(np.diff(a) > 0)
    assert gait.pendulum_amplitude_mps2(0.6, 2.2, 0.9) > gait.pendulum_amplitude_mps2(0.6, 1.8, 0.9)
    # leg 0.9 m, L / K = 0.48 m: h = 0.9 - sqrt(0.81 - 0.0576)
    h = 0.9 - np.sqrt(0.81 - 0.24**2)
    assert float(gait.pendulum_amplitude_mps2(0.6, 2.0, 0.9)) == pytest.approx((4 * np.pi) ** 2 * h / 2)
    w = gait.make_walkers(1, 5, world="assumed")[0]
    sw = gait.simulate_walk(gait.straight_route(200.0), w, 5, gait.gait_config("assumed"))
    st = sw.steps.iloc[1:-1]
    cv_t = st["duration_s"].std() / st["duration_s"].mean()
    cv_l = st["length_m"].std() / st["length_m"].mean()
    assert 0.015 < cv_t < 0.035 and 0.02 < cv_l < 0.04  # cv 2.5 % and 3 % (Hausdorff 2005)
    np.testing.assert_allclose(st["amp_mps2"], gait.pendulum_amplitude_mps2(st["length_m"], 1 / st["duration_s"],
                                                                            w.leg_m))
def test_pass_times_are_increasing_and_within_the_walk():
    route = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]])
    w = gait.make_walkers(1, 0)[0]
    sw = gait.simulate_walk(route, w, 0)
    t = gait.pass_times_s(sw, route)
    assert np.all(np.diff(t) > 0)
    assert t[0] == sw.steps["t_strike_s"].iloc[0]
    assert t[-1] <= sw.imu.index[-1]


def test_times_at_arc_are_the_step_ends():
    w = gait.make_walkers(1, 1)[0]
    sw = gait.simulate_walk(gait.straight_route(10.0), w, 1)
    ends = np.cumsum(sw.steps["length_m"].to_numpy())
    t_end = (sw.steps["t_strike_s"] + sw.steps["duration_s"]).to_numpy()
    np.testing.assert_allclose(gait.times_at_arc_s(sw, ends), t_end)


def test_training_walks_and_features():
    rng = np.random.default_rng(0)
    ws = gait.make_walkers(2, 0)
    walks = gait.training_walks(ws, rng, (0.5, 0.7), n_steps=10)
    assert [(w.name, L) for w, L, _ in walks] == [(ws[0].name, 0.5), (ws[0].name, 0.7), (ws[1].name, 0.5),
                                                  (ws[1].name, 0.7)]
    assert all(len(sw.steps) == 10 for _, _, sw in walks)
    f = gait.fixed_length_features(walks)
    assert set(f["target_m"]) == {0.5, 0.7}
    assert (f["length_m"] - f["target_m"]).abs().max() < 0.15      # N(target, 0.02 m) steps
    assert len(f) <= 40 and len(f) > 30                           # most true steps have a wave
    cw = gait.count_walks(ws, rng, n_steps=20)
    assert [len(sw.steps) for sw in cw] == [20, 20]


def test_measured_world_breaks_the_amplitude_length_link():
    from ilocalg.sim.measured import calibrated, param

    cc = gait.gait_config("copied")  # the uncalibrated world: the measured values copied
    assert cc.step_time_sd_rel == param("gait_stride_period_cv") and cc.amp_sd_rel == param("gait_step_amp_cv")
    cfg = gait.gait_config("measured")
    assert cfg.world == "measured"
    assert cfg.amp_sd_rel == calibrated("gait.amp_sd_rel") and cfg.strike_jitter_rel == calibrated(
        "gait.strike_jitter_rel")
    w = gait.make_walkers(1, 5, world="measured")[0]
    sw = gait.simulate_walk(gait.straight_route(200.0), w, 5, cfg)
    st = sw.steps.iloc[1:-1]
    pend = gait.pendulum_amplitude_mps2(st["length_m"], 1 / st["duration_s"], w.leg_m) * w.gain
    ratio = st["amp_mps2"] / pend
    # amplitude scatters about the pendulum value (the published model stays the mean), independently of length
    assert abs(ratio.mean() - 1.0) < 0.05
    assert abs(ratio.std() - cfg.amp_sd_rel) < 0.05
    assert abs(np.corrcoef(ratio, st["length_m"])[0, 1]) < 0.25
    # the assumed world is still reachable and unchanged by the measured draws
    a = gait.make_walkers(3, 1, world="assumed")
    assert all(x.gain == 1.0 for x in a)
    with pytest.raises(ValueError, match="world"):
        gait.gait_config("imagined")
