"""PSO learning of the Weinberg step-length factor against GPS: Chao (2008)'s two-phase experiment.

Phase 1 (good sky, straight or looped walk): detect steps by slope sign change (Fig. 3.9) on the
vertical acceleration, measure the walk's length from the 1 Hz GPS track (haversine sum), and learn
the walker's ``k`` by PSO on the fitness of eq. 4.4 with the Weinberg length ``k (Amax - Amin)^(1/4)``
(eq. 2.5; :mod:`ilocalg.pdr.k_factor`). Phase 2 (partly shaded loops): dead-reckon with the learned
``k`` and the compass heading on latitude/longitude (eq. 3.1-3.3) from the first GPS fix, and report
the start-end (closure) distance beside the fixed ``k = 0.5`` of the thesis ("TAR").

Readings (line numbers of the thesis's text copy; every choice is listed by :func:`readings`):

* MA(nL = nR = 2) on the walking acceleration before step detection by default: the thesis's
  processing chain lists "signal correction and filtering (MA Signal Filter)" before the step
  detection algorithm (L692), L718 adopts MA filtering "for the experiments", and the only width the
  text gives is nL = nR = 2 (L713, L735-743). No moving average (``prefilter="none"``, the toolkit's
  earlier default, which read the MA as the compass's only) is the labelled alternative reading,
  and MA width 1 a sensitivity row. At 8 Hz MA(2,2) zeroes 1.6 Hz, inside the step-rate band: that
  is what the text's chain does, and it lowers the detected amplitudes, hence a larger learned k;
* the +-RMS band of Fig. 3.9 (L519-520) from the static-noise RMS (eq. 3.4, L440-444, L699-701) of a
  simulated static accelerometer log after the same pre-filter; the accelerometer's noise (HAAM-325B,
  ref. [34], no value in the text) is assumed 0.10 m/s^2 and swept 0.05-0.20 m/s^2 (the band follows
  it), a band of 0 (no rejection) and the walking-signal RMS (``band="signal"``) are sensitivity rows;
* eq. 4.4 read per step (default, Fig. 5.12: Fitness 0.0939 with the PSO distance 2.0996 m off,
  L834, L840), walk-total as the alternative (:mod:`ilocalg.pdr.k_factor`);
* Table 5-2's accuracy is ``1 - |GPS - PSO| / GPS`` on the learning walk itself (L927-935; A1:
  1 - |160.25 - 158.28| / 160.25 = 98.7 %);
* in this 1-D problem the PSO's k is set by its stop rule (minFitness 0.1, L811): it stops anywhere
  in the interval of k whose fitness is below 0.1 (``k_stop_lo``, ``k_stop_hi``), and the closed
  form gives the minimiser itself; the initial search box (0, 1) is not in the thesis.

The PSO is :func:`ilocalg.optim.pso_minimize` with the thesis's settings
(:data:`ilocalg.pdr.k_factor.PSO_SETTINGS_PAPER`).

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
from ilocalg.papers import PAPERS, paper_ref, reading, readings_table
from ilocalg.papers.pso import K_FIXED_PAPER, PAPER_COMPASS_RMS, PAPER_PHASE2_A1, PAPER_TABLE_5_2
from ilocalg.pdr.filters import moving_average, rms, savitzky_golay
from ilocalg.pdr.k_factor import FITNESSES, K_BOUNDS, PSO_SETTINGS_PAPER, learn_k, step_factors
from ilocalg.pdr.registry import detect_steps
from ilocalg.pdr.sign_change import static_rms_mps2
from ilocalg.pdr.signals import along_gravity_mps2, gravity_lowpass_mps2
from ilocalg.pdr.step_length import k_from_distance, weinberg_length_m
from ilocalg.sim.pso_walks import Walk, simulate_pso_walks, simulate_static_acc, simulate_static_compass

__all__ = [
    "PAPER",
    "PAPER_TABLE_5_2",
    "PAPER_PHASE2_A1",
    "PAPER_COMPASS_RMS",
    "K_FIXED_PAPER",
    "PREFILTERS",
    "BANDS",
    "ROUTE_SCALES",
    "SENSITIVITY_VARIANTS",
    "EARLIER_READING",
    "detect_walk_steps",
    "static_band_mps2",
    "readings",
    "sensitivity",
    "step_headings_deg",
    "dr_track",
    "compass_filter_study",
    "ilc_vertical_acc",
    "ilc_k_study",
    "run",
]

#: Source label of the comparison rows (kept as in earlier result tables, which must stay byte-identical).
PAPER = PAPERS["pso"]
# The published values (PAPER_TABLE_5_2, PAPER_PHASE2_A1, PAPER_COMPASS_RMS, K_FIXED_PAPER) are declared once in
# ilocalg.papers.pso and re-exported here.

#: Pre-filters of the walking acceleration: none (alternative reading), MA half-width 1, MA half-width 2
#: (nL = nR = 2, the text's reading and the default).
PREFILTERS = ("none", "ma1", "ma2")
_MA_HALF = {"none": 0, "ma1": 1, "ma2": 2}
#: Half-width of the +-RMS band: the static-noise RMS (default) or the walking signal's RMS.
BANDS = ("static", "signal")
#: True route length over the thesis's GPS distance, swept by :func:`sensitivity` (1.0 is the default).
ROUTE_SCALES = (0.95, 1.05)


# ------------------------------------------------------------------------------------------------
# walk processing
# ------------------------------------------------------------------------------------------------

def _check_choice(name, value, allowed):
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")


def static_band_mps2(seed: int = 0, prefilter: str = "ma2", sensors: dict | None = None) -> float:
    """Static-noise RMS of the device's accelerometer (eq. 3.4), after the walk's pre-filter.

    A 60 s static log (device on a table, the thesis's static calibration, sec. 5.1.3) from
    :func:`ilocalg.sim.pso_walks.simulate_static_acc`, one per run (one device); ``sensors``
    overrides the simulator's settings (e.g. the accelerometer noise).
    """
    _check_choice("prefilter", prefilter, PREFILTERS)
    log = simulate_static_acc(np.random.default_rng([seed, 54]), sensors=sensors)
    n = _MA_HALF[prefilter]
    return static_rms_mps2(log["acc_z_mps2"].to_numpy(), n, n, smooth=n > 0)


def detect_walk_steps(walk: Walk, prefilter: str = "ma2", band_mps2: float | None = None) -> pd.DataFrame:
    """Sign-change steps of a simulated walk (Fig. 3.9).

    Parameters
    ----------
    prefilter : {"none", "ma1", "ma2"}
        Moving average on the walking acceleration (MA(2,2) by default; module docstring).
    band_mps2 : float, optional
        Half-width of the +-RMS band (the static-noise RMS, :func:`static_band_mps2`); None uses the
        walking signal's RMS (the alternative reading).
    """
    _check_choice("prefilter", prefilter, PREFILTERS)
    imu = walk.imu
    n = _MA_HALF[prefilter]
    return detect_steps("sign_change", imu["acc_z_mps2"].to_numpy(), imu["t_s"].to_numpy(), smooth=n > 0,
                        n_left=max(n, 1), n_right=max(n, 1), rms_mps2=band_mps2)


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


def _amp_cv(steps: pd.DataFrame) -> float:
    """Coefficient of variation of the per-step ``Amax - Amin`` (NaN below 3 steps)."""
    if len(steps) < 3:
        return float("nan")
    d = (steps["a_max_mps2"] - steps["a_min_mps2"]).to_numpy(float)
    return float(d.std(ddof=1) / d.mean())


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
        ``walks``: one row per walk (with ``amp_cv``, the CV of the per-step ``Amax - Amin``: the
        measured step-to-step amplitude scatter behind the simulator's ``step_amp_cv``); ``summary``:
        learned k (PSO, closed form), mean absolute and
        relative distance error on the test walks with the learned k and with k = 0.5.
    """
    from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor

    names = list_ilc_traces(data_dir)
    floor = load_ilc_floor(data_dir, names=names[:10] if fast else None, duplicate_bssid="keep_latest",
                           relisted_wifi="keep")
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
        st = detect_steps("sign_change", av[m], t[m], n_left=ma_halfwidth, n_right=ma_halfwidth,
                          smooth=True)
        dur = float(wp["t_s"].iloc[-1] - wp["t_s"].iloc[0])
        rows.append({"trace": tr.name, "n_waypoints": len(wp), "duration_s": dur, "waypoint_dist_m": d,
                     "det_steps": len(st), "steps_per_s": len(st) / dur,
                     "sum_q": float(step_factors(st).sum()) if len(st) else 0.0,
                     "amp_cv": _amp_cv(st)})
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

def _band(seed: int, prefilter: str, band, sensors: dict | None = None) -> float | None:
    """Band half-width: "static" (static-log RMS), "signal" (None: the walking signal's RMS) or a number."""
    if band == "static":
        return static_band_mps2(seed, prefilter, sensors)
    if band == "signal":
        return None
    b = float(band)
    if not np.isfinite(b) or b < 0:
        raise ValueError(f"band must be 'static', 'signal' or a non-negative number in m/s^2, got {band!r}")
    return b


def _phase1(walks: list[Walk], prefilter: str, fitness: str, seed: int, band="static",
            sensors: dict | None = None):
    rows, results, tracks = [], {}, {}
    b = _band(seed, prefilter, band, sensors)
    for i, w in enumerate(walks):
        st = detect_walk_steps(w, prefilter, b)
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
            "fitness_closed_m": summ["fitness_closed_m"],
            "k_stop_lo": summ["k_stop_lo"], "k_stop_hi": summ["k_stop_hi"],
            "pso_stopped_by": "minFitness" if summ["iters"] < PSO_SETTINGS_PAPER["max_iters"] else "maxIters",
            "band_mps2": np.nan if b is None else b,
            "true_steps": w.n_steps, "det_steps": len(st),
            "true_m": w.route_m, "gps_m": d_gps, "pso_m": pso_m,
            "start_end_m": _closure_m(tr),
            "acc_pct": 100 * (1 - abs(d_gps - pso_m) / d_gps),
            "acc_vs_true_pct": 100 * (1 - abs(w.route_m - pso_m) / w.route_m),
        })
        results[w.walker] = res
        tracks[w.walker] = tr
    return pd.DataFrame(rows), results, tracks


