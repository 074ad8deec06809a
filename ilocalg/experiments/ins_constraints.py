"""Smartphone INS with constraints and control points (Liao et al. 2016, sec. 4.1, Tables 4-7, Figs 7-12).

For each phone (Samsung S5 on the Fig 5 route, iPhone 5S on the Fig 6 route) and seed: simulate the
walk, run Filtering + NHC/ZUPT, Filtering + WVC/ZUPT, Filtering + WVC/ZUPT + GCP and the RTS
Smoothing + WVC/ZUPT + GCP, and score the indoor part (the paper removes the GNSS-aided start).
Statistics are per run, then averaged over seeds.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd

from ilocalg.ins import error_stats, eskf_rts_smooth, heading_error_with_lag_deg
from ilocalg.ins.chain import (
    METHODS,
    indoor_errors,
    run_methods,
    run_methods_many,
    smooth_gcp,
    stats_rows,
    trajectory_frame,
)
from ilocalg.ins.eskf import run_eskf, run_eskf_batch, same_run
from ilocalg.ins.evaluate import AXES
from ilocalg.ins.paper_values import paper_value, side_by_side
from ilocalg.ins.pipeline import run_walks, stair_mask, walk_filter_args
from ilocalg.ins.smoother import rts_gains_shared
from ilocalg.papers.comparison_liao import constraints_rows
from ilocalg.papers.readings_liao import (
    BIAS_INSTABILITY_FACTORS,
    GCP_RSSI_SD_SWEEP_DB,
    NOISE_FACTORS,
    TIME_JITTERS_S,
    constraints_readings,
)
from ilocalg.sim import ins_walk
from ilocalg.sim.ins_walk import PHONES

__all__ = ["error_budget", "GCP_RSSI_LABEL", "GCP_RSSI_SD_SWEEP_DB", "METHODS", "STAIR_OPTIONS", "STAIR_VARIANTS",
           "BIAS_INSTABILITY_FACTORS", "TIME_JITTERS_S", "NOISE_FACTORS",
           "GAIT_VARIANTS", "run_methods", "run_phone", "readings", "sensor_sensitivity", "gait_sensitivity", "run"]

_IDEAL_50HZ = ins_walk.PhoneProfile("error-free", (4, 4), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


#: Stair handling of the WVC compared in the ``stair_handling`` table (:func:`ilocalg.ins.pipeline.stair_mask`).
STAIR_OPTIONS = ("none", "baro", "truth")
#: Columns of the ``stair_handling`` table: (label, stair source, action on stairs).
STAIR_VARIANTS = (("none", "none", "drop"), ("baro", "baro", "drop"), ("baro, downweight", "baro", "downweight"),
                  ("truth", "truth", "drop"))


#: Label of the default control-point model in the gcp_grade table.
GCP_RSSI_LABEL = "Bluetooth RSSI (100 ms advertising, 1 s ranging, immediate zone; default)"
_PROFILE_NOISE_FACTOR = ins_walk.PHONE_NOISE_FACTOR


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


def run_phone(route: str, profile: str, seed: int, stairs: str = "none", stair_action: str = "drop", **sim_kw):
    """Simulate one walk and run the four methods: ``(walk, {method: (pos, mat)}, gcp_filter_result)``."""
    walk = ins_walk.simulate(route, profile, seed=seed, **sim_kw)
    out, r = run_methods(walk, stairs, stair_action)
    return walk, out, r


def readings(stairs: str, stair_action: str, noise_factor: float = ins_walk.PHONE_NOISE_FACTOR,
             bias_instability_factor: float = 1.0, time_jitter_sd_s: float = ins_walk.PHONE_TIME_JITTER_SD_S,
             rssi_sd_db: float = ins_walk.BLE_RSSI_SD_DB,
             speed_mean_mps: float = ins_walk.LEVEL_SPEED_MEAN_MPS) -> pd.DataFrame:
    """One row per modelling choice (declared in :mod:`ilocalg.papers.readings_liao`) for a run's choices."""
    return constraints_readings(stairs, stair_action, noise_factor, bias_instability_factor, time_jitter_sd_s,
                                rssi_sd_db, speed_mean_mps)


