import numpy as np
import pytest

from ilocalg import ins
from ilocalg.sim import ins_walk


@pytest.fixture(scope="module")
def walk():
    return ins_walk.simulate("samsung", "samsung_s5", seed=3)


def test_same_seed_same_arrays(walk):
    w2 = ins_walk.simulate("samsung", "samsung_s5", seed=3)
    for name in ("t_s", "gyr_b_radps", "acc_b_mps2", "pos_true_n_m", "gnss_pos_n_m", "gcp_pos_n_m"):
        assert np.array_equal(getattr(walk, name), getattr(w2, name))
    w3 = ins_walk.simulate("samsung", "samsung_s5", seed=4)
    assert not np.array_equal(walk.acc_b_mps2[:100], w3.acc_b_mps2[:100])


def test_phone_rate_irregular_15_to_20_hz(walk):
    rate = 1.0 / np.diff(walk.t_true_s)
    assert rate.min() >= 14.2 and rate.max() <= 20.01 and 15.5 < rate.mean() < 18.0
    assert np.unique(np.round(np.diff(walk.t_true_s), 6)).size > 2


def test_time_tags_jitter_within_two_sd_and_stay_ordered(walk):
    sd = ins_walk.PROFILES["samsung_s5"].time_jitter_sd_s
    err = walk.t_s - walk.t_true_s
    assert np.abs(err).max() <= 2 * sd + 1e-12 and 0.8 * sd < err.std() < 1.1 * sd
    assert np.all(np.diff(walk.t_s) > 0)
    ideal = ins_walk.simulate("samsung", ins_walk.PROFILES["samsung_s5"].ideal_timing(), seed=3)
    assert np.array_equal(ideal.t_s, ideal.t_true_s)


def test_walker_gait_from_published_relations_not_eq7():
    g = [ins_walk.walker_gait(np.random.default_rng(s), 1.70) for s in range(400)]
    v = np.array([d["speed_mps"] for d in g])
    f = np.array([d["cadence_hz"] for d in g])
    L = np.array([d["step_length_m"] for d in g])
    assert np.allclose(v, L * f)
    assert abs(v.mean() - ins_walk.LEVEL_SPEED_MEAN_MPS) < 0.03 and 0.12 < v.std() < 0.2
    assert 1.7 < f.mean() < 2.1 and 0.6 < L.mean() < 0.85


def test_stairs_one_tread_per_step(walk):
    st = walk.stairs_true & ~walk.stationary_true
    vh = np.hypot(walk.vel_true_n_mps[st, 0], walk.vel_true_n_mps[st, 1])
    tread = 7.0 / round(4.0 / ins_walk.STAIR_RISER_M)
    fmax = max(walk.params["stair_up_cadence_hz"], walk.params["stair_down_cadence_hz"])
    # horizontal speed on the flights (median over the stairs) is about tread x stair cadence, ~0.5 m/s
    assert 0.6 * tread * 1.4 < np.median(vh) < 1.2 * tread * fmax


def test_barometer_only_on_the_samsung(walk):
    assert walk.baro_t_s.size == walk.t_s.size
    assert np.std(walk.baro_height_m - walk.pos_true_n_m[:, 2]) == pytest.approx(0.1, rel=0.1)
    assert ins_walk.simulate("iphone", "iphone_5s", seed=0).baro_t_s.size == 0


def test_gauss_markov_stationary_sd_and_correlation():
    t = np.arange(0.0, 20000.0, 0.5)
    b = ins_walk.gauss_markov(np.random.default_rng(1), t, 2.0, 10.0, 2)
    assert b.std() == pytest.approx(2.0, rel=0.05)
    lag = 20  # 10 s = one correlation time
    r = np.corrcoef(b[:-lag, 0], b[lag:, 0])[0, 1]
    assert r == pytest.approx(np.exp(-1.0), abs=0.05)


