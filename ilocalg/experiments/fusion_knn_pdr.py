"""Fingerprint + PDR positioning (Luo et al. 2017, sec. 3-4, Fig 6) on the simulated i-Loc floor.

The paper's library floor and its data are not published; the toolkit's simulated i-Loc floor
(:mod:`ilocalg.sim.iloc_floor`) and gait simulator (:mod:`ilocalg.sim.gait`) stand in, walkers
walking the floor's 28-point test route (as in :mod:`ilocalg.experiments.fusion_iloc_kf`).

* Survey: the i-Loc floor's survey (its own sessions, 2 m grid). Luo et al. say only that a handheld
  phone collects the coordinates and Wi-Fi hotspots of sample points (L9) in a collection phase before
  the locating phase (sec. 2.3, L91): no spacing, scan count or procedure, so the scans per point are
  an assumption, swept in ``survey_sweep``.
* Wi-Fi only: KNN, Manhattan distance (a = 1), K = 5 (eq. 1-2, L83) on the per-point mean
  fingerprints of the survey. Each walk is its own session (a new per-AP drift: another day than
  every survey session, L239). The phone scans back to back while the tester walks the route (L222):
  each scan is a walking scan (:func:`ilocalg.sim.iloc_floor.walking_fixes`: APs read along the
  ``scan_latency_s`` scan, facing the walking direction), tagged at its start. The start scan gives
  the initial position (L212); every scan started while walking is a test position: the walker's true
  position then, off the reference grid. Fig 6's "coordinate index" is the scan's number.
* PDR only: the paper's sliding-window peak detector on |a| with its literal rule b (a peak is
  rejected when it differs from the previous peak by more than the threshold or comes outside
  0.2-2 s after it, L185, L189), step length eq. (4) with ``k`` fitted on fixed-length training walks
  (total true length / total eq. (4) length), WDM heading (accelerometer + magnetometer, sec.
  3.4.3); started at the true start, as in the paper (L235).
* Combined (default, the paper's own combination): the walk starts at the first Wi-Fi fix (L212:
  "the initial position is obtained by Wi-Fi positioning"), PDR carries it from step to step
  (eq. 5-6) and each fingerprint fix adjusts the position ("the absoluteness of fingerprint
  positioning adjusts the position and removes PDR's accumulated error", L9, L245):
  :func:`ilocalg.fusion.fingerprint_adjusted_track`. The paper gives no weight for the adjustment:
  ``adjust_weight`` (0.5) is an assumption, swept in ``adjust_sweep``.
* Labelled alternative, not in the paper: the i-Loc step Kalman filter (Chiu 2013,
  :mod:`ilocalg.fusion.step_kf`) with the PDR steps as control input and the KNN fixes as
  observations, from the same Wi-Fi start; its ``Q`` (step-length error spread of the training
  walks) and ``R`` (KNN error variance over standing scans at the route points on another day) are
  the toolkit's, not the paper's: Luo et al. give no filter for the combination (their sec. 3.1 is a
  generic Kalman filter for KF-based inertial navigation, which their sec. 3.2, L141-143, argues
  against on phones). Also the same filter smoothed (RTS) and with a heading error term.

Scored: the error at each test position (Fig 6: error per point index), each track taken at its
latest state at or before the scan's start. Every modelling choice is in :func:`readings`.

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Sec. 3-4, eq. (1)-(6), Fig 6.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.fusion import filter_walk, fingerprint_adjusted_track, fixes_at_states, rts_smooth
from ilocalg.metrics import summarise_by_method
from ilocalg.papers import PAPERS, comparison_table, paper_ref, reading, readings_table
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import fit_luo_k, luo_steps
from ilocalg.sim import gait, iloc_floor
from ilocalg.units import as_rng

__all__ = ["run", "crossover_point", "findings", "readings", "PAPER_LUO", "COMBINED", "KF_ALT", "ADJUST_WEIGHTS",
           "SURVEY_SCANS", "LATENCIES_S", "DETECTOR_VARIANTS"]

#: Name of the default combination (the paper's) and of the labelled i-Loc Kalman-filter alternative.
COMBINED = "combined (Wi-Fi start + fingerprint adjustment)"
KF_ALT = "i-Loc step KF (alternative)"
#: Adjustment weights swept (the paper gives none; 0.5 is the default).
ADJUST_WEIGHTS = (0.25, 0.5, 0.75, 1.0)
#: Survey scans per reference point swept (the paper gives none).
SURVEY_SCANS = (10, 30, 300)
#: Walking-scan latencies swept, s (the paper gives none; phones take 1-3 s per scan; 2 s is the default).
LATENCIES_S = (1.0, 2.0, 3.0)
#: Peak-detector variants swept: the literal rule b with several thresholds, and the valley-rise reading.
DETECTOR_VARIANTS = (
    ("literal rule b, threshold 1.0 m/s^2 (default)", {"rule": "literal", "threshold_mps2": 1.0}),
    ("literal rule b, threshold 0.5 m/s^2", {"rule": "literal", "threshold_mps2": 0.5}),
    ("literal rule b, threshold 2.0 m/s^2", {"rule": "literal", "threshold_mps2": 2.0}),
    ("literal rule b, threshold 4.0 m/s^2", {"rule": "literal", "threshold_mps2": 4.0}),
    ("valley rise >= 1.0 m/s^2 (earlier reading)", {"rule": "valley_rise", "threshold_mps2": 1.0}),
)

PAPER = PAPERS["luo"]
# Settings from the paper
# -----------------------
# PAPER_LUO: Luo et al. (2017) sec. 4, item 2 (Wi-Fi only mean, min, max error) and item 3
# (combined mean error; PDR better than the combination for the first 6 points); reference only.
#: Published values (paper, sec. 4 items 2-3): reference only.
PAPER_LUO = {"wifi_mean_m": 11.38, "wifi_min_m": 1.0, "wifi_max_m": 21.5,
             "combined_mean_m": 6.74, "pdr_better_points": 6}


def crossover_point(pdr_err: np.ndarray, comb_err: np.ndarray) -> int:
    """Number of leading points (1-based count) before which PDR is better and after which the
    combined error stays below PDR's: the last point where PDR < combined (0 if never)."""
    better = np.flatnonzero(np.asarray(pdr_err) < np.asarray(comb_err))
    return int(better[-1] + 1) if better.size else 0


