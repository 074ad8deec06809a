"""Simulated smartphone walks for the INS experiments (Liao et al. 2016, sec. 4).

A pedestrian holds a phone in front of them and walks: two loops outdoors with GNSS (filter
initialisation), into a building, up a staircase to the 2nd floor, around a classroom and back
(route ``"samsung"``, Fig 5); or up the stairs to the corridor end, back to the classroom, around
it and on to a lab (route ``"iphone"``, Fig 6). The walker stops 1-3 s after every turn. Four
indoor control points (corners and corridor middles) are met along the way.

Everything is deterministic from ``seed``. The truth is generated at 200 Hz (the paper's reference
rate); the phone IMU samples it at irregular 14.3-20 Hz intervals as interval means with
phone-grade biases, scale factors and white noise.

Parameters and their sources
----------------------------
Paper (Liao et al. 2016):
  - reference solution rate 200 Hz; phone IMU "15-17 Hz ... about 20 Hz, irregular" -> phone intervals of
    10-14 ticks of the 200 Hz grid (uniform), mean 16.7 Hz;
  - stops of 1-3 s after turns (ZUPT), uniform in [1, 3] s;
  - GNSS only during the two outdoor loops; four indoor control points, met "about every 15 s" (the
    indoor legs are sized so that the passages come every ~15 s);
    control points surveyed by total station (cm level): position-fix sd ``gcp_sd_m`` = 0.05 m;
  - MIDG-II (Table 3): 50 Hz, gyro bias 4.7 deg/h, accelerometer bias 6 mg, scale factors 5000 ppm
    (gyro) and 19700 ppm (accelerometer): the ``"midg2"`` reference-grade profile.
Phone profiles (datasheet class; the paper defers to Liao et al. 2014 and states only that the two
phones' IMUs are similar, the iPhone's somewhat better): InvenSense MPU-6500 class parts:
  - ``samsung_s5``: accelerometer bias sd 30 mg (datasheet zero-g offset +-60 mg, read as 2 sd),
    gyro residual bias sd 0.3 deg/s (after the phone's own at-rest calibration), scale factors sd
    1.5 % (datasheet sensitivity tolerance +-3 %), noise densities 300 ug/sqrt(Hz) and
    0.01 deg/s/sqrt(Hz) x 3 (phone output filtering and electrical noise);
  - ``iphone_5s``: 20 mg, 0.2 deg/s, 1.0 %, same noise densities.
Walker (modelling assumptions, not from the paper):
  - step frequency 1.85 Hz (sd 0.05 Hz, slow Ornstein-Uhlenbeck variation, 10 s correlation);
  - true step length from eq. (7) with the walker's own height 1.70 m and a personal scale factor
    ``c`` ~ N(1.0, 0.05): the default-parameter WVC therefore mis-predicts speed by a few percent
    (the paper cites 40-50 % step-length variation between walkers; we keep one walker modest);
  - stairs: 0.5 m/s horizontal, rise 4 m over 7 m (about 24 steps of 0.17 m x 0.29 m at 1.75 steps/s);
  - hand-held vibration and dynamic misalignment: vertical bounce 2.5 cm at the step frequency,
    lateral sway 1.5 cm at half of it; attitude oscillation roll 2 deg, pitch 2 deg, yaw 3 deg; a slowly
    wandering yaw misalignment (sd 3 deg, 5 s correlation); hand tremor at rest (0.3 deg, 0.3 s); the
    random attitude terms are Ornstein-Uhlenbeck sequences smoothed over 0.5 s / 0.1 s (Gaussian sigma)
    so that their angular rates stay physical.
GNSS outdoors (phone grade, assumption): 1 Hz, sd 2.5 m horizontal, 4 m vertical.
Initial heading (assumption): truth + N(0, 5 deg), as from a map-aligned start.

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 4, Figs 5-6, Table 3; Chen et al. (2011) step model.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ilocalg.ins.constraints import walking_speed_mps
from ilocalg.ins.mechanisation import GRAVITY_N_MPS2, dcm_to_rotvec, euler_to_dcm
from ilocalg.units import as_rng

__all__ = ["PhoneProfile", "PROFILES", "ROUTES", "PHONES", "GCP_XYZ_M", "InsWalk", "simulate"]

# ---- published values: Liao et al. (2016), sec. 4 (reference rate) and Table 3 (MIDG-II) -------------------
#: Rate of the paper's reference solution, Hz.
TRUTH_RATE_HZ = 200.0
#: MIDG-II reference IMU (Table 3): sampling interval in 200 Hz ticks (50 Hz), accelerometer bias (mg), gyro
#: bias (deg/h), accelerometer and gyro scale factors (5000 ppm gyro, 19700 ppm accelerometer).
_MIDG2_TICKS, _MIDG2_ACC_BIAS_MG, _MIDG2_GYR_BIAS_DPH, _MIDG2_ACC_SF, _MIDG2_GYR_SF = (4, 4), 6, 4.7, 0.0197, 0.005
# ---- end of published values -------------------------------------------------------------------------------


@dataclass(frozen=True)
class PhoneProfile:
    """IMU error profile. Biases/scale factors are drawn once per run (sd given); noise is white.

    ``ticks`` is the allowed range of sample intervals in 200 Hz ticks (inclusive).
    """

    name: str
    ticks: tuple[int, int]
    acc_bias_sd_mps2: float
    gyr_bias_sd_radps: float
    acc_sf_sd: float
    gyr_sf_sd: float
    acc_noise_mps2_rsqrt_hz: float
    gyr_noise_radps_rsqrt_hz: float


_MG = 9.80665e-3
PROFILES = {
    "samsung_s5": PhoneProfile("samsung_s5", (10, 14), 30 * _MG, np.deg2rad(0.3), 0.015, 0.015,
                               3 * 300e-6 * 9.80665, 3 * np.deg2rad(0.01)),
    "iphone_5s": PhoneProfile("iphone_5s", (10, 14), 20 * _MG, np.deg2rad(0.2), 0.010, 0.010,
                              3 * 300e-6 * 9.80665, 3 * np.deg2rad(0.01)),
    "midg2": PhoneProfile("midg2", _MIDG2_TICKS, _MIDG2_ACC_BIAS_MG * _MG, np.deg2rad(_MIDG2_GYR_BIAS_DPH / 3600),
                          _MIDG2_ACC_SF, _MIDG2_GYR_SF, 300e-6 * 9.80665, np.deg2rad(0.01)),
}

#: Indoor control points (ENU, m), at corners and corridor middles as in the paper: the corner at the
#: foot of the stairs, the 2nd-floor corridor middle, the corner at the classroom door, a classroom corner.
GCP_XYZ_M = np.array([[30.0, 0.0, 0.0], [30.0, 11.0, 4.0], [20.0, 15.0, 4.0], [13.0, 22.0, 4.0]])

_OUT = [(0, 0, 0), (15, 0, 0), (15, 10, 0), (0, 10, 0), (0, 0, 0)]
_LOOPS = _OUT + _OUT[1:]
_IN = [(20, 0, 0), (30, 0, 0), (30, 7, 4), (30, 15, 4), (20, 15, 4)]
_CLASS = [(20, 22, 4), (13, 22, 4), (13, 17, 4), (19, 17, 4), (20, 15, 4)]
#: Waypoints (x, y, z) of the two routes; the outdoor part ends at the first indoor waypoint.
ROUTES = {
    "samsung": _LOOPS + _IN + _CLASS + [(30, 15, 4), (30, 7, 4), (30, 0, 0), (20, 0, 0), (0, 0, 0)],
    "iphone": _LOOPS + _IN[:3] + [(30, 22, 4), (30, 15, 4), (20, 15, 4)] + _CLASS + [(24, 15, 4), (24, 13, 4)],
}
_N_OUTDOOR_WP = len(_LOOPS)
#: The paper's two phones: (label in the paper's tables, route, IMU profile).
PHONES = (("Samsung", "samsung", "samsung_s5"), ("iPhone", "iphone", "iphone_5s"))


@dataclass(frozen=True)
class InsWalk:
    """One simulated walk.

    Truth at 200 Hz: ``t_ref_s`` (M,), ``pos_ref_n_m`` (M, 3), ``mat_ref_nb`` (M, 3, 3).
    Phone IMU: ``t_s`` (N,), ``gyr_b_radps`` (N, 3), ``acc_b_mps2`` (N, 3); truth at the phone
    epochs ``pos_true_n_m``, ``vel_true_n_mps``, ``mat_true_nb``, ``stationary_true`` (N,).
    ``gnss_t_s`` / ``gnss_pos_n_m`` / ``gnss_sd_m`` (G,), (G, 3), (3,); control-point passages
    ``gcp_t_s`` (C,), ``gcp_pos_n_m`` (C, 3), ``gcp_id`` (C,), ``gcp_sd_m``; ``t_indoor_s`` the time the
    walker leaves the outdoor loops (errors are analysed after it); ``init``: initial state for the
    filter; ``sensor_true`` (12,) the drawn ``[b_acc, b_gyr, s_acc, s_gyr]``; ``params``.
    """

    t_ref_s: np.ndarray
    pos_ref_n_m: np.ndarray
    mat_ref_nb: np.ndarray
    t_s: np.ndarray
    gyr_b_radps: np.ndarray
    acc_b_mps2: np.ndarray
    pos_true_n_m: np.ndarray
    vel_true_n_mps: np.ndarray
    mat_true_nb: np.ndarray
    stationary_true: np.ndarray
    gnss_t_s: np.ndarray
    gnss_pos_n_m: np.ndarray
    gnss_sd_m: np.ndarray
    gcp_t_s: np.ndarray
    gcp_pos_n_m: np.ndarray
    gcp_id: np.ndarray
    gcp_sd_m: float
    t_indoor_s: float
    init: dict
    sensor_true: np.ndarray
    params: dict = field(default_factory=dict)


def _ou(rng, n, dt, sd, tau):
    """Stationary Ornstein-Uhlenbeck sequence (n,) with standard deviation sd and correlation time tau."""
    a = np.exp(-dt / tau)
    e = rng.normal(0.0, sd * np.sqrt(1 - a * a), n)
    e[0] = rng.normal(0.0, sd)
    from scipy.signal import lfilter

    return lfilter([1.0], [1.0, -a], e)


def _gauss_smooth(x, sigma_samples):
    from scipy.ndimage import gaussian_filter1d

    return gaussian_filter1d(x, sigma_samples, axis=0, mode="nearest")


def _path(rng, waypoints, dt, user_c, user_height_m, stair_speed_mps, step_freq_mean_hz):
    """Walk the waypoints: (t, pos (M,3) unsmoothed, walking flag (M,), step freq (M,), index of indoor start)."""
    wp = np.asarray(waypoints, dtype=float)
    pos_chunks, walk_chunks = [], []
    t_indoor_idx = None
    n_total = 0
    # initial standstill for levelling
    n0 = int(5.0 / dt)
    pos_chunks.append(np.repeat(wp[:1], n0, axis=0))
    walk_chunks.append(np.zeros(n0, bool))
    n_total += n0
    freq_proc = step_freq_mean_hz + _ou(rng, 200000, dt, 0.05, 10.0)
    for i in range(len(wp) - 1):
        if i == _N_OUTDOOR_WP - 1:
            t_indoor_idx = n_total
        a, b = wp[i], wp[i + 1]
        d = b - a
        horiz = float(np.hypot(d[0], d[1]))
        stairs = abs(d[2]) > 0.1
        f = freq_proc[n_total:n_total + int(120 / dt)]
        v = np.full(f.size, stair_speed_mps) if stairs else walking_speed_mps(f, user_height_m, c=user_c)
        s = np.cumsum(v) * dt
        m = int(np.searchsorted(s, horiz)) + 1
        frac = np.clip(s[:m] / horiz, 0.0, 1.0)
        pos_chunks.append(a + frac[:, None] * d)
        walk_chunks.append(np.ones(m, bool))
        n_total += m
        # stop 1-3 s after every turn (at every waypoint)
        ns = int(rng.uniform(1.0, 3.0) / dt)
        pos_chunks.append(np.repeat(b[None], ns, axis=0))
        walk_chunks.append(np.zeros(ns, bool))
        n_total += ns
    pos = np.concatenate(pos_chunks)
    walking = np.concatenate(walk_chunks)
    return pos, walking, freq_proc[:pos.shape[0]], t_indoor_idx


def simulate(route: str = "samsung", profile: str | PhoneProfile = "samsung_s5", seed=0, gcp_sd_m: float = 0.05,
             gnss_sd_m=(2.5, 2.5, 4.0), user_height_m: float = 1.70, user_c_sd: float = 0.05,
             init_yaw_sd_deg: float = 5.0) -> InsWalk:
    """Simulate one hand-held phone walk (see the module docstring for every parameter's source).

    Parameters
    ----------
    route : "samsung" or "iphone" (Figs 5 and 6)
    profile : a key of :data:`PROFILES` or a :class:`PhoneProfile`
    seed : int, Generator or None
    gcp_sd_m : control-point position-fix sd (m); gnss_sd_m : GNSS sd (E, N, U) in m
    user_height_m, user_c_sd : the walker's true height and the sd of their personal step scale
    init_yaw_sd_deg : sd of the initial heading error handed to the filter
    """
    if route not in ROUTES:
        raise ValueError(f"route must be one of {sorted(ROUTES)}, got {route!r}")
    prof = PROFILES[profile] if isinstance(profile, str) and profile in PROFILES else profile
    if not isinstance(prof, PhoneProfile):
        raise ValueError(f"profile must be one of {sorted(PROFILES)} or a PhoneProfile, got {profile!r}")
    if not gcp_sd_m > 0:
        raise ValueError(f"gcp_sd_m must be > 0, got {gcp_sd_m}")
    rng = as_rng(seed)
    dt = 1.0 / TRUTH_RATE_HZ
    user_c = 1.0 + rng.normal(0.0, user_c_sd)
    raw, walking, freq, i_indoor = _path(rng, ROUTES[route], dt, user_c, user_height_m, 0.5, 1.85)
    m = raw.shape[0]
    t = np.arange(m) * dt
    sig = int(0.25 / dt)
    pos_c = _gauss_smooth(raw, sig)
    walk_w = _gauss_smooth(walking.astype(float), int(0.3 / dt))
    # walking direction (held at stops), unwrapped and smoothed
    vel_c = np.gradient(pos_c, dt, axis=0)
    sp = np.hypot(vel_c[:, 0], vel_c[:, 1])
    yaw = np.arctan2(vel_c[:, 1], vel_c[:, 0])
    ok = sp > 0.05
    idx = np.where(ok, np.arange(m), 0)
    np.maximum.accumulate(idx, out=idx)
    first = np.argmax(ok)
    idx[:first] = first
    yaw = _gauss_smooth(np.unwrap(yaw[idx]), int(0.2 / dt))
    # gait phase and hand-held vibration / dynamic misalignment
    phase = 2 * np.pi * np.cumsum(freq * walk_w) * dt
    up = np.array([0.0, 0.0, 1.0])
    lat = np.column_stack([-np.sin(yaw), np.cos(yaw), np.zeros(m)])
    fwd = np.column_stack([np.cos(yaw), np.sin(yaw), np.zeros(m)])
    pos = (pos_c + (walk_w * 0.025 * (1 - np.cos(phase)))[:, None] * up
           + (walk_w * 0.015 * np.sin(phase / 2))[:, None] * lat
           + (walk_w * 0.01 * np.sin(phase))[:, None] * fwd)
    tremor = 1 - walk_w

    def smooth_ou(sd_deg, tau_s, smooth_s):
        # an OU sequence has no derivative; smoothing it keeps the angular rate physical
        return _gauss_smooth(_ou(rng, m, dt, sd_deg, tau_s), smooth_s / dt)

    roll = np.deg2rad(2.0 * walk_w * np.sin(phase / 2 + 0.3) + tremor * smooth_ou(0.3, 0.3, 0.1))
    pitch = np.deg2rad(2.0 * walk_w * np.sin(phase + 1.0) + tremor * smooth_ou(0.3, 0.3, 0.1))
    yaw_b = yaw + np.deg2rad(3.0 * walk_w * np.sin(phase / 2) + smooth_ou(3.0, 5.0, 0.5)
                             + tremor * smooth_ou(0.3, 0.3, 0.1))
    mat = euler_to_dcm(roll, pitch, yaw_b)
    # kinematics on the 200 Hz grid; truth position is the trapezoid integral of the velocity
    vel = np.gradient(pos, dt, axis=0)
    pos = pos[0] + np.concatenate([np.zeros((1, 3)), np.cumsum(0.5 * (vel[1:] + vel[:-1]) * dt, axis=0)])
    # increments over [t_k, t_k+1): consistent with mechanisation.strapdown
    dtheta = dcm_to_rotvec(np.matmul(np.swapaxes(mat[:-1], 1, 2), mat[1:]))
    dv_n = vel[1:] - vel[:-1] - GRAVITY_N_MPS2 * dt
    cmid = 0.5 * (mat[1:] + mat[:-1])
    dvel_b = np.linalg.solve(cmid, dv_n[..., None])[..., 0]
    # irregular phone epochs on the 200 Hz grid
    lo, hi = prof.ticks
    steps = rng.integers(lo, hi + 1, size=m // lo + 2)
    ep = np.concatenate([[0], np.cumsum(steps)])
    ep = ep[ep < m]
    cs_th = np.concatenate([np.zeros((1, 3)), np.cumsum(dtheta, axis=0)])
    cs_dv = np.concatenate([np.zeros((1, 3)), np.cumsum(dvel_b, axis=0)])
    nxt = np.append(ep[1:], ep[-1] + (ep[-1] - ep[-2]))
    nxt = np.minimum(nxt, m - 1)
    valid = nxt > ep
    ep, nxt = ep[valid], nxt[valid]
    dt_ph = (nxt - ep) * dt
    gyr_true = (cs_th[nxt] - cs_th[ep]) / dt_ph[:, None]
    acc_true = (cs_dv[nxt] - cs_dv[ep]) / dt_ph[:, None]
    n = ep.size
    ba = rng.normal(0.0, prof.acc_bias_sd_mps2, 3)
    bg = rng.normal(0.0, prof.gyr_bias_sd_radps, 3)
    sa = rng.normal(0.0, prof.acc_sf_sd, 3)
    sg = rng.normal(0.0, prof.gyr_sf_sd, 3)
    acc = (1 + sa) * acc_true + ba + rng.normal(0.0, 1.0, (n, 3)) * (prof.acc_noise_mps2_rsqrt_hz
                                                                     / np.sqrt(dt_ph))[:, None]
    gyr = (1 + sg) * gyr_true + bg + rng.normal(0.0, 1.0, (n, 3)) * (prof.gyr_noise_radps_rsqrt_hz
                                                                       / np.sqrt(dt_ph))[:, None]
    t_ph = t[ep]
    t_indoor = float(t[i_indoor])
    # GNSS at 1 Hz on the outdoor part (at phone epochs)
    gsd = np.asarray(gnss_sd_m, dtype=float)
    g_idx = np.unique(np.searchsorted(t_ph, np.arange(0.0, t_indoor, 1.0)))
    gnss_pos = pos[ep[g_idx]] + rng.normal(0.0, 1.0, (g_idx.size, 3)) * gsd
    # control-point passages: local minima of the distance below 0.5 m, on the indoor part
    gcp_t, gcp_p, gcp_i = [], [], []
    ph_pos = pos[ep]
    for j, g in enumerate(GCP_XYZ_M):
        dist = np.linalg.norm(ph_pos - g, axis=1)
        close = (dist < 0.6) & (t_ph >= t_indoor)
        runs = np.flatnonzero(np.diff(np.concatenate([[0], close.astype(int), [0]])))
        for a0, b0 in zip(runs[::2], runs[1::2], strict=True):
            k = a0 + int(np.argmin(dist[a0:b0]))
            gcp_t.append(t_ph[k])
            gcp_p.append(ph_pos[k] + rng.normal(0.0, gcp_sd_m, 3))
            gcp_i.append(j)
    order = np.argsort(gcp_t)
    init_att = np.array([roll[0], pitch[0], yaw_b[0] + np.deg2rad(rng.normal(0.0, init_yaw_sd_deg))])
    stationary = ~walking[ep] & (walk_w[ep] < 0.05)
    return InsWalk(
        t_ref_s=t, pos_ref_n_m=pos, mat_ref_nb=mat, t_s=t_ph, gyr_b_radps=gyr, acc_b_mps2=acc,
        pos_true_n_m=pos[ep], vel_true_n_mps=vel[ep], mat_true_nb=mat[ep], stationary_true=stationary,
        gnss_t_s=t_ph[g_idx], gnss_pos_n_m=gnss_pos, gnss_sd_m=gsd,
        gcp_t_s=np.asarray(gcp_t)[order], gcp_pos_n_m=np.asarray(gcp_p).reshape(-1, 3)[order],
        gcp_id=np.asarray(gcp_i, dtype=np.int64)[order], gcp_sd_m=float(gcp_sd_m), t_indoor_s=t_indoor,
        init={"pos_n_m": gnss_pos[0].copy(), "vel_n_mps": np.zeros(3), "euler_rad": init_att},
        sensor_true=np.concatenate([ba, bg, sa, sg]),
        params={"route": route, "profile": prof.name, "user_c": float(user_c), "user_height_m": user_height_m},
    )
