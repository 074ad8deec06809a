"""Inertial navigation: strapdown mechanisation, the 21-state error-state EKF with pedestrian
constraints, RTS / online-window smoothing, and the Hartmann et al. 15-state IMU + video EKF.

Frames and units
----------------
The frames are defined once in the :mod:`ilocalg` package docstring: navigation frame ``n``
(local-level east-north-up, metres, fixed to the site), INS body frame ``b`` (x forward, y left,
z up) and the phone's sensor frame ``p`` (Android axes), related by
:data:`ilocalg.ins.mechanisation.MAT_PHONE_TO_BODY`. Earth rotation and transport rate are
neglected (indoor scale: far below phone gyro errors); gravity is constant, ``[0, 0, -9.80665]``
m/s^2. Attitude: ``mat_nb`` (body -> nav), Z-Y-X Euler angles ``(roll, pitch, yaw)`` in rad, yaw
counter-clockwise from east. IMU logs are arrays in the body frame: ``t_s`` (N,), ``gyr_b_radps``
(N, 3), ``acc_b_mps2`` (N, 3, specific force); sample k is the mean over ``[t_k, t_{k+1})`` and
sampling may be irregular (phones).

Modules
-------
``mechanisation``  strapdown integration and attitude helpers
``eskf``           21-state closed-loop error-state EKF (Liao et al. 2016, eq. 1-6) and its
                   measurement protocol (innovation, H, R) with PositionFix, NavVelocity, BodyVelocity
``constraints``    step epochs, WVC walking speed (eq. 7), NHC, ZUPT measurement sets
``smoother``       RTS over the whole run and the online fixed-window smoother (eq. 8-10)
``hartmann``       15-state Euler-angle EKF fusing an IMU with marker video tracking (Hartmann et al.
                   2010 as cited by Yeh & Huang, eq. 6-29)
``evaluate``       error statistics in the paper's table layout, online-window scoring
``paper_values``   published values of Liao et al. (2016) and Hartmann et al. (2010), as labelled references
``pipeline``       the paper's processing chain for a phone walk (measurement sets, levelling, filter)
"""

from ilocalg.ins.constraints import (
    WVC_REFERENCE_DEFAULTS,
    detect_stairs_baro,
    detect_stationary,
    nhc_updates,
    step_epochs,
    step_frequency_hz,
    walking_speed_mps,
    wvc_updates,
    zupt_updates,
)
from ilocalg.ins.eskf import (
    N_STATES,
    BodyVelocity,
    EskfConfig,
    EskfResult,
    Measurement,
    NavVelocity,
    PositionFix,
    body_velocity_rows,
    check_covariance,
    correct_nav,
    correct_sensors,
    covariance_chunk,
    eskf_predict,
    initial_covariance,
    joseph_update,
    joseph_update_stacked,
    nav_velocity_rows,
    position_rows,
    process_noise_diag,
    run_eskf,
    run_eskf_batch,
    same_run,
    transition_matrices,
    transition_matrix,
)
from ilocalg.ins.evaluate import (
    AXES,
    WindowSweep,
    error_stats,
    heading_error_with_lag_deg,
    nav_errors,
    window_sweep,
    window_sweep_tables,
    window_sweeps,
)
from ilocalg.ins.hartmann import (
    HartmannEKF,
    HartmannResult,
    hartmann_correct,
    hartmann_f,
    hartmann_jacobians,
    hartmann_predict,
    run_hartmann,
)
from ilocalg.ins.mechanisation import (
    GRAVITY_N_MPS2,
    MAT_PHONE_TO_BODY,
    coarse_level,
    dcm_to_euler,
    dcm_to_rotvec,
    euler_to_dcm,
    mechanise,
    phone_to_body,
    rotvec_to_dcm,
    rotvecs_to_dcm,
    skew,
    strapdown,
)
from ilocalg.ins.pipeline import PhoneFilterSettings, body_imu_from_log, run_walk, run_walks, walk_updates
from ilocalg.ins.smoother import (
    ErrorStateINS,
    EskfSmoothResult,
    eskf_rts_smooth,
    eskf_rts_smooth_grids,
    online_window_smooth,
    rts_gains,
    rts_gains_shared,
    window_ends,
)

__all__ = [
    "AXES",
    "WindowSweep",
    "window_sweep",
    "window_sweep_tables",
    "window_sweeps",
    "GRAVITY_N_MPS2",
    "MAT_PHONE_TO_BODY",
    "phone_to_body",
    "HartmannEKF",
    "HartmannResult",
    "PhoneFilterSettings",
    "body_imu_from_log",
    "coarse_level",
    "hartmann_correct",
    "heading_error_with_lag_deg",
    "hartmann_f",
    "hartmann_jacobians",
    "hartmann_predict",
    "rotvecs_to_dcm",
    "run_hartmann",
    "run_walk",
    "run_walks",
    "transition_matrices",
    "walk_updates",
    "N_STATES",
    "WVC_REFERENCE_DEFAULTS",
    "EskfConfig",
    "ErrorStateINS",
    "EskfResult",
    "EskfSmoothResult",
    "Measurement",
    "PositionFix",
    "NavVelocity",
    "BodyVelocity",
    "correct_nav",
    "correct_sensors",
    "body_velocity_rows",
    "dcm_to_euler",
    "dcm_to_rotvec",
    "detect_stationary",
    "detect_stairs_baro",
    "check_covariance",
    "covariance_chunk",
    "step_epochs",
    "error_stats",
    "eskf_predict",
    "euler_to_dcm",
    "initial_covariance",
    "joseph_update",
    "joseph_update_stacked",
    "strapdown",
    "mechanise",
    "nav_errors",
    "nav_velocity_rows",
    "nhc_updates",
    "online_window_smooth",
    "position_rows",
    "process_noise_diag",
    "rotvec_to_dcm",
    "rts_gains",
    "rts_gains_shared",
    "eskf_rts_smooth",
    "eskf_rts_smooth_grids",
    "run_eskf",
    "run_eskf_batch",
    "same_run",
    "skew",
    "step_frequency_hz",
    "transition_matrix",
    "walking_speed_mps",
    "window_ends",
    "wvc_updates",
    "zupt_updates",
]
