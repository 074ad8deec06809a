"""Smartphone INS with constraints and control points (Liao et al. 2016, sec. 4.1, Tables 4-7, Figs 7-12).

For each phone (Samsung S5 on the Fig 5 route, iPhone 5S on the Fig 6 route) and seed: simulate the
walk, run Filtering + NHC/ZUPT, Filtering + WVC/ZUPT, Filtering + WVC/ZUPT + GCP and the RTS
Smoothing + WVC/ZUPT + GCP, and score the indoor part (the paper removes the GNSS-aided start).
Statistics are per run, then averaged over seeds.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins import dcm_to_euler, error_stats, eskf_rts_smooth, heading_error_with_lag_deg, nav_errors
from ilocalg.ins.evaluate import AXES
from ilocalg.ins.paper_values import LIAO_2016, paper_value, side_by_side
from ilocalg.ins.pipeline import run_walk
from ilocalg.papers import paper_ref, reading, readings_table
from ilocalg.sim import ins_walk
from ilocalg.sim.ins_walk import PHONES

__all__ = ["error_budget", "GCP_RSSI_LABEL", "GCP_RSSI_SD_SWEEP_DB", "METHODS", "STAIR_OPTIONS", "STAIR_VARIANTS",
           "BIAS_INSTABILITY_FACTORS", "TIME_JITTERS_S", "NOISE_FACTORS",
           "GAIT_VARIANTS", "run_methods", "run_phone", "readings", "sensor_sensitivity", "gait_sensitivity", "run"]

METHODS = ("Filtering + NHC/ZUPT", "Filtering + WVC/ZUPT", "Filtering + WVC/ZUPT + GCP",
           "Smoothing + WVC/ZUPT + GCP")
_IDEAL_50HZ = ins_walk.PhoneProfile("error-free", (4, 4), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


#: Stair handling of the WVC compared in the ``stair_handling`` table (:func:`ilocalg.ins.pipeline.stair_mask`).
STAIR_OPTIONS = ("none", "baro", "truth")
#: Columns of the ``stair_handling`` table: (label, stair source, action on stairs).
STAIR_VARIANTS = (("none", "none", "drop"), ("baro", "baro", "drop"), ("baro, downweight", "baro", "downweight"),
                  ("truth", "truth", "drop"))


#: Sensitivity sweep of the phone sensor values no published measurement fixes for these phones: factors on the
#: Gauss-Markov bias instability (0.5 mg / 20 deg/h, 300 s) and time-tag error sds (s); the defaults are 1 and 10 ms.
#: Label of the default control-point model in the gcp_grade table, and the RSSI scatters swept there (dB).
GCP_RSSI_LABEL = "Bluetooth RSSI (100 ms advertising, 1 s ranging, immediate zone; default)"
GCP_RSSI_SD_SWEEP_DB = (2.0, 8.0)
BIAS_INSTABILITY_FACTORS = (0.0, 1.0, 3.0)
TIME_JITTERS_S = (0.0, 0.01, 0.03)
#: Factor on the MPU-6500 datasheet white-noise densities (300 ug/sqrt(Hz), 0.01 deg/s/sqrt(Hz)); the phone
#: profiles use 3 (an assumption: phone output filtering and electrical noise), swept 1 (datasheet) to 5.
NOISE_FACTORS = (1.0, 3.0, 5.0)
_PROFILE_NOISE_FACTOR = 3.0


_WR = ins_walk.WALK_RATIO_PER_HEIGHT
#: Gait sensitivity: each published population mean moved by one between-walker sd of the same study (level speed
#: 0.16 m/s, walk ratio 10 %, stair cadence 0.12 Hz), and the earlier walker (speed from eq. 7, stairs 0.5 m/s):
#: (label, gait, walker_gait keywords).
GAIT_VARIANTS = (
    ("published", "published", {}),
    ("level speed mean - 1 sd", "published", {"speed_mean_mps": ins_walk.LEVEL_SPEED_MEAN_MPS
                                              - ins_walk.LEVEL_SPEED_SD_MPS}),
    ("level speed mean + 1 sd", "published", {"speed_mean_mps": ins_walk.LEVEL_SPEED_MEAN_MPS
                                              + ins_walk.LEVEL_SPEED_SD_MPS}),
    ("walk ratio - 1 sd", "published", {"walk_ratio_per_height": _WR - ins_walk.WALK_RATIO_PER_HEIGHT_SD}),
    ("walk ratio + 1 sd", "published", {"walk_ratio_per_height": _WR + ins_walk.WALK_RATIO_PER_HEIGHT_SD}),
    ("stair cadence - 1 sd", "published", {
        "stair_up_cadence_hz": ins_walk.STAIR_UP_CADENCE_HZ - ins_walk.STAIR_CADENCE_SD_HZ,
        "stair_down_cadence_hz": ins_walk.STAIR_DOWN_CADENCE_HZ - ins_walk.STAIR_CADENCE_SD_HZ}),
    ("stair cadence + 1 sd", "published", {
        "stair_up_cadence_hz": ins_walk.STAIR_UP_CADENCE_HZ + ins_walk.STAIR_CADENCE_SD_HZ,
        "stair_down_cadence_hz": ins_walk.STAIR_DOWN_CADENCE_HZ + ins_walk.STAIR_CADENCE_SD_HZ}),
    ("legacy walker (eq. 7 speed, stairs 0.5 m/s)", "legacy", {}),
)


def run_methods(walk, stairs: str = "none", stair_action: str = "drop"):
    """The four methods on one walk: ``({method: (pos, mat)}, gcp_filter_result)``."""
    out = {}
    r = run_walk(walk, "nhc", use_gcp=False)
    out[METHODS[0]] = (r.pos_n_m, r.mat_nb)
    r = run_walk(walk, "wvc", use_gcp=False, stairs=stairs, stair_action=stair_action)
    out[METHODS[1]] = (r.pos_n_m, r.mat_nb)
    r = run_walk(walk, "wvc", use_gcp=True, stairs=stairs, stair_action=stair_action)
    out[METHODS[2]] = (r.pos_n_m, r.mat_nb)
    s = eskf_rts_smooth(r, with_cov=False)
    out[METHODS[3]] = (s.pos_n_m, s.mat_nb)
    return out, r


def run_phone(route: str, profile: str, seed: int, stairs: str = "none", stair_action: str = "drop", **sim_kw):
    """Simulate one walk and run the four methods: ``(walk, {method: (pos, mat)}, gcp_filter_result)``."""
    walk = ins_walk.simulate(route, profile, seed=seed, **sim_kw)
    out, r = run_methods(walk, stairs, stair_action)
    return walk, out, r


def readings(stairs: str, stair_action: str) -> pd.DataFrame:
    """One row per modelling choice: paper line, what the text says, what the code does, source of the value."""
    rows = [
        ("filter state and update", "L109-L134", "21-state EKF, eq. (1)-(6), Joseph update",
         "ilocalg.ins.eskf.run_eskf, closed loop", "paper"),
        ("WVC forward speed", "L151-L158", "step model of Chen et al. (2011), eq. (7), default height and "
         "parameters", "eq. (7), h = 1.75 m, a = 0.371, b = 0.227, c = 1",
         "a, b, c: the widely reproduced Chen et al. (2011) values, not checked against that paper"),
        ("step frequency", "L151", "from the step counter in real time", "1 / time since the previous step "
         "(option: F = 1 / (0.8 dt_k + 0.2 dt_(k-1)))", "smoothing: the same step-model lineage, unchecked"),
        ("WVC / NHC weights", "L146", "WVC lowers the lateral / vertical weights of NHC", "NHC sd 0.05 m/s; "
         "WVC forward 0.15 m/s, lateral / vertical 0.3 m/s", "assumption (the paper gives no numbers)"),
        ("stairs", "L200 (route climbs stairs); L202 (both phones' data processed by the same algorithm)",
         "nothing on the filter's stair behaviour; the same algorithm for both phones",
         f"stairs={stairs!r}, stair_action={stair_action!r}" + (
             ": no stair handling on either phone (eq. 7 everywhere), the one processing both phones share "
             "(the iPhone 5S has no barometer)" if stairs == "none" else
             ": WVC forward and vertical rows dropped where the barometric height rises or falls faster than "
             "0.1 m/s (iPhone 5S: no barometer, so the phones are NOT processed alike)" if stairs == "baro" else
             ": the simulator's true stair flag on both phones (an upper bound, not a detector)"),
         "text (L202): the default processes both phones alike; barometric handling (Samsung only) and the true "
         "flag are labelled alternatives in the stair_handling table (threshold 0.1 m/s: half of 0.17 m x 1.3 Hz)"),
        ("walker on stairs", "-", "not described", "one tread (0.29 m) per step, cadence 1.62 Hz up / "
         "1.80 Hz down (horizontal speed about 0.47 m/s up, derived)", "Blondel's rule; Riener et al. (2002), "
         "Protopapadaki et al. (2007): recalled, not re-read (Kretz et al. 2008, cited earlier for the horizontal "
         "speed, does not give it: dropped); covered by the gait_sensitivity table (stair cadence +- 1 sd, the "
         "earlier 0.5 m/s walker) and the stair_handling table (WVC on stairs off / barometer / true flag)"),
        ("walker on level ground", "-", "not described", "speed N(1.40, 0.16) m/s, walk ratio per height",
         "Bohannon (1997); Sekiya & Nagasaki (1998); Hof (1996): recalled, not re-read (independent of eq. 7); "
         "covered by the gait_sensitivity table (level speed and walk ratio means +- 1 sd, the eq. 7 walker)"),
        ("ZUPT", "L146", "stand still 1-3 s after turns", "ZUPT at detected standstills, sd 0.05 m/s",
         "paper (stops); sd assumed"),
        ("control points", "L73, L109, L202", "4 surveyed points sent by Bluetooth, cm (survey) / m (Bluetooth) "
         "level, about every 15 s; the user is taken to be at the point when its beacon is sensed (L73)",
         "fix = surveyed coordinate when the phone sees the beacon: packets every 100 ms (+0-10 ms advDelay), "
         "RSSI -59 dBm at 1 m, path-loss exponent 2, 5 dB per-packet scatter, averaged over 1 s ranging cycles, "
         "fix at the end of the first cycle at or above the RSSI of 0.5 m (immediate); filter sd 1 m",
         "iBeacon 100 ms advertising and 0.5 m immediate zone, iOS 1 s ranging: recalled, not re-read; -59 dBm "
         "calibrated power (Blue Charm chart; cancels); 4-6 dB scatter (vendor stability tests, weak source): "
         "swept 2 / 8 dB; the earlier truth-gate model (0.6 m gate, U(0, 1 s) delay, 0.5 m offset) and the "
         "ideal fix are rows of the gcp_grade table, with the fixes' count and mean horizontal error"),
        ("phone sampling", "L171, L324", "15-17 Hz; about 20 Hz, unstable, poor time tags",
         "14.3-20 Hz irregular, point samples, time-tag error sd 10 ms (clipped at 2 sd, monotonic tags)",
         "10 ms: no published measurement for these phones; swept 0 / 10 / 30 ms in the sensor_sensitivity "
         "table; on/off in sensor_grade"),
        ("sensor errors", "L178, L202", "the phones' IMUs calibrated in Liao et al. (2014), similar; no values "
         "in this paper", "MPU-6500 class turn-on bias (30 / 20 mg, 0.3 / 0.2 deg/s), scale factor; white noise "
         "3 x the datasheet densities (300 ug/sqrt(Hz), 0.01 deg/s/sqrt(Hz))",
         "InvenSense MPU-6500 product specification (zero-g offset, sensitivity tolerance): recalled, not "
         "re-read; Liao et al. (2014)'s calibration values not available here; the x3 noise factor is an "
         "assumption swept x1 / x3 / x5 in the sensor_sensitivity table (noise_factor); the whole sensor grade "
         "in the reference_grade table"),
        ("bias instability", "-", "not given", "first-order Gauss-Markov, 0.5 mg / 20 deg/h, 300 s",
         "no published measurement used (assumed order of consumer-MEMS Allan-variance studies); swept x0 / x1 / "
         "x3 in the sensor_sensitivity table; on/off in sensor_grade"),
        ("barometer", "-", "not mentioned (stair handling is this code's)", "Samsung S5 heights, noise sd 0.1 m; "
         "used only by the stair_handling alternatives (no effect on the default rows)",
         "BMP280-class RMS noise about 1.2 Pa: recalled, not re-read; covered by the stair_handling table "
         "(barometric detection vs the true stair flag)"),
        ("GNSS", "L109, L202", "only the two outdoor loops (initialisation)", "1 Hz, sd 2.5 / 2.5 / 4 m",
         "assumption (phone grade)"),
        ("reference", "L178-L191", "MIDG-II (Table 3) on the same walk, NHC/ZUPT, smoothed", "the simulated "
         "truth (reference_grade table processes a MIDG-II-grade IMU like the paper's reference; it has no "
         "barometer, so its WVC rows use the same stair handling as the phones only when that handling needs "
         "none: column 'barometer used' labels each row)", "Table 3"),
        ("scored part", "L202", "the GNSS-aided start removed", "indoor part after the outdoor loops", "paper"),
    ]
    return readings_table([reading(c, "" if line == "-" else "Liao et al. (2016), " + line, text, code, src)
                           for c, line, text, code, src in rows])


def sensor_sensitivity(seeds, gait: str = "published", stairs: str = "none", stair_action: str = "drop",
                       bias_instability_factors=BIAS_INSTABILITY_FACTORS, time_jitters_s=TIME_JITTERS_S,
                       reuse=None, full_grid: bool = True, noise_factors=NOISE_FACTORS) -> pd.DataFrame:
    """RMS errors of Filtering + WVC/ZUPT + GCP over the grid of bias-instability factors and time-tag jitters.

    Every cell simulates the same walks (same seeds; the swept draws are paired, see
    :meth:`ilocalg.sim.ins_walk.PhoneProfile.swept`) and scores the indoor part. ``reuse`` maps
    ``(phone, seed)`` to ``(walk, filter result)`` of the default profile, reused for its own cell.
    ``full_grid=False`` sweeps one value at a time (each factor at the profile's jitter, each jitter at x1).
    ``noise_factors`` (factors on the datasheet white-noise densities; the profiles' is 3) are swept one at a
    time, at the default bias instability and jitter.

    Returns
    -------
    DataFrame: phone, noise_factor, bias_instability_factor, time_jitter_sd_ms, tag_error_sd_ms (realised, after
    the 2 sd clip and the monotonic clock), n_seeds, N, E, H (m), Heading (deg), mean over seeds.
    """
    seeds = list(seeds)
    if not seeds:
        raise ValueError("seeds must hold at least one seed")
    rows = []
    for phone, route, profile in PHONES:
        base = ins_walk.PROFILES[profile]
        cells = [(_PROFILE_NOISE_FACTOR, k, j) for k in bias_instability_factors for j in time_jitters_s
                 if full_grid or k == 1.0 or j == base.time_jitter_sd_s]
        cells += [(c, 1.0, base.time_jitter_sd_s) for c in noise_factors if c != _PROFILE_NOISE_FACTOR]
        for c, k, jit in cells:
            prof = base.swept(k, jit, noise_scale=c / _PROFILE_NOISE_FACTOR)
            for s in seeds:
                if reuse is not None and (phone, s) in reuse and prof == base:
                    walk, r = reuse[(phone, s)]
                else:
                    walk = ins_walk.simulate(route, prof, seed=s, gait=gait)
                    r = run_walk(walk, "wvc", use_gcp=True, stairs=stairs, stair_action=stair_action)
                ind = walk.t_s >= walk.t_indoor_s
                err = nav_errors(r.pos_n_m[ind], r.mat_nb[ind], walk.pos_true_n_m[ind], walk.mat_true_nb[ind])
                rows.append({"phone": phone, "noise_factor": float(c), "bias_instability_factor": float(k),
                             "time_jitter_sd_ms": 1e3 * float(jit),
                             "tag_error_sd_ms": 1e3 * float(np.std(walk.t_s - walk.t_true_s)),
                             **{ax: error_stats(err)["rms"][ax] for ax in ("N", "E", "H", "Heading")}})
    out = (pd.DataFrame(rows).groupby(["phone", "noise_factor", "bias_instability_factor", "time_jitter_sd_ms"],
                                      sort=False)[["tag_error_sd_ms", "N", "E", "H", "Heading"]].mean().reset_index())
    out.insert(5, "n_seeds", len(seeds))
    return out


def gait_sensitivity(seeds, stairs: str = "none", stair_action: str = "drop", variants=GAIT_VARIANTS,
                     reuse=None) -> pd.DataFrame:
    """RMS errors of Filtering + WVC/ZUPT + GCP with the published gait means moved by one between-walker sd.

    The published walker's draws are paired across variants (same seeds); ``reuse`` maps ``(phone, seed)`` to
    ``(walk, filter result)`` of the default walker (used for the ``published`` row when the experiment's walker
    is the published one).

    Returns
    -------
    DataFrame: phone, walker, level speed (m/s), cadence (Hz), n_seeds, N, E, H (m), Heading (deg), mean over seeds.
    """
    seeds = list(seeds)
    if not seeds:
        raise ValueError("seeds must hold at least one seed")
    rows = []
    for phone, route, profile in PHONES:
        for label, gait, kw in variants:
            for s in seeds:
                if reuse is not None and (phone, s) in reuse and gait == "published" and not kw:
                    walk, r = reuse[(phone, s)]
                else:
                    walk = ins_walk.simulate(route, profile, seed=s, gait=gait, gait_kw=kw)
                    r = run_walk(walk, "wvc", use_gcp=True, stairs=stairs, stair_action=stair_action)
                ind = walk.t_s >= walk.t_indoor_s
                err = nav_errors(r.pos_n_m[ind], r.mat_nb[ind], walk.pos_true_n_m[ind], walk.mat_true_nb[ind])
                rows.append({"phone": phone, "walker": label,
                             "speed_mps": walk.params.get("speed_mps", np.nan),
                             "cadence_hz": walk.params.get("cadence_hz", np.nan),
                             **{ax: error_stats(err)["rms"][ax] for ax in ("N", "E", "H", "Heading")}})
    out = (pd.DataFrame(rows).groupby(["phone", "walker"], sort=False)
           [["speed_mps", "cadence_hz", "N", "E", "H", "Heading"]].mean().reset_index())
    out.insert(4, "n_seeds", len(seeds))
    return out


def _stats_rows(phone, method, seed, err):
    st = error_stats(err)
    return [{"phone": phone, "method": method, "seed": seed, "stat": k, **st[k]} for k in ("max", "rms", "std")]


def run(seed: int = 0, fast: bool = False, n_seeds: int | None = None, time_lags_s=(0.0, 0.05, 0.1, 0.2),
        reference_grade: bool = True, stairs: str = "none", stair_action: str = "drop",
        gait: str = "published", sensitivity_seeds: int | None = None) -> dict[str, pd.DataFrame]:
    """Tables 4-7 reproduced on simulated walks.

    ``stairs`` (default "none"): the WVC's stair handling, the same on both phones by default (Liao et al.
    2016, L202: both phones' data are processed by the same algorithm; the iPhone 5S has no barometer);
    "baro" (Samsung only) and "truth" are the alternatives of the ``stair_handling`` table.

    Returns
    -------
    dict with ``errors`` (phone, method, stat, N, E, H [m], Roll, Pitch, Heading [deg], mean over seeds),
    ``errors_per_seed``, ``position_side_by_side`` and ``attitude_side_by_side`` (the paper's layout,
    paper value beside the reproduced one), ``comparison`` (paper_ref rows: RMS N/E/H and heading),
    ``walk_stats`` (the simulated inputs: duration, IMU rate, control-point passages), ``trajectory``
    (first seed: per-epoch E, N, H of the truth and of every method), ``gcp_grade`` (RMS errors with
    Bluetooth control-point fixes vs the ideal fix, true position + 5 cm), ``sensor_grade`` (RMS errors with the
    realistic phone timing vs the ideal sensor), ``stair_handling`` (RMS and max errors of every method with
    the WVC's stair handling off, from the barometer (forward speed dropped, or down-weighted to 0.5 m/s), and
    from the true stair flag), ``error_budget`` (:func:`error_budget`: each error source changed, beside the same
    seeds' default and the paper's GCP / smoothing rows), ``readings`` and
    ``heading_time_sync`` (heading RMS / max when the reference is read ``time_lags_s`` off) and
    ``reference_grade`` (the same walks measured by a MIDG-II-grade IMU, paper Table 3, processed like the
    paper's reference trajectory - NHC/ZUPT and smoothing - and with WVC/ZUPT/GCP and smoothing; not in
    fast mode also by an error-free IMU), ``sensor_sensitivity`` (:func:`sensor_sensitivity`: Filtering +
    WVC/ZUPT + GCP RMS errors for bias instability x0, x1, x3 and time-tag error sd 0, 10, 30 ms, on the first
    ``sensitivity_seeds`` seeds: default 3; in fast mode 1 seed and one value at a time), ``gait_sensitivity``
    (:func:`gait_sensitivity`: the same filter with each published gait mean moved by one between-walker sd,
    and the earlier walker, on the same seeds).
    """
    if stairs not in STAIR_OPTIONS:
        raise ValueError(f"stairs must be one of {STAIR_OPTIONS}, got {stairs!r}")
    n_seeds = n_seeds or (1 if fast else 6)
    n_sens = min(n_seeds, sensitivity_seeds or (1 if fast else 3))
    reuse = {}
    rows, stats, traj, grade, sync, refg, stair_rows, sens_rows = [], [], [], [], [], [], [], []
    for phone, route, profile in PHONES:
        # Disjoint simulation seeds per experiment seed: seed k uses k*n_seeds .. (k+1)*n_seeds - 1, so runs
        # with different seeds are independent (a sweep over seeds gives honest confidence intervals).
        for s in range(seed * n_seeds, (seed + 1) * n_seeds):
            walk, sol, rgcp = run_phone(route, profile, s, stairs, stair_action, gait=gait)
            if s < seed * n_seeds + n_sens:
                reuse[(phone, s)] = (walk, rgcp)
            ind = walk.t_s >= walk.t_indoor_s
            for method, (pos, mat) in sol.items():
                err = nav_errors(pos[ind], mat[ind], walk.pos_true_n_m[ind], walk.mat_true_nb[ind])
                rows += _stats_rows(phone, method, s, err)
            for label, opt, action in STAIR_VARIANTS:
                same = opt == stairs and (action == stair_action or opt == "none")
                sol_o = sol if same else run_methods(walk, opt, action)[0]
                for method, (pos, mat) in sol_o.items():
                    st = error_stats(nav_errors(pos[ind], mat[ind], walk.pos_true_n_m[ind], walk.mat_true_nb[ind]))
                    stair_rows += [{"phone": phone, "stairs": label, "method": method, "seed": s, "stat": k,
                                    **st[k]} for k in ("max", "rms")]
            gcp_variants = [(GCP_RSSI_LABEL, walk)]
            for sd_db in GCP_RSSI_SD_SWEEP_DB:
                gcp_variants.append((f"Bluetooth RSSI, packet scatter {sd_db:g} dB",
                                     ins_walk.simulate(route, profile, seed=s, gait=gait, rssi_sd_db=sd_db)))
            gcp_variants += [("Bluetooth (surveyed point, delay, offset)",
                              ins_walk.simulate(route, profile, seed=s, gait=gait, gcp_mode="ble")),
                             ("ideal (true position + 5 cm)",
                              ins_walk.simulate(route, profile, seed=s, gait=gait, gcp_mode="ideal"))]
            for gname, w2 in gcp_variants:
                r2 = rgcp if w2 is walk else run_walk(w2, "wvc", use_gcp=True, stairs=stairs,
                                                       stair_action=stair_action)
                for method, sol2 in ((METHODS[2], r2), (METHODS[3], eskf_rts_smooth(r2, with_cov=False))):
                    err = nav_errors(sol2.pos_n_m[ind], sol2.mat_nb[ind], walk.pos_true_n_m[ind],
                                     walk.mat_true_nb[ind])
                    k_fix = np.minimum(np.searchsorted(w2.t_s, w2.gcp_t_s), w2.t_s.size - 1)
                    fix_err = np.linalg.norm(w2.pos_true_n_m[k_fix, :2] - w2.gcp_pos_n_m[:, :2], axis=1)
                    grade.append({"phone": phone, "control points": gname, "gcp_sd_m": w2.gcp_sd_m,
                                  "n_fixes": int(w2.gcp_t_s.size),
                                  "fix_horizontal_error_mean_m": float(fix_err.mean()) if fix_err.size else np.nan,
                                  "method": method, "seed": s, **error_stats(err)["rms"]})
            ideal = ins_walk.simulate(route, ins_walk.PROFILES[profile].ideal_timing(), seed=s, gait=gait)
            indi = ideal.t_s >= ideal.t_indoor_s
            for label, w3 in (("realistic phone (jitter, point samples, bias instability)", walk),
                              ("ideal sensor timing", ideal)):
                r3 = rgcp if w3 is walk else run_walk(w3, "wvc", use_gcp=True, stairs=stairs,
                                                       stair_action=stair_action)
                i3 = ind if w3 is walk else indi
                for method, sol3 in ((METHODS[2], r3), (METHODS[3], eskf_rts_smooth(r3, with_cov=False))):
                    err = nav_errors(sol3.pos_n_m[i3], sol3.mat_nb[i3], w3.pos_true_n_m[i3], w3.mat_true_nb[i3])
                    sens_rows.append({"phone": phone, "sensor": label, "method": method, "seed": s,
                                      **error_stats(err)["rms"]})
            for method in METHODS[2:]:
                pos, mat = sol[method]
                for lag in time_lags_s:
                    # on the true sampling clock (the phone's jittered tags may fall outside the reference)
                    e = heading_error_with_lag_deg(walk.t_true_s[ind], mat[ind], walk.t_ref_s, walk.mat_ref_nb, lag)
                    sync.append({"phone": phone, "method": method, "seed": s, "lag_s": lag,
                                 "heading_rms_deg": float(np.sqrt(np.mean(e**2))),
                                 "heading_max_deg": float(np.max(np.abs(e)))})
            ref_imus = [("MIDG-II grade (paper Table 3)", "midg2")]  # reference IMUs: exact timing
            if not fast:
                ref_imus.append(("error-free, 50 Hz", _IDEAL_50HZ))
            for imu_label, prof in ref_imus if reference_grade else ():
                wr = ins_walk.simulate(route, prof, seed=s, gait=gait)
                indr = wr.t_s >= wr.t_indoor_s
                for label, cons, gcp in (("Smoothing + NHC/ZUPT (as the paper's reference)", "nhc", False),
                                         (METHODS[3], "wvc", True)):
                    sm = eskf_rts_smooth(run_walk(wr, cons, use_gcp=gcp, stairs=stairs if cons == "wvc" else "none",
                                                  stair_action=stair_action), with_cov=False)
                    err = nav_errors(sm.pos_n_m[indr], sm.mat_nb[indr], wr.pos_true_n_m[indr], wr.mat_true_nb[indr])
                    st_used = stairs if cons == "wvc" else "none"
                    refg.append({"phone route": phone, "imu": imu_label, "method": label,
                                 "barometer used": bool(st_used == "baro" and wr.baro_t_s.size > 0),
                                 "phone rows use barometer": bool(st_used == "baro" and walk.baro_t_s.size > 0),
                                 "seed": s, **error_stats(err)["rms"]})
            gap = np.diff(walk.gcp_t_s)
            stats.append({"phone": phone, "seed": s, "duration_s": walk.t_s[-1] - walk.t_s[0],
                          "indoor_s": walk.t_s[-1] - walk.t_indoor_s, "imu_rate_hz": 1.0 / np.mean(np.diff(walk.t_s)),
                          "imu_rate_min_hz": 1.0 / np.max(np.diff(walk.t_s)),
                          "imu_rate_max_hz": 1.0 / np.min(np.diff(walk.t_s)),
                          "gnss_fixes": walk.gnss_t_s.size, "gcp_passages": walk.gcp_t_s.size,
                          "gcp_interval_mean_s": float(gap.mean()) if gap.size else np.nan,
                          "walker_speed_mps": walk.params.get("speed_mps", np.nan),
                          "walker_cadence_hz": walk.params.get("cadence_hz", np.nan),
                          "walker_step_scale_c": walk.params["user_c"],
                          "stair_epochs": int(walk.stairs_true.sum()),
                          "gcp_delay_mean_s": _gcp_delay(walk)})
            if s == seed * n_seeds:
                traj.append(_trajectory(phone, walk, sol, ind))
    per_seed = pd.DataFrame(rows)
    errors = (per_seed.groupby(["phone", "method", "stat"], sort=False)[list(AXES)].mean().reset_index())
    errors.insert(3, "n_seeds", n_seeds)
    comp = []
    for phone, *_ in PHONES:
        for method in METHODS:
            sel = errors[(errors.phone == phone) & (errors.method == method) & (errors.stat == "rms")].iloc[0]
            table = "Table 4" if phone == "Samsung" else "Table 6"
            for ax in ("N", "E", "H"):
                comp.append(paper_ref(LIAO_2016, table, f"{phone} {method}: RMS {ax} error",
                                      paper_value(phone, method, "rms", ax), sel[ax], unit="m",
                                      note=f"simulated walk, mean of {n_seeds} seed(s)"))
            table = "Table 5" if phone == "Samsung" else "Table 7"
            comp.append(paper_ref(LIAO_2016, table, f"{phone} {method}: RMS heading error",
                                  paper_value(phone, method, "rms", "Heading"), sel["Heading"], unit="deg",
                                  note="paper's heading includes phone/reference time-sync errors"))
    out = {
        "errors": errors,
        "errors_per_seed": per_seed,
        "position_side_by_side": side_by_side(errors, ("N", "E", "H")),
        "attitude_side_by_side": side_by_side(errors, ("Roll", "Pitch", "Heading")),
        "comparison": pd.DataFrame(comp),
        "walk_stats": pd.DataFrame(stats),
        "trajectory": pd.concat(traj, ignore_index=True),
        "gcp_grade": (pd.DataFrame(grade).groupby(["phone", "control points", "gcp_sd_m", "method"], sort=False)
                      [["n_fixes", "fix_horizontal_error_mean_m", *AXES]].mean().reset_index()),
        "heading_time_sync": (pd.DataFrame(sync).groupby(["phone", "method", "lag_s"], sort=False)
                              [["heading_rms_deg", "heading_max_deg"]].mean().reset_index()),
        "reference_grade": (pd.DataFrame(refg).groupby(["phone route", "imu", "method", "barometer used",
                                                         "phone rows use barometer"], sort=False)[list(AXES)]
                            .mean().reset_index() if refg else pd.DataFrame()),
        "sensor_grade": (pd.DataFrame(sens_rows).groupby(["phone", "sensor", "method"], sort=False)[list(AXES)]
                         .mean().reset_index()),
        "stair_handling": _stair_table(pd.DataFrame(stair_rows)),
        "sensor_sensitivity": sensor_sensitivity(range(seed * n_seeds, seed * n_seeds + n_sens), gait, stairs,
                                                 stair_action, reuse=reuse, full_grid=not fast),
        "gait_sensitivity": gait_sensitivity(range(seed * n_seeds, seed * n_seeds + n_sens), stairs, stair_action,
                                             reuse=reuse if gait == "published" else None),
        "readings": readings(stairs, stair_action),
        "measures": _measures(errors, pd.DataFrame(sync)),
    }
    out["error_budget"] = error_budget(out)
    return out


def error_budget(tables: dict, phones=("Samsung", "iPhone")) -> pd.DataFrame:
    """Which error source carries the distance to the paper's GCP / smoothing rows (Tables 4 and 6)?

    Assembled from the experiment's own tables: for each source, the RMS errors of Filtering + WVC/ZUPT + GCP
    and of Smoothing + WVC/ZUPT + GCP with that source changed (idealised or swept) beside the same seeds'
    default (``baseline_*``), the change of the horizontal RMS (``delta_horizontal_m``, negative: the source
    costs that much) and the paper's values. Rows from ``sensor_sensitivity`` and ``gait_sensitivity`` have the
    filter only (those sweeps do not smooth).
    """
    rows = []
    gcp = tables["gcp_grade"].set_index(["phone", "control points", "method"])
    sg = tables["sensor_grade"].set_index(["phone", "sensor", "method"])
    st = tables["stair_handling"]
    ss = tables["sensor_sensitivity"]
    gs = tables["gait_sensitivity"].set_index(["phone", "walker"])

    def add(phone, source, method, new, base, table):
        h, hb = float(np.hypot(new["N"], new["E"])), float(np.hypot(base["N"], base["E"]))
        rows.append({"phone": phone, "source": source, "method": method, "table": table,
                     **{ax: float(new[ax]) for ax in ("N", "E", "H")}, "horizontal": h,
                     **{f"baseline_{ax}": float(base[ax]) for ax in ("N", "E", "H")}, "baseline_horizontal": hb,
                     "delta_horizontal_m": h - hb,
                     **{f"paper_{ax}": paper_value(phone, method, "rms", ax) for ax in ("N", "E", "H")}})

    for phone in phones:
        for method in METHODS[2:]:
            for label in gcp.index.get_level_values(1).unique():
                if label != GCP_RSSI_LABEL and (phone, label, method) in gcp.index:
                    add(phone, f"control points: {label}", method, gcp.loc[(phone, label, method)],
                        gcp.loc[(phone, GCP_RSSI_LABEL, method)], "gcp_grade")
            ideal = (phone, "ideal sensor timing", method)
            real = (phone, "realistic phone (jitter, point samples, bias instability)", method)
            if ideal in sg.index:
                add(phone, "sensor timing ideal (exact tags, interval means, no bias instability)", method,
                    sg.loc[ideal], sg.loc[real], "sensor_grade")
            sel = st[(st.phone == phone) & (st.method == method) & (st.stat == "rms")]
            if len(sel):
                r = sel.iloc[0]
                for opt in ("baro", "truth"):
                    add(phone, f"stairs: {opt} (WVC off on stairs)", method,
                        {ax: r[f"{ax} ({opt})"] for ax in ("N", "E", "H")},
                        {ax: r[f"{ax} (none)"] for ax in ("N", "E", "H")}, "stair_handling")
        method = METHODS[2]
        p = ss[ss.phone == phone]
        default = p[(p.noise_factor == _PROFILE_NOISE_FACTOR) & (p.bias_instability_factor == 1.0)
                    & np.isclose(p.time_jitter_sd_ms, 1e3 * ins_walk.PROFILES[
                        dict((ph, pr) for ph, _, pr in PHONES)[phone]].time_jitter_sd_s)]
        if len(default):
            b = default.iloc[0]
            for r in p.itertuples():
                if r.Index == default.index[0]:
                    continue
                add(phone, f"sensor: noise x{r.noise_factor:g}, bias instability x{r.bias_instability_factor:g}, "
                    f"time tags {r.time_jitter_sd_ms:g} ms", method, r._asdict(), b, "sensor_sensitivity")
        if (phone, "published") in gs.index:
            for walker in gs.loc[phone].index:
                if walker != "published":
                    add(phone, f"walker: {walker}", method, gs.loc[(phone, walker)], gs.loc[(phone, "published")],
                        "gait_sensitivity")
    return pd.DataFrame(rows)


def _measures(errors: pd.DataFrame, sync: pd.DataFrame) -> pd.DataFrame:
    """Named scalars for the claims ledger (ilocalg.papers.liao): max and RMS error per phone, method and axis
    (mean over seeds), and the heading errors against a reference read ``lag_s`` late."""
    rows = [{"quantity": f"{r['stat']} {ax} error", "item": f"{r['phone']} {r['method']}", "value": float(r[ax]),
             "unit": "m" if ax in ("N", "E", "H") else "deg"}
            for _, r in errors[errors["stat"].isin(["max", "rms"])].iterrows() for ax in AXES]
    for (phone, method, lag), g in (sync.groupby(["phone", "method", "lag_s"], sort=False) if len(sync) else ()):
        for stat in ("max", "rms"):
            rows.append({"quantity": f"{stat} heading error, reference lag", "item": f"{phone} {method} lag={lag:g}s",
                         "value": float(g[f"heading_{stat}_deg"].mean()), "unit": "deg"})
    return pd.DataFrame(rows)


def _stair_table(df: pd.DataFrame) -> pd.DataFrame:
    """Mean over seeds, one row per phone, method and statistic; N, E, H and heading per stair option."""
    m = df.groupby(["phone", "method", "stat", "stairs"], sort=False)[["N", "E", "H", "Heading"]].mean()
    out = m.unstack("stairs")
    out.columns = [f"{ax} ({opt})" for ax, opt in out.columns]
    order = [f"{ax} ({v[0]})" for ax in ("N", "E", "H", "Heading") for v in STAIR_VARIANTS]
    return out[order].reset_index()


def _gcp_delay(walk) -> float:
    """Mean time from the closest approach to a control point to its fix (s), on the true clock."""
    k = np.searchsorted(walk.t_s, walk.gcp_t_s)
    d = []
    for kk, j in zip(k, walk.gcp_id, strict=True):
        g = ins_walk.GCP_XYZ_M[j]
        lo = max(0, kk - 60)
        dist = np.linalg.norm(walk.pos_true_n_m[lo:kk + 1] - g, axis=1)
        d.append(walk.t_true_s[kk] - walk.t_true_s[lo + int(np.argmin(dist))])
    return float(np.mean(d)) if d else np.nan


def _trajectory(phone, walk, sol, ind):
    frames = []
    eul = np.rad2deg(dcm_to_euler(walk.mat_true_nb))
    frames.append(pd.DataFrame({"phone": phone, "method": "Truth", "t_s": walk.t_s, "indoor": ind,
                                "E": walk.pos_true_n_m[:, 0], "N": walk.pos_true_n_m[:, 1],
                                "H": walk.pos_true_n_m[:, 2], "heading_deg": eul[:, 2]}))
    for method, (pos, mat) in sol.items():
        e = np.rad2deg(dcm_to_euler(mat))
        frames.append(pd.DataFrame({"phone": phone, "method": method, "t_s": walk.t_s, "indoor": ind,
                                    "E": pos[:, 0], "N": pos[:, 1], "H": pos[:, 2], "heading_deg": e[:, 2]}))
    return pd.concat(frames, ignore_index=True)
