"""The i-Loc Kalman filter (PTS + Wi-Fi) on the simulated i-Loc floor (i-Loc thesis ch. 5, Figs 22-23).

Data: the simulated i-Loc floor (:mod:`ilocalg.sim.iloc_floor`) and new simulated walkers
(:mod:`ilocalg.sim.gait`, not the walkers SAM and SLM were trained on) walking the floor's 28-point
test route (about 4 m apart, L515), the same route as notebooks 01 and 05:

* Wi-Fi: the estimator (Simplified-Horus by default, the thesis's choice) is fitted on the survey.
  A fix is one scan taken while walking, started when the walker passes a test point and tagged
  there; each AP is read during the scan (``scan_latency_s``, 2 s), so the scan hears the walker
  metres further on; each walk is its own session (its own per-AP drift).
* R: per test point, the variance of the fix error over the chapter 3 test session (standing scans
  at the 28 points on another day: how Table 5 was made, L588); the thesis's Table 5 as R and one
  constant R are the labelled alternatives.
* Q (eq. 22): rank 1 along the heading with Table 4's variances read as relative variances (L478);
  the m^2 reading is shown beside it.
* Start: a Wi-Fi fix from a scan at the start (L792-795), with its point's R as P0; PTS alone is
  shown from that start and from the true start.
* PTS: SAM steps (ranges = 5-95 % of the training steps' features, L399), quadratic SLM lengths,
  WDM headings.
* KF (eq. 20-26): one predict per detected step, one update per Wi-Fi fix (on the latest state at
  or before the scan's start).

Scored: the position error at each of the 28 test points (the state at the passing time; Wi-Fi
only = the fix tagged there). Beyond the paper: a heading-error term in Q, fixed-lag and RTS
smoothing, innovation gating.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Ch. 3-5, eq. (20)-(26), Tables 4-5, Figs 22-23.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.fusion import (
    PAPER_TABLE5_SIGMA_RF_VAR_M2,
    filter_walk,
    fixed_lag_smooth,
    fixes_at_states,
    nis_gate,
    rts_smooth,
    sigma_sl_paper_m,
)
from ilocalg.metrics import summarise_by_method
from ilocalg.papers import PAPERS, comparison_table, paper_ref, reading, readings_table
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.pts import pts_steps
from ilocalg.pdr.sam import learn_feature_ranges
from ilocalg.pdr.step_length import fit_step_length_models
from ilocalg.sim import gait, iloc_floor
from ilocalg.units import as_rng

__all__ = ["run", "route_walk", "run_filters", "score_points", "readings", "PAPER_KF"]

_T = "i-Loc (Chiu 2013)"
MAIN = "KF (R calibrated)"

PAPER = PAPERS["iloc"]
# Settings from the paper
# -----------------------
# PAPER_KF: Chiu (2013) ch. 5, text below Table 5 and Fig 23 ("5.15 m -> 2.82 m"); reference only.
#: Published values (paper, thesis ch. 5 text below Table 5 and Fig 23): reference only.
PAPER_KF = {"pts_mean_m": 5.15, "kf_mean_m": 2.82}


def route_walk(sw, ranges, slm_p) -> dict:
    """The thesis' PTS (:func:`ilocalg.pdr.pts.pts_steps`) on one simulated walk, as filter inputs.

    Returns ``state_t_s`` (n+1: the log start, then each detected step), ``step_m``, ``theta_rad`` (n).
    """
    st = pts_steps(sw.imu, ranges, slm_p, sw.config.stand_s)
    return {"state_t_s": np.concatenate([[sw.imu.index[0]], st["t_s"].to_numpy()]),
            "step_m": st["length_m"].to_numpy(), "theta_rad": st["theta_rad"].to_numpy()}


def run_filters(x0_m, pdr: dict, fix_t_s, fix_xy_m, r_var: dict, P0_var_m2: float = 0.25, gate_prob: float = 0.99,
                sigma_theta_rad: float = 0.2, lag: int = 5, table4_reading: str = "relative") -> tuple[dict, dict]:
    """Every PDR / KF variant on one walk.

    Parameters
    ----------
    x0_m : (2,) start position.
    pdr : dict from :func:`route_walk` (or any dict with ``state_t_s``, ``step_m``, ``theta_rad``).
    fix_t_s, fix_xy_m : (m,), (m, 2) Wi-Fi fixes (time order); a NaN row is a scan without a fix.
    r_var : dict label -> (m,) isotropic fix variances (one KF variant per entry; the first is the main one).
    P0_var_m2 : float, the start's variance per axis.
    table4_reading : {"relative", "m2"}, how Table 4 reads (:func:`ilocalg.fusion.sigma_sl_paper_m`); the
        main variant is also run with the other reading.

    Returns
    -------
    tracks : dict label -> (n+1, 2) state estimates (``"PTS"``, ``"KF (...)"``, ...)
    info : dict with ``state_index`` of each fix, the number of gated fixes, ``n_superseded``.
    """
    ts, d, th = pdr["state_t_s"], pdr["step_m"], pdr["theta_rad"]
    n1 = ts.size
    tr = dead_reckon(d, th, *x0_m)[["x_m", "y_m"]].to_numpy()
    tracks = {"PTS": tr}
    first = next(iter(r_var))
    fxy = np.asarray(fix_xy_m, dtype=np.float64)
    ok = np.isfinite(fxy).all(axis=1)
    # align on the fix times (positions only fill the slots; a scan without a fix leaves its state empty)
    al = fixes_at_states(ts, fix_t_s, np.where(ok[:, None], fxy, 0.0), before_start="drop", same_state="last")
    used = al.used & ok
    z = np.full((n1, 2), np.nan)
    z[al.state_index[used]] = fxy[used]
    other = "m2" if table4_reading == "relative" else "relative"
    sig = sigma_sl_paper_m(d, reading=table4_reading)
    P0 = P0_var_m2 * np.eye(2)
    info = {"state_index": al.state_index, "n_superseded": al.n_superseded, "n_before_start": al.n_before_start}
    for label, rv in r_var.items():
        r = np.full(n1, np.nan)
        r[al.state_index[used]] = np.asarray(rv, dtype=np.float64)[used]
        rr = np.where(np.isnan(r), 1.0, r)
        res = filter_walk(x0_m, P0, th, d, sig, z, r_var_m2=rr)
        tracks[f"KF ({label})"] = res.x
        if label == first:
            alt = filter_walk(x0_m, P0, th, d, sigma_sl_paper_m(d, reading=other), z, r_var_m2=rr)
            tracks[f"KF ({label}, Table 4 read as {other})"] = alt.x
            tracks[f"KF ({label}) + RTS"] = rts_smooth(res).x
            tracks[f"KF ({label}) + fixed-lag {lag}"] = fixed_lag_smooth(res, lag).x
            h = filter_walk(x0_m, P0, th, d, sig, z, r_var_m2=rr, sigma_theta_rad=sigma_theta_rad)
            tracks[f"KF ({label}) + heading noise"] = h.x
            tracks[f"KF ({label}) + heading noise + RTS"] = rts_smooth(h).x
            # gating needs a P that admits the heading error, else good fixes are rejected as the PTS drifts
            g = filter_walk(x0_m, P0, th, d, sig, z, r_var_m2=rr, gate_nis=nis_gate(gate_prob),
                            sigma_theta_rad=sigma_theta_rad)
            tracks[f"KF ({label}) + heading noise + gating"] = g.x
            info["n_gated"] = int(g.n_rejected)
            info["n_fixes"] = int(used.sum())
    return tracks, info


def score_points(tracks: dict, state_index: np.ndarray, true_xy_m: np.ndarray, fix_xy_m: np.ndarray) -> pd.DataFrame:
    """Error at each point: every track's state at the point's state index; Wi-Fi only = the fix itself."""
    rows = []
    ok = state_index >= 0
    k = np.where(ok, state_index, 0)
    n = true_xy_m.shape[0]
    for label, xy in {"Wi-Fi only": None, **tracks}.items():
        est = fix_xy_m if xy is None else np.where(ok[:, None], xy[k], np.nan)
        rows.append(pd.DataFrame({"method": label, "point": np.arange(1, n + 1), "x_true_m": true_xy_m[:, 0],
                                  "y_true_m": true_xy_m[:, 1], "x_est_m": est[:, 0], "y_est_m": est[:, 1],
                                  "error_m": np.hypot(*(est - true_xy_m).T)}))
    return pd.concat(rows, ignore_index=True)


def _train_pts(rng, n_train, q_range=(0.05, 0.95)):
    walkers = gait.make_walkers(n_train, rng)
    feats = gait.fixed_length_features(gait.training_walks(walkers, rng))
    models, _ = fit_step_length_models(feats)
    return walkers, feats, learn_feature_ranges(feats, *q_range), models


def readings(scan_latency_s: float = 2.0, q_range=(0.05, 0.95), table4_reading: str = "relative") -> pd.DataFrame:
    """The modelling choices of this experiment against the thesis's text, one row each."""
    rows = [
        ("route", f"{_T}, L515, L588", "28 test points 4.11 m apart, also the Wi-Fi test points",
         "the floor's 28-point route 4 m apart (shared with notebooks 01, 05)", "2 m grid of L295; Fig 2 missing"),
        ("Wi-Fi fix", f"{_T}, L779", "Wi-Fi positions from scans taken while the user walks",
         f"one scan per test point, started when passing it and tagged there; each AP read within "
         f"{scan_latency_s:g} s; a new session (drift) per walk",
         "scan latency: assumption (phones 1-3 s), swept in latency_sweep"),
        ("R", f"{_T}, L586-588, Table 5", "R = sigma_RF^2 I, per test point, from the Wi-Fi experiment at the "
         "28 points", "per-point error variance of the chapter 3 test session (standing scans, another day)",
         "Table 5 as R and a constant R: labelled alternatives"),
        ("Q", f"{_T}, L574-578, Table 4 (L602-605)", "Q = sigma_SL^2 [cos^2, sc; sc, sin^2]; Table 4 prints no unit",
         "Table 4 read as " + ("relative variances (sigma = sqrt(var) x step)" if table4_reading == "relative"
                               else "m^2") + "; the other reading shown",
         "L478: mean SLM error 18.43 % = sqrt(0.054) sqrt(2/pi)"),
        ("start", f"{_T}, L735, L792-795", "initial position from Wi-Fi or set by hand",
         "a Wi-Fi fix from a scan at the start, P0 = that point's R; PTS also from the true start", ""),
        ("SAM ranges", f"{_T}, L399", "5 % and 95 % points of the training features' CDFs",
         f"{q_range[0]:.0%}-{q_range[1]:.0%} quantiles of fixed-length training walks", ""),
        ("test walkers", f"{_T}, L515", "users walking the route", "new simulated walkers, not the training walkers",
         "gait model: data/gait"),
        ("F, B, H", f"{_T}, eq. 22-23", "F = I, B = [cos, sin]^T, H = I", "as the text", ""),
        ("update", f"{_T}, eq. 24-26", "Kalman gain, Joseph-form covariance", "as the text", ""),
    ]
    return readings_table([reading(*r) for r in rows])


