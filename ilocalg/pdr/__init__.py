"""Pedestrian dead reckoning: step detection, step length, heading, dead reckoning.

Every step detector returns a DataFrame with one row per detected step and at least the columns
``i_peak`` (int sample index), ``t_s`` (time of the step, s), ``a_max_mps2`` and ``a_min_mps2``
(the step's largest and smallest acceleration, used by the step-length models).
"""

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
    "SLM",
    "StepLengthFit",
    "fit_slm",
    "fit_weinberg_k",
    "kim_length_m",
    "luo_length_m",
    "slm_design",
    "slm_length_m",
    "weinberg_length_m",
]
