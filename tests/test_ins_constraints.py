import numpy as np
import pytest

from ilocalg import ins


def test_walking_speed_eq7_reference_point_and_monotone():
    # at the model's reference height and frequency the step length is 0.7 m (eq. 7)
    assert ins.walking_speed_mps(1.79, height_m=1.75) == pytest.approx(0.7 * 1.79)
    v = ins.walking_speed_mps(np.linspace(1.2, 2.4, 20))
    assert np.all(np.diff(v) > 0)
    assert ins.walking_speed_mps(2.0, height_m=1.9) > ins.walking_speed_mps(2.0, height_m=1.6)
    with pytest.raises(ValueError, match="step_freq_hz"):
        ins.walking_speed_mps(-1.0)


def test_step_detection_and_frequency_on_synthetic_gait():
    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.05, 0.07, 1200))
    t -= t[0]
    f_step = 1.9
    acc = np.column_stack([0.2 * rng.normal(size=t.size), 0.2 * rng.normal(size=t.size),
                           9.81 + 2.5 * np.cos(2 * np.pi * f_step * t)])
    steps = ins.step_epochs(t, acc)
    assert steps.dtype.kind == "i" and abs(steps.size - f_step * t[-1]) <= 3
    f = ins.step_frequency_hz(t, steps)
    assert np.nanmedian(f) == pytest.approx(f_step, rel=0.05)


def test_stationary_detection():
    t = np.arange(600) * 0.06
    acc = np.tile([0.0, 0.0, 9.81], (600, 1))
    acc[300:, 2] += 2.5 * np.cos(2 * np.pi * 1.9 * t[300:])
    still = ins.detect_stationary(t, acc, np.zeros((600, 3)))
    assert still[:280].all() and not still[320:].any()


def test_update_sets_shapes_and_weights():
    t = np.arange(100) * 0.06
    moving = np.ones(100, bool)
    nhc = ins.nhc_updates(t, moving, 0.05, 0.05, interval_s=0.5)
    assert isinstance(nhc, ins.BodyVelocity) and np.isnan(nhc.sd[:, 0]).all() and np.allclose(nhc.sd[:, 1:], 0.05)
    steps = np.arange(5, 100, 9)
    wvc = ins.wvc_updates(t, steps, ins.step_frequency_hz(t, steps), moving)
    assert np.all(wvc.sd[:, 1] > nhc.sd[0, 1])  # relaxed lateral weight
    assert np.allclose(wvc.z[:, 0], ins.walking_speed_mps(1 / 0.54))
    assert isinstance(wvc, ins.BodyVelocity)
    z = ins.zupt_updates(t, ~moving)
    assert isinstance(z, ins.NavVelocity)
    assert z.t_s.size == 0


def test_step_frequency_chen_smoothing():
    t = np.array([0.0, 0.5, 1.1, 1.6, 5.0, 5.5])
    idx = np.arange(t.size)
    f = ins.step_frequency_hz(t, idx, smoothing="chen")
    assert np.isnan(f[0]) and f[1] == pytest.approx(2.0)  # second step of a bout: 1 / dt
    assert f[2] == pytest.approx(1.0 / (0.8 * 0.6 + 0.2 * 0.5))
    assert np.isnan(f[4]) and f[5] == pytest.approx(2.0)  # a new bout after a pause
    with pytest.raises(ValueError, match="smoothing"):
        ins.step_frequency_hz(t, idx, smoothing="kalman")


def test_detect_stairs_baro_finds_a_climb_and_not_noise():
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 60.0, 0.06)
    h = np.interp(t, [0, 20, 35, 60], [0, 0, 4.0, 4.0]) + rng.normal(0, 0.1, t.size)
    on = ins.detect_stairs_baro(t, t, h)
    climbing = (t > 22) & (t < 35)
    assert on[climbing].mean() > 0.95
    assert on[(t < 19) | (t > 38)].mean() < 0.02
    with pytest.raises(ValueError, match="barometer"):
        ins.detect_stairs_baro(t, t[:2], h[:2])


def test_wvc_on_stairs_drops_forward_and_vertical():
    t = np.arange(0.0, 10.0, 0.05)
    steps = np.arange(10, 190, 10)
    f = ins.step_frequency_hz(t, steps)
    st = t > 5.0
    w = ins.wvc_updates(t, steps, f, np.ones(t.size, bool), on_stairs=st)
    s_on = st[np.searchsorted(t, w.t_s)]
    assert np.all(np.isnan(w.sd[s_on][:, [0, 2]])) and np.all(np.isfinite(w.sd[s_on][:, 1]))
    assert np.all(np.isfinite(w.sd[~s_on]))
    d = ins.wvc_updates(t, steps, f, np.ones(t.size, bool), on_stairs=st, stair_action="downweight",
                        stair_forward_sd_mps=0.7)
    assert np.all(d.sd[s_on][:, 0] == 0.7) and np.all(np.isnan(d.sd[s_on][:, 2]))
