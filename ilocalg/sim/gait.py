"""Gait + phone simulator: handheld smartphone IMU logs of pedestrians walking a route, with ground truth.

Deterministic from a seed: the same ``rng`` seed gives identical arrays.

Model (each value from a published gait measurement; data/gait/README.md gives the table)
-----
Walkers
    Height ``U(1.55, 1.90)`` m (adults of different builds, thesis L399); leg length (greater
    trochanter height) ``0.530 height`` (Winter 2009, anthropometric segment lengths); preferred
    walking speed ``N(1.39, 0.15)`` m/s clipped to [1.0, 1.8] (comfortable gait speed of adults aged
    20-49, Bohannon 1997).
Step length and cadence vs height and speed: dynamic similarity (Alexander 1976, 1984)
    Relative stride length ``lambda / l = 2.3 (v^2 / (g l))^0.3`` with ``l`` the leg length and the
    stride two steps: a walker's natural step is ``L = lambda / 2`` at the preferred speed ``v`` and
    the cadence ``f = v / L``. A walk with an imposed step length (the thesis's 40-80 cm walks,
    L399) takes the speed the same relation gives for that length, ``f = v(L) / L``.
Step-to-step variability
    Step length ``N(L, cv_length L)``, ``cv_length = 0.03``, and step time ``N(1/f, cv_time / f)``,
    ``cv_time = 0.025`` (healthy young adults: stride-time CV 1.5-2.5 %, stride-length CV 2-3 %;
    Hausdorff 2005; Beauchet et al. 2009); on imposed lengths ``N(target, 0.02 m)`` (stepping on
    floor marks: an assumption).
Worlds
    ``world="measured"`` (default of :func:`gait_config`, :func:`make_walkers` and
    :func:`simulate_walk`): step-time CV, per-step amplitude scatter, per-walker hand gain and phone
    misalignment are rows of data/measured_parameters.csv (:data:`MEASURED_ROWS`, measured on the
    Oxford InHand walks and the ILC 2.0 site1 walks); the published models below stay the mean.
    Where a copied value does not come back when measured on the simulated walks, the measured world
    takes its inverse calibration (:data:`CALIBRATED`, data/calibrated_parameters.csv): step time CV,
    a per-cycle timing jitter ``strike_jitter_rel`` (heel strikes jitter about the cadence without
    accumulating: the phone's step-period CV is about twice its stride CV on the Oxford walks), the
    amplitude scatter, the magnetic disturbance sd and a slow yaw wander of the hand
    (``yaw_wander_sd_deg``, first-order low-pass at ``yaw_wander_bw_hz = 0.1`` Hz, an assumption).
    ``world="copied"`` is the uncalibrated variant (no jitter, no wander).
    ``world="assumed"`` is the earlier world: amplitude an exact function of step length and
    cadence, step time CV 2.5 %, misalignment 5 deg (an assumption).
Vertical acceleration vs speed: inverted pendulum (Zijlstra & Hof 2003)
    The centre of mass rises and falls by ``h = l - sqrt(l^2 - (L / (2 K))^2)`` per step, with
    Zijlstra & Hof's correction ``K = 1.25`` (the pendulum estimate of step length is ``L / K``);
    over a step of frequency ``f`` the vertical acceleration is
    ``a_up = B [cos(2 pi phi) + h2 cos(4 pi phi + psi2)]`` with ``B = (2 pi f)^2 h / 2`` (a
    sinusoidal excursion of peak-to-peak ``h``), so the amplitude grows with step length and
    cadence, i.e. with speed. The phone held in front follows the trunk's vertical motion (gain 1,
    an assumption). The second harmonic (``h2 ~ U(0.2, 0.5)``, ``psi2 ~ U(-1, 1)`` rad per walker)
    gives the wave its asymmetry (T1 != T2): a waveform assumption, not a measured value.
Horizontal acceleration
    Fore-aft ``0.55 B_k sin(2 pi phi + 0.4)`` and lateral sway at the stride frequency
    ``0.5 sin(pi (k + phi))`` m/s^2, rotated by the walking direction.
Phone attitude
    Held in front, screen up, y axis pointing ``misalign`` from the walking direction, with a
    per-walker ``misalign ~ N(0, misalign_sd_deg = 5)`` deg (how straight a user holds the phone:
    an assumption; switched off in the WDM sensitivity of notebook 05), pitched up by ``N(25, 5)``
    deg per walker; smooth attitude jitter (roll, pitch, yaw; white noise low-passed to about 1 Hz) with standard
    deviations 3.5, 3.5, 4 deg: the tilt leaks gravity into the horizontal axes, which is what the
    feature I (0.6-1.8 m/s^2 in Table 1) mostly measures for a handheld phone.
Accelerometer
    Specific force ``R_nb^T (a_n + g e_up)`` + white noise 0.06 m/s^2 (a consumer MEMS part at the
    rates used here).
Gyroscope
    Body rate from successive attitudes + constant bias ``N(0, 0.01)`` rad/s per axis + white noise
    0.005 rad/s.
Magnetometer
    Earth field at the thesis's site (NCTU, Hsinchu, 24.79 N 121.00 E, 2013; World Magnetic Model
    2010, Maus et al. 2010): horizontal 36 microtesla, vertical 27 microtesla down, declination
    ``declination_deg = -4.5`` deg (magnetic north west of true north; map y = true north)
    + a per-walker hard-iron residual ``N(0, hard_iron_sd_ut = 2)`` microtesla per axis in the phone
    frame (what remains after a phone's automatic calibration; an assumption, switched off in notebook 05)
    + indoor disturbances: ``n_disturbances`` Gaussian blobs per 100 m^2 of floor, each a random
    vector of ``N(0, 12)`` microtesla per axis with width ``U(1, 3)`` m (steel and electrical
    installations; the thesis notes the field "may deviate slightly" indoors)
    + white noise 0.4 microtesla.
Sample rate
    ``rate_hz = 50`` by default (Android's SENSOR_DELAY_GAME). The thesis does not report its
    phone's rate; X1 (eq. 15) is a sum over ``2N + 1 = 2 floor(0.25 f) - 1`` samples, so its range
    scales with the rate: 50 Hz is an assumption, swept in notebook 03. Other rates are a parameter.

Ground truth
    Per step: heel-strike time ``t_strike_s``, the time of the vertical-acceleration trough
    (mid-step, where SAM's a_perp peaks) ``t_mid_s``, length ``length_m``, direction
    ``theta_rad`` (from the map x axis, counter-clockwise) and the position at its end
    ``x_m, y_m``; per sample: true position and heading.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1-4.4. Alexander R. McN., "Estimates of speeds of
dinosaurs", Nature 261, 1976, and "The gaits of bipedal and quadrupedal animals", Int. J. Robotics
Research 3(2), 1984. Zijlstra W., Hof A. L., "Assessment of spatio-temporal gait parameters from
trunk accelerations during human walking", Gait & Posture 18(2), 2003. Bohannon R. W., "Comfortable
and maximum walking speed of adults aged 20-79 years", Age and Ageing 26, 1997. Winter D. A.,
Biomechanics and Motor Control of Human Movement, 4th ed., 2009. Hausdorff J. M., "Gait
variability: methods, modeling and meaning", J. NeuroEng. Rehabil. 2:19, 2005. Beauchet O. et al.,
"Gait variability among healthy adults: low and high stride-to-stride variability are both a
reflection of gait stability", Gerontology 55, 2009. Maus S. et al., "The US/UK World Magnetic
Model for 2010-2015", NOAA technical report, 2010.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.io.schema import ACC_COLS, GYR_COLS, MAG_COLS, T_S
from ilocalg.units import G0_MPS2, as_rng

__all__ = [
    "Walker",
    "GaitConfig",
    "gait_config",
    "world_reading",
    "WORLDS",
    "MEASURED_ROWS",
    "MEASURED_SOURCES",
    "SimWalk",
    "make_walkers",
    "simulate_walk",
    "loop_route",
    "straight_route",
    "magnetic_disturbances",
    "alexander_step",
    "pendulum_amplitude_mps2",
    "LENGTHS_M",
    "training_walks",
    "count_walks",
    "fixed_length_features",
    "times_at_arc_s",
    "pass_times_s",
]

#: The fixed step lengths of the i-Loc thesis's training walks (sec. 4.1-4.2: 40-80 cm), m.
LENGTHS_M = (0.4, 0.5, 0.6, 0.7, 0.8)
#: A SAM wave belongs to a true step when its peak lies within this time of the step's mid-point, s.
MATCH_TOL_S = 0.15


@dataclass(frozen=True)
class Walker:
    """One simulated pedestrian (see the module docstring for the distributions)."""

    name: str
    height_m: float
    leg_m: float
    step_length_m: float
    cadence_hz: float
    gain: float
    h2: float
    psi2_rad: float
    pitch_rad: float
    speed_mps: float = 1.39
    misalign_rad: float = 0.0
    hard_iron_ut: tuple = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class GaitConfig:
    """Sensor and motion parameters of the simulator (module docstring gives their sources)."""

    rate_hz: float = 50.0
    length_sd_rel: float = 0.03
    fixed_length_sd_m: float = 0.02
    step_time_sd_rel: float = 0.025
    pendulum_k: float = 1.25
    hand_gain: float = 1.0
    fore_aft_rel: float = 0.55
    sway_mps2: float = 0.5
    jitter_deg: tuple = (3.5, 3.5, 4.0)
    jitter_bw_hz: float = 1.0
    acc_noise_mps2: float = 0.06
    gyr_bias_sd_radps: float = 0.01
    gyr_noise_radps: float = 0.005
    mag_horizontal_ut: float = 36.0
    mag_down_ut: float = 27.0
    declination_deg: float = -4.5
    mag_noise_ut: float = 0.4
    n_disturbances_per_100m2: float = 1.5
    disturbance_sd_ut: float = 12.0
    disturbance_width_m: tuple = (1.0, 3.0)
    stand_s: float = 1.0
    amp_sd_rel: float = 0.0
    strike_jitter_rel: float = 0.0
    yaw_wander_sd_deg: float = 0.0
    yaw_wander_bw_hz: float = 0.1
    world: str = "assumed"

    @property
    def mag_earth_ut(self) -> tuple:
        """Earth field (east, north, up) in the map frame (y = true north), microtesla."""
        d = np.deg2rad(self.declination_deg)
        return (self.mag_horizontal_ut * np.sin(d), self.mag_horizontal_ut * np.cos(d), -self.mag_down_ut)


#: Walker population (published gait measurements; see the module docstring).
HEIGHT_RANGE_M = (1.55, 1.90)
LEG_PER_HEIGHT = 0.530  # Winter 2009: greater trochanter height / body height
SPEED_MPS = (1.39, 0.15, 1.0, 1.8)  # Bohannon 1997: mean, sd, clip low, clip high
ALEXANDER_C, ALEXANDER_EXP = 2.3, 0.3  # Alexander 1976, 1984: lambda / l = 2.3 Fr^0.3
MISALIGN_SD_DEG = 5.0  # assumption (switched off in the WDM sensitivity table)
HARD_IRON_SD_UT = 2.0  # assumption (switched off in the WDM sensitivity table)

#: The simulated worlds: "measured" (defaults from data/measured_parameters.csv, inverse-calibrated
#: where a copied value does not come back: data/calibrated_parameters.csv), "copied" (the measured values
#: copied, uncalibrated: the world of issue 24) and "assumed" (the published-value world used before the
#: table existed, kept for comparison).
WORLDS = ("measured", "copied", "assumed")

#: Calibrated world: GaitConfig fields set by the inverse calibration (:mod:`ilocalg.measure.calibrate`);
#: ``strike_jitter_rel`` and ``yaw_wander_sd_deg`` are 0 in the other worlds.
CALIBRATED = ("step_time_sd_rel", "strike_jitter_rel", "amp_sd_rel", "disturbance_sd_ut", "yaw_wander_sd_deg")

#: Measured world: GaitConfig field / walker spread -> row of data/measured_parameters.csv.
MEASURED_ROWS = {
    "step_time_sd_rel": "gait_stride_period_cv",
    "amp_sd_rel": "gait_step_amp_cv",
    "walker_gain_sd_rel": "gait_A_resid_rel",
    "misalign_sd_deg": "heading_mis_rv_walk_sd_deg",
}

#: Where each measured-world default comes from (readings tables quote these).
MEASURED_SOURCES = {
    "step_time_sd_rel": "within-walk robust CV of the two-step stride period (phone peak to peak) of the 16 Oxford "
                        "InHand walks (heel-sensor contacts quantised at ~48 ms, so the phone's peaks time it); "
                        "replaces Hausdorff 2005's 2.5 %",
    "amp_sd_rel": "within-walk robust CV of the per-step peak-to-trough amplitude (3 Hz low-passed norm), Oxford "
                  "InHand walks: each step's amplitude is the pendulum value times (1 + amp_sd_rel N(0, 1)), "
                  "independent of its length",
    "walker_gain_sd_rel": "residual sd of segment amplitude at equal step length and speed across ILC site1 walks "
                          "(A ~ 1 + SL + speed): each walker's (hand) gain is 1 + walker_gain_sd_rel N(0, 1)",
    "misalign_sd_deg": "sd over ILC site1 walks of the walk's mean rotation-vector heading minus walking direction "
                       "(each floor's median removed)",
}


def _measured(name: str) -> float:
    from ilocalg.sim.measured import param

    return param(MEASURED_ROWS[name])


def _check_world(world: str) -> None:
    if world not in WORLDS:
        raise ValueError(f"unknown world {world!r}; known: {list(WORLDS)}")


def world_reading(world: str = "measured") -> tuple[str, str]:
    """``(what the world does, where its values come from)`` for a readings table row."""
    _check_world(world)
    if world == "assumed":
        return ("assumed world: step time CV 2.5 %, amplitude an exact function of step length and cadence, "
                "hand gain 1, misalignment N(0, 5 deg)", "Hausdorff 2005; Zijlstra & Hof 2003; assumption")
    from ilocalg.sim.measured import calibrated_cite, cite

    v = {k: _measured(k) for k in MEASURED_ROWS}
    if world == "copied":
        what = (f"copied world (uncalibrated): step time CV {v['step_time_sd_rel']:.3g}, per-step amplitude CV "
                f"{v['amp_sd_rel']:.3g} independent of length, hand gain sd {v['walker_gain_sd_rel']:.3g}, "
                f"misalignment sd {v['misalign_sd_deg']:.3g} deg; Alexander/Zijlstra-Hof models stay the mean")
        return what, "; ".join(cite(r) for r in MEASURED_ROWS.values())
    c = gait_config("measured")
    what = (f"measured world, calibrated: step time CV {c.step_time_sd_rel:.3g}, step timing jitter "
            f"{c.strike_jitter_rel:.3g}, per-step amplitude CV {c.amp_sd_rel:.3g} independent of length, magnetic "
            f"disturbance sd {c.disturbance_sd_ut:.3g} uT, yaw wander sd {c.yaw_wander_sd_deg:.3g} deg; hand gain sd "
            f"{v['walker_gain_sd_rel']:.3g}, misalignment sd {v['misalign_sd_deg']:.3g} deg (measured); "
            "Alexander/Zijlstra-Hof models stay the mean")
    return what, "; ".join([cite(MEASURED_ROWS[k]) for k in ("walker_gain_sd_rel", "misalign_sd_deg")]
                           + [calibrated_cite(f"gait.{k}") for k in CALIBRATED])


def gait_config(world: str = "measured", **overrides) -> GaitConfig:
    """The simulator's configuration of a world, with ``overrides`` (any :class:`GaitConfig` field).

    ``world="copied"`` takes ``step_time_sd_rel`` and ``amp_sd_rel`` from
    data/measured_parameters.csv (:data:`MEASURED_ROWS`, :data:`MEASURED_SOURCES`);
    ``world="measured"`` (default) replaces the fields of :data:`CALIBRATED` by their inverse
    calibration (data/calibrated_parameters.csv); ``"assumed"`` is the published-value world (step time
    CV 2.5 %, amplitude a deterministic function of step length and cadence).
    """
    _check_world(world)
    base = {"world": world}
    if world in ("measured", "copied"):
        base.update(step_time_sd_rel=_measured("step_time_sd_rel"), amp_sd_rel=_measured("amp_sd_rel"))
    if world == "measured":
        from ilocalg.sim.measured import calibrated

        base.update({k: calibrated(f"gait.{k}") for k in CALIBRATED})
    base.update(overrides)
    return GaitConfig(**base)


def alexander_step(leg_m, speed_mps=None, step_length_m=None):
    """Step length and cadence from dynamic similarity (Alexander 1976, 1984).

    ``stride / leg = 2.3 (v^2 / (g leg))^0.3``, step = stride / 2, cadence = v / step. Give the speed
    (natural walking) or the step length (imposed length; the speed follows from the relation).

    Returns
    -------
    step_length_m, cadence_hz, speed_mps : ndarray
    """
    leg = np.asarray(leg_m, dtype=np.float64)
    if (speed_mps is None) == (step_length_m is None):
        raise ValueError("give exactly one of speed_mps and step_length_m")
    if speed_mps is not None:
        v = np.asarray(speed_mps, dtype=np.float64)
        fr = v**2 / (G0_MPS2 * leg)
        L = 0.5 * ALEXANDER_C * fr**ALEXANDER_EXP * leg
    else:
        L = np.asarray(step_length_m, dtype=np.float64)
        fr = (2.0 * L / (ALEXANDER_C * leg)) ** (1.0 / ALEXANDER_EXP)
        v = np.sqrt(fr * G0_MPS2 * leg)
    return L, v / L, v


def pendulum_amplitude_mps2(step_length_m, cadence_hz, leg_m, k: float = 1.25):
    """Vertical-acceleration amplitude of the centre of mass (Zijlstra & Hof 2003 inverted pendulum).

    ``h = l - sqrt(l^2 - (L / (2 k))^2)`` (rise and fall per step), ``B = (2 pi f)^2 h / 2``, m/s^2.
    """
    L = np.asarray(step_length_m, dtype=np.float64) / k
    leg = np.asarray(leg_m, dtype=np.float64)
    h = leg - np.sqrt(np.maximum(leg**2 - 0.25 * L**2, 0.0))
    return (2.0 * np.pi * np.asarray(cadence_hz, dtype=np.float64)) ** 2 * 0.5 * h


@dataclass(frozen=True)
class SimWalk:
    """A simulated walk: the IMU log, the per-step truth and the per-sample truth."""

    imu: pd.DataFrame
    steps: pd.DataFrame
    truth: pd.DataFrame
    walker: Walker
    config: GaitConfig = field(repr=False)


def make_walkers(n: int, rng=None, misalign_sd_deg: float | None = None,
                 hard_iron_sd_ut: float = HARD_IRON_SD_UT, world: str = "measured") -> list[Walker]:
    """``n`` walkers of different builds (module docstring: distributions and sources).

    ``misalign_sd_deg`` (phone y axis vs walking direction; default: the world's value, measured
    or :data:`MISALIGN_SD_DEG`) and ``hard_iron_sd_ut`` (magnetometer hard-iron residual per axis)
    are per-walker spreads; 0 turns them off. In the measured world each walker also gets a hand
    gain ``1 + walker_gain_sd_rel N(0, 1)`` (clipped to >= 0.3; :data:`MEASURED_SOURCES`), drawn
    after the walker's other values so the assumed world's draws are unchanged.
    """
    _check_world(world)
    if misalign_sd_deg is None:
        misalign_sd_deg = MISALIGN_SD_DEG if world == "assumed" else _measured("misalign_sd_deg")
    gain_sd = 0.0 if world == "assumed" else _measured("walker_gain_sd_rel")
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    if not (misalign_sd_deg >= 0 and hard_iron_sd_ut >= 0):
        raise ValueError("misalign_sd_deg and hard_iron_sd_ut must be >= 0")
    r = as_rng(rng)
    out = []
    mu, sd, lo, hi = SPEED_MPS
    for i in range(n):
        h = r.uniform(*HEIGHT_RANGE_M)
        leg = LEG_PER_HEIGHT * h
        v = float(np.clip(r.normal(mu, sd), lo, hi))
        L, f, _ = alexander_step(leg, speed_mps=v)
        h2, psi2 = r.uniform(0.2, 0.5), r.uniform(-1.0, 1.0)
        pitch = np.deg2rad(r.normal(25.0, 5.0))
        mis = np.deg2rad(r.normal(0.0, misalign_sd_deg))
        hi_ut = tuple(float(x) for x in r.normal(0.0, hard_iron_sd_ut, 3))
        gain = max(1.0 + gain_sd * r.normal(), 0.3) if gain_sd > 0 else 1.0
        out.append(Walker(
            name=f"walker{i}", height_m=float(h), leg_m=float(leg), step_length_m=float(L),
            cadence_hz=float(f), gain=float(gain), h2=float(h2), psi2_rad=float(psi2), pitch_rad=float(pitch),
            speed_mps=v, misalign_rad=float(mis), hard_iron_ut=hi_ut,
        ))
    return out


def straight_route(length_m: float, theta_rad: float = 0.0) -> np.ndarray:
    """Two waypoints: a straight walk of ``length_m`` from the origin, shape (2, 2)."""
    return np.array([[0.0, 0.0], [length_m * np.cos(theta_rad), length_m * np.sin(theta_rad)]])


def loop_route(n_points: int = 28, spacing_m: float = 4.11, nx: int = 9) -> np.ndarray:  # thesis sec. 4.4
    """A closed rectangular loop of ``n_points`` test points ``spacing_m`` apart, shape (n_points + 1, 2).

    ``nx`` segments along x and ``n_points / 2 - nx`` along y (the i-Loc thesis's test loop: 28
    points 4.11 m apart, thesis sec. 4.4). The last row repeats the first point.
    """
    ny = n_points // 2 - nx
    if n_points % 2 or ny < 1:
        raise ValueError(f"n_points must be even and > 2 nx, got {n_points}, nx={nx}")
    pts = [(i, 0) for i in range(nx)] + [(nx, j) for j in range(ny)] + \
          [(nx - i, ny) for i in range(nx)] + [(0, ny - j) for j in range(ny)] + [(0, 0)]
    return np.asarray(pts, dtype=np.float64) * spacing_m


def magnetic_disturbances(extent_m, cfg: GaitConfig, rng) -> dict:
    """Random disturbance blobs over a rectangle ``extent_m = (xmin, xmax, ymin, ymax)``."""
    r = as_rng(rng)
    x0, x1, y0, y1 = extent_m
    area = max((x1 - x0) * (y1 - y0), 1.0)
    n = max(int(round(cfg.n_disturbances_per_100m2 * area / 100.0)), 1)
    return {
        "centre_m": np.column_stack([r.uniform(x0, x1, n), r.uniform(y0, y1, n)]),
        "vec_ut": r.normal(0.0, cfg.disturbance_sd_ut, (n, 3)),
        "width_m": r.uniform(*cfg.disturbance_width_m, n),
    }


def _mag_field_ut(xy_m: np.ndarray, cfg: GaitConfig, dist: dict) -> np.ndarray:
    d2 = ((xy_m[:, None, :] - dist["centre_m"][None, :, :]) ** 2).sum(-1)
    w = np.exp(-0.5 * d2 / dist["width_m"][None, :] ** 2)
    return np.asarray(cfg.mag_earth_ut)[None, :] + w @ dist["vec_ut"]


def _smooth_noise(r, n: int, rate_hz: float, bw_hz: float, sd: float) -> np.ndarray:
    """White noise through a first-order low-pass, scaled to standard deviation ``sd``."""
    a = np.exp(-2.0 * np.pi * bw_hz / rate_hz)
    e = r.normal(0.0, 1.0, n + 200)
    from scipy.signal import lfilter

    y = lfilter([1.0 - a], [1.0, -a], e)[200:]
    s = y.std()
    return y * (sd / s) if s > 0 else y


def _rot_z(a):
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def _rot_x(a):
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2)


def _rot_y(a):
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)


def _along(route: np.ndarray, s_m: np.ndarray):
    """Points and segment directions at arc lengths ``s_m`` along a polyline."""
    seg = np.diff(route, axis=0)
    seg_len = np.hypot(seg[:, 0], seg[:, 1])
    cum = np.concatenate([[0.0], np.cumsum(seg_len)])
    s = np.clip(s_m, 0.0, cum[-1])
    j = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, seg.shape[0] - 1)
    frac = (s - cum[j]) / seg_len[j]
    xy = route[j] + frac[:, None] * seg[j]
    return xy, np.arctan2(seg[j, 1], seg[j, 0])


def simulate_walk(route_xy_m, walker: Walker, rng=None, config: GaitConfig | None = None,
                  step_length_m: float | None = None, n_steps: int | None = None,
                  disturbances: dict | None = None) -> SimWalk:
    """Simulate a handheld phone's IMU while ``walker`` walks along a route.

    Parameters
    ----------
    route_xy_m : array_like, shape (k, 2)
        Polyline waypoints, m. The walk follows it from the first point; it stops at the end of
        the route or after ``n_steps`` steps, whichever comes first (``n_steps`` may exceed the
        route: the walker then stops at its end).
    walker : Walker
    rng : Generator, int or None
    config : GaitConfig, optional
        Default :func:`gait_config` (the measured world).
    step_length_m : float, optional
        Impose a step length (fixed-length walks); default the walker's natural length.
    n_steps : int, optional
        Number of steps; default enough to cover the route.
    disturbances : dict, optional
        Magnetic disturbance field (:func:`magnetic_disturbances`); default drawn over the route's
        bounding box (+5 m).

    Returns
    -------
    SimWalk
        ``imu`` indexed by ``t_s`` with accelerometer, gyroscope and magnetometer columns;
        ``steps`` (one row per step: ``t_strike_s, t_mid_s, length_m, theta_rad, x_m, y_m``);
        ``truth`` (per sample ``x_m, y_m, theta_rad``).
    """
    cfg = config or gait_config()
    r = as_rng(rng)
    route = np.asarray(route_xy_m, dtype=np.float64)
    if route.ndim != 2 or route.shape[1] != 2 or route.shape[0] < 2:
        raise ValueError(f"route_xy_m must have shape (k >= 2, 2), got {route.shape}")
    seg_len = np.hypot(*np.diff(route, axis=0).T)
    if np.any(seg_len <= 0):
        raise ValueError("route_xy_m has repeated consecutive waypoints")
    total = float(seg_len.sum())
    if step_length_m is not None and not step_length_m > 0:
        raise ValueError(f"step_length_m must be > 0, got {step_length_m}")
    if n_steps is not None and n_steps < 1:
        raise ValueError(f"n_steps must be >= 1, got {n_steps}")
    if disturbances is None:
        lo, hi = route.min(0) - 5.0, route.max(0) + 5.0
        disturbances = magnetic_disturbances((lo[0], hi[0], lo[1], hi[1]), cfg, r)

    # --- steps: lengths, cadences, amplitudes
    cap = n_steps if n_steps is not None else int(np.ceil(total / 0.2)) + 2
    if step_length_m is None:
        L = walker.step_length_m * (1.0 + cfg.length_sd_rel * r.normal(size=cap))
        f_mean = walker.cadence_hz
    else:
        L = step_length_m + cfg.fixed_length_sd_m * r.normal(size=cap)
        f_mean = float(alexander_step(walker.leg_m, step_length_m=step_length_m)[1])
    L = np.maximum(L, 0.15)
    cs = np.cumsum(L)
    if n_steps is None:
        k_end = int(np.searchsorted(cs, total - 0.5 * np.median(L)))
        L = L[: k_end + 1]
        L[-1] = max(total - (cs[k_end - 1] if k_end > 0 else 0.0), 0.15)
    else:
        over = cs > total
        if over.any():
            raise ValueError(f"{n_steps} steps of about {np.mean(L):.2f} m exceed the route ({total:.1f} m)")
    n = L.size
    dur = (1.0 + cfg.step_time_sd_rel * r.normal(size=n)) / f_mean
    if cfg.strike_jitter_rel > 0:  # calibrated world: each cycle's timing jitters about the cadence (not cumulative)
        e = np.concatenate([[0.0], r.normal(size=n)]) * (cfg.strike_jitter_rel / f_mean)
        dur = np.maximum(dur + np.diff(e), 0.3 / f_mean)
    f = 1.0 / dur
    B = cfg.hand_gain * walker.gain * pendulum_amplitude_mps2(L, f, walker.leg_m, cfg.pendulum_k)
    if cfg.amp_sd_rel > 0:  # measured world: step amplitude scatters independently of the step's length
        B = B * np.maximum(1.0 + cfg.amp_sd_rel * r.normal(size=n), 0.2)

    # --- time base
    rate = float(cfg.rate_hz)
    strike = cfg.stand_s + np.concatenate([[0.0], np.cumsum(dur)])   # n + 1 heel strikes
    t_end = strike[-1] + cfg.stand_s
    t = np.arange(int(np.floor(t_end * rate)) + 1) / rate
    k = np.clip(np.searchsorted(strike, t, side="right") - 1, 0, n - 1)
    walking = (t >= strike[0]) & (t < strike[-1])
    phi = np.where(walking, (t - strike[k]) / dur[k], 0.0)

    # --- motion in the map frame (east, north, up)
    s_prev = np.concatenate([[0.0], np.cumsum(L)])
    s_m = np.where(t < strike[0], 0.0, np.where(walking, s_prev[k] + phi * L[k], s_prev[-1]))
    xy, seg_theta = _along(route, s_m)
    step_start, _ = _along(route, s_prev[:-1])
    step_end, _ = _along(route, s_prev[1:])
    d = step_end - step_start
    theta_step = np.arctan2(d[:, 1], d[:, 0])
    # heading of the body: the current step's direction, smoothed over about a step through turns
    theta_cont = np.unwrap(theta_step)[k]
    theta_cont = np.where(t < strike[0], theta_cont[0] if theta_cont.size else 0.0, theta_cont)
    from scipy.ndimage import uniform_filter1d

    theta_body = uniform_filter1d(theta_cont, size=max(int(round(0.5 * rate)), 1), mode="nearest")
    a_up = np.where(walking, B[k] * (np.cos(2 * np.pi * phi) + walker.h2 * np.cos(4 * np.pi * phi + walker.psi2_rad)),
                    0.0)
    a_fwd = np.where(walking, cfg.fore_aft_rel * B[k] * np.sin(2 * np.pi * phi + 0.4), 0.0)
    a_lat = np.where(walking, cfg.sway_mps2 * np.sin(np.pi * (k + phi)), 0.0)
    c, s = np.cos(theta_body), np.sin(theta_body)
    a_n = np.column_stack([a_fwd * c - a_lat * s, a_fwd * s + a_lat * c, a_up])

    # --- attitude: R_nb = Rz(theta - pi/2 + jitter) Rx(pitch + jitter) Ry(roll jitter)
    jr, jp, jy = (np.deg2rad(v) for v in cfg.jitter_deg)
    m = t.size
    roll = _smooth_noise(r, m, rate, cfg.jitter_bw_hz, jr)
    pitch = walker.pitch_rad + _smooth_noise(r, m, rate, cfg.jitter_bw_hz, jp)
    yaw = theta_body - np.pi / 2 + walker.misalign_rad + _smooth_noise(r, m, rate, cfg.jitter_bw_hz, jy)
    if cfg.yaw_wander_sd_deg > 0:  # calibrated world: the hand's slow yaw wander within a walk
        yaw = yaw + _smooth_noise(r, m, rate, cfg.yaw_wander_bw_hz, np.deg2rad(cfg.yaw_wander_sd_deg))
    R = _rot_z(yaw) @ _rot_x(pitch) @ _rot_y(roll)

    f_n = a_n + np.array([0.0, 0.0, G0_MPS2])
    acc = np.einsum("nji,nj->ni", R, f_n) + r.normal(0.0, cfg.acc_noise_mps2, (m, 3))
    dR = np.einsum("nji,njk->nik", R[:-1], R[1:])           # R_k^T R_{k+1}
    w = 0.5 * np.column_stack([dR[:, 2, 1] - dR[:, 1, 2], dR[:, 0, 2] - dR[:, 2, 0], dR[:, 1, 0] - dR[:, 0, 1]])
    w = np.vstack([w, w[-1:]]) * rate
    gyr = w + r.normal(0.0, cfg.gyr_bias_sd_radps, 3)[None, :] + r.normal(0.0, cfg.gyr_noise_radps, (m, 3))
    mag_n = _mag_field_ut(xy, cfg, disturbances)
    mag = (np.einsum("nji,nj->ni", R, mag_n) + np.asarray(walker.hard_iron_ut)[None, :]
           + r.normal(0.0, cfg.mag_noise_ut, (m, 3)))

    imu = pd.DataFrame(np.column_stack([acc, gyr, mag]), columns=list(ACC_COLS + GYR_COLS + MAG_COLS),
                       index=pd.Index(t, name=T_S))
    # the trough of a_up (peak of SAM's a_perp) within each step
    fine = np.linspace(0.0, 1.0, 401)[:-1]
    shape = np.cos(2 * np.pi * fine) + walker.h2 * np.cos(4 * np.pi * fine + walker.psi2_rad)
    phi_mid = fine[np.argmin(shape)]
    steps = pd.DataFrame({
        "t_strike_s": strike[:-1], "t_mid_s": strike[:-1] + phi_mid * dur, "duration_s": dur, "length_m": L,
        "theta_rad": theta_step, "x_m": step_end[:, 0], "y_m": step_end[:, 1], "amp_mps2": B,
    }, index=pd.RangeIndex(n, name="step"))
    truth = pd.DataFrame({"x_m": xy[:, 0], "y_m": xy[:, 1], "theta_rad": theta_body, "walking": walking},
                         index=pd.Index(t, name=T_S))
    return SimWalk(imu=imu, steps=steps, truth=truth, walker=walker, config=cfg)


def training_walks(walkers, rng, lengths_m=LENGTHS_M, n_steps: int = 15, config=None):
    """Fixed-length walks: every walker x every length, ``n_steps`` steps each.

    Returns
    -------
    list of (Walker, float, SimWalk)
        ``(walker, imposed step length m, walk)``, walkers outer, lengths inner.
    """
    out = []
    for w in walkers:
        for L in lengths_m:
            sw = simulate_walk(straight_route(max(2.0 * L * n_steps, 5.0)), w, rng, config,
                               step_length_m=L, n_steps=n_steps)
            out.append((w, L, sw))
    return out


def count_walks(walkers, rng, n_steps: int = 100, config=None) -> list[SimWalk]:
    """Each walker walks ``n_steps`` natural steps along a straight corridor."""
    return [simulate_walk(straight_route(1.2 * n_steps), w, rng, config, n_steps=n_steps) for w in walkers]


def fixed_length_features(walks, tol_s: float = MATCH_TOL_S) -> pd.DataFrame:
    """SAM features of the true steps of fixed-length walks (the thesis's training set).

    Each true step is matched to the SAM wave nearest its mid-point (within ``tol_s``,
    :func:`ilocalg.pdr.sam.match_waves_to_steps`) and labelled with the walk's ``walker`` name,
    the imposed ``target_m`` and the step's true ``length_m``.

    Parameters
    ----------
    walks : list of (Walker, float, SimWalk)
        From :func:`training_walks`.
    """
    from ilocalg.pdr.sam import match_waves_to_steps, sam_waves
    from ilocalg.pdr.signals import acc_from_log

    rows = []
    for w, L, sw in walks:
        acc, t = acc_from_log(sw.imu)
        waves = sam_waves(acc, t)
        m = match_waves_to_steps(waves, sw.steps["t_mid_s"], tol_s)
        # the true length of the step each wave belongs to
        j = np.abs(sw.steps["t_mid_s"].to_numpy()[None, :] - m["t_s"].to_numpy()[:, None]).argmin(axis=1)
        rows.append(m.assign(walker=w.name, target_m=L, length_m=sw.steps["length_m"].to_numpy()[j]))
    return pd.concat(rows, ignore_index=True)


def times_at_arc_s(sw: SimWalk, s_m) -> np.ndarray:
    """Time at which a simulated walk has covered the arc lengths ``s_m`` (m) along its true steps, s."""
    st = sw.steps
    ends = np.concatenate([[0.0], np.cumsum(st["length_m"].to_numpy())])
    t_ends = np.concatenate([[st["t_strike_s"].iloc[0]], (st["t_strike_s"] + st["duration_s"]).to_numpy()])
    return np.interp(s_m, ends, t_ends)


def pass_times_s(sw: SimWalk, route_xy_m) -> np.ndarray:
    """Time at which a simulated walk passes each vertex of its route (by arc length), s."""
    route = np.asarray(route_xy_m, dtype=np.float64)
    seg = np.hypot(*np.diff(route, axis=0).T)
    return times_at_arc_s(sw, np.concatenate([[0.0], np.cumsum(seg)]))