def test_gauss_markov_has_the_bits_of_the_recursion_on_rows():
    rng = np.random.default_rng(5)
    t = np.cumsum(rng.uniform(0.01, 0.1, 500))
    got = ins_walk.gauss_markov(np.random.default_rng(2), t, 0.3, 50.0, 3)
    g = np.random.default_rng(2)  # the same draws, the recursion one numpy row at a time
    a = np.exp(-np.diff(t) / 50.0)
    w = g.normal(0.0, 1.0, (t.size, 3))
    w[0] *= 0.3
    w[1:] *= (0.3 * np.sqrt(1.0 - a * a))[:, None]
    ref = np.empty_like(w)
    ref[0] = w[0]
    for k in range(1, t.size):
        ref[k] = a[k - 1] * ref[k - 1] + w[k]
    assert got.shape == (500, 3) and got.flags.c_contiguous and np.array_equal(got, ref)
    assert ins_walk.gauss_markov(np.random.default_rng(2), t[:1], 0.3, 50.0, 2).shape == (1, 2)


def test_route_climbs_to_second_floor_and_returns(walk):
    z = walk.pos_true_n_m[:, 2]
    assert z.max() == pytest.approx(4.0, abs=0.1)
    assert np.linalg.norm(walk.pos_true_n_m[-1] - walk.pos_true_n_m[0]) < 0.5


def test_control_points_met_regularly_indoors(walk):
    assert walk.gcp_t_s.size >= 6 and np.all(walk.gcp_t_s >= walk.t_indoor_s)
    gap = np.diff(walk.gcp_t_s)
    assert 8.0 < gap.mean() < 35.0
    # Bluetooth fix: the surveyed coordinate (exact height) within the proximity offset, after the ranging delay
    g = ins_walk.GCP_XYZ_M[walk.gcp_id]
    assert np.array_equal(walk.gcp_pos_n_m[:, 2], g[:, 2])
    assert np.abs(walk.gcp_pos_n_m[:, :2] - g[:, :2]).max() < 4 * ins_walk.BLE_PROXIMITY_SD_M
    assert walk.gcp_sd_m == ins_walk.BLE_FIX_SD_M
    k = np.searchsorted(walk.t_s, walk.gcp_t_s)
    d = np.linalg.norm(walk.pos_true_n_m[k] - g, axis=1)
    assert d.max() < 0.6 + 2.0 * ins_walk.BLE_RANGING_CYCLE_S  # walked on for at most one ranging cycle


def test_ideal_control_point_fix_is_the_true_position():
    w = ins_walk.simulate("samsung", "samsung_s5", seed=3, gcp_mode="ideal")
    k = np.searchsorted(w.t_s, w.gcp_t_s)
    assert w.gcp_sd_m == 0.05
    assert np.abs(w.gcp_pos_n_m - w.pos_true_n_m[k]).max() < 5 * w.gcp_sd_m


def test_gnss_only_outdoors(walk):
    assert walk.gnss_t_s.max() < walk.t_indoor_s and walk.gnss_t_s.size > 60


def test_error_free_sensors_integrate_to_truth():
    prof = ins_walk.PhoneProfile("ideal", (1, 1), 0, 0, 0, 0, 0, 0)
    w = ins_walk.simulate("iphone", prof, seed=0)
    n = 20000
    p, _, C = ins.mechanise(w.t_s[:n], w.gyr_b_radps[:n], w.acc_b_mps2[:n], w.pos_true_n_m[0],
                            w.vel_true_n_mps[0], w.mat_true_nb[0])
    assert np.abs(p - w.pos_true_n_m[:n]).max() < 1e-6
    assert np.allclose(C, w.mat_true_nb[:n], atol=1e-9)


def test_bad_arguments():
    with pytest.raises(ValueError, match="route"):
        ins_walk.simulate("nokia")
    with pytest.raises(ValueError, match="profile"):
        ins_walk.simulate("samsung", "nokia")
    with pytest.raises(ValueError, match="gait"):
        ins_walk.simulate("samsung", gait="fast")
    with pytest.raises(ValueError, match="gcp_mode"):
        ins_walk.simulate("samsung", gcp_mode="wifi")