def _filter_rms_many(jobs, stairs, stair_action):
    """Filtering + WVC/ZUPT + GCP on several walks, scored: ``jobs`` holds ``(walk, filter result or None)`` per
    walk (a result when already run); the others run as one batch (:func:`ilocalg.ins.pipeline.run_walks`, the
    same numbers as one by one). Returns the RMS N, E, H and heading on each walk's indoor part."""
    new = iter(run_walks([w for w, r in jobs if r is None], "wvc", use_gcp=True, stairs=stairs,
                         stair_action=stair_action, keep_covariance=False))
    out = []
    for walk, r in jobs:
        r = next(new) if r is None else r
        rms = error_stats(indoor_errors(walk, r.pos_n_m, r.mat_nb))["rms"]
        out.append({ax: rms[ax] for ax in ("N", "E", "H", "Heading")})
    return out


def sensor_sensitivity(seeds, gait: str = "published", stairs: str = "none", stair_action: str = "drop",
                       bias_instability_factors=BIAS_INSTABILITY_FACTORS, time_jitters_s=TIME_JITTERS_S,
                       reuse=None, full_grid: bool = True, noise_factors=NOISE_FACTORS,
                       truth_cache: ins_walk.TruthCache | None = None) -> pd.DataFrame:
    """RMS errors of Filtering + WVC/ZUPT + GCP over the grid of bias-instability factors and time-tag jitters.

    Every cell simulates the same walks (same seeds; the swept draws are paired, see
    :meth:`ilocalg.sim.ins_walk.PhoneProfile.swept`) and scores the indoor part. ``reuse`` maps
    ``(phone, seed)`` to ``(walk, filter result)`` of the default profile (any object with its ``pos_n_m`` and
    ``mat_nb``), reused for its own cell.
    ``full_grid=False`` sweeps one value at a time (each factor at the profile's jitter, each jitter at x1).
    ``noise_factors`` (factors on the datasheet white-noise densities; the profiles' is 3) are swept one at a
    time, at the default bias instability and jitter. ``truth_cache`` (:class:`ilocalg.sim.ins_walk.TruthCache`,
    of at least ``len(seeds)`` entries to help): the cells walk the same truths, each simulated once.

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
        jobs, keys = [], []
        for c, k, jit in cells:
            prof = ins_walk.phone_profile(profile, c, k, jit)
            for s in seeds:
                reused = reuse.get((phone, s)) if reuse and prof == base else None
                jobs.append(reused or (ins_walk.simulate(route, prof, seed=s, gait=gait, truth_cache=truth_cache),
                                       None))
                keys.append((c, k, jit))
        for (c, k, jit), (walk, _), rms in zip(keys, jobs, _filter_rms_many(jobs, stairs, stair_action), strict=True):
            rows.append({"phone": phone, "noise_factor": float(c), "bias_instability_factor": float(k),
                         "time_jitter_sd_ms": 1e3 * float(jit),
                         "tag_error_sd_ms": 1e3 * float(np.std(walk.t_s - walk.t_true_s)), **rms})
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
        jobs, labels = [], []
        for label, gait, kw in variants:
            for s in seeds:
                reused = reuse.get((phone, s)) if reuse and gait == "published" and not kw else None
                jobs.append(reused or (ins_walk.simulate(route, profile, seed=s, gait=gait, gait_kw=kw), None))
                labels.append(label)
        for label, (walk, _), rms in zip(labels, jobs, _filter_rms_many(jobs, stairs, stair_action), strict=True):
            rows.append({"phone": phone, "walker": label, "speed_mps": walk.params.get("speed_mps", np.nan),
                         "cadence_hz": walk.params.get("cadence_hz", np.nan), **rms})
    out = (pd.DataFrame(rows).groupby(["phone", "walker"], sort=False)
           [["speed_mps", "cadence_hz", "N", "E", "H", "Heading"]].mean().reset_index())
    out.insert(4, "n_seeds", len(seeds))
    return out


def _gcp_filter_args(w, rgcp, stairs, stair_action) -> dict:
    """The filter of :func:`_filter_and_smoothing` on the walk ``w`` (Filtering + WVC/ZUPT + GCP), as
    :func:`ilocalg.ins.eskf.run_eskf` keywords: a walk with other control points has the default walk's IMU log,
    so the filters agree up to the first difference (``prefix``)."""
    return {**walk_filter_args(w, "wvc", use_gcp=True, stairs=stairs, stair_action=stair_action), "prefix": (rgcp,)}


def _filter_and_smoothing(w, walk, sol, rgcp, stairs, stair_action, r=None, gains=None):
    """``((METHODS[2], (pos, mat)), (METHODS[3], (pos, mat)))`` of Filtering + WVC/ZUPT + GCP and its smoothing
    on the walk ``w``: those of the default run (``sol``, ``rgcp``) when ``w`` is its walk ``walk``. ``r``: the
    filter result on ``w`` when already run (:func:`_gcp_filter_args`); ``gains``: the smoother gains of ``rgcp``,
    reused where ``r`` has its covariances (:func:`ilocalg.ins.smoother.rts_gains_shared`, the same numbers)."""
    if w is walk:
        return (METHODS[2], (rgcp.pos_n_m, rgcp.mat_nb)), (METHODS[3], sol[METHODS[3]])
    if r is None:
        r = run_eskf(**_gcp_filter_args(w, rgcp, stairs, stair_action))
    if same_run(rgcp, r):  # the same fixes as the default walk's (e.g. little RSSI scatter): the same smoothing
        return (METHODS[2], (r.pos_n_m, r.mat_nb)), (METHODS[3], sol[METHODS[3]])
    sm = eskf_rts_smooth(r, with_cov=False, gains=None if gains is None else rts_gains_shared(r, rgcp, gains))
    return (METHODS[2], (r.pos_n_m, r.mat_nb)), (METHODS[3], (sm.pos_n_m, sm.mat_nb))


def _side_rows(phone, route, profile, s, walk, sol, rgcp, ind, stairs, stair_action, sim_kw, fast,
               reference_grade, gains=None):
    """One seed's rows of the side studies (stair handling, control-point grade, sensor timing, reference
    IMUs) on the walk ``walk`` of the default run (``sol``: its four methods, ``rgcp``: its GCP filter result,
    ``gains``: that filter's smoother gains, reused by the smoothings of filters that share its beginning):
    ``(stair_rows, grade, sens_rows, refg)``. Every other walk is simulated here from the same seed ``s``."""
    stair_rows, grade, sens_rows, refg = [], [], [], []

    def handling(opt, action):  # what the WVC does: no stair mask (e.g. "baro" on a phone without one) = "none"
        return "none" if stair_mask(walk, opt) is None else (opt, action)

    for label, opt, action in STAIR_VARIANTS:
        same = handling(opt, action) == handling(stairs, stair_action)
        sol_o = sol if same else run_methods(walk, opt, action, nhc=sol[METHODS[0]], prefix=(rgcp,),
                                             gains_of=None if gains is None else (rgcp, gains))[0]
        for method, (pos, mat) in sol_o.items():
            st = error_stats(indoor_errors(walk, pos, mat, ind))
            stair_rows += [{"phone": phone, "stairs": label, "method": method, "seed": s, "stat": k,
                            **st[k]} for k in ("max", "rms")]
    gcp_variants = [(GCP_RSSI_LABEL, walk)]
    for sd_db in GCP_RSSI_SD_SWEEP_DB:
        gcp_variants.append((f"Bluetooth RSSI, packet scatter {sd_db:g} dB",
                             ins_walk.simulate(route, profile, seed=s, **{**sim_kw, "rssi_sd_db": sd_db})))
    gcp_variants += [("Bluetooth (surveyed point, delay, offset)",
                      ins_walk.simulate(route, profile, seed=s, gcp_mode="ble", **sim_kw)),
                     ("ideal (true position + 5 cm)",
                      ins_walk.simulate(route, profile, seed=s, gcp_mode="ideal", **sim_kw))]
    ideal = ins_walk.simulate(route, profile.ideal_timing(), seed=s, **sim_kw)
    ref_imus = [("MIDG-II grade (paper Table 3)", "midg2")]  # reference IMUs: exact timing
    if not fast:
        ref_imus.append(("error-free, 50 Hz", _IDEAL_50HZ))
    ref_walks = [(imu_label, ins_walk.simulate(route, prof, seed=s, **sim_kw))
                 for imu_label, prof in (ref_imus if reference_grade else ())]
    ref_methods = (("Smoothing + NHC/ZUPT (as the paper's reference)", "nhc", False), (METHODS[3], "wvc", True))
    # every filter of these side studies advanced together (the same numbers as one by one)
    other = [w2 for _, w2 in gcp_variants if w2 is not walk] + [ideal]
    jobs = [_gcp_filter_args(w2, rgcp, stairs, stair_action) for w2 in other]
    jobs += [walk_filter_args(wr, cons, use_gcp=gcp, stairs=stairs if cons == "wvc" else "none",
                              stair_action=stair_action) for _, wr in ref_walks for _, cons, gcp in ref_methods]
    filters = run_eskf_batch(jobs)
    done = {id(w2): r for w2, r in zip(other, filters, strict=False)}
    for gname, w2 in gcp_variants:
        for method, (pos2, mat2) in _filter_and_smoothing(w2, walk, sol, rgcp, stairs, stair_action,
                                                          done.get(id(w2)), gains):
            err = indoor_errors(walk, pos2, mat2, ind)
            k_fix = np.minimum(np.searchsorted(w2.t_s, w2.gcp_t_s), w2.t_s.size - 1)
            fix_err = np.linalg.norm(w2.pos_true_n_m[k_fix, :2] - w2.gcp_pos_n_m[:, :2], axis=1)
            grade.append({"phone": phone, "control points": gname, "gcp_sd_m": w2.gcp_sd_m,
                          "n_fixes": int(w2.gcp_t_s.size),
                          "fix_horizontal_error_mean_m": float(fix_err.mean()) if fix_err.size else np.nan,
                          "method": method, "seed": s, **error_stats(err)["rms"]})
    indi = ideal.t_s >= ideal.t_indoor_s
    for label, w3 in (("realistic phone (jitter, point samples, bias instability)", walk),
                      ("ideal sensor timing", ideal)):
        i3 = ind if w3 is walk else indi
        for method, (pos3, mat3) in _filter_and_smoothing(w3, walk, sol, rgcp, stairs, stair_action,
                                                          done.get(id(w3))):
            err = indoor_errors(w3, pos3, mat3, i3)
            sens_rows.append({"phone": phone, "sensor": label, "method": method, "seed": s,
                              **error_stats(err)["rms"]})
    ref_filters = iter(filters[len(other):])
    for imu_label, wr in ref_walks:
        indr = wr.t_s >= wr.t_indoor_s
        for label, cons, _ in ref_methods:
            sm = eskf_rts_smooth(next(ref_filters), with_cov=False)
            err = indoor_errors(wr, sm.pos_n_m, sm.mat_nb, indr)
            st_used = stairs if cons == "wvc" else "none"
            refg.append({"phone route": phone, "imu": imu_label, "method": label,
                         "barometer used": bool(st_used == "baro" and wr.baro_t_s.size > 0),
                         "phone rows use barometer": bool(st_used == "baro" and walk.baro_t_s.size > 0),
                         "seed": s, **error_stats(err)["rms"]})
    return stair_rows, grade, sens_rows, refg


def run(seed: int = 0, fast: bool = False, n_seeds: int | None = None, time_lags_s=(0.0, 0.05, 0.1, 0.2),
        reference_grade: bool = True, stairs: str = "none", stair_action: str = "drop",
        gait: str = "published", sensitivity_seeds: int | None = None,
        noise_factor: float = ins_walk.PHONE_NOISE_FACTOR, bias_instability_factor: float = 1.0,
        time_jitter_sd_s: float = ins_walk.PHONE_TIME_JITTER_SD_S, rssi_sd_db: float = ins_walk.BLE_RSSI_SD_DB,
        speed_mean_mps: float = ins_walk.LEVEL_SPEED_MEAN_MPS, side_studies: bool = True) -> dict[str, pd.DataFrame]:
    """Tables 4-7 reproduced on simulated walks.

    ``noise_factor``, ``bias_instability_factor``, ``time_jitter_sd_s`` (the phones' white noise over the
    datasheet densities, bias-instability factor, time-tag error sd), ``rssi_sd_db`` (the control-point
    beacons' per-packet RSSI scatter) and ``speed_mean_mps`` (the walkers' mean level speed, published gait
    only) are the values the paper does not fix (readings table); they set the walks of every table but the
    sensitivity sweeps, which vary them one at a time about the defaults.

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

    ``side_studies=False`` leaves out the side studies (``gcp_grade``, ``reference_grade``, ``sensor_grade``,
    ``stair_handling``, ``sensor_sensitivity``, ``gait_sensitivity``) and the ``error_budget`` built from them:
    each re-simulates walks of its own from the same seeds, so the tables returned are the same either way.
    The seed sweep and the claims' robustness samples read none of them
    (:data:`ilocalg.workflow.manifest.SWEEP_KWARGS`).
    """
    if stairs not in STAIR_OPTIONS:
        raise ValueError(f"stairs must be one of {STAIR_OPTIONS}, got {stairs!r}")
    n_seeds = n_seeds or (1 if fast else 6)
    n_sens = min(n_seeds, sensitivity_seeds or (1 if fast else 3))
    profiles = {pr: ins_walk.phone_profile(pr, noise_factor, bias_instability_factor, time_jitter_sd_s)
                for _, _, pr in PHONES}
    sim_kw = {"gait": gait, "rssi_sd_db": rssi_sd_db}
    if speed_mean_mps != ins_walk.LEVEL_SPEED_MEAN_MPS:
        sim_kw["gait_kw"] = {"speed_mean_mps": speed_mean_mps}
    # every walk of one walker (seed) shares its truth: the side studies' other phones, control points and
    # sensor errors, and the sensitivity cells (their seeds, the first n_sens, still held after the main loop);
    # every seed of a phone is simulated before its side studies run (the filters of the seeds run together)
    cache = ins_walk.TruthCache(maxsize=max(2, n_sens, n_seeds))
    # the sensitivity sweeps reuse the default walks only when the run's are the default ones
    at_default = (all(profiles[pr] == ins_walk.PROFILES[pr] for pr in profiles) and "gait_kw" not in sim_kw
                  and rssi_sd_db == ins_walk.BLE_RSSI_SD_DB)
    reuse = {}
    rows, stats, traj, grade, sync, refg, stair_rows, sens_rows = [], [], [], [], [], [], [], []
    for phone, route, name in PHONES:
        profile = profiles[name]
        # Disjoint simulation seeds per experiment seed: seed k uses k*n_seeds .. (k+1)*n_seeds - 1, so runs
        # with different seeds are independent (a sweep over seeds gives honest confidence intervals).
        seeds = range(seed * n_seeds, (seed + 1) * n_seeds)
        walks = [ins_walk.simulate(route, profile, seed=s, truth_cache=cache, **sim_kw) for s in seeds]
        # every seed's four methods, each filter advanced together with the other seeds' (the same numbers)
        for s, walk, (sol, rgcp) in zip(seeds, walks, run_methods_many(walks, stairs, stair_action,
                                                                         smooth=not side_studies), strict=True):
            # with the side studies, each seed's smoothing here: its gains serve the side studies' smoothings
            # (rts_gains_shared), one seed's at a time
            gains = smooth_gcp(sol, rgcp) if side_studies else None
            if at_default and s < seed * n_seeds + n_sens:
                # its solution only: the filter's covariance histories (shared by the seeds' batch) are not kept
                reuse[(phone, s)] = (walk, SimpleNamespace(pos_n_m=rgcp.pos_n_m, mat_nb=rgcp.mat_nb))
            ind = walk.t_s >= walk.t_indoor_s
            for method, (pos, mat) in sol.items():
                err = indoor_errors(walk, pos, mat, ind)
                rows += stats_rows(phone, method, s, err)
            if side_studies:
                for acc, part in zip((stair_rows, grade, sens_rows, refg),
                                     _side_rows(phone, route, profile, s, walk, sol, rgcp, ind, stairs,
                                                stair_action, {**sim_kw, "truth_cache": cache}, fast,
                                                reference_grade, gains), strict=True):
                    acc += part
            for method in METHODS[2:]:
                pos, mat = sol[method]
                for lag in time_lags_s:
                    # on the true sampling clock (the phone's jittered tags may fall outside the reference)
                    e = heading_error_with_lag_deg(walk.t_true_s[ind], mat[ind], walk.t_ref_s, walk.mat_ref_nb, lag)
                    sync.append({"phone": phone, "method": method, "seed": s, "lag_s": lag,
                                 "heading_rms_deg": float(np.sqrt(np.mean(e**2))),
                                 "heading_max_deg": float(np.max(np.abs(e)))})
            stats.append({"phone": phone, "seed": s, **ins_walk.walk_summary(walk)})
            if s == seed * n_seeds:
                traj.append(trajectory_frame(phone, walk, sol, ind))
        # the last seed's filter is a view into its batch's covariance histories: not kept past its phone
        del rgcp, gains
    per_seed = pd.DataFrame(rows)
    errors = (per_seed.groupby(["phone", "method", "stat"], sort=False)[list(AXES)].mean().reset_index())
    errors.insert(3, "n_seeds", n_seeds)
    comp = constraints_rows(errors, [ph for ph, *_ in PHONES], METHODS, n_seeds)
    out = {
        "errors": errors,
        "errors_per_seed": per_seed,
        "position_side_by_side": side_by_side(errors, ("N", "E", "H")),
        "attitude_side_by_side": side_by_side(errors, ("Roll", "Pitch", "Heading")),
        "comparison": pd.DataFrame(comp),
        "walk_stats": pd.DataFrame(stats),
        "trajectory": pd.concat(traj, ignore_index=True),
    }
    if side_studies:
        out["gcp_grade"] = (pd.DataFrame(grade).groupby(["phone", "control points", "gcp_sd_m", "method"],
                                                        sort=False)
                            [["n_fixes", "fix_horizontal_error_mean_m", *AXES]].mean().reset_index())
    out["heading_time_sync"] = (pd.DataFrame(sync).groupby(["phone", "method", "lag_s"], sort=False)
                                [["heading_rms_deg", "heading_max_deg"]].mean().reset_index())
    if side_studies:
        out.update({
            "reference_grade": (pd.DataFrame(refg).groupby(["phone route", "imu", "method", "barometer used",
                                                             "phone rows use barometer"], sort=False)[list(AXES)]
                                .mean().reset_index() if refg else pd.DataFrame()),
            "sensor_grade": (pd.DataFrame(sens_rows).groupby(["phone", "sensor", "method"], sort=False)
                             [list(AXES)].mean().reset_index()),
            "stair_handling": _stair_table(pd.DataFrame(stair_rows)),
            "sensor_sensitivity": sensor_sensitivity(range(seed * n_seeds, seed * n_seeds + n_sens), gait, stairs,
                                                     stair_action, reuse=reuse, full_grid=not fast,
                                                     truth_cache=cache),
            "gait_sensitivity": gait_sensitivity(range(seed * n_seeds, seed * n_seeds + n_sens), stairs,
                                                 stair_action, reuse=reuse if gait == "published" else None),
        })
    out["readings"] = readings(stairs, stair_action, noise_factor, bias_instability_factor, time_jitter_sd_s,
                               rssi_sd_db, speed_mean_mps)
    out["measures"] = _measures(errors, pd.DataFrame(sync))
    if side_studies:
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