def _phase2(walks: list[Walk], k_by_walker: dict, prefilter: str, seed: int, band: str = "static"):
    rows, tracks = [], {}
    b = _band(seed, prefilter, band)
    for w in walks:
        st = detect_walk_steps(w, prefilter, b)
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


def _pso_repeat(walks: list[Walk], prefilter: str, fitness: str, seed: int, n_rep: int,
                band: str = "static") -> pd.DataFrame:
    """PSO from ``n_rep`` seeds per walker beside the closed-form minimiser of the same fitness."""
    rows = []
    b = _band(seed, prefilter, band)
    for i, w in enumerate(walks):
        st = detect_walk_steps(w, prefilter, b)
        d_gps = gps_track_length_m(w.gps)
        ks, iters = [], []
        for r in range(n_rep):
            s, _ = learn_k(st, d_gps, fitness, rng=np.random.default_rng([seed, 20, i, r]))
            ks.append(s["k_pso"])
            iters.append(s["iters"])
        ks = np.asarray(ks)
        rows.append({"walker": w.walker, "prefilter": prefilter, "band": band, "fitness": fitness, "n_runs": n_rep,
                     "k_closed": s["k_closed"], "k_stop_lo": s["k_stop_lo"], "k_stop_hi": s["k_stop_hi"],
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


def _comparison(t52: pd.DataFrame, p2: pd.DataFrame, compass: pd.DataFrame, label: str,
                default_label: str | None = None, note: str = "") -> list[dict]:
    """Table 5-2 and Fig 5.15 rows; with ``default_label`` the rows are an alternative reading of the rows
    labelled ``default_label``; ``note`` prefixes every row's note. Detected steps and PSO distance are set by
    input: the simulator walks the paper's true step count along a route as long as the paper's GPS distance."""
    rows = []

    def ref(item, quantity, p, r, unit="", row_note="", by_input=False):
        full = "; ".join(x for x in (note, row_note) if x)
        if default_label is not None:
            alt_item = item.replace(label, default_label)
            return paper_ref(PAPER, item, quantity, p, r, unit, full, row_class="alternative reading",
                             replaces=(alt_item, quantity))
        return paper_ref(PAPER, item, quantity, p, r, unit, full,
                         row_class="set by input" if by_input else "result")

    for r in t52.itertuples():
        p = PAPER_TABLE_5_2[r.walker]
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} k (PSO)", p["k"], r.k_pso))
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} detected steps", p["det_steps"], r.det_steps,
                        row_note=f"true steps {r.true_steps} (walk design, from the paper)", by_input=True))
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} PSO distance", p["pso_m"], r.pso_m, "m",
                        row_note="simulated true route = the paper's GPS distance (route_scale 1, swept)",
                        by_input=True))
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} accuracy vs GPS", p["acc_pct"], r.acc_pct, "%"))
    for place in ("park", "hall"):
        sel = p2[(p2["walker"] == "A1") & (p2["place"] == place)]
        if len(sel):
            r = sel.iloc[0]
            p = PAPER_PHASE2_A1[place]
            rows.append(ref(f"Fig 5.15 {label}", f"A1 {place} closure (PSO k)", p["closure_m"],
                            r["pso_closure_m"], "m"))
            rows.append(ref(f"Fig 5.15 {label}", f"A1 {place} closure (PSO k)", p["closure_pct"],
                            r["pso_closure_pct"], "%"))
    return rows