def test_bias_instability_x0_leaves_a_constant_bias_and_scales_linearly():
    prof = ins_walk.PROFILES["samsung_s5"]
    w0, w1, w3 = (ins_walk.simulate("samsung", prof.swept(k), seed=3) for k in (0.0, 1.0, 3.0))
    # paired: the same walk, tags and control-point fixes; only the bias instability differs
    assert np.array_equal(w0.t_s, w1.t_s) and np.array_equal(w0.gcp_pos_n_m, w3.gcp_pos_n_m)
    d1 = w1.acc_b_mps2 - w0.acc_b_mps2
    g1 = w1.gyr_b_radps - w0.gyr_b_radps
    # x1 adds a slowly varying Gauss-Markov bias: not constant, below 4 sd, smooth from sample to sample
    assert np.all(d1.std(axis=0) > 0) and np.abs(d1).max() < 4 * prof.acc_gm_sd_mps2
    assert np.abs(np.diff(d1, axis=0)).max() < 0.1 * prof.acc_gm_sd_mps2
    assert np.abs(g1).max() < 4 * prof.gyr_gm_sd_radps
    # x3 adds three times the same sequence; x0 adds nothing beyond the constant turn-on bias
    assert np.allclose(w3.acc_b_mps2 - w0.acc_b_mps2, 3 * d1, rtol=0, atol=1e-12)
    assert np.allclose(w3.gyr_b_radps - w0.gyr_b_radps, 3 * g1, rtol=0, atol=1e-14)
    assert prof.swept(0.0).acc_gm_sd_mps2 == 0 and prof.swept(0.0).gyr_gm_sd_radps == 0


def test_time_jitter_zero_gives_the_nominal_clock_and_large_jitter_stays_monotonic():
    prof = ins_walk.PROFILES["iphone_5s"]
    w0 = ins_walk.simulate("iphone", prof.swept(1.0, 0.0), seed=2)
    assert np.array_equal(w0.t_s, w0.t_true_s)
    w30 = ins_walk.simulate("iphone", prof.swept(1.0, 0.03), seed=2)
    err = w30.t_s - w30.t_true_s
    assert np.all(np.diff(w30.t_s) >= ins_walk.MIN_TAG_GAP_S - 1e-12)
    assert np.abs(err).max() <= 2 * 0.03 + 1e-9 and 0.8 * 0.03 < err.std() < 0.03
    # the jitter changes only the tags: the walk and the control-point fixes are the same
    assert np.array_equal(w0.t_true_s, w30.t_true_s) and np.array_equal(w0.gcp_pos_n_m, w30.gcp_pos_n_m)
    with pytest.raises(ValueError, match="bias_instability_factor"):
        prof.swept(-1.0)
    with pytest.raises(ValueError, match="time_jitter_sd_s"):
        prof.swept(1.0, float("nan"))


def test_gait_kw_moves_the_population_mean_with_the_same_walker_draws():
    a = ins_walk.simulate("iphone", "iphone_5s", seed=5)
    b = ins_walk.simulate("iphone", "iphone_5s", seed=5, gait_kw={"speed_mean_mps": 1.0})
    assert b.params["speed_mps"] == pytest.approx(a.params["speed_mps"] - 0.4)
    assert b.params["stair_up_cadence_hz"] == a.params["stair_up_cadence_hz"]
    with pytest.raises(ValueError, match="gait_kw"):
        ins_walk.simulate("iphone", gait_kw={"speed": 1.0})
    with pytest.raises(ValueError, match="gait_kw"):
        ins_walk.simulate("iphone", gait="legacy", gait_kw={"speed_mean_mps": 1.0})


