"""The i-Loc Kalman filter (PTS + Wi-Fi) on the simulated i-Loc floor (i-Loc thesis ch. 5, Figs 22-23).

Data: the simulated i-Loc floor (:mod:`ilocalg.sim.iloc_floor`: radio map, new scans at the 28
test-route points) and simulated walkers (:mod:`ilocalg.sim.gait`) walking that same test route
with a handheld phone. Nothing new is simulated here; the two simulators are put together:

* Wi-Fi: the estimator (Simplified-Horus by default, thesis ch. 3) is fitted on the training
  survey; each test-route point has new scans; walker ``w`` gets scan ``n_cal + w`` of each point
  when it passes it (its Wi-Fi fix there). The first ``n_cal`` scans of every point are a
  calibration survey: the per-point variance of the fix error there is the analogue of the thesis'
  Table 5 (how the thesis made its R).
* PTS: SAM steps (ranges learned on training walks), quadratic SLM lengths, WDM headings, exactly
  the pipeline of :mod:`ilocalg.experiments.pdr_heading_trajectory`, dead-reckoned from the true start.
* KF (eq. 20-26): one predict per detected step (``Q`` from Table 4), one update per Wi-Fi fix (on
  the latest state at or before the time the walker passes the point), started at the true start
  (the thesis sets the start by hand or by Wi-Fi).

Scored: the position error at each of the 28 test points (error of the state at the passing time).
Variants: R per point from the calibration survey (the thesis' model), one constant R (no
knowledge of where the fix was taken), R = the thesis' own Table 5, innovation gating, and, beyond
the paper, a heading-error term in Q, fixed-lag and RTS smoothing.

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
from ilocalg.papers import comparison_table, paper_ref
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.pts import pts_steps
from ilocalg.pdr.sam import learn_feature_ranges
from ilocalg.pdr.step_length import fit_step_length_models
from ilocalg.sim import gait, iloc_floor
from ilocalg.units import as_rng

__all__ = ["run", "route_walk", "run_filters", "score_points", "PAPER_KF"]

PAPER = "i-Loc thesis"
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
                sigma_theta_rad: float = 0.2, lag: int = 5) -> tuple[dict, dict]:
    """Every PDR / KF variant on one walk.

    Parameters
    ----------
    x0_m : (2,) start position.
    pdr : dict from :func:`route_walk` (or any dict with ``state_t_s``, ``step_m``, ``theta_rad``).
    fix_t_s, fix_xy_m : (m,), (m, 2) Wi-Fi fixes (time order).
    r_var : dict label -> (m,) isotropic fix variances (one KF variant per entry).

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
    al = fixes_at_states(ts, fix_t_s, fix_xy_m, before_start="drop", same_state="last")
    sig = sigma_sl_paper_m(d)
    P0 = P0_var_m2 * np.eye(2)
    info = {"state_index": al.state_index, "n_superseded": al.n_superseded, "n_before_start": al.n_before_start}
    for label, rv in r_var.items():
        r = np.full(n1, np.nan)
        r[al.state_index[al.used]] = np.asarray(rv, dtype=np.float64)[al.used]
        res = filter_walk(x0_m, P0, th, d, sig, al.z_m, r_var_m2=np.where(np.isnan(r), 1.0, r))
        tracks[f"KF ({label})"] = res.x
        if label == first:
            tracks[f"KF ({label}) + RTS"] = rts_smooth(res).x
            tracks[f"KF ({label}) + fixed-lag {lag}"] = fixed_lag_smooth(res, lag).x
            h = filter_walk(x0_m, P0, th, d, sig, al.z_m, r_var_m2=np.where(np.isnan(r), 1.0, r),
                            sigma_theta_rad=sigma_theta_rad)
            tracks[f"KF ({label}) + heading noise"] = h.x
            tracks[f"KF ({label}) + heading noise + RTS"] = rts_smooth(h).x
            # gating needs a P that admits the heading error, else good fixes are rejected as the PTS drifts
            g = filter_walk(x0_m, P0, th, d, sig, al.z_m, r_var_m2=np.where(np.isnan(r), 1.0, r),
                            gate_nis=nis_gate(gate_prob), sigma_theta_rad=sigma_theta_rad)
            tracks[f"KF ({label}) + heading noise + gating"] = g.x
            info["n_gated"] = int(g.n_rejected)
            info["n_fixes"] = int(al.used.sum())
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


