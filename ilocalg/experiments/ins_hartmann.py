"""Hartmann et al. IMU + marker video-tracking EKF (Yeh & Huang's survey, sec. 5, Table 2, Figs 11-12).

For each simulated test sequence: level the object during its initial rest, initialise yaw and
position from the first tracker measurement, run the 15-state EKF and compare it with the video
tracker (VT). The deviation at each VT epoch is taken - our interpretation; the survey does not say
how - as that of the EKF's prediction just before it uses that measurement (``prior``), i.e. what the
IMU alone carried from the previous VT fix - after an outage this is the coasting error; the
deviation after the correction and the prediction's error against the truth are also given. The
simulated tracker has the outages Table 2 describes (about 21 over 1 s, the longest about 2.2 s). Table 2's
layout: mean and maximal absolute deviation per axis, VT sampling rate, longest outage, number of
outages over 1 s; the overall row averages the sequences (maximum for the maximal deviation).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins.hartmann import run_hartmann
from ilocalg.ins.mechanisation import coarse_level
from ilocalg.ins.paper_values import HARTMANN_2010, HARTMANN_TABLE2_OVERALL
from ilocalg.papers import paper_ref, reading, readings_table
from ilocalg.sim import hartmann as sim

__all__ = ["run_sequence", "run"]


def run_sequence(seq, level_s: float = 1.0, vt_sd=None):
    """Initialise and run the EKF on one :class:`ilocalg.sim.hartmann.HartmannSequence` (``vt_sd``: the
    tracker noise the filter assumes; default the simulator's)."""
    first = seq.t_s < seq.t_s[0] + level_s
    roll, pitch = coarse_level(seq.acc_b_mps2[first])
    x0 = np.zeros(15)
    x0[0:3] = roll, pitch, seq.z_vt[0, 0]
    x0[3:6] = seq.z_vt[0, 1:4]
    P0 = np.diag(np.square(np.concatenate([np.deg2rad([3.0, 3.0, 2.0]), np.full(3, 0.01), np.full(3, 0.05),
                                           np.full(3, np.deg2rad(0.5)), np.full(3, 0.2)])))
    vt_sd = seq.params["vt_sd"] if vt_sd is None else vt_sd
    return run_hartmann(seq.t_s, seq.gyr_b_radps, seq.acc_b_mps2, seq.t_vt_s, seq.z_vt, x0, P0, vt_sd=vt_sd)


def _settling_time(t, est, true, tol):
    """First time after which every component of ``est`` stays within ``tol`` of ``true`` (NaN if never)."""
    bad = np.any(np.abs(est - true) > tol, axis=1)
    if not bad.any():
        return float(t[0])
    last_bad = np.flatnonzero(bad)[-1]
    return float(t[last_bad + 1]) if last_bad + 1 < t.size else np.nan


def _sequence_row(label, seq, res):
    """Table 2's columns for one sequence plus prediction-minus-truth beside the deviation from the tracker."""
    dev_prior = np.abs(res.prior_at_vt[:, 3:6] - seq.z_vt[:, 1:4])[1:]
    err_prior = np.abs(res.prior_at_vt[:, 3:6] - seq.pos_v_m[res.vt_idx])[1:]
    dev_post = np.abs(res.x[res.vt_idx, 3:6] - seq.z_vt[:, 1:4])[1:]
    err_truth = np.abs(res.x[:, 3:6] - seq.pos_v_m)
    gaps = np.diff(seq.t_vt_s)
    return {"sequence": label,
            **{f"mean_dev_{a}_m": dev_prior[:, j].mean() for j, a in enumerate("xyz")},
            **{f"max_dev_{a}_m": dev_prior[:, j].max() for j, a in enumerate("xyz")},
            "vt_rate_hz": seq.t_vt_s.size / (seq.t_s[-1] - seq.t_s[0]),
            "outage_max_s": gaps.max(), "outages_over_1s": float((gaps > 1.0).sum()),
            **{f"mean_pred_err_truth_{a}_m": err_prior[:, j].mean() for j, a in enumerate("xyz")},
            **{f"max_pred_err_truth_{a}_m": err_prior[:, j].max() for j, a in enumerate("xyz")},
            **{f"mean_dev_post_{a}_m": dev_post[:, j].mean() for j, a in enumerate("xyz")},
            **{f"mean_err_truth_{a}_m": err_truth[:, j].mean() for j, a in enumerate("xyz")},
            "psd_repairs": res.n_psd_repairs}


def readings() -> pd.DataFrame:
    """One row per modelling choice (paper line of the survey, what it says, what the code does, source)."""
    vt = sim.VT_SD_DEFAULT
    rows = [
        ("EKF", "survey eq. (6)-(29)", "15-state EKF: Euler angles, position, velocity, gyro and accelerometer "
         "biases; yaw + position from the tracker", "ilocalg.ins.hartmann.run_hartmann; Joseph-form update "
         "(algebraically eq. 29)", "survey"),
        ("IMU", "survey sec. 5.1", "ADIS16350 at 400 Hz, 0.4 deg/s and 0.05 m/s^2 noise", "as stated", "survey"),
        ("tracker noise (an input)", "L218", "position precision in the millimetre range",
         f"sd {vt[1] * 1e3:g} / {vt[2] * 1e3:g} / {vt[3] * 1e3:g} mm (x / y / z depth), "
         f"{np.rad2deg(vt[0]):g} deg yaw", "assumption (no published value for this tracker); Table 2's mean "
         "deviation largely echoes it, so it is shown as a sensitivity curve: tracker_noise (mean deviation for "
         "the noise x 0.5-4, the paper's value beside) and tracker_noise_implied (the noise at which the curve "
         "meets the paper's mean deviation: a reading, not an input)"),
        ("tracker rate and outages", "Table 2 (VT measurements)", "5.82 Hz mean, longest outage 2.24 s, "
         "21.5 outages over 1 s (input statistics)", "10 frames/s minus blur / random losses, plus Poisson "
         "outages of 1 s + Exp(0.34 s), 21.5 per 120 s", "set from Table 2 (sequence length not given, 120 s "
         "assumed), so the Table 2 rate / outage rows are inputs, not reproductions (their comparison notes say "
         "so); no published marker-tracking outage statistics used: outage_sensitivity sweeps the rate and the "
         "excess duration x 0.5 and x 2 and shows what the deviations do"),
        ("deviation metric", "Table 2 (mean / maximal deviation to VT)", "deviation of the EKF position to the "
         "VT (how and when it is taken is not said)", "the EKF prediction just before each tracker fix minus "
         "that fix (an interpretation); prediction minus truth and the after-correction deviation beside it",
         "interpretation"),
        ("sequences", "Table 2", "6 test sequences of hand motion", "6 simulated sequences of 120 s",
         "duration assumed"),
    ]
    where = "Yeh & Huang survey (Hartmann et al. 2010), "
    return readings_table([reading(c, "" if line == "-" else where + line, text, code, src)
                           for c, line, text, code, src in rows])


def run(seed: int = 0, fast: bool = False, n_sequences: int | None = None,
        duration_s: float | None = None, noise_scales=(0.5, 1.0, 2.0, 4.0),
        outage_factors=((0.5, 1.0), (2.0, 1.0), (1.0, 0.5), (1.0, 2.0))) -> dict[str, pd.DataFrame]:
    """Table 2 reproduced on simulated sequences (with the tracker outages Table 2 describes).

    Returns
    -------
    dict with ``table2`` (one row per sequence plus ``overall``; the deviation columns are the EKF prediction
    before each tracker fix minus that fix - an interpretation of Table 2's "deviation to VT" - with
    prediction-minus-truth, after-correction deviation and EKF-minus-truth beside them), ``comparison``
    (paper_ref rows), ``tracker_noise`` (the assumed tracker noise as an input, and the overall mean
    deviations with the tracker noise scaled by ``noise_scales`` on the first sequences), ``settling`` (bias
    settling times and final bias errors per sequence), ``tracker_noise_implied`` (per axis: the tracker noise
    at which the mean-deviation curve meets the paper's value, by linear interpolation; NaN outside the swept
    range), ``outage_sensitivity`` (the outage rate and excess duration scaled by ``outage_factors`` =
    ((rate factor, excess factor), ...), beside the default, on the first sequences), ``trace`` (first
    sequence, decimated: time, EKF and
    true position, bias estimates and truths), ``vt`` (its tracker fixes) and ``readings``.
    """
    n_sequences = n_sequences or (2 if fast else 6)
    duration_s = duration_s or (60.0 if fast else 120.0)
    rows, settle, noise_rows = [], [], []
    trace = vt = None
    for i in range(n_sequences):
        seq = sim.simulate(duration_s, seed=seed * 1000 + i)
        res = run_hartmann_result = run_sequence(seq)
        rows.append(_sequence_row(str(i + 1), seq, res))
        bg, ba = res.x[:, 9:12], res.x[:, 12:15]
        settle.append({"sequence": str(i + 1),
                       "gyro_bias_settle_s": _settling_time(seq.t_s, bg, seq.bias_true[:3], np.deg2rad(0.05)),
                       "acc_bias_settle_s": _settling_time(seq.t_s, ba, seq.bias_true[3:], 0.02),
                       "gyro_bias_final_err_dps": float(np.rad2deg(np.abs(bg[-1] - seq.bias_true[:3])).max()),
                       "acc_bias_final_err_mps2": float(np.abs(ba[-1] - seq.bias_true[3:]).max())})
        if i == 0:
            k = np.arange(0, seq.t_s.size, 20)
            trace = pd.DataFrame({"t_s": seq.t_s[k],
                                  **{f"ekf_{a}_m": run_hartmann_result.x[k, 3 + j] for j, a in enumerate("xyz")},
                                  **{f"true_{a}_m": seq.pos_v_m[k, j] for j, a in enumerate("xyz")},
                                  **{f"bg_{a}_dps": np.rad2deg(bg[k, j]) for j, a in enumerate("xyz")},
                                  **{f"bg_true_{a}_dps": np.rad2deg(seq.bias_true[j]) for j, a in enumerate("xyz")},
                                  **{f"ba_{a}_mps2": ba[k, j] for j, a in enumerate("xyz")},
                                  **{f"ba_true_{a}_mps2": seq.bias_true[3 + j] for j, a in enumerate("xyz")}})
            vt = pd.DataFrame({"t_s": seq.t_vt_s, "yaw_rad": seq.z_vt[:, 0],
                               **{f"{a}_m": seq.z_vt[:, 1 + j] for j, a in enumerate("xyz")}})
    n_noise = 1 if fast else min(2, n_sequences)
    for scale in noise_scales:
        sd = tuple(scale * np.asarray(sim.VT_SD_DEFAULT))
        devs = []
        for i in range(n_noise):
            seq = sim.simulate(duration_s, seed=seed * 1000 + i, vt_sd=sd)
            devs.append(_sequence_row(str(i + 1), seq, run_sequence(seq, vt_sd=sd)))
        d = pd.DataFrame(devs)
        noise_rows.append({"noise_scale": scale, "vt_sd_x_mm": 1e3 * sd[1], "vt_sd_y_mm": 1e3 * sd[2],
                           "vt_sd_z_mm": 1e3 * sd[3], "vt_sd_yaw_deg": float(np.rad2deg(sd[0])),
                           "n_sequences": n_noise,
                           **{f"mean_dev_{a}_m": d[f"mean_dev_{a}_m"].mean() for a in "xyz"},
                           **{f"mean_pred_err_truth_{a}_m": d[f"mean_pred_err_truth_{a}_m"].mean() for a in "xyz"},
                           **{f"paper_mean_dev_{a}_m": HARTMANN_TABLE2_OVERALL[f"mean_dev_{a}_m"] for a in "xyz"},
                           "source": ("assumption: survey L218 'millimetre precision'" if scale == 1.0
                                      else "sensitivity: the assumed noise scaled")})
    tn = pd.DataFrame(noise_rows).sort_values("noise_scale")
    implied = []
    for j, a in enumerate("xyz"):
        dev = tn[f"mean_dev_{a}_m"].to_numpy(float)
        pv = HARTMANN_TABLE2_OVERALL[f"mean_dev_{a}_m"]
        ok = np.all(np.diff(dev) > 0) and dev[0] <= pv <= dev[-1]
        sc = float(np.interp(pv, dev, tn["noise_scale"].to_numpy(float))) if ok else np.nan
        implied.append({"axis": a, "paper_mean_dev_m": pv, "implied_noise_scale": sc,
                        "implied_vt_sd_mm": 1e3 * sc * sim.VT_SD_DEFAULT[1 + j],
                        "swept_scales": f"{tn['noise_scale'].min():g}-{tn['noise_scale'].max():g}"})
    out_rows = []
    for fr, fe in ((1.0, 1.0), *outage_factors):
        devs = []
        for i in range(n_noise):
            seq = sim.simulate(duration_s, seed=seed * 1000 + i, outage_rate_per_s=fr * sim.OUTAGE_RATE_PER_S,
                               outage_excess_mean_s=fe * sim.OUTAGE_EXCESS_MEAN_S)
            devs.append(_sequence_row(str(i + 1), seq, run_sequence(seq)))
        d = pd.DataFrame(devs)
        out_rows.append({"outage_rate_factor": fr, "outage_excess_factor": fe,
                         "outage_rate_per_120s": 120.0 * fr * sim.OUTAGE_RATE_PER_S,
                         "outage_excess_mean_s": fe * sim.OUTAGE_EXCESS_MEAN_S, "n_sequences": n_noise,
                         **{c: d[c].mean() for c in ("vt_rate_hz", "outage_max_s", "outages_over_1s")},
                         **{f"mean_dev_{a}_m": d[f"mean_dev_{a}_m"].mean() for a in "xyz"},
                         **{f"max_dev_{a}_m": d[f"max_dev_{a}_m"].max() for a in "xyz"}})
    t2 = pd.DataFrame(rows)
    overall = {"sequence": "overall"}
    for c in t2.columns[1:]:
        overall[c] = t2[c].max() if c.startswith(("max_dev", "max_pred")) else t2[c].mean()
    t2 = pd.concat([t2, pd.DataFrame([overall])], ignore_index=True)
    ov = t2.iloc[-1]
    comp = []
    for key, pv in HARTMANN_TABLE2_OVERALL.items():
        unit = "Hz" if key.endswith("hz") else "s" if key.endswith("_s") else "" if key.startswith("outages") else "m"
        is_input = key in ("vt_rate_hz", "outage_max_s", "outages_over_1s")
        note = (f"input, not a reproduction: the simulated tracker's outages were set from Table 2 "
                f"({n_sequences} sequences of {duration_s:g} s)" if is_input
                else f"EKF prediction vs VT, {n_sequences} simulated sequences of {duration_s:g} s"
                + ("; echoes the assumed tracker noise: see tracker_noise (sensitivity curve)"
                   if key.startswith("mean_dev") else "; see outage_sensitivity"))
        comp.append(paper_ref(HARTMANN_2010, "Table 2", f"overall {key}", pv, float(ov[key]), unit=unit, note=note))
    st = pd.DataFrame(settle)
    # named scalars for the claims ledger (ilocalg.papers.survey): bias settling (survey L336, Fig 12)
    measures = pd.DataFrame([
        {"quantity": "gyro bias settling time", "value": float(st["gyro_bias_settle_s"].mean()), "unit": "s"},
        {"quantity": "accelerometer bias settling time", "value": float(st["acc_bias_settle_s"].mean()), "unit": "s"},
        {"quantity": "share of sequences whose biases settle", "unit": "%",
         "value": 100.0 * float((st[["gyro_bias_settle_s", "acc_bias_settle_s"]].notna().all(axis=1)).mean())},
    ])
    return {"table2": t2, "comparison": pd.DataFrame(comp), "tracker_noise": tn.reset_index(drop=True),
            "tracker_noise_implied": pd.DataFrame(implied), "outage_sensitivity": pd.DataFrame(out_rows),
            "settling": st, "trace": trace, "vt": vt, "readings": readings(), "measures": measures}
