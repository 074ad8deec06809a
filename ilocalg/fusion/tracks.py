"""Tracks scored at test points: each track's state when a point is passed, Wi-Fi fixes as they arrive.

Data types: times in seconds, positions in metres; a track is an ``(n + 1, 2)`` array of states (the
start, then one per step) with its state times.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.fusion.budget import track_at

__all__ = ["score_points", "score_at_times", "crossover_point"]


def score_points(tracks: dict, state_index: np.ndarray, true_xy_m: np.ndarray, fix_xy_m: np.ndarray) -> pd.DataFrame:
    """Error at each point: every track's state at the point's state index; Wi-Fi only = the fix itself."""
    rows = []
    ok = state_index >= 0
    k = np.where(ok, state_index, 0)
    n = true_xy_m.shape[0]
    for label, xy in {"Wi-Fi only": None, **tracks}.items():
        est = fix_xy_m if xy is None else np.where(ok[:, None], xy[k], np.nan)
        rows.append(pd.DataFrame({"method": label, "point": np.arange(1, n + 1), "x_true_m": true_xy_m[:, 0],
                                  "y_true_m": true_xy_m[:, 1], "x_est_m": est[:, 0], "y_est_m": est[:, 1],
                                  "error_m": np.hypot(*(est - true_xy_m).T)}))
    return pd.concat(rows, ignore_index=True)


def score_at_times(tracks: dict, state_t_s, eval_t_s, true_xy_m, fix_t_s, fix_xy_m, start_xy_m) -> pd.DataFrame:
    """Error at each point, causally: every track's latest state at or before the point's time; Wi-Fi only =
    the latest fix available then (the start fix before any other)."""
    te = np.asarray(eval_t_s, dtype=np.float64)
    ft = np.asarray(fix_t_s, dtype=np.float64)
    fxy = np.asarray(fix_xy_m, dtype=np.float64)
    ok = np.isfinite(fxy).all(axis=1)
    held = np.vstack([np.asarray(start_xy_m, dtype=np.float64)[None, :], fxy[ok]])
    wifi = held[np.searchsorted(ft[ok], te, side="right")]
    rows = []
    n = true_xy_m.shape[0]
    for label, xy in {"Wi-Fi only": None, **tracks}.items():
        est = wifi if xy is None else track_at(state_t_s, xy, te)
        rows.append(pd.DataFrame({"method": label, "point": np.arange(1, n + 1), "x_true_m": true_xy_m[:, 0],
                                  "y_true_m": true_xy_m[:, 1], "x_est_m": est[:, 0], "y_est_m": est[:, 1],
                                  "error_m": np.hypot(*(est - true_xy_m).T)}))
    return pd.concat(rows, ignore_index=True)


def crossover_point(pdr_err: np.ndarray, comb_err: np.ndarray) -> int:
    """Number of leading points (1-based count) before which PDR is better and after which the
    combined error stays below PDR's: the last point where PDR < combined (0 if never)."""
    better = np.flatnonzero(np.asarray(pdr_err) < np.asarray(comb_err))
    return int(better[-1] + 1) if better.size else 0
