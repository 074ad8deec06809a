import numpy as np
import pandas as pd
import pytest

from ilocalg.pdr.peak_window import PeakWindowDetector, detect_steps_peak_window
from ilocalg.sim import gait


def test_counts_simulated_walks_and_class_agrees():
    ws = gait.make_walkers(3, 21)
    rng = np.random.default_rng(2)
    for w in ws:
        sw = gait.simulate_walk(gait.straight_route(80.0), w, rng, n_steps=100)
        acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
        t = sw.imu.index.to_numpy()
        st = detect_steps_peak_window(acc, t, threshold_mps2=1.5, rule="valley_rise")
        assert abs(len(st) - 100) <= 5
        assert np.diff(st["t_s"]).min() >= 0.2
        assert (st["a_max_mps2"] >= st["a_min_mps2"] + 1.5).all()
        pd.testing.assert_frame_equal(st, PeakWindowDetector(threshold_mps2=1.5, rule="valley_rise").detect(acc, t))


def test_time_window_and_new_bouts():
    rate = 50.0
    t = np.arange(int(20 * rate)) / rate
    m = 9.8 + 3.0 * np.sin(2 * np.pi * 2.0 * t) * ((t < 8) | (t > 12))
    st = detect_steps_peak_window(m, t, threshold_mps2=2.0, rule="valley_rise")
    # the first step, and the first after the 4 s pause, open bouts
    assert st["new_bout"].sum() == 2 and st["new_bout"].iloc[0]
    assert abs(len(st) - 32) <= 2
    # min_dt 0.6 s > the 0.5 s step period: only every other peak survives
    st2 = detect_steps_peak_window(m, t, threshold_mps2=2.0, min_dt_s=0.6, rule="valley_rise")
    assert len(st2) < 0.6 * len(st)


def test_literal_rule_b():
    """Luo et al. 2017 rule b: a peak is rejected when it differs from the previous peak by more than the
    threshold or comes outside 0.2-2 s after it; the sequence (re)starts with an uncounted reference peak."""
    rate = 50.0
    t = np.arange(int(20 * rate)) / rate
    walking = (t < 8) | (t > 12)
    m = 9.8 + 3.0 * np.sin(2 * np.pi * 2.0 * t) * walking
    st = detect_steps_peak_window(m, t, threshold_mps2=0.5, smooth_s=0.0)
    # 16 peaks before the pause, 16 after: one reference peak per bout is not counted
    assert len(st) == 30 and st["new_bout"].sum() == 2
    assert np.diff(st["t_s"]).min() >= 0.2
    # one peak 2 m/s^2 higher than its neighbours (difference > threshold) is rejected, the next kept
    spike = m.copy()
    i = int(np.argmin(np.abs(t - 3.125)))           # the peak at t = 3.125 s
    spike[i] += 2.0
    st2 = detect_steps_peak_window(spike, t, threshold_mps2=0.5, smooth_s=0.0)
    assert len(st2) == len(st) - 1 and not np.isclose(st2["t_s"], t[i]).any()
    # with a threshold above the spike it is kept; the class agrees with the function
    st3 = PeakWindowDetector(threshold_mps2=2.5, smooth_s=0.0).detect(spike, t)
    assert len(st3) == len(st)
    with pytest.raises(ValueError, match="rule must be one of"):
        detect_steps_peak_window(m, t, rule="valley")


def test_bad_input():
    t = np.arange(50) / 50.0
    with pytest.raises(ValueError, match="min_dt_s < max_dt_s"):
        detect_steps_peak_window(np.ones(50), t, min_dt_s=3.0)
    with pytest.raises(ValueError, match="not finite"):
        detect_steps_peak_window(np.r_[np.ones(49), np.nan], t)
    with pytest.raises(ValueError, match="too short"):
        detect_steps_peak_window(np.ones(2), t[:2])
    with pytest.raises(ValueError, match="one time per sample"):
        detect_steps_peak_window(np.ones(50), t[:40])
    irregular = t.copy()
    irregular[25:] += 0.3
    with pytest.raises(ValueError, match="irregularly sampled"):
        detect_steps_peak_window(np.ones(50), irregular)
    backwards = t.copy()
    backwards[10] = backwards[8]
    with pytest.raises(ValueError, match="strictly increasing"):
        detect_steps_peak_window(np.ones(50), backwards)
