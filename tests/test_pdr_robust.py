import numpy as np
import pandas as pd
import pytest
from scipy import signal as ss

from ilocalg.pdr.robust import (
    ROBUST_DEFAULTS,
    RobustSignal,
    RobustStepDetector,
    bout_gate,
    detect_steps_robust,
    stride_nac,
    trim_bout_ends,
    trim_bout_onsets,
)
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


def test_stride_nac_agrees_with_corrcoef_and_separates_walking_from_noise():
    rng = np.random.default_rng(5)
    t = np.arange(0, 20, 0.01)
    walk = 9.8 + 2.0 * np.sin(2 * np.pi * 2.0 * t) + 0.6 * np.sin(2 * np.pi * 1.0 * t + 0.3)   # stride 1.0 s
    noise = 9.8 + rng.normal(0.0, 1.0, t.size)
    idx = np.array([300, 1000, 1700])
    # one lag: the Pearson correlation of the centred stride window with the window before or after it
    for i in idx:
        ref = max(np.corrcoef(walk[i - 50:i + 50], walk[i - 50 + s:i + 50 + s])[0, 1] for s in (100, -100))
        assert stride_nac(walk, [i], 100, 100)[0] == pytest.approx(ref, abs=1e-12)
    assert (stride_nac(walk, idx, 50, 200) > 0.99).all()        # a repeating stride
    assert (stride_nac(noise, idx, 50, 200) < 0.5).all()        # no stride repeats in white noise
    # a window that leaves the signal does not count; with none inside, -1
    assert stride_nac(walk, [10, t.size - 10], 100, 100).tolist() == [-1.0, -1.0]
    assert stride_nac(np.full(500, 9.8), [250], 50, 100)[0] == -1.0     # constant: no correlation
    assert stride_nac(walk, [], 50, 100).size == 0
    with pytest.raises(ValueError, match="lag_min"):
        stride_nac(walk, idx, 0, 10)


def test_trim_bout_ends_drops_only_low_scoring_ends():
    t = np.array([0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 5.0, 5.5, 9.0])       # bouts: 6 peaks, 2 peaks, 1 peak
    score = np.array([0.1, 0.2, 0.9, 0.1, 0.8, 0.3, 0.1, 0.1, 0.9])
    asked = []

    def fn(k):
        asked.extend(k.tolist())
        return score[k]

    keep = trim_bout_ends(t, fn, max_step_s=1.0, min_score=0.5)
    # the first bout loses its two low first peaks and its low last one, never the low peak inside (index 3)
    assert keep.tolist() == [False, False, True, True, True, False, False, False, True]
    assert 3 not in asked                                             # only the current ends are scored
    assert trim_bout_ends(t, fn, 1.0, -1.0).all()
    assert trim_bout_ends([], fn, 1.0, 0.5).size == 0


def test_walk_detection_drops_handling_before_a_walk():
    # 3 s of handling (seeded broadband noise: irregular peaks less than max_step_s apart) before 20 s of
    # walking at 2 steps/s
    rate = 100.0
    t = np.arange(0, 23, 1 / rate)
    m = np.full(t.size, 9.8)
    walk = t >= 3.0
    m[walk] += 2.0 * np.sin(2 * np.pi * 2.0 * (t[walk] - 3.0) - np.pi / 2) + 0.5 * np.sin(np.pi * 2.0 * t[walk])
    m[~walk] += np.random.default_rng(0).normal(0.0, 3.0, int((~walk).sum()))
    true = int(round(2.0 * 20.0))
    gated = detect_steps_robust(m, t)
    plain = detect_steps_robust(m, t, min_stride_nac=None)
    assert abs(len(gated) - true) <= 1
    assert len(plain) >= len(gated) + 3                               # the bumps join the bout without the gate
    assert (gated["t_s"] > 2.8).all()
    with pytest.raises(ValueError, match="min_stride_nac"):
        detect_steps_robust(m, t, min_stride_nac=1.5)


def test_trim_bout_onsets_drops_only_a_bout_s_weak_first_peaks():
    # two bouts; the first starts with two weak peaks (0.2 and 0.5 against the same foot's 2.0 and 2.2 one stride
    # later), and a weak peak inside it (0.3) and at its end (0.2) stay; the second bout starts strong
    t = np.r_[0.5 * np.arange(8), 10.0 + 0.5 * np.arange(4)]
    prom = np.array([0.2, 0.5, 2.0, 2.2, 0.3, 2.1, 2.0, 0.2, 1.0, 1.0, 0.1, 1.0])
    keep = trim_bout_onsets(t, prom, max_step_s=1.0, min_ratio=0.3)
    assert keep.tolist() == [False, False] + [True] * 10
    assert trim_bout_onsets(t, prom, 1.0, 0.0).all()
    # one stride = one peak: the first peak against the next one
    assert trim_bout_onsets(t, prom, 1.0, 0.3, stride_peaks=1).tolist() == [True] * 12
    # a bout too short to hold the peak one stride later is left alone
    assert trim_bout_onsets([0.0, 0.5], [0.1, 5.0], 1.0, 0.3).all()
    assert trim_bout_onsets([], [], 1.0, 0.3).size == 0
    with pytest.raises(ValueError, match="shape"):
        trim_bout_onsets(t, prom[:-1], 1.0, 0.3)
    with pytest.raises(ValueError, match="stride_peaks"):
        trim_bout_onsets(t, prom, 1.0, 0.3, stride_peaks=0)


