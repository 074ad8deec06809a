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

import inspect

import numpy as np
import pandas as pd

from ilocalg.fusion import filter_walk, fingerprint_adjusted_track, fixes_at_states, rts_smooth
from ilocalg.fusion.budget import SOURCES as BUDGET_SOURCES
from ilocalg.fusion.budget import FusionInputs, error_budget, input_diagnostics, inputs_sentence, track_at
from ilocalg.fusion.fingerprint_adjust import combined_method, pdr_true_start_method, principled_weight
from ilocalg.fusion.tracks import crossover_point
from ilocalg.metrics import summarise_by_method
from ilocalg.papers import PAPERS, comparison_table, paper_ref, readings_luo
from ilocalg.papers.claims import interval
from ilocalg.papers.luo import PUBLISHED
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.luo_pdr import LuoLogs, eq4_vs_constant_error, luo_pdr, luo_training_spread
from ilocalg.pdr.peak_window import detect_steps_peak_window
from ilocalg.sim import gait, iloc_floor, iloc_scenario
from ilocalg.sim.iloc_scenario import SCAN_LATENCY_S, walk_fixes
from ilocalg.units import as_rng

__all__ = ["run", "seed_table", "findings", "readings", "PAPER_LUO", "COMBINED", "KF_ALT", "ADJUST_WEIGHTS",
           "SURVEY_SCANS", "LATENCIES_S", "DETECTOR_VARIANTS"]

#: Name of the default combination (the paper's) and of the labelled i-Loc Kalman-filter alternative.
COMBINED = "combined (Wi-Fi start + fingerprint adjustment)"
KF_ALT = "i-Loc step KF (alternative)"
#: Adjustment weights swept as a sensitivity curve (the paper gives none; the default is the inverse-variance
#: weight from the training data, :func:`principled_weight`).
ADJUST_WEIGHTS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
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
#: Published values (:data:`ilocalg.papers.luo.PUBLISHED`, sec. 4 items 2-3): reference only.
PAPER_LUO = PUBLISHED


class _Shared:
    """What the :func:`_walk_tracks` calls of one :func:`run` would compute alike, computed once.

    The run's tables, its survey / detector / latency sweeps and a second pass for a given weight call
    :func:`_walk_tracks` up to twelve times on the same floor, training walks and walk logs: the KNN fit and its
    standing variance depend on the floor only, the walks' fixes on the floor and their scans, eq. (4)'s ``k``
    and the training spreads on the training walks and the detector, a walk's PDR on its log, ``k`` and the
    detector. Entries are keyed by those objects (held here, so their ids stay unique for the run) and the
    detector's full parameters (:func:`_detector_key`: ``None`` and its defaults spelled out are one detector);
    cached arrays are read-only.
    """

    def __init__(self):
        self._values: dict = {}
        self._held: list = []
        self.logs = LuoLogs()  # each log's accelerometer array, steps per detector and headings (any k)

    def get(self, objs: tuple, key, compute):
        k = (tuple(id(o) for o in objs), key)
        if k not in self._values:
            self._held.extend(objs)
            self._values[k] = _read_only(compute())
        return self._values[k]


def _read_only(value):
    for v in (value.values() if isinstance(value, dict) else value if isinstance(value, tuple) else ()):
        if isinstance(v, np.ndarray):
            v.flags.writeable = False
    return value


def _detector_key(detector: dict | None) -> tuple:
    """The peak-window detector's parameters in full (its defaults filled in), as a hashable key."""
    params = {n: p.default for n, p in inspect.signature(detect_steps_peak_window).parameters.items()
              if p.default is not inspect.Parameter.empty}
    unknown = set(detector or {}) - set(params)
    if unknown:
        raise ValueError(f"unknown peak-window detector parameters {sorted(unknown)}; known: {sorted(params)}")
    return tuple(sorted({**params, **(detector or {})}.items()))


