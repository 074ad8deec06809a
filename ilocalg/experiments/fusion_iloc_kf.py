"""The i-Loc Kalman filter (PTS + Wi-Fi) on the simulated i-Loc floor (i-Loc thesis ch. 5, Figs 22-23).

Data: the simulated i-Loc floor (:mod:`ilocalg.sim.iloc_floor`) and new simulated walkers
(:mod:`ilocalg.sim.gait`, not the walkers SAM and SLM were trained on) walking the floor's 28-point
test route (about 4 m apart, L515), the same route as notebooks 01 and 05:

* World: built once as a scenario (:func:`ilocalg.sim.iloc_scenario.build`): the survey, a standing
  calibration session on another day, fixed-length training walks, and the test walks with their IMU
  logs and Wi-Fi scans; the experiment only applies methods to it.
* Wi-Fi: the estimator (Simplified-Horus by default, the thesis's choice) is fitted on the survey.
  The phone scans periodically while walking (L777): one scan every ``scan_interval_s``, each AP read
  within the scan's ``scan_latency_s``; a fix is available only when its scan ends (causal); each
  walk is its own session (its own per-AP drift).
* R: per test point, the variance of the fix error over the chapter 3 test session (standing scans
  at the 28 points on another day: how Table 5 was made, L588); a fix gets the R of the test point
  nearest to it; the thesis's Table 5 as R and one constant R are the labelled alternatives.
* Q (eq. 22): rank 1 along the heading with Table 4's variances read as relative variances (L478);
  the m^2 reading is shown beside it.
* Start: a Wi-Fi fix from a scan at the start (L792-795), with its point's R as P0; PTS alone is
  shown from that start and from the true start.
* PTS: SAM steps (ranges = 5-95 % of the training steps' features, L399), quadratic SLM lengths,
  WDM headings.
* KF (eq. 20-26): one predict per detected step, one update per Wi-Fi fix (on the latest state at
  or before the scan's end, when the fix becomes available).

Scored: the position error at each of the 28 test points (each track's latest state at the passing
time; Wi-Fi only = the latest fix available then). Beyond the paper: a heading-error term in Q,
fixed-lag and RTS smoothing, innovation gating, and an error budget (:mod:`ilocalg.fusion.budget`:
the KF and PTS rerun with one error source replaced by the truth at a time).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Ch. 3-5, eq. (20)-(26), Tables 4-5, Figs 22-23.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.fusion import PAPER_TABLE5_SIGMA_RF_VAR_M2
from ilocalg.fusion.budget import SOURCES as BUDGET_SOURCES
from ilocalg.fusion.budget import FusionInputs, error_budget, input_diagnostics, inputs_sentence
from ilocalg.fusion.iloc_kf import kf_method, nearest_point_variance, pts_method, run_filters
from ilocalg.fusion.tracks import score_at_times
from ilocalg.metrics import summarise_by_method
from ilocalg.papers import PAPERS, comparison_table, paper_ref, readings_iloc
from ilocalg.papers.iloc import PUBLISHED
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.pts import pts_filter_inputs
from ilocalg.pdr.sam import learn_feature_ranges
from ilocalg.pdr.step_length import fit_step_length_models
from ilocalg.sim import gait, iloc_floor, iloc_scenario
from ilocalg.sim.iloc_scenario import SCAN_LATENCY_S, walk_fixes

__all__ = ["run", "readings", "findings", "PAPER_KF"]

MAIN = "KF (R calibrated)"

PAPER = PAPERS["iloc"]
#: The thesis's published values (:data:`ilocalg.papers.iloc.PUBLISHED`, ch. 5 "5.15 m -> 2.82 m"): reference only.
PAPER_KF = PUBLISHED["fusion_iloc_kf"]


def _train_pts(scn, q_range=(0.05, 0.95)):
    feats = gait.fixed_length_features(list(scn.train_walks))
    models, _ = fit_step_length_models(feats)
    return learn_feature_ranges(feats, *q_range), models


def readings(scan_latency_s: float = SCAN_LATENCY_S, q_range=(0.05, 0.95), table4_reading: str = "relative",
             scan_interval_s: float | None = None, lag_model: str = "measured") -> pd.DataFrame:
    """The modelling choices of this experiment against the thesis's text (:mod:`ilocalg.papers.readings_iloc`)."""
    return readings_iloc.readings(
        "fusion_iloc_kf", q_range=q_range, table4_reading=table4_reading,
        scan_interval_s=iloc_scenario.resolve_scan_interval_s(scan_interval_s),
        scan_text=iloc_scenario.scan_model_text(lag_model, scan_latency_s),
        scan_source=iloc_scenario.scan_model_source(scan_interval_s))