def test_gait_onset_drops_the_weight_shift_before_a_walk_and_only_with_walk_detection():
    # 2.5 s standing, then a 20 s walk at 2 steps/s (first landing 2.75 s, prominence about 2 m/s^2) with a bump
    # (the weight shift) one step period before its first landing; the stride test keeps the bump
    rate = 100.0
    t = np.arange(0, 24, 1 / rate)
    m = np.full(t.size, 9.8)
    walk = (t >= 2.5) & (t < 22.5)
    m[walk] += 2.0 * np.sin(2 * np.pi * 2.0 * (t[walk] - 2.5) - np.pi / 2) + 2.0

    def with_bump(amp):
        return m + amp * np.exp(-0.5 * ((t - 2.25) / 0.08) ** 2)

    weak = with_bump(1.5)                                   # filtered prominence ~0.5: about 0.26 of the next ones
    on, off = detect_steps_robust(weak, t), detect_steps_robust(weak, t, min_onset_ratio=None)
    assert len(off) == len(on) + 1 == 41 and off["t_s"].iloc[0] < 2.3 < 2.7 < on["t_s"].iloc[0]
    assert off["prominence_mps2"].iloc[0] < ROBUST_DEFAULTS["min_onset_ratio"] * off["prominence_mps2"].iloc[2]
    # a bump at ~0.4 of the same foot's next landing is kept (a weak first step is still a step)
    assert len(detect_steps_robust(with_bump(2.0), t)) == 41
    # without walk detection (the track's and the gait statistics' setting) the onset rule is off too
    pd.testing.assert_frame_equal(detect_steps_robust(weak, t, min_stride_nac=None),
                                  detect_steps_robust(weak, t, min_stride_nac=None, min_onset_ratio=None))
    assert len(detect_steps_robust(weak, t, min_stride_nac=None)) == 41
    assert RobustStepDetector().get_params() == ROBUST_DEFAULTS
    with pytest.raises(ValueError, match="min_onset_ratio"):
        detect_steps_robust(weak, t, min_onset_ratio=1.5)


def test_robust_signal_reused_over_a_grid_gives_each_call_s_result_exactly():
    # irregular sampling (resampled), handling noise before a walk, a weak onset bump, and a stretch of constant |a|
    # after the walk whose windows are flat (their stride correlation is never reused from another call)
    rng = np.random.default_rng(5)
    t = np.cumsum(rng.uniform(0.004, 0.006, 6000))
    m = np.full(t.size, 9.8)
    walk = (t >= 5.0) & (t < 21.0)
    m[walk] += 2.0 * np.sin(2 * np.pi * 1.9 * (t[walk] - 5.0) - np.pi / 2) + 0.4 * np.sin(np.pi * 1.9 * t[walk])
    m[t < 4.0] += rng.normal(0.0, 2.0, int((t < 4.0).sum()))
    m += 1.2 * np.exp(-0.5 * ((t - 4.7) / 0.08) ** 2) + 3.0 * np.exp(-0.5 * ((t - 23.0) / 0.05) ** 2)
    grid = [dict(cutoff_hz=c, prominence_mps2=p, max_step_s=x, min_bout_steps=b, min_stride_nac=n, min_onset_ratio=o)
            for c in (2.0, 3.0) for p in (0.3, 1.2) for x in (1.0, 1.2, np.inf) for b in (1, 8)
            for n in (None, 0.0, 0.5) for o in (None, 0.3)]
    sig = RobustSignal(m, t)
    for k in rng.permutation(len(grid)).tolist() + [0, 1]:      # any order, and again
        pd.testing.assert_frame_equal(sig.detect(**grid[k]), detect_steps_robust(m, t, **grid[k]), check_exact=True)
        pd.testing.assert_frame_equal(detect_steps_robust(sig, None, **grid[k]), detect_steps_robust(m, t, **grid[k]),
                                      check_exact=True)
    # each peak's stride correlation is its own, whichever peaks are asked with it
    y, idx = m[:3000], np.arange(700, 2800, 37)
    assert stride_nac(y, idx, 50, 200, 2).tolist() == [stride_nac(y, [i], 50, 200, 2)[0] for i in idx]
    with pytest.raises(ValueError, match="lag_min"):
        sig.detect(min_step_s=0.6, max_step_s=0.5)
    with pytest.raises(ValueError, match="min_bout_steps"):
        RobustSignal(m, t).detect(min_bout_steps=0)
    with pytest.raises(ValueError, match="strictly increasing"):
        RobustSignal(np.ones(5), [0.0, 0.1, 0.1, 0.2, 0.3]).detect()
