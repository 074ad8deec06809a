"""WDM heading and the pedestrian trajectory system on simulated walks (i-Loc thesis sec. 4.3-4.4, Figs 16-18).

Walkers carry the phone around the thesis's closed loop of 28 test points 4.11 m apart (sec. 4.4). Steps are
found by SAM (ranges learned from fixed-length training walks, experiment ``pdr_step_features``),
their lengths by the quadratic SLM fitted on the same training steps, their headings by WDM from
gravity (1 s mean of the accelerometer) and the magnetic field (0.5 s mean) at each step; the
track is dead-reckoned from the true start. Scored: the per-step heading error (Fig 16, thesis
13.87 deg mean) and the position error when the walker passes each test point (Figs 17-18, thesis
5.2 m mean). Beside the thesis's pipeline: gyro-integrated heading (uncalibrated bias), and true steps with WDM
headings (isolating the heading error).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.3-4.4, eq. (18)-(19), (22), Figs 16-18.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.metrics import error_cdf
from ilocalg.papers import paper_ref
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.pts import pts_steps
from ilocalg.pdr.sam import learn_feature_ranges
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import fit_step_length_models
from ilocalg.sim import gait
from ilocalg.units import as_rng, wrap_angle_rad

__all__ = ["run", "track_errors", "PAPER"]

PAPER = "i-Loc thesis"

# Settings from the paper
# -----------------------
# Chiu (2013): HEADING_ERROR_PAPER_DEG, Fig 16 text (WDM mean heading error); PTS_ERROR_PAPER_M,
# Fig 18 text (PTS mean position error): reference values only. The test loop of run() (28
# points 4.11 m apart) is sec. 4.4.
HEADING_ERROR_PAPER_DEG = 13.87
PTS_ERROR_PAPER_M = 5.2


def track_errors(track: pd.DataFrame, step_t_s: np.ndarray, test_xy_m: np.ndarray, test_t_s: np.ndarray):
    """Position error (m) at each test point: the track after the last step before the passing time."""
    k = np.searchsorted(step_t_s, test_t_s, side="right")      # steps taken so far
    est = track[["x_m", "y_m"]].to_numpy()[k]
    return np.hypot(*(est - test_xy_m).T), est


def run(seed: int = 0, fast: bool = False, n_train: int = 8, n_walkers: int = 8, q_range=(0.01, 0.99),
        n_points: int = 28, spacing_m: float = 4.11) -> dict[str, pd.DataFrame]:
    """Heading errors beside Fig 16 and test-point position errors beside Figs 17-18.

    Returns
    -------
    dict of DataFrame
        ``heading_steps`` (per detected step), ``heading_summary``, ``test_points`` (per walker,
        method and test point: true and estimated position, error), ``summary``, ``cdf``,
        ``track_example`` (walker 0's tracks), ``comparison``.
    """
    rng = as_rng(seed)
    if fast:
        n_train, n_walkers = min(n_train, 4), min(n_walkers, 2)
    train_walkers = gait.make_walkers(n_train, rng)
    feats = gait.fixed_length_features(gait.training_walks(train_walkers, rng))
    ranges = learn_feature_ranges(feats, *q_range)
    models, _ = fit_step_length_models(feats)
    p_quad = models["SLM quadratic"]
    route = gait.loop_route(n_points, spacing_m)
    walkers = gait.make_walkers(n_walkers, rng) if n_walkers > n_train else train_walkers[:n_walkers]
    test_xy = route[1:]                                    # the points passed after the start
    s_test = spacing_m * np.arange(1, n_points + 1)

    hrows, prow, examples = [], [], []
    for w in walkers:
        sw = gait.simulate_walk(route, w, rng)
        acc, t = acc_from_log(sw.imu)
        heads = log_headings_rad(sw.imu, sw.config.stand_s)
        steps = pts_steps(sw.imu, ranges, p_quad, headings=heads)
        i = steps["i_peak"].to_numpy()
        true_st = sw.steps
        j = np.abs(true_st["t_mid_s"].to_numpy()[None, :] - steps["t_s"].to_numpy()[:, None]).argmin(axis=1)
        true_th = true_st["theta_rad"].to_numpy()[j]
        for name, h in heads.items():
            err = np.rad2deg(np.abs(wrap_angle_rad(h[i] - true_th)))
            hrows.append(pd.DataFrame({"walker": w.name, "heading": name, "step": np.arange(i.size),
                                       "true_deg": np.rad2deg(true_th), "est_deg": np.rad2deg(h[i]), "error_deg": err}))
        lengths = steps["length_m"].to_numpy()
        test_t = gait.times_at_arc_s(sw, s_test)
        x0, y0 = route[0]
        # true steps (heel strikes) with true lengths and WDM headings: the heading error alone
        i_true = np.clip(np.searchsorted(t, true_st["t_mid_s"].to_numpy()), 0, t.size - 1)
        variants = {
            "PTS: SAM + SLM + WDM": (steps["t_s"].to_numpy(), lengths, steps["theta_rad"].to_numpy()),
            "SAM + SLM + gyro heading": (steps["t_s"].to_numpy(), lengths, steps["theta_gyr_rad"].to_numpy()),
            "true steps and lengths + WDM": (true_st["t_mid_s"].to_numpy(), true_st["length_m"].to_numpy(),
                                             heads["WDM"][i_true]),
        }
        for name, (ts, d, th) in variants.items():
            tr = dead_reckon(d, th, x0, y0)
            err, est = track_errors(tr, ts, test_xy, test_t)
            prow.append(pd.DataFrame({"walker": w.name, "method": name, "point": np.arange(1, n_points + 1),
                                      "x_true_m": test_xy[:, 0], "y_true_m": test_xy[:, 1], "x_est_m": est[:, 0],
                                      "y_est_m": est[:, 1], "error_m": err}))
            if w is walkers[0]:
                examples.append(tr.assign(method=name).reset_index())
        if w is walkers[0]:
            examples.append(pd.DataFrame({"step": np.arange(len(true_st) + 1), "x_m": np.r_[x0, true_st["x_m"]],
                                          "y_m": np.r_[y0, true_st["y_m"]], "method": "truth"}))
    hs = pd.concat(hrows, ignore_index=True)
    hsum = hs.groupby("heading").agg(mean_error_deg=("error_deg", "mean"), median_error_deg=("error_deg", "median"),
                                     p90_error_deg=("error_deg", lambda e: float(np.quantile(e, 0.9)))).reset_index()
    tp = pd.concat(prow, ignore_index=True)
    summ = tp.groupby("method", sort=False)["error_m"].agg(["mean", "median", "max"]).reset_index()
    summ.columns = ["method", "mean_error_m", "median_error_m", "max_error_m"]
    cdf = pd.concat([error_cdf(g["error_m"].to_numpy()).assign(method=m) for m, g in tp.groupby("method", sort=False)],
                    ignore_index=True)
    comp = [
        paper_ref(PAPER, "Fig 16", "WDM mean per-step heading error",
                  HEADING_ERROR_PAPER_DEG, hsum.set_index("heading").loc["WDM", "mean_error_deg"], unit="deg"),
        paper_ref(PAPER, "Figs 17-18", "PTS mean position error at the 28 test points",
                  PTS_ERROR_PAPER_M, summ.set_index("method").loc["PTS: SAM + SLM + WDM", "mean_error_m"], unit="m"),
    ]
    return {"heading_steps": hs, "heading_summary": hsum, "test_points": tp, "summary": summ, "cdf": cdf,
            "track_example": pd.concat(examples, ignore_index=True), "comparison": pd.DataFrame(comp)}
