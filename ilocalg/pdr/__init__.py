"""Pedestrian dead reckoning: step detection, step length, heading, dead reckoning.

Every step detector returns a DataFrame with one row per detected step and at least the columns
``i_peak`` (int sample index), ``t_s`` (time of the step, s), ``a_max_mps2`` and ``a_min_mps2``
(the step's largest and smallest acceleration, used by the step-length models).

Modules
-------
``sam``            i-Loc SAM: vertical acceleration, eight wave features, range classifier (eq. 8-15)
``peak_window``    004's |a| sliding-window peak detector with a threshold and a 0.2-2 s window
``robust``         the toolkit's best detector for real phones (resample, low-pass, prominence, bouts)
``step_length``    Weinberg, Kim, 004 eq. (4), i-Loc SLM regressions (eq. 16-17)
``heading``        i-Loc WDM (eq. 18-19) and gyro-integrated heading
``dead_reckoning`` position update (i-Loc eq. 22, 004 eq. 5-6)
``signals``        input checks, resampling, sliding extrema
``filters``        moving average and Savitzky-Golay (003 eq. 3.5-3.6; written in the PSO slice)
``sign_change``    003's slope-sign-change detector with the +-RMS band (Fig 3.9; PSO slice)
"""

from ilocalg.pdr.dead_reckoning import PDR, dead_reckon
from ilocalg.pdr.filters import moving_average, rms, savitzky_golay, savitzky_golay_coeffs
from ilocalg.pdr.heading import WDM, axis_yaw_rad, gyro_heading_theta_rad, heading_theta_rad, wdm_rotation, wdm_yaw_rad
from ilocalg.pdr.peak_window import PeakWindowDetector, detect_steps_peak_window
from ilocalg.pdr.robust import ROBUST_DEFAULTS, RobustStepDetector, detect_steps_robust
from ilocalg.pdr.sam import (
    SAM_FEATURES,
    SAM_RANGES_PAPER,
    SAMDetector,
    detect_steps_sam,
    learn_feature_ranges,
    sam_waves,
    vertical_horizontal_mps2,
)
from ilocalg.pdr.sign_change import STEP_COLUMNS, detect_steps_sign_change, slope_sign_extrema
from ilocalg.pdr.signals import magnitude_mps2, resample_uniform
from ilocalg.pdr.step_length import (
    SLM,
    StepLengthFit,
    fit_slm,
    fit_weinberg_k,
    kim_length_m,
    luo_length_m,
    slm_design,
    slm_length_m,
    weinberg_length_m,
)

__all__ = [
    "PDR",
    "ROBUST_DEFAULTS",
    "RobustStepDetector",
    "SAMDetector",
    "SAM_FEATURES",
    "SAM_RANGES_PAPER",
    "SLM",
    "STEP_COLUMNS",
    "StepLengthFit",
    "PeakWindowDetector",
    "WDM",
    "axis_yaw_rad",
    "dead_reckon",
    "detect_steps_peak_window",
    "detect_steps_robust",
    "detect_steps_sam",
    "detect_steps_sign_change",
    "fit_slm",
    "fit_weinberg_k",
    "gyro_heading_theta_rad",
    "heading_theta_rad",
    "kim_length_m",
    "learn_feature_ranges",
    "luo_length_m",
    "magnitude_mps2",
    "moving_average",
    "resample_uniform",
    "rms",
    "sam_waves",
    "savitzky_golay",
    "savitzky_golay_coeffs",
    "slm_design",
    "slm_length_m",
    "slope_sign_extrema",
    "vertical_horizontal_mps2",
    "wdm_rotation",
    "wdm_yaw_rad",
    "weinberg_length_m",
]
