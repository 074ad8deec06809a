"""Kalman fusion of detected steps with Wi-Fi fixes (the i-Loc step filter), smoothers, fix noise.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Ch. 5, eq. (20)-(26), Tables 4-5.
"""

from ilocalg.fusion.align import AlignedFixes, fixes_at_states
from ilocalg.fusion.fingerprint_adjust import fingerprint_adjusted_track
from ilocalg.fusion.noise import fix_covariance_from_spread
from ilocalg.fusion.smoothers import SmoothResult, fixed_lag_smooth, rts_smooth
from ilocalg.fusion.step_kf import (
    PAPER_TABLE4_SIGMA_SL_VAR_M2,
    PAPER_TABLE4_STEP_M,
    PAPER_TABLE5_SIGMA_RF_VAR_M2,
    StepKalmanFilter,
    StepKFResult,
    filter_walk,
    filter_walks,
    innovation,
    kf_predict_step,
    kf_update,
    nis_gate,
    sigma_sl_paper_m,
    step_control,
    step_process_noise,
)
from ilocalg.fusion.synthetic import SyntheticWalk, straight_walk

__all__ = [
    "AlignedFixes",
    "fixes_at_states",
    "fingerprint_adjusted_track",
    "PAPER_TABLE4_SIGMA_SL_VAR_M2",
    "PAPER_TABLE4_STEP_M",
    "PAPER_TABLE5_SIGMA_RF_VAR_M2",
    "SmoothResult",
    "StepKFResult",
    "StepKalmanFilter",
    "SyntheticWalk",
    "filter_walk",
    "filter_walks",
    "fix_covariance_from_spread",
    "fixed_lag_smooth",
    "innovation",
    "kf_predict_step",
    "kf_update",
    "nis_gate",
    "rts_smooth",
    "sigma_sl_paper_m",
    "step_control",
    "step_process_noise",
    "straight_walk",
]
