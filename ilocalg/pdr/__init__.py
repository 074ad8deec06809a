"""Pedestrian dead reckoning: step detection, step length, heading, dead reckoning.

Every step detector takes ``(acc_mps2, t_s)`` (specific force, m/s^2, shape (n, 3); times, s) and
returns a DataFrame with one row per detected step and at least the columns ``i_peak`` (int sample
index), ``t_s`` (time of the step, s), ``a_max_mps2`` and ``a_min_mps2`` (the step's largest and
smallest acceleration, used by the step-length models). Every detector is registered by name in
:data:`STEP_DETECTORS` (:mod:`ilocalg.pdr.registry`); experiments and the command line call them
through :func:`detect_steps` / :func:`count_steps`. A new detector is one
``@register_step_detector("name")`` in its module.

Signals are passed before times everywhere: ``f(signal, t_s, ...)``.

Modules
-------
``registry``       the step-detector registry (name -> function) and :func:`count_steps`
``sam``            i-Loc SAM: vertical acceleration, eight wave features, range classifier (eq. 8-15)
``peak_window``    Luo et al.'s |a| sliding-window peak detector with a threshold and a 0.2-2 s window
``robust``         the toolkit's best detector for real phones (resample, low-pass, prominence, walk detection
                   at bout ends by stride auto-correlation, bouts)
``sign_change``    Chao's slope-sign-change detector with the +-RMS band (Fig 3.9)
``step_length``    Weinberg, Kim, Luo et al. eq. (4), i-Loc SLM regressions (eq. 16-17), k from a distance
``k_factor``       learning the Weinberg k of a walker by PSO against a reference distance (Chao eq. 4.4)
``heading``        i-Loc WDM (eq. 18-19) and gyro-integrated heading
``pts``            i-Loc PTS: SAM steps + SLM lengths + WDM headings of one sensor log
``dead_reckoning`` position update (i-Loc eq. 22, Luo et al. eq. 5-6)
``signals``        input checks, resampling, sliding extrema, moving mean, gravity low-pass and projection
``filters``        the moving-average and Savitzky-Golay pre-filters of Chao (2008) eq. 3.5-3.6
``step_evaluate``  detectors on recordings with counted steps: leave-one-recording-out tuning, diagnosis

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
"""

from ilocalg.pdr.dead_reckoning import PDR, dead_reckon
from ilocalg.pdr.filters import moving_average, rms, savitzky_golay, savitzky_golay_coeffs
from ilocalg.pdr.heading import (
    WDM,
    axis_yaw_rad,
    gyr_heading_theta_rad,
    heading_theta_rad,
    log_headings_rad,
    wdm_rotation,
    wdm_yaw_rad,
)
from ilocalg.pdr.k_factor import PSO_SETTINGS_PAPER, closed_form_k, learn_k, step_factors
from ilocalg.pdr.norm_peaks import detect_steps_norm_peaks
from ilocalg.pdr.peak_window import PeakWindowDetector, detect_steps_peak_window
from ilocalg.pdr.pts import pts_steps
from ilocalg.pdr.registry import STEP_DETECTORS, count_steps, detect_steps, register_step_detector, step_detector
from ilocalg.pdr.robust import ROBUST_DEFAULTS, RobustStepDetector, detect_steps_find_peaks, detect_steps_robust
from ilocalg.pdr.sam import (
    SAM_FEATURES,
    SAM_RANGES_PAPER,
    SAMDetector,
    detect_steps_sam,
    learn_feature_ranges,
    sam_waves,
    seconds_to_samples,
    vertical_horizontal_mps2,
)
from ilocalg.pdr.sign_change import STEP_COLUMNS, detect_steps_sign_change, slope_sign_extrema
from ilocalg.pdr.signals import (
    acc_from_log,
    along_gravity_mps2,
    gravity_lowpass_mps2,
    magnitude_mps2,
    moving_mean,
    moving_mean_time,
    resample_uniform,
)
from ilocalg.pdr.step_length import (
    SLM,
    StepLengthFit,
    fit_luo_k,
    fit_scale,
    fit_slm,
    fit_step_length_models,
    fit_weinberg_k,
    k_from_distance,
    kim_length_m,
    kim_mean_abs_mps2,
    luo_length_m,
    luo_steps,
    slm_design,
    slm_length_m,
    step_lengths_m,
    weinberg_length_m,
)

__all__ = [
    "PDR",
    "PSO_SETTINGS_PAPER",
    "STEP_DETECTORS",
    "acc_from_log",
    "along_gravity_mps2",
    "closed_form_k",
    "count_steps",
    "detect_steps",
    "detect_steps_find_peaks",
    "detect_steps_norm_peaks",
    "fit_luo_k",
    "fit_scale",
    "fit_step_length_models",
    "gravity_lowpass_mps2",
    "k_from_distance",
    "kim_mean_abs_mps2",
    "learn_k",
    "log_headings_rad",
    "luo_steps",
    "moving_mean",
    "moving_mean_time",
    "register_step_detector",
    "step_detector",
    "step_factors",
    "pts_steps",
    "step_lengths_m",
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
    "gyr_heading_theta_rad",
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
    "seconds_to_samples",
    "slm_design",
    "slm_length_m",
    "slope_sign_extrema",
    "vertical_horizontal_mps2",
    "wdm_rotation",
    "wdm_yaw_rad",
    "weinberg_length_m",
]