def _walk_tracks(seed, fast, n_walkers, n_train, n_cal, detector, sigma_theta_rad, adjust_weights, scans_per_point,
                 scan_latency_s):
    """Simulate, detect, combine: the per-position error table and the example tracks."""
    if fast:
        n_walkers, n_train, n_cal = min(n_walkers, 2), min(n_train, 3), min(n_cal, 5)
    # independent streams for the floor, the walks and each walk's scans, so that a sweep of the survey
    # size or of the scan latency changes only what it sweeps (same walkers, walks and sessions)
    floor_rng, rng, scan_root = as_rng(seed).spawn(3)
    scan_rngs = scan_root.spawn(n_walkers)
    method = "KNN (Manhattan, K=5)"
    spp = scans_per_point if scans_per_point is not None else (60 if fast else iloc_floor.SCANS_PER_POINT)
    # survey (its own sessions) and a standing calibration session at the route points (another day)
    sim = iloc_floor.simulate(floor_rng, scans_per_point=spp, scans_per_test_point=n_cal)
    est = iloc_floor.fit_estimator(sim, method)
    r_var = float(iloc_floor.standing_fix_variance_m2(sim, est).mean())
    walkers = gait.make_walkers(max(n_train, n_walkers), rng)
    train = gait.training_walks(walkers[:n_train], rng)
    k, sig_sl = fit_luo_k([(*acc_from_log(sw.imu), sw.steps["length_m"]) for _, _, sw in train], detector)
    route = iloc_floor.route_xy_m()
    tps, ex, nsteps, x0_err, n_deaf = [], [], [], [], 0
    for w_i, w in enumerate(walkers[:n_walkers]):
        sw = gait.simulate_walk(route, w, rng)
        acc, t = acc_from_log(sw.imu)
        st = luo_steps(acc, t, k, detector)
        nsteps.append((len(st), len(sw.steps)))
        th = log_headings_rad(sw.imu, sw.config.stand_s)["WDM"][st["i_peak"].to_numpy()]
        d = st["length_m"].to_numpy()
        ts = np.concatenate([[t[0]], st["t_s"].to_numpy()])
        truth_t = sw.truth.index.to_numpy()
        truth_xy = sw.truth[["x_m", "y_m"]].to_numpy()
        # this walk's session: a new per-AP drift (another day than every survey session)
        drift = iloc_floor.session_drift_db(sim, scan_rngs[w_i])
        # the phone scans back to back from the start; scan 0 (at the start, L212) gives the initial position,
        # the scans started while walking are the test positions (off the reference grid)
        starts = iloc_floor.back_to_back_scan_starts_s(truth_t[0], truth_t[-1], scan_latency_s)
        fx = iloc_floor.walking_fixes(sim, est, truth_t, truth_xy, starts, scan_latency_s, scan_rngs[w_i], drift)
        walk_t0 = float(sw.steps["t_strike_s"].iloc[0])
        walk_t1 = float((sw.steps["t_strike_s"] + sw.steps["duration_s"]).iloc[-1])
        start_fix = fx[["fix_x_m", "fix_y_m"]].to_numpy()[0]
        x0 = start_fix if np.isfinite(start_fix).all() else route[0]
        x0_err.append(float(np.hypot(*(x0 - route[0]))))
        tst = fx[(fx["t_start_s"] > walk_t0) & (fx["t_start_s"] < walk_t1)].reset_index(drop=True)
        fix = tst[["fix_x_m", "fix_y_m"]].to_numpy()
        true_xy = tst[["x_m", "y_m"]].to_numpy()
        heard = np.isfinite(fix).all(axis=1)
        n_deaf += int((~heard).sum())
        al = fixes_at_states(ts, tst["t_start_s"].to_numpy()[heard], fix[heard], before_start="drop",
                             same_state="last")
        z = al.z_m
        tracks = {"PDR only": dead_reckon(d, th, *route[0])[["x_m", "y_m"]].to_numpy()}
        for wgt in adjust_weights:
            tracks[f"{COMBINED}, weight {wgt:g}"] = fingerprint_adjusted_track(x0, th, d, z, wgt)
        res = filter_walk(x0, r_var * np.eye(2), th, d, sig_sl, z, r_var_m2=r_var)
        hres = filter_walk(x0, r_var * np.eye(2), th, d, sig_sl, z, r_var_m2=r_var, sigma_theta_rad=sigma_theta_rad)
        tracks.update({KF_ALT: res.x, f"{KF_ALT} + RTS": rts_smooth(res).x,
                       f"{KF_ALT} + heading noise": hres.x, f"{KF_ALT} + heading noise + RTS": rts_smooth(hres).x})
        # each method's estimate at a test position: its latest state at or before the scan's start
        idx = np.maximum(np.searchsorted(ts, tst["t_start_s"].to_numpy(), side="right") - 1, 0)
        rows = [("Wi-Fi only (KNN)", fix)] + [(m, xy[idx]) for m, xy in tracks.items()]
        for m, est_xy in rows:
            keep = heard if m == "Wi-Fi only (KNN)" else np.ones(len(tst), dtype=bool)
            tps.append(pd.DataFrame({"walker": w.name, "method": m, "point": np.arange(1, len(tst) + 1)[keep],
                                     "t_s": tst["t_start_s"].to_numpy()[keep], "x_true_m": true_xy[keep, 0],
                                     "y_true_m": true_xy[keep, 1], "x_est_m": est_xy[keep, 0],
                                     "y_est_m": est_xy[keep, 1],
                                     "error_m": np.hypot(*(est_xy[keep] - true_xy[keep]).T)}))
        if w_i == 0:
            ex.append(pd.DataFrame({"method": "truth", "x_m": np.r_[route[0, 0], sw.steps["x_m"]],
                                    "y_m": np.r_[route[0, 1], sw.steps["y_m"]]}))
            ex.append(pd.DataFrame({"method": "Wi-Fi only (KNN)", "x_m": fix[heard, 0], "y_m": fix[heard, 1]}))
            ex += [pd.DataFrame({"method": m, "x_m": v[:, 0], "y_m": v[:, 1]}) for m, v in tracks.items()]
    tp = pd.concat(tps, ignore_index=True)
    det = np.asarray(nsteps, dtype=float)
    info = {"k": k, "sig_sl": sig_sl, "r_var": r_var, "n_walkers": n_walkers, "scans_per_point": spp,
            "det_over_true_steps": float(det[:, 0].sum() / det[:, 1].sum()),
            "start_fix_error_m": float(np.mean(x0_err)), "n_deaf": n_deaf, "scan_latency_s": float(scan_latency_s)}
    return tp, ex, info


