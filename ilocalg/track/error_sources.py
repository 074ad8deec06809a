"""Where an online track's error comes from: oracle ablations of one walk's :class:`TrackProblem` (diagnostics only).

Each oracle removes one error source from a scored walk's problem using that walk's own truth, re-runs an
estimator and reports what is left; none of them is a method (they read the truth). Together they say which
source dominates and so which fix is worth building (issue 26):

start-up (:func:`with_true_start`)
    the first Wi-Fi fix, where every online track starts, replaced by the true position at its time.
fix outliers (:func:`without_outlier_fixes`)
    the fixes whose true error is improbable under their own variance (chi-square, 2 degrees of freedom, above
    its ``1 - alpha`` quantile) dropped: what perfect innovation gating could buy at most.
step scale and heading (:func:`with_own_gain`)
    every PDR step multiplied by the walk's own similarity gain ``g = s exp(i b)`` fitted to its waypoints (one
    per walk), or one per waypoint interval (``per_interval``: heading drift and scale changes within the walk
    removed too), the filter then told the gain is known.
persistent fix error (:func:`without_fix_bias`)
    each walk's mean fix error subtracted from its fixes (the slowly varying Wi-Fi bias, 56 % of the fix error
    variance on site1 F1).

:func:`nees` checks the filter's own consistency (its normalised estimation error squared, 2 on average for a
consistent 2-D position; Bar-Shalom, Li, Kirubarajan, Estimation with Applications to Tracking and Navigation,
Wiley (2001), sec. 5.4), :func:`error_by_time_since_first_fix` splits the error over the walk's time.
:func:`walk_record` turns an :func:`ilocalg.track.evaluate_walk` result (asked for a least-squares or ``kf_gain*``
method, so that it carries its ``problem``) into the walk record these functions take.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from ilocalg.track.estimators import TrackProblem
from ilocalg.track.motion import GainStats, _track_at

__all__ = ["walk_record", "with_true_start", "without_outlier_fixes", "with_own_gain", "without_fix_bias", "own_gain",
           "truth_at", "nees", "error_by_time_since_first_fix", "oracle_table", "ORACLES", "CHI2_2_99"]

#: The 99 % quantile of the chi-square distribution with 2 degrees of freedom (``-2 ln 0.01``).
CHI2_2_99 = float(-2.0 * np.log(0.01))


def walk_record(result: dict, truth_xy_m, grid=None) -> dict:
    """The record of one scored walk from :func:`ilocalg.track.evaluate_walk`'s ``result`` and its waypoints'
    positions ``truth_xy_m`` (in the database's frame, the rows of ``result["errors"]``): ``problem`` (its
    :class:`TrackProblem`, with ``grid`` when given), ``truth_t_s``, ``truth_xy_m``, ``fix_true_xy_m`` and
    ``wifi_m`` (the Wi-Fi-only errors at the waypoints, None when not scored)."""
    p = result.get("problem")
    if p is None:
        raise ValueError("walk_record needs a result with a problem (ask evaluate_walk for a lsq* or kf_gain* method)")
    if grid is not None:
        p = dataclasses.replace(p, grid=grid)
    e = result["errors"]
    xy = np.asarray(truth_xy_m, dtype=np.float64).reshape(-1, 2)
    if xy.shape[0] != len(e):
        raise ValueError(f"walk_record: {xy.shape[0]} waypoint positions for {len(e)} scored waypoints")
    return {"problem": p, "truth_t_s": e["t_s"].to_numpy(), "truth_xy_m": xy,
            "fix_true_xy_m": result["fixes"].true_xy_m, "wifi_m": e["wifi"].to_numpy() if "wifi" in e else None}


def truth_at(truth_t_s, truth_xy_m, t_s) -> np.ndarray:
    """The true position at times ``t_s``: linear between the waypoints, held outside them; (k, 2)."""
    tt = np.asarray(truth_t_s, dtype=np.float64)
    xy = np.asarray(truth_xy_m, dtype=np.float64).reshape(-1, 2)
    t = np.asarray(t_s, dtype=np.float64)
    return np.column_stack([np.interp(t, tt, xy[:, 0]), np.interp(t, tt, xy[:, 1])])


def with_true_start(problem: TrackProblem, truth_t_s, truth_xy_m, sd_m: float = 0.5) -> TrackProblem:
    """``problem`` with its first fix at the true position of its time (per-axis sd ``sd_m``) and no map start."""
    xy = np.array(problem.fix_xy_m, dtype=np.float64)
    xy[0] = truth_at(truth_t_s, truth_xy_m, problem.fix_t_s[:1])[0]
    fv = np.array(problem.fix_var_at(), dtype=np.float64)
    fv[0] = sd_m ** 2
    return dataclasses.replace(problem, fix_xy_m=xy, fix_var_m2=fv, map_start=False)


def without_outlier_fixes(problem: TrackProblem, fix_true_xy_m, threshold: float = CHI2_2_99) -> TrackProblem:
    """``problem`` without the fixes whose true error ``e`` has ``|e|^2 / var > threshold`` (``var`` the fix's own
    per-axis variance); the first fix (the start) is always kept, as are fixes without a true position."""
    e = np.asarray(problem.fix_xy_m, dtype=np.float64) - np.asarray(fix_true_xy_m, dtype=np.float64)
    c = (e ** 2).sum(axis=1) / problem.fix_var_at()
    keep = ~(c > threshold)                     # NaN (no true position) kept
    keep[0] = True
    fa = None if problem.fix_avail_t_s is None else np.asarray(problem.fix_avail_t_s)[keep]
    return dataclasses.replace(problem, fix_t_s=np.asarray(problem.fix_t_s)[keep],
                               fix_xy_m=np.asarray(problem.fix_xy_m)[keep], fix_var_m2=problem.fix_var_at()[keep],
                               fix_avail_t_s=fa)


def own_gain(problem: TrackProblem, truth_t_s, truth_xy_m, per_interval: bool = False) -> np.ndarray:
    """The walk's own similarity gain (complex) that maps its PDR displacement between waypoints onto the true
    one (least squares, Umeyama 1991 in complex form): one value, or with ``per_interval`` one per waypoint
    interval (the walk's value where an interval has no PDR displacement)."""
    tw = np.asarray(truth_t_s, dtype=np.float64)
    tr = np.asarray(truth_xy_m, dtype=np.float64).reshape(-1, 2)
    if tw.size < 2:
        raise ValueError("own_gain needs at least two waypoints")
    cum = np.vstack([[0.0, 0.0], np.cumsum(problem.disp_m, axis=0)])
    c = _track_at(problem.state_t_s, cum, tw)
    pred = np.diff(c[:, 0] + 1j * c[:, 1])
    true = np.diff(tr[:, 0] + 1j * tr[:, 1])
    den = float((np.abs(pred) ** 2).sum())
    if den <= 0:
        raise ValueError("own_gain: no PDR displacement between the waypoints")
    g = complex((np.conj(pred) * true).sum() / den)
    if not per_interval:
        return np.array(g)
    ok = np.abs(pred) > 1e-6
    return np.where(ok, true / np.where(ok, pred, 1.0), g)


def with_own_gain(problem: TrackProblem, truth_t_s, truth_xy_m, per_interval: bool = False) -> TrackProblem:
    """``problem`` with every step multiplied by the walk's own gain (:func:`own_gain`) and a gain spread that
    says it is known (``gain_var`` 1e-8, no random walk)."""
    g = own_gain(problem, truth_t_s, truth_xy_m, per_interval)
    if per_interval:
        k = np.searchsorted(np.asarray(truth_t_s, dtype=np.float64), problem.state_t_s[1:], side="left") - 1
        g = g[np.clip(k, 0, g.size - 1)]
    d = (problem.disp_m[:, 0] + 1j * problem.disp_m[:, 1]) * g
    sv = problem.gain.step_var_m2 if problem.gain is not None else problem.step_var_m2
    return dataclasses.replace(problem, disp_m=np.column_stack([d.real, d.imag]),
                               gain=GainStats(1e-8, 0.0, sv, 1))


def without_fix_bias(problem: TrackProblem, fix_true_xy_m) -> TrackProblem:
    """``problem`` with the walk's mean fix error (over the fixes with a true position) subtracted from every fix."""
    e = np.asarray(problem.fix_xy_m, dtype=np.float64) - np.asarray(fix_true_xy_m, dtype=np.float64)
    ok = np.isfinite(e).all(axis=1)
    b = e[ok].mean(axis=0) if ok.any() else np.zeros(2)
    return dataclasses.replace(problem, fix_xy_m=np.asarray(problem.fix_xy_m, dtype=np.float64) - b)


#: The oracles of :func:`oracle_table`: label -> ``f(problem, walk)`` with ``walk`` a dict of ``truth_t_s``,
#: ``truth_xy_m``, ``fix_true_xy_m``.
ORACLES = {
    "true start (first fix = truth)": lambda p, w: with_true_start(p, w["truth_t_s"], w["truth_xy_m"]),
    "no outlier fixes (true chi2 > 99 %)": lambda p, w: without_outlier_fixes(p, w["fix_true_xy_m"]),
    "walk's own gain known": lambda p, w: with_own_gain(p, w["truth_t_s"], w["truth_xy_m"]),
    "own gain per waypoint interval (drift removed)": lambda p, w: with_own_gain(p, w["truth_t_s"], w["truth_xy_m"],
                                                                                per_interval=True),
    "walk's mean fix error removed": lambda p, w: without_fix_bias(p, w["fix_true_xy_m"]),
}


def _errors(estimator, problem: TrackProblem, walk: dict) -> np.ndarray:
    xy = estimator(problem)
    return np.hypot(*(_track_at(problem.state_t_s, xy, walk["truth_t_s"]) - walk["truth_xy_m"]).T)


def oracle_table(walks: dict, estimator, wifi_mean_m: float | None = None, oracles=None) -> pd.DataFrame:
    """Each oracle of ``oracles`` (default :data:`ORACLES`) applied to every walk and ``estimator``
    (``problem -> (n+1, 2)``) re-run: one row per condition (``as is`` first) with ``mean_m``, ``p75_m``,
    ``start_mean_m`` (the error at each walk's first waypoint) and, given ``wifi_mean_m``, ``ratio_to_wifi``.
    ``walks``: name -> dict of ``problem`` (:class:`TrackProblem`), ``truth_t_s``, ``truth_xy_m``,
    ``fix_true_xy_m``."""
    oracles = ORACLES if oracles is None else oracles
    rows = []
    for label, f in {"as is": None, **oracles}.items():
        e = [_errors(estimator, w["problem"] if f is None else f(w["problem"], w), w) for w in walks.values()]
        v = np.concatenate(e)
        rows.append({"condition": label, "mean_m": float(v.mean()), "p75_m": float(np.quantile(v, 0.75)),
                     "start_mean_m": float(np.mean([x[0] for x in e])), "n_waypoints": int(v.size)})
    out = pd.DataFrame(rows)
    if wifi_mean_m is not None:
        out["ratio_to_wifi"] = out["mean_m"] / wifi_mean_m
    return out


def error_by_time_since_first_fix(errors: dict, walks: dict, edges_s=(-np.inf, 0.0, 10.0, 30.0, 60.0, np.inf)):
    """Waypoint errors (``errors``: name -> per-waypoint errors of one method) binned by the time since the walk's
    first fix became known: per bin ``n``, ``mean_m`` and ``share`` (of the summed error)."""
    dt, v = [], []
    for nm, e in errors.items():
        p = walks[nm]["problem"]
        known = p.fix_t_s if p.fix_avail_t_s is None else p.fix_avail_t_s
        dt.append(np.asarray(walks[nm]["truth_t_s"], dtype=np.float64) - float(np.min(known)))
        v.append(np.asarray(e, dtype=np.float64))
    dt, v = np.concatenate(dt), np.concatenate(v)
    rows = []
    for a, b in zip(edges_s[:-1], edges_s[1:], strict=True):
        s = (dt >= a) & (dt < b)
        rows.append({"from_s": a, "to_s": b, "n": int(s.sum()), "mean_m": float(v[s].mean()) if s.any() else np.nan,
                     "share": float(v[s].sum() / v.sum())})
    return pd.DataFrame(rows)


def nees(xy_m, P_m2, state_t_s, truth_t_s, truth_xy_m) -> np.ndarray:
    """Normalised estimation error squared ``e^T P^-1 e`` of the filter's position at the state at or before each
    waypoint (``xy_m`` (n+1, 2), ``P_m2`` (n+1, >=2, >=2)), ``e`` against the truth at that state's time."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    k = np.clip(np.searchsorted(ts, np.asarray(truth_t_s, dtype=np.float64), side="right") - 1, 0, ts.size - 1)
    e = np.asarray(xy_m)[k, :2] - truth_at(truth_t_s, truth_xy_m, ts[k])
    P = np.asarray(P_m2)[k, :2, :2]
    return np.einsum("ni,ni->n", e, np.linalg.solve(P, e[..., None])[..., 0])
