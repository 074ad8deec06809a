"""Pedestrian constraints for the INS: step detection, walking speed (WVC), NHC, ZUPT.

NHC: the body's lateral and vertical velocities are zero (tight weight). WVC (walking velocity
constraint): NHC with relaxed lateral/vertical weights plus a forward-velocity measurement from
the detected step frequency ``F`` and the user height ``h`` (eq. 7). ZUPT: the velocity is zero
while the user stands still (the paper's walkers stop 1-3 s after turns).

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 3.2, eq. (7); Chen, Pei, Chen (2011), "A smart phone based
PDR solution for indoor navigation", ION GNSS 2011 (the step model and its default parameters).
"""

from __future__ import annotations

import numpy as np

from ilocalg.ins.eskf import BodyVelocity, NavVelocity
from ilocalg.pdr.norm_peaks import detect_steps_norm_peaks
from ilocalg.pdr.signals import moving_mean_time

__all__ = [
    "WVC_REFERENCE_DEFAULTS",
    "walking_speed_mps",
    "step_epochs",
    "step_frequency_hz",
    "detect_stationary",
    "nhc_updates",
    "wvc_updates",
    "zupt_updates",
]

# ---- published values: Chen, Pei, Chen (2011), the step model's reference parameters --------------------
#: Default model parameters of eq. (7): a, b, c and the user height h (m). The paper uses "the
#: default height and model parameters" without printing a, b, c; these are the reference values of
#: Chen et al. (2011) (model reference, not an outcome of the paper).
WVC_REFERENCE_DEFAULTS = {"a": 0.371, "b": 0.227, "c": 1.0, "height_m": 1.75}
# ---- end of published values -------------------------------------------------------------------------------


def walking_speed_mps(step_freq_hz, height_m=None, a=None, b=None, c=None):
    """Forward walking speed ``v = (0.7 + a (h - 1.75) + b (F - 1.79) h / 1.75) c F`` (paper eq. 7).

    Parameters
    ----------
    step_freq_hz : float or array, step frequency F (steps per second)
    height_m : user height h (m); a, b, c : model parameters (None: :data:`WVC_REFERENCE_DEFAULTS`)

    References
    ----------
    Liao et al. (2016), eq. (7); Chen et al. (2011).
    """
    d = WVC_REFERENCE_DEFAULTS
    height_m = d["height_m"] if height_m is None else height_m
    a, b, c = (d[k] if v is None else v for k, v in (("a", a), ("b", b), ("c", c)))
    f = np.asarray(step_freq_hz, dtype=float)
    if np.any(f < 0) or not np.all(np.isfinite(f)):
        raise ValueError("step_freq_hz must be finite and >= 0")
    if not (np.isfinite(height_m) and height_m > 0):
        raise ValueError(f"height_m must be > 0, got {height_m}")
    step_len_m = (0.7 + a * (height_m - 1.75) + b * (f - 1.79) * height_m / 1.75) * c
    return step_len_m * f


def step_epochs(t_s, acc_b_mps2, min_interval_s=0.3, min_prominence_mps2=0.8, smooth_s=0.15) -> np.ndarray:
    """Indices (S,) of the IMU epochs at which a step is detected, for the WVC.

    The detector is :func:`ilocalg.pdr.norm_peaks.detect_steps_norm_peaks` (see there for the parameters);
    this adapter takes the INS's ``(t_s, acc_b_mps2)`` and keeps only the epochs the filter needs.
    """
    t_s = np.asarray(t_s, dtype=float)
    acc = np.asarray(acc_b_mps2, dtype=float)
    if acc.shape != (t_s.size, 3):
        raise ValueError(f"acc_b_mps2 must have shape ({t_s.size}, 3), got {acc.shape}")
    steps = detect_steps_norm_peaks(acc, t_s, min_interval_s=min_interval_s, min_prominence_mps2=min_prominence_mps2,
                                    smooth_s=smooth_s)
    return steps["i_peak"].to_numpy()