def _compass_rows(compass: pd.DataFrame) -> list[dict]:
    rows = []
    for key, r in zip(("raw", "ma", "sg"), compass.itertuples(), strict=True):
        note = "input: the simulator's static noise is scaled to this value" if key == "raw" else ""
        rows.append(paper_ref(PAPER, "Sec 5.1.3", f"static compass RMS, {r.filter}", PAPER_COMPASS_RMS[key],
                              r.rms_deg_mean, "deg", note=note, row_class="set by input" if key == "raw" else "result"))
    return rows


def readings(prefilter: str = "ma2", band: str = "static", fitness: str = "per_step") -> pd.DataFrame:
    """One row per modelling choice of :func:`run`: the thesis's line, what it says, what the code does, the source.

    Line numbers are lines of the thesis's text copy (Chao 2008). The earlier readings of the toolkit
    appear as labelled sensitivity rows (computed in :func:`sensitivity`).
    """
    s = PSO_SETTINGS_PAPER
    rows = [
        ("MA on the walking acceleration", "L692, L718, L713, L735-743",
         "processing chain: 'signal correction and filtering (MA Signal Filter)', then the step detection "
         "algorithm (L692); 'MA filtering is adopted for the experiments' (L718); the only width given is "
         "nL=nR=2 (compass Fig 5.4, accelerometer Figs 5.6-5.8)",
         {"none": "no moving average", "ma1": "MA nL=nR=1", "ma2": "MA nL=nR=2"}[prefilter],
         "thesis (default MA nL=nR=2); no MA (the toolkit's earlier default) is the labelled alternative "
         "reading (comparison rows 'Table 5-2 (none, ...)', tables *_no_ma), MA 1 a sensitivity row. "
         "MA(2,2) at 8 Hz zeroes 1.6 Hz (pdr.filters.smoother_gain), inside the step-rate band"),
        ("+-RMS band of Fig 3.9", "L519-520; eq. 3.4 L440-444; L699-701",
         "reject extrema inside [-RMS, +RMS]; RMS (eq. 3.4) measures the static error; the static experiment "
         "gives 'the error range for the correction of eq. 4.4'",
         "static-noise RMS of a simulated 60 s static log, after the walk's pre-filter" if band == "static"
         else ("RMS of the walking signal itself" if band == "signal" else f"fixed {band} m/s^2"),
         "thesis reading (the band is the static RMS); its size follows the accelerometer noise, which the "
         "text does not give (HAAM-325B, ref. [34]): 0.10 m/s^2 assumed, swept 0.05-0.20 m/s^2; band 0 and "
         "the walking-signal RMS are sensitivity rows (sensitivity table)"),
        ("fitness, eq. 4.4", "L632-634; Fig 5.12 L834, L840",
         "f(k) = |S_gps - S_ins| with S the step length; A1: Fitness 0.0939 with Diff(GPS) 2.0996 m",
         "mean over steps of |D_gps/N - k q_j|" if fitness == "per_step" else "|D_gps - k sum q_j| over the walk",
         "per step: the only reading compatible with Fig 5.12; walk-total (the toolkit's earlier default) is a "
         "sensitivity row"),
        ("Table 5-2 accuracy", "L927-935, L845",
         "accuracy (%) beside GPS (PSO) distance; A1 158.28 m vs 160.25 m -> 98.7 %",
         "100 (1 - |GPS - PSO| / GPS) on the learning walk itself (PSO = DR path length with the learned k)",
         "thesis"),
        ("PSO settings", "L807-812", f"maxIters {s['max_iters']}, particles {s['n_particles']}, weight "
         f"{s['w_init']} -> {s['w_final']}, maxSpeed {s['max_speed']}, minFitness {s['min_fitness']}, c1 = c2 = "
         f"{s['c1']}", "the same (ilocalg.optim.pso_minimize)", "thesis"),
        ("what sets the PSO's k", "L811", "stop when the fitness is below minFitness (0.1)",
         "the PSO stops anywhere in [k_stop_lo, k_stop_hi] (fitness < 0.1); k_closed is the exact minimiser",
         "a property of the 1-D problem: the PSO result is set by its stop rule"),
        ("initial search box", "", "silent", f"initial swarm uniform in k in {K_BOUNDS}",
         "toolkit's choice"),
        ("true route length", "L927-935 (Table 5-2)", "the walk's length is known only from GPS",
         "true length = route_scale x the thesis's GPS distance, route_scale 1",
         f"assumption; route_scale {ROUTE_SCALES} are sensitivity rows"),
        ("GPS error", "L750-752 (sec. 5.1.3, Fig 5.9)", "static ~30 s, accuracy better than 1.5 m",
         "Gauss-Markov per axis, sd 0.61 m (1.5 m as the 95 % radius), tau 20 s, no white part",
         "thesis bound; tau is not in the text (assumed) and sets the GPS distance's bias (the 1 Hz track "
         "sums the fixes' noise: GPS/true distance 1.028 at tau 20 s); swept tau 5-300 s and bound 0.75 m "
         "(sensitivity table, column gps_over_true_mean)"),
        ("step-to-step scatter", "L771 (walk at a normal, steady pace, steps as even as possible)",
         "no variability value", "step length and duration CV 3 % (Hausdorff 2005); vertical-acceleration "
         "amplitude scatter CV 0.18 per step beyond the pendulum's",
         "amplitude CV measured on the ILC 2020 site2/F4 walks (per-step Amax-Amin CV 0.20, median of the 19 walks; "
         "ilc_walks.amp_cv) minus the pendulum's 0.085; swept 0-0.27 and step CV 1.5-5 % (sensitivity table)"),
        ("hand sway, magnetic disturbance", "L769", "the device is held in the hand; no sway or disturbance values",
         "yaw sway 4.5 deg at the stride rate; heading error along the route, sd 2 deg, 10 m correlation",
         "Crosbie et al. 1997 (trunk axial rotation ~9 deg); smartphone azimuth RMSE <= 2 deg (Lviv field study); "
         "correlation length assumed"),
        ("step heading", "L718", "MA used on the compass", "compass yaw after MA(2,2) at each detected step",
         "thesis (compass calibration, Fig 5.4)"),
        ("fixed k of the comparison (TAR)", "L899", "eq. 2.5 with k = 0.5", f"k = {K_FIXED_PAPER}", "thesis"),
    ]
    return readings_table([reading(c, f"Chao 2008, {ln}" if ln.startswith("L") else ln, t, d, src)
                           for c, ln, t, d, src in rows])


