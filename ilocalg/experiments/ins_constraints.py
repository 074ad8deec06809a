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
from ilocalg.papers import paper_ref
from ilocalg.sim import ins_walk
from ilocalg.sim.ins_walk import PHONES

__all__ = ["METHODS", "run_phone", "run"]

METHODS = ("Filtering + NHC/ZUPT", "Filtering + WVC/ZUPT", "Filtering + WVC/ZUPT + GCP",
           "Smoothing + WVC/ZUPT + GCP")
_IDEAL_50HZ = ins_walk.PhoneProfile("error-free", (4, 4), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def run_phone(route: str, profile: str, seed: int):
    """Simulate one walk and run the four methods: ``(walk, {method: (pos, mat)}, gcp_filter_result)``."""
    walk = ins_walk.simulate(route, profile, seed=seed)
    out = {}
    r = run_walk(walk, "nhc", use_gcp=False)
    out[METHODS[0]] = (r.pos_n_m, r.mat_nb)
    r = run_walk(walk, "wvc", use_gcp=False)
    out[METHODS[1]] = (r.pos_n_m, r.mat_nb)
    r = run_walk(walk, "wvc", use_gcp=True)
    out[METHODS[2]] = (r.pos_n_m, r.mat_nb)
    s = eskf_rts_smooth(r, with_cov=False)
    out[METHODS[3]] = (s.pos_n_m, s.mat_nb)
    return walk, out, r


def _stats_rows(phone, method, seed, err):
    st = error_stats(err)
    return [{"phone": phone, "method": method, "seed": seed, "stat": k, **st[k]} for k in ("max", "rms", "std")]


def run(seed: int = 0, fast: bool = False, n_seeds: int | None = None, bluetooth_gcp_sd_m: float = 1.5,
        time_lags_s=(0.0, 0.05, 0.1, 0.2), reference_grade: bool = True) -> dict[str, pd.DataFrame]:
    """Tables 4-7 reproduced on simulated walks.

    Returns
    -------
    dict with ``errors`` (phone, method, stat, N, E, H [m], Roll, Pitch, Heading [deg], mean over seeds),
    ``errors_per_seed``, ``position_side_by_side`` and ``attitude_side_by_side`` (the paper's layout,
    paper value beside the reproduced one), ``comparison`` (paper_ref rows: RMS N/E/H and heading),
    ``walk_stats`` (the simulated inputs: duration, IMU rate, control-point passages), ``trajectory``
    (first seed: per-epoch E, N, H of the truth and of every method), ``gcp_grade`` (RMS errors with
    cm-level total-station control points vs m-level Bluetooth ones of sd ``bluetooth_gcp_sd_m``) and
    ``heading_time_sync`` (heading RMS / max when the reference is read ``time_lags_s`` off) and
    ``reference_grade`` (the same walks measured by a MIDG-II-grade IMU, paper Table 3, processed like the
    paper's reference trajectory - NHC/ZUPT and smoothing - and with WVC/ZUPT/GCP and smoothing; not in
    fast mode also by an error-free IMU).
    """
    n_seeds = n_seeds or (1 if fast else 6)
    rows, stats, traj, grade, sync, refg = [], [], [], [], [], []
    for phone, route, profile in PHONES:
        # Disjoint simulation seeds per experiment seed: seed k uses k*n_seeds .. (k+1)*n_seeds - 1, so runs
        # with different seeds are independent (a sweep over seeds gives honest confidence intervals).
        for s in range(seed * n_seeds, (seed + 1) * n_seeds):
            walk, sol, rgcp = run_phone(route, profile, s)
            ind = walk.t_s >= walk.t_indoor_s
            for method, (pos, mat) in sol.items():
                err = nav_errors(pos[ind], mat[ind], walk.pos_true_n_m[ind], walk.mat_true_nb[ind])
                rows += _stats_rows(phone, method, s, err)
            for gname, w2 in (("total station (cm)", walk),
                              ("Bluetooth (m)", ins_walk.simulate(route, profile, seed=s,
                                                                  gcp_sd_m=bluetooth_gcp_sd_m))):
                r2 = rgcp if w2 is walk else run_walk(w2, "wvc", use_gcp=True)
                for method, sol2 in ((METHODS[2], r2), (METHODS[3], eskf_rts_smooth(r2, with_cov=False))):
                    err = nav_errors(sol2.pos_n_m[ind], sol2.mat_nb[ind], walk.pos_true_n_m[ind],
                                     walk.mat_true_nb[ind])
                    grade.append({"phone": phone, "control points": gname, "gcp_sd_m": w2.gcp_sd_m,
                                  "method": method, "seed": s, **error_stats(err)["rms"]})
            for method in METHODS[2:]:
                pos, mat = sol[method]
                for lag in time_lags_s:
                    e = heading_error_with_lag_deg(walk.t_s[ind], mat[ind], walk.t_ref_s, walk.mat_ref_nb, lag)
                    sync.append({"phone": phone, "method": method, "seed": s, "lag_s": lag,
                                 "heading_rms_deg": float(np.sqrt(np.mean(e**2))),
                                 "heading_max_deg": float(np.max(np.abs(e)))})
            ref_imus = [("MIDG-II grade (paper Table 3)", "midg2")]
            if not fast:
                ref_imus.append(("error-free, 50 Hz", _IDEAL_50HZ))
            for imu_label, prof in ref_imus if reference_grade else ():
                wr = ins_walk.simulate(route, prof, seed=s)
                indr = wr.t_s >= wr.t_indoor_s
                for label, cons, gcp in (("Smoothing + NHC/ZUPT (as the paper's reference)", "nhc", False),
                                         (METHODS[3], "wvc", True)):
                    sm = eskf_rts_smooth(run_walk(wr, cons, use_gcp=gcp), with_cov=False)
                    err = nav_errors(sm.pos_n_m[indr], sm.mat_nb[indr], wr.pos_true_n_m[indr], wr.mat_true_nb[indr])
                    refg.append({"phone route": phone, "imu": imu_label, "method": label,
                                 "seed": s, **error_stats(err)["rms"]})
            gap = np.diff(walk.gcp_t_s)
            stats.append({"phone": phone, "seed": s, "duration_s": walk.t_s[-1] - walk.t_s[0],
                          "indoor_s": walk.t_s[-1] - walk.t_indoor_s, "imu_rate_hz": 1.0 / np.mean(np.diff(walk.t_s)),
                          "imu_rate_min_hz": 1.0 / np.max(np.diff(walk.t_s)),
                          "imu_rate_max_hz": 1.0 / np.min(np.diff(walk.t_s)),
                          "gnss_fixes": walk.gnss_t_s.size, "gcp_passages": walk.gcp_t_s.size,
                          "gcp_interval_mean_s": float(gap.mean()) if gap.size else np.nan,
                          "walker_step_scale_c": walk.params["user_c"]})
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
    return {
        "errors": errors,
        "errors_per_seed": per_seed,
        "position_side_by_side": side_by_side(errors, ("N", "E", "H")),
        "attitude_side_by_side": side_by_side(errors, ("Roll", "Pitch", "Heading")),
        "comparison": pd.DataFrame(comp),
        "walk_stats": pd.DataFrame(stats),
        "trajectory": pd.concat(traj, ignore_index=True),
        "gcp_grade": (pd.DataFrame(grade).groupby(["phone", "control points", "gcp_sd_m", "method"], sort=False)
                      [list(AXES)].mean().reset_index()),
        "heading_time_sync": (pd.DataFrame(sync).groupby(["phone", "method", "lag_s"], sort=False)
                              [["heading_rms_deg", "heading_max_deg"]].mean().reset_index()),
        "reference_grade": (pd.DataFrame(refg).groupby(["phone route", "imu", "method"], sort=False)[list(AXES)]
                            .mean().reset_index() if refg else pd.DataFrame()),
    }


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