def step_frequency_hz(t_s, step_idx, max_period_s=1.2):
    """Step frequency at each step (1 / time since the previous step); NaN for the first step
    of a walking bout (gap longer than ``max_period_s``)."""
    t_steps = np.asarray(t_s, dtype=float)[np.asarray(step_idx)]
    period = np.diff(t_steps, prepend=np.nan)
    with np.errstate(invalid="ignore"):
        f = 1.0 / period
    f[~(period <= max_period_s)] = np.nan
    return f


def detect_stationary(t_s, acc_b_mps2, gyr_b_radps, window_s=1.0, acc_sd_max_mps2=0.3,
                      gyr_max_radps=0.1):
    """Boolean (N,): the device is still (moving-window acc-norm spread and gyro norm both small)."""
    t_s = np.asarray(t_s, dtype=float)
    an = np.linalg.norm(np.asarray(acc_b_mps2, dtype=float), axis=1)
    gn = np.linalg.norm(np.asarray(gyr_b_radps, dtype=float), axis=1)
    m = moving_mean_time(an, t_s, window_s)
    m2 = moving_mean_time(an**2, t_s, window_s)
    sd = np.sqrt(np.clip(m2 - m**2, 0.0, None))
    gm = moving_mean_time(gn, t_s, window_s)
    return (sd < acc_sd_max_mps2) & (gm < gyr_max_radps)


def _every(t_s, mask, interval_s):
    """Indices of ``mask`` epochs thinned to at most one per ``interval_s``."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return idx
    slot = np.floor((t_s[idx] - t_s[0]) / interval_s).astype(np.int64)
    keep = np.concatenate([[True], slot[1:] != slot[:-1]])
    return idx[keep]


def nhc_updates(t_s, moving, lateral_sd_mps=0.05, vertical_sd_mps=0.05, interval_s=0.5) -> BodyVelocity:
    """NHC: body lateral and vertical velocity zero while moving, every ``interval_s`` seconds."""
    t_s = np.asarray(t_s, dtype=float)
    idx = _every(t_s, np.asarray(moving, dtype=bool), interval_s)
    z = np.zeros((idx.size, 3))
    sd = np.tile([np.nan, lateral_sd_mps, vertical_sd_mps], (idx.size, 1))
    return BodyVelocity(t_s[idx], z, sd, name="NHC")


def wvc_updates(t_s, step_idx, step_freq, moving, height_m=None, params=None, forward_sd_mps=0.15,
                lateral_sd_mps=0.3, vertical_sd_mps=0.3) -> BodyVelocity:
    """WVC at every detected step with a valid frequency: forward speed from eq. (7), relaxed NHC.

    References
    ----------
    Liao et al. (2016), sec. 3.2 and eq. (7).
    """
    p = {k: v for k, v in WVC_REFERENCE_DEFAULTS.items() if k != "height_m"}
    p.update(params or {})
    t_s = np.asarray(t_s, dtype=float)
    step_idx = np.asarray(step_idx)
    f = np.asarray(step_freq, dtype=float)
    ok = np.isfinite(f) & np.asarray(moving, dtype=bool)[step_idx]
    idx, f = step_idx[ok], f[ok]
    v = walking_speed_mps(f, height_m, **p)
    z = np.column_stack([v, np.zeros_like(v), np.zeros_like(v)])
    sd = np.tile([forward_sd_mps, lateral_sd_mps, vertical_sd_mps], (idx.size, 1))
    return BodyVelocity(t_s[idx], z, sd, name="WVC")


def zupt_updates(t_s, stationary, sd_mps=0.02, interval_s=0.25) -> NavVelocity:
    """ZUPT: ENU velocity zero while stationary, every ``interval_s`` seconds."""
    t_s = np.asarray(t_s, dtype=float)
    idx = _every(t_s, np.asarray(stationary, dtype=bool), interval_s)
    return NavVelocity(t_s[idx], np.zeros((idx.size, 3)), np.full((idx.size, 3), sd_mps), name="ZUPT")
