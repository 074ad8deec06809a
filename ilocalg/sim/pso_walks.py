"""Simulated walks of the PSO pedestrian-navigation thesis: six walkers, two phases.

The thesis (ch. 5) records, on a hand-held GPS platform, an electronic compass and a three-axis
accelerometer at 8 Hz and GPS fixes at 1 Hz, for six walkers A1, A2, A3 (leg 94 cm), B1, B2 (100 cm)
and C (108 cm). Phase 1 walks (good sky: a school playground lap for A1, a car park for the others)
teach the Weinberg factor k against GPS; phase 2 walks (a park and the campus hall for A1, the
management college for the others, partly shaded) apply it. This module makes such walks
deterministically from a seed; nothing in it is tuned to the thesis's outcome table (Table 5-2).

Walk design (what the walkers did, taken from the thesis; marked "paper" in the code)
    Leg lengths (Table 5-1); the number of steps counted on each phase-1 walk (Table 5-2). The true
    length of a route is an input (``route_m``): the thesis never measured it, it gives only each
    phase-1 walk's GPS distance (Table 5-2), itself a noisy measurement. By default the true length
    is that GPS distance times ``route_scale`` (1.0), i.e. the assumption "the GPS distance is
    unbiased"; the simulated GPS then measures the route with its own error, so the simulated GPS
    distance is *not* forced to the thesis's. Callers sweep ``route_scale`` or pass ``route_m``.
    A1's phase-2 step counts (250 and 408, thesis Fig. 5.14 file names). Other phase-2 walks:
    300 steps (assumption). Phase-1 routes: A1 a playground lap (stadium oval), the others a straight
    line (the thesis asks for straight phase-1 walks, sec. 5.2.2). Phase-2 routes: closed loops
    (rounded rectangles, aspect 2:1) that start and end at the same point, as the thesis's walks do.

Gait (literature, not the thesis)
    Walking speed: each walker's comfortable speed ~ N(1.30, 0.08) m/s (Bohannon & Andrews 2011,
    adults 20-59 y: 1.3-1.4 m/s); cadence = speed / step length. Step-to-step variability: 3 % in
    step length and in step duration (coefficients of variation of normal gait, Hausdorff 2005).
    Vertical motion of the trunk: inverted pendulum with Zijlstra & Hof's correction (Gait & Posture
    18, 2003): centre-of-mass rise ``h = l - sqrt(l^2 - (s / (2 K_ZH))^2)`` with ``K_ZH = 1.25``,
    sinusoidal at the step rate, so the vertical acceleration amplitude of a step of length ``s`` and
    duration ``T`` is ``(h / 2)(2 pi / T)^2``; a second harmonic (heel strike) of relative amplitude
    ~ U(0.2, 0.4) per walker. The Weinberg factor is therefore not an input: it emerges from leg
    length, step length and cadence.
    Step-to-step scatter of the vertical acceleration amplitude beyond the pendulum's (the hand-held
    device's own motion, foot placement): each step's amplitude is multiplied by a log-normal factor
    with coefficient of variation ``step_amp_cv`` = 0.18. Measured on the public ILC 2020 site2/F4
    walks (hand-held phone, 50 Hz): the per-step ``Amax - Amin`` of the sign-change steps has a CV of
    0.20 (median over the 19 walks, IQR 0.18-0.28; :func:`ilocalg.pdr.k_walks.ilc_k_study`
    reports it per walk as ``amp_cv``); the pendulum already gives about 0.085 from the 3 % step
    length and duration CVs (amplitude ~ s^2 / T^2), so the added part is sqrt(0.20^2 - 0.085^2) =
    0.18. Swept over 0 (the toolkit's earlier simulator) to 0.27 (the IQR's upper end) by the PSO
    experiment's sensitivity table.

Sensors (thesis where it says, else typical values of the MEMS parts of the time)
    Accelerometer (z vertical): 8 Hz (thesis sec. 5.1.1), quantised to the thesis's scale, 244.25
    counts per g (thesis sec. 5.1.3: 0 g at 417.57 counts, 1 g at 661.82), white noise 0.10 m/s^2
    (assumption), no anti-alias filter (samples of the continuous signal).
    A static accelerometer log (device on a table, as the thesis's static calibration, sec. 5.1.3)
    comes from :func:`simulate_static_acc`: its RMS (eq. 3.4) is the static-noise RMS of the +-RMS
    band of the step detector (Fig. 3.9).
    Compass: 8 Hz, static noise RMS 0.716 deg (thesis sec. 5.1.3, raw signal) made of AR(1) noise
    (lag-1 correlation 0.6, assumption) plus rare spikes (the thesis notes occasional spikes; 0.5 %
    of samples, sd 4 deg, assumption), scaled to the thesis's total static RMS 0.716 deg. While
    walking: a residual calibration bias ~ N(0, 2 deg) per walk (smartphone compasses right after
    calibration: 1-3 deg azimuth error, RMSE <= 2 deg, Lviv Polytechnic field study "Use of
    smartphones for determining orientation angles in the field"); hand sway of the hand-held device
    with the trunk's axial rotation, 4.5 deg amplitude at the stride rate (half the step rate): the
    trunk's rotation about the vertical axis is "of the order of nine degrees" peak to peak in
    walking (Crosbie, Vachalathiti & Smith, Gait & Posture 5, 1997, citing the gait studies of the
    1960s); magnetic disturbance of the surroundings as a heading error that varies along the
    route, a first-order Gauss-Markov process in distance with sd 2 deg (the same field study's
    RMSE outdoors) and correlation length 10 m (assumption; not swept).
    GPS: 1 Hz (thesis sec. 5.1.1). Open sky: per-axis first-order Gauss-Markov error with sd
    0.61 m, from the thesis's own GPS test (sec. 5.1.3, Fig. 5.9: static for about 30 s, "accuracy
    better than 1.5 m"), read as the 95 % radius of the horizontal error: 1.5 / sqrt(-2 ln 0.05) =
    0.61 m per axis; correlation time 20 s (assumption: the thesis gives none; not swept).
    No white component by default (the thesis's test shows none separately; ``gps_white_sd_m``
    adds one). Shaded phase-2 segments (two, each 20 % of the walk): sd 4 m, correlation time 5 s,
    and 30 % of the fixes missing (assumptions: "partial shading", sec. 5.2.3).
    Each walk starts and ends with 3 s standing still.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Tables 5-1, 5-2, sec. 5.1-5.3. Crosbie, J., Vachalathiti, R. and Smith, R. (1997). Patterns of spinal
motion during walking. Gait & Posture 5, 6-12. W. Zijlstra and A. L. Hof,
"Assessment of spatio-temporal gait parameters from trunk accelerations during human walking",
Gait & Posture 18 (2003). R. W. Bohannon and A. W. Andrews, "Normal walking speed: a descriptive
meta-analysis", Physiotherapy 97 (2011).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.gnss import local_to_latlon
from ilocalg.units import G0_MPS2, as_rng

__all__ = [
    "WALK_DESIGN_PAPER",
    "PHASE2_STEPS_PAPER",
    "SENSORS",
    "Walk",
    "stadium_route",
    "loop_route",
    "line_route",
    "simulate_walk",
    "simulate_pso_walks",
    "simulate_static_compass",
    "simulate_static_acc",
    "gps_static_sd_m",
]

# Settings from the paper
# -----------------------
# Chao (2008): WALK_DESIGN_PAPER from Tables 5-1 (legs) and 5-2 (counted steps, phase-1 GPS distance,
# the default true route length times ``route_scale``: an input);
# PHASE2_STEPS_PAPER from the Fig. 5.14 file names; SENSORS: sensor rates from sec. 5.1.1, the
# accelerometer's 1 g and 0 g counts and the raw static compass RMS from sec. 5.1.3 (inputs), the GPS
# static bound of sec. 5.1.3 (Fig. 5.9).
# The other SENSORS values are this simulator's (module docstring).
#: Walk design from the thesis (Table 5-1 legs, Table 5-2 counted steps and phase-1 length).
WALK_DESIGN_PAPER = {
    "A1": {"leg_m": 0.94, "n_steps": 217, "route_m": 160.25},
    "A2": {"leg_m": 0.94, "n_steps": 116, "route_m": 93.26},
    "A3": {"leg_m": 0.94, "n_steps": 128, "route_m": 96.65},
    "B1": {"leg_m": 1.00, "n_steps": 108, "route_m": 92.71},
    "B2": {"leg_m": 1.00, "n_steps": 118, "route_m": 95.96},
    "C": {"leg_m": 1.08, "n_steps": 106, "route_m": 93.73},
}

#: Phase-2 walks: A1's two (paper Fig. 5.14 file names: 250 and 408 steps); 300 steps elsewhere (assumed).
PHASE2_STEPS_PAPER = {
    "A1": {"park": 250, "hall": 408},
}
PHASE2_DEFAULT_STEPS = 300

#: Sensor and gait constants (see the module docstring for each source).
SENSORS = {
    "acc_rate_hz": 8.0,
    "compass_rate_hz": 8.0,
    "gps_rate_hz": 1.0,
    "acc_counts_per_g": 661.82 - 417.57,
    "acc_noise_mps2": 0.10,
    "compass_static_rms_deg": 0.716,
    "compass_ar1": 0.6,
    "compass_spike_rate": 0.005,
    "compass_spike_sd_deg": 4.0,
    "compass_bias_sd_deg": 2.0,
    "compass_sway_deg": 4.5,
    "mag_disturb_sd_deg": 2.0,
    "mag_disturb_len_m": 10.0,
    "gps_static_95_m": 1.5,
    "gps_open_tau_s": 20.0,
    "gps_white_sd_m": 0.0,
    "gps_shaded_sd_m": 4.0,
    "gps_shaded_tau_s": 5.0,
    "gps_shaded_fraction": 0.2,
    "gps_shaded_dropout": 0.3,
    "speed_mean_mps": 1.30,
    "speed_sd_mps": 0.08,
    "step_cv": 0.03,
    "step_amp_cv": 0.18,
    "k_zijlstra_hof": 1.25,
    "harmonic2_range": (0.2, 0.4),
    "stand_s": 3.0,
}


def gps_static_sd_m(bound_95_m: float | None = None) -> float:
    """Per-axis sd of the open-sky GPS error from the thesis's static test bound.

    The thesis's GPS test (sec. 5.1.3, Fig. 5.9) reports a static accuracy better than 1.5 m. Read
    as the radius holding 95 % of the horizontal errors of a circular 2-D Gaussian,
    ``sd = bound / sqrt(-2 ln 0.05)`` (0.61 m for 1.5 m).
    """
    b = SENSORS["gps_static_95_m"] if bound_95_m is None else float(bound_95_m)
    if not np.isfinite(b) or b <= 0:
        raise ValueError(f"bound_95_m must be a positive distance in m, got {bound_95_m!r}")
    return b / float(np.sqrt(-2.0 * np.log(0.05)))

#: Map origins (for the lat/lon of the routes): Tunghai University, Taichung; Wenhu, Taipei.
ORIGINS_DEG = {"tunghai": (24.1797, 120.6003), "wenhu": (25.0797, 121.5733)}


@dataclass(frozen=True)
class Walk:
    """One simulated walk.

    Attributes
    ----------
    walker, phase, place : str
        Walker id, ``"1"`` or ``"2"``, and the place name.
    leg_m, speed_mps, step_mean_m : float
        Gait of the walker.
    imu : DataFrame
        8 Hz samples: ``t_s``, ``acc_z_mps2`` (vertical specific force, gravity included),
        ``yaw_deg`` (compass, from north clockwise, in [0, 360)).
    gps : DataFrame
        1 Hz fixes: ``t_s``, ``lat_deg``, ``lon_deg`` (missing fixes are absent rows).
    truth : DataFrame
        8 Hz truth: ``t_s``, ``x_m``, ``y_m`` (east, north from the origin), ``yaw_deg``.
    steps : DataFrame
        True steps: ``t_s`` (heel strike), ``length_m``, ``duration_s``, ``amp_mps2`` (vertical
        acceleration amplitude of the fundamental).
    origin_deg : tuple
        (lat, lon) of the local frame origin (the walk's start).
    route_m : float
        True walked distance.
    """

    walker: str
    phase: str
    place: str
    leg_m: float
    speed_mps: float
    step_mean_m: float
    imu: pd.DataFrame = field(repr=False)
    gps: pd.DataFrame = field(repr=False)
    truth: pd.DataFrame = field(repr=False)
    steps: pd.DataFrame = field(repr=False)
    origin_deg: tuple = (0.0, 0.0)
    route_m: float = 0.0

    @property
    def n_steps(self) -> int:
        return len(self.steps)


def stadium_route(perimeter_m: float, straight_frac: float = 0.5, n: int = 400) -> np.ndarray:
    """Closed stadium (running-track) polyline of the given perimeter, shape (n+1, 2), starting at (0, 0)."""
    L = perimeter_m * straight_frac / 2
    r = perimeter_m * (1 - straight_frac) / (2 * np.pi)
    s = np.linspace(0, perimeter_m, n + 1)
    pts = np.empty((n + 1, 2))
    for i, si in enumerate(s):
        if si <= L:
            pts[i] = (si, 0.0)
        elif si <= L + np.pi * r:
            a = (si - L) / r
            pts[i] = (L + r * np.sin(a), r - r * np.cos(a))
        elif si <= 2 * L + np.pi * r:
            pts[i] = (L - (si - L - np.pi * r), 2 * r)
        else:
            a = (si - 2 * L - np.pi * r) / r
            pts[i] = (-r * np.sin(a), r + r * np.cos(a))
    return pts


def loop_route(perimeter_m: float, aspect: float = 2.0, corner_frac: float = 0.15, n: int = 400,
               rotation_deg: float = 0.0) -> np.ndarray:
    """Closed rounded-rectangle polyline of the given perimeter, starting and ending at (0, 0)."""
    # perimeter = 2(a + b) - 8 r + 2 pi r, with b = a / aspect and r = corner_frac * b
    a = perimeter_m / (2 * (1 + 1 / aspect) - 8 * corner_frac / aspect + 2 * np.pi * corner_frac / aspect)
    b = a / aspect
    r = corner_frac * b
    segs = [("line", (r, 0), (a - r, 0)), ("arc", (a - r, r), -np.pi / 2),
            ("line", (a, r), (a, b - r)), ("arc", (a - r, b - r), 0.0),
            ("line", (a - r, b), (r, b)), ("arc", (r, b - r), np.pi / 2),
            ("line", (0, b - r), (0, r)), ("arc", (r, r), np.pi)]
    pts = []
    for kind, p, q in segs:
        if kind == "line":
            t = np.linspace(0, 1, 20)[:-1, None]
            pts.append(np.asarray(p) + t * (np.asarray(q) - np.asarray(p)))
        else:
            ang = q + np.linspace(0, np.pi / 2, 12)[:-1]
            pts.append(np.asarray(p) + r * np.c_[np.cos(ang), np.sin(ang)])
    xy = np.vstack(pts + [np.array([[r, 0.0]])])
    xy = xy - xy[0]
    c, s_ = np.cos(np.deg2rad(rotation_deg)), np.sin(np.deg2rad(rotation_deg))
    xy = xy @ np.array([[c, s_], [-s_, c]])
    # resample uniformly in arc length
    d = np.r_[0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    si = np.linspace(0, d[-1], n + 1)
    out = np.c_[np.interp(si, d, xy[:, 0]), np.interp(si, d, xy[:, 1])]
    return out * (perimeter_m / _arc(out)[-1])


def line_route(length_m: float, bearing_deg: float = 30.0) -> np.ndarray:
    """Straight route from (0, 0), shape (2, 2)."""
    b = np.deg2rad(bearing_deg)
    return np.array([[0.0, 0.0], [length_m * np.sin(b), length_m * np.cos(b)]])


def _arc(route_xy: np.ndarray) -> np.ndarray:
    return np.r_[0.0, np.cumsum(np.hypot(*np.diff(route_xy, axis=0).T))]


def _along(route_xy: np.ndarray, s_m: np.ndarray):
    """Position and yaw (deg from north, clockwise) at arc lengths ``s_m``."""
    d = _arc(route_xy)
    s = np.clip(s_m, 0, d[-1])
    x = np.interp(s, d, route_xy[:, 0])
    y = np.interp(s, d, route_xy[:, 1])
    seg = np.clip(np.searchsorted(d, s, side="right") - 1, 0, len(d) - 2)
    dx, dy = np.diff(route_xy, axis=0)[seg].T
    yaw = np.rad2deg(np.arctan2(dx, dy)) % 360.0
    return x, y, yaw


def _gauss_markov(n: int, dt: float, sd: float, tau: float, rng) -> np.ndarray:
    phi = np.exp(-dt / tau)
    e = rng.normal(0.0, sd * np.sqrt(1 - phi**2), n)
    out = np.empty(n)
    out[0] = rng.normal(0.0, sd)
    for i in range(1, n):
        out[i] = phi * out[i - 1] + e[i]
    return out


def _compass_noise(n: int, rng) -> np.ndarray:
    """Static compass noise, deg: AR(1) plus rare spikes with total RMS ``compass_static_rms_deg``."""
    p, sd_sp = SENSORS["compass_spike_rate"], SENSORS["compass_spike_sd_deg"]
    var_ar = SENSORS["compass_static_rms_deg"] ** 2 - p * sd_sp**2
    phi = SENSORS["compass_ar1"]
    ar = _gauss_markov(n, 1.0, np.sqrt(var_ar), -1.0 / np.log(phi), rng)
    spikes = np.where(rng.random(n) < p, rng.normal(0.0, sd_sp, n), 0.0)
    return ar + spikes


def simulate_static_compass(rng=None, duration_s: float = 60.0, yaw0_deg: float = 123.0) -> pd.DataFrame:
    """A static compass log (device on a table), as in thesis sec. 5.1.3 / Fig. 5.3.

    Returns
    -------
    DataFrame
        ``t_s``, ``yaw_deg`` at :data:`SENSORS` ``compass_rate_hz``.
    """
    gen = as_rng(rng)
    fs = SENSORS["compass_rate_hz"]
    n = int(round(duration_s * fs))
    if n < 10:
        raise ValueError(f"duration_s must give at least 10 samples, got {duration_s}")
    t = np.arange(n) / fs
    return pd.DataFrame({"t_s": t, "yaw_deg": yaw0_deg + _compass_noise(n, gen)})


def simulate_static_acc(rng=None, duration_s: float = 60.0, sensors: dict | None = None) -> pd.DataFrame:
    """A static accelerometer log (device still on a table, z up), as the thesis's calibration (sec. 5.1.3).

    Gravity plus the accelerometer's white noise, quantised to the thesis's scale (the same sensor
    model as :func:`simulate_walk`). Its RMS (eq. 3.4) is the static-noise RMS that sets the
    +-RMS band of the step detector (Fig. 3.9). ``sensors`` overrides :data:`SENSORS` entries.

    Returns
    -------
    DataFrame
        ``t_s``, ``acc_z_mps2`` at :data:`SENSORS` ``acc_rate_hz``.
    """
    gen = as_rng(rng)
    S = _sensors(sensors)
    fs = S["acc_rate_hz"]
    n = int(round(duration_s * fs))
    if n < 10:
        raise ValueError(f"duration_s must give at least 10 samples, got {duration_s}")
    lsb = G0_MPS2 / S["acc_counts_per_g"]
    acc = np.round((G0_MPS2 + gen.normal(0, S["acc_noise_mps2"], n)) / lsb) * lsb
    return pd.DataFrame({"t_s": np.arange(n) / fs, "acc_z_mps2": acc})


def _mag_disturbance_deg(s_m: np.ndarray, rng) -> np.ndarray:
    """Heading error of the magnetic surroundings along the route (deg), Gauss-Markov in distance."""
    sd, L = SENSORS["mag_disturb_sd_deg"], SENSORS["mag_disturb_len_m"]
    ds = 0.5
    grid = np.arange(0.0, float(np.max(s_m)) + ds, ds)
    if sd <= 0:
        rng.standard_normal(grid.size)  # keep the stream's position independent of the setting
        return np.zeros_like(s_m)
    e = _gauss_markov(grid.size, ds, sd, L, rng)
    return np.interp(s_m, grid, e)


def _sensors(overrides: dict | None) -> dict:
    """:data:`SENSORS` with ``overrides`` (unknown names raise)."""
    if not overrides:
        return SENSORS
    unknown = sorted(set(overrides) - set(SENSORS))
    if unknown:
        raise ValueError(f"sensors: unknown settings {unknown}; known: {sorted(SENSORS)}")
    for k, v in overrides.items():
        if isinstance(SENSORS[k], float) and (not np.isfinite(v) or v < 0):
            raise ValueError(f"sensors[{k!r}] must be a finite non-negative number, got {v!r}")
    return {**SENSORS, **overrides}


def simulate_walk(walker: str, phase: str, place: str, route_xy: np.ndarray, n_steps: int, leg_m: float,
                  speed_mps: float, harmonic2: float, origin_deg: tuple, shaded: bool, rng,
                  sensors: dict | None = None) -> Walk:
    """Simulate one walk along ``route_xy`` with ``n_steps`` steps (see the module docstring).

    Parameters
    ----------
    route_xy : ndarray, shape (m, 2)
        Route polyline, m (east, north), starting at (0, 0).
    n_steps : int
        Number of steps; the step lengths (3 % jitter) are rescaled to cover the route exactly.
    leg_m, speed_mps, harmonic2 : float
        Walker's leg length, speed and heel-strike harmonic ratio.
    origin_deg : (lat, lon)
        Latitude/longitude of the route's (0, 0).
    shaded : bool
        Partial GPS shading (phase 2).
    rng : Generator, int or None
    sensors : dict, optional
        Overrides of :data:`SENSORS` entries (for sweeps).
    """
    gen = as_rng(rng)
    S = _sensors(sensors)
    if n_steps < 2:
        raise ValueError(f"n_steps must be >= 2, got {n_steps}")
    route_m = float(_arc(route_xy)[-1])
    cv = S["step_cv"]
    s = 1.0 + cv * gen.standard_normal(n_steps)
    s = s * route_m / s.sum()
    T_mean = (route_m / n_steps) / speed_mps
    T = T_mean * (1.0 + cv * gen.standard_normal(n_steps))
    stand = S["stand_s"]
    t_hs = stand + np.r_[0.0, np.cumsum(T)[:-1]]  # heel strikes
    t_end_walk = stand + T.sum()
    t_total = t_end_walk + stand
    # vertical trunk motion: inverted pendulum with the Zijlstra-Hof correction
    K = S["k_zijlstra_hof"]
    h = leg_m - np.sqrt(leg_m**2 - (s / (2 * K)) ** 2)
    amp = 0.5 * h * (2 * np.pi / T) ** 2
    # step-to-step amplitude scatter beyond the pendulum's (log-normal, mean 1, CV step_amp_cv)
    sig = np.sqrt(np.log1p(S["step_amp_cv"] ** 2))
    # (its own stream, jumped from the walk's, so the other draws do not depend on the setting)
    amp_gen = np.random.Generator(gen.bit_generator.jumped())
    amp = amp * np.exp(sig * amp_gen.standard_normal(n_steps) - 0.5 * sig**2)
    psi2 = gen.uniform(0, 2 * np.pi)
    fs = S["acc_rate_hz"]
    t = np.arange(int(np.floor(t_total * fs)) + 1) / fs
    j = np.searchsorted(t_hs, t, side="right") - 1
    walking = (t >= stand) & (t < t_end_walk)
    jj = np.clip(j, 0, n_steps - 1)
    u = np.where(walking, (t - t_hs[jj]) / T[jj], 0.0)
    a_dyn = np.where(walking, amp[jj] * (np.cos(2 * np.pi * u) + harmonic2 * np.cos(4 * np.pi * u + psi2)), 0.0)
    lsb = G0_MPS2 / S["acc_counts_per_g"]
    acc = G0_MPS2 + a_dyn + gen.normal(0, S["acc_noise_mps2"], t.size)
    acc = np.round(acc / lsb) * lsb
    # position along the route (linear within each step)
    s_cum = np.r_[0.0, np.cumsum(s)]
    s_t = np.where(walking, s_cum[jj] + s[jj] * u, np.where(t < stand, 0.0, route_m))
    x, y, yaw_true = _along(route_xy, s_t)
    # while standing keep the first / last walking direction
    yaw_true = np.where(t < stand, _along(route_xy, np.array([0.0]))[2][0], yaw_true)
    yaw_true = np.where(t >= t_end_walk, _along(route_xy, np.array([route_m - 1e-6]))[2][0], yaw_true)
    sway = np.where(walking, S["compass_sway_deg"] * np.sin(np.pi * (j + u)), 0.0)
    bias = gen.normal(0, S["compass_bias_sd_deg"])
    mag = _mag_disturbance_deg(s_t, gen)
    yaw_meas = (yaw_true + bias + sway + mag + _compass_noise(t.size, gen)) % 360.0
    imu = pd.DataFrame({"t_s": t, "acc_z_mps2": acc, "yaw_deg": yaw_meas})
    truth = pd.DataFrame({"t_s": t, "x_m": x, "y_m": y, "yaw_deg": yaw_true})
    # GPS at 1 Hz
    tg = np.arange(0.0, t_total + 1e-9, 1.0 / S["gps_rate_hz"])
    xg, yg, _ = _along(route_xy, np.interp(tg, t, s_t))
    sd_open = gps_static_sd_m(S["gps_static_95_m"])
    ex = _gauss_markov(tg.size, 1.0, sd_open, S["gps_open_tau_s"], gen)
    ey = _gauss_markov(tg.size, 1.0, sd_open, S["gps_open_tau_s"], gen)
    ex += gen.normal(0, 1.0, tg.size) * S["gps_white_sd_m"]
    ey += gen.normal(0, 1.0, tg.size) * S["gps_white_sd_m"]
    keep = np.ones(tg.size, dtype=bool)
    if shaded:
        frac = S["gps_shaded_fraction"]
        n_sh = int(frac * tg.size)
        for start in (int(0.25 * tg.size), int(0.6 * tg.size)):
            sl = slice(start, start + n_sh)
            m = tg[sl].size
            ex[sl] += _gauss_markov(m, 1.0, S["gps_shaded_sd_m"], S["gps_shaded_tau_s"], gen)
            ey[sl] += _gauss_markov(m, 1.0, S["gps_shaded_sd_m"], S["gps_shaded_tau_s"], gen)
            keep[sl] &= gen.random(m) >= S["gps_shaded_dropout"]
    lat, lon = local_to_latlon(xg + ex, yg + ey, *origin_deg)
    gps = pd.DataFrame({"t_s": tg[keep], "lat_deg": lat[keep], "lon_deg": lon[keep]})
    steps = pd.DataFrame({"t_s": t_hs, "length_m": s, "duration_s": T, "amp_mps2": amp})
    return Walk(walker=walker, phase=phase, place=place, leg_m=leg_m, speed_mps=speed_mps,
                step_mean_m=route_m / n_steps, imu=imu, gps=gps, truth=truth, steps=steps,
                origin_deg=tuple(origin_deg), route_m=route_m)


def simulate_pso_walks(seed: int = 0, route_scale: float = 1.0,
                       route_m: dict | None = None, sensors: dict | None = None) -> dict[str, list[Walk]]:
    """All walks of the two-phase experiment.

    Parameters
    ----------
    seed : int
    route_scale : float
        True phase-1 route length as a multiple of the thesis's GPS distance (1.0: the GPS distance
        taken as unbiased); phase-2 routes scale with it (same mean step length).
    route_m : dict, optional
        ``{walker: true phase-1 route length in m}``, overriding ``route_scale`` for those walkers.
    sensors : dict, optional
        Overrides of :data:`SENSORS` entries (e.g. ``{"step_amp_cv": 0.0}``, ``{"gps_open_tau_s": 60.0}``).

    Returns
    -------
    dict
        ``{"1": [six phase-1 walks], "2": [phase-2 walks: A1 park, A1 hall, A2 ... C]}``.
        Each walk has its own child seed of ``seed`` so walks do not depend on each other.
    """
    if not np.isfinite(route_scale) or route_scale <= 0:
        raise ValueError(f"route_scale must be a positive number, got {route_scale!r}")
    unknown = sorted(set(route_m or {}) - set(WALK_DESIGN_PAPER))
    if unknown:
        raise ValueError(f"route_m: unknown walkers {unknown}; known: {list(WALK_DESIGN_PAPER)}")
    lengths = {w: float((route_m or {}).get(w, route_scale * d["route_m"])) for w, d in WALK_DESIGN_PAPER.items()}
    for w, v in lengths.items():
        if not np.isfinite(v) or v <= 0:
            raise ValueError(f"route_m[{w!r}] must be a positive length in m, got {v!r}")
    S = _sensors(sensors)
    ss = np.random.SeedSequence(seed)
    names = list(WALK_DESIGN_PAPER)
    walker_ss, walk_ss = ss.spawn(2)
    wgen = np.random.default_rng(walker_ss)
    speeds = S["speed_mean_mps"] + S["speed_sd_mps"] * wgen.standard_normal(len(names))
    harm = wgen.uniform(*S["harmonic2_range"], len(names))
    seeds = iter(walk_ss.spawn(32))
    out: dict[str, list[Walk]] = {"1": [], "2": []}
    for i, name in enumerate(names):
        d = WALK_DESIGN_PAPER[name]
        if name == "A1":
            route, origin, place = stadium_route(lengths[name]), ORIGINS_DEG["wenhu"], "playground"
        else:
            route, origin, place = line_route(lengths[name], 20.0 + 15 * i), ORIGINS_DEG["tunghai"], "car park"
        out["1"].append(simulate_walk(name, "1", place, route, d["n_steps"], d["leg_m"], float(speeds[i]),
                                      float(harm[i]), origin, False, np.random.default_rng(next(seeds)), sensors))
    for i, name in enumerate(names):
        d = WALK_DESIGN_PAPER[name]
        step_m = lengths[name] / d["n_steps"]
        places = PHASE2_STEPS_PAPER.get(name, {"management college": PHASE2_DEFAULT_STEPS})
        for place, n in places.items():
            route = loop_route(n * step_m, rotation_deg=10.0 * i)
            origin = ORIGINS_DEG["wenhu"] if place == "park" else ORIGINS_DEG["tunghai"]
            out["2"].append(simulate_walk(name, "2", place, route, n, d["leg_m"], float(speeds[i]), float(harm[i]),
                                          origin, True, np.random.default_rng(next(seeds)), sensors))
    return out