#: Variants of :func:`sensitivity`: (name, prefilter, band, fitness, route_scale[, simulator overrides]);
#: the first is the default. ``band`` is "static", "signal" or a half-width in m/s^2.
SENSITIVITY_VARIANTS = (
    ("default (text reading)", "ma2", "static", "per_step", 1.0),
    ("alternative reading: no MA", "none", "static", "per_step", 1.0),
    ("MA nL=nR=1", "ma1", "static", "per_step", 1.0),
    ("band: walking-signal RMS", "ma2", "signal", "per_step", 1.0),
    ("band 0 (no rejection)", "ma2", 0.0, "per_step", 1.0),
    ("accelerometer noise 0.05 m/s^2 (band follows)", "ma2", "static", "per_step", 1.0, {"acc_noise_mps2": 0.05}),
    ("accelerometer noise 0.20 m/s^2 (band follows)", "ma2", "static", "per_step", 1.0, {"acc_noise_mps2": 0.20}),
    ("fitness: walk total", "ma2", "static", "total", 1.0),
    ("earlier reading (MA 2, signal RMS, walk total)", "ma2", "signal", "total", 1.0),
    ("route 0.95 x GPS distance", "ma2", "static", "per_step", 0.95),
    ("route 1.05 x GPS distance", "ma2", "static", "per_step", 1.05),
    ("amplitude scatter 0 (earlier simulator)", "ma2", "static", "per_step", 1.0, {"step_amp_cv": 0.0}),
    ("amplitude scatter CV 0.10", "ma2", "static", "per_step", 1.0, {"step_amp_cv": 0.10}),
    ("amplitude scatter CV 0.27 (ILC IQR top)", "ma2", "static", "per_step", 1.0, {"step_amp_cv": 0.27}),
    ("step CV 1.5 %", "ma2", "static", "per_step", 1.0, {"step_cv": 0.015}),
    ("step CV 5 %", "ma2", "static", "per_step", 1.0, {"step_cv": 0.05}),
    ("GPS tau 5 s", "ma2", "static", "per_step", 1.0, {"gps_open_tau_s": 5.0}),
    ("GPS tau 60 s", "ma2", "static", "per_step", 1.0, {"gps_open_tau_s": 60.0}),
    ("GPS tau 300 s", "ma2", "static", "per_step", 1.0, {"gps_open_tau_s": 300.0}),
    ("GPS 95 % bound 0.75 m", "ma2", "static", "per_step", 1.0, {"gps_static_95_m": 0.75}),
)


