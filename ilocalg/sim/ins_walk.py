"""Simulated smartphone walks for the INS experiments (Liao et al. 2016, sec. 4).

A pedestrian holds a phone in front of them and walks: two loops outdoors with GNSS (filter
initialisation), into a building, up a staircase to the 2nd floor, around a classroom and back
(route ``"samsung"``, Fig 5); or up the stairs to the corridor end, back to the classroom, around
it and on to a lab (route ``"iphone"``, Fig 6). The walker stops 1-3 s after every turn. Four
indoor control points (corners and corridor middles) are met along the way.

Everything is deterministic from ``seed``. The truth is generated at 200 Hz (the paper's reference
rate); the phone IMU samples it at irregular 14.3-20 Hz intervals with phone-grade biases, scale factors,
white noise, bias instability and poor time tags (the ideal sensor: ``PROFILES[k].ideal_timing()``).

Parameters and their sources
----------------------------
Paper (Liao et al. 2016; L = line of the paper's text file):
  - reference solution rate 200 Hz (L324); phone IMU "15-17 Hz" (L171), "low and unstable (about 20 Hz)",
    time tags of poor precision (L324) -> phone intervals of 10-14 ticks of the 200 Hz grid (uniform), mean
    16.7 Hz; time-tag error sd 10 ms (assumption with no published measurement, clipped at 2 sd, tags kept
    monotonic; swept by ``PhoneProfile.swept``) and instantaneous (point) samples;
  - stops of 1-3 s after turns (ZUPT, L146), uniform in [1, 3] s;
  - GNSS only during the two outdoor loops (L202); four indoor control points met "about every 15 s" (L202);
    control points are total-station surveyed (cm level) and delivered by Bluetooth (m level) (L109, L202;
    Bluetooth proximity: "the user is taken to be at the beacon when it is sensed", L73): the fix is the
    surveyed coordinate, given after the beacon ranging cycle (U(0, 1 s): iOS Core Location ranges once per
    second) with a horizontal proximity offset sd 0.5 m (the iBeacon "immediate" zone) and handed to the
    filter with sd 1.0 m; ``gcp_mode="ideal"`` keeps the true position + 5 cm at closest approach;
  - MIDG-II (Table 3): 50 Hz, gyro bias 4.7 deg/h, accelerometer bias 6 mg, scale factors 5000 ppm
    (gyro) and 19700 ppm (accelerometer): the ``"midg2"`` reference-grade profile.
Phone profiles (datasheet class; the paper defers to Liao et al. 2014 and states only that the two
phones' IMUs are similar, L202): InvenSense MPU-6500 class parts:
  - ``samsung_s5``: accelerometer bias sd 30 mg (datasheet zero-g offset +-60 mg, read as 2 sd),
    gyro residual bias sd 0.3 deg/s (after the phone's own at-rest calibration), scale factors sd
    1.5 % (datasheet sensitivity tolerance +-3 %), noise densities 300 ug/sqrt(Hz) and
    0.01 deg/s/sqrt(Hz) x 3 (phone output filtering and electrical noise); barometer (BMP280 class,
    height noise sd 0.1 m);
  - ``iphone_5s``: 20 mg, 0.2 deg/s, 1.0 %, same noise densities; no barometer;
  - both: first-order Gauss-Markov bias instability, accelerometer 0.5 mg and gyro 20 deg/h with a 300 s
    correlation time (assumption of the order of consumer-MEMS Allan-variance bias instabilities; no
    specific measurement was checked for these two numbers; swept by ``PhoneProfile.swept``).
Values quoted from the studies and documents cited below (gait, stairs, MPU-6500, BMP280, iOS ranging, iBeacon
zones) are recalled, not re-read (data/ins_walk/README.md lists them with the sweep that covers each).
Walker (published gait measurements, independent of the filter's eq. 7):
  - level: comfortable speed N(1.40, 0.16) m/s (Bohannon 1997), personal walk ratio (step length /
    cadence) 0.0064 m min/step per 1.70 m of height, 10 % between walkers (Sekiya & Nagasaki 1998; Hof
    1996 body-size scaling); cadence and step length follow from the speed and the walk ratio; the cadence
    wanders slowly (Ornstein-Uhlenbeck, sd 0.05 Hz, 10 s) with the walk ratio fixed;
  - stairs: riser 0.17 m, tread 0.29 m (Blondel's 2R + T = 0.63 m), one tread per step, cadence per walker
    N(1.62, 0.12) Hz up and N(1.80, 0.12) Hz down (gait-laboratory stair cadences, Riener et al. 2002,
    Protopapadaki et al. 2007), i.e. about 0.47 m/s horizontal upstairs (derived: cadence x tread; no
    published horizontal stair speed is used - Kretz et al. 2008, cited here earlier as a cross-check, does
    not give this quantity for a building stair and is dropped - the speed is swept through the stair
    cadence +- 1 sd by the experiment's gait_sensitivity);
  - ``gait="legacy"``: the earlier walker (eq. 7 with a personal scale c ~ N(1, 0.05), stairs at 0.5 m/s
    with the level cadence);
  - hand-held vibration and dynamic misalignment: vertical bounce 2.5 cm at the step frequency,
    lateral sway 1.5 cm at half of it; attitude oscillation roll 2 deg, pitch 2 deg, yaw 3 deg; a slowly
    wandering yaw misalignment (sd 3 deg, 5 s correlation); hand tremor at rest (0.3 deg, 0.3 s); the
    random attitude terms are Ornstein-Uhlenbeck sequences smoothed over 0.5 s / 0.1 s (Gaussian sigma)
    so that their angular rates stay physical (assumptions).
GNSS outdoors (phone grade, assumption): 1 Hz, sd 2.5 m horizontal, 4 m vertical.
Initial heading (assumption): truth + N(0, 5 deg), as from a map-aligned start.

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 4, Figs 5-6, Table 3; Chen et al. (2011) step model;
Bohannon (1997), Age and Ageing 26:15-19; Sekiya & Nagasaki (1998), Gait & Posture 7:225-227;
Hof (1996), Gait & Posture 4:222-223; Riener, Rabuffetti, Frigo (2002), Gait & Posture 15:32-44;
Protopapadaki et al. (2007), Clinical Biomechanics 22:203-210; Gelb (1974) Applied Optimal Estimation (Gauss-Markov).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ilocalg.ins.constraints import walking_speed_mps
from ilocalg.ins.mechanisation import GRAVITY_N_MPS2, dcm_to_rotvec, euler_to_dcm
from ilocalg.units import as_rng

__all__ = ["PhoneProfile", "PROFILES", "PHONE_NOISE_FACTOR", "PHONE_TIME_JITTER_SD_S", "phone_profile", "ROUTES",
           "PHONES", "GCP_XYZ_M", "InsWalk", "TruthCache", "simulate", "walk_summary", "walker_gait", "gauss_markov"]

# ---- published values: Liao et al. (2016), sec. 4 (reference rate) and Table 3 (MIDG-II) -------------------
#: Rate of the paper's reference solution, Hz.
TRUTH_RATE_HZ = 200.0
#: MIDG-II reference IMU (Table 3): sampling interval in 200 Hz ticks (50 Hz), accelerometer bias (mg), gyro
#: bias (deg/h), accelerometer and gyro scale factors (5000 ppm gyro, 19700 ppm accelerometer).
_MIDG2_TICKS, _MIDG2_ACC_BIAS_MG, _MIDG2_GYR_BIAS_DPH, _MIDG2_ACC_SF, _MIDG2_GYR_SF = (4, 4), 6, 4.7, 0.0197, 0.005
# ---- end of published values -------------------------------------------------------------------------------

# ---- published values: walker gait (independent of the filter's eq. 7) -------------------------------------
#: Comfortable level walking speed (m/s) of adults in their twenties to forties, mean and between-walker sd:
#: Bohannon (1997), Table 2 (men 20-29: 139.3 +- 15.3 cm/s; women 20-29: 140.7 +- 17.0 cm/s), pooled.
LEVEL_SPEED_MEAN_MPS, LEVEL_SPEED_SD_MPS = 1.40, 0.16
#: Walk ratio (step length / cadence, m per step/min) per metre of height, mean and between-walker sd:
#: Sekiya & Nagasaki (1998) walk ratio of young adults, about 0.0064 m min/step at about 1.70 m height, with a
#: between-walker coefficient of variation of about 10 %; step length scales with body size (Hof 1996).
WALK_RATIO_PER_HEIGHT, WALK_RATIO_PER_HEIGHT_SD = 0.0064 / 1.70, 0.1 * 0.0064 / 1.70
#: Stair riser (m): 2 R + T = 0.63 m with tread T = 0.29 m (Blondel's rule, kept by building codes); the route's
#: 4 m rise over 7 m then has 24 steps of 0.17 m x 0.29 m.
STAIR_RISER_M = 0.17
#: Self-paced stair cadence (Hz), ascent and descent, between-walker sd: about 95-110 steps/min in gait
#: laboratories (Riener et al. 2002; Protopapadaki et al. 2007). With one tread (0.29 m) per step the ascent's
#: horizontal speed is about 0.47 m/s (derived, swept through the cadence +- 1 sd; no published horizontal
#: stair speed is used).
STAIR_UP_CADENCE_HZ, STAIR_DOWN_CADENCE_HZ, STAIR_CADENCE_SD_HZ = 1.62, 1.80, 0.12
# ---- end of published values -------------------------------------------------------------------------------

# ---- published values: Bluetooth control points -----------------------------------------------------------
#: Beacon ranging cycle (s): iOS Core Location delivers beacon ranging results once per second, Android beacon
#: libraries scan in cycles of about 1.1 s (AltBeacon default); the trigger comes U(0, cycle) after the phone
#: reaches the beacon. The beacon's surveyed coordinate is the fix (Liao et al. 2016, L109, L202).
BLE_RANGING_CYCLE_S = 1.0
#: Proximity offset (m, horizontal sd per axis): the phone is "at" a beacon when its RSSI says "immediate"
#: (within about 0.5 m; Apple iBeacon proximity classes), not at the surveyed point itself.
BLE_PROXIMITY_SD_M = 0.5
#: Filter noise of a Bluetooth control-point fix (m): "metre level" (Liao et al. 2016, L109).
BLE_FIX_SD_M = 1.0
#: RSSI detection (``gcp_mode="rssi"``, the default), as a phone sees a beacon:
#: advertising interval (s): 100 ms, the iBeacon recommendation (Apple Proximity Beacon Specification;
#: recalled, not re-read), plus the Bluetooth Core specification's pseudo-random advDelay of 0-10 ms per event;
BLE_ADV_INTERVAL_S, BLE_ADV_DELAY_MAX_S = 0.1, 0.01
#: RSSI at 1 m (dBm): the calibrated "measured power" a beacon broadcasts, -59 dBm at 0 dBm TX (Blue Charm
#: Beacons' calibration chart; it cancels in the threshold below); path-loss exponent 2 (free space, the model
#: behind iOS's distance estimate);
BLE_RSSI_1M_DBM, BLE_PATH_LOSS_EXP = -59.0, 2.0
#: per-packet RSSI scatter (dB): 4-6 dB measured on beacons at a fixed distance (BlueCats / beacon vendors'
#: stability tests, a blog-level source: swept 2-8 dB in the experiment's gcp_grade table);
BLE_RSSI_SD_DB = 5.0
#: proximity declared when the ranging cycle's mean RSSI reaches the model's RSSI at the iBeacon "immediate"
#: distance (0.5 m; recalled); the fix is handed over at the end of that ranging cycle (BLE_RANGING_CYCLE_S).
BLE_IMMEDIATE_M = 0.5
# ---- end of published values -------------------------------------------------------------------------------


@dataclass(frozen=True)
class PhoneProfile:
    """IMU error profile. Biases/scale factors are drawn once per run (sd given); noise is white.

    ``ticks`` is the allowed range of sample intervals in 200 Hz ticks (inclusive). The remaining fields
    default to the ideal sensor: ``time_jitter_sd_s`` sd of the error of each time tag (s, clipped at 2 sd);
    ``point_sampling`` samples are instantaneous values (True) or interval means (False, what the filter's
    strapdown assumes); ``acc_gm_sd_mps2`` / ``gyr_gm_sd_radps`` and ``gm_tau_s``: first-order Gauss-Markov
    bias instability (sd and correlation time) on top of the turn-on bias; ``baro_sd_m`` barometric height
    noise sd (m), None for a phone without a barometer.
    """

    name: str
    ticks: tuple[int, int]
    acc_bias_sd_mps2: float
    gyr_bias_sd_radps: float
    acc_sf_sd: float
    gyr_sf_sd: float
    acc_noise_mps2_rsqrt_hz: float
    gyr_noise_radps_rsqrt_hz: float
    time_jitter_sd_s: float = 0.0
    point_sampling: bool = False
    acc_gm_sd_mps2: float = 0.0
    gyr_gm_sd_radps: float = 0.0
    gm_tau_s: float = 300.0
    baro_sd_m: float | None = None

    def ideal_timing(self) -> PhoneProfile:
        """The same sensor errors with exact time tags, interval-mean samples and no bias instability."""
        return replace(self, time_jitter_sd_s=0.0, point_sampling=False, acc_gm_sd_mps2=0.0, gyr_gm_sd_radps=0.0)

    def swept(self, bias_instability_factor: float = 1.0, time_jitter_sd_s: float | None = None,
              noise_scale: float = 1.0) -> PhoneProfile:
        """The same sensor with its Gauss-Markov bias instability scaled and its time-tag error sd replaced.

        Parameters
        ----------
        bias_instability_factor : float
            Factor (>= 0) on both Gauss-Markov sds (0: only the constant turn-on bias remains); correlation
            time unchanged.
        time_jitter_sd_s : float, optional
            Time-tag error sd (s, >= 0; 0: the nominal clock); None keeps the profile's.
        noise_scale : float
            Factor (> 0) on both white-noise densities (the phone profiles carry 3 x the MPU-6500 datasheet
            densities: ``noise_scale = 1/3`` gives the datasheet's, 5/3 five times it).

        Used by sensitivity sweeps over values no published measurement fixes for these phones; with a
        point-sampled profile the swept walks share the walk and every other error draw (same seed).
        """
        k = float(bias_instability_factor)
        if not (np.isfinite(k) and k >= 0):
            raise ValueError(f"bias_instability_factor must be a finite factor >= 0, got {bias_instability_factor}")
        j = self.time_jitter_sd_s if time_jitter_sd_s is None else float(time_jitter_sd_s)
        if not (np.isfinite(j) and j >= 0):
            raise ValueError(f"time_jitter_sd_s must be >= 0 s, got {time_jitter_sd_s}")
        c = float(noise_scale)
        if not (np.isfinite(c) and c > 0):
            raise ValueError(f"noise_scale must be a finite factor > 0, got {noise_scale}")
        return replace(self, acc_gm_sd_mps2=k * self.acc_gm_sd_mps2, gyr_gm_sd_radps=k * self.gyr_gm_sd_radps,
                       time_jitter_sd_s=j, acc_noise_mps2_rsqrt_hz=c * self.acc_noise_mps2_rsqrt_hz,
                       gyr_noise_radps_rsqrt_hz=c * self.gyr_noise_radps_rsqrt_hz)


_MG = 9.80665e-3
#: Phone timing and bias instability (assumptions, see the module docstring): time-tag error sd (s); Gauss-Markov
#: bias sd of the accelerometer (0.5 mg) and gyroscope (20 deg/h) with a 300 s correlation time.
PHONE_TIME_JITTER_SD_S = 0.01
_PHONE_TIMING = {"time_jitter_sd_s": PHONE_TIME_JITTER_SD_S, "point_sampling": True, "acc_gm_sd_mps2": 0.5 * 9.80665e-3,
                 "gyr_gm_sd_radps": float(np.deg2rad(20.0 / 3600.0)), "gm_tau_s": 300.0}
#: Smallest step between two phone time tags (s): tags never go backwards (a monotonic sensor clock); only a
#: time-tag error sd above a quarter of the shortest sampling interval (12.5 ms here) ever meets this floor.
MIN_TAG_GAP_S = 1e-3
#: Barometric height noise (m): Bosch BMP280-class pressure sensor, RMS noise about 1.2 Pa (standard
#: resolution), about 0.1 m. The Galaxy S5 has a barometer, the iPhone 5S has none.
_BARO_SD_M = 0.1
#: Factor on the MPU-6500 datasheet white-noise densities (300 ug/sqrt(Hz), 0.01 deg/s/sqrt(Hz)) that the phone
#: profiles carry: an assumption (phone output filtering and electrical noise), swept 1 (datasheet) to 5.
PHONE_NOISE_FACTOR = 3.0
PROFILES = {
    "samsung_s5": PhoneProfile("samsung_s5", (10, 14), 30 * _MG, np.deg2rad(0.3), 0.015, 0.015,
                               PHONE_NOISE_FACTOR * 300e-6 * 9.80665, PHONE_NOISE_FACTOR * np.deg2rad(0.01),
                               **_PHONE_TIMING, baro_sd_m=_BARO_SD_M),
    "iphone_5s": PhoneProfile("iphone_5s", (10, 14), 20 * _MG, np.deg2rad(0.2), 0.010, 0.010,
                              PHONE_NOISE_FACTOR * 300e-6 * 9.80665, PHONE_NOISE_FACTOR * np.deg2rad(0.01),
                              **_PHONE_TIMING),
    "midg2": PhoneProfile("midg2", _MIDG2_TICKS, _MIDG2_ACC_BIAS_MG * _MG, np.deg2rad(_MIDG2_GYR_BIAS_DPH / 3600),
                          _MIDG2_ACC_SF, _MIDG2_GYR_SF, 300e-6 * 9.80665, np.deg2rad(0.01)),
}


def phone_profile(name: str, noise_factor: float = PHONE_NOISE_FACTOR, bias_instability_factor: float = 1.0,
                  time_jitter_sd_s: float | None = None) -> PhoneProfile:
    """``PROFILES[name]`` with the values no published measurement fixes changed (:meth:`PhoneProfile.swept`):
    the white-noise factor on the datasheet densities, the bias-instability factor and the time-tag error sd
    (None keeps the profile's). At the defaults it equals ``PROFILES[name]``."""
    if name not in PROFILES:
        raise ValueError(f"profile must be one of {sorted(PROFILES)}, got {name!r}")
    return PROFILES[name].swept(bias_instability_factor, time_jitter_sd_s,
                                noise_scale=noise_factor / PHONE_NOISE_FACTOR)


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
    filter; ``sensor_true`` (12,) the drawn ``[b_acc, b_gyr, s_acc, s_gyr]`` (turn-on values); ``stairs_true``
    (N,) the walker is on a staircase; ``baro_t_s`` / ``baro_height_m`` (B,) barometric heights (empty without
    a barometer); ``t_true_s`` (N,) the true sampling instants (``t_s`` are the phone's time tags); ``params``.
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
    stairs_true: np.ndarray
    baro_t_s: np.ndarray
    baro_height_m: np.ndarray
    t_true_s: np.ndarray
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


def walker_gait(rng, user_height_m: float = 1.70, speed_mean_mps: float = LEVEL_SPEED_MEAN_MPS,
                speed_sd_mps: float = LEVEL_SPEED_SD_MPS, walk_ratio_per_height: float = WALK_RATIO_PER_HEIGHT,
                stair_up_cadence_hz: float = STAIR_UP_CADENCE_HZ,
                stair_down_cadence_hz: float = STAIR_DOWN_CADENCE_HZ) -> dict:
    """Draw one walker's gait, independently of the WVC model (eq. 7) used by the filter.

    Level walking: comfortable speed ``v ~ N(speed_mean_mps, speed_sd_mps)`` (Bohannon 1997) and a personal
    walk ratio (step length over cadence) ``W = w_h h`` with ``w_h ~ N(WALK_RATIO_PER_HEIGHT, sd)``
    (Sekiya & Nagasaki 1998, scaled with body size after Hof 1996). Cadence and step length follow from
    ``v = L F`` and ``L = 60 W F``: ``F = sqrt(v / (60 W))`` (Hz), ``L = 60 W F`` (m). Stairs: one tread per
    step, cadence ``N(stair_*_cadence_hz, STAIR_CADENCE_SD_HZ)`` per walker (see the module docstring). The
    population means default to the published values; a sensitivity sweep may move them (same draws).

    Returns
    -------
    dict with ``speed_mps``, ``walk_ratio_m_min``, ``cadence_hz``, ``step_length_m``, ``stair_up_cadence_hz``,
    ``stair_down_cadence_hz``.

    References
    ----------
    Bohannon (1997), Age and Ageing 26:15-19; Sekiya & Nagasaki (1998), Gait & Posture 7:225-227;
    Hof (1996), Gait & Posture 4:222-223.
    """
    v = max(0.6, rng.normal(speed_mean_mps, speed_sd_mps))
    w = max(0.002, rng.normal(walk_ratio_per_height, WALK_RATIO_PER_HEIGHT_SD)) * user_height_m
    f = float(np.sqrt(v / (60.0 * w)))
    up = max(1.0, rng.normal(stair_up_cadence_hz, STAIR_CADENCE_SD_HZ))
    down = max(1.0, rng.normal(stair_down_cadence_hz, STAIR_CADENCE_SD_HZ))
    return {"speed_mps": float(v), "walk_ratio_m_min": float(w), "cadence_hz": f, "step_length_m": 60.0 * w * f,
            "stair_up_cadence_hz": float(up), "stair_down_cadence_hz": float(down)}


def _path(rng, waypoints, dt, gait, legacy):
    """Walk the waypoints.

    Returns ``(pos (M,3) unsmoothed, walking flag (M,), step freq (M,), on-stairs flag (M,), index of indoor start)``.
    ``legacy`` = (user_c, user_height_m): the earlier walker (speed from eq. 7, stairs at 0.5 m/s, level cadence).
    """
    wp = np.asarray(waypoints, dtype=float)
    pos_chunks, walk_chunks, stair_chunks = [], [], []
    t_indoor_idx = None
    n_total = 0
    # initial standstill for levelling
    n0 = int(5.0 / dt)
    pos_chunks.append(np.repeat(wp[:1], n0, axis=0))
    walk_chunks.append(np.zeros(n0, bool))
    stair_chunks.append(np.zeros(n0, bool))
    n_total += n0
    f0 = 1.85 if legacy else gait["cadence_hz"]
    fluct = _ou(rng, 200000, dt, 0.05, 10.0)
    freq_proc = f0 + fluct
    freq_out = freq_proc.copy()
    for i in range(len(wp) - 1):
        if i == _N_OUTDOOR_WP - 1:
            t_indoor_idx = n_total
        a, b = wp[i], wp[i + 1]
        d = b - a
        horiz = float(np.hypot(d[0], d[1]))
        stairs = abs(d[2]) > 0.1
        f = freq_proc[n_total:n_total + int(120 / dt)]
        if legacy:
            user_c, user_height_m = legacy
            v = np.full(f.size, 0.5) if stairs else walking_speed_mps(f, user_height_m, c=user_c)
        elif stairs:
            n_steps = max(1, int(round(abs(d[2]) / STAIR_RISER_M)))
            tread = horiz / n_steps
            fs = gait["stair_up_cadence_hz"] if d[2] > 0 else gait["stair_down_cadence_hz"]
            f = fs + fluct[n_total:n_total + f.size]
            freq_out[n_total:n_total + f.size] = f
            v = tread * f  # one tread per step
        else:
            v = 60.0 * gait["walk_ratio_m_min"] * f * f  # v = L F with L = 60 W F (constant walk ratio)
        s = np.cumsum(v) * dt
        m = int(np.searchsorted(s, horiz)) + 1
        frac = np.clip(s[:m] / horiz, 0.0, 1.0)
        pos_chunks.append(a + frac[:, None] * d)
        walk_chunks.append(np.ones(m, bool))
        stair_chunks.append(np.full(m, stairs))
        n_total += m
        # stop 1-3 s after every turn (at every waypoint)
        ns = int(rng.uniform(1.0, 3.0) / dt)
        pos_chunks.append(np.repeat(b[None], ns, axis=0))
        walk_chunks.append(np.zeros(ns, bool))
        stair_chunks.append(np.zeros(ns, bool))
        n_total += ns
    pos = np.concatenate(pos_chunks)
    walking = np.concatenate(walk_chunks)
    return pos, walking, freq_out[:pos.shape[0]], np.concatenate(stair_chunks), t_indoor_idx


def _truth(rng, dt, route, gait, gait_kw, user_height_m, user_c_sd) -> dict:
    """The walker and the 200 Hz truth of :func:`simulate` (the draws before the phone's): path, attitude,
    kinematics and the increments the sensors sample."""
    if gait == "legacy":
        user_c = 1.0 + rng.normal(0.0, user_c_sd)
        gait_d = {}
        raw, walking, freq, on_stairs, i_indoor = _path(rng, ROUTES[route], dt, None, (user_c, user_height_m))
    else:
        user_c = float("nan")
        gait_d = walker_gait(rng, user_height_m, **gait_kw)
        raw, walking, freq, on_stairs, i_indoor = _path(rng, ROUTES[route], dt, gait_d, None)
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
    return {"user_c": user_c, "gait_d": gait_d, "walking": walking, "on_stairs": on_stairs, "i_indoor": i_indoor,
            "t": t, "walk_w": walk_w, "roll": roll, "pitch": pitch, "yaw_b": yaw_b, "mat": mat, "vel": vel, "pos": pos,
            "dtheta": dtheta, "dvel_b": dvel_b}


class TruthCache:
    """The truths of :func:`simulate` kept between its calls, the ``maxsize`` used last (least recently used
    dropped): a caller that simulates the same walker again with another phone, another control-point model or
    other sensor errors (same route, seed, gait and walker) passes one, e.g. for the span of one experiment run.

    An entry is keyed by everything the truth depends on (route, int seed, gait, ``gait_kw``, the walker's height
    and step-scale sd) and holds the truth's arrays (read-only) and the random generator's state after its draws,
    so that a walk built from it has the same bits as one simulated from scratch.
    """

    def __init__(self, maxsize: int = 4):
        if maxsize < 1:
            raise ValueError(f"maxsize must be >= 1, got {maxsize}")
        self.maxsize = int(maxsize)
        self._d: dict = {}

    def __len__(self) -> int:
        return len(self._d)

    def get(self, key):
        v = self._d.pop(key, None)
        if v is not None:
            self._d[key] = v  # most recently used last
        return v

    def put(self, key, value) -> None:
        self._d.pop(key, None)
        self._d[key] = value
        while len(self._d) > self.maxsize:
            del self._d[next(iter(self._d))]


def simulate(route: str = "samsung", profile: str | PhoneProfile = "samsung_s5", seed=0, gcp_sd_m: float | None = None,
             gnss_sd_m=(2.5, 2.5, 4.0), user_height_m: float = 1.70, user_c_sd: float = 0.05,
             init_yaw_sd_deg: float = 5.0, gait: str = "published", gcp_mode: str = "rssi",
             ble_lag_s: float = 0.0, gait_kw: dict | None = None, rssi_sd_db: float = BLE_RSSI_SD_DB,
             truth_cache: TruthCache | None = None) -> InsWalk:
    """Simulate one hand-held phone walk (see the module docstring for every parameter's source).

    Parameters
    ----------
    route : "samsung" or "iphone" (Figs 5 and 6)
    profile : a key of :data:`PROFILES` or a :class:`PhoneProfile` (``PROFILES[k].ideal_timing()`` for exact
        time tags, interval means and no bias instability)
    seed : int, Generator or None
    gcp_sd_m : control-point fix sd handed to the filter (m); default 1.0 m for Bluetooth fixes
        (:data:`BLE_FIX_SD_M`), 0.05 m for the ideal fix; gnss_sd_m : GNSS sd (E, N, U) in m
    user_height_m : the walker's true height (m)
    user_c_sd : sd of the personal step scale of the ``"legacy"`` walker
    init_yaw_sd_deg : sd of the initial heading error handed to the filter
    gait : "published" (level speed and cadence from :func:`walker_gait`, stairs one tread per step) or
        "legacy" (speed from eq. 7 with a personal scale, stairs at 0.5 m/s with the level cadence)
    gcp_mode : "rssi" (default: the surveyed coordinate when the beacon's packets, advertised every 100 ms
        and received with a log-distance RSSI and 5 dB scatter, average over a 1 s ranging cycle to the RSSI of
        the "immediate" distance; :data:`BLE_ADV_INTERVAL_S` ff.), "ble" (the earlier model: 0.6 m truth gate,
        a U(0, 1 s) ranging delay and a 0.5 m proximity offset) or "ideal" (the true phone position plus
        ``gcp_sd_m`` noise at closest approach)
    rssi_sd_db : per-packet RSSI scatter of the "rssi" model (dB)
    ble_lag_s : extra trigger delay of the Bluetooth fix (s), e.g. RSSI averaging (default none)
    gait_kw : population means handed to :func:`walker_gait` for ``gait="published"`` (``speed_mean_mps``,
        ``walk_ratio_per_height``, ``stair_up_cadence_hz``, ``stair_down_cadence_hz``); default the published
        values. The walker's draws are the same for any means (paired sensitivity sweeps).
    truth_cache : a :class:`TruthCache` to take the truth from when it holds this walker's (int ``seed`` only),
        and to keep it in otherwise; the walk is the same either way
    """
    if route not in ROUTES:
        raise ValueError(f"route must be one of {sorted(ROUTES)}, got {route!r}")
    prof = PROFILES[profile] if isinstance(profile, str) and profile in PROFILES else profile
    if not isinstance(prof, PhoneProfile):
        raise ValueError(f"profile must be one of {sorted(PROFILES)} or a PhoneProfile, got {profile!r}")
    if gait not in ("published", "legacy"):
        raise ValueError(f"gait must be 'published' or 'legacy', got {gait!r}")
    if gcp_mode not in ("rssi", "ble", "ideal"):
        raise ValueError(f"gcp_mode must be 'rssi', 'ble' or 'ideal', got {gcp_mode!r}")
    if not (np.isfinite(rssi_sd_db) and rssi_sd_db >= 0):
        raise ValueError(f"rssi_sd_db must be >= 0 dB, got {rssi_sd_db}")
    if gcp_sd_m is None:
        gcp_sd_m = 0.05 if gcp_mode == "ideal" else BLE_FIX_SD_M
    if not gcp_sd_m > 0:
        raise ValueError(f"gcp_sd_m must be > 0, got {gcp_sd_m}")
    if not (np.isfinite(ble_lag_s) and ble_lag_s >= 0):
        raise ValueError(f"ble_lag_s must be >= 0 s, got {ble_lag_s}")
    gait_kw = dict(gait_kw or {})
    allowed = {"speed_mean_mps", "walk_ratio_per_height", "stair_up_cadence_hz", "stair_down_cadence_hz"}
    if set(gait_kw) - allowed or not all(np.isfinite(v) and v > 0 for v in gait_kw.values()):
        raise ValueError(f"gait_kw must map some of {sorted(allowed)} to positive values, got {gait_kw!r}")
    if gait_kw and gait != "published":
        raise ValueError("gait_kw applies to gait='published' only")
    rng = as_rng(seed)
    dt = 1.0 / TRUTH_RATE_HZ
    key = None
    if truth_cache is not None and isinstance(seed, (int, np.integer)):
        key = (route, int(seed), gait, tuple(sorted(gait_kw.items())), float(user_height_m), float(user_c_sd))
    hit = truth_cache.get(key) if key is not None else None
    if hit is None:
        tr = _truth(rng, dt, route, gait, gait_kw, user_height_m, user_c_sd)
        if key is not None:
            for v in tr.values():
                if isinstance(v, np.ndarray):
                    v.setflags(write=False)
            truth_cache.put(key, (tr, rng.bit_generator.state))
    else:
        tr, state = hit
        rng.bit_generator.state = state  # as if the truth had just been drawn
    user_c, gait_d, walking, on_stairs, i_indoor = (tr[k] for k in ("user_c", "gait_d", "walking", "on_stairs",
                                                                    "i_indoor"))
    t, walk_w, roll, pitch, yaw_b, mat, vel, pos, dtheta, dvel_b = (
        tr[k] for k in ("t", "walk_w", "roll", "pitch", "yaw_b", "mat", "vel", "pos", "dtheta", "dvel_b"))
    m = t.size
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
    if prof.point_sampling:
        # instantaneous values (one 200 Hz increment), not means over the phone interval
        gyr_true = dtheta[ep] / dt
        acc_true = dvel_b[ep] / dt
    else:
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
    t_true = t[ep]
    t_ph = t_true.copy()
    # realistic phone: Gauss-Markov bias instability and poor time tags (drawn after the ideal sensor's
    # numbers, so an ideal-timing profile keeps the same random stream). A point-sampled (realistic) sensor
    # draws them even at zero size, so that a sweep over their sizes keeps the same walk and the same other
    # errors (paired comparisons).
    if prof.point_sampling or prof.acc_gm_sd_mps2 > 0 or prof.gyr_gm_sd_radps > 0:
        for arr, sd in ((acc, prof.acc_gm_sd_mps2), (gyr, prof.gyr_gm_sd_radps)):
            if sd > 0 or prof.point_sampling:
                arr += gauss_markov(rng, t_true, sd, prof.gm_tau_s, 3)
    if prof.point_sampling or prof.time_jitter_sd_s > 0:
        j = np.clip(rng.normal(0.0, prof.time_jitter_sd_s, n), -2 * prof.time_jitter_sd_s,
                    2 * prof.time_jitter_sd_s)
        t_ph = _monotonic_tags(t_true + j, MIN_TAG_GAP_S)
    t_indoor = float(t[i_indoor])
    # GNSS at 1 Hz on the outdoor part (at phone epochs)
    gsd = np.asarray(gnss_sd_m, dtype=float)
    g_idx = np.unique(np.searchsorted(t_ph, np.arange(0.0, t_indoor, 1.0)))
    gnss_pos = pos[ep[g_idx]] + rng.normal(0.0, 1.0, (g_idx.size, 3)) * gsd
    # control-point passages: local minima of the distance below 0.6 m, on the indoor part
    gcp_t, gcp_p, gcp_i = [], [], []
    ph_pos = pos[ep]
    # the RSSI model draws from its own stream (jumped), so the other draws do not depend on the GCP model
    rssi_rng = np.random.Generator(rng.bit_generator.jumped())
    for jj, g in enumerate(GCP_XYZ_M) if gcp_mode == "rssi" else ():
        for tt in _rssi_triggers(t, pos, g, t_indoor, rssi_sd_db, rssi_rng):
            k2 = min(int(np.searchsorted(t_true, tt + ble_lag_s)), n - 1)
            gcp_t.append(t_ph[k2])
            gcp_p.append(g.copy())
            gcp_i.append(jj)
    for jj, g in enumerate(GCP_XYZ_M) if gcp_mode != "rssi" else ():
        dist = np.linalg.norm(ph_pos - g, axis=1)
        close = (dist < 0.6) & (t_true >= t_indoor)
        runs = np.flatnonzero(np.diff(np.concatenate([[0], close.astype(int), [0]])))
        for a0, b0 in zip(runs[::2], runs[1::2], strict=True):
            k = a0 + int(np.argmin(dist[a0:b0]))
            if gcp_mode == "ideal":
                gcp_t.append(t_ph[k])
                gcp_p.append(ph_pos[k] + rng.normal(0.0, gcp_sd_m, 3))
            else:
                # Bluetooth: the surveyed coordinate, after the ranging cycle (and any lag), with the offset
                # between the phone and the beacon at which proximity is declared
                t_trig = t_true[k] + rng.uniform(0.0, BLE_RANGING_CYCLE_S) + ble_lag_s
                k2 = min(int(np.searchsorted(t_true, t_trig)), n - 1)
                gcp_t.append(t_ph[k2])
                gcp_p.append(g + np.append(rng.normal(0.0, BLE_PROXIMITY_SD_M, 2), 0.0))
            gcp_i.append(jj)
    order = np.argsort(gcp_t)
    init_att = np.array([roll[0], pitch[0], yaw_b[0] + np.deg2rad(rng.normal(0.0, init_yaw_sd_deg))])
    stationary = ~walking[ep] & (walk_w[ep] < 0.05)
    if prof.baro_sd_m is not None:
        baro_t, baro_h = t_ph.copy(), pos[ep, 2] + rng.normal(0.0, prof.baro_sd_m, n)
    else:
        baro_t, baro_h = np.zeros(0), np.zeros(0)
    if key is not None:  # the walk owns its arrays; the cache keeps its own
        t, pos, mat = t.copy(), pos.copy(), mat.copy()
    return InsWalk(
        t_ref_s=t, pos_ref_n_m=pos, mat_ref_nb=mat, t_s=t_ph, gyr_b_radps=gyr, acc_b_mps2=acc,
        pos_true_n_m=pos[ep], vel_true_n_mps=vel[ep], mat_true_nb=mat[ep], stationary_true=stationary,
        gnss_t_s=t_ph[g_idx], gnss_pos_n_m=gnss_pos, gnss_sd_m=gsd,
        gcp_t_s=np.asarray(gcp_t)[order], gcp_pos_n_m=np.asarray(gcp_p).reshape(-1, 3)[order],
        gcp_id=np.asarray(gcp_i, dtype=np.int64)[order], gcp_sd_m=float(gcp_sd_m), t_indoor_s=t_indoor,
        init={"pos_n_m": gnss_pos[0].copy(), "vel_n_mps": np.zeros(3), "euler_rad": init_att},
        sensor_true=np.concatenate([ba, bg, sa, sg]), stairs_true=on_stairs[ep], baro_t_s=baro_t,
        baro_height_m=baro_h, t_true_s=t_true,
        params={"route": route, "profile": prof.name, "user_c": float(user_c), "user_height_m": user_height_m,
                "gait": gait, "gcp_mode": gcp_mode, **gait_d},
    )


def walk_summary(walk: InsWalk) -> dict:
    """The simulated inputs of one walk: duration and indoor part (s), IMU rate (mean, min, max, Hz), GNSS fixes,
    control-point passages and their mean interval (s), the walker's speed, cadence and step scale, the epochs on
    stairs and the control-point fixes' mean delay after the closest approach (s)."""
    from ilocalg.ins.chain import gcp_fix_delay_s

    gap = np.diff(walk.gcp_t_s)
    dt = np.diff(walk.t_s)
    return {"duration_s": walk.t_s[-1] - walk.t_s[0], "indoor_s": walk.t_s[-1] - walk.t_indoor_s,
            "imu_rate_hz": 1.0 / np.mean(dt), "imu_rate_min_hz": 1.0 / np.max(dt), "imu_rate_max_hz": 1.0 / np.min(dt),
            "gnss_fixes": walk.gnss_t_s.size, "gcp_passages": walk.gcp_t_s.size,
            "gcp_interval_mean_s": float(gap.mean()) if gap.size else np.nan,
            "walker_speed_mps": walk.params.get("speed_mps", np.nan),
            "walker_cadence_hz": walk.params.get("cadence_hz", np.nan), "walker_step_scale_c": walk.params["user_c"],
            "stair_epochs": int(walk.stairs_true.sum()), "gcp_delay_mean_s": gcp_fix_delay_s(walk, GCP_XYZ_M)}


def _rssi_triggers(t_s: np.ndarray, pos_m: np.ndarray, beacon_m: np.ndarray, t_from_s: float, rssi_sd_db: float,
                   rng) -> list:
    """Times (s, true clock) at which a phone declares itself at ``beacon_m`` (the "rssi" model of :func:`simulate`).

    Packets every :data:`BLE_ADV_INTERVAL_S` plus U(0, :data:`BLE_ADV_DELAY_MAX_S`); RSSI =
    ``BLE_RSSI_1M_DBM - 10 n log10(d) + N(0, rssi_sd_db)`` with ``d`` the phone-beacon distance (at least
    0.1 m); ranging cycles of :data:`BLE_RANGING_CYCLE_S` with a random phase; a cycle whose mean RSSI
    reaches the RSSI of :data:`BLE_IMMEDIATE_M` triggers a fix at its end, once per passage (re-armed by a
    cycle below the threshold or without packets). Only times after ``t_from_s`` (the indoor part).
    """
    n_adv = int((t_s[-1] - t_s[0]) / BLE_ADV_INTERVAL_S)
    t_adv = t_s[0] + np.cumsum(np.full(n_adv, BLE_ADV_INTERVAL_S) + rng.uniform(0, BLE_ADV_DELAY_MAX_S, n_adv))
    noise = rng.normal(0.0, rssi_sd_db, n_adv)
    phase = rng.uniform(0.0, BLE_RANGING_CYCLE_S)
    keep = (t_adv >= t_from_s) & (t_adv <= t_s[-1])
    t_adv, noise = t_adv[keep], noise[keep]
    p = np.column_stack([np.interp(t_adv, t_s, pos_m[:, j]) for j in range(3)])
    d = np.maximum(np.linalg.norm(p - beacon_m, axis=1), 0.1)
    rssi = BLE_RSSI_1M_DBM - 10 * BLE_PATH_LOSS_EXP * np.log10(d) + noise
    thr = BLE_RSSI_1M_DBM - 10 * BLE_PATH_LOSS_EXP * np.log10(BLE_IMMEDIATE_M)
    cyc = np.floor((t_adv - phase) / BLE_RANGING_CYCLE_S).astype(np.int64)
    out, armed, last = [], True, None
    # t_adv increases, so each cycle's packets are one slice (the same values, in the same order, as rssi[cyc == c])
    cycles, first = np.unique(cyc, return_index=True)
    bounds = np.append(first, cyc.size).tolist()
    for i, c in enumerate(cycles):
        if last is not None and c != last + 1:
            armed = True                       # a cycle without packets re-arms
        hit = rssi[bounds[i]:bounds[i + 1]].mean() >= thr
        if hit and armed:
            out.append(phase + (c + 1) * BLE_RANGING_CYCLE_S)
        armed = not hit
        last = c
    return out


def _monotonic_tags(t_tag_s: np.ndarray, min_gap_s: float) -> np.ndarray:
    """Time tags that never go backwards: a tag earlier than ``min_gap_s`` after its predecessor is moved to it.

    Phone sensor clocks are monotonic; with a time-tag error sd up to a quarter of the shortest interval
    (2 sd clip < half of it) no tag moves and no random number is drawn, so the same seed gives the same tags.
    """
    out = np.array(t_tag_s, dtype=float)
    bad = np.flatnonzero(np.diff(out) < min_gap_s)
    if bad.size:
        for k in range(int(bad[0]) + 1, out.size):  # in order: a moved tag may push its successor
            if out[k] < out[k - 1] + min_gap_s:
                out[k] = out[k - 1] + min_gap_s
    return out


def gauss_markov(rng, t_s, sd, tau_s, n_axes=3) -> np.ndarray:
    """First-order Gauss-Markov sequences (N, n_axes) at (irregular) times ``t_s``: stationary sd, correlation time.

    ``b_k = exp(-dt/tau) b_{k-1} + w_k``, ``var(w_k) = sd^2 (1 - exp(-2 dt/tau))``, ``b_0 ~ N(0, sd^2)``.

    References
    ----------
    Gelb (1974), Applied Optimal Estimation, Table 3.8-1 (first-order Markov process).
    """
    t_s = np.asarray(t_s, dtype=float)
    a = np.exp(-np.diff(t_s) / tau_s)
    w = rng.normal(0.0, 1.0, (t_s.size, n_axes))
    w[0] *= sd
    w[1:] *= (sd * np.sqrt(1.0 - a * a))[:, None]
    # the recursion per axis on Python floats: the same IEEE products and sums as on numpy rows, without the
    # per-sample array overhead
    cols = []
    for wj in w.T.tolist():
        b_k = wj[0]
        col = [b_k]
        for ak, wk in zip(a.tolist(), wj[1:], strict=True):
            b_k = ak * b_k + wk
            col.append(b_k)
        cols.append(col)
    return np.array(cols, dtype=float).T.reshape(w.shape).copy()
