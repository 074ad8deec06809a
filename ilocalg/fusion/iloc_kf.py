"""The i-Loc thesis's Kalman filter (PTS + Wi-Fi) on one walk, with its variants and budget methods.

:func:`run_filters` runs PTS alone and every KF variant of the thesis's ch. 5 on one walk: the main KF
(eq. 20-26, one predict per detected step, one update per Wi-Fi fix at the latest state at or before the
fix is available), Table 4 read the other way, RTS and fixed-lag smoothing, a heading-error term in Q and
innovation gating. :func:`nearest_point_variance` gives a fix the R calibrated at the test point nearest
it (Table 5's procedure, L586-588); :func:`kf_method` and :func:`pts_method` are the main KF and PTS as
error-budget methods (:mod:`ilocalg.fusion.budget`).

Data types: times in seconds, positions in metres in the floor frame, headings in radians from the x axis.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Ch. 5, eq. (20)-(26), Tables 4-5, Figs 22-23.
"""

from __future__ import annotations

import numpy as np

from ilocalg.fusion.align import fixes_at_states
from ilocalg.fusion.budget import FusionInputs
from ilocalg.fusion.smoothers import fixed_lag_smooth, rts_smooth
from ilocalg.fusion.step_kf import filter_walk, nis_gate, sigma_sl_paper_m
from ilocalg.pdr.dead_reckoning import dead_reckon

__all__ = ["run_filters", "nearest_point_variance", "kf_method", "pts_method"]


def run_filters(x0_m, pdr: dict, fix_t_s, fix_xy_m, r_var: dict, P0_var_m2: float = 0.25, gate_prob: float = 0.99,
                sigma_theta_rad: float = 0.2, lag: int = 5, table4_reading: str = "relative") -> tuple[dict, dict]:
    """Every PDR / KF variant on one walk.

    Parameters
    ----------
    x0_m : (2,) start position.
    pdr : dict from :func:`ilocalg.pdr.pts.pts_filter_inputs` (any dict with ``state_t_s``, ``step_m``,
        ``theta_rad``).
    fix_t_s, fix_xy_m : (m,), (m, 2) Wi-Fi fixes (time order); a NaN row is a scan without a fix.
    r_var : dict label -> (m,) isotropic fix variances (one KF variant per entry; the first is the main one).
    P0_var_m2 : float, the start's variance per axis.
    table4_reading : {"relative", "m2"}, how Table 4 reads (:func:`ilocalg.fusion.sigma_sl_paper_m`); the
        main variant is also run with the other reading.

    Returns
    -------
    tracks : dict label -> (n+1, 2) state estimates (``"PTS"``, ``"KF (...)"``, ...)
    info : dict with ``state_index`` of each fix, the number of gated fixes, ``n_superseded``.
    """
    ts, d, th = pdr["state_t_s"], pdr["step_m"], pdr["theta_rad"]
    n1 = ts.size
    tr = dead_reckon(d, th, *x0_m)[["x_m", "y_m"]].to_numpy()
    tracks = {"PTS": tr}
    first = next(iter(r_var))
    fxy = np.asarray(fix_xy_m, dtype=np.float64)
    ok = np.isfinite(fxy).all(axis=1)
    # align on the fix times (positions only fill the slots; a scan without a fix leaves its state empty)
    al = fixes_at_states(ts, fix_t_s, np.where(ok[:, None], fxy, 0.0), before_start="drop", same_state="last")
    used = al.used & ok
    z = np.full((n1, 2), np.nan)
    z[al.state_index[used]] = fxy[used]
    other = "m2" if table4_reading == "relative" else "relative"
    sig = sigma_sl_paper_m(d, reading=table4_reading)
    P0 = P0_var_m2 * np.eye(2)
    info = {"state_index": al.state_index, "n_superseded": al.n_superseded, "n_before_start": al.n_before_start}
    for label, rv in r_var.items():
        r = np.full(n1, np.nan)
        r[al.state_index[used]] = np.asarray(rv, dtype=np.float64)[used]
        rr = np.where(np.isnan(r), 1.0, r)
        res = filter_walk(x0_m, P0, th, d, sig, z, r_var_m2=rr)
        tracks[f"KF ({label})"] = res.x
        if label == first:
            alt = filter_walk(x0_m, P0, th, d, sigma_sl_paper_m(d, reading=other), z, r_var_m2=rr)
            tracks[f"KF ({label}, Table 4 read as {other})"] = alt.x
            tracks[f"KF ({label}) + RTS"] = rts_smooth(res).x
            tracks[f"KF ({label}) + fixed-lag {lag}"] = fixed_lag_smooth(res, lag).x
            h = filter_walk(x0_m, P0, th, d, sig, z, r_var_m2=rr, sigma_theta_rad=sigma_theta_rad)
            tracks[f"KF ({label}) + heading noise"] = h.x
            tracks[f"KF ({label}) + heading noise + RTS"] = rts_smooth(h).x
            # gating needs a P that admits the heading error, else good fixes are rejected as the PTS drifts
            g = filter_walk(x0_m, P0, th, d, sig, z, r_var_m2=rr, gate_nis=nis_gate(gate_prob),
                            sigma_theta_rad=sigma_theta_rad)
            tracks[f"KF ({label}) + heading noise + gating"] = g.x
            info["n_gated"] = int(g.n_rejected)
            info["n_fixes"] = int(used.sum())
    return tracks, info