def _walk_tracks(scn, est, cal_var, ranges, models, table4_reading, gate_prob, sigma_theta_rad, lag,
                 main_only=False):
    """Every track of every walk on a scenario: test-point table, gating, example, budget inputs."""
    route = scn.route_xy_m
    paper_r = np.asarray(PAPER_TABLE5_SIGMA_RF_VAR_M2, dtype=np.float64)
    r_cal = nearest_point_variance(route, cal_var)
    r_paper = nearest_point_variance(route, paper_r)
    tps, gat, ex, inputs = [], [], [], []
    for w_i, w in enumerate(scn.walks):
        heads = log_headings_rad(w.imu, w.stand_s)
        pdr = pts_filter_inputs(w.imu, ranges, models["SLM quadratic"], w.stand_s, headings=heads)
        fx = walk_fixes(scn, w, est)
        start_fix = fx[["fix_x_m", "fix_y_m"]].to_numpy()[0]
        f = fx.iloc[1:]
        fix = f[["fix_x_m", "fix_y_m"]].to_numpy()
        fix_t = f["t_ready_s"].to_numpy()
        x0 = start_fix if np.isfinite(start_fix).all() else route[0]
        r_var = {"R calibrated": r_cal(fix)}
        if not main_only:
            r_var.update({"R = thesis Table 5": r_paper(fix), "R constant": np.full(len(fix), cal_var.mean())})
        tracks, info = run_filters(x0, pdr, fix_t, fix, r_var, P0_var_m2=float(r_cal(x0)[0]), gate_prob=gate_prob,
                                   sigma_theta_rad=sigma_theta_rad, lag=lag, table4_reading=table4_reading)
        tracks = {"PTS (Wi-Fi start)" if k == "PTS" else k: v for k, v in tracks.items()}
        tracks["PTS (true start)"] = dead_reckon(pdr["step_m"], pdr["theta_rad"], *route[0])[["x_m", "y_m"]].to_numpy()
        tps.append(score_at_times(tracks, pdr["state_t_s"], w.pass_t_s, route, fix_t, fix, x0).assign(walker=w.name))
        inputs.append(FusionInputs.from_walk(
            w, state_t_s=pdr["state_t_s"], step_m=pdr["step_m"], theta_rad=pdr["theta_rad"], heading_rad=heads["WDM"],
            start_xy_m=start_fix, start_ref_t_s=fx["t_ref_s"].iloc[0], fixes=f, eval_t_s=w.pass_t_s, eval_xy_m=route))
        gat.append({"walker": w.name, "fixes": info["n_fixes"], "gated_out": info["n_gated"],
                    "superseded": info["n_superseded"], "steps_detected": int(pdr["step_m"].size),
                    "steps_true": int(len(w.steps)), "start_fix_error_m": float(np.hypot(*(x0 - route[0]))),
                    "median_aps_heard": float(fx["n_heard"].median()),
                    "mean_fix_age_at_entry_s": float((f["t_ready_s"] - f["t_ref_s"]).mean())})
        if w_i == 0:
            ex.append(pd.DataFrame({"method": "truth", "x_m": np.r_[route[0, 0], w.steps["x_m"]],
                                    "y_m": np.r_[route[0, 1], w.steps["y_m"]]}))
            ex.append(pd.DataFrame({"method": "Wi-Fi only", "x_m": fix[:, 0], "y_m": fix[:, 1]}))
            ex += [pd.DataFrame({"method": k, "x_m": v[:, 0], "y_m": v[:, 1]}) for k, v in tracks.items()]
    tp = pd.concat(tps, ignore_index=True)
    tp = tp[["walker"] + [c for c in tp.columns if c != "walker"]]
    return tp, gat, ex, inputs, r_cal