def _train_pts(rng, n_train, q_range=(0.01, 0.99)):
    walkers = gait.make_walkers(n_train, rng)
    feats = gait.fixed_length_features(gait.training_walks(walkers, rng))
    models, _ = fit_step_length_models(feats)
    return walkers, feats, learn_feature_ranges(feats, *q_range), models


def run(seed: int = 0, fast: bool = False, n_walkers: int = 8, n_train: int = 8, n_cal: int = 10,
        method: str = "Simplified-Horus", gate_prob: float = 0.99, sigma_theta_rad: float = 0.2,
        lag: int = 5, wifi_methods=("Simplified-RADAR", "Simplified-Horus", "KNN (Manhattan, K=5)")
        ) -> dict[str, pd.DataFrame]:
    """PTS, Wi-Fi and the KF variants at the 28 test points (Figs 22-23) for ``n_walkers`` walkers.

    Returns
    -------
    dict of DataFrame
        ``test_points`` (walker, method, point, true/estimated position, error), ``summary``,
        ``cdf``, ``track_example`` (walker 0: every track, the truth and the fixes),
        ``r_table`` (calibrated per-point fix variance beside the thesis' Table 5), ``gating``,
        ``comparison`` (the thesis' means beside the reproduced ones), ``by_wifi_method`` (the
        main variants rerun with each estimator of ``wifi_methods``: same seed, so same walks).
    """
    rng = as_rng(seed)
    if fast:
        n_walkers, n_train, n_cal = min(n_walkers, 2), min(n_train, 3), min(n_cal, 5)
    ff = iloc_floor.floor_fixes(rng, n_walkers, n_cal, method,
                                scans_per_point=60 if fast else iloc_floor.SCANS_PER_POINT)
    train_walkers, _, ranges, models = _train_pts(rng, n_train)
    walkers = train_walkers[:n_walkers] if n_walkers <= n_train else gait.make_walkers(n_walkers, rng)
    route = ff.route_xy_m
    paper_r = np.asarray(PAPER_TABLE5_SIGMA_RF_VAR_M2, dtype=np.float64)
    tps, gat, ex = [], [], []
    for w_i, w in enumerate(walkers):
        sw = gait.simulate_walk(route, w, rng)
        pdr = route_walk(sw, ranges, models["SLM quadratic"])
        t_pass = gait.pass_times_s(sw, route)
        fix = ff.fix_xy_m[:, ff.n_cal + w_i]
        r_var = {"R per point, calibrated": ff.cal_var_m2,
                 "R constant": np.full(route.shape[0], ff.cal_var_m2.mean()),
                 "R = thesis Table 5": paper_r}
        tracks, info = run_filters(route[0], pdr, t_pass, fix, r_var, gate_prob=gate_prob,
                                   sigma_theta_rad=sigma_theta_rad, lag=lag)
        tps.append(score_points(tracks, info["state_index"], route, fix).assign(walker=w.name))
        gat.append({"walker": w.name, "fixes": info["n_fixes"], "gated_out": info["n_gated"],
                    "superseded": info["n_superseded"], "steps_detected": int(pdr["step_m"].size),
                    "steps_true": int(len(sw.steps))})
        if w_i == 0:
            ex.append(pd.DataFrame({"method": "truth", "x_m": np.r_[route[0, 0], sw.steps["x_m"]],
                                    "y_m": np.r_[route[0, 1], sw.steps["y_m"]]}))
            ex.append(pd.DataFrame({"method": "Wi-Fi only", "x_m": fix[:, 0], "y_m": fix[:, 1]}))
            ex += [pd.DataFrame({"method": k, "x_m": v[:, 0], "y_m": v[:, 1]}) for k, v in tracks.items()]
    tp = pd.concat(tps, ignore_index=True)
    tp = tp[["walker"] + [c for c in tp.columns if c != "walker"]]
    summ, cdf = summarise_by_method(tp)
    m = summ.set_index("method")["mean_error_m"]
    note = f"{len(walkers)} simulated walkers on the simulated floor's 28-point route; Wi-Fi: {method}"
    comp = [
        paper_ref(PAPER, "Fig 23", "PTS mean error at the test points", PAPER_KF["pts_mean_m"], m["PTS"], "m", note),
        paper_ref(PAPER, "Fig 23", "KF (PTS + Wi-Fi) mean error at the test points", PAPER_KF["kf_mean_m"],
                  m["KF (R per point, calibrated)"], "m", "R per point from a calibration survey (the thesis' Table 5 "
                  "procedure)"),
        paper_ref(PAPER, "Fig 23", "KF mean error, R = the thesis' Table 5", PAPER_KF["kf_mean_m"],
                  m["KF (R = thesis Table 5)"], "m", "the thesis' variances, measured on its floor"),
        paper_ref(PAPER, "Fig 23", "KF mean / PTS mean", PAPER_KF["kf_mean_m"] / PAPER_KF["pts_mean_m"],
                  m["KF (R per point, calibrated)"] / m["PTS"], "-", "the improvement ratio"),
    ]
    by_method = []
    if wifi_methods:
        for meth in wifi_methods:  # the main KF variant with each Wi-Fi estimator, same walkers and walks
            by_method.append(_method_row(seed, meth, fast, n_walkers, n_train, n_cal, sigma_theta_rad))
    r_table = pd.DataFrame({"point": np.arange(1, route.shape[0] + 1), "x_m": route[:, 0], "y_m": route[:, 1],
                            "calibrated_var_m2": ff.cal_var_m2, "thesis_table5_var_m2_paper": paper_r})
    return {"test_points": tp, "summary": summ, "cdf": cdf, "track_example": pd.concat(ex, ignore_index=True),
            "r_table": r_table, "gating": pd.DataFrame(gat), "comparison": comparison_table(comp),
            "by_wifi_method": pd.DataFrame(by_method)}


