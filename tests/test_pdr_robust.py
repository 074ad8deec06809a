import numpy as np
import pandas as pd
import pytest
from scipy import signal as ss

from ilocalg.pdr.robust import RobustStepDetector, bout_gate, detect_steps_robust
from ilocalg.sim import gait


def test_counts_simulated_walks_at_any_rate_and_class_agrees():
    ws = gait.make_walkers(3, 31)
    rng = np.random.default_rng(3)
    for w, rate in zip(ws, (50.0, 100.0, 200.0), strict=True):
        cfg = gait.GaitConfig(rate_hz=rate)
        sw = gait.simulate_walk(gait.straight_route(80.0), w, rng, cfg, n_steps=100)
        acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
        t = sw.imu.index.to_numpy()
        st = detect_steps_robust(acc, t)
        assert abs(len(st) - 100) <= 2
        pd.testing.assert_frame_equal(st, RobustStepDetector().detect(acc, t))


def test_irregular_sampling_is_resampled():
    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.002, 0.012, 8000))
    m = 9.8 + 2.0 * np.sin(2 * np.pi * 1.9 * t)
    st = detect_steps_robust(m, t)
    expected = 1.9 * (t[-1] - t[0])
    assert abs(len(st) - expected) <= 2
    # agrees with scipy find_peaks on the clean uniformly sampled sine
    tu = np.arange(t[0], t[-1], 0.01)
    p, _ = ss.find_peaks(np.sin(2 * np.pi * 1.9 * tu))
    assert abs(len(st) - p.size) <= 1


def test_bout_gate_drops_isolated_peaks():
    t = np.r_[0.0, 3.0, 5.0 + 0.5 * np.arange(10), 20.0]
    keep = bout_gate(t, 1.0, 8)
    np.testing.assert_array_equal(keep, np.r_[False, False, np.ones(10, bool), False])


def test_bad_input():
    with pytest.raises(ValueError, match="cutoff_hz"):
        detect_steps_robust(np.ones(500), np.arange(500) / 100.0, cutoff_hz=80.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        detect_steps_robust(np.ones(5), [0.0, 0.1, 0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="too short"):
        detect_steps_robust(np.ones(5), np.arange(5) / 100.0)
    with pytest.raises(ValueError, match="min_bout_steps"):
        detect_steps_robust(np.ones(500), np.arange(500) / 100.0, min_bout_steps=0)
