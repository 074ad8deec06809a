"""PTS, the i-Loc pedestrian trajectory system: SAM steps, SLM lengths, WDM headings for one sensor log.

The pipeline of Chiu (2013) ch. 4 on a sensor log (the package's DataFrame indexed by time):
steps by SAM with learned ranges (:func:`ilocalg.pdr.sam.detect_steps_sam`), each step's length by
the quadratic SLM (:func:`ilocalg.pdr.step_length.slm_length_m`, negative lengths clipped to 0),
its heading by WDM at the step's peak (:func:`ilocalg.pdr.heading.log_headings_rad`; the
gyro-integrated heading beside it). Dead reckoning of the result is
:func:`ilocalg.pdr.dead_reckoning.dead_reckon`.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1-4.4, eq. (8)-(19), Figs 17-18.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.sam import detect_steps_sam
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import slm_length_m

__all__ = ["pts_steps", "pts_filter_inputs"]


def pts_steps(imu: pd.DataFrame, ranges: pd.DataFrame, slm_p, rest_s: float = 0.0,
              headings: dict | None = None) -> pd.DataFrame:
    """Steps of one sensor log with their SLM length and WDM (and gyro) heading.

    Parameters
    ----------
    imu : DataFrame
        Sensor log indexed by time (s) with accelerometer, gyroscope and magnetometer columns.
    ranges : DataFrame
        SAM feature ranges (:func:`ilocalg.pdr.sam.learn_feature_ranges`).
    slm_p : array_like, shape (6,)
        Quadratic SLM coefficients (:func:`ilocalg.pdr.step_length.fit_slm`), m.
    rest_s : float
        Time at rest at the start of the log, s (starts the gyro heading).
    headings : dict, optional
        Per-sample headings already computed by :func:`ilocalg.pdr.heading.log_headings_rad`.

    Returns
    -------
    DataFrame
        The SAM step table with ``length_m`` (m, >= 0), ``theta_rad`` (WDM) and ``theta_gyr_rad``
        (rad, from the map x axis, counter-clockwise) added.
    """
    acc, t = acc_from_log(imu)
    heads = log_headings_rad(imu, rest_s) if headings is None else headings
    steps = detect_steps_sam(acc, t, ranges)
    i = steps["i_peak"].to_numpy()
    lengths = np.maximum(slm_length_m(steps["A"], steps["X1"], slm_p), 0.0)
    return steps.assign(length_m=np.asarray(lengths), theta_rad=heads["WDM"][i], theta_gyr_rad=heads["gyro"][i])


def pts_filter_inputs(imu: pd.DataFrame, ranges: pd.DataFrame, slm_p, rest_s: float = 0.0,
                      headings: dict | None = None) -> dict:
    """PTS on one sensor log (:func:`pts_steps`) as a step filter's inputs.

    Returns
    -------
    dict
        ``state_t_s`` (n + 1: the log's start, then each detected step), ``step_m`` and ``theta_rad`` (n, WDM).
    """
    st = pts_steps(imu, ranges, slm_p, rest_s, headings=headings)
    return {"state_t_s": np.concatenate([[imu.index[0]], st["t_s"].to_numpy()]),
            "step_m": st["length_m"].to_numpy(), "theta_rad": st["theta_rad"].to_numpy()}
