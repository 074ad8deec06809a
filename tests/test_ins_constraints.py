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
