"""Readings of the i-Loc thesis (Chiu 2013), as data: one table per experiment of its chapters 3-5.

Each table has one row per modelling choice (:data:`ilocalg.papers.READINGS_COLUMNS`: the choice, the
thesis's line, what the text says, what the code does, the source of a value the text does not give).
Where the row depends on the run's choices, the text is a :meth:`str.format` template filled by
:func:`readings` with the values the experiment passes (e.g. ``{q_range[0]:.0%}``, the world's
parameters ``{wp[...]}`` and their sources ``{ws[...]}``); the experiments only compute.

References
----------
Chiu, P.-J. (2013). Implement an Integrated Indoor Positioning System (i-Loc). M.S. thesis,
National Chiao Tung University.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers import PAPERS
from ilocalg.papers._reading_rows import fill

__all__ = ["READINGS", "readings"]

_T = PAPERS["iloc"]

# The gait world's row, shared by the PDR experiments: ``gait_code``, ``gait_source`` from
# ilocalg.sim.gait.world_reading(world).
_GAIT = ("gait world", "", "silent (the thesis's walkers are not published)", "{gait_code}", "{gait_source}")
_ROUTE = ("the floor's 28-point route 4 m apart", "2 m grid of L295; Fig 2 missing")
_TEST_WALKERS = ("test walkers", f"{_T}, L515", "users walking the route",
                 "new simulated walkers, not the training walkers", "gait model: data/gait")
_SAM_RANGES = ("SAM ranges", f"{_T}, L399", "5 % and 95 % points of the training features' CDFs")

#: experiment -> rows (choice, paper_line, text_says, code_does, source), templates where the run decides.
READINGS = {
    # ch. 3: values wp, sources ws of ilocalg.sim.iloc_floor.world_params/world_sources(world), p = PARAM_SOURCES
    "wifi_iloc": (
        ("floor plan", "", "Fig 2 (missing from the text)",
         "assumed ring corridor 36 m x 20 m + stair corridor, offices in 8 m bays", "assumption (data/iloc_floor)"),
        ("training points", f"{_T}, L295", "63 points 2 m apart, 300 scans each at different times",
         "63 points 2 m apart; 300 scans in sessions of 30 (60 in fast mode)", "{p[scans_per_session]}"),
        ("test route", f"{_T}, L295, L515", "28 test points that are training points, 4.11 m apart",
         "28 ring points 4.0 m apart (every second 2 m point), 108 m", "2 m grid of L295"),
        ("APs per scan", f"{_T}, L295", "4-18 APs per scan", "AP counts and detection calibrated to it",
         "{p[n_aps_floor]}"),
        ("wall losses", "", "silent",
         "light {wp[light_wall_db]:.3g} dB, heavy {wp[heavy_wall_db]:.3g} dB, floor {wp[floor_db]:.3g} dB "
         "({world} world)", "{ws[heavy_wall_db]}"),
        ("survey vs test", f"{_T}, L295", "signals drift; points near windows and corners drift more",
         "test session on another day: per-AP drift {wp[drift_sd_db]:.3g} dB, body shadowing "
         "{wp[body_loss_db]:.3g} dB, device offset {wp[device_offset_db]:.3g} dB ({world} world)",
         "{ws[drift_sd_db]}; {p[body_loss_db]}; {p[device_offset_db]}"),
        ("radio world", "", "silent (the thesis's radio map is not published)",
         "{world} world: path-loss exponent {wp[path_loss_exponent]:.3g}, shadowing {wp[shadow_sd_db]:.3g} dB, "
         "fast fading {wp[fade_sd_db]:.3g} dB, detection at {wp[detect_dbm]:.4g} dBm, miss {wp[miss_p]:.3g}",
         "{ws[path_loss_exponent]}; {ws[shadow_sd_db]}; {ws[fade_sd_db]}; {ws[detect_dbm]}; {ws[miss_p]}"),
        ("test scans per point", "", "silent", "20 standing scans per test point facing the walking direction "
         "(5 in fast mode)", "assumption"),
        ("RADAR database", f"{_T}, L283, L287", "every stored scan of every point; N nearest training points",
         "query vs every stored scan; a point's distance is its nearest scan; N = 3 nearest points",
         "mean map shown as 'Simplified-RADAR (mean map)'"),
        ("RADAR k, N", f"{_T}, L287, L297", "k strongest APs (k = 5 best), N = 3", "k = 5, N = 3", ""),
        ("Horus", f"{_T}, L329, L331", "per-point RSSI histograms of every scan, k strongest APs",
         "1 dB histograms of every scan, k = 5, probability floor 1e-3", "probability floor: assumption"),
        ("KNN", "Luo et al. 2017, eq. 1-2", "Manhattan, K = 5 (their paper)", "per-point mean map, K = 5",
         "not in the i-Loc thesis"),
    ),
    # ch. 4.1 SAM
    "pdr_step_features": (
        ("training walks", f"{_T}, L399", "walkers of different builds, 15 steps at each fixed length 40-80 cm",
         "8 simulated walkers x 15 steps x 40, 50, 60, 70, 80 cm", "gait model: data/gait"),
        ("feature ranges", f"{_T}, L399", "5 % and 95 % points of each feature's CDF",
         "5-95 % quantiles (1-99 % and 0-100 % shown beside)", ""),
        ("tested features", f"{_T}, L385-397", "A2, A, T1, T2, T, X1, I in range (A1 listed in Table 1, not tested)",
         "the same seven tests, all must pass", ""),
        ("peak window", f"{_T}, L357", "W_peak = 0.25 s", "no larger value within 0.125 s either side", ""),
        ("valley window", f"{_T}, L357, Table 1 (L424-425)", "valleys within W_wave / 2 = 0.25 s, yet T1 and T2 "
         "reach 0.35-0.40 s", "valleys within 0.5 s either side (the literal window cannot give Table 1's T1, T2)",
         ""),
        ("window in samples", f"{_T}, L357", "N = floor(W_wave f / 2) - 1",
         "seconds snapped to 1e-3 samples then rounded, so 49.99999 and 50.000001 Hz logs agree", ""),
        ("sample rate", "", "silent", "50 Hz", "assumption; X1 scales with it: swept in rate_sweep"),
        ("count test", f"{_T}, L430", "8 testers x 100 steps, 4.13 % error", "8 walkers x 100 natural steps; "
         "training walkers and new walkers", "the text does not say whether the testers trained SAM"),
        ("real data", "", "not in the thesis", "Oxford step counter, in-hand optimisation recordings, leave one "
         "recording out, 5-95 % ranges, resampled to 50 Hz", "Oxford step counter data set (CC BY 4.0)"),
        _GAIT,
    ),
    # ch. 4.2 SLM
    "pdr_step_length": (
        ("training walks", f"{_T}, L399, L478", "walkers at fixed lengths 40-80 cm", "8 simulated walkers x 15 steps "
         "x 40-80 cm", "gait model: data/gait"),
        ("SLM", f"{_T}, eq. 16-17, Table 3", "linear and quadratic regression on A and X1, fitted in cm",
         "least squares on the training steps' A, X1 (cm)", ""),
        ("SAM ranges", f"{_T}, L399", "5 % and 95 % points", "{q_range[0]:.0%}-{q_range[1]:.0%}; 1-99 % shown beside",
         ""),
        ("fixed-length test", f"{_T}, L478", "8 testers at 40-80 cm, mean error 18.43 %",
         "training walkers and new walkers at 40-80 cm", "the text does not say who the testers were"),
        ("free walk", f"{_T}, L478", "8 testers walk 20 m freely, 96.41 % accuracy", "20 m straight, natural steps",
         ""),
        ("Table 4 units", f"{_T}, L578, L602-605", "variances of the step length error, no unit",
         "table4: relative-error variance and m^2 variance per target length, both shown", "L478 supports relative"),
        _GAIT,
    ),
    # ch. 4.3-4.4 WDM and PTS; misalign_sd_deg, misalign_source from the gait world
    "pdr_heading_trajectory": (
        ("route", f"{_T}, L515", "28 test points marked on the floor, 4.11 m apart",
         _ROUTE[0] + ", 108 m (shared with notebooks 01, 07)", _ROUTE[1]),
        _TEST_WALKERS,
        (*_SAM_RANGES, "{q_range[0]:.0%}-{q_range[1]:.0%} quantiles; 1-99 % shown as 'PTS (SAM 1-99 %)'", ""),
        ("valley window", f"{_T}, L357, Table 1 (L424-425)", "W_wave / 2 = 0.25 s either side, yet T1, T2 reach "
         "0.35-0.40 s", "0.5 s either side (the literal window cannot produce Table 1's T1, T2)", ""),
        ("WDM", f"{_T}, eq. 18-19", "yaw from gravity and the magnetic field; magnetic north",
         "phone y axis yaw from 1 s gravity and 0.5 s field means; no declination or hard-iron correction", ""),
        ("phone misalignment", "", "silent (the phone is assumed to point where the walker goes)",
         "per walker N(0, {misalign_sd_deg:.3g} deg)", "{misalign_source}; switched off in wdm_sensitivity"),
        ("hard-iron residual", "", "silent", "per walker N(0, 2 uT) per axis", "assumption; switched off in "
         "wdm_sensitivity"),
        ("declination", "", "silent (magnetic north)", "-4.5 deg at the site, not corrected by WDM",
         "WMM2010 for Hsinchu, 2013 (approximate); corrected in wdm_sensitivity"),
        ("indoor magnetic disturbances", f"{_T}, sec. 4.3", "the field may deviate slightly",
         "1.5 blobs per 100 m^2, N(0, 12 uT)", "assumption (data/gait)"),
        ("sample rate", "", "silent", "50 Hz", "assumption (X1 scales with it)"),
        _GAIT,
    ),
    # ch. 5 Kalman filter; scan_interval_s resolved, scan_text and scan_source from ilocalg.sim.iloc_scenario,
    # q_text from TABLE4_READING_TEXT
    "fusion_iloc_kf": (
        ("route", f"{_T}, L515, L588", "28 test points 4.11 m apart, also the Wi-Fi test points",
         _ROUTE[0] + " (shared with notebooks 01, 05)", _ROUTE[1]),
        ("Wi-Fi fix", f"{_T}, L777, L779", "the phone detects the Wi-Fi signals periodically (L777); Wi-Fi "
         "positions from scans taken while the user walks",
         "periodic scans while walking, one every {scan_interval_s:g} s; {scan_text}; a fix is available only "
         "when its scan is stamped and enters the KF at the latest step state then (causal); a new session "
         "(drift) per walk", "{scan_source}; the uniform-within-a-scan model (0-3 s) swept in latency_sweep"),
        ("scoring", f"{_T}, L588, Fig 23", "errors at the 28 test points",
         "at each test point's passing time: each track's latest state then; Wi-Fi only = the latest fix "
         "available then (earlier versions started a scan exactly at each test point: an oracle)", "causal"),
        ("R", f"{_T}, L586-588, Table 5", "R = sigma_RF^2 I, per test point, from the Wi-Fi experiment at the "
         "28 points", "per-point error variance of the chapter 3 test session (standing scans, another day); a "
         "fix taken anywhere gets the R of the test point nearest the fix itself",
         "Table 5 as R and a constant R: labelled alternatives"),
        ("Q", f"{_T}, L574-578, Table 4 (L602-605)", "Q = sigma_SL^2 [cos^2, sc; sc, sin^2]; Table 4 prints no unit",
         "Table 4 read as {q_text}; the other reading shown", "L478: mean SLM error 18.43 % = sqrt(0.054) sqrt(2/pi)"),
        ("start", f"{_T}, L735, L792-795", "initial position from Wi-Fi or set by hand",
         "the first periodic scan (at the start of the log) gives x0, P0 = the R of its nearest point; the steps "
         "taken before it ends are dead-reckoned from it; PTS also from the true start", ""),
        (*_SAM_RANGES, "{q_range[0]:.0%}-{q_range[1]:.0%} quantiles of fixed-length training walks", ""),
        _TEST_WALKERS,
        ("F, B, H", f"{_T}, eq. 22-23", "F = I, B = [cos, sin]^T, H = I", "as the text", ""),
        ("update", f"{_T}, eq. 24-26", "Kalman gain, Joseph-form covariance", "as the text", ""),
        ("error budget", "beyond the thesis", "no error budget",
         "the main KF and PTS rerun with one error source replaced by the truth at a time (Wi-Fi fix error, "
         "scan lag, step detection, step length, heading): ilocalg.fusion.budget", "toolkit"),
    ),
}

#: How each reading of Table 4 (no unit printed) enters Q (fusion_iloc_kf's ``table4_reading``).
TABLE4_READING_TEXT = {"relative": "relative variances (sigma = sqrt(var) x step)", "m2": "m^2"}

def readings(experiment: str, **values) -> pd.DataFrame:
    """The readings table of one of the thesis's experiments (:data:`READINGS`), filled with ``values``."""
    if experiment not in READINGS:
        raise ValueError(f"no i-Loc readings for {experiment!r}; one of {sorted(READINGS)}")
    if experiment == "fusion_iloc_kf" and "table4_reading" in values:
        values["q_text"] = TABLE4_READING_TEXT[values["table4_reading"]]
    return fill(READINGS[experiment], **values)
