"""Motion of a walk: steps, heading and what the other walks teach (step length factor, floor heading offset)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.fusion.heading_offset import circular_mean_rad, fit_track_to_fixes
from ilocalg.io.schema import ACC_COLS, GYR_COLS, MAG_COLS, T_S, X_M, Y_M
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import gyr_heading_theta_rad, heading_theta_rad
from ilocalg.pdr.robust import detect_steps_robust
from ilocalg.pdr.signals import moving_mean
from ilocalg.pdr.step_length import weinberg_length_m
from ilocalg.track._config import DEFAULT_CONFIG, RealWalkConfig
from ilocalg.units import wrap_angle_rad


@dataclass(frozen=True)
class WalkSteps:
    """Steps of one walk: ``state_t_s`` (n+1: the log start, then each step), ``a_range_mps2`` (n, the
    Weinberg input), ``theta_rel_rad`` (n, compass-aligned gyro heading, map convention, before the floor
    offset)."""

    state_t_s: np.ndarray
    a_range_mps2: np.ndarray
    theta_rel_rad: np.ndarray


def _n_samples(duration_s: float, rate_hz: float) -> int:
    """Samples in a window: ``floor(duration * rate)`` (at least 1), immune to the rounding of the rate
    estimated from timestamps (a 50 Hz log stored as Unix milliseconds gives 49.99999 or 50.00005 Hz)."""
    return max(int(duration_s * rate_hz + 1e-3), 1)


def walk_steps(trace, cfg: RealWalkConfig = DEFAULT_CONFIG) -> WalkSteps:
    """Detect the steps of a walk and their heading (gyro shape, compass mean); uses no waypoint.

    Gravity is the 1 s moving mean of the accelerometer, the magnetic field the 0.5 s one
    (:func:`ilocalg.pdr.signals.moving_mean`).

    References
    ----------
    Chiu (2013), eq. 18-19 (WDM heading from gravity and the magnetic field).
    """
    imu = trace.imu
    if len(imu) < 50:
        raise ValueError(f"{trace.name}: too few IMU samples ({len(imu)})")
    t = imu.index.to_numpy()
    acc = imu[list(ACC_COLS)].to_numpy()
    rate = 1.0 / float(np.median(np.diff(t)))
    st = detect_steps_robust(acc, t, min_bout_steps=cfg.min_bout_steps, min_stride_nac=cfg.min_stride_nac)
    g = np.column_stack([moving_mean(acc[:, j], _n_samples(0.5, rate)) for j in range(3)])
    m = np.column_stack([moving_mean(imu[list(MAG_COLS)].to_numpy()[:, j], _n_samples(0.25, rate))
                         for j in range(3)])
    wdm = heading_theta_rad(g, m)
    gyro = gyr_heading_theta_rad(imu[list(GYR_COLS)].to_numpy(), g, t, 0.0)
    th = wrap_angle_rad(gyro + circular_mean_rad(wdm - gyro))
    i = st["i_peak"].to_numpy()
    return WalkSteps(np.concatenate([[t[0]], st["t_s"].to_numpy()]),
                     (st["a_max_mps2"] - st["a_min_mps2"]).to_numpy(), th[i])


def _track_at(state_t_s, xy, t_s):
    """Positions at times ``t_s`` by linear interpolation between states (held outside)."""
    return np.column_stack([np.interp(t_s, state_t_s, xy[:, 0]), np.interp(t_s, state_t_s, xy[:, 1])])


@dataclass(frozen=True)
class Calibration:
    """What the other walks teach: Weinberg ``k``, the floor heading offset, per-walk fits."""

    k_weinberg: float
    offset_rad: float
    per_walk: pd.DataFrame


def calibrate(traces, steps: dict | None = None, cfg: RealWalkConfig = DEFAULT_CONFIG) -> Calibration:
    """Fit ``k`` and the compass-to-map heading offset on walks with waypoints (never the scored one).

    ``steps`` (walk name -> :class:`WalkSteps`, optional) saves re-detecting the steps.

    References
    ----------
    Weinberg (2002), the step length ``k * (a_max - a_min)^(1/4)``; Umeyama (1991), the rotation of
    each walk's track onto its waypoints.
    """
    items = list(traces.values() if isinstance(traces, dict) else traces)
    if not items:
        raise ValueError("calibrate: no walks given")
    rows = []
    for tr in items:
        ws = (steps or {}).get(tr.name) or walk_steps(tr, cfg)
        wp = tr.waypoints
        tw = wp[T_S].to_numpy()
        inside = (ws.state_t_s[1:] >= tw[0]) & (ws.state_t_s[1:] <= tw[-1])
        path_m = float(np.hypot(*np.diff(wp[[X_M, Y_M]].to_numpy(), axis=0).T).sum())
        f = float((ws.a_range_mps2[inside] ** 0.25).sum())
        row = {"walk": tr.name, "steps": int(ws.a_range_mps2.size), "path_m": path_m, "angle_rad": np.nan,
               "rms_m": np.nan, "f_sum": f, "used": False}
        if inside.sum() >= 2 and len(wp) >= 2:
            row["used"] = True
            rel = dead_reckon(np.full(ws.theta_rel_rad.size, 0.7), ws.theta_rel_rad)[["x_m", "y_m"]].to_numpy()
            fit = fit_track_to_fixes(_track_at(ws.state_t_s, rel, tw), wp[[X_M, Y_M]].to_numpy(), huber_m=None)
            row.update(angle_rad=fit.angle_rad, rms_m=fit.rms_m)
        rows.append(row)
    return calibration_from_rows(pd.DataFrame(rows))


def calibration_from_rows(per_walk: pd.DataFrame) -> Calibration:
    """The :class:`Calibration` of the walks of a per-walk table made by :func:`calibrate` (leave walks
    out by dropping their rows): ``k = sum(path) / sum(f)`` over the used walks, the offset their
    path-weighted circular mean angle."""
    pw = per_walk
    u = pw["used"].to_numpy(dtype=bool) & pw["angle_rad"].notna().to_numpy()
    f_tot = float(pw.loc[u, "f_sum"].sum())
    if f_tot <= 0 or not u.any():
        raise ValueError("calibrate: no walk with steps inside its waypoint span")
    off = circular_mean_rad(pw.loc[u, "angle_rad"].to_numpy(), pw.loc[u, "path_m"].to_numpy())
    return Calibration(float(pw.loc[u, "path_m"].sum()) / f_tot, off, pw)




def step_errors(trace, steps: WalkSteps, calibration: Calibration) -> tuple[float, int]:
    """Sum of squared PDR displacement errors (m^2) between consecutive waypoints of a walk and the number
    of steps they span: the PDR displacement (Weinberg length with ``calibration.k_weinberg``, heading with
    the floor offset) between two waypoint times against the waypoints' own displacement."""
    wp = trace.waypoints
    tw = wp[T_S].to_numpy()
    if len(wp) < 2 or steps.a_range_mps2.size < 1:
        return 0.0, 0
    d = weinberg_length_m(steps.a_range_mps2, np.zeros_like(steps.a_range_mps2), calibration.k_weinberg)
    th = wrap_angle_rad(steps.theta_rel_rad + calibration.offset_rad)
    rel = dead_reckon(d, th)[["x_m", "y_m"]].to_numpy()
    inside = (tw >= steps.state_t_s[0]) & (tw <= steps.state_t_s[-1])
    tw, true = tw[inside], wp[[X_M, Y_M]].to_numpy()[inside]
    if tw.size < 2:
        return 0.0, 0
    at = _track_at(steps.state_t_s, rel, tw)
    e = np.diff(at, axis=0) - np.diff(true, axis=0)
    n = np.diff(np.searchsorted(steps.state_t_s, tw))
    ok = n > 0
    return float((e[ok] ** 2).sum()), int(n[ok].sum())


