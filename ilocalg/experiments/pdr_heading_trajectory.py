"""WDM heading and the pedestrian trajectory system on simulated walks (i-Loc thesis sec. 4.3-4.4, Figs 16-18).

New walkers (not the training walkers) carry the phone along the floor's test route: 28 training
points about 4 m apart (thesis L515: 4.11 m; :func:`ilocalg.sim.iloc_floor.route_xy_m`, the route of
notebooks 01 and 07). Steps are found by SAM (ranges = the 5-95 % quantiles of fixed-length training
walks' features, L399; 1-99 % shown beside), their lengths by the quadratic SLM fitted on the same
training steps, their headings by WDM from gravity (1 s mean of the accelerometer) and the magnetic
field (0.5 s mean) at each step, with neither a declination nor a hard-iron correction (eq. 18-19);
the track is dead-reckoned from the true start. The phone is held a few degrees off the walking
direction, its magnetometer keeps a hard-iron residual and the site has a declination
(:mod:`ilocalg.sim.gait`); ``wdm_sensitivity`` switches each off in turn. Scored: the per-step
heading error (Fig 16, thesis 13.87 deg mean) and the position error when the walker passes each of
the 27 test points after the start (Figs 17-18, thesis 5.2 m mean). Beside the thesis's pipeline:
gyro-integrated heading (uncalibrated bias), and true steps with WDM headings (the heading error alone).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.3-4.4, eq. (18)-(19), (22), Figs 16-18.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from ilocalg.metrics import error_cdf
from ilocalg.papers import PAPERS, paper_ref, readings_iloc
from ilocalg.papers.iloc import PUBLISHED
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.pts import pts_steps
from ilocalg.pdr.sam import learn_feature_ranges
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import fit_step_length_models
from ilocalg.sim import gait, iloc_floor
from ilocalg.units import as_rng, wrap_angle_rad, yaw_to_theta

__all__ = ["run", "track_errors", "readings", "PAPER"]

PAPER = PAPERS["iloc"]

#: The thesis's published values (:data:`ilocalg.papers.iloc.PUBLISHED`): reference only, never used to compute.
PUB = PUBLISHED["pdr_heading_trajectory"]


def track_errors(track: pd.DataFrame, step_t_s: np.ndarray, test_xy_m: np.ndarray, test_t_s: np.ndarray):
    """Position error (m) at each test point: the track after the last step before the passing time."""
    k = np.searchsorted(step_t_s, test_t_s, side="right")      # steps taken so far
    est = track[["x_m", "y_m"]].to_numpy()[k]
    return np.hypot(*(est - test_xy_m).T), est


def readings(q_range=(0.05, 0.95), world: str = "measured") -> pd.DataFrame:
    """The modelling choices of this experiment against the thesis's text (:mod:`ilocalg.papers.readings_iloc`)."""
    from ilocalg.sim.measured import cite

    code, source = gait.world_reading(world)
    assumed = world == "assumed"
    return readings_iloc.readings(
        "pdr_heading_trajectory", q_range=q_range, gait_code=code, gait_source=source,
        misalign_sd_deg=gait.MISALIGN_SD_DEG if assumed else gait._measured("misalign_sd_deg"),
        misalign_source="assumption" if assumed else cite(gait.MEASURED_ROWS["misalign_sd_deg"]))


def _mean_heading_error_deg(walkers, rng, route, config=None, declination_rad: float = 0.0) -> float:
    """Mean per-true-step WDM heading error over one walk per walker (for the sensitivity table)."""
    errs = []
    offset = float(yaw_to_theta(declination_rad) - yaw_to_theta(0.0))  # a declination correction, map convention
    for w in walkers:
        sw = gait.simulate_walk(route, w, rng, config)
        _, t = acc_from_log(sw.imu)
        h = log_headings_rad(sw.imu, sw.config.stand_s)["WDM"] + offset
        i = np.clip(np.searchsorted(t, sw.steps["t_mid_s"].to_numpy()), 0, t.size - 1)
        errs.append(np.rad2deg(np.abs(wrap_angle_rad(h[i] - sw.steps["theta_rad"].to_numpy()))))
    return float(np.concatenate(errs).mean())