def _walk_tracks(scn, detector, sigma_theta_rad, adjust_weights, principled: bool, shared: _Shared | None = None):
    """Detect, combine and score every walk of a scenario: the per-position error table and the example tracks
    (``shared``: what earlier calls of the same run computed, :class:`_Shared`)."""
    method = "KNN (Manhattan, K=5)"
    shared = _Shared() if shared is None else shared
    det = _detector_key(detector)

    def wifi():
        est = iloc_floor.fit_estimator(scn.floor, method)
        return est, float(iloc_floor.standing_fix_variance_m2(scn.floor, est).mean())

    def training():
        walks = [sw for _, _, sw in scn.train_walks]
        k, sig_sl = shared.logs.fit_k(walks, detector)
        return (k, sig_sl, *luo_training_spread(walks, k, detector, logs=shared.logs))

    est, r_var = shared.get((scn.floor,), "wifi", wifi)
    k, sig_sl, sig_th, step_s, step_m = shared.get((scn.train_walks,), ("training", det), training)
    w_p, q_var = principled_weight(sig_sl, sig_th, step_m, step_s, scn.params["scan_interval_s"], r_var)
    weights = tuple(sorted(set(adjust_weights) | ({round(w_p, 3)} if principled else set())))
    route = scn.route_xy_m
    tps, ex, nsteps, x0_err, inputs, n_deaf = [], [], [], [], [], 0
    for w_i, w in enumerate(scn.walks):
        pdr = shared.get((w.imu,), ("pdr", k, det, w.stand_s), lambda w=w: luo_pdr(w.imu, k, detector, w.stand_s,
                                                                              logs=shared.logs))
        ts, d, th = pdr["state_t_s"], pdr["step_m"], pdr["theta_rad"]
        nsteps.append((d.size, len(w.steps)))
        fx = shared.get((scn.floor, w.scans), "fixes", lambda w=w: walk_fixes(scn, w, est))
        walk_t0 = float(w.steps["t_strike_s"].iloc[0])
        walk_t1 = float((w.steps["t_strike_s"] + w.steps["duration_s"]).iloc[-1])
        start_fix = fx[["fix_x_m", "fix_y_m"]].to_numpy()[0]
        x0 = start_fix if np.isfinite(start_fix).all() else route[0]
        x0_err.append(float(np.hypot(*(x0 - route[0]))))
        # test positions: where the walker is when a fix becomes available (its scan has ended) while walking
        rest = fx.iloc[1:]
        tst = rest[(rest["t_ready_s"] > walk_t0) & (rest["t_ready_s"] <= walk_t1)].reset_index(drop=True)
        fix = tst[["fix_x_m", "fix_y_m"]].to_numpy()
        t_eval = tst["t_ready_s"].to_numpy()
        true_xy = np.column_stack([np.interp(t_eval, w.truth_t_s, w.truth_xy_m[:, 0]),
                                   np.interp(t_eval, w.truth_t_s, w.truth_xy_m[:, 1])])
        heard = np.isfinite(fix).all(axis=1)
        n_deaf += int((~heard).sum())
        fr = rest[np.isfinite(rest[["fix_x_m", "fix_y_m"]].to_numpy()).all(axis=1)]
        al = fixes_at_states(ts, fr["t_ready_s"].to_numpy(), fr[["fix_x_m", "fix_y_m"]].to_numpy(),
                             before_start="drop", same_state="last")
        z = al.z_m
        tracks = {"PDR only": dead_reckon(d, th, *route[0])[["x_m", "y_m"]].to_numpy()}
        for wgt in weights:
            tracks[f"{COMBINED}, weight {wgt:g}"] = fingerprint_adjusted_track(x0, th, d, z, wgt)
        res = filter_walk(x0, r_var * np.eye(2), th, d, sig_sl, z, r_var_m2=r_var)
        hres = filter_walk(x0, r_var * np.eye(2), th, d, sig_sl, z, r_var_m2=r_var, sigma_theta_rad=sigma_theta_rad)
        tracks.update({KF_ALT: res.x, f"{KF_ALT} + RTS": rts_smooth(res).x,
                       f"{KF_ALT} + heading noise": hres.x, f"{KF_ALT} + heading noise + RTS": rts_smooth(hres).x})
        rows = [("Wi-Fi only (KNN)", fix)] + [(m, track_at(ts, xy, t_eval)) for m, xy in tracks.items()]
        for m, est_xy in rows:
            keep = heard if m == "Wi-Fi only (KNN)" else np.ones(len(tst), dtype=bool)
            tps.append(pd.DataFrame({"walker": w.name, "method": m, "point": np.arange(1, len(tst) + 1)[keep],
                                     "t_s": t_eval[keep], "x_true_m": true_xy[keep, 0],
                                     "y_true_m": true_xy[keep, 1], "x_est_m": est_xy[keep, 0],
                                     "y_est_m": est_xy[keep, 1],
                                     "error_m": np.hypot(*(est_xy[keep] - true_xy[keep]).T)}))
        inputs.append(FusionInputs.from_walk(
            w, state_t_s=ts, step_m=d, theta_rad=th, heading_rad=pdr["heading_rad"], start_xy_m=x0,
            start_ref_t_s=fx["t_ref_s"].iloc[0], fixes=fr, eval_t_s=t_eval, eval_xy_m=true_xy))
        if w_i == 0:
            ex.append(pd.DataFrame({"method": "truth", "x_m": np.r_[route[0, 0], w.steps["x_m"]],
                                    "y_m": np.r_[route[0, 1], w.steps["y_m"]]}))
            ex.append(pd.DataFrame({"method": "Wi-Fi only (KNN)", "x_m": fix[heard, 0], "y_m": fix[heard, 1]}))
            ex += [pd.DataFrame({"method": m, "x_m": v[:, 0], "y_m": v[:, 1]}) for m, v in tracks.items()]
    tp = pd.concat(tps, ignore_index=True)
    det = np.asarray(nsteps, dtype=float)
    info = {"k": k, "sig_sl": sig_sl, "sig_theta": sig_th, "step_s": step_s, "step_m": step_m, "q_var": q_var,
            "principled_weight": w_p, "r_var": r_var, "n_walkers": len(scn.walks),
            "scans_per_point": scn.params["scans_per_point"],
            "det_over_true_steps": float(det[:, 0].sum() / det[:, 1].sum()),
            "start_fix_error_m": float(np.mean(x0_err)), "n_deaf": n_deaf,
            "scan_latency_s": scn.params["scan_latency_s"], "scan_interval_s": scn.params["scan_interval_s"],
            "inputs": inputs}
    return tp, ex, info


