"""The measurement functions of :mod:`ilocalg.measure` applied to the simulators' output.

Each statistic of data/measured_parameters.csv that a simulator reproduces is measured here on a
simulated world (same function, same bootstrap), so :func:`side_by_side` can set the real value
beside the simulated one. A world is *calibrated* for a statistic when the real value lies inside
the simulated 95 % interval.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.measure import gait as mgait
from ilocalg.measure import heading, radio
from ilocalg.measure.stats import N_BOOT, bootstrap_many

__all__ = ["radio_measures", "gait_measures", "scan_lag_model_s", "side_by_side", "COMPARED"]

#: parameter -> (simulated statistic key, unit); the rows compared side by side
COMPARED = {
    "shadow_sd_db": "dB", "path_loss_exponent": "1", "fade_sd_db": "dB", "drift_sd_db": "dB",
    "detect_m50_dbm": "dBm", "aps_per_scan_median": "1", "wifi_reading_age_median_s": "s",
    "gait_step_period_cv": "1", "gait_step_amp_cv": "1", "gait_stride_period_cv": "1",
    "gait_corr_A_SL": "1", "gait_corr_T_SL": "1", "gait_A_resid_rel": "1",
    "heading_mis_wdm_rms_deg": "deg", "mag_norm_sd_ut": "uT",
}


def _est(groups, fn, ci: bool = True, n_boot: int = N_BOOT):
    """``fn`` on the pooled groups with its bootstrap interval (``n_boot`` replicates), or the point value alone
    (``ci=False``, what the inverse calibration iterates on: same statistic, no resampling)."""
    return _est_many(groups, lambda x: (fn(x),), ci, n_boot)[0]


def _est_many(groups, fn, ci: bool = True, n_boot: int = N_BOOT) -> list[dict]:
    """:func:`_est` of a statistic with several outputs (``fn`` returns a sequence): one pass over the bootstrap
    draws, each output's interval the one :func:`_est` gives for it alone."""
    if not ci:
        g = groups if isinstance(groups, np.ndarray) and groups.dtype != object else [np.asarray(x) for x in groups
                                                                                        if len(x)]
        vs = fn(g if isinstance(g, np.ndarray) else np.concatenate(g))
        return [{"value": float(v), "ci_low": np.nan, "ci_high": np.nan, "n": len(g)} for v in vs]
    return [{"value": e.value, "ci_low": e.ci_low, "ci_high": e.ci_high, "n": e.n}
            for e in bootstrap_many(groups, fn, n_boot)]


def radio_measures(sim, ci: bool = True, only=None, n_boot: int = N_BOOT) -> tuple[dict, dict]:
    """Radio statistics of an :class:`ilocalg.sim.iloc_floor.IlocFloor` (survey = training, test session).

    Returns ``(stats, samples)``: per parameter a dict ``value, ci_low, ci_high, n``; ``samples`` holds
    raw distributions for plots (``shadow_residual_db``). ``ci=False`` gives the point values only (NaN
    intervals); ``only`` (names) skips the other statistics' work.
    """
    want = set(COMPARED) if only is None else set(only)
    tr, te = sim.train, sim.test
    point = tr.meta["point"].to_numpy()
    cell = point * 1000 + tr.meta["session"].to_numpy()
    pm, places = radio.place_means(tr.rssi_dbm, point)
    pxy = sim.points_xy_m[places]
    on_floor = np.flatnonzero(sim.ap_floor == 0)
    stats, res = {}, np.array([])
    if want & {"shadow_sd_db", "path_loss_exponent"}:
        pl = radio.path_loss_per_ap(pxy, pm[:, on_floor])
        stats["shadow_sd_db"] = _est(pl["sigma_db"].to_numpy(), np.median, ci, n_boot)
        stats["path_loss_exponent"] = _est(pl["n"].to_numpy(), np.median, ci, n_boot)
        res = np.concatenate(list(pl.attrs["residuals"].values())) if len(pl) else res
    if "fade_sd_db" in want:
        sd = radio.within_place_sd_db(tr.rssi_dbm, cell)
        stats["fade_sd_db"] = _est(sd, lambda x: float(np.sqrt(np.mean(x**2))), ci, n_boot)
    if "drift_sd_db" in want:
        dr = radio.drift_per_ap_db(pm, pxy, np.zeros(len(pxy)), te.rssi_dbm, te.xy_m, np.zeros(te.n_samples),
                                   radius_m=0.5)
        stats["drift_sd_db"] = _est(dr.to_numpy(), lambda x: float(np.std(x, ddof=1)), ci, n_boot)
    if "detect_m50_dbm" in want:
        mm, ff, kk = radio.detection_curve(tr.rssi_dbm, cell)
        grp = [np.column_stack([mm[kk == k], ff[kk == k]]) for k in np.unique(kk)]
        stats["detect_m50_dbm"] = _est(grp, lambda a: radio.fit_detection(a[:, 0], a[:, 1])["m50_dbm"], ci, n_boot)
    if "aps_per_scan_median" in want:
        stats["aps_per_scan_median"] = _est(radio.aps_per_scan(tr.rssi_dbm).astype(float), np.median, ci, n_boot)
    return stats, {"shadow_residual_db": res}