def run(seed: int = 0, fast: bool = False, n_walkers: int = 8, n_train: int = 8, n_cal: int = 20,
        method: str = "Simplified-Horus", q_range=(0.05, 0.95), scan_latency_s: float = 2.0,
        table4_reading: str = "relative", gate_prob: float = 0.99, sigma_theta_rad: float = 0.2,
        lag: int = 5, wifi_methods=("Simplified-RADAR", "Simplified-Horus", "KNN (Manhattan, K=5)"),
        latencies_s=(0.0, 1.0, 2.0, 3.0)) -> dict[str, pd.DataFrame]:
    """Wi-Fi only, PTS only and the KF variants at the 28 test points (Figs 22-23) for ``n_walkers`` new walkers.

    Returns
    -------
    dict of DataFrame
        ``test_points`` (walker, method, point, true/estimated position, error), ``summary``, ``cdf``,
        ``track_example`` (walker 0: every track, the truth and the fixes), ``r_table`` (calibrated
        per-point fix variance beside the thesis's Table 5), ``gating``, ``comparison``,
        ``by_wifi_method`` (the main variants with each estimator of ``wifi_methods``), ``latency_sweep``
        (Wi-Fi only and the main KF with each scan latency of ``latencies_s``, same walks, new scans),
        ``readings``.
    """
    rng = as_rng(seed)
    if fast:
        n_walkers, n_train, n_cal = min(n_walkers, 2), min(n_train, 3), min(n_cal, 5)
    sim = iloc_floor.simulate(rng, scans_per_point=60 if fast else iloc_floor.SCANS_PER_POINT,
                              scans_per_test_point=n_cal)
    est = iloc_floor.fit_estimator(sim, method)
    cal_var = iloc_floor.standing_fix_variance_m2(sim, est)
    _, _, ranges, models = _train_pts(rng, n_train, q_range)
    walkers = gait.make_walkers(n_walkers, rng)  # new walkers: not those SAM and SLM were trained on
    route = iloc_floor.route_xy_m()
    paper_r = np.asarray(PAPER_TABLE5_SIGMA_RF_VAR_M2, dtype=np.float64)
    tps, gat, ex, walks = [], [], [], []
    for w_i, w in enumerate(walkers):
        sw = gait.simulate_walk(route, w, rng)
        pdr = route_walk(sw, ranges, models["SLM quadratic"])
        t_pass = gait.pass_times_s(sw, route)
        truth_t = sw.truth.index.to_numpy()
        truth_xy = sw.truth[["x_m", "y_m"]].to_numpy()
        drift = iloc_floor.session_drift_db(sim, rng)  # this walk's session
        walks.append((truth_t, truth_xy, t_pass, pdr, drift))
        fixes = iloc_floor.walking_fixes(sim, est, truth_t, truth_xy, np.r_[truth_t[0], t_pass], scan_latency_s,
                                         rng, drift)
        start_fix = fixes[["fix_x_m", "fix_y_m"]].to_numpy()[0]
        fix = fixes[["fix_x_m", "fix_y_m"]].to_numpy()[1:]
        x0 = start_fix if np.isfinite(start_fix).all() else route[0]
        r_var = {"R calibrated": cal_var, "R = thesis Table 5": paper_r,
                 "R constant": np.full(route.shape[0], cal_var.mean())}
        tracks, info = run_filters(x0, pdr, t_pass, fix, r_var, P0_var_m2=float(cal_var[0]), gate_prob=gate_prob,
                                   sigma_theta_rad=sigma_theta_rad, lag=lag, table4_reading=table4_reading)
        tracks = {"PTS (Wi-Fi start)" if k == "PTS" else k: v for k, v in tracks.items()}
        tracks["PTS (true start)"] = dead_reckon(pdr["step_m"], pdr["theta_rad"], *route[0])[["x_m", "y_m"]].to_numpy()
        tps.append(score_points(tracks, info["state_index"], route, fix).assign(walker=w.name))
        gat.append({"walker": w.name, "fixes": info["n_fixes"], "gated_out": info["n_gated"],
                    "superseded": info["n_superseded"], "steps_detected": int(pdr["step_m"].size),
                    "steps_true": int(len(sw.steps)), "start_fix_error_m": float(np.hypot(*(x0 - route[0]))),
                    "median_aps_heard": float(fixes["n_heard"].median())})
        if w_i == 0:
            ex.append(pd.DataFrame({"method": "truth", "x_m": np.r_[route[0, 0], sw.steps["x_m"]],
                                    "y_m": np.r_[route[0, 1], sw.steps["y_m"]]}))
            ex.append(pd.DataFrame({"method": "Wi-Fi only", "x_m": fix[:, 0], "y_m": fix[:, 1]}))
            ex += [pd.DataFrame({"method": k, "x_m": v[:, 0], "y_m": v[:, 1]}) for k, v in tracks.items()]
    tp = pd.concat(tps, ignore_index=True)
    tp = tp[["walker"] + [c for c in tp.columns if c != "walker"]]
    summ, cdf = summarise_by_method(tp)
    m = summ.set_index("method")["mean_error_m"]
    note = f"{len(walkers)} new simulated walkers on the floor's 28-point route; Wi-Fi: {method}"
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
    by_method = []
    if wifi_methods:
        for meth in wifi_methods:  # the main KF variant with each Wi-Fi estimator
            by_method.append(_method_row(seed, meth, fast, n_walkers, n_train, n_cal, q_range, scan_latency_s,
                                         table4_reading, sigma_theta_rad))
    # scan latency (an assumption): the same walks and sessions, new scans at each latency (drawn after
    # everything above, so the main tables do not depend on the sweep)
    lat_rows = []
    for lat in latencies_s:
        errs_w, errs_k, errs_h = [], [], []
        for truth_t, truth_xy, t_pass, pdr, drift in walks:
            fx = iloc_floor.walking_fixes(sim, est, truth_t, truth_xy, np.r_[truth_t[0], t_pass], lat, rng, drift)
            xy = fx[["fix_x_m", "fix_y_m"]].to_numpy()
            x0 = xy[0] if np.isfinite(xy[0]).all() else route[0]
            tr, inf = run_filters(x0, pdr, t_pass, xy[1:], {"R calibrated": cal_var}, P0_var_m2=float(cal_var[0]),
                                  gate_prob=gate_prob, sigma_theta_rad=sigma_theta_rad, lag=lag,
                                  table4_reading=table4_reading)
            e = score_points(tr, inf["state_index"], route, xy[1:]).set_index("method")["error_m"]
            errs_w.append(e.loc["Wi-Fi only"].to_numpy())
            errs_k.append(e.loc[MAIN].to_numpy())
            errs_h.append(e.loc[f"{MAIN} + heading noise + RTS"].to_numpy())
        lat_rows.append({"scan_latency_s": float(lat), "wifi_only_mean_m": float(np.nanmean(np.concatenate(errs_w))),
                         "kf_mean_m": float(np.nanmean(np.concatenate(errs_k))),
                         "kf_heading_noise_rts_mean_m": float(np.nanmean(np.concatenate(errs_h)))})
    r_table = pd.DataFrame({"point": np.arange(1, route.shape[0] + 1), "x_m": route[:, 0], "y_m": route[:, 1],
                            "calibrated_var_m2": cal_var, "thesis_table5_var_m2_paper": paper_r})
    return {"test_points": tp, "summary": summ, "cdf": cdf, "track_example": pd.concat(ex, ignore_index=True),
            "r_table": r_table, "gating": pd.DataFrame(gat), "comparison": comparison_table(comp),
            "by_wifi_method": pd.DataFrame(by_method), "latency_sweep": pd.DataFrame(lat_rows),
            "readings": readings(scan_latency_s, q_range, table4_reading)}