def readings(adjust_weight: float = 0.5, detector: dict | None = None, scans_per_point=None,
             scan_latency_s: float = 2.0) -> pd.DataFrame:
    """One row per modelling choice of :func:`run` (line numbers of Luo et al. 2017's text copy)."""
    det = {"rule": "literal", "threshold_mps2": 1.0, **(detector or {})}
    spp = scans_per_point if scans_per_point is not None else iloc_floor.SCANS_PER_POINT
    rows = [
        ("combination of Wi-Fi and PDR", "L9, L212, L245",
         "Wi-Fi gives the initial position; fingerprint positioning adjusts the PDR position and removes its "
         "accumulated error; no filter or weight given",
         f"Wi-Fi start, PDR between fixes, each fix pulls the track by {adjust_weight:g} of the gap",
         "paper's scheme; the weight is an assumption, swept in adjust_sweep"),
        ("Kalman filter", "L103-139 (sec. 3.1), L141-143 (sec. 3.2)",
         "sec. 3.1: a generic KF for KF-based inertial navigation; sec. 3.2 argues against it on phones; no Q",
         "the i-Loc step KF (Chiu 2013) with the toolkit's Q and R, from the same Wi-Fi start",
         "labelled alternative, not the paper's method"),
        ("KNN", "L77-85 (eq. 1-2)", "Manhattan distance (a = 1), K = 5", "KNN, Manhattan, K = 5, mean fingerprints",
         "paper"),
        ("peak rule", "L185", "reject a peak whose value differs from the previous peak by more than the threshold "
         "or whose interval is outside the time window", f"rule {det['rule']!r}",
         "paper; the valley-rise reading (the toolkit's earlier default) is a sensitivity row"),
        ("peak threshold", "L175-185", "a threshold; no value", f"{det['threshold_mps2']:g} m/s^2",
         "assumption, swept in detector_sweep"),
        ("time window", "L189", "0.2-2 s", "0.2-2 s", "paper"),
        ("sliding window, smoothing", "L175-177, L183", "window size matters; filtered before peak detection; "
         "no values", "0.4 s window, 0.1 s moving mean", "assumption"),
        ("step length", "L202 (eq. 4)", "k((a_max - a_min) * 3.5 + (a_max - a_min)^(1/4))",
         "eq. 4 with k fitted on training walks of known length", "paper (k: not given, fitted)"),
        ("PDR start", "L235", "PDR starts at the true start", "PDR only starts at the true start", "paper"),
        ("survey", "L9, L91 (sec. 2.3), L233, L251",
         "a handheld phone collects the coordinates and Wi-Fi hotspots of sample points in a given area (L9); "
         "two phases, collect and upload, then locate (L91); Fig 8 (missing) shows the sample points; much "
         "Wi-Fi data is needed (L251); no point spacing, scan count or procedure",
         f"the i-Loc floor survey: {spp} scans per 2 m grid point in sessions of "
         f"{iloc_floor.PARAMS['scans_per_session']}, each session facing one corridor direction; KNN on the "
         "per-point mean fingerprints",
         "assumption (i-Loc thesis L295; RADAR's survey protocol), scans per point swept in survey_sweep"),
        ("test session", "L222, L239",
         "the test is a walk of its own (L222); environment and weather change the Wi-Fi signal strength (L239)",
         "each walk is its own session: a new per-AP drift, unlike every survey session, plus a local change "
         "per scan",
         "iloc_floor drift_sd_db, local_sd_db (Kaemarungsi & Krishnamurthy 2004; data/iloc_floor/README.md)"),
        ("test positions", "L91, L222",
         "the locating phase scans where the user is (L91); the tester walks a preset route holding the phone "
         "(L222); Fig 6's x axis is a coordinate index; no scan rate",
         "the phone scans back to back from the start; a test position is the walker's true position when a "
         "scan starts while walking (off the 2 m reference grid); Fig 6's index = the scan's number; the start "
         "scan gives the initial position only (L212)",
         "paper (walking); back-to-back scanning: assumption"),
        ("test scans", "L222", "the tester walks the route holding the phone, which locates as it goes; no scan "
         "duration or timing",
         f"iloc_floor.walking_scans: each AP read at a uniform time within the {scan_latency_s:g} s scan at the "
         "walker's position then, facing the walking direction (body shadowing); the fix is tagged at the "
         "scan's start and adjusts the latest PDR state at or before it (as notebook 07)",
         "scan latency: assumption (phones 1-3 s), swept in latency_sweep; fix timing: assumption"),
    ]
    return readings_table([reading(c, f"Luo et al. 2017, {ln}" if ln.startswith("L") else ln, t, d, src)
                           for c, ln, t, d, src in rows])