def nearest_point_variance(route_xy_m, var_m2):
    """R of a fix: the calibrated variance of the route point nearest the fix (the filter knows the fix, not
    the truth).

    Parameters
    ----------
    route_xy_m : (p, 2) the test points whose fix variance was calibrated.
    var_m2 : (p,) the isotropic fix variance at each point (m^2 per axis).

    Returns
    -------
    callable
        ``r_of(xy) -> (m,)``: for fixes ``xy`` ((2,) or (m, 2)), the variance of the nearest point; NaN for
        a NaN fix.
    """
    def r_of(xy):
        xy = np.atleast_2d(np.asarray(xy, dtype=np.float64))
        good = np.isfinite(xy).all(axis=1)
        d = np.where(good[:, None], xy, 0.0)[:, None, :] - route_xy_m[None, :, :]
        j = np.hypot(*d.transpose(2, 0, 1)).argmin(1)
        return np.where(good, var_m2[j], np.nan)
    return r_of


def kf_method(r_of, table4_reading: str = "relative"):
    """The main KF variant (R per fix from ``r_of``, Table 4 Q, start fix with its R as P0) as a budget method."""
    def kf(inp: FusionInputs) -> np.ndarray:
        x0 = inp.start_xy_m if np.isfinite(inp.start_xy_m).all() else inp.truth_at([inp.t0_s])[0]
        fxy = np.asarray(inp.fix_xy_m, dtype=np.float64)
        ok = np.isfinite(fxy).all(axis=1)
        al = fixes_at_states(inp.state_t_s, inp.fix_t_s, np.where(ok[:, None], fxy, 0.0), before_start="drop",
                             same_state="last")
        used = al.used & ok
        z = np.full((inp.step_t_s.size + 1, 2), np.nan)
        z[al.state_index[used]] = fxy[used]
        r = np.ones(inp.step_t_s.size + 1)
        r[al.state_index[used]] = r_of(fxy[used])
        d = np.asarray(inp.step_m, dtype=np.float64)
        p0 = float(r_of(x0)[0])
        return filter_walk(x0, p0 * np.eye(2), inp.theta_rad, d, sigma_sl_paper_m(d, reading=table4_reading), z,
                           r_var_m2=r).x
    return kf


def pts_method(inp: FusionInputs) -> np.ndarray:
    """PTS alone from the start fix (the PDR-only trajectory of Fig 23) as a budget method."""
    x0 = inp.start_xy_m if np.isfinite(inp.start_xy_m).all() else inp.truth_at([inp.t0_s])[0]
    return dead_reckon(np.asarray(inp.step_m), np.asarray(inp.theta_rad), *x0)[["x_m", "y_m"]].to_numpy()