def sensitivity(seed: int = 0, variants=SENSITIVITY_VARIANTS) -> pd.DataFrame:
    """Table 5-2 summarised for every reading: the default and the labelled alternatives.

    Returns one row per variant: the share of true steps detected, the PSO's k (min, mean, max), the
    closed-form minimiser's mean, the accuracy vs GPS (min, mean, max) and vs the true distance, the
    PSO's iterations and best fitness (means over walkers), the band used and the GPS/true distance.
    """
    rows = []
    cache = {}
    for v in variants:
        name, pf, band, fit, scale = v[:5]
        sensors = dict(v[5]) if len(v) > 5 else {}
        _check_choice("prefilter", pf, PREFILTERS)
        if isinstance(band, str):
            _check_choice("band", band, BANDS)
        _check_choice("fitness", fit, FITNESSES)
        key = (scale, tuple(sorted(sensors.items())))
        if key not in cache:
            cache[key] = simulate_pso_walks(seed, route_scale=scale, sensors=sensors or None)["1"]
        p1, _, _ = _phase1(cache[key], pf, fit, seed, band, sensors or None)
        rows.append({"variant": name, "prefilter": pf, "band": str(band), "fitness": fit, "route_scale": scale,
                     "simulator": ", ".join(f"{k}={x:g}" for k, x in sensors.items()) or "default",
                     "band_mps2": float(p1["band_mps2"].iloc[0]),
                     "pso_iters_mean": float(p1["pso_iters"].mean()),
                     "pso_fitness_mean_m": float(p1["pso_fitness_m"].mean()),
                     "k_pso_sd": float(p1["k_pso"].std(ddof=1)),
                     "det_over_true_steps": float(p1["det_steps"].sum() / p1["true_steps"].sum()),
                     "k_pso_min": float(p1["k_pso"].min()), "k_pso_mean": float(p1["k_pso"].mean()),
                     "k_pso_max": float(p1["k_pso"].max()), "k_closed_mean": float(p1["k_closed"].mean()),
                     "acc_pct_min": float(p1["acc_pct"].min()), "acc_pct_mean": float(p1["acc_pct"].mean()),
                     "acc_pct_max": float(p1["acc_pct"].max()),
                     "acc_vs_true_pct_mean": float(p1["acc_vs_true_pct"].mean()),
                     "gps_over_true_mean": float((p1["gps_m"] / p1["true_m"]).mean())})
    return pd.DataFrame(rows)