def _summary_rows(tp, label_col, label):
    m = tp.groupby("method", sort=False)["error_m"].mean()
    return {label_col: label, **{f"{k} mean error [m]": float(v) for k, v in m.items()}}


def run(seed: int = 0, fast: bool = False, n_walkers: int = 8, n_train: int = 8, n_cal: int = 10,
        detector: dict | None = None, sigma_theta_rad: float = 0.2, adjust_weight: float = 0.5,
        scans_per_point: int | None = None, scan_latency_s: float = 2.0,
        sweeps: bool = True) -> dict[str, pd.DataFrame]:
    """PDR only, Wi-Fi only (KNN) and the paper's combination at the route points (Fig 6).

    Parameters
    ----------
    detector : dict, optional
        Parameters of :func:`ilocalg.pdr.peak_window.detect_steps_peak_window` (default: its literal
        rule b, threshold 1.0 m/s^2).
    sigma_theta_rad : float
        Heading error sd of the KF variant whose ``Q`` also covers the heading.
    adjust_weight : float
        Weight of the fingerprint adjustment of the default combination (swept in ``adjust_sweep``).
    scans_per_point : int, optional
        Survey scans per reference point (default: the i-Loc floor's 300; fast: 60).
    scan_latency_s : float
        Duration of one walking scan, s (> 0); the phone scans back to back, so it is also the time
        between test positions (swept in ``latency_sweep``).
    sweeps : bool
        Also run the survey, detector and scan-latency sweeps.

    Returns
    -------
    dict of DataFrame
        ``test_points`` (one row per walker, method and test position: the walker's true position
        when a scan started while walking, ``point`` = the scan's number), ``summary``, ``cdf``,
        ``per_point`` (mean error per point and method over the walkers, for the points every walker
        reached: the Fig 6 curves), ``track_example``, ``calibration`` (k, sigma_SL, R, ...),
        ``comparison``, ``readings``, ``adjust_sweep``, and with ``sweeps`` ``survey_sweep``,
        ``detector_sweep``, ``latency_sweep``.
    """
    weights = tuple(sorted(set(ADJUST_WEIGHTS) | {float(adjust_weight)}))
    tp, ex, info = _walk_tracks(seed, fast, n_walkers, n_train, n_cal, detector, sigma_theta_rad, weights,
                                scans_per_point, scan_latency_s)
    default = f"{COMBINED}, weight {adjust_weight:g}"
    adjust_rows = [_summary_rows(tp[tp["method"].str.startswith(COMBINED + ",")
                                    & (tp["method"] == f"{COMBINED}, weight {w:g}")], "weight", w) for w in weights]
    adjust = pd.DataFrame([{"weight": r["weight"], "mean_error_m": list(r.values())[1]} for r in adjust_rows])
    keep = ~tp["method"].str.startswith(COMBINED + ",") | (tp["method"] == default)
    tp = tp[keep].replace({"method": {default: COMBINED}}).reset_index(drop=True)
    ex = [e.replace({"method": {default: COMBINED}}) for e in ex
          if not (e["method"].iloc[0].startswith(COMBINED + ",") and e["method"].iloc[0] != default)]
    summ, cdf = summarise_by_method(tp)
    n_common = int(tp.groupby("walker")["point"].max().min())  # points every walker reached
    pp = (tp[tp["point"] <= n_common].groupby(["method", "point"], sort=False)["error_m"].mean()
          .unstack("method").reset_index())
    pp = pp[["point"] + list(tp["method"].unique())]
    m = summ.set_index("method")["mean_error_m"]
    cross = crossover_point(pp["PDR only"].to_numpy(), pp[COMBINED].to_numpy())
    cross_kf = crossover_point(pp["PDR only"].to_numpy(), pp[KF_ALT].to_numpy())
    wifi_pp = pp["Wi-Fi only (KNN)"]
    note = f"{info['n_walkers']} simulated walkers, simulated i-Loc floor (not the paper's library)"
    comp = [
        paper_ref(PAPER, "Fig 6", "Wi-Fi only (KNN, Manhattan, K=5) mean error", PAPER_LUO["wifi_mean_m"],
                  m["Wi-Fi only (KNN)"], "m", note + "; walking scans off the reference grid, own session per walk"),
        paper_ref(PAPER, "Fig 6", "Wi-Fi only, smallest per-point error", PAPER_LUO["wifi_min_m"],
                  tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"].min(), "m", "over every walker and point"),
        paper_ref(PAPER, "Fig 6", "Wi-Fi only, largest per-point error", PAPER_LUO["wifi_max_m"],
                  tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"].max(), "m", "over every walker and point"),
        paper_ref(PAPER, "Fig 6", "combined mean error (Wi-Fi start + fingerprint adjustment)",
                  PAPER_LUO["combined_mean_m"], m[COMBINED], "m", note + f"; weight {adjust_weight:g} (assumption)"),
        paper_ref(PAPER, "Fig 6", "combined / Wi-Fi only mean error",
                  PAPER_LUO["combined_mean_m"] / PAPER_LUO["wifi_mean_m"],
                  m[COMBINED] / m["Wi-Fi only (KNN)"], "-", "the improvement ratio"),
        paper_ref(PAPER, "Fig 6", "last point where PDR only beats combined", PAPER_LUO["pdr_better_points"], cross,
                  "points", "mean over walkers per scan (points every walker reached)"),
        paper_ref(PAPER, "Fig 6 (alternative, not the paper's)", "i-Loc step KF mean error",
                  PAPER_LUO["combined_mean_m"], m[KF_ALT], "m", "labelled alternative: Chiu 2013's filter",
                  row_class="alternative reading",
                  replaces=("Fig 6", "combined mean error (Wi-Fi start + fingerprint adjustment)")),
        paper_ref(PAPER, "Fig 6 (alternative, not the paper's)", "last point where PDR only beats the i-Loc step KF",
                  PAPER_LUO["pdr_better_points"], cross_kf, "points", "labelled alternative",
                  row_class="alternative reading", replaces=("Fig 6", "last point where PDR only beats combined")),
    ]
    calib = pd.DataFrame([{"quantity": "eq. (4) k (fitted on training walks)", "value": info["k"]},
                          {"quantity": "detected / true steps on the test walks", "value": info["det_over_true_steps"]},
                          {"quantity": "sigma_SL, step-length error sd [m] (KF alternative)", "value": info["sig_sl"]},
                          {"quantity": "R, KNN fix variance per axis [m^2] (KF alternative)", "value": info["r_var"]},
                          {"quantity": "survey scans per reference point", "value": info["scans_per_point"]},
                          {"quantity": "scan latency = time between test positions [s]",
                           "value": info["scan_latency_s"]},
                          {"quantity": "test positions per walker (points every walker reached)", "value": n_common},
                          {"quantity": "Wi-Fi start: mean error of the initial fix [m]",
                           "value": info["start_fix_error_m"]},
                          {"quantity": "test scans hearing no AP (no Wi-Fi fix)", "value": info["n_deaf"]},
                          {"quantity": "Wi-Fi only per-point mean error, min over points [m]", "value": wifi_pp.min()},
                          {"quantity": "Wi-Fi only per-point mean error, max over points [m]", "value": wifi_pp.max()}])
    out = {"test_points": tp, "summary": summ, "cdf": cdf, "per_point": pp,
           "track_example": pd.concat(ex, ignore_index=True), "calibration": calib,
           "comparison": comparison_table(comp),
           "readings": readings(adjust_weight, detector, scans_per_point, scan_latency_s),
           "adjust_sweep": adjust}
    if sweeps:
        srows = []
        for spp in ((60,) if fast else SURVEY_SCANS):
            t2, _, i2 = _walk_tracks(seed, fast, n_walkers, n_train, n_cal, detector, sigma_theta_rad,
                                     (adjust_weight,), spp, scan_latency_s)
            mm = t2.groupby("method", sort=False)["error_m"].mean()
            srows.append({"scans_per_point": i2["scans_per_point"], "wifi_only_mean_m": mm["Wi-Fi only (KNN)"],
                          "combined_mean_m": mm[f"{COMBINED}, weight {adjust_weight:g}"],
                          "kf_alt_mean_m": mm[KF_ALT], "pdr_only_mean_m": mm["PDR only"]})
        out["survey_sweep"] = pd.DataFrame(srows)
        drows = []
        for name, det in (DETECTOR_VARIANTS[:2] if fast else DETECTOR_VARIANTS):
            t2, _, i2 = _walk_tracks(seed, fast, n_walkers, n_train, n_cal, det, sigma_theta_rad,
                                     (adjust_weight,), scans_per_point, scan_latency_s)
            mm = t2.groupby("method", sort=False)["error_m"].mean()
            drows.append({"detector": name, "det_over_true_steps": i2["det_over_true_steps"], "k": i2["k"],
                          "pdr_only_mean_m": mm["PDR only"],
                          "combined_mean_m": mm[f"{COMBINED}, weight {adjust_weight:g}"],
                          "kf_alt_mean_m": mm[KF_ALT]})
        out["detector_sweep"] = pd.DataFrame(drows)
        lrows = []
        for lat in ((scan_latency_s,) if fast else LATENCIES_S):
            t2, _, i2 = _walk_tracks(seed, fast, n_walkers, n_train, n_cal, detector, sigma_theta_rad,
                                     (adjust_weight,), scans_per_point, lat)
            mm = t2.groupby("method", sort=False)["error_m"].mean()
            lrows.append({"scan_latency_s": lat, "test_positions": int(t2[t2["method"] == "PDR only"].shape[0]),
                          "wifi_only_mean_m": mm["Wi-Fi only (KNN)"], "pdr_only_mean_m": mm["PDR only"],
                          "combined_mean_m": mm[f"{COMBINED}, weight {adjust_weight:g}"],
                          "kf_alt_mean_m": mm[KF_ALT]})
        out["latency_sweep"] = pd.DataFrame(lrows)
    return out


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    m = tables["summary"].set_index("method")["mean_error_m"]
    pp = tables["per_point"]
    tp = tables["test_points"]
    cal = tables["calibration"].set_index("quantity")["value"]
    cross = crossover_point(pp["PDR only"].to_numpy(), pp[COMBINED].to_numpy())
    w, c, p, kf = m["Wi-Fi only (KNN)"], m[COMBINED], m["PDR only"], m[KF_ALT]
    we = tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"]
    lines = [
        f"Mean error: Wi-Fi only {w:.2f} m, PDR only {p:.2f} m, combined (the paper's scheme) {c:.2f} m; "
        f"the i-Loc step KF alternative {kf:.2f} m, + RTS {m[KF_ALT + ' + RTS']:.2f} m (paper values: Wi-Fi "
        f"{PAPER_LUO['wifi_mean_m']} m, combined {PAPER_LUO['combined_mean_m']} m).",
        f"Wi-Fi only errors span [{we.min():.2f}, {we.max():.2f}] m over {we.size} walking test positions "
        f"(paper: [{PAPER_LUO['wifi_min_m']}, {PAPER_LUO['wifi_max_m']}] m); the Wi-Fi start is off by "
        f"{cal['Wi-Fi start: mean error of the initial fix [m]']:.2f} m on average.",
        f"Combined / Wi-Fi only = {c / w:.2f} (paper {PAPER_LUO['combined_mean_m'] / PAPER_LUO['wifi_mean_m']:.2f}); "
        f"PDR only beats the combined scheme up to point {cross} (paper: the first {PAPER_LUO['pdr_better_points']}).",
    ]
    if "latency_sweep" in tables:
        ls = tables["latency_sweep"]
        lines.append("Scan latency " + ", ".join(f"{r.scan_latency_s:g} s" for r in ls.itertuples())
                     + ": Wi-Fi only " + " / ".join(f"{v:.2f}" for v in ls["wifi_only_mean_m"])
                     + " m, combined " + " / ".join(f"{v:.2f}" for v in ls["combined_mean_m"]) + " m.")
    if "survey_sweep" in tables:
        sv = tables["survey_sweep"]
        lines.append("Survey scans per point " + ", ".join(f"{int(v)}" for v in sv["scans_per_point"])
                     + ": Wi-Fi only " + " / ".join(f"{v:.2f}" for v in sv["wifi_only_mean_m"])
                     + " m, combined " + " / ".join(f"{v:.2f}" for v in sv["combined_mean_m"]) + " m.")
    return "\n".join(lines)