def scan_lag_model_s(latency_s: float, n: int = 4000, rng=0) -> np.ndarray:
    """Ages at the scan stamp in the simulator's walking-scan model: each AP read at a uniform time
    within the scan (:func:`ilocalg.sim.iloc_floor.walking_scans`), the scan stamped when it ends."""
    r = np.random.default_rng(rng)
    return latency_s * r.uniform(0.0, 1.0, n)


def gait_measures(walks, route_xy_m, ci: bool = True, only=None, n_boot: int = N_BOOT) -> tuple[dict, dict]:
    """Gait and heading statistics of simulated walks (:class:`ilocalg.sim.gait.SimWalk`) along a route.

    Step variability from the true steps (as the Oxford heel contacts), gait correlations over the
    route's vertex-to-vertex segments with detected steps (as the ILC waypoints), WDM misalignment per
    segment and the field magnitude's spread. Returns ``(stats, samples)``; ``ci`` and ``only`` as
    :func:`radio_measures` (without the gait correlations, the segments' step detection is skipped).
    """
    want = set(COMPARED) if only is None else set(only)
    corr_wanted = bool(want & {"gait_corr_A_SL", "gait_corr_T_SL", "gait_A_resid_rel"})
    from ilocalg.sim.gait import pass_times_s

    route = np.asarray(route_xy_m, dtype=np.float64)
    var, segs, mis, mags, steps_T, steps_A = [], [], [], [], [], []
    for sw in walks:
        acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
        t = sw.imu.index.to_numpy()
        s = mgait.step_series(acc, t, sw.steps["t_strike_s"].to_numpy())
        v = mgait.step_variability(s)
        var.append(v)
        steps_T.append(s["T_s"].to_numpy() / s["T_s"].median())
        steps_A.append(s["A_mps2"].to_numpy() / s["A_mps2"].median())
        tp = pass_times_s(sw, route)
        if corr_wanted:
            seg = mgait.segment_gait(acc, t, tp, route)
            segs.append(seg[["A_mps2", "SL_m", "T_s", "speed_mps"]].to_numpy())
        wp = pd.DataFrame({"t_s": tp, "x_m": route[:, 0], "y_m": route[:, 1]})
        h = heading.segment_headings(sw.imu, None, wp)
        mis.append(heading.misalignment(h["wdm_rad"], h["dir_rad"], np.zeros(len(h))))
        mags.append(np.linalg.norm(sw.imu[["mag_x_ut", "mag_y_ut", "mag_z_ut"]].to_numpy(), axis=1))
    V = pd.DataFrame(var)
    corr_keys = ("corr_A_SL", "corr_T_SL", "A_resid_rel")

    def corr(a):  # the three from one fit per resampled set of segments (columns as a DataFrame's: contiguous)
        c = mgait.gait_correlation_arrays(*np.ascontiguousarray(a.T))
        return tuple(c[key] for key in corr_keys)

    med = np.median(np.concatenate(mags))
    stats = {
        "gait_step_period_cv": _est(V["rcv_T"].to_numpy(), np.median, ci, n_boot),
        "gait_step_amp_cv": _est(V["rcv_A"].to_numpy(), np.median, ci, n_boot),
        "gait_stride_period_cv": _est(V["cv_stride"].to_numpy(), np.median, ci, n_boot),
        "heading_mis_wdm_rms_deg": _est(mis, lambda x: float(np.sqrt(np.mean(np.degrees(x) ** 2))), ci, n_boot),
        "mag_norm_sd_ut": _est([m - med for m in mags], lambda x: float(np.std(x)), ci, n_boot),
    }
    if corr_wanted:
        stats.update(zip(("gait_corr_A_SL", "gait_corr_T_SL", "gait_A_resid_rel"), _est_many(segs, corr, ci, n_boot),
                         strict=True))
    samples = {"misalignment_deg": np.degrees(np.concatenate(mis)), "step_T_rel": np.concatenate(steps_T),
               "step_A_rel": np.concatenate(steps_A)}
    return stats, samples


def side_by_side(real: pd.DataFrame, simulated: dict[str, dict]) -> pd.DataFrame:
    """Real rows of the measured table beside simulated statistics (one column group per world).

    Parameters
    ----------
    real : DataFrame
        data/measured_parameters.csv (:func:`ilocalg.sim.measured.table`).
    simulated : dict
        world label -> {parameter: {value, ci_low, ci_high}}.

    Returns
    -------
    DataFrame
        ``parameter, unit, real, real_ci_low, real_ci_high`` and per world ``<world>``,
        ``<world>_ci_low``, ``<world>_ci_high``, ``<world>_calibrated`` (real value inside the
        simulated interval).
    """
    rows = []
    r = real.set_index("parameter")
    for p, unit in COMPARED.items():
        if p not in r.index:
            continue
        row = {"parameter": p, "unit": unit, "real": r.loc[p, "value"], "real_ci_low": r.loc[p, "ci_low"],
               "real_ci_high": r.loc[p, "ci_high"]}
        for w, st in simulated.items():
            s = st.get(p)
            if s is None:
                row.update({w: np.nan, f"{w}_ci_low": np.nan, f"{w}_ci_high": np.nan, f"{w}_calibrated": None})
                continue
            row.update({w: s["value"], f"{w}_ci_low": s["ci_low"], f"{w}_ci_high": s["ci_high"],
                        f"{w}_calibrated": bool(s["ci_low"] <= row["real"] <= s["ci_high"])})
        rows.append(row)
    return pd.DataFrame(rows)