def run(seed: int = 0, fast: bool = False, n_walkers: int = 8, n_train: int = 8, n_cal: int = 20,
        method: str = "Simplified-Horus", q_range=(0.05, 0.95), scan_latency_s: float = SCAN_LATENCY_S,
        table4_reading: str = "relative", gate_prob: float = 0.99, sigma_theta_rad: float = 0.2,
        lag: int = 5, wifi_methods=("Simplified-RADAR", "Simplified-Horus", "KNN (Manhattan, K=5)"),
        latencies_s=(0.0, 1.0, 2.0, 3.0), scan_interval_s: float | None = None,
        budget: bool = True, lag_model: str = "measured") -> dict[str, pd.DataFrame]:
    """Wi-Fi only, PTS only and the KF variants at the 28 test points (Figs 22-23) for ``n_walkers`` new walkers.

    The world is built once (:func:`ilocalg.sim.iloc_scenario.build`); everything below applies methods
    to that scenario.

    Returns
    -------
    dict of DataFrame
        ``test_points`` (walker, method, point, true/estimated position, error), ``summary``, ``cdf``,
        ``track_example`` (walker 0: every track, the truth and the fixes), ``r_table`` (calibrated
        per-point fix variance beside the thesis's Table 5), ``gating``, ``comparison``,
        ``by_wifi_method`` (the main variants with each estimator of ``wifi_methods``, same scenario),
        ``latency_sweep`` (Wi-Fi only and the main KF with each scan latency of ``latencies_s``: same
        walks, new scans), ``budget`` (the error budget of the main KF and PTS), ``budget_inputs`` (the inputs against
        their truth: fix offsets and age, step counts, distance, heading), ``measures``, ``readings``.

    ``wifi_methods=()`` and ``latencies_s=()`` leave ``by_wifi_method`` and ``latency_sweep`` empty and every other
    table as it is: the seed sweep and the claims' robustness samples read neither and run so
    (:data:`ilocalg.workflow.manifest.SWEEP_KWARGS`).
    """
    if fast:
        n_walkers, n_train, n_cal = min(n_walkers, 2), min(n_train, 3), min(n_cal, 5)
    scn = iloc_scenario.build(seed, n_walkers=n_walkers, n_train=n_train, n_cal=n_cal,
                              scans_per_point=60 if fast else None, scan_interval_s=scan_interval_s,
                              scan_latency_s=scan_latency_s, lag_model=lag_model)
    iv = scn.params["scan_interval_s"]
    ranges, models = _train_pts(scn, q_range)
    est = iloc_floor.fit_estimator(scn.floor, method)
    cal_var = iloc_floor.standing_fix_variance_m2(scn.floor, est)
    tp, gat, ex, inputs, r_cal = _walk_tracks(scn, est, cal_var, ranges, models, table4_reading, gate_prob,
                                              sigma_theta_rad, lag)
    route = scn.route_xy_m
    paper_r = np.asarray(PAPER_TABLE5_SIGMA_RF_VAR_M2, dtype=np.float64)
    summ, cdf = summarise_by_method(tp)
    m = summ.set_index("method")["mean_error_m"]
    note = (f"{n_walkers} new simulated walkers on the floor's 28-point route; Wi-Fi: {method}; periodic causal "
            f"scans every {iv:g} s")
    comp = [
        paper_ref(PAPER, "Fig 23", "PTS mean error at the test points", PAPER_KF["pts_mean_m"],
                  m["PTS (Wi-Fi start)"], "m", note + "; PTS from the Wi-Fi start"),
        paper_ref(PAPER, "Fig 23", "KF (PTS + Wi-Fi) mean error at the test points", PAPER_KF["kf_mean_m"],
                  m[MAIN], "m", "R per point from the chapter 3 test session (the thesis' Table 5 procedure)"),
        paper_ref(PAPER, "Fig 23", "KF mean error, R = the thesis' Table 5", PAPER_KF["kf_mean_m"],
                  m["KF (R = thesis Table 5)"], "m", "the thesis' variances, measured on its floor",
                  row_class="alternative reading", replaces="KF (PTS + Wi-Fi) mean error at the test points"),
        paper_ref(PAPER, "Fig 23", "KF mean / PTS mean", PAPER_KF["kf_mean_m"] / PAPER_KF["pts_mean_m"],
                  m[MAIN] / m["PTS (Wi-Fi start)"], "-", "the improvement ratio"),
    ]
    # named scalars for the claims ledger: every method's mean and median error (as on main, c62a9bb), the KF
    # against its own (causal) Wi-Fi, and the budget shares below; "KF mean / PTS mean" is a comparison row
    measures = [{"quantity": f"{stat} error at the test points", "item": r["method"],
                 "value": float(r[f"{stat}_error_m"]), "unit": "m"}
                for _, r in summ.iterrows() for stat in ("mean", "median")]
    measures.append({"quantity": "KF mean / Wi-Fi only mean", "value": m[MAIN] / m["Wi-Fi only"], "unit": "-"})
    out = {"test_points": tp, "summary": summ, "cdf": cdf, "track_example": pd.concat(ex, ignore_index=True),
           "gating": pd.DataFrame(gat), "comparison": comparison_table(comp)}
    if budget:
        bud = error_budget(inputs, {MAIN: kf_method(r_cal, table4_reading), "PTS (Wi-Fi start)": pts_method})
        out["budget"] = bud
        out["budget_inputs"] = input_diagnostics(inputs)
        for r in bud[bud["replaced_by_truth"].isin(BUDGET_SOURCES)].itertuples():
            measures.append({"quantity": f"budget share: {r.replaced_by_truth}", "value": r.share_of_error,
                             "unit": "-", "item": r.method})
    by_method = []
    for meth in wifi_methods or ():  # the main variants with each Wi-Fi estimator, on the same scenario
        if meth == method:  # the run's own estimator: its tracks are the run's
            t2 = tp
        else:
            e2 = iloc_floor.fit_estimator(scn.floor, meth)
            cv2 = iloc_floor.standing_fix_variance_m2(scn.floor, e2)
            t2 = _walk_tracks(scn, e2, cv2, ranges, models, table4_reading, gate_prob, sigma_theta_rad, lag)[0]
        mm = t2.groupby("method", sort=False)["error_m"].mean()
        by_method.append({"wifi_method": meth, "wifi_only_mean_m": mm["Wi-Fi only"],
                          "pts_mean_m": mm["PTS (Wi-Fi start)"], "kf_mean_m": mm[MAIN],
                          "kf_table5_mean_m": mm["KF (R = thesis Table 5)"],
                          "kf_constant_r_mean_m": mm["KF (R constant)"],
                          "kf_rts_mean_m": mm[f"{MAIN} + RTS"],
                          "kf_heading_noise_rts_mean_m": mm[f"{MAIN} + heading noise + RTS"]})
    lat_rows = []
    for lat in latencies_s:  # same world and walks, new periodic scans (uniform reads within a scan of each latency)
        s2 = iloc_scenario.rescan(scn, seed, scan_interval_s=max(iv, lat), scan_latency_s=lat,
                                  lag_model="uniform")
        t2 = _walk_tracks(s2, est, cal_var, ranges, models, table4_reading, gate_prob, sigma_theta_rad, lag,
                          main_only=True)[0]
        mm = t2.groupby("method", sort=False)["error_m"].mean()
        lat_rows.append({"scan_latency_s": float(lat), "scan_interval_s": float(max(iv, lat)),
                         "wifi_only_mean_m": mm["Wi-Fi only"], "kf_mean_m": mm[MAIN],
                         "kf_heading_noise_rts_mean_m": mm[f"{MAIN} + heading noise + RTS"]})
    out.update({
        "r_table": pd.DataFrame({"point": np.arange(1, route.shape[0] + 1), "x_m": route[:, 0], "y_m": route[:, 1],
                                 "calibrated_var_m2": cal_var, "thesis_table5_var_m2_paper": paper_r}),
        "by_wifi_method": pd.DataFrame(by_method), "latency_sweep": pd.DataFrame(lat_rows),
        "measures": pd.DataFrame([{"item": "", **r} for r in measures])[["quantity", "value", "unit", "item"]],
        "readings": readings(scan_latency_s, q_range, table4_reading, scan_interval_s, lag_model)})
    return out


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    m = tables["summary"].set_index("method")["mean_error_m"].rename({"PTS (Wi-Fi start)": "PTS"})
    kf = m[MAIN]
    best = m.drop(["Wi-Fi only", "PTS", "PTS (true start)"]).idxmin()
    g = tables["gating"]
    r = tables["r_table"]
    lines = [
        f"Mean error at the test points: PTS {m['PTS']:.2f} m, Wi-Fi only {m['Wi-Fi only']:.2f} m (the latest fix "
        f"available when the point is passed), KF {kf:.2f} m (thesis, paper values: PTS {PAPER_KF['pts_mean_m']} m, "
        f"KF {PAPER_KF['kf_mean_m']} m).",
        f"The KF is {'better' if kf < min(m['PTS'], m['Wi-Fi only']) else 'not better'} than both inputs; "
        f"KF / PTS = {kf / m['PTS']:.2f} (thesis {PAPER_KF['kf_mean_m'] / PAPER_KF['pts_mean_m']:.2f}, paper); "
        f"KF / Wi-Fi only = {kf / m['Wi-Fi only']:.2f}.",
        f"With the thesis's Table 5 as R: {m['KF (R = thesis Table 5)']:.2f} m; "
        f"with one constant R (no knowledge of where a fix was taken): {m['KF (R constant)']:.2f} m, "
        f"{'better' if m['KF (R constant)'] < m['Wi-Fi only'] else 'not better'} than Wi-Fi alone.",
        f"Best variant: {best} ({m[best]:.2f} m). Gating rejected {int(g['gated_out'].sum())} of "
        f"{int(g['fixes'].sum())} fixes.",
        f"Fix variance per point: calibrated median {r['calibrated_var_m2'].median():.2f} m^2, thesis Table 5 median "
        f"{r['thesis_table5_var_m2_paper'].median():.2f} m^2 (paper values); the thesis' is larger at "
        f"{int((r['thesis_table5_var_m2_paper'] > r['calibrated_var_m2']).sum())} of {len(r)} points.",
    ]
    if "budget" in tables:
        b = tables["budget"]
        k = b[(b["method"] == MAIN) & b["replaced_by_truth"].isin(BUDGET_SOURCES)].set_index("replaced_by_truth")
        top = k["share_of_error"].idxmax()
        lines.append(f"Error budget of the KF: {top} carries the largest share ({k.loc[top, 'share_of_error']:.0%} of "
                     "the mean error disappears when it is replaced by the truth); "
                     + ", ".join(f"{s} {v:.0%}" for s, v in k["share_of_error"].items()) + ".")
    if "budget_inputs" in tables:
        lines.append(inputs_sentence(tables["budget_inputs"]))
    return "\n".join(lines)
