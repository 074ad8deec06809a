"""ilocalg.pdr.luo_pdr: Luo et al.'s PDR on a seeded simulated walk."""

import numpy as np
import pytest

from ilocalg.pdr.luo_pdr import LuoLogs, eq4_vs_constant_error, luo_pdr, luo_training_spread
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import fit_luo_k
from ilocalg.sim import gait


def test_luo_pdr_gives_filter_inputs_along_the_walk_and_a_physical_training_spread():
    rng = np.random.default_rng(5)
    train = [sw for _, _, sw in gait.training_walks(gait.make_walkers(2, rng), rng)]
    k, _ = fit_luo_k([(*acc_from_log(sw.imu), sw.steps["length_m"]) for sw in train])
    sw = gait.simulate_walk(gait.straight_route(30.0), gait.make_walkers(1, rng)[0], rng)
    p = luo_pdr(sw.imu, k, rest_s=sw.config.stand_s)
    n = p["step_m"].size
    assert p["state_t_s"].shape == (n + 1,) and p["theta_rad"].shape == (n,)
    assert p["state_t_s"][0] == sw.imu.index[0] and np.all(np.diff(p["state_t_s"]) > 0)
    assert p["heading_rad"].shape == (len(sw.imu),)
    assert (p["step_m"] >= 0).all() and 0.5 * len(sw.steps) < n < 1.5 * len(sw.steps)
    # the walk goes straight along x: the WDM heading at each step is within 30 deg of it on average
    assert np.degrees(np.abs(np.angle(np.exp(1j * p["theta_rad"])))).mean() < 30.0
    sig_th, step_s, step_m = luo_training_spread(train, k)
    assert 0 < sig_th < np.pi and 0.3 < step_s < 1.5 and 0.3 < step_m < 1.0


def test_eq4_against_a_constant_on_walks_of_known_length():
    rng = np.random.default_rng(6)
    tw = gait.training_walks(gait.make_walkers(2, rng), rng)
    train = [sw for _, _, sw in tw]
    test = [(length, sw) for _, length, sw in tw]
    e4, ec = eq4_vs_constant_error(train, test)
    const = np.mean([sw.steps["length_m"].mean() for sw in train])
    assert ec == pytest.approx(np.mean([abs(const - length) / length for length, _ in test]))
    assert 0 < ec < 1 and np.isfinite(e4) and e4 >= 0


def test_logs_shared_across_k_and_detectors_give_the_uncached_results():
    """One LuoLogs for several k and detectors (as fusion_knn_pdr's runs use it) gives, bit for bit, what each call
    computes alone; its arrays are read-only and the step frames it returns are new ones."""
    rng = np.random.default_rng(7)
    train = [sw for _, _, sw in gait.training_walks(gait.make_walkers(2, rng), rng)]
    sw = gait.simulate_walk(gait.straight_route(25.0), gait.make_walkers(1, rng)[0], rng)
    logs = LuoLogs()
    for det in (None, {"threshold_mps2": 0.5}, {"rule": "valley_rise"}, None):
        k, sig = fit_luo_k([(*acc_from_log(w.imu), w.steps["length_m"]) for w in train], det)
        assert logs.fit_k(train, det) == (k, sig)
        assert luo_training_spread(train, k, det, logs=logs) == luo_training_spread(train, k, det)
        for kk in (k, 1.3 * k):
            got, want = luo_pdr(sw.imu, kk, det, sw.config.stand_s, logs=logs), luo_pdr(sw.imu, kk, det,
                                                                                           sw.config.stand_s)
            assert got.keys() == want.keys()
            assert all(got[n].tobytes() == want[n].tobytes() for n in got)
        test = [(0.6, w) for w in train]
        assert eq4_vs_constant_error(train, test, det, logs=logs) == eq4_vs_constant_error(train, test, det)
    assert not logs.headings(sw.imu, sw.config.stand_s).flags.writeable
    assert not logs.acc(sw.imu)[0].flags.writeable
    a, b = logs.steps(sw.imu, 1.0), logs.steps(sw.imu, 1.0)
    assert a is not b and a.equals(b)