def _method_row(seed, method, fast, n_walkers, n_train, n_cal, q_range, scan_latency_s, table4_reading,
                sigma_theta_rad) -> dict:
    t = run(seed=seed, fast=fast, n_walkers=n_walkers, n_train=n_train, n_cal=n_cal, method=method,
            q_range=q_range, scan_latency_s=scan_latency_s, table4_reading=table4_reading,
            sigma_theta_rad=sigma_theta_rad, wifi_methods=(), latencies_s=())
    m = t["summary"].set_index("method")["mean_error_m"]
    return {"wifi_method": method, "wifi_only_mean_m": m["Wi-Fi only"], "pts_mean_m": m["PTS (Wi-Fi start)"],
            "kf_mean_m": m[MAIN], "kf_table5_mean_m": m["KF (R = thesis Table 5)"],
            "kf_constant_r_mean_m": m["KF (R constant)"], "kf_rts_mean_m": m[f"{MAIN} + RTS"],
            "kf_heading_noise_rts_mean_m": m[f"{MAIN} + heading noise + RTS"]}


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    m = tables["summary"].set_index("method")["mean_error_m"].rename({"PTS (Wi-Fi start)": "PTS"})
    kf = m[MAIN]
    best = m.drop(["Wi-Fi only", "PTS", "PTS (true start)"]).idxmin()
    g = tables["gating"]
    r = tables["r_table"]
    return "\n".join([
        f"Mean error at the test points: PTS {m['PTS']:.2f} m, Wi-Fi only {m['Wi-Fi only']:.2f} m, "
        f"KF {kf:.2f} m (thesis, paper values: PTS {PAPER_KF['pts_mean_m']} m, KF {PAPER_KF['kf_mean_m']} m).",
        f"The KF is {'better' if kf < min(m['PTS'], m['Wi-Fi only']) else 'not better'} than both inputs; "
        f"KF / PTS = {kf / m['PTS']:.2f} (thesis {PAPER_KF['kf_mean_m'] / PAPER_KF['pts_mean_m']:.2f}, paper).",
        f"With the thesis's Table 5 as R: {m['KF (R = thesis Table 5)']:.2f} m; "
        f"with one constant R (no knowledge of where a fix was taken): {m['KF (R constant)']:.2f} m, "
        f"{'better' if m['KF (R constant)'] < m['Wi-Fi only'] else 'not better'} than Wi-Fi alone.",
        f"Best variant: {best} ({m[best]:.2f} m). Gating rejected {int(g['gated_out'].sum())} of "
        f"{int(g['fixes'].sum())} fixes.",
        f"Fix variance per point: calibrated median {r['calibrated_var_m2'].median():.2f} m^2, thesis Table 5 median "
        f"{r['thesis_table5_var_m2_paper'].median():.2f} m^2 (paper values); the thesis' is larger at "
        f"{int((r['thesis_table5_var_m2_paper'] > r['calibrated_var_m2']).sum())} of {len(r)} points.",
    ])