def calibrate_step_var(traces, steps: dict, calibration: Calibration) -> float:
    """Per-axis variance (m^2) of one step's PDR displacement error, measured on walks with waypoints
    (never the scored one): the squared errors of :func:`step_errors` over all walks, divided by twice
    the steps they span (a random-walk error model: the variance grows with the number of steps)."""
    items = list(traces.values() if isinstance(traces, dict) else traces)
    s, n = 0.0, 0
    for tr in items:
        ws = steps.get(tr.name) if steps else None
        a, b = step_errors(tr, ws or walk_steps(tr), calibration)
        s, n = s + a, n + b
    if n == 0:
        raise ValueError("calibrate_step_var: no walk has steps between two waypoints")
    return s / (2.0 * n)


def step_intervals(trace, steps: WalkSteps) -> pd.DataFrame:
    """Per pair of consecutive waypoints of a walk: the PDR displacement for ``k = 1`` and no heading offset
    as a complex number (``s_re, s_im``; the displacement for any calibration is ``k exp(i offset) s``),
    the waypoints' displacement (``dx_m, dy_m``) and the steps spanned (``n``). The table
    :func:`step_var_from_intervals` turns into a step variance for any leave-walks-out calibration."""
    wp = trace.waypoints
    tw = wp[T_S].to_numpy()
    cols = ["walk", "s_re", "s_im", "dx_m", "dy_m", "n"]
    if len(wp) < 2 or steps.a_range_mps2.size < 1:
        return pd.DataFrame(columns=cols)
    d = steps.a_range_mps2 ** 0.25
    rel = dead_reckon(d, steps.theta_rel_rad)[["x_m", "y_m"]].to_numpy()
    inside = (tw >= steps.state_t_s[0]) & (tw <= steps.state_t_s[-1])
    tw, true = tw[inside], wp[[X_M, Y_M]].to_numpy()[inside]
    if tw.size < 2:
        return pd.DataFrame(columns=cols)
    ds = np.diff(_track_at(steps.state_t_s, rel, tw), axis=0)
    dt = np.diff(true, axis=0)
    n = np.diff(np.searchsorted(steps.state_t_s, tw))
    return pd.DataFrame({"walk": trace.name, "s_re": ds[:, 0], "s_im": ds[:, 1], "dx_m": dt[:, 0], "dy_m": dt[:, 1],
                         "n": n})