def test_swept_noise_scale_scales_the_white_noise_only():
    base = ins_walk.PROFILES["samsung_s5"]
    lo = base.swept(noise_scale=1 / 3)          # the MPU-6500 datasheet densities
    assert lo.acc_noise_mps2_rsqrt_hz == pytest.approx(300e-6 * 9.80665)
    assert lo.gyr_noise_radps_rsqrt_hz == pytest.approx(np.deg2rad(0.01))
    assert (lo.acc_bias_sd_mps2, lo.time_jitter_sd_s, lo.acc_gm_sd_mps2) == (
        base.acc_bias_sd_mps2, base.time_jitter_sd_s, base.acc_gm_sd_mps2)
    a = ins_walk.simulate("samsung", base, seed=5)
    b = ins_walk.simulate("samsung", base.swept(noise_scale=2.0), seed=5)
    np.testing.assert_array_equal(a.t_s, b.t_s)            # paired draws: same clock, same walk
    np.testing.assert_allclose(a.pos_true_n_m, b.pos_true_n_m)
    with pytest.raises(ValueError, match="noise_scale"):
        base.swept(noise_scale=0.0)


def test_rssi_control_points_fire_near_the_beacon_once_per_passage():
    w = ins_walk.simulate("samsung", "samsung_s5", seed=4)          # default: the RSSI model
    assert w.params["gcp_mode"] == "rssi" and w.gcp_t_s.size >= 4
    k = np.minimum(np.searchsorted(w.t_s, w.gcp_t_s), w.t_s.size - 1)
    d = np.linalg.norm(w.pos_true_n_m[k] - ins_walk.GCP_XYZ_M[w.gcp_id], axis=1)
    assert np.all(d < 3.0)                                          # fired near the beacon it names
    np.testing.assert_allclose(w.gcp_pos_n_m, ins_walk.GCP_XYZ_M[w.gcp_id])   # the surveyed coordinate
    assert np.all(w.gcp_t_s >= w.t_indoor_s)
    # no RSSI scatter and the walker never within the immediate zone of a far beacon: no fix from it
    trig = ins_walk._rssi_triggers(np.array([0.0, 100.0]), np.array([[0.0, 0.0, 0.0], [50.0, 0.0, 0.0]]),
                                   np.array([0.0, 10.0, 0.0]), 0.0, 0.0, np.random.default_rng(0))
    assert trig == []
    # walking straight through a beacon without scatter: exactly one fix, within a cycle of the passage
    trig = ins_walk._rssi_triggers(np.array([0.0, 100.0]), np.array([[-50.0, 0.0, 0.0], [50.0, 0.0, 0.0]]),
                                   np.array([0.0, 0.0, 0.0]), 0.0, 0.0, np.random.default_rng(0))
    assert len(trig) == 1 and 49.0 < trig[0] < 52.0
    # with scatter: the cycles' mean RSSI as the boolean-mask mean of each cycle's packets (the reference)
    t = np.linspace(0.0, 200.0, 4001)
    pos = np.c_[3.0 * np.sin(t / 10.0), np.zeros_like(t), np.zeros_like(t)]
    for sd in (3.0, 8.0):
        trig = ins_walk._rssi_triggers(t, pos, np.array([0.0, 0.3, 0.0]), 20.0, sd, np.random.default_rng(7))
        g = np.random.default_rng(7)
        n_adv = int(200.0 / ins_walk.BLE_ADV_INTERVAL_S)
        t_adv = np.cumsum(np.full(n_adv, ins_walk.BLE_ADV_INTERVAL_S) + g.uniform(0, ins_walk.BLE_ADV_DELAY_MAX_S,
                                                                                  n_adv))
        noise = g.normal(0.0, sd, n_adv)
        phase = g.uniform(0.0, ins_walk.BLE_RANGING_CYCLE_S)
        keep = (t_adv >= 20.0) & (t_adv <= 200.0)
        t_adv, noise = t_adv[keep], noise[keep]
        p = np.column_stack([np.interp(t_adv, t, pos[:, j]) for j in range(3)])
        d = np.maximum(np.linalg.norm(p - np.array([0.0, 0.3, 0.0]), axis=1), 0.1)
        rssi = ins_walk.BLE_RSSI_1M_DBM - 10 * ins_walk.BLE_PATH_LOSS_EXP * np.log10(d) + noise
        thr = ins_walk.BLE_RSSI_1M_DBM - 10 * ins_walk.BLE_PATH_LOSS_EXP * np.log10(ins_walk.BLE_IMMEDIATE_M)
        cyc = np.floor((t_adv - phase) / ins_walk.BLE_RANGING_CYCLE_S).astype(np.int64)
        ref, armed, last = [], True, None
        for c in np.unique(cyc):
            armed = armed or (last is not None and c != last + 1)
            hit = rssi[cyc == c].mean() >= thr
            if hit and armed:
                ref.append(phase + (c + 1) * ins_walk.BLE_RANGING_CYCLE_S)
            armed, last = not hit, c
        assert len(ref) >= 2 and trig == ref
    with pytest.raises(ValueError, match="gcp_mode"):
        ins_walk.simulate("samsung", "samsung_s5", seed=0, gcp_mode="gate")


