"""Gait + phone simulator: handheld smartphone IMU logs of pedestrians walking a route, with ground truth.

Deterministic from a seed: the same ``rng`` seed gives identical arrays.

Model
-----
Walkers
    Builds drawn per walker: height ``U(1.55, 1.90)`` m; leg length ``0.53 height`` and natural step
    length ``0.415 height`` (anthropometric rules of thumb); natural cadence ``N(2.05, 0.15)``
    steps/s (the i-Loc thesis sec. 4.1 assumes about two steps per second); a handheld gain
    ``lognormal(0, 0.25)`` (how much of the body's bounce reaches the hand) and a waveform shape
    (second-harmonic weight ``U(0.2, 0.5)`` and phase ``U(-1, 1)`` rad) that sets the
    asymmetry T1 / T2 of the wave.
Steps
    Step length: the walker's natural length (``length_sd_rel = 0.06`` relative spread) or an
    imposed length (``N(target, 0.02 m)``, the thesis's fixed-length walks of 40-80 cm).
    Cadence ``f = f_walker (L / L_walker)^0.3 (1 + 0.04 N(0,1))``: longer steps are taken faster.
Vertical acceleration (up)
    Within step k (phase ``phi`` from heel strike 0 to the next heel strike 1)
    ``a_up = B_k [cos(2 pi phi) + h2 cos(4 pi phi + psi2)]`` with
    ``B_k = b0 gain (L_k / 0.6 m)^0.7 (f_k / 2 Hz) lognormal(0, 0.3)``, ``b0 = 2.3 m/s^2``.
    b0, the exponents and the spreads are calibrated so that the SAM features of the raw signal
    (A, A1, A2, T, T1, T2 at the chosen rate) spread over the ranges of the thesis's Table 1 for
    40-80 cm steps; they are not tuned to any outcome (step counts, lengths, positions).
Horizontal acceleration
    Fore-aft ``0.55 B_k sin(2 pi phi + 0.4)`` and lateral sway at the stride frequency
    ``0.5 sin(pi (k + phi))`` m/s^2, rotated by the walking direction.
Phone attitude
    Held in front, screen up, y axis forward, pitched up by ``N(25, 5)`` deg per walker; smooth
    attitude jitter (roll, pitch, yaw; white noise low-passed to about 1 Hz) with standard
    deviations 3.5, 3.5, 4 deg: the tilt leaks gravity into the horizontal axes, which is what the
    feature I (0.6-1.8 m/s^2 in Table 1) mostly measures for a handheld phone.
Accelerometer
    Specific force ``R_nb^T (a_n + g e_up)`` + white noise 0.06 m/s^2 (a consumer MEMS part at the
    rates used here).
Gyroscope
    Body rate from successive attitudes + constant bias ``N(0, 0.01)`` rad/s per axis + white noise
    0.005 rad/s.
Magnetometer
    Earth field (east, north, up) = (0, 33, -35) microtesla (mid-latitude, declination taken as 0)
    + indoor disturbances: ``n_disturbances`` Gaussian blobs per 100 m^2 of floor, each a random
    vector of ``N(0, 12)`` microtesla per axis with width ``U(1, 3)`` m (steel and electrical
    installations; the thesis notes the field "may deviate slightly" indoors)
    + white noise 0.4 microtesla.
Sample rate
    ``rate_hz = 50`` by default (Android's SENSOR_DELAY_GAME). The thesis does not report its
    phone's rate; X1 (eq. 15) is a sum over ``2N + 1 = 2 floor(0.25 f) - 1`` samples, so its range
    scales with the rate: at 50 Hz the upper end of the X1 range of 40-80 cm steps is near Table 1's
    (its lower end is not: see data/gait/README.md). Other rates are a parameter.

Ground truth
    Per step: heel-strike time ``t_strike_s``, the time of the vertical-acceleration trough
    (mid-step, where SAM's a_perp peaks) ``t_mid_s``, length ``length_m``, direction
    ``theta_rad`` (from the map x axis, counter-clockwise) and the position at its end
    ``x_m, y_m``; per sample: true position and heading.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1-4.4, Table 1 (feature ranges of the raw signals), Figs 7-18.
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Sec. 3.4.1 (the bounce of the centre of mass during a step).
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
    "SimWalk",
    "make_walkers",
    "simulate_walk",
    "loop_route",
    "straight_route",
    "magnetic_disturbances",
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


@dataclass(frozen=True)
class GaitConfig:
    """Sensor and motion parameters of the simulator (module docstring gives their sources)."""

    rate_hz: float = 50.0
    b0_mps2: float = 2.3
    amp_sd_log: float = 0.3
    length_sd_rel: float = 0.06
    fixed_length_sd_m: float = 0.02
    cadence_sd_rel: float = 0.04
    fore_aft_rel: float = 0.55
    sway_mps2: float = 0.5
    jitter_deg: tuple = (3.5, 3.5, 4.0)
    jitter_bw_hz: float = 1.0
    acc_noise_mps2: float = 0.06
    gyr_bias_sd_radps: float = 0.01
    gyr_noise_radps: float = 0.005
    mag_earth_ut: tuple = (0.0, 33.0, -35.0)
    mag_noise_ut: float = 0.4
    n_disturbances_per_100m2: float = 1.5
    disturbance_sd_ut: float = 12.0
    disturbance_width_m: tuple = (1.0, 3.0)
    stand_s: float = 1.0


@dataclass(frozen=True)
class SimWalk:
    """A simulated walk: the IMU log, the per-step truth and the per-sample truth."""

    imu: pd.DataFrame
    steps: pd.DataFrame
    truth: pd.DataFrame
    walker: Walker
    config: GaitConfig = field(repr=False)


def make_walkers(n: int, rng=None) -> list[Walker]:
    """``n`` walkers of different builds (module docstring: distributions and sources)."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    r = as_rng(rng)
    out = []
    for i in range(n):
        h = r.uniform(1.55, 1.90)
        out.append(Walker(
            name=f"walker{i}", height_m=float(h), leg_m=float(0.53 * h), step_length_m=float(0.415 * h),
            cadence_hz=float(r.normal(2.05, 0.15)), gain=float(np.exp(r.normal(0.0, 0.25))),
            h2=float(r.uniform(0.2, 0.5)), psi2_rad=float(r.uniform(-1.0, 1.0)),
            pitch_rad=float(np.deg2rad(r.normal(25.0, 5.0))),
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
    cfg = config or GaitConfig()
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
    else:
        L = step_length_m + cfg.fixed_length_sd_m * r.normal(size=cap)
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
    f = walker.cadence_hz * (L / walker.step_length_m) ** 0.3 * (1.0 + cfg.cadence_sd_rel * r.normal(size=n))
    dur = 1.0 / f
    B = cfg.b0_mps2 * walker.gain * (L / 0.6) ** 0.7 * (f / 2.0) * np.exp(cfg.amp_sd_log * r.normal(size=n))

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
    yaw = theta_body - np.pi / 2 + _smooth_noise(r, m, rate, cfg.jitter_bw_hz, jy)
    R = _rot_z(yaw) @ _rot_x(pitch) @ _rot_y(roll)

    f_n = a_n + np.array([0.0, 0.0, G0_MPS2])
    acc = np.einsum("nji,nj->ni", R, f_n) + r.normal(0.0, cfg.acc_noise_mps2, (m, 3))
    dR = np.einsum("nji,njk->nik", R[:-1], R[1:])           # R_k^T R_{k+1}
    w = 0.5 * np.column_stack([dR[:, 2, 1] - dR[:, 1, 2], dR[:, 0, 2] - dR[:, 2, 0], dR[:, 1, 0] - dR[:, 0, 1]])
    w = np.vstack([w, w[-1:]]) * rate
    gyr = w + r.normal(0.0, cfg.gyr_bias_sd_radps, 3)[None, :] + r.normal(0.0, cfg.gyr_noise_radps, (m, 3))
    mag_n = _mag_field_ut(xy, cfg, disturbances)
    mag = np.einsum("nji,nj->ni", R, mag_n) + r.normal(0.0, cfg.mag_noise_ut, (m, 3))

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