def step_var_from_intervals(intervals: pd.DataFrame, calibration: Calibration) -> float:
    """Per-axis variance (m^2) of one step's displacement error from :func:`step_intervals` tables:
    ``sum |k exp(i offset) s - (dx + i dy)|^2 / (2 sum n)`` over intervals spanning at least one step."""
    iv = intervals[intervals["n"] > 0]
    if not len(iv):
        raise ValueError("no walk has steps between two waypoints; the step variance cannot be learned")
    s = (iv["s_re"].to_numpy(dtype=float) + 1j * iv["s_im"].to_numpy(dtype=float))
    pred = calibration.k_weinberg * np.exp(1j * calibration.offset_rad) * s
    e = pred - (iv["dx_m"].to_numpy(dtype=float) + 1j * iv["dy_m"].to_numpy(dtype=float))
    return float((np.abs(e) ** 2).sum() / (2.0 * iv["n"].sum()))


@dataclass(frozen=True)
class GainStats:
    """How a walk's own similarity gain ``g = s exp(i b)`` (step scale ``s``, heading bias ``b``, beyond the
    floor calibration) varies, measured on walks with waypoints (:func:`gain_stats`): ``gain_var``
    (variance of each component of the per-walk ``g`` around 1, its fit noise removed), ``gain_walk_var``
    (its random-walk variance per step, from the change between the two halves of each walk, their fit
    noise removed), ``step_var_m2`` (per-axis
    variance of one step's displacement error once the walk's own ``g`` is applied) and ``n_walks``."""

    gain_var: float
    gain_walk_var: float
    step_var_m2: float
    n_walks: int


