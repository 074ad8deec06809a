"""Fingerprint + PDR positioning (Luo et al. 2017, sec. 3-4, Fig 6) on the simulated i-Loc floor.

The paper's library floor and its data are not published; the toolkit's simulated i-Loc floor
(:mod:`ilocalg.sim.iloc_floor`) and gait simulator (:mod:`ilocalg.sim.gait`) stand in, walkers
walking the floor's 28-point test route (as in :mod:`ilocalg.experiments.fusion_iloc_kf`).

* Wi-Fi only: KNN, Manhattan distance (a = 1), K = 5 (eq. 1-2) on the per-point mean
  fingerprints; walker ``w`` gets a new scan at every route point.
* PDR only: the paper's sliding-window peak detector on |a| (0.2-2 s time window, sec. 3.4.2),
  step length eq. (4) with ``k`` fitted on fixed-length training walks (total true length /
  total eq. (4) length), WDM heading (accelerometer + magnetometer, sec. 3.4.3); started at the
  true start, as in the paper ("PDR 的起点与实际起点一致").
* Combined: a Kalman filter (sec. 3.1) with the PDR steps as control input and the KNN fixes as
  observations (the i-Loc step filter, :mod:`ilocalg.fusion.step_kf`); it starts at the first
  Wi-Fi fix (sec. 3.4.4: the initial position comes from Wi-Fi) with that fix's variance. ``Q`` uses
  the step-length error spread of the training walks, ``R`` the KNN's error variance over a
  calibration survey. Beyond the paper: the same filter smoothed (RTS), and a ``Q`` with a heading
  error term (the WDM heading error, not the step length, is what makes PDR drift).

Scored: the error at each route point (Fig 6: error per point index).

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Sec. 3-4, eq. (1)-(6), Fig 6.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.fusion import filter_walk, fixes_at_states, rts_smooth
from ilocalg.metrics import summarise_by_method
from ilocalg.papers import comparison_table, paper_ref
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import fit_luo_k, luo_steps
from ilocalg.sim import gait, iloc_floor
from ilocalg.units import as_rng

__all__ = ["run", "crossover_point", "findings", "PAPER_LUO"]

PAPER = "罗思奇 et al. 2017"
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


def run(seed: int = 0, fast: bool = False, n_walkers: int = 8, n_train: int = 8, n_cal: int = 10,
        detector: dict | None = None, sigma_theta_rad: float = 0.2) -> dict[str, pd.DataFrame]:
    """PDR only, Wi-Fi only (KNN) and combined at the route points (Fig 6).

    ``sigma_theta_rad``: heading error sd of the beyond-the-paper variant whose ``Q`` also covers the
    heading (the paper's ``Q`` covers the step length only).

    Returns
    -------
    dict of DataFrame
        ``test_points``, ``summary``, ``cdf``, ``per_point`` (mean error per point and method, the
        Fig 6 curves), ``track_example``, ``calibration`` (k, sigma_SL, R), ``comparison``.
    """
    rng = as_rng(seed)
    if fast:
        n_walkers, n_train, n_cal = min(n_walkers, 2), min(n_train, 3), min(n_cal, 5)
    method = "KNN (Manhattan, K=5)"
    ff = iloc_floor.floor_fixes(rng, n_walkers, n_cal, method,
                                scans_per_point=60 if fast else iloc_floor.SCANS_PER_POINT)
    walkers = gait.make_walkers(max(n_train, n_walkers), rng)
    train = gait.training_walks(walkers[:n_train], rng)
    k, sig_sl = fit_luo_k([(*acc_from_log(sw.imu), sw.steps["length_m"]) for _, _, sw in train], detector)
    r_var = float(ff.cal_var_m2.mean())
    route = ff.route_xy_m
    n_pts = route.shape[0]
    tps, ex = [], []
    for w_i, w in enumerate(walkers[:n_walkers]):
        sw = gait.simulate_walk(route, w, rng)
        acc, t = acc_from_log(sw.imu)
        st = luo_steps(acc, t, k, detector)
        th = log_headings_rad(sw.imu, sw.config.stand_s)["WDM"][st["i_peak"].to_numpy()]
        d = st["length_m"].to_numpy()
        ts = np.concatenate([[t[0]], st["t_s"].to_numpy()])
        fix = ff.fix_xy_m[:, ff.n_cal + w_i]
        al = fixes_at_states(ts, gait.pass_times_s(sw, route), fix, before_start="drop", same_state="last")
        z = al.z_m.copy()
        x0 = fix[0]                      # the combined scheme starts from the first Wi-Fi fix (sec. 3.4.4)
        z[al.state_index[0]] = np.nan    # ... which is therefore not used a second time
        res = filter_walk(x0, r_var * np.eye(2), th, d, sig_sl, z, r_var_m2=r_var)
        hres = filter_walk(x0, r_var * np.eye(2), th, d, sig_sl, z, r_var_m2=r_var, sigma_theta_rad=sigma_theta_rad)
        tracks = {"PDR only": dead_reckon(d, th, *route[0])[["x_m", "y_m"]].to_numpy(),
                  "combined (KF)": res.x, "combined (KF) + RTS": rts_smooth(res).x,
                  "combined (KF) + heading noise": hres.x, "combined (KF) + heading noise + RTS": rts_smooth(hres).x}
        idx = np.where(al.state_index >= 0, al.state_index, 0)
        rows = [("Wi-Fi only (KNN)", fix)] + [(m, xy[idx]) for m, xy in tracks.items()]
        for m, est in rows:
            tps.append(pd.DataFrame({"walker": w.name, "method": m, "point": np.arange(1, n_pts + 1),
                                     "x_true_m": route[:, 0], "y_true_m": route[:, 1], "x_est_m": est[:, 0],
                                     "y_est_m": est[:, 1], "error_m": np.hypot(*(est - route).T)}))
        if w_i == 0:
            ex.append(pd.DataFrame({"method": "truth", "x_m": np.r_[route[0, 0], sw.steps["x_m"]],
                                    "y_m": np.r_[route[0, 1], sw.steps["y_m"]]}))
            ex.append(pd.DataFrame({"method": "Wi-Fi only (KNN)", "x_m": fix[:, 0], "y_m": fix[:, 1]}))
            ex += [pd.DataFrame({"method": m, "x_m": v[:, 0], "y_m": v[:, 1]}) for m, v in tracks.items()]
    tp = pd.concat(tps, ignore_index=True)
    summ, cdf = summarise_by_method(tp)
    pp = tp.groupby(["method", "point"], sort=False)["error_m"].mean().unstack("method").reset_index()
    m = summ.set_index("method")["mean_error_m"]
    cross = crossover_point(pp["PDR only"].to_numpy(), pp["combined (KF)"].to_numpy())
    wifi_pp = pp["Wi-Fi only (KNN)"]
    note = f"{n_walkers} simulated walkers, simulated i-Loc floor (not the paper's library)"
    comp = [
        paper_ref(PAPER, "Fig 6", "Wi-Fi only (KNN, Manhattan, K=5) mean error", PAPER_LUO["wifi_mean_m"],
                  m["Wi-Fi only (KNN)"], "m", note),
        paper_ref(PAPER, "Fig 6", "Wi-Fi only, smallest per-point error", PAPER_LUO["wifi_min_m"],
                  tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"].min(), "m", "over every walker and point"),
        paper_ref(PAPER, "Fig 6", "Wi-Fi only, largest per-point error", PAPER_LUO["wifi_max_m"],
                  tp.loc[tp["method"] == "Wi-Fi only (KNN)", "error_m"].max(), "m", "over every walker and point"),
        paper_ref(PAPER, "Fig 6", "combined (KF) mean error", PAPER_LUO["combined_mean_m"], m["combined (KF)"], "m",
                  note),
        paper_ref(PAPER, "Fig 6", "combined / Wi-Fi only mean error",
                  PAPER_LUO["combined_mean_m"] / PAPER_LUO["wifi_mean_m"],
                  m["combined (KF)"] / m["Wi-Fi only (KNN)"], "-", "the improvement ratio"),
        paper_ref(PAPER, "Fig 6", "last point where PDR only beats combined", PAPER_LUO["pdr_better_points"], cross,
                  "points", "mean over walkers per point"),
    ]
    calib = pd.DataFrame([{"quantity": "eq. (4) k (fitted on training walks)", "value": k},
                          {"quantity": "sigma_SL, step-length error sd [m]", "value": sig_sl},
                          {"quantity": "R, KNN fix variance per axis [m^2]", "value": r_var},
                          {"quantity": "Wi-Fi only per-point mean error, min over points [m]", "value": wifi_pp.min()},
                          {"quantity": "Wi-Fi only per-point mean error, max over points [m]", "value": wifi_pp.max()}])
    return {"test_points": tp, "summary": summ, "cdf": cdf, "per_point": pp,
            "track_example": pd.concat(ex, ignore_index=True), "calibration": calib,
            "comparison": comparison_table(comp)}


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    m = tables["summary"].set_index("method")["mean_error_m"]
    pp = tables["per_point"]
    cross = crossover_point(pp["PDR only"].to_numpy(), pp["combined (KF)"].to_numpy())
    w, c, p = m["Wi-Fi only (KNN)"], m["combined (KF)"], m["PDR only"]
    return "\n".join([
        f"Mean error: Wi-Fi only {w:.2f} m, PDR only {p:.2f} m, combined {c:.2f} m, combined + RTS "
        f"{m['combined (KF) + RTS']:.2f} m (paper values: Wi-Fi {PAPER_LUO['wifi_mean_m']} m, combined "
        f"{PAPER_LUO['combined_mean_m']} m).",
        f"Combined / Wi-Fi only = {c / w:.2f} (paper {PAPER_LUO['combined_mean_m'] / PAPER_LUO['wifi_mean_m']:.2f}); "
        f"PDR only beats the combined scheme up to point {cross} (paper: the first {PAPER_LUO['pdr_better_points']}).",
    ])
