"""PSO learning of the Weinberg step-length factor against GPS: Chao (2008)'s two-phase experiment.

Phase 1 (good sky, straight or looped walk): detect steps by slope sign change (Fig. 3.9) on the
vertical acceleration, measure the walk's length from the 1 Hz GPS track (haversine sum), and learn
the walker's ``k`` by PSO on the fitness of eq. 4.4 with the Weinberg length ``k (Amax - Amin)^(1/4)``
(eq. 2.5; :mod:`ilocalg.pdr.k_factor`). Phase 2 (partly shaded loops): dead-reckon with the learned
``k`` and the compass heading on latitude/longitude (eq. 3.1-3.3) from the first GPS fix, and report
the start-end (closure) distance beside the fixed ``k = 0.5`` of the thesis ("TAR").

Fitness: eq. 4.4 has two readings over a walk, ``"total"`` (default) and ``"per_step"``
(:mod:`ilocalg.pdr.k_factor`); both are computed. The PSO is :func:`ilocalg.optim.pso_minimize` with
the thesis's settings (:data:`ilocalg.pdr.k_factor.PSO_SETTINGS_PAPER`).

Settings from the paper
-----------------------
All of Chao (2008), used as labelled reference values only: :data:`PAPER_TABLE_5_2` (Table 5-2:
leg length, PSO k, true and detected steps, GPS and PSO distance, accuracy), :data:`PAPER_PHASE2_A1`
(Figs. 5.14-5.15: closure m and %, PSO, TAR and GPS distances), :data:`PAPER_COMPASS_RMS` (sec. 5.1.3:
static compass RMS raw, after MA and SG). Used to compute: the fixed ``K_FIXED_PAPER = 0.5`` of
eq. 2.5 ("TAR", Fig. 5.15) and the PSO settings of sec. 5.3.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Eq. 2.5, 3.1-3.6, 4.1-4.4, Figs. 3.9, 5.10-5.21, Table 5-2.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.gnss import dead_reckon_latlon, gps_track_length_m, haversine_m, latlon_to_local_m, path_length_m
from ilocalg.papers import paper_ref
from ilocalg.pdr.filters import moving_average, rms, savitzky_golay
from ilocalg.pdr.k_factor import FITNESSES, PSO_SETTINGS_PAPER, learn_k, step_factors
from ilocalg.pdr.registry import detect_steps
from ilocalg.pdr.signals import along_gravity_mps2, gravity_lowpass_mps2
from ilocalg.pdr.step_length import k_from_distance, weinberg_length_m
from ilocalg.sim.pso_walks import Walk, simulate_pso_walks, simulate_static_compass

__all__ = [
    "PAPER",
    "PAPER_TABLE_5_2",
    "PAPER_PHASE2_A1",
    "PAPER_COMPASS_RMS",
    "K_FIXED_PAPER",
    "detect_walk_steps",
    "step_headings_deg",
    "dr_track",
    "compass_filter_study",
    "ilc_vertical_acc",
    "ilc_k_study",
    "run",
]

#: Source label of the comparison rows (kept as in earlier result tables, which must stay byte-identical).
PAPER = "PSO thesis (003)"
PAPER_TABLE_5_2 = {
    "A1": {"leg_cm": 94, "k": 0.444, "true_steps": 217, "det_steps": 216, "gps_m": 160.25, "pso_m": 158.28, "acc_pct": 98.7},  # noqa: E501
    "A2": {"leg_cm": 94, "k": 0.489, "true_steps": 116, "det_steps": 115, "gps_m": 93.26, "pso_m": 90.15, "acc_pct": 96.7},  # noqa: E501
    "A3": {"leg_cm": 94, "k": 0.477, "true_steps": 128, "det_steps": 123, "gps_m": 96.65, "pso_m": 91.07, "acc_pct": 94.2},  # noqa: E501
    "B1": {"leg_cm": 100, "k": 0.554, "true_steps": 108, "det_steps": 110, "gps_m": 92.71, "pso_m": 89.53, "acc_pct": 96.6},  # noqa: E501
    "B2": {"leg_cm": 100, "k": 0.494, "true_steps": 118, "det_steps": 116, "gps_m": 95.96, "pso_m": 91.84, "acc_pct": 95.7},  # noqa: E501
    "C": {"leg_cm": 108, "k": 0.522, "true_steps": 106, "det_steps": 107, "gps_m": 93.73, "pso_m": 96.13, "acc_pct": 97.5},  # noqa: E501
}
PAPER_PHASE2_A1 = {
    "park": {"closure_m": 2.81, "closure_pct": 1.6, "pso_m": 180.52, "tar_m": 203.18, "gps_m": 277.41},
    "hall": {"closure_m": 5.79, "closure_pct": 1.9, "pso_m": 298.92, "tar_m": 336.10, "gps_m": 423.55},
}
PAPER_COMPASS_RMS = {"raw": 0.716, "ma": 0.563, "sg": 0.638}
K_FIXED_PAPER = 0.5

PREFILTERS = ("ma", "none")


# ------------------------------------------------------------------------------------------------
# walk processing
# ------------------------------------------------------------------------------------------------

def detect_walk_steps(walk: Walk, prefilter: str = "ma") -> pd.DataFrame:
    """Sign-change steps of a simulated walk, with MA(2,2) pre-filter (thesis) or none."""
    if prefilter not in PREFILTERS:
        raise ValueError(f"prefilter must be one of {PREFILTERS}, got {prefilter!r}")
    imu = walk.imu
    return detect_steps("sign_change", imu["acc_z_mps2"].to_numpy(), imu["t_s"].to_numpy(), smooth=prefilter == "ma")


def step_headings_deg(imu: pd.DataFrame, steps: pd.DataFrame) -> np.ndarray:
    """Compass yaw at each step (deg from north, clockwise), after MA(2,2) on the unwrapped yaw."""
    yaw = np.rad2deg(np.unwrap(np.deg2rad(imu["yaw_deg"].to_numpy(float))))
    return moving_average(yaw, 2, 2)[steps["i_peak"].to_numpy()] % 360.0


def dr_track(walk: Walk, steps: pd.DataFrame, k: float) -> pd.DataFrame:
    """Great-circle dead reckoning (eq. 3.1-3.3) from the first GPS fix with Weinberg steps.

    Returns
    -------
    DataFrame
        ``lat_deg``, ``lon_deg``, ``x_m``, ``y_m`` (local east/north about the walk's origin); one
        row for the start and one per step.
    """
    if len(walk.gps) == 0:
        raise ValueError(f"walk {walk.walker}/{walk.place}: no GPS fix to start from")
    lat0, lon0 = walk.gps["lat_deg"].iloc[0], walk.gps["lon_deg"].iloc[0]
    L = weinberg_length_m(steps["a_max_mps2"].to_numpy(float), steps["a_min_mps2"].to_numpy(float), k)
    lat, lon = dead_reckon_latlon(lat0, lon0, step_headings_deg(walk.imu, steps), L)
    x, y = latlon_to_local_m(lat, lon, *walk.origin_deg)
    return pd.DataFrame({"lat_deg": lat, "lon_deg": lon, "x_m": x, "y_m": y})


def _closure_m(track: pd.DataFrame) -> float:
    return float(haversine_m(track["lat_deg"].iloc[0], track["lon_deg"].iloc[0],
                             track["lat_deg"].iloc[-1], track["lon_deg"].iloc[-1]))


def _gps_local(walk: Walk) -> pd.DataFrame:
    x, y = latlon_to_local_m(walk.gps["lat_deg"], walk.gps["lon_deg"], *walk.origin_deg)
    return pd.DataFrame({"t_s": walk.gps["t_s"].to_numpy(), "x_m": x, "y_m": y})


# ------------------------------------------------------------------------------------------------
# compass filter study (sec. 5.1.3)
# ------------------------------------------------------------------------------------------------

def compass_filter_study(seed: int = 0, fast: bool = False, n_logs: int | None = None) -> pd.DataFrame:
    """RMS of static compass logs raw, after MA(2,2) and after SG(m=2, 2, 2) (thesis Figs. 5.3-5.5).

    Each log is 60 s at 8 Hz (:func:`ilocalg.sim.pso_walks.simulate_static_compass`); the RMS is
    eq. 3.4. Returns one row per filter: mean and sd of the RMS over ``n_logs`` logs (default 200,
    fast 20), the ratio to raw, and the thesis's value.
    """
    n = n_logs if n_logs is not None else (20 if fast else 200)
    ss = np.random.SeedSequence([seed, 51])
    vals = {"raw": [], "ma": [], "sg": []}
    for child in ss.spawn(n):
        y = simulate_static_compass(np.random.default_rng(child))["yaw_deg"].to_numpy()
        vals["raw"].append(rms(y))
        vals["ma"].append(rms(moving_average(y, 2, 2)))
        vals["sg"].append(rms(savitzky_golay(y, 2, 2, 2)))
    raw = np.mean(vals["raw"])
    rows = []
    for name, label in (("raw", "raw"), ("ma", "MA nL=nR=2"), ("sg", "SG m=2 nL=nR=2")):
        v = np.asarray(vals[name])
        rows.append({"filter": label, "rms_deg_mean": v.mean(), "rms_deg_sd": v.std(ddof=1),
                     "ratio_to_raw": v.mean() / raw, "paper_rms_deg": PAPER_COMPASS_RMS[name],
                     "paper_ratio_to_raw": PAPER_COMPASS_RMS[name] / PAPER_COMPASS_RMS["raw"], "n_logs": n})
    return pd.DataFrame(rows)


# ------------------------------------------------------------------------------------------------
# real data: ILC 2020 site2/F4 walks (waypoint distance as the 'GPS' distance)
# ------------------------------------------------------------------------------------------------

def ilc_vertical_acc(imu: pd.DataFrame, gravity_halfwidth: int = 25) -> np.ndarray:
    """Vertical specific force, m/s^2: projection of the accelerometer on the gravity direction.

    Gravity is the moving average of the accelerometer over ``2 * gravity_halfwidth + 1`` samples
    (about 1 s at the ILC's 50 Hz).
    """
    A = imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy(float)
    return along_gravity_mps2(A, gravity_lowpass_mps2(A, gravity_halfwidth))


def ilc_k_study(data_dir: str | Path, seed: int = 0, fast: bool = False, ma_halfwidth: int = 6,
                min_dist_m: float = 5.0) -> dict[str, pd.DataFrame]:
    """Learn k on half of the ILC site2/F4 walks and apply it to the other half (fast: 10 walks).

    The ILC traces do not say who walked; they were all recorded with the same phone model, so they
    are treated as one surveyor. Traces sorted by start time alternate between learning (even) and
    test (odd). A walk's reference distance is the sum of straight segments between consecutive
    surveyor waypoints (the 'GPS' distance); its steps are the sign-change steps between the first
    and last waypoint on the vertical acceleration (:func:`ilc_vertical_acc`) after an MA of
    half-width ``ma_halfwidth`` samples (6 at 50 Hz keeps the MA's first null, 3.8 Hz, above the
    step rate; the thesis's MA(2,2) at 8 Hz has it at 1.6 Hz). k is learned by PSO on the pooled
    learning walks (total-distance fitness).

    Returns
    -------
    dict
        ``walks``: one row per walk; ``summary``: learned k (PSO, closed form), mean absolute and
        relative distance error on the test walks with the learned k and with k = 0.5.
    """
    from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor

    names = list_ilc_traces(data_dir)
    floor = load_ilc_floor(data_dir, names=names[:10] if fast else None, duplicate_bssid="keep_latest")
    traces = sorted(floor.traces.values(), key=lambda tr: float(tr.imu.index[0]))
    rows, step_tabs = [], []
    for tr in traces:
        wp = tr.waypoints
        if len(wp) < 2 or len(tr.imu) == 0:
            continue
        d = float(np.hypot(np.diff(wp["x_m"]), np.diff(wp["y_m"])).sum())
        if d < min_dist_m:
            continue
        t = tr.imu.index.to_numpy(float)
        av = ilc_vertical_acc(tr.imu)
        m = (t >= wp["t_s"].iloc[0]) & (t <= wp["t_s"].iloc[-1])
        st = detect_steps("sign_change", av[m], t[m], n_left=ma_halfwidth, n_right=ma_halfwidth)
        dur = float(wp["t_s"].iloc[-1] - wp["t_s"].iloc[0])
        rows.append({"trace": tr.name, "n_waypoints": len(wp), "duration_s": dur, "waypoint_dist_m": d,
                     "det_steps": len(st), "steps_per_s": len(st) / dur,
                     "sum_q": float(step_factors(st).sum()) if len(st) else 0.0})
        step_tabs.append(st)
    walks = pd.DataFrame(rows)
    walks["role"] = np.where(np.arange(len(walks)) % 2 == 0, "learn", "test")
    learn = walks["role"] == "learn"
    d_learn = float(walks.loc[learn, "waypoint_dist_m"].sum())
    pooled = pd.concat([s for s, r in zip(step_tabs, learn, strict=True) if r], ignore_index=True)
    summ, _ = learn_k(pooled, d_learn, "total", rng=np.random.default_rng([seed, 52]))
    walks["dist_learned_k_m"] = summ["k_pso"] * walks["sum_q"]
    walks["dist_k05_m"] = K_FIXED_PAPER * walks["sum_q"]
    for c in ("learned_k", "k05"):
        est = walks[f"dist_{c}_m"]
        walks[f"err_{c}_m"] = est - walks["waypoint_dist_m"]
        walks[f"err_{c}_pct"] = 100 * walks[f"err_{c}_m"] / walks["waypoint_dist_m"]
    test = walks[~learn]
    summary = pd.DataFrame([{
        "n_learn_walks": int(learn.sum()), "n_test_walks": int((~learn).sum()),
        "learn_dist_m": d_learn, "k_pso": summ["k_pso"], "k_closed": summ["k_closed"], "pso_iters": summ["iters"],
        "test_mae_learned_k_m": float(test["err_learned_k_m"].abs().mean()),
        "test_mae_k05_m": float(test["err_k05_m"].abs().mean()),
        "test_mape_learned_k_pct": float(test["err_learned_k_pct"].abs().mean()),
        "test_mape_k05_pct": float(test["err_k05_pct"].abs().mean()),
        "test_total_dist_err_learned_k_pct": float(100 * test["err_learned_k_m"].sum() / test["waypoint_dist_m"].sum()),
        "test_total_dist_err_k05_pct": float(100 * test["err_k05_m"].sum() / test["waypoint_dist_m"].sum()),
    }])
    return {"walks": walks, "summary": summary}


# ------------------------------------------------------------------------------------------------
# the experiment
# ------------------------------------------------------------------------------------------------

def _phase1(walks: list[Walk], prefilter: str, fitness: str, seed: int):
    rows, results, tracks = [], {}, {}
    for i, w in enumerate(walks):
        st = detect_walk_steps(w, prefilter)
        d_gps = gps_track_length_m(w.gps)
        summ, res = learn_k(st, d_gps, fitness, rng=np.random.default_rng([seed, 10, i]))
        tr = dr_track(w, st, summ["k_pso"])
        pso_m = path_length_m(tr["lat_deg"].to_numpy(), tr["lon_deg"].to_numpy())
        k_true = k_from_distance((2 * w.steps["amp_mps2"]) ** 0.25, np.sum(w.steps["length_m"]))
        rows.append({
            "walker": w.walker, "leg_cm": round(100 * w.leg_m), "place": w.place,
            "cadence_hz": float(1 / w.steps["duration_s"].mean()),
            "k_pso": summ["k_pso"], "k_closed": summ["k_closed"], "k_ls": summ["k_ls"], "k_scipy": summ["k_scipy"],
            "k_continuous": k_true,
            "pso_iters": summ["iters"], "pso_fitness_m": summ["fitness_pso_m"],
            "true_steps": w.n_steps, "det_steps": len(st),
            "true_m": w.route_m, "gps_m": d_gps, "pso_m": pso_m,
            "start_end_m": _closure_m(tr),
            "acc_pct": 100 * (1 - abs(d_gps - pso_m) / d_gps),
            "acc_vs_true_pct": 100 * (1 - abs(w.route_m - pso_m) / w.route_m),
        })
        results[w.walker] = res
        tracks[w.walker] = tr
    return pd.DataFrame(rows), results, tracks


def _phase2(walks: list[Walk], k_by_walker: dict, prefilter: str):
    rows, tracks = [], {}
    for w in walks:
        st = detect_walk_steps(w, prefilter)
        k = k_by_walker[w.walker]
        tr_pso = dr_track(w, st, k)
        tr_tar = dr_track(w, st, K_FIXED_PAPER)
        pso_m = path_length_m(tr_pso["lat_deg"].to_numpy(), tr_pso["lon_deg"].to_numpy())
        tar_m = path_length_m(tr_tar["lat_deg"].to_numpy(), tr_tar["lon_deg"].to_numpy())
        gps_m = gps_track_length_m(w.gps, max_gap_s=np.inf)
        gaps = np.diff(w.gps["t_s"].to_numpy())
        c_pso, c_tar = _closure_m(tr_pso), _closure_m(tr_tar)
        rows.append({
            "walker": w.walker, "place": w.place, "k_pso": k, "true_steps": w.n_steps, "det_steps": len(st),
            "true_m": w.route_m, "gps_m": gps_m, "gps_fix_rate": len(w.gps) / (w.gps["t_s"].iloc[-1] + 1),
            "gps_max_gap_s": float(gaps.max()), "pso_m": pso_m, "tar_m": tar_m,
            "pso_closure_m": c_pso, "pso_closure_pct": 100 * c_pso / pso_m,
            "tar_closure_m": c_tar, "tar_closure_pct": 100 * c_tar / tar_m,
            "pso_dist_err_pct": 100 * (pso_m - w.route_m) / w.route_m,
            "tar_dist_err_pct": 100 * (tar_m - w.route_m) / w.route_m,
            "gps_dist_err_pct": 100 * (gps_m - w.route_m) / w.route_m,
        })
        tracks[f"{w.walker} {w.place}"] = {"pso": tr_pso, "tar": tr_tar, "gps": _gps_local(w),
                                          "truth": w.truth[["x_m", "y_m"]]}
    return pd.DataFrame(rows), tracks


def _pso_repeat(walks: list[Walk], prefilter: str, fitness: str, seed: int, n_rep: int) -> pd.DataFrame:
    """PSO from ``n_rep`` seeds per walker beside the closed-form minimiser of the same fitness."""
    rows = []
    for i, w in enumerate(walks):
        st = detect_walk_steps(w, prefilter)
        d_gps = gps_track_length_m(w.gps)
        ks, iters = [], []
        for r in range(n_rep):
            s, _ = learn_k(st, d_gps, fitness, rng=np.random.default_rng([seed, 20, i, r]))
            ks.append(s["k_pso"])
            iters.append(s["iters"])
        ks = np.asarray(ks)
        rows.append({"walker": w.walker, "prefilter": prefilter, "fitness": fitness, "n_runs": n_rep,
                     "k_closed": s["k_closed"],
                     "k_pso_mean": ks.mean(), "k_pso_sd": ks.std(ddof=1) if n_rep > 1 else 0.0,
                     "max_abs_dev_from_closed": float(np.max(np.abs(ks - s["k_closed"]))),
                     "iters_mean": float(np.mean(iters)), "iters_max": int(np.max(iters)),
                     "share_converged": float(np.mean(np.asarray(iters) < PSO_SETTINGS_PAPER["max_iters"]))})
    return pd.DataFrame(rows)


def _paper_table(df: pd.DataFrame) -> pd.DataFrame:
    out = df[["walker", "leg_cm", "k_pso", "true_steps", "det_steps", "gps_m", "pso_m", "acc_pct"]].copy()
    for col in ("k", "true_steps", "det_steps", "gps_m", "pso_m", "acc_pct"):
        out[f"paper_{col}"] = [PAPER_TABLE_5_2[w][col] for w in out["walker"]]
    return out


def _comparison(t52: pd.DataFrame, p2: pd.DataFrame, compass: pd.DataFrame, label: str) -> list[dict]:
    rows = []
    for r in t52.itertuples():
        p = PAPER_TABLE_5_2[r.walker]
        rows.append(paper_ref(PAPER, f"Table 5-2 {label}", f"{r.walker} k (PSO)", p["k"], r.k_pso))
        rows.append(paper_ref(PAPER, f"Table 5-2 {label}", f"{r.walker} detected steps", p["det_steps"], r.det_steps,
                              note=f"true steps {r.true_steps} (walk design, from the paper)"))
        rows.append(paper_ref(PAPER, f"Table 5-2 {label}", f"{r.walker} PSO distance", p["pso_m"], r.pso_m, "m",
                              note="the simulated route length is set from the paper's GPS distance"))
        rows.append(paper_ref(PAPER, f"Table 5-2 {label}", f"{r.walker} accuracy vs GPS", p["acc_pct"], r.acc_pct, "%"))
    for place in ("park", "hall"):
        sel = p2[(p2["walker"] == "A1") & (p2["place"] == place)]
        if len(sel):
            r = sel.iloc[0]
            p = PAPER_PHASE2_A1[place]
            rows.append(paper_ref(PAPER, f"Fig 5.15 {label}", f"A1 {place} closure (PSO k)", p["closure_m"],
                                  r["pso_closure_m"], "m"))
            rows.append(paper_ref(PAPER, f"Fig 5.15 {label}", f"A1 {place} closure (PSO k)", p["closure_pct"],
                                  r["pso_closure_pct"], "%"))
    return rows


def _compass_rows(compass: pd.DataFrame) -> list[dict]:
    rows = []
    for key, r in zip(("raw", "ma", "sg"), compass.itertuples(), strict=True):
        note = "input: the simulator's static noise is scaled to this value" if key == "raw" else ""
        rows.append(paper_ref(PAPER, "Sec 5.1.3", f"static compass RMS, {r.filter}", PAPER_COMPASS_RMS[key],
                              r.rms_deg_mean, "deg", note=note))
    return rows


def run(seed: int = 0, fast: bool = False, prefilter: str = "ma", fitness: str = "total",
        data_dir: str | Path | None = None, real: bool = True) -> dict[str, pd.DataFrame]:
    """The two-phase experiment on the simulated walks, the compass study and the ILC k study.

    Parameters
    ----------
    seed : int
        Seed of the simulated walks and of the PSO runs.
    fast : bool
        Fewer PSO repeats, fewer compass logs, fewer ILC walks.
    prefilter : {"ma", "none"}
        Step-detection pre-filter of Table 5-2 (the thesis: MA nL = nR = 2); the other one is run
        too, as ``table_5_2_alt``.
    fitness : {"total", "per_step"}
        Reading of eq. 4.4 for Table 5-2; the other one is summarised in ``fitness_variants``.
    data_dir : path, optional
        Folder holding ``ilc2020_site2_F4`` (None: :func:`ilocalg.io.paths.data_dir`).
    real : bool
        Run the ILC study when the data are present.

    Returns
    -------
    dict of DataFrame
        ``table_5_2`` (reproduced beside the paper), ``phase1``, ``phase2``, ``table_5_2_alt``,
        ``phase2_alt``, ``fitness_variants``, ``pso_repeat``, ``pso_a1_swarm``, ``pso_a1_history``,
        ``pso_a1_result``, ``compass``, ``comparison`` (paper_ref rows), ``tracks_*`` (paths for the
        maps), and when the ILC data are present ``ilc_walks``, ``ilc_summary``; ``ilc_status`` always.
    """
    if prefilter not in PREFILTERS:
        raise ValueError(f"prefilter must be one of {PREFILTERS}, got {prefilter!r}")
    if fitness not in FITNESSES:
        raise ValueError(f"fitness must be one of {FITNESSES}, got {fitness!r}")
    walks = simulate_pso_walks(seed)
    other = "none" if prefilter == "ma" else "ma"
    p1, results, tracks1 = _phase1(walks["1"], prefilter, fitness, seed)
    k_by = dict(zip(p1["walker"], p1["k_pso"], strict=True))
    p2, tracks2 = _phase2(walks["2"], k_by, prefilter)
    p1_alt, _, _ = _phase1(walks["1"], other, fitness, seed)
    p2_alt, tracks2_alt = _phase2(walks["2"], dict(zip(p1_alt["walker"], p1_alt["k_pso"], strict=True)), other)
    other_fit = "per_step" if fitness == "total" else "total"
    p1_fit, _, _ = _phase1(walks["1"], prefilter, other_fit, seed)
    variants = pd.concat([
        p1[["walker", "k_pso", "k_closed", "k_ls", "k_scipy", "pso_iters", "pso_fitness_m", "pso_m", "acc_pct"]]
        .assign(fitness=fitness),
        p1_fit[["walker", "k_pso", "k_closed", "k_ls", "k_scipy", "pso_iters", "pso_fitness_m", "pso_m", "acc_pct"]]
        .assign(fitness=other_fit),
    ], ignore_index=True)
    n_rep = 5 if fast else 50
    rep = pd.concat([_pso_repeat(walks["1"], pf, f, seed, n_rep) for pf in (prefilter, other)
                     for f in ("total", "per_step")], ignore_index=True)
    a1 = results["A1"]
    r1 = p1.iloc[0]
    a1_block = pd.DataFrame([{
        "particles": PSO_SETTINGS_PAPER["n_particles"], "maxSpeed": PSO_SETTINGS_PAPER["max_speed"],
        "minFitness": PSO_SETTINGS_PAPER["min_fitness"], "initWeight": PSO_SETTINGS_PAPER["w_init"],
        "finalWeight": PSO_SETTINGS_PAPER["w_final"], "c1": PSO_SETTINGS_PAPER["c1"], "c2": PSO_SETTINGS_PAPER["c2"],
        "Iters": a1.n_iters, "Fitness": a1.f_best, "Index": a1.best_particle, "BestPos": float(a1.x_best[0]),
        "PSO_sigma_dist_m": r1["pso_m"], "PSO_start_end_dist_m": r1["start_end_m"], "GPS_sigma_dist_m": r1["gps_m"],
        "PSO_diff_gps_m": abs(r1["gps_m"] - r1["pso_m"]),
        "PSO_diff_gps_rel": abs(r1["gps_m"] - r1["pso_m"]) / r1["gps_m"],
    }])
    compass = compass_filter_study(seed, fast)
    log = simulate_static_compass(np.random.default_rng([seed, 53]))
    y = log["yaw_deg"].to_numpy()
    out_log = pd.DataFrame({"t_s": log["t_s"], "raw_deg": y, "ma_deg": moving_average(y, 2, 2),
                            "sg_deg": savitzky_golay(y, 2, 2, 2)})
    t52 = _paper_table(p1)
    t52_alt = _paper_table(p1_alt)
    rows = _comparison(t52, p2, compass, f"(prefilter {prefilter})")
    rows += _comparison(t52_alt, p2_alt, compass, f"(prefilter {other})")
    rows += _compass_rows(compass)
    out = {
        "table_5_2": t52, "phase1": p1, "phase2": p2, "table_5_2_alt": t52_alt, "phase1_alt": p1_alt,
        "phase2_alt": p2_alt, "fitness_variants": variants, "pso_repeat": rep,
        "pso_a1_swarm": a1.swarm_table(), "pso_a1_history": a1.history_table(), "pso_a1_result": a1_block,
        "compass": compass, "compass_example": out_log,
    }
    # paths for the maps (not result tables)
    out["tracks_phase1"] = pd.concat([t.assign(walker=w) for w, t in tracks1.items()], ignore_index=True)
    for name, trs in (("tracks_phase2", tracks2), ("tracks_phase2_alt", tracks2_alt)):
        tr2 = []
        for key, d in trs.items():
            for kind, t in d.items():
                tr2.append(t[["x_m", "y_m"]].assign(walk=key, kind=kind))
        out[name] = pd.concat(tr2, ignore_index=True)
    gps1 = []
    for w in walks["1"]:
        gps1.append(_gps_local(w).assign(walker=w.walker))
    out["gps_phase1"] = pd.concat(gps1, ignore_index=True)
    a1w = walks["1"][0]
    a1_steps = detect_walk_steps(a1w, prefilter)
    out["a1_signal"] = a1w.imu.assign(acc_ma_mps2=moving_average(a1w.imu["acc_z_mps2"].to_numpy(), 2, 2))
    out["a1_steps"] = a1_steps
    # real data
    from ilocalg.io.paths import dataset_path
    ilc = Path(data_dir) / "ilc2020_site2_F4" if data_dir is not None else dataset_path("ilc2020_site2_F4")
    status = {"dataset": "ilc2020_site2_F4", "path": str(ilc), "present": ilc.is_dir(), "ran": False}
    if real and ilc.is_dir():
        res = ilc_k_study(ilc, seed, fast)
        out["ilc_walks"] = res["walks"]
        out["ilc_summary"] = res["summary"]
        status["ran"] = True
    out["ilc_status"] = pd.DataFrame([status])
    out["comparison"] = pd.DataFrame(rows)
    return out
