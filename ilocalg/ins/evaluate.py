"""Error statistics of a navigation solution in the paper's layout (max / RMS / STD per axis).

References
----------
Liao, Chiang, Zhou, Li (2016), Tables 4-11 (N, E, H position and roll, pitch, heading errors).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins.mechanisation import dcm_to_euler
from ilocalg.units import wrap_angle_rad

__all__ = ["nav_errors", "error_stats", "heading_error_with_lag_deg", "POS_AXES", "ATT_AXES"]

POS_AXES = ("N", "E", "H")
ATT_AXES = ("Roll", "Pitch", "Heading")


def nav_errors(pos_n_m, mat_nb, pos_true_n_m, mat_true_nb) -> pd.DataFrame:
    """Per-epoch errors (estimate - truth): N, E, H in metres and roll, pitch, heading in degrees."""
    pos, pt = np.asarray(pos_n_m, dtype=float), np.asarray(pos_true_n_m, dtype=float)
    if pos.shape != pt.shape or pos.ndim != 2 or pos.shape[1] != 3:
        raise ValueError(f"pos_n_m and pos_true_n_m must both be (N, 3), got {pos.shape} and {pt.shape}")
    d = pos - pt
    e = dcm_to_euler(mat_nb)
    et = dcm_to_euler(mat_true_nb)
    da = np.rad2deg(wrap_angle_rad(e - et))
    return pd.DataFrame({"N": d[:, 1], "E": d[:, 0], "H": d[:, 2],
                         "Roll": da[:, 0], "Pitch": da[:, 1], "Heading": da[:, 2]})


def error_stats(err: pd.DataFrame) -> dict[str, dict[str, float]]:
    """``{"max": {axis: ..}, "rms": {..}, "std": {..}}`` over the rows of :func:`nav_errors` output.

    Max is the largest absolute error, RMS the root mean square, STD the standard deviation.
    """
    a = err.to_numpy(dtype=float)
    return {
        "max": dict(zip(err.columns, np.max(np.abs(a), axis=0), strict=True)),
        "rms": dict(zip(err.columns, np.sqrt(np.mean(a**2, axis=0)), strict=True)),
        "std": dict(zip(err.columns, np.std(a, axis=0), strict=True)),
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
