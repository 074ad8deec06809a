"""Simulated Hartmann et al. (2010) set-up: a hand-held object with a MEMS IMU and a video-tracked marker.

Deterministic from ``seed``. The object (IMU and marker on a hand) moves smoothly inside a volume of
about 1 m, with quicker passages during which the marker tracker loses the marker.

Parameters and their sources
----------------------------
From Yeh & Huang's survey (sec. 5.1, Table 2):
  - IMU (ADIS16350) at 400 Hz; white noise sd 0.4 deg/s (gyro) and 0.05 m/s^2 (accelerometer) per sample;
  - video tracking typically 5-10 measurements per second, millimetre precision; the camera looks along
    the z axis, so roll/pitch are unreliable (yaw and position are measured);
  - Table 2's tracker statistics (inputs of the experiment, not its outcome): mean rate ~5.8 Hz, longest
    outage ~2.2 s, many outages over 1 s. Our tracker model: camera frames at 10 Hz; a frame yields a
    measurement unless the marker moves too fast (angular rate above ``blur_rate_dps`` = 60 deg/s or speed
    above ``blur_speed_mps`` = 0.6 m/s, motion blur) and otherwise with probability 0.85 (occlusion, detection
    failures).
  - outages over 1 s (occlusion, marker out of view), on top of the frame losses: Poisson, 21.5 per 120 s,
    lasting 1 s + Exp(0.34 s) (Table 2: 21.5 outages over 1 s per sequence, longest 2.24 s on average; the
    sequence length is not given, 120 s is assumed).
Assumptions (not given by the paper):
  - IMU biases drawn once: gyro sd 0.3 deg/s, accelerometer sd 0.1 m/s^2 (ADIS16350-class residual
    turn-on biases); constant during a sequence;
  - tracker noise sd: 3 mm in x and y, 8 mm in z (depth along the optical axis), 1 deg in yaw (the survey,
    L218: "position precision in the millimetre range"; the numbers are an assumption and an input of
    Table 2's mean deviation, which largely echoes them);
  - motion: per axis a sum of three sinusoids (0.05-0.5 Hz) with +-0.35 m amplitude in x, y and +-0.2 m in z;
    roll and pitch +-25 deg, yaw +-60 deg; a 3 s rest at the start (levelling).

References
----------
Yeh & Huang (葉濟賢, 黃偉立), image/inertial positioning survey (teaching report), sec. 5.1-5.3, Table 2,
citing Hartmann, Link, Trommer (2010), IEEE/ION PLANS.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ilocalg.ins.hartmann import ACC_SD_DEFAULT_MPS2, GYR_SD_DEFAULT_DPS, VT_SD_DEFAULT
from ilocalg.ins.mechanisation import GRAVITY_N_MPS2, dcm_to_rotvec, euler_to_dcm
from ilocalg.units import as_rng

__all__ = ["HartmannSequence", "simulate", "IMU_RATE_HZ"]

# ---- published values: Yeh & Huang's survey, sec. 5.1 (with the IMU noise of ilocalg.ins.hartmann) -----------
#: IMU (ADIS16350) sampling rate, Hz.
IMU_RATE_HZ = 400.0
#: Tracker outages over 1 s (Table 2 describes the input data): 21.5 per test sequence on average, the longest
#: 2.24 s on average. The survey gives no sequence durations; with this package's 120 s sequences the rate is
#: 21.5 / 120 per second. Durations 1 s + Exp(0.34 s): the expected longest of 21.5 draws is then
#: 1 + 0.34 x H_21 ~ 2.24 s (H_n the harmonic number).
OUTAGE_RATE_PER_S, OUTAGE_EXCESS_MEAN_S = 21.5 / 120.0, 0.34
# ---- end of published values -------------------------------------------------------------------------------


@dataclass(frozen=True)
class HartmannSequence:
    """One test sequence.

    ``t_s`` (N,), ``gyr_b_radps`` / ``acc_b_mps2`` (N, 3) IMU samples (sample k = mean over [t_k, t_k+1));
    truth ``pos_v_m`` (N, 3), ``vel_v_mps`` (N, 3), ``euler_rad`` (N, 3); video tracker ``t_vt_s`` (M,),
    ``z_vt`` (M, 4) = (yaw rad, x, y, z m); ``bias_true`` (6,) = (gyro rad/s, acc m/s^2); ``params``.
    """

    t_s: np.ndarray
    gyr_b_radps: np.ndarray
    acc_b_mps2: np.ndarray
    pos_v_m: np.ndarray
    vel_v_mps: np.ndarray
    euler_rad: np.ndarray
    t_vt_s: np.ndarray
    z_vt: np.ndarray
    bias_true: np.ndarray
    params: dict = field(default_factory=dict)


def _sines(rng, t, amp, n=3, fmin=0.05, fmax=0.5):
    f = rng.uniform(fmin, fmax, n)
    ph = rng.uniform(0, 2 * np.pi, n)
    a = rng.uniform(0.5, 1.0, n)
    a = a / a.sum() * amp
    x = np.sum(a[:, None] * (np.sin(2 * np.pi * f[:, None] * t[None] + ph[:, None]) - np.sin(ph[:, None])), axis=0)
    return x


def simulate(duration_s: float = 120.0, seed=0, gyr_sd_dps: float = GYR_SD_DEFAULT_DPS,
             acc_sd_mps2: float = ACC_SD_DEFAULT_MPS2,
             gyr_bias_sd_dps: float = 0.3, acc_bias_sd_mps2: float = 0.1, frame_rate_hz: float = 10.0,
             detect_prob: float = 0.85, blur_rate_dps: float = 60.0, blur_speed_mps: float = 0.6,
             vt_sd=VT_SD_DEFAULT, rest_s: float = 3.0, outage_rate_per_s: float = OUTAGE_RATE_PER_S,
             outage_excess_mean_s: float = OUTAGE_EXCESS_MEAN_S) -> HartmannSequence:
    """Simulate one sequence (see the module docstring for every parameter's source).

    Besides the frame-by-frame losses (motion blur, detection failures), the tracker has outages longer than
    1 s (the marker occluded or out of view): a Poisson number, ``outage_rate_per_s`` per second after the rest,
    starting uniformly, lasting ``1 s + Exp(outage_excess_mean_s)``; ``outage_rate_per_s=0`` turns them off.
    """
    if not duration_s > rest_s + 1:
        raise ValueError(f"duration_s must exceed rest_s + 1 s, got {duration_s}")
    if not 0 < detect_prob <= 1:
        raise ValueError(f"detect_prob must be in (0, 1], got {detect_prob}")
    rng = as_rng(seed)
    dt = 1.0 / IMU_RATE_HZ
    t = np.arange(int(round(duration_s * IMU_RATE_HZ)) + 1) * dt
    # motion starts smoothly after the rest period
    tm = np.clip(t - rest_s, 0.0, None)
    ramp = np.where(t < rest_s, 0.0, 1.0 - np.exp(-(tm / 1.5) ** 2))
    pos = np.column_stack([ramp * _sines(rng, tm, a) for a in (0.35, 0.35, 0.2)]) + [0.0, 0.0, 1.0]
    e0 = np.array([rng.normal(0, np.deg2rad(3)), rng.normal(0, np.deg2rad(3)), rng.uniform(-np.pi, np.pi)])
    eul = e0 + np.column_stack([ramp * _sines(rng, tm, np.deg2rad(a), fmin=0.05, fmax=0.4) for a in (25, 25, 60)])
    mat = euler_to_dcm(eul[:, 0], eul[:, 1], eul[:, 2])
    vel = np.gradient(pos, dt, axis=0)
    pos = pos[0] + np.concatenate([np.zeros((1, 3)), np.cumsum(0.5 * (vel[1:] + vel[:-1]) * dt, axis=0)])
    # increments over [t_k, t_k+1), consistent with the strapdown step (see ilocalg.sim.ins_walk)
    gyr_true = dcm_to_rotvec(np.matmul(np.swapaxes(mat[:-1], 1, 2), mat[1:])) / dt
    dv_n = vel[1:] - vel[:-1] - GRAVITY_N_MPS2 * dt
    acc_true = np.linalg.solve(0.5 * (mat[1:] + mat[:-1]), dv_n[..., None])[..., 0] / dt
    gyr_true = np.vstack([gyr_true, gyr_true[-1:]])
    acc_true = np.vstack([acc_true, acc_true[-1:]])
    bg = rng.normal(0, np.deg2rad(gyr_bias_sd_dps), 3)
    ba = rng.normal(0, acc_bias_sd_mps2, 3)
    n = t.size
    gyr = gyr_true + bg + rng.normal(0, np.deg2rad(gyr_sd_dps), (n, 3))
    acc = acc_true + ba + rng.normal(0, acc_sd_mps2, (n, 3))
    # video tracker: frames at frame_rate_hz, lost on fast motion (blur) or at random
    step = int(round(IMU_RATE_HZ / frame_rate_hz))
    fr = np.arange(0, n, step)
    rate_dps = np.rad2deg(np.linalg.norm(gyr_true[fr], axis=1))
    speed = np.linalg.norm(vel[fr], axis=1)
    ok = (rate_dps < blur_rate_dps) & (speed < blur_speed_mps) & (rng.random(fr.size) < detect_prob)
    ok[0] = True
    fr = fr[ok]
    sd = np.asarray(vt_sd, dtype=float)
    z = np.column_stack([eul[fr, 2], pos[fr]]) + rng.normal(0, 1, (fr.size, 4)) * sd
    z[:, 0] = (z[:, 0] + np.pi) % (2 * np.pi) - np.pi
    outages = np.zeros((0, 2))
    if not (np.isfinite(outage_rate_per_s) and outage_rate_per_s >= 0 and outage_excess_mean_s > 0):
        raise ValueError("outage_rate_per_s must be >= 0 and outage_excess_mean_s > 0")
    if outage_rate_per_s > 0 and duration_s - 3.0 > rest_s + 1.0:
        n_out = rng.poisson(outage_rate_per_s * (duration_s - rest_s))
        start = rng.uniform(rest_s + 1.0, duration_s - 3.0, n_out)
        outages = np.column_stack([start, start + 1.0 + rng.exponential(outage_excess_mean_s, n_out)])
        tf = t[fr]
        lost = np.zeros(fr.size, bool)
        for a, b in outages:
            lost |= (tf > a) & (tf < b)
        lost[0] = False
        fr, z = fr[~lost], z[~lost]
    return HartmannSequence(t_s=t, gyr_b_radps=gyr, acc_b_mps2=acc, pos_v_m=pos, vel_v_mps=vel,
                            euler_rad=(eul + np.pi) % (2 * np.pi) - np.pi, t_vt_s=t[fr], z_vt=z,
                            bias_true=np.concatenate([bg, ba]),
                            params={"duration_s": duration_s, "vt_sd": sd.tolist(), "rest_s": rest_s,
                                    "outages_s": outages.tolist()})
