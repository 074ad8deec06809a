"""How the toolkit reads Yeh & Huang's survey on Hartmann et al.'s IMU + video-tracking EKF: the readings of
experiment ``ins_hartmann``, as data.

One row per modelling choice (:mod:`ilocalg.papers._reading_rows`): the survey's line, what it says, what the
code does, and the source of each value the text does not give; the run's tracker noise fills the rows
(:func:`readings`). Line numbers are lines of the survey's text copy (``/work/shared/papers/002_bd9d55b2d42bda80.txt``).

References
----------
Yeh, C.-H., Huang, W.-L. (advisor Huang, C.-C.), Positioning by combining images and inertial sensors,
teaching report, National Kaohsiung University of Applied Sciences (undated).
Hartmann, B., Link, N., Trommer, G. F. (2010). Indoor 3D position estimation using low-cost inertial
sensors and marker-based video-tracking. IEEE/ION PLANS, 319-326.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.papers._reading_rows import Fmt, render

__all__ = ["ROWS", "readings"]

ROWS = (
    ("EKF", "survey eq. (6)-(29)", "15-state EKF: Euler angles, position, velocity, gyro and accelerometer "
     "biases; yaw + position from the tracker", "ilocalg.ins.hartmann.run_hartmann; Joseph-form update "
     "(algebraically eq. 29)", "survey"),
    ("IMU", "survey sec. 5.1", "ADIS16350 at 400 Hz, 0.4 deg/s and 0.05 m/s^2 noise", "as stated", "survey"),
    ("tracker noise (an input)", "L218", "position precision in the millimetre range",
     Fmt("sd {x_mm:g} / {y_mm:g} / {z_mm:g} mm (x / y / z depth), {yaw_deg:g} deg yaw"),
     "assumption (no published value for this tracker); Table 2's mean deviation largely echoes it, so it is "
     "shown as a sensitivity curve: tracker_noise (mean deviation for the noise x 0.5-4, the paper's value "
     "beside) and tracker_noise_implied (the noise at which the curve meets the paper's mean deviation: a "
     "reading, not an input)"),
    ("tracker rate and outages", "Table 2 (VT measurements)", "5.82 Hz mean, longest outage 2.24 s, "
     "21.5 outages over 1 s (input statistics)", "10 frames/s minus blur / random losses, plus Poisson "
     "outages of 1 s + Exp(0.34 s), 21.5 per 120 s", "set from Table 2 (sequence length not given, 120 s "
     "assumed), so the Table 2 rate / outage rows are inputs, not reproductions (their comparison notes say "
     "so); no published marker-tracking outage statistics used: outage_sensitivity sweeps the rate and the "
     "excess duration x 0.5 and x 2 and shows what the deviations do"),
    ("deviation metric", "Table 2 (mean / maximal deviation to VT)", "deviation of the EKF position to the "
     "VT (how and when it is taken is not said)", "the EKF prediction just before each tracker fix minus "
     "that fix (an interpretation); prediction minus truth and the after-correction deviation beside it",
     "interpretation"),
    ("sequences", "Table 2", "6 test sequences of hand motion", "6 simulated sequences of 120 s",
     "duration assumed"),
)


def readings(vt_sd) -> pd.DataFrame:
    """The readings table of one run with the tracker noise ``vt_sd`` (yaw rad, x, y, z m)."""
    return render(ROWS, "Yeh & Huang survey (Hartmann et al. 2010), ", x_mm=vt_sd[1] * 1e3, y_mm=vt_sd[2] * 1e3,
                  z_mm=vt_sd[3] * 1e3, yaw_deg=np.rad2deg(vt_sd[0]))