#: The toolkit's earlier reading (MA 2, walking-signal RMS band, walk-total fitness): the ``*_alt`` tables.
EARLIER_READING = {"prefilter": "ma2", "band": "signal", "fitness": "total"}


def run(seed: int = 0, fast: bool = False, prefilter: str = "ma2", band: str = "static",
        fitness: str = "per_step", data_dir: str | Path | None = None, real: bool = True) -> dict[str, pd.DataFrame]:
    """The two-phase experiment on the simulated walks, the compass study and the ILC k study.

    Parameters
    ----------
    seed : int
        Seed of the simulated walks and of the PSO runs.
    fast : bool
        Fewer PSO repeats, fewer compass logs, fewer ILC walks.
    prefilter : {"none", "ma1", "ma2"}
        Moving average on the walking acceleration (default MA nL=nR=2, the text's reading; module docstring).
    band : {"static", "signal"}
        Half-width of the +-RMS band: static-noise RMS (default) or the walking signal's RMS.
    fitness : {"per_step", "total"}
        Reading of eq. 4.4 for Table 5-2; the other one is summarised in ``fitness_variants``.
    data_dir : path, optional
        Folder holding ``ilc2020_site2_F4`` (None: :func:`ilocalg.io.paths.data_dir`).
    real : bool
        Run the ILC study when the data are present.

    Returns
    -------
    dict of DataFrame
        ``table_5_2`` (reproduced beside the paper), ``phase1``, ``phase2``, ``table_5_2_no_ma``,
        ``phase1_no_ma``, ``phase2_no_ma`` (the alternative reading: no moving average), ``table_5_2_alt``,
        ``phase1_alt``, ``phase2_alt`` (the toolkit's earlier reading, :data:`EARLIER_READING`),
        ``fitness_variants``, ``pso_repeat``, ``stop_rule``, ``pso_a1_swarm``, ``pso_a1_history``,
        ``pso_a1_result``, ``compass``, ``sensitivity``, ``readings``, ``comparison`` (paper_ref
        rows), ``tracks_*`` (paths for the maps), and when the ILC data are present ``ilc_walks``,
        ``ilc_summary``; ``ilc_status`` always.
    """
    _check_choice("prefilter", prefilter, PREFILTERS)
    _check_choice("band", band, BANDS)
    _check_choice("fitness", fitness, FITNESSES)
    walks = simulate_pso_walks(seed)
    old = EARLIER_READING
    p1, results, tracks1 = _phase1(walks["1"], prefilter, fitness, seed, band)
    k_by = dict(zip(p1["walker"], p1["k_pso"], strict=True))
    p2, tracks2 = _phase2(walks["2"], k_by, prefilter, seed, band)
    alt_pf = "none" if prefilter != "none" else "ma2"
    p1_noma, _, _ = _phase1(walks["1"], alt_pf, fitness, seed, band)
    p2_noma, _ = _phase2(walks["2"], dict(zip(p1_noma["walker"], p1_noma["k_pso"], strict=True)), alt_pf, seed,
                         band)
    p1_alt, _, _ = _phase1(walks["1"], old["prefilter"], old["fitness"], seed, old["band"])
    p2_alt, tracks2_alt = _phase2(walks["2"], dict(zip(p1_alt["walker"], p1_alt["k_pso"], strict=True)),
                                  old["prefilter"], seed, old["band"])
    other_fit = "total" if fitness == "per_step" else "per_step"
    p1_fit, _, _ = _phase1(walks["1"], prefilter, other_fit, seed, band)
    cols = ["walker", "k_pso", "k_closed", "k_ls", "k_scipy", "k_stop_lo", "k_stop_hi", "pso_iters", "pso_fitness_m",
            "fitness_closed_m", "pso_m", "gps_m", "acc_pct"]
    variants = pd.concat([p1[cols].assign(fitness=fitness), p1_fit[cols].assign(fitness=other_fit)],
                         ignore_index=True)
    stop_rule = p1[["walker", "k_pso", "k_closed", "k_stop_lo", "k_stop_hi", "pso_iters", "pso_stopped_by",
                    "pso_fitness_m", "fitness_closed_m"]].copy()
    stop_rule["stop_interval_width"] = stop_rule["k_stop_hi"] - stop_rule["k_stop_lo"]
    stop_rule["k_pso_minus_closed"] = stop_rule["k_pso"] - stop_rule["k_closed"]
    n_rep = 5 if fast else 50
    rep = pd.concat([_pso_repeat(walks["1"], pf, f, seed, n_rep, b)
                     for pf, b in ((prefilter, band), (old["prefilter"], old["band"]))
                     for f in FITNESSES], ignore_index=True)
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
    lab = f"({prefilter}, {band} band, {fitness} fitness)"
    rows = _comparison(t52, p2, compass, lab)
    t52_noma = _paper_table(p1_noma)
    rows += _comparison(t52_noma, p2_noma, compass, f"({alt_pf}, {band} band, {fitness} fitness)", lab,
                        note="alternative reading: " + ("no moving average on the walking acceleration (L692, "
                                                        "L718 read as the compass's only)" if alt_pf == "none"
                                                        else "MA nL=nR=2 before detection (the text's, L692/L718)"))
    rows += _comparison(t52_alt, p2_alt, compass, "(earlier reading: MA 2, signal band, walk total)", lab,
                        note="alternative reading: the toolkit's earlier one (walking-signal RMS band, walk-total "
                             "fitness)")
    rows += _compass_rows(compass)
    out = {
        "table_5_2": t52, "phase1": p1, "phase2": p2, "table_5_2_alt": t52_alt, "phase1_alt": p1_alt,
        "phase2_alt": p2_alt, "table_5_2_no_ma": t52_noma, "phase1_no_ma": p1_noma, "phase2_no_ma": p2_noma,
        "fitness_variants": variants, "pso_repeat": rep, "stop_rule": stop_rule,
        "pso_a1_swarm": a1.swarm_table(), "pso_a1_history": a1.history_table(), "pso_a1_result": a1_block,
        "compass": compass, "compass_example": out_log,
        "static_band": pd.DataFrame([{"prefilter": pf, "static_rms_mps2": static_band_mps2(seed, pf)}
                                     for pf in PREFILTERS]),
        "sensitivity": sensitivity(seed),
        "readings": readings(prefilter, band, fitness),
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
    a1_steps = detect_walk_steps(a1w, prefilter, _band(seed, prefilter, band))
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
    out["measures"] = _measures(p1, p2, walks["2"], prefilter, _band(seed, prefilter, band))
    return out


def _measures(p1: pd.DataFrame, p2: pd.DataFrame, walks2: list[Walk], prefilter: str, band_mps2) -> pd.DataFrame:
    """Named scalars for the claims ledger (ilocalg.papers.pso): Table 5-2 summaries, A1's phase-2 closures, and
    the great-circle dead reckoning (eq. 3.1-3.3) against a flat-earth sum of the same steps."""
    leg94 = p1.loc[p1["leg_cm"] == 94, "k_pso"]
    rows = [("mean k (PSO)", p1["k_pso"].mean(), "", ""), ("min k (PSO)", p1["k_pso"].min(), "", ""),
            ("max k (PSO)", p1["k_pso"].max(), "", ""),
            ("k range among the 94 cm walkers", leg94.max() - leg94.min(), "", ""),
            ("mean |detected - true| / true steps", 100 * (abs(p1["det_steps"] - p1["true_steps"])
                                                          / p1["true_steps"]).mean(), "%", ""),
            ("mean accuracy vs GPS", p1["acc_pct"].mean(), "%", ""),
            ("phase 2 mean |distance error| vs true route, PSO k", p2["pso_dist_err_pct"].abs().mean(), "%", ""),
            ("phase 2 mean |distance error| vs true route, k = 0.5", p2["tar_dist_err_pct"].abs().mean(), "%", "")]
    for r in p2[p2["walker"] == "A1"].itertuples():
        item = f"A1 {r.place}"
        rows += [("closure, PSO k", r.pso_closure_m, "m", item), ("closure, k = 0.5", r.tar_closure_m, "m", item),
                 ("closure / PSO path length", r.pso_closure_pct, "%", item),
                 ("GPS / PSO path length", r.gps_m / r.pso_m, "ratio", item)]
    dev = 0.0
    for w, k in ((w, p2.loc[p2["walker"] == w.walker, "k_pso"].iloc[0]) for w in walks2 if w.walker == "A1"):
        st = detect_walk_steps(w, prefilter, band_mps2)
        tr = dr_track(w, st, k)
        L = weinberg_length_m(st["a_max_mps2"].to_numpy(float), st["a_min_mps2"].to_numpy(float), k)
        h = np.deg2rad(step_headings_deg(w.imu, st))
        x0, y0 = tr["x_m"].iloc[0], tr["y_m"].iloc[0]
        xf = np.r_[x0, x0 + np.cumsum(L * np.sin(h))]
        yf = np.r_[y0, y0 + np.cumsum(L * np.cos(h))]
        dev = max(dev, float(np.max(np.hypot(tr["x_m"] - xf, tr["y_m"] - yf))))
    rows.append(("great-circle vs flat dead reckoning, max difference", dev, "m", "A1 phase 2"))
    return pd.DataFrame([{"quantity": q, "value": float(v), "unit": u, "item": i} for q, v, u, i in rows])
