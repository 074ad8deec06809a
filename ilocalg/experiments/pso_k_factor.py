"""PSO learning of the Weinberg step-length factor against GPS: Chao (2008)'s two-phase experiment.

Phase 1 (good sky, straight or looped walk): detect steps by slope sign change (Fig. 3.9) on the
vertical acceleration, measure the walk's length from the 1 Hz GPS track (haversine sum), and learn
the walker's ``k`` by PSO on the fitness of eq. 4.4 with the Weinberg length ``k (Amax - Amin)^(1/4)``
(eq. 2.5; :mod:`ilocalg.pdr.k_factor`). Phase 2 (partly shaded loops): dead-reckon with the learned
``k`` and the compass heading on latitude/longitude (eq. 3.1-3.3) from the first GPS fix, and report
the start-end (closure) distance beside the fixed ``k = 0.5`` of the thesis ("TAR").

Readings: every modelling choice (the MA before detection by default, L692/L718; the +-RMS band from the
static-noise RMS; eq. 4.4 per step; Table 5-2's accuracy on the learning walk; the stop rule) is declared
with its thesis line in :mod:`ilocalg.papers.readings_pso` and returned as the ``readings`` table. The walk
pipeline (steps, headings, great-circle dead reckoning, the ILC k study) is :mod:`ilocalg.pdr.k_walks`.

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

from ilocalg.gnss import gps_track_length_m, latlon_to_local_m, path_length_m
from ilocalg.papers import PAPERS
from ilocalg.papers.comparison_pso import comparison_rows, compass_rows, fig_5_12_block, table_5_2
from ilocalg.papers.pso import K_FIXED_PAPER, PAPER_COMPASS_RMS, PAPER_PHASE2_A1, PAPER_TABLE_5_2
from ilocalg.papers.readings_pso import SENSITIVITY_VARIANTS
from ilocalg.papers.readings_pso import readings as _readings
from ilocalg.pdr import k_walks
from ilocalg.pdr.filters import moving_average, rms, savitzky_golay
from ilocalg.pdr.k_factor import FITNESSES, PSO_SETTINGS_PAPER, learn_k, learn_k_repeats
from ilocalg.pdr.k_walks import PREFILTERS
from ilocalg.pdr.step_length import k_from_distance, weinberg_length_m
from ilocalg.sim import pso_walks as sim
from ilocalg.sim.pso_walks import SENSORS, Walk, simulate_pso_walks

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
    "static_band_mps2",
    "readings",
    "sensitivity",
    "compass_filter_study",
    "run",
]

#: Source label of the comparison rows (kept as in earlier result tables, which must stay byte-identical).
PAPER = PAPERS["pso"]
# The published values (PAPER_TABLE_5_2, PAPER_PHASE2_A1, PAPER_COMPASS_RMS, K_FIXED_PAPER) are declared once in
# ilocalg.papers.pso and re-exported here.

#: Half-width of the +-RMS band: the static-noise RMS (default) or the walking signal's RMS.
BANDS = ("static", "signal")
#: True route length over the thesis's GPS distance, swept by :func:`sensitivity` (1.0 is the default).
ROUTE_SCALES = (0.95, 1.05)


def _check_choice(name, value, allowed):
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")


def static_band_mps2(seed: int = 0, prefilter: str = "ma2", sensors: dict | None = None) -> float:
    """Static-noise RMS of the device's accelerometer (eq. 3.4), after the walk's pre-filter.

    A 60 s static log (device on a table, the thesis's static calibration, sec. 5.1.3) from
    :func:`ilocalg.sim.pso_walks.simulate_static_acc`, one per run (one device); ``sensors``
    overrides the simulator's settings (e.g. the accelerometer noise).
    """
    k_walks.check_prefilter(prefilter)
    log = sim.simulate_static_acc(np.random.default_rng([seed, 54]), sensors=sensors)
    return k_walks.static_band_mps2(log["acc_z_mps2"].to_numpy(), prefilter)


def _steps(walk: Walk, prefilter: str, band_mps2) -> pd.DataFrame:
    return k_walks.detect_walk_steps(walk.imu, prefilter, band_mps2)


def _track(walk: Walk, steps: pd.DataFrame, k: float) -> pd.DataFrame:
    return k_walks.dr_track(walk.imu, walk.gps, steps, k, walk.origin_deg, f"{walk.walker}/{walk.place}")


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
        y = sim.simulate_static_compass(np.random.default_rng(child))["yaw_deg"].to_numpy()
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
        st = _steps(w, prefilter, b)
        d_gps = gps_track_length_m(w.gps)
        summ, res = learn_k(st, d_gps, fitness, rng=np.random.default_rng([seed, 10, i]))
        tr = _track(w, st, summ["k_pso"])
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
            "start_end_m": k_walks.closure_m(tr),
            "acc_pct": 100 * (1 - abs(d_gps - pso_m) / d_gps),
            "acc_vs_true_pct": 100 * (1 - abs(w.route_m - pso_m) / w.route_m),
        })
        results[w.walker] = res
        tracks[w.walker] = tr
    return pd.DataFrame(rows), results, tracks


def _phase2(walks: list[Walk], k_by_walker: dict, prefilter: str, seed: int, band: str = "static",
            sensors: dict | None = None):
    rows, tracks = [], {}
    b = _band(seed, prefilter, band, sensors)
    for w in walks:
        st = _steps(w, prefilter, b)
        k = k_by_walker[w.walker]
        tr_pso = _track(w, st, k)
        tr_tar = _track(w, st, K_FIXED_PAPER)
        pso_m = path_length_m(tr_pso["lat_deg"].to_numpy(), tr_pso["lon_deg"].to_numpy())
        tar_m = path_length_m(tr_tar["lat_deg"].to_numpy(), tr_tar["lon_deg"].to_numpy())
        gps_m = gps_track_length_m(w.gps, max_gap_s=np.inf)
        gaps = np.diff(w.gps["t_s"].to_numpy())
        c_pso, c_tar = k_walks.closure_m(tr_pso), k_walks.closure_m(tr_tar)
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
                band: str = "static", sensors: dict | None = None) -> pd.DataFrame:
    """PSO from ``n_rep`` seeds per walker beside the closed-form minimiser of the same fitness."""
    rows = []
    b = _band(seed, prefilter, band, sensors)
    for i, w in enumerate(walks):
        st = _steps(w, prefilter, b)
        d_gps = gps_track_length_m(w.gps)
        # learn_k from each seed: the swarms in one pass, the seed-independent references once
        s, runs = learn_k_repeats(st, d_gps, fitness, [np.random.default_rng([seed, 20, i, r]) for r in range(n_rep)])
        ks = np.asarray([float(res.x_best[0]) for res in runs])
        iters = [res.n_iters for res in runs]
        rows.append({"walker": w.walker, "prefilter": prefilter, "band": band, "fitness": fitness, "n_runs": n_rep,
                     "k_closed": s["k_closed"], "k_stop_lo": s["k_stop_lo"], "k_stop_hi": s["k_stop_hi"],
                     "k_pso_mean": ks.mean(), "k_pso_sd": ks.std(ddof=1) if n_rep > 1 else 0.0,
                     "max_abs_dev_from_closed": float(np.max(np.abs(ks - s["k_closed"]))),
                     "iters_mean": float(np.mean(iters)), "iters_max": int(np.max(iters)),
                     "share_converged": float(np.mean(np.asarray(iters) < PSO_SETTINGS_PAPER["max_iters"]))})
    return pd.DataFrame(rows)


def readings(prefilter: str = "ma2", band: str = "static", fitness: str = "per_step", route_scale: float = 1.0,
             **sensors) -> pd.DataFrame:
    """One row per modelling choice of :func:`run` (declared in :mod:`ilocalg.papers.readings_pso`); ``sensors``
    overrides :data:`ilocalg.sim.pso_walks.SENSORS` as in the run."""
    S = {**SENSORS, **sensors}
    return _readings(prefilter, band, fitness, S, route_scale, ROUTE_SCALES,
                     sim.gps_static_sd_m(S["gps_static_95_m"]))


def sensitivity(seed: int = 0, variants=SENSITIVITY_VARIANTS, _default=None) -> pd.DataFrame:
    """Table 5-2 summarised for every reading: the default and the labelled alternatives.

    Returns one row per variant: the share of true steps detected, the PSO's k (min, mean, max), the
    closed-form minimiser's mean, the accuracy vs GPS (min, mean, max) and vs the true distance, the
    PSO's iterations and best fitness (means over walkers), the band used and the GPS/true distance.
    ``_default`` (from :func:`run`): ``(phase-1 walks, {(prefilter, band, fitness): phase-1 table})`` of the default
    simulator (route scale 1, default sensors) at ``seed``, already computed: used, not computed again.
    """
    rows = []
    cache = {}
    done = {}
    if _default is not None:
        cache[(1.0, ())] = _default[0]
        done = {(1.0, ()) + k: v for k, v in _default[1].items()}
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
        p1 = done.get(key + (pf, band, fit))
        if p1 is None:
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
        fitness: str = "per_step", data_dir: str | Path | None = None, real: bool = True,
        acc_noise_mps2: float = SENSORS["acc_noise_mps2"], step_amp_cv: float = SENSORS["step_amp_cv"],
        step_cv: float = SENSORS["step_cv"], gps_open_tau_s: float = SENSORS["gps_open_tau_s"],
        gps_static_95_m: float = SENSORS["gps_static_95_m"], route_scale: float = 1.0,
        side_studies: bool = True) -> dict[str, pd.DataFrame]:
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
    acc_noise_mps2, step_amp_cv, step_cv, gps_open_tau_s, gps_static_95_m : float
        The simulated walks' values the thesis does not fix (:data:`ilocalg.sim.pso_walks.SENSORS`, sources in
        the readings table): accelerometer noise (the band follows), per-step amplitude scatter, step length and
        duration CV, the open-sky GPS error's correlation time and its 95 % bound (the text: better than 1.5 m).
    route_scale : float
        True route length over the thesis's GPS distance.
    side_studies : bool
        False leaves out the side studies no comparison row or measure is computed from: the other eq. 4.4
        reading (``fitness_variants``), the PSO repeats (``pso_repeat``), the readings' ``sensitivity`` and the
        ILC k study (``ilc_walks``, ``ilc_summary``, ``ilc_status``); the tables returned are the same either way.
        The seed sweep and the claims' robustness samples read none of them
        (:data:`ilocalg.workflow.manifest.SWEEP_KWARGS`).

    Returns
    -------
    dict of DataFrame
        ``table_5_2`` (reproduced beside the paper), ``phase1``, ``phase2``, ``table_5_2_no_ma``,
        ``phase1_no_ma``, ``phase2_no_ma`` (the alternative reading: no moving average), ``table_5_2_alt``,
        ``phase1_alt``, ``phase2_alt`` (the toolkit's earlier reading, :data:`EARLIER_READING`),
        ``fitness_variants``, ``pso_repeat``, ``stop_rule``, ``pso_a1_swarm``, ``pso_a1_history``,
        ``pso_a1_result``, ``compass``, ``sensitivity``, ``readings``, ``comparison`` (paper_ref
        rows), ``tracks_*`` (paths for the maps), and when the ILC data are present ``ilc_walks``,
        ``ilc_summary``; ``ilc_status`` always (with ``side_studies``).
    """
    _check_choice("prefilter", prefilter, PREFILTERS)
    _check_choice("band", band, BANDS)
    _check_choice("fitness", fitness, FITNESSES)
    given = {"acc_noise_mps2": acc_noise_mps2, "step_amp_cv": step_amp_cv, "step_cv": step_cv,
             "gps_open_tau_s": gps_open_tau_s, "gps_static_95_m": gps_static_95_m}
    sv = {k: float(v) for k, v in given.items() if v != SENSORS[k]} or None  # only the changed settings
    walks = simulate_pso_walks(seed, route_scale=route_scale, sensors=sv)
    old = EARLIER_READING
    p1, results, tracks1 = _phase1(walks["1"], prefilter, fitness, seed, band, sv)
    k_by = dict(zip(p1["walker"], p1["k_pso"], strict=True))
    p2, tracks2 = _phase2(walks["2"], k_by, prefilter, seed, band, sv)
    alt_pf = "none" if prefilter != "none" else "ma2"
    p1_noma, _, _ = _phase1(walks["1"], alt_pf, fitness, seed, band, sv)
    p2_noma, _ = _phase2(walks["2"], dict(zip(p1_noma["walker"], p1_noma["k_pso"], strict=True)), alt_pf, seed,
                         band, sv)
    p1_alt, _, _ = _phase1(walks["1"], old["prefilter"], old["fitness"], seed, old["band"], sv)
    p2_alt, tracks2_alt = _phase2(walks["2"], dict(zip(p1_alt["walker"], p1_alt["k_pso"], strict=True)),
                                  old["prefilter"], seed, old["band"], sv)
    variants = None
    if side_studies:
        other_fit = "total" if fitness == "per_step" else "per_step"
        p1_fit, _, _ = _phase1(walks["1"], prefilter, other_fit, seed, band, sv)
        cols = ["walker", "k_pso", "k_closed", "k_ls", "k_scipy", "k_stop_lo", "k_stop_hi", "pso_iters",
                "pso_fitness_m", "fitness_closed_m", "pso_m", "gps_m", "acc_pct"]
        variants = pd.concat([p1[cols].assign(fitness=fitness), p1_fit[cols].assign(fitness=other_fit)],
                             ignore_index=True)
    # the phase-1 tables of the default simulator computed here, for the sensitivity rows of the same readings
    default = (walks["1"], {(prefilter, band, fitness): p1, (alt_pf, band, fitness): p1_noma,
                            (old["prefilter"], old["band"], old["fitness"]): p1_alt}
               ) if route_scale == 1.0 and sv is None else None
    if default is not None and variants is not None:
        default[1][(prefilter, band, other_fit)] = p1_fit
    stop_rule = p1[["walker", "k_pso", "k_closed", "k_stop_lo", "k_stop_hi", "pso_iters", "pso_stopped_by",
                    "pso_fitness_m", "fitness_closed_m"]].copy()
    stop_rule["stop_interval_width"] = stop_rule["k_stop_hi"] - stop_rule["k_stop_lo"]
    stop_rule["k_pso_minus_closed"] = stop_rule["k_pso"] - stop_rule["k_closed"]
    n_rep = 5 if fast else 50
    rep = (pd.concat([_pso_repeat(walks["1"], pf, f, seed, n_rep, b, sv)
                      for pf, b in ((prefilter, band), (old["prefilter"], old["band"]))
                      for f in FITNESSES], ignore_index=True) if side_studies else None)
    a1 = results["A1"]
    a1_block = fig_5_12_block(a1, p1.iloc[0])
    compass = compass_filter_study(seed, fast)
    log = sim.simulate_static_compass(np.random.default_rng([seed, 53]))
    y = log["yaw_deg"].to_numpy()
    out_log = pd.DataFrame({"t_s": log["t_s"], "raw_deg": y, "ma_deg": moving_average(y, 2, 2),
                            "sg_deg": savitzky_golay(y, 2, 2, 2)})
    t52 = table_5_2(p1)
    t52_alt = table_5_2(p1_alt)
    lab = f"({prefilter}, {band} band, {fitness} fitness)"
    rows = comparison_rows(t52, p2, lab, route_scale=route_scale)
    t52_noma = table_5_2(p1_noma)
    rows += comparison_rows(t52_noma, p2_noma, f"({alt_pf}, {band} band, {fitness} fitness)", lab,
                            note="alternative reading: " + (
                                "no moving average on the walking acceleration (L692, L718 read as the compass's "
                                "only)" if alt_pf == "none" else "MA nL=nR=2 before detection (the text's, L692/L718)"),
                            route_scale=route_scale)
    rows += comparison_rows(t52_alt, p2_alt, "(earlier reading: MA 2, signal band, walk total)", lab,
                            note="alternative reading: the toolkit's earlier one (walking-signal RMS band, walk-total "
                                 "fitness)", route_scale=route_scale)
    rows += compass_rows(compass)
    out = {
        "table_5_2": t52, "phase1": p1, "phase2": p2, "table_5_2_alt": t52_alt, "phase1_alt": p1_alt,
        "phase2_alt": p2_alt, "table_5_2_no_ma": t52_noma, "phase1_no_ma": p1_noma, "phase2_no_ma": p2_noma,
        "fitness_variants": variants, "pso_repeat": rep, "stop_rule": stop_rule,
        "pso_a1_swarm": a1.swarm_table(), "pso_a1_history": a1.history_table(), "pso_a1_result": a1_block,
        "compass": compass, "compass_example": out_log,
        "static_band": pd.DataFrame([{"prefilter": pf, "static_rms_mps2": static_band_mps2(seed, pf, sv)}
                                     for pf in PREFILTERS]),
        "sensitivity": sensitivity(seed, _default=default) if side_studies else None,
        "readings": readings(prefilter, band, fitness, route_scale, **(sv or {})),
    }
    out = {name: df for name, df in out.items() if df is not None}  # side studies left out (side_studies=False)
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
    a1_steps = _steps(a1w, prefilter, _band(seed, prefilter, band, sv))
    out["a1_signal"] = a1w.imu.assign(acc_ma_mps2=moving_average(a1w.imu["acc_z_mps2"].to_numpy(), 2, 2))
    out["a1_steps"] = a1_steps
    # real data
    from ilocalg.io.paths import dataset_path
    ilc = Path(data_dir) / "ilc2020_site2_F4" if data_dir is not None else dataset_path("ilc2020_site2_F4")
    status = {"dataset": "ilc2020_site2_F4", "path": str(ilc), "present": ilc.is_dir(), "ran": False}
    if side_studies:
        if real and ilc.is_dir():
            res = k_walks.ilc_k_study(ilc, seed, fast, k_fixed=K_FIXED_PAPER)
            out["ilc_walks"] = res["walks"]
            out["ilc_summary"] = res["summary"]
            status["ran"] = True
        out["ilc_status"] = pd.DataFrame([status])
    out["comparison"] = pd.DataFrame(rows)
    out["measures"] = _measures(p1, p2, walks["2"], prefilter, _band(seed, prefilter, band, sv))
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
        st = _steps(w, prefilter, band_mps2)
        tr = _track(w, st, k)
        L = weinberg_length_m(st["a_max_mps2"].to_numpy(float), st["a_min_mps2"].to_numpy(float), k)
        h = np.deg2rad(k_walks.step_headings_deg(w.imu, st))
        x0, y0 = tr["x_m"].iloc[0], tr["y_m"].iloc[0]
        xf = np.r_[x0, x0 + np.cumsum(L * np.sin(h))]
        yf = np.r_[y0, y0 + np.cumsum(L * np.cos(h))]
        dev = max(dev, float(np.max(np.hypot(tr["x_m"] - xf, tr["y_m"] - yf))))
    rows.append(("great-circle vs flat dead reckoning, max difference", dev, "m", "A1 phase 2"))
    return pd.DataFrame([{"quantity": q, "value": float(v), "unit": u, "item": i} for q, v, u, i in rows])