def run(seed: int = 0, fast: bool = False, n_train: int = 8, n_walkers: int = 8, q_range=(0.05, 0.95),
        q_range_alt=(0.01, 0.99), world: str = "measured") -> dict[str, pd.DataFrame]:
    """Heading errors beside Fig 16 and test-point position errors beside Figs 17-18.

    Returns
    -------
    dict of DataFrame
        ``heading_steps`` (per detected step), ``heading_summary``, ``test_points`` (per walker,
        method and test point: true and estimated position, error), ``summary``, ``cdf``,
        ``track_example`` (walker 0's tracks), ``comparison``, ``wdm_sensitivity`` (mean WDM error with
        misalignment, hard-iron residual and declination each switched off), ``readings``.
    """
    rng = as_rng(seed)
    gcfg = gait.gait_config(world)
    if fast:
        n_train, n_walkers = min(n_train, 4), min(n_walkers, 2)
    train_walkers = gait.make_walkers(n_train, rng, world=world)
    feats = gait.fixed_length_features(gait.training_walks(train_walkers, rng, config=gcfg))
    ranges = learn_feature_ranges(feats, *q_range)
    ranges_alt = learn_feature_ranges(feats, *q_range_alt)
    models, _ = fit_step_length_models(feats)
    p_quad = models["SLM quadratic"]
    route = iloc_floor.route_xy_m()
    walkers = gait.make_walkers(n_walkers, rng, world=world)  # new walkers: not those SAM and SLM were trained on
    test_xy = route[1:]                                    # the points passed after the start
    n_points = test_xy.shape[0]
    s_test = np.cumsum(np.hypot(*np.diff(route, axis=0).T))

    hrows, prow, examples = [], [], []
    for w in walkers:
        sw = gait.simulate_walk(route, w, rng, gcfg)
        acc, t = acc_from_log(sw.imu)
        heads = log_headings_rad(sw.imu, sw.config.stand_s)
        steps = pts_steps(sw.imu, ranges, p_quad, headings=heads)
        i = steps["i_peak"].to_numpy()
        steps_alt = pts_steps(sw.imu, ranges_alt, p_quad, headings=heads)
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
            f"PTS (SAM {q_range_alt[0]:.0%}-{q_range_alt[1]:.0%})": (
                steps_alt["t_s"].to_numpy(), steps_alt["length_m"].to_numpy(), steps_alt["theta_rad"].to_numpy()),
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
                  PUB["heading_error_deg"], hsum.set_index("heading").loc["WDM", "mean_error_deg"], unit="deg"),
        paper_ref(PAPER, "Figs 17-18", "PTS mean position error at the test points (27 after the start)",
                  PUB["pts_error_m"], summ.set_index("method").loc["PTS: SAM + SLM + WDM", "mean_error_m"], unit="m"),
    ]
    # WDM sensitivity: the same new-walker population with one heading error source switched off at a time
    dec = np.deg2rad(gcfg.declination_deg)
    straight = [dataclasses.replace(w, misalign_rad=0.0) for w in walkers]
    calibrated = [dataclasses.replace(w, hard_iron_ut=(0.0, 0.0, 0.0)) for w in walkers]
    ideal = [dataclasses.replace(w, misalign_rad=0.0, hard_iron_ut=(0.0, 0.0, 0.0)) for w in walkers]
    cases = [("as simulated (thesis's WDM)", walkers, 0.0), ("phone held straight (no misalignment)", straight, 0.0),
             ("no hard-iron residual", calibrated, 0.0), ("declination corrected", walkers, dec),
             ("none of the three", ideal, dec)]
    sub = int(rng.integers(2**31))  # every case walks the same walks (same noise, disturbances): one change each
    sens = pd.DataFrame([{"case": c, "wdm_mean_error_deg": _mean_heading_error_deg(ws, np.random.default_rng(sub),
                                                                                   route, gcfg, d)}
                         for c, ws, d in cases])
    return {"heading_steps": hs, "heading_summary": hsum, "test_points": tp, "summary": summ, "cdf": cdf,
            "track_example": pd.concat(examples, ignore_index=True), "comparison": pd.DataFrame(comp),
            "wdm_sensitivity": sens, "readings": readings(q_range, world)}