def _walk_gain(pred, true):
    """Least-squares complex gain ``g`` of ``g pred ~ true`` (complex arrays), its residuals and the variance of
    each component of ``g`` (``sigma^2 / sum |pred|^2``, ``sigma^2 = sum |e|^2 / (2 n - 2)``; NaN with one
    interval)."""
    den = float((np.abs(pred) ** 2).sum())
    if den <= 0:
        return np.nan, true - pred, np.nan
    g = complex((np.conj(pred) * true).sum() / den)
    e = true - g * pred
    var = float((np.abs(e) ** 2).sum()) / (2.0 * pred.size - 2.0) / den if pred.size > 1 else np.nan
    return g, e, var


def gain_stats(intervals: pd.DataFrame, calibration: Calibration, min_intervals: int = 4) -> GainStats:
    """Measure the per-walk similarity gain's spread from :func:`step_intervals` tables (never the scored
    walk's). Per walk with at least ``min_intervals`` waypoint intervals spanning steps: ``g`` fitted by
    least squares of ``g G s ~ (dx + i dy)`` (``G = k exp(i offset)``, the floor calibration), with the
    variance ``v`` of each component of the fit. ``gain_var = mean(|g - 1|^2 / 2 - v)``: the spread of the
    walks' gains less their fits' own noise. The walk's first and second half of intervals fitted apart
    (``g_1``, ``g_2``, fit variances ``v_1``, ``v_2``) give the random walk per step,
    ``gain_walk_var = mean((|g_1 - g_2|^2 / 2 - v_1 - v_2) / m)`` with ``m`` the steps between the halves'
    centres; both clipped at 0. ``step_var_m2``: the residuals' ``sum |e|^2 / (2 sum n)``.

    References
    ----------
    Umeyama S., IEEE PAMI 13(4) (1991) (the similarity fit, here in complex form); the variance of a
    least-squares coefficient, e.g. Seber & Lee, Linear Regression Analysis, Wiley (2003), sec. 3.
    """
    n_all = intervals["n"].to_numpy()
    use = np.flatnonzero(n_all > 0)
    G = calibration.k_weinberg * np.exp(1j * calibration.offset_rad)
    dev, walk_var, res2, nsum = [], [], 0.0, 0
    # the columns read once; each walk's rows (groupby(sort=False)'s groups: walks in order of first row, rows in
    # table order) taken from them: the same arrays as the walk's own columns, so the same numbers
    cols = {c: intervals[c].to_numpy(dtype=float)[use] for c in ("s_re", "s_im", "dx_m", "dy_m")}
    n_use = n_all[use].astype(np.int64)
    codes, _ = pd.factorize(intervals["walk"].to_numpy()[use])      # a missing name: -1, no group (as groupby)
    order = np.argsort(codes, kind="stable")
    order = order[codes[order] >= 0]
    bounds = np.flatnonzero(np.diff(codes[order])) + 1
    for rows in np.split(order, bounds) if use.size else []:
        if rows.size < min_intervals:
            continue
        pred = G * (cols["s_re"][rows] + 1j * cols["s_im"][rows])
        true = cols["dx_m"][rows] + 1j * cols["dy_m"][rows]
        n = n_use[rows]
        g, e, v = _walk_gain(pred, true)
        if not (np.isfinite(g) and np.isfinite(v)):
            continue
        dev.append(abs(g - 1.0) ** 2 / 2.0 - v)
        res2 += float((np.abs(e) ** 2).sum())
        nsum += int(n.sum())
        h = rows.size // 2
        g1, _, v1 = _walk_gain(pred[:h], true[:h])
        g2, _, v2 = _walk_gain(pred[h:], true[h:])
        m = 0.5 * (n[:h].sum() + n[h:].sum())
        if np.isfinite(g1) and np.isfinite(g2) and np.isfinite(v1) and np.isfinite(v2) and m > 0:
            walk_var.append((abs(g1 - g2) ** 2 / 2.0 - v1 - v2) / m)
    if len(dev) < 2 or nsum == 0:
        raise ValueError(f"gain_stats: need at least 2 walks with >= {min_intervals} waypoint intervals, got "
                         f"{len(dev)}")
    return GainStats(max(float(np.mean(dev)), 0.0), max(float(np.mean(walk_var)), 0.0) if walk_var else 0.0,
                     res2 / (2.0 * nsum), len(dev))
