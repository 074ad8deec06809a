"""Readings of Luo et al. 2017 (fingerprint + PDR), as data: the table of experiment ``fusion_knn_pdr``.

One row per modelling choice (:data:`ilocalg.papers.READINGS_COLUMNS`), line numbers of the paper's text
copy. Templates (:meth:`str.format`) carry the run's choices: the adjustment weight and how it was chosen,
the peak detector, the survey scans, and the scan model's text and source
(:mod:`ilocalg.sim.iloc_scenario`), filled by :func:`readings`.

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers._reading_rows import fill

__all__ = ["READINGS", "PRINCIPLED_WEIGHT_TEXT", "readings"]

_P = "Luo et al. 2017, "

#: The clause added to the combination's row when the weight is the inverse-variance one (``principled``).
PRINCIPLED_WEIGHT_TEXT = (
    " (the steady-state inverse-variance weight: PDR variance accumulated over one scan interval from the "
    "training walks' step-length and heading errors, against the KNN fix variance of the standing "
    "calibration session)")

#: experiment -> rows (choice, paper_line, text_says, code_does, source); templates where the run decides.
READINGS = {
    "fusion_knn_pdr": (
        ("combination of Wi-Fi and PDR", _P + "L9, L212, L245",
         "Wi-Fi gives the initial position; fingerprint positioning adjusts the PDR position and removes its "
         "accumulated error; no filter or weight given",
         "Wi-Fi start, PDR between fixes, each fix pulls the track by {adjust_weight:g} of the gap{weight_why}",
         "the paper gives no weight: a principled one from variances measured on training data, never from the "
         "test outcome (earlier: 0.5, the best of its own sweep); the sweep is shown as a sensitivity curve "
         "(adjust_sweep)"),
        ("Kalman filter", _P + "L103-139 (sec. 3.1), L141-143 (sec. 3.2)",
         "sec. 3.1: a generic KF for KF-based inertial navigation; sec. 3.2 argues against it on phones; no Q",
         "the i-Loc step KF (Chiu 2013) with the toolkit's Q and R, from the same Wi-Fi start",
         "labelled alternative, not the paper's method"),
        ("KNN", _P + "L77-85 (eq. 1-2)", "Manhattan distance (a = 1), K = 5",
         "KNN, Manhattan, K = 5, mean fingerprints", "paper"),
        ("peak rule", _P + "L185", "reject a peak whose value differs from the previous peak by more than the "
         "threshold or whose interval is outside the time window", "rule {rule!r}",
         "paper; the valley-rise reading (the toolkit's earlier default) is a sensitivity row"),
        ("peak threshold", _P + "L175-185", "a threshold; no value", "{threshold_mps2:g} m/s^2",
         "assumption, swept in detector_sweep"),
        ("time window", _P + "L189", "0.2-2 s", "0.2-2 s", "paper"),
        ("sliding window, smoothing", _P + "L175-177, L183", "window size matters; filtered before peak "
         "detection; no values", "0.4 s window, 0.1 s moving mean", "assumption"),
        ("step length", _P + "L202 (eq. 4)", "k((a_max - a_min) * 3.5 + (a_max - a_min)^(1/4))",
         "eq. 4 with k fitted on training walks of known length", "paper (k: not given, fitted)"),
        ("PDR start", _P + "L235", "PDR starts at the true start", "PDR only starts at the true start", "paper"),
        ("survey", _P + "L9, L91 (sec. 2.3), L233, L251",
         "a handheld phone collects the coordinates and Wi-Fi hotspots of sample points in a given area (L9); "
         "two phases, collect and upload, then locate (L91); Fig 8 (missing) shows the sample points; much "
         "Wi-Fi data is needed (L251); no point spacing, scan count or procedure",
         "the i-Loc floor survey: {scans_per_point} scans per 2 m grid point in sessions of "
         "{scans_per_session}, each session facing one corridor direction; KNN on the per-point mean fingerprints",
         "assumption (i-Loc thesis L295; RADAR's survey protocol), scans per point swept in survey_sweep"),
        ("test session", _P + "L222, L239",
         "the test is a walk of its own (L222); environment and weather change the Wi-Fi signal strength (L239)",
         "each walk is its own session: a new per-AP drift, unlike every survey session, plus a local change "
         "per scan",
         "iloc_floor drift_sd_db, local_sd_db (Kaemarungsi & Krishnamurthy 2004; data/iloc_floor/README.md)"),
        ("test positions", _P + "L91, L222",
         "the locating phase scans where the user is (L91); the tester walks a preset route holding the phone "
         "(L222); Fig 6's x axis is a coordinate index; no scan rate",
         "the phone scans periodically (every {scan_interval_s:g} s) from the start; a test position is where the "
         "walker is when a fix becomes available (its scan has ended) while walking; Fig 6's index = the fix's "
         "number; the start scan gives the initial position only (L212)",
         "paper (walking); periodic scanning as i-Loc L777; {scan_source}"),
        ("test scans", _P + "L222", "the tester walks the route holding the phone, which locates as it goes; no "
         "scan duration or timing",
         "iloc_floor.walking_scans: {scan_text}, facing the walking direction (body shadowing); a fix is available "
         "only when its scan is stamped and adjusts the latest PDR state then (causal; earlier versions applied "
         "it at the scan's start)",
         "reading ages measured (see 'test positions'); the uniform-within-a-scan model (1-3 s, an assumption) "
         "swept in latency_sweep"),
        ("error budget", "beyond the paper", "no error budget",
         "the combination and PDR only rerun with one error source replaced by the truth at a time (Wi-Fi fix "
         "error, scan lag, step detection, step length, heading): ilocalg.fusion.budget", "toolkit"),
        ("headline", "sec. 4 item 3", "one walk: combined 6.74 m vs Wi-Fi only 11.38 m",
         "the ratio combined / Wi-Fi only per seed; seed_table gives its mean and Student-t 95 % interval over "
         "seeds", "toolkit (one seed is one draw of the simulated world)"),
    ),
}


def readings(experiment: str = "fusion_knn_pdr", *, principled: bool = True, **values) -> pd.DataFrame:
    """The readings table of a Luo et al. experiment (:data:`READINGS`), filled with ``values``
    (``adjust_weight``, ``rule``, ``threshold_mps2``, ``scans_per_point``, ``scans_per_session``,
    ``scan_interval_s``, ``scan_text``, ``scan_source``)."""
    if experiment not in READINGS:
        raise ValueError(f"no Luo et al. readings for {experiment!r}; one of {sorted(READINGS)}")
    return fill(READINGS[experiment], weight_why=PRINCIPLED_WEIGHT_TEXT if principled else "", **values)
