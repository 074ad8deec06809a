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

__all__ = ["nav_errors", "error_stats", "POS_AXES", "ATT_AXES"]

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