def _claim_measures(seed, tp, pp, summ, n_walkers, n_train, detector) -> list:
    """The claims ledger's named scalars as on main (c62a9bb, ilocalg/papers/luo.py), unchanged in meaning."""
    # each method's mean error; the PDR drift (Spearman rho of its per-point error with the point index, L235);
    # how much each error jumps from one test position to the next (mean |change| within a walk, L239-241);
    # and, on new walkers drawn from a stream of their own (the tables above do not change), the step detector
    # against its sliding window (L175-177) and time window (L189) and eq. (4) against one constant step length
    # (L200)
    meas = [{"quantity": "mean error", "item": r["method"], "value": float(r["mean_error_m"]), "unit": "m"}
            for _, r in summ.iterrows()]
    meas.append({"quantity": "PDR only per-point error vs point index, Spearman rho", "item": "PDR only",
                 "value": float(pp["point"].corr(pp["PDR only"], method="spearman")), "unit": "-"})
    for mth in ("Wi-Fi only (KNN)", COMBINED, "PDR only"):
        jumps = tp[tp["method"] == mth].sort_values(["walker", "point"]).groupby("walker")["error_m"].diff().abs()
        meas.append({"quantity": "mean |error change| between successive test positions", "item": mth,
                     "value": float(jumps.mean()), "unit": "m"})
    m_rng = as_rng(seed).spawn(4)[3]
    m_walkers = gait.make_walkers(max(2, n_train // 2) + max(2, n_walkers // 2), m_rng)
    m_train, m_test = m_walkers[:max(2, n_train // 2)], m_walkers[max(2, n_train // 2):]
    det0 = {"rule": "literal", "threshold_mps2": 1.0, **(detector or {})}
    route_walks = [gait.simulate_walk(iloc_floor.route_xy_m(), w, m_rng) for w in m_test]
    logs = LuoLogs()  # each route walk's accelerometer array once for the five detectors
    for lab, det in (*((f"sliding window {ws:g} s", {**det0, "window_s": ws}) for ws in (0.1, 0.4, 1.2)),
                     ("time window 0.2-2 s", {**det0, "min_dt_s": 0.2, "max_dt_s": 2.0}),
                     ("time window 0.05-5 s", {**det0, "min_dt_s": 0.05, "max_dt_s": 5.0})):
        n_det = sum(len(logs.steps(sw.imu, 1.0, det)) for sw in route_walks)
        meas.append({"quantity": "detected / true steps", "item": lab,
                     "value": n_det / sum(len(sw.steps) for sw in route_walks), "unit": "-"})
    tr = [sw for _, _, sw in gait.training_walks(m_train, m_rng)]
    e4, ec = eq4_vs_constant_error(tr, [(length_m, sw) for _, length_m, sw in gait.training_walks(m_test, m_rng)],
                                   detector)
    meas += [{"quantity": "fixed-length walks 40-80 cm, mean relative step-length error", "item": "eq. (4)",
              "value": 100 * e4, "unit": "%"},
             {"quantity": "fixed-length walks 40-80 cm, mean relative step-length error",
              "item": "one constant step length", "value": 100 * ec, "unit": "%"}]
    return meas


def readings(adjust_weight: float = 0.5, detector: dict | None = None, scans_per_point=None,
             scan_latency_s: float = SCAN_LATENCY_S, scan_interval_s: float | None = None,
             principled: bool = True, lag_model: str = "measured") -> pd.DataFrame:
    """One row per modelling choice of :func:`run` (:mod:`ilocalg.papers.readings_luo`)."""
    det = {"rule": "literal", "threshold_mps2": 1.0, **(detector or {})}
    return readings_luo.readings(
        principled=principled, adjust_weight=adjust_weight, rule=det["rule"], threshold_mps2=det["threshold_mps2"],
        scans_per_point=scans_per_point if scans_per_point is not None else iloc_floor.SCANS_PER_POINT,
        scans_per_session=iloc_floor.PARAMS["scans_per_session"],
        scan_interval_s=iloc_scenario.resolve_scan_interval_s(scan_interval_s),
        scan_text=iloc_scenario.scan_model_text(lag_model, scan_latency_s),
        scan_source=iloc_scenario.scan_model_source(scan_interval_s))


def _scenario(seed, fast, n_walkers, n_train, n_cal, scans_per_point, scan_interval_s, scan_latency_s,
              lag_model="measured"):
    if fast:
        n_walkers, n_train, n_cal = min(n_walkers, 2), min(n_train, 3), min(n_cal, 5)
    spp = scans_per_point if scans_per_point is not None else (60 if fast else iloc_floor.SCANS_PER_POINT)
    # the tester's own walks train k (train_on_test_walkers); the survey and a standing calibration session
    # at the route points on another day come with the world
    return iloc_scenario.build(seed, n_walkers=n_walkers, n_train=n_train, n_cal=n_cal, scans_per_point=spp,
                               scan_interval_s=scan_interval_s, scan_latency_s=scan_latency_s,
                               train_on_test_walkers=True, lag_model=lag_model)


def run(seed: int = 0, fast: bool = False, n_walkers: int = 8, n_train: int = 8, n_cal: int = 10,
        detector: dict | None = None, sigma_theta_rad: float = 0.2, adjust_weight: float | None = None,
        scans_per_point: int | None = None, scan_latency_s: float = SCAN_LATENCY_S, sweeps: bool = True,
        scan_interval_s: float | None = None, budget: bool = True, claim_measures: bool = True,
        lag_model: str = "measured") -> dict[str, pd.DataFrame]:
    """PDR only, Wi-Fi only (KNN) and the paper's combination at the walking test positions (Fig 6).

    Parameters
    ----------
    detector : dict, optional
        Parameters of :func:`ilocalg.pdr.peak_window.detect_steps_peak_window` (default: its literal
        rule b, threshold 1.0 m/s^2).
    sigma_theta_rad : float
        Heading error sd of the KF variant whose ``Q`` also covers the heading.
    adjust_weight : float, optional
        Weight of the fingerprint adjustment of the default combination. The paper gives none; default
        (None) the steady-state inverse-variance weight from the training walks and the standing
        calibration session (:func:`principled_weight`). Swept in ``adjust_sweep``.
    scans_per_point : int, optional
        Survey scans per reference point (default: the i-Loc floor's 300; fast: 60).
    scan_latency_s, scan_interval_s, lag_model
        Periodic scans while walking, causal fixes (:mod:`ilocalg.sim.iloc_scenario`): the interval
        (default measured), the lag model (default the measured reading ages; ``"uniform"``: reads
        uniform within a scan of ``scan_latency_s``).
    sweeps : bool
        Also run the survey, detector and scan-latency sweeps (``survey_sweep``, ``detector_sweep``,
        ``latency_sweep``). The seed sweep and the claims' robustness samples read none of them and run with
        ``sweeps=False`` (:data:`ilocalg.workflow.manifest.SWEEP_KWARGS`): the other tables are the same either way.
    budget : bool
        Also compute the error budget of the combination and of PDR only.
    claim_measures : bool
        Also compute the claims ledger's scalars on extra walkers (the step detector's windows, eq. (4) against a
        constant; rows of ``measures``). Those walkers come from a random stream of their own, so every other table
        and row is the same without them (:func:`seed_table` reads only ``summary`` and ``calibration`` and leaves
        them out).

    Returns
    -------
    dict of DataFrame
        ``test_points`` (one row per walker, method and test position: the walker's true position when a
        fix became available while walking, ``point`` = the fix's number), ``summary``, ``cdf``,
        ``per_point`` (mean error per point and method over the walkers, for the points every walker
        reached: the Fig 6 curves), ``track_example``, ``calibration`` (k, sigma_SL, R, weight, ...),
        ``comparison``, ``readings``, ``adjust_sweep``, ``measures``, with ``budget`` ``budget`` and
        ``budget_inputs`` (the inputs against their truth), and with
        ``sweeps`` ``survey_sweep``, ``detector_sweep``, ``latency_sweep``.
    """
    scn = _scenario(seed, fast, n_walkers, n_train, n_cal, scans_per_point, scan_interval_s, scan_latency_s,
                    lag_model)
    shared = _Shared()  # the calls below share fits, fixes and PDR (same bits as computing them per call)
    tp, ex, info = _walk_tracks(scn, detector, sigma_theta_rad, ADJUST_WEIGHTS, principled=True, shared=shared)
    w_used = round(info["principled_weight"], 3) if adjust_weight is None else float(adjust_weight)
    if adjust_weight is not None and f"{COMBINED}, weight {w_used:g}" not in set(tp["method"]):
        tp, ex, info = _walk_tracks(scn, detector, sigma_theta_rad, ADJUST_WEIGHTS + (w_used,), principled=True,
                                    shared=shared)
    default = f"{COMBINED}, weight {w_used:g}"
    wts = sorted({float(m.rsplit(" ", 1)[1]) for m in tp["method"].unique() if m.startswith(COMBINED + ",")})
    mm0 = tp.groupby("method", sort=False)["error_m"].mean()
    adjust = pd.DataFrame([{"weight": w, "mean_error_m": float(mm0[f"{COMBINED}, weight {w:g}"]),
                            "wifi_only_mean_m": float(mm0["Wi-Fi only (KNN)"]),
                            "pdr_only_mean_m": float(mm0["PDR only"]),
                            "default": w == w_used} for w in wts])
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
    w_note = ("inverse-variance weight from the training data" if adjust_weight is None else "given weight")
    comp = [
        paper_ref(PAPER, "Fig 6", "Wi-Fi only (KNN, Manhattan, K=5) mean error", PAPER_LUO["wifi_mean_m"],
                  m["Wi-Fi only (KNN)"], "m", note + "; periodic walking scans, each fix scored when it is available"),
        paper_ref(PAPER, "Fig 6", "Wi-Fi only, smallest per-point error", PAPER_LUO["wifi_min_m"],
                  tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"].min(), "m", "over every walker and point"),
        paper_ref(PAPER, "Fig 6", "Wi-Fi only, largest per-point error", PAPER_LUO["wifi_max_m"],
                  tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"].max(), "m", "over every walker and point"),
        paper_ref(PAPER, "Fig 6", "combined mean error (Wi-Fi start + fingerprint adjustment)",
                  PAPER_LUO["combined_mean_m"], m[COMBINED], "m", note + f"; weight {w_used:g} ({w_note})"),
        paper_ref(PAPER, "Fig 6", "combined / Wi-Fi only mean error",
                  PAPER_LUO["combined_mean_m"] / PAPER_LUO["wifi_mean_m"],
                  m[COMBINED] / m["Wi-Fi only (KNN)"], "-", "the improvement ratio (one seed; see seed_table)"),
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
                          {"quantity": "WDM heading error rms on the training walks [rad]", "value": info["sig_theta"]},
                          {"quantity": "PDR variance per axis between two fixes [m^2]", "value": info["q_var"]},
                          {"quantity": "adjustment weight, inverse variances (training data)",
                           "value": info["principled_weight"]},
                          {"quantity": "adjustment weight used", "value": w_used},
                          {"quantity": "survey scans per reference point", "value": info["scans_per_point"]},
                          {"quantity": "scan latency [s] (uniform lag model only)", "value": info["scan_latency_s"]},
                          {"quantity": "scan interval = time between test positions [s]",
                           "value": info["scan_interval_s"]},
                          {"quantity": "test positions per walker (points every walker reached)", "value": n_common},
                          {"quantity": "Wi-Fi start: mean error of the initial fix [m]",
                           "value": info["start_fix_error_m"]},
                          {"quantity": "test scans hearing no AP (no Wi-Fi fix)", "value": info["n_deaf"]},
                          {"quantity": "Wi-Fi only per-point mean error, min over points [m]", "value": wifi_pp.min()},
                          {"quantity": "Wi-Fi only per-point mean error, max over points [m]", "value": wifi_pp.max()}])
    # named scalars for the claims ledger ("combined / Wi-Fi only mean error" is a comparison row, not repeated)
    measures = [{"quantity": "adjustment weight used", "value": w_used, "unit": "-"},
                {"quantity": "i-Loc step KF / Wi-Fi only mean error", "value": m[KF_ALT] / m["Wi-Fi only (KNN)"],
                 "unit": "-"}]
    if claim_measures:
        measures += _claim_measures(seed, tp, pp, summ, n_walkers, n_train, detector)
    out = {"test_points": tp, "summary": summ, "cdf": cdf, "per_point": pp,
           "track_example": pd.concat(ex, ignore_index=True), "calibration": calib,
           "comparison": comparison_table(comp),
           "readings": readings(w_used, detector, scans_per_point, scan_latency_s, scan_interval_s,
                                adjust_weight is None, lag_model),
           "adjust_sweep": adjust}
    if budget:
        bud = error_budget(info["inputs"], {COMBINED: combined_method(w_used), "PDR only": pdr_true_start_method})
        out["budget"] = bud
        out["budget_inputs"] = input_diagnostics(info["inputs"])
        for r in bud[bud["replaced_by_truth"].isin(BUDGET_SOURCES)].itertuples():
            measures.append({"quantity": f"budget share: {r.replaced_by_truth}", "value": r.share_of_error,
                             "unit": "-", "item": r.method})
    out["measures"] = pd.DataFrame([{"item": "", **r} for r in measures])[["quantity", "value", "unit", "item"]]
    if sweeps:
        def _means(t2):
            return t2.groupby("method", sort=False)["error_m"].mean()
        srows = []
        for spp in ((60,) if fast else SURVEY_SCANS):
            # the run's own survey size is the run's scenario (the same seed and settings): not built again
            s2 = (scn if spp == scn.params["scans_per_point"] else
                  _scenario(seed, fast, n_walkers, n_train, n_cal, spp, scan_interval_s, scan_latency_s, lag_model))
            t2, _, i2 = _walk_tracks(s2, detector, sigma_theta_rad, (w_used,), principled=False, shared=shared)
            mm = _means(t2)
            srows.append({"scans_per_point": i2["scans_per_point"], "wifi_only_mean_m": mm["Wi-Fi only (KNN)"],
                          "combined_mean_m": mm[f"{COMBINED}, weight {w_used:g}"],
                          "kf_alt_mean_m": mm[KF_ALT], "pdr_only_mean_m": mm["PDR only"]})
        out["survey_sweep"] = pd.DataFrame(srows)
        drows = []
        for name, det in (DETECTOR_VARIANTS[:2] if fast else DETECTOR_VARIANTS):
            t2, _, i2 = _walk_tracks(scn, det, sigma_theta_rad, (w_used,), principled=False, shared=shared)
            mm = _means(t2)
            drows.append({"detector": name, "det_over_true_steps": i2["det_over_true_steps"], "k": i2["k"],
                          "pdr_only_mean_m": mm["PDR only"],
                          "combined_mean_m": mm[f"{COMBINED}, weight {w_used:g}"],
                          "kf_alt_mean_m": mm[KF_ALT]})
        out["detector_sweep"] = pd.DataFrame(drows)
        lrows = []
        for lat in ((scan_latency_s,) if fast else LATENCIES_S):  # the uniform-within-a-scan model
            s2 = iloc_scenario.rescan(scn, seed, scan_interval_s=max(scn.params["scan_interval_s"], lat),
                                      scan_latency_s=lat,
                                      lag_model="uniform")
            t2, _, i2 = _walk_tracks(s2, detector, sigma_theta_rad, (w_used,), principled=False, shared=shared)
            mm = _means(t2)
            lrows.append({"scan_latency_s": lat, "scan_interval_s": max(scn.params["scan_interval_s"], lat),
                          "test_positions": int(t2[t2["method"] == "PDR only"].shape[0]),
                          "wifi_only_mean_m": mm["Wi-Fi only (KNN)"], "pdr_only_mean_m": mm["PDR only"],
                          "combined_mean_m": mm[f"{COMBINED}, weight {w_used:g}"],
                          "kf_alt_mean_m": mm[KF_ALT]})
        out["latency_sweep"] = pd.DataFrame(lrows)
    return out


def seed_table(seeds=range(5), fast: bool = False, runs: dict | None = None,
               **params) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The headline over several seeds: each seed's Wi-Fi only and combined means and their ratio, and the
    ratio's mean with a Student-t 95 % interval (:func:`ilocalg.papers.claims.interval`).

    ``runs`` maps a seed to the tables :func:`run` already returned for it with the same ``fast`` and
    ``params`` (a notebook's own run): that seed is read from them, not run again (its ``summary`` and
    ``calibration`` do not depend on ``sweeps`` or ``budget``).

    Returns
    -------
    per_seed : DataFrame (``seed``, ``wifi_only_mean_m``, ``combined_mean_m``, ``ratio``, ``weight``)
    headline : DataFrame, one row: ``quantity``, ``mean``, ``ci_low``, ``ci_high``, ``n_seeds``, ``paper_value``
    """
    rows = []
    for s in seeds:
        t = (runs or {}).get(s) or run(seed=s, fast=fast, sweeps=False, budget=False, claim_measures=False,
                                       **params)
        m = t["summary"].set_index("method")["mean_error_m"]
        w = t["calibration"].set_index("quantity")["value"]["adjustment weight used"]
        rows.append({"seed": s, "wifi_only_mean_m": m["Wi-Fi only (KNN)"], "combined_mean_m": m[COMBINED],
                     "ratio": m[COMBINED] / m["Wi-Fi only (KNN)"], "weight": w})
    per = pd.DataFrame(rows)
    mean, lo, hi, n = interval(per["ratio"])
    head = pd.DataFrame([{"quantity": "combined / Wi-Fi only mean error", "mean": mean, "ci_low": lo, "ci_high": hi,
                          "n_seeds": n, "paper_value": PAPER_LUO["combined_mean_m"] / PAPER_LUO["wifi_mean_m"]}])
    return per, head


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
    aw = tables["adjust_sweep"]
    if "default" in aw.columns and aw["default"].any():
        d = aw[aw["default"]].iloc[0]
        b = aw.loc[aw["mean_error_m"].idxmin()]
        lines.append(f"Adjustment weight {d['weight']:.2f} (inverse variances measured on training data): "
                     f"{d['mean_error_m']:.2f} m; the sweep's lowest error is {b['mean_error_m']:.2f} m at weight "
                     f"{b['weight']:g}, a value read off the outcome and not used.")
    if "budget" in tables:
        bd = tables["budget"]
        k = bd[(bd["method"] == COMBINED) & bd["replaced_by_truth"].isin(BUDGET_SOURCES)].set_index("replaced_by_truth")
        lines.append("Error budget of the combination (share of its mean error removed when the source is true): "
                     + ", ".join(f"{s} {v:.0%}" for s, v in k["share_of_error"].items()) + ".")
    if "budget_inputs" in tables:
        lines.append(inputs_sentence(tables["budget_inputs"]))
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