def test_phone_profile_changes_only_the_unsourced_values():
    from ilocalg.sim.ins_walk import PHONE_NOISE_FACTOR, PROFILES, phone_profile

    for name in ("samsung_s5", "iphone_5s"):
        assert phone_profile(name) == PROFILES[name]
        p = phone_profile(name, noise_factor=1.0, bias_instability_factor=0.0, time_jitter_sd_s=0.03)
        base = PROFILES[name]
        assert p.acc_noise_mps2_rsqrt_hz == pytest.approx(base.acc_noise_mps2_rsqrt_hz / PHONE_NOISE_FACTOR)
        assert p.acc_gm_sd_mps2 == 0.0 and p.time_jitter_sd_s == 0.03 and p.acc_bias_sd_mps2 == base.acc_bias_sd_mps2
    with pytest.raises(ValueError, match="profile must be one of"):
        phone_profile("nokia")


def _assert_same_walk(a, b):
    import dataclasses

    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), f.name
        elif isinstance(x, dict):
            assert x.keys() == y.keys(), f.name
            assert all(np.asarray(x[k]).tobytes() == np.asarray(y[k]).tobytes() for k in x), f.name
        else:
            assert x == y or (x != x and y != y), f.name


def test_truth_cache_gives_the_same_walks_and_keeps_walkers_apart():
    cache = ins_walk.TruthCache(maxsize=3)
    ideal = ins_walk.PROFILES["samsung_s5"].ideal_timing()
    cases = [("samsung", "samsung_s5", 3, {}),                       # fills the cache
             ("samsung", ideal, 3, {"gcp_mode": "ble"}),              # same walker: taken from the cache
             ("samsung", "midg2", 3, {"rssi_sd_db": 2.0}),
             ("samsung", "samsung_s5", 4, {}),                        # another seed, another walker
             ("iphone", "samsung_s5", 3, {}),                         # another route
             ("samsung", "samsung_s5", 3, {"gait": "legacy"}),        # another walker model
             ("samsung", "samsung_s5", 3, {"gait_kw": {"speed_mean_mps": 1.5}})]
    for route, prof, seed, kw in cases:
        got = ins_walk.simulate(route, prof, seed=seed, truth_cache=cache, **kw)
        _assert_same_walk(got, ins_walk.simulate(route, prof, seed=seed, **kw))
        got.pos_ref_n_m[0] += 1.0  # the walk owns its arrays: the cached truth is not touched
        assert len(cache) <= 3
    _assert_same_walk(ins_walk.simulate("samsung", "samsung_s5", seed=3, gait="legacy", truth_cache=cache),
                      ins_walk.simulate("samsung", "samsung_s5", seed=3, gait="legacy"))
    # a generator seed is never cached (its stream is the caller's)
    n = len(cache)
    ins_walk.simulate("samsung", "samsung_s5", seed=np.random.default_rng(3), truth_cache=cache)
    assert len(cache) == n
    with pytest.raises(ValueError, match="maxsize"):
        ins_walk.TruthCache(0)