def _method_row(seed, method, fast, n_walkers, n_train, n_cal, sigma_theta_rad) -> dict:
    t = run(seed=seed, fast=fast, n_walkers=n_walkers, n_train=n_train, n_cal=n_cal, method=method,
            sigma_theta_rad=sigma_theta_rad, wifi_methods=())
    m = t["summary"].set_index("method")["mean_error_m"]
    return {"wifi_method": method, "wifi_only_mean_m": m["Wi-Fi only"], "pts_mean_m": m["PTS"],
            "kf_mean_m": m["KF (R per point, calibrated)"], "kf_rts_mean_m": m["KF (R per point, calibrated) + RTS"],
            "kf_heading_noise_rts_mean_m": m["KF (R per point, calibrated) + heading noise + RTS"]}


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    m = tables["summary"].set_index("method")["mean_error_m"]
    kf = m["KF (R per point, calibrated)"]
    best = m.drop(["Wi-Fi only", "PTS"]).idxmin()
    g = tables["gating"]
    r = tables["r_table"]
    return "\n".join([
        f"Mean error at the test points: PTS {m['PTS']:.2f} m, Wi-Fi only {m['Wi-Fi only']:.2f} m, "
        f"KF {kf:.2f} m (thesis, paper values: PTS {PAPER_KF['pts_mean_m']} m, KF {PAPER_KF['kf_mean_m']} m).",
        f"The KF is {'better' if kf < min(m['PTS'], m['Wi-Fi only']) else 'not better'} than both inputs; "
        f"KF / PTS = {kf / m['PTS']:.2f} (thesis {PAPER_KF['kf_mean_m'] / PAPER_KF['pts_mean_m']:.2f}, paper).",
        f"With one constant R (no knowledge of where a fix was taken) the KF gives {m['KF (R constant)']:.2f} m: "
        f"{'better' if m['KF (R constant)'] < m['Wi-Fi only'] else 'not better'} than Wi-Fi alone.",
        f"Best variant: {best} ({m[best]:.2f} m). Gating rejected {int(g['gated_out'].sum())} of "
        f"{int(g['fixes'].sum())} fixes.",
        f"Fix variance per point: calibrated median {r['calibrated_var_m2'].median():.2f} m^2, thesis Table 5 median "
        f"{r['thesis_table5_var_m2_paper'].median():.2f} m^2 (paper values); the thesis' is larger at "
        f"{int((r['thesis_table5_var_m2_paper'] > r['calibrated_var_m2']).sum())} of {len(r)} points.",
    ])
