"""Error statistics of a navigation solution in the paper's layout (max / RMS / STD per axis).

References
----------
Liao, Chiang, Zhou, Li (2016), Tables 4-11 (N, E, H position and roll, pitch, heading errors).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.ins.mechanisation import dcm_to_euler, rotvecs_to_dcm
from ilocalg.units import wrap_angle_rad

__all__ = ["nav_errors", "error_stats", "heading_error_with_lag_deg", "POS_AXES", "ATT_AXES", "AXES", "WindowSweep",
           "window_sweep", "window_sweeps", "window_sweep_tables"]

POS_AXES = ("N", "E", "H")
ATT_AXES = ("Roll", "Pitch", "Heading")


def nav_errors(pos_n_m, mat_nb, pos_true_n_m, mat_true_nb) -> pd.DataFrame:
    """Per-epoch errors (estimate - truth): N, E, H in metres and roll, pitch, heading in degrees."""
    pos, pt = np.asarray(pos_n_m, dtype=float), np.asarray(pos_true_n_m, dtype=float)
    if pos.shape != pt.shape or pos.ndim != 2 or pos.shape[1] != 3:
        raise ValueError(f"pos_n_m and pos_true_n_m must both be (N, 3), got {pos.shape} and {pt.shape}")
    return _errors(pos, mat_nb, pt, dcm_to_euler(mat_true_nb))


def _errors(pos, mat_nb, pos_true, euler_true) -> pd.DataFrame:
    """:func:`nav_errors` with the truth's Euler angles (``dcm_to_euler(mat_true_nb)``) given (shared by the
    solutions of a sweep)."""
    d = pos - pos_true
    da = np.rad2deg(wrap_angle_rad(dcm_to_euler(mat_nb) - euler_true))
    return pd.DataFrame({"N": d[:, 1], "E": d[:, 0], "H": d[:, 2],
                         "Roll": da[:, 0], "Pitch": da[:, 1], "Heading": da[:, 2]})


def _error_array(pos, euler, pos_true, euler_true) -> np.ndarray:
    """The values of :func:`_errors` (Euler angles of the estimate given) as the (S, 6) array its
    ``to_numpy()`` gives: column-major, so that the statistics sum in the same order."""
    d = pos - pos_true
    da = np.rad2deg(wrap_angle_rad(euler - euler_true))
    a = np.empty((6, d.shape[0]))
    a[0], a[1], a[2] = d[:, 1], d[:, 0], d[:, 2]
    a[3:] = da.T
    return a.T


def error_stats(err: pd.DataFrame) -> dict[str, dict[str, float]]:
    """``{"max": {axis: ..}, "rms": {..}, "std": {..}}`` over the rows of :func:`nav_errors` output.

    Max is the largest absolute error, RMS the root mean square, STD the standard deviation.
    """
    return _stats(err.to_numpy(dtype=float), err.columns)


def _stats(a: np.ndarray, columns) -> dict[str, dict[str, float]]:
    """:func:`error_stats` of the array ``err.to_numpy()`` with the column names ``columns``."""
    return {
        "max": dict(zip(columns, np.max(np.abs(a), axis=0), strict=True)),
        "rms": dict(zip(columns, np.sqrt(np.mean(a**2, axis=0)), strict=True)),
        "std": dict(zip(columns, np.std(a, axis=0), strict=True)),
    }


def heading_error_with_lag_deg(t_s, mat_nb, t_ref_s, mat_ref_nb, lag_s: float) -> np.ndarray:
    """Heading error (deg) against a reference read ``lag_s`` seconds off (time-tag misalignment).

    The estimate at ``t`` is compared with the reference heading interpolated at ``t - lag_s`` (the phone's
    time tags lagging the reference by ``lag_s``). The paper attributes its large heading errors to
    such phone/reference time-synchronisation errors (sec. 4.1).
    """
    t_s = np.asarray(t_s, dtype=float)
    t_ref = np.asarray(t_ref_s, dtype=float)
    if t_ref.ndim != 1 or np.any(np.diff(t_ref) <= 0):
        raise ValueError("t_ref_s must be 1-D and strictly increasing")
    yaw_ref = np.unwrap(dcm_to_euler(mat_ref_nb)[:, 2])
    tq = t_s - lag_s
    if tq.min() < t_ref[0] or tq.max() > t_ref[-1]:
        raise ValueError("lag_s moves the evaluation times outside the reference")
    ref = np.interp(tq, t_ref, yaw_ref)
    return np.rad2deg(wrap_angle_rad(dcm_to_euler(mat_nb)[:, 2] - ref))


#: Every error axis of :func:`nav_errors`, in the paper's table order.
AXES = POS_AXES + ATT_AXES


@dataclass(frozen=True)
class WindowSweep:
    """Online smoothing of one filtered walk for several window sizes (see :func:`window_sweep`).

    ``solutions``: a mapping ``{key: (pos_n_m, mat_nb, latency_s)}`` with keys ``"Filtering"``, every window size
    (float, s, ascending) and ``"RTS (whole run)"``, in that order (a window's whole solution is formed when first
    read); ``stats``: ``{key: error_stats}`` on the
    scored epochs; ``sweep``: one row per key and statistic (``window_s`` 0 for the filter, inf for the
    whole-run RTS; ``stat``, ``N``, ``E``, ``H``, ``horizontal`` (RMS rows only), ``latency_mean_s``);
    ``gcp``: one row per window size (``windows_indoor``, ``share_without_gcp``, ``rms_h_with_gcp_m``,
    ``rms_h_without_gcp_m``: horizontal RMS error inside windows that hold / do not hold a control point).
    """

    solutions: dict
    stats: dict
    sweep: pd.DataFrame
    gcp: pd.DataFrame


def window_sweep(res, windows_s, scored, pos_true_n_m, mat_true_nb, gcp_t_s, gains=None,
                 offset_frac: float = 0.0, whole_run=None) -> WindowSweep:
    """Filter, online fixed-window smoothers and whole-run RTS of one stored filter, scored against the truth.

    Parameters
    ----------
    res : :class:`ilocalg.ins.eskf.EskfResult`
    windows_s : window sizes (s), ascending floats
    scored : (N,) bool, the epochs scored (e.g. the indoor part of a walk)
    pos_true_n_m, mat_true_nb : truth at the scored epochs, (S, 3) and (S, 3, 3)
    gcp_t_s : (C,) times of the control-point updates (to find the windows that hold one)
    gains : precomputed :func:`ilocalg.ins.smoother.rts_gains` (computed when None)
    offset_frac : the window grid starts ``offset_frac x window`` seconds after the first epoch, in [0, 1)
    whole_run : precomputed whole-run RTS of ``res`` (``eskf_rts_smooth(res, with_cov=False, gains=gains)``;
        computed when None): it does not depend on the grid, so a sweep over offsets computes it once

    References
    ----------
    Liao et al. (2016), sec. 3.3 and 4.2 (Tables 8-11, Fig 19; windows without a control point, Figs 20-21).
    """
    return window_sweeps(res, windows_s, scored, pos_true_n_m, mat_true_nb, gcp_t_s, gains, (offset_frac,),
                         whole_run)[0]


def window_sweeps(res, windows_s, scored, pos_true_n_m, mat_true_nb, gcp_t_s, gains=None, offset_fracs=(0.0,),
                  whole_run=None) -> list[WindowSweep]:
    """:func:`window_sweep` for several grid offsets at once: one :class:`WindowSweep` per ``offset_fracs`` entry.

    Every window of every offset is smoothed in one backward pass
    (:func:`ilocalg.ins.smoother.eskf_rts_smooth_grids`); the filter and the whole-run RTS, which do not depend
    on the grid, are scored once. Only the scored epochs of each smoothed solution are formed to score it (every
    grid at once); a solution's whole run (``solutions[key]``) is formed when it is first read. The same tables
    as :func:`window_sweep` offset by offset.
    """
    from ilocalg.ins.smoother import _backward, rts_gains, window_ends

    G = rts_gains(res) if gains is None else gains
    offsets = [float(f) for f in offset_fracs]
    grids = [(w, f * w) for f in offsets for w in windows_s]
    if whole_run is None:
        grids.append((None, 0.0))
    ends = np.array([window_ends(res.t_s, w, o) for w, o in grids])
    xs, _ = _backward(res, ends, G)
    euler_true = dcm_to_euler(mat_true_nb)
    pos_true = np.asarray(pos_true_n_m, dtype=float)
    gcp_epoch = np.zeros(res.t_s.size, bool)
    gcp_epoch[np.searchsorted(res.t_s, gcp_t_s)] = True
    scored = np.asarray(scored, dtype=bool)
    pos_f, mat_f = res.pos_n_m[scored], res.mat_nb[scored]
    # every grid's smoothed solution at the scored epochs, (S, M, ...): the same element-wise operations and the
    # same 3 x 3 products as the whole solution (:func:`ilocalg.ins.smoother.eskf_rts_smooth_grids`) at those epochs
    xs_s = xs[scored]
    n_s, m = xs_s.shape[:2]
    pos_g = pos_f[:, None, :] + xs_s[:, :, 0:3]
    mat_g = np.matmul(rotvecs_to_dcm(xs_s[:, :, 6:9].reshape(n_s * m, 3)).reshape(n_s, m, 3, 3), mat_f[:, None])
    euler_g = dcm_to_euler(mat_g)
    t_s = res.t_s

    def latency(e):
        end_idx = np.flatnonzero(e)
        return t_s[end_idx[np.searchsorted(end_idx, np.arange(t_s.size), side="left")]] - t_s

    def score(key, pos, euler, lat):
        a = _error_array(pos, euler, pos_true, euler_true)
        st = _stats(a, AXES)
        wsec = key if isinstance(key, float) else (0.0 if key == "Filtering" else np.inf)
        rows = [{"window_s": wsec, "stat": k, **{ax: st[k][ax] for ax in POS_AXES},
                 "horizontal": float(np.hypot(st[k]["N"], st[k]["E"])) if k == "rms" else np.nan,
                 "latency_mean_s": float(np.mean(lat[scored]))} for k in ("max", "rms", "std")]
        return a, st, rows

    def solution(j):
        def make():
            from ilocalg.ins.smoother import _smooth_result

            sm = _smooth_result(res, xs[:, j], np.full((t_s.size, xs.shape[2]), np.nan), ends[j])
            return sm.pos_n_m, sm.mat_nb, sm.latency_s
        return make

    filt = (res.pos_n_m, res.mat_nb, np.zeros(t_s.size))
    if whole_run is not None:
        full_sol = (whole_run.pos_n_m, whole_run.mat_nb, whole_run.latency_s)
        full_score = score("RTS (whole run)", whole_run.pos_n_m[scored], dcm_to_euler(whole_run.mat_nb[scored]),
                           whole_run.latency_s)
    else:
        full_sol = solution(m - 1)
        full_score = score("RTS (whole run)", pos_g[:, m - 1], euler_g[:, m - 1], latency(ends[m - 1]))
    fixed_scores = {"Filtering": score("Filtering", pos_f, dcm_to_euler(mat_f), filt[2]),
                    "RTS (whole run)": full_score}
    out = []
    for jo in range(len(offsets)):
        sols = {"Filtering": filt}
        stats, sweep, gcp_rows = {"Filtering": fixed_scores["Filtering"][1]}, list(fixed_scores["Filtering"][2]), []
        for i, w in enumerate(windows_s):
            j = jo * len(windows_s) + i
            sols[w] = solution(j)
            a, st, rows = score(w, pos_g[:, j], euler_g[:, j], latency(ends[j]))
            stats[w] = st
            sweep += rows
            win = np.concatenate([[0], np.cumsum(ends[j, :-1])])
            has = np.zeros(win.max() + 1, bool)
            has[win[gcp_epoch]] = True
            hz = np.hypot(a[:, 0], a[:, 1])
            wi = win[scored]
            in_gcp = has[wi]
            scored_windows = np.unique(wi)
            gcp_rows.append({
                "window_s": w,
                "windows_indoor": scored_windows.size,
                "share_without_gcp": float(np.mean(~has[scored_windows])),
                "rms_h_with_gcp_m": float(np.sqrt(np.mean(hz[in_gcp] ** 2))) if in_gcp.any() else np.nan,
                "rms_h_without_gcp_m": (float(np.sqrt(np.mean(hz[~in_gcp] ** 2))) if (~in_gcp).any()
                                        else np.nan)})
        sols["RTS (whole run)"] = full_sol
        stats["RTS (whole run)"] = fixed_scores["RTS (whole run)"][1]
        sweep += fixed_scores["RTS (whole run)"][2]
        out.append(WindowSweep(solutions=_Solutions(sols), stats=stats, sweep=pd.DataFrame(sweep),
                               gcp=pd.DataFrame(gcp_rows)))
    return out


class _Solutions(Mapping):
    """``{key: (pos_n_m, mat_nb, latency_s)}`` of :class:`WindowSweep`, in key order; a value given as a function
    is called when first read (a sweep scores every window at the scored epochs only, and a caller reads the
    whole solution of a few)."""

    def __init__(self, items: dict):
        self._d = dict(items)

    def __getitem__(self, key):
        v = self._d[key]
        if callable(v):
            v = self._d[key] = v()
        return v

    def __iter__(self):
        return iter(self._d)

    def __len__(self) -> int:
        return len(self._d)


def window_sweep_tables(sweep: pd.DataFrame, gcp: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Means over seeds of stacked :class:`WindowSweep` tables carrying a ``phone`` column.

    Returns ``(window_sweep, windows_without_gcp)``: the first per phone, window and statistic, sorted
    by phone, statistic and window; the second per phone and window.
    """
    sw = (sweep.groupby(["phone", "window_s", "stat"], sort=False)
          [["N", "E", "H", "horizontal", "latency_mean_s"]].mean().reset_index())
    sw = sw.sort_values(["phone", "stat", "window_s"], kind="stable").reset_index(drop=True)
    gw = (gcp.groupby(["phone", "window_s"], sort=False)
          [["windows_indoor", "share_without_gcp", "rms_h_with_gcp_m", "rms_h_without_gcp_m"]].mean().reset_index())
    return sw, gw
