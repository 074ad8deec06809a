"""Scoring a walk: every estimator's track at the ground-truth points, the error tables."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from ilocalg.fusion import filter_walk, fixes_at_states, rts_smooth
from ilocalg.fusion.heading_offset import fit_track_to_fixes, rotate_xy
from ilocalg.fusion.map_align import map_align
from ilocalg.fusion.particle_filter import OccupancyGrid, map_particle_filter
from ilocalg.io.recording import (
    as_recording,
    common_frame,
)
from ilocalg.io.schema import FLOOR, T_S, X_M, Y_M
from ilocalg.metrics import penalised_error_m
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.step_length import weinberg_length_m
from ilocalg.track._config import (
    CAUSAL_METHODS,
    DEFAULT_CONFIG,
    GAIN_METHODS,
    GRID_METHODS,
    METHODS,
    PATH_METHODS,
    RealWalkConfig,
)
from ilocalg.track.database import WifiDatabase
from ilocalg.track.estimators import ESTIMATORS, STATES_USED_METHODS, TrackProblem
from ilocalg.track.fixes import (
    FixVarModel,
    calibrate_fix_var,
    estimate_floors,
    fix_error_correlation,
    log_variance_fit,
    loo_fix_features,
    select_wifi,
    wifi_fixes,
)
from ilocalg.track.grid import bend_track, grid_queries, off_grid_share, survey_points
from ilocalg.track.motion import (
    Calibration,
    GainStats,
    WalkSteps,
    _track_at,
    calibrate,
    calibrate_step_var,
    gain_stats,
    step_intervals,
    walk_steps,
)
from ilocalg.track.paths import WalkedPaths
from ilocalg.units import as_rng, wrap_angle_rad


def _latest_fix(fix_t, fix_xy, t_s):
    i = np.clip(np.searchsorted(fix_t, t_s, side="right") - 1, 0, fix_t.size - 1)
    return fix_xy[i]


def evaluate_walk(trace, db: WifiDatabase, calibration: Calibration, fix_var_m2: float,
                  cfg: RealWalkConfig = DEFAULT_CONFIG, grid: OccupancyGrid | None = None,
                  steps: WalkSteps | None = None, rng=None, methods=METHODS, step_var_m2: float | None = None,
                  gain: GainStats | None = None, fix_var_model: FixVarModel | None = None,
                  paths: WalkedPaths | None = None, loo_fixes: tuple | None = None,
                  path_var_m2: float | None = None, score_only: bool = False, survey=None) -> dict:
    """Score every track of :data:`METHODS` at the ground-truth points of ``trace``.

    ``db``, ``calibration`` and ``fix_var_m2`` must come from other walks (see :func:`evaluate_track`,
    which builds them from walk files); ``db`` containing the walk (by name or sensor content) raises.
    ``grid``: the floor's walkable raster (:meth:`OccupancyGrid.from_floor_map`), needed by
    ``map_align`` and ``lsq*_map``; the particle filter runs unconstrained without it. ``step_var_m2``:
    the per-step PDR displacement variance of the least-squares estimators
    (:func:`ilocalg.track.motion.calibrate_step_var` on the other walks; default ``cfg.sigma_sl_m**2``).
    ``gain``: the spread of a walk's own step scale and heading offset (:func:`ilocalg.track.motion.gain_stats`
    on the other walks), needed by the ``kf_gain*`` methods. ``fix_var_model``: each fix's own variance
    (:class:`~ilocalg.track.fixes.FixVarModel`); when None and ``cfg.fix_var == "per_fix"`` it is fitted on
    ``db`` (:func:`~ilocalg.track.fixes.fit_fix_var_model`), every method then weighting each fix by it;
    ``fix_var_m2`` is the one variance of ``cfg.fix_var == "isotropic"``. ``paths``: the walked-path graph of
    the database walks' waypoints (:class:`~ilocalg.track.paths.WalkedPaths`, without the scored walk: one
    that holds it raises), needed by :data:`~ilocalg.track.PATH_METHODS`; when None they use the graph of
    ``db``'s scan positions (:meth:`~ilocalg.track.paths.WalkedPaths.from_database`). ``loo_fixes``: the database
    walks' leave-one-walk-out fixes the per-fix variance and the fix-error correlation are fitted on, when already
    computed (:func:`~ilocalg.track.fixes.loo_fix_features` of ``db`` with ``cfg``, e.g.
    :attr:`ilocalg.track.floor.WalkModel.loo_fixes`, kept with the floor model); None: computed here.
    ``path_var_m2``: the graph's spread when already measured (:attr:`ilocalg.track.floor.WalkModel.path_var_m2`,
    kept with the floor model); None: :meth:`~ilocalg.track.paths.WalkedPaths.spread_var_m2` here.
    ``score_only``: the tracks are needed only at the ground-truth points (a leave-one-walk-out sweep): the
    estimators that can (the causal least squares, :data:`~ilocalg.track.estimators.STATES_USED_METHODS`) compute
    only the states around them (:attr:`~ilocalg.track.estimators.TrackProblem.states_used`), their other states
    NaN in ``tracks``, and ``track`` is None; the errors are the same numbers. :func:`complete_tracks` gives the
    ``track`` table of such a result, every state computed.
    ``survey``: the walked-path graph of the database walks' *waypoints* whose ends are the marked points the
    :data:`~ilocalg.track.GRID_METHODS` move a query onto (:mod:`ilocalg.track.grid`; without the scored walk: one
    that holds it raises); None: ``paths`` when given. Those variants are located at the query times, the walk's
    ground-truth times, and need such a graph (a database's scan positions are not marked points).

    Returns
    -------
    dict
        ``errors`` (DataFrame: one row per ground-truth point, one column per method, metres),
        ``tracks`` (method -> (n+1, 2) states), ``state_t_s``, ``fixes`` (WifiFixes), ``info`` (dict),
        ``scans`` (counts of the scans left out), ``floors`` (DataFrame per ground-truth point:
        ``floor_true`` and one column per method, or None without floor numbers), ``problem`` (the
        :class:`~ilocalg.track.estimators.TrackProblem` the least-squares and ``kf_gain*`` methods solved, or
        None when none was asked for), ``track`` (long
        DataFrame ``t_s, method, x_m, y_m, floor`` of every state, :func:`track_table`; None with ``score_only``),
        ``state_floor`` (method -> floor estimate per state, empty without floor numbers), ``grid`` (method of
        :data:`~ilocalg.track.GRID_METHODS` -> ``(query times, positions, on a marked point)``). ``errors``
        also has ``oracle_shape_m``: a diagnostic (the track fitted onto the walk's own waypoints),
        never a method.

    References
    ----------
    Chiu (2013), eq. 20-26 (the step Kalman filter); Rauch, Tung, Striebel (1965); Huber (1981), the
    robust placement of the track on the fixes.
    """
    unknown = set(methods) - set(METHODS)
    if unknown:
        raise ValueError(f"unknown methods {sorted(unknown)}; known: {METHODS}")
    rec = as_recording(trace)
    if db.frame is not None and len(rec.truth):
        rec = rec.in_frame(db.frame)
    if len(rec.truth) < 1:
        raise ValueError(f"{rec.source or rec.name}: no ground-truth point to score")
    grid_names = [m for m in methods if m in GRID_METHODS]
    if grid_names:
        survey = paths if survey is None else survey
        if survey is None:
            raise ValueError(f"{grid_names} need the walked-path graph of the database walks' waypoints (survey=)")
        if rec.name in set(survey.walk):
            raise ValueError(f"the surveyed points must not include the scored walk {rec.name!r}")
    scored_methods = tuple(methods)
    # the grid variants' base tracks are computed too (scored only when asked for)
    methods = tuple(dict.fromkeys([*methods, *(GRID_METHODS[m] for m in grid_names)]))
    cal = calibration
    fv_note, fix_corr = "isotropic", None
    if (fix_var_model is None and cfg.fix_var == "per_fix") or cfg.fix_corr:
        try:
            # the database walks' own leave-one-walk-out fixes
            err, feats = loo_fix_features(db, cfg) if loo_fixes is None else loo_fixes
            if fix_var_model is None and cfg.fix_var == "per_fix":
                fix_var_model = log_variance_fit((err ** 2).sum(axis=1), feats)
            if cfg.fix_corr:
                fix_corr = fix_error_correlation(err, db.walk)
        except ValueError as e:       # too few database scans (or a non-Euclidean WKNN): one variance for all
            fv_note = f"isotropic ({e})"
    if fix_var_model is not None:
        fv_note = "per_fix"
    fx = wifi_fixes(rec, db, cfg, fix_var_m2=fix_var_m2, fix_var_model=fix_var_model)
    fvar = fix_var_m2 if fx.var_m2 is None else fx.var_m2
    ws = steps or walk_steps(rec, cfg)
    if ws.a_range_mps2.size < 1:
        raise ValueError(f"{rec.name}: no step detected")
    d = weinberg_length_m(ws.a_range_mps2, np.zeros_like(ws.a_range_mps2), cal.k_weinberg)
    th = wrap_angle_rad(ws.theta_rel_rad + cal.offset_rad)
    ts = ws.state_t_s
    # fixes before the first state go onto state 0 (t is clamped); several on one state: the latest
    al = fixes_at_states(ts, np.maximum(fx.t_s, ts[0]), fx.xy_m, fx.R_m2, same_state="last")
    nanR = np.isnan(al.R_m2)
    z, R = al.z_m, np.where(nanR, np.eye(2), al.R_m2)
    x0, P0 = fx.xy_m[0], fx.R_m2[0]
    z_kf = z.copy()
    if al.used[0] and al.state_index[0] == 0:
        z_kf[0] = np.nan           # the first fix is the start; not used twice
    wp = rec.truth
    tw = wp[T_S].to_numpy()
    true = wp[[X_M, Y_M]].to_numpy()
    tracks = {"pdr": dead_reckon(d, th, *x0)[["x_m", "y_m"]].to_numpy()}
    res = filter_walk(x0, P0, th, d, cfg.sigma_sl_m, z_kf, R_m2=R, sigma_theta_rad=cfg.sigma_heading_rad)
    tracks["kf"] = res.x
    tracks["kf_rts"] = rts_smooth(res).x
    rel = dead_reckon(d, th)[["x_m", "y_m"]].to_numpy()       # floor offset, from the origin
    at_fix = _track_at(ts, rel, fx.t_s)
    if fx.t_s.size >= 2:            # Huber-robust start with the heading held fixed
        t0 = fit_track_to_fixes(at_fix, fx.xy_m, huber_m=cfg.huber_m, rotation=False).t_m
    else:
        t0 = fx.xy_m[0] - at_fix[0]
    tracks["aligned"] = rel + t0
    ra = filter_walk(t0, P0, th, d, cfg.sigma_sl_m, z, R_m2=R, sigma_theta_rad=cfg.sigma_heading_rad)
    tracks["aligned_kf_rts"] = rts_smooth(ra).x
    info = {"n_steps": int(d.size), "n_fixes": int(fx.t_s.size), "k_weinberg": cal.k_weinberg,
            "floor_offset_deg": float(np.degrees(cal.offset_rad)), "fix_sd_m": float(np.sqrt(np.mean(fvar))),
            "fix_var": fv_note, "fix_corr_c0": np.nan if fix_corr is None else fix_corr[0],
            "fix_corr_rho": np.nan if fix_corr is None else fix_corr[1],
            "fix_corr_sd_m": np.nan if fix_corr is None else float(np.sqrt(fix_corr[2]))}
    if fx.t_s.size >= 3:
        fit = fit_track_to_fixes(at_fix, fx.xy_m, huber_m=cfg.huber_m)
        tracks["aligned_rot"] = rotate_xy(rel, fit.angle_rad) + fit.t_m
        info["walk_offset_from_wifi_deg"] = float(np.degrees(fit.angle_rad))
    else:                           # too few fixes to fit a rotation: translation only
        tracks["aligned_rot"] = tracks["aligned"]
        info["walk_offset_from_wifi_deg"] = np.nan
    if "pf" in methods or "pf_smooth" in methods:
        pf = map_particle_filter(x0, P0, th, d, z_kf, R, grid=grid, n_particles=cfg.n_particles, rng=as_rng(rng),
                                 sigma_heading_rad=cfg.pf_sigma_heading_rad,
                                 sigma_offset0_rad=cfg.pf_sigma_offset0_rad, outlier_prob=cfg.pf_outlier_prob,
                                 blocked_weight=cfg.pf_blocked_weight, recovery=cfg.pf_recovery)
        tracks["pf"], tracks["pf_smooth"] = pf.x, pf.x_smooth
        info.update(pf_resamples=pf.n_resample, pf_resets=pf.n_reset, pf_injected=pf.n_injected)
    if "map_align" in methods or "map_align_kf_rts" in methods:
        if grid is None:
            raise ValueError("map_align needs the floor map (grid)")
        g1 = grid.coarsen(1.0)
        used = al.used
        ma = map_align(rel, al.state_index[used], fx.xy_m[used], np.broadcast_to(fvar, fx.t_s.shape)[used], g1,
                       sigma_angle_rad=cfg.pf_sigma_offset0_rad, outlier_prob=cfg.pf_outlier_prob,
                       blocked_weight=cfg.pf_blocked_weight)
        tracks["map_align"] = ma.track_m
        th_m = wrap_angle_rad(th + ma.angle_rad)
        rm = filter_walk(ma.t_m, P0, th_m, d, cfg.sigma_sl_m, z, R_m2=R, sigma_theta_rad=cfg.sigma_heading_rad)
        tracks["map_align_kf_rts"] = rts_smooth(rm).x
        info.update(map_align_offset_deg=float(np.degrees(ma.angle_rad)), map_align_off_map=ma.off_map)
    lsq_names = [m for m in methods if m in ESTIMATORS]
    if grid is None and any(ESTIMATORS[m].needs_map for m in lsq_names):
        raise ValueError(f"{[m for m in lsq_names if ESTIMATORS[m].needs_map]} need the floor map (grid)")
    prob = None
    if any(m in PATH_METHODS for m in lsq_names):
        if paths is None:
            paths = WalkedPaths.from_database(db)
        elif rec.name in set(paths.walk):
            raise ValueError(f"the walked-path graph must not include the scored walk {rec.name!r}")
    else:
        paths = None
    if lsq_names or grid_names:
        sv = cfg.sigma_sl_m ** 2 if step_var_m2 is None else step_var_m2
        # least squares: each fix constrains the walk where it was when its readings were taken
        t_fix = fx.t_s if fx.t_read_s is None or not cfg.align_fix_time else fx.t_read_s
        used = None
        if score_only:          # the states each ground-truth time is interpolated between (np.interp)
            j = np.clip(np.searchsorted(ts, tw, side="right") - 1, 0, ts.size - 1)
            used = np.unique(np.concatenate([j, np.minimum(j + 1, ts.size - 1)]))
        prob = TrackProblem(ts, np.diff(dead_reckon(d, th)[["x_m", "y_m"]].to_numpy(), axis=0), sv, t_fix, fx.xy_m,
                            fvar, grid, fix_avail_t_s=fx.t_s, gain=gain, map_start=cfg.map_start,
                            fix_corr=fix_corr, paths=paths, path_var_m2=path_var_m2, states_used=used)
        for m in lsq_names:
            tracks[m] = ESTIMATORS[m].fn(prob)
        info["step_sd_m"] = float(np.sqrt(sv))
    grid_out = {}
    if grid_names:        # located at the query times (the ground-truth times) on the database walks' marked points
        pts = survey_points(survey)
        pi = off_grid_share(survey)
        for m in grid_names:
            c = m in CAUSAL_METHODS
            xy, on = grid_queries(prob, tracks[GRID_METHODS[m]], tw, pts, pi, causal=c)
            grid_out[m] = (tw, xy, on)
            tracks[m] = bend_track(ts, tracks[GRID_METHODS[m]], tw, xy, causal=c)
        info["grid_off_share"] = pi
    for m in set(methods) - set(scored_methods):     # a base computed for a grid variant only: not reported
        tracks.pop(m, None)
    methods = scored_methods
    err = {"waypoint": np.arange(len(wp)), "t_s": tw}
    # diagnostic only, not a method: the PDR track rigidly fitted onto this walk's own waypoints (how good
    # the track's shape is; the remaining error of every method is mostly its placement)
    if len(wp) >= 2:
        ofit = fit_track_to_fixes(_track_at(ts, rel, tw), true, huber_m=None)
        err["oracle_shape_m"] = np.hypot(*(_track_at(ts, rotate_xy(rel, ofit.angle_rad) + ofit.t_m, tw) - true).T)
    else:
        err["oracle_shape_m"] = np.zeros(len(wp))
    for m in methods:
        if m == "wifi":
            est = _latest_fix(fx.t_s, fx.xy_m, tw)
        elif m in grid_out:
            est = grid_out[m][1]
        else:
            est = _track_at(ts, tracks[m], tw)
        err[m] = np.hypot(*(est - true).T)
    fe = np.hypot(*(fx.xy_m - fx.true_xy_m).T)
    info["fix_mean_error_m"] = float(np.nanmean(fe)) if np.isfinite(fe).any() else np.nan
    info["first_fix_error_m"] = float(fe[0])
    fest = estimate_floors(fx, rec.pressure, cfg)
    floors = None
    state_floor = {}
    if fest is not None:
        floors = {"waypoint": np.arange(len(wp)), "t_s": tw, "floor_true": wp[FLOOR].to_numpy(dtype=np.float64)}
        for m in methods:
            if m == "wifi":
                floors[m] = _latest_fix(fx.t_s, fx.floor, tw)
                state_floor[m] = _latest_fix(fx.t_s, fx.floor, ts)
            else:
                c = m in CAUSAL_METHODS
                floors[m] = fest.at(tw, causal=c, n_votes=cfg.floor_votes)
                state_floor[m] = fest.at(ts, causal=c, n_votes=cfg.floor_votes)
        floors = pd.DataFrame(floors)
    scans = {"n_scans_outside_walk": fx.n_outside_walk, "n_scans_no_shared_ap": fx.n_no_shared_ap,
             "floor_source": None if fest is None else fest.source}
    out = {"errors": pd.DataFrame(err), "tracks": tracks, "state_t_s": ts, "fixes": fx, "info": info, "problem": prob,
           "scans": scans, "floors": floors}
    # scored only: the long table (every state of every method) is made for the walks drawn, by complete_tracks
    out["track"] = None if score_only else track_table(out, state_floor)
    out["state_floor"] = state_floor
    out["grid"] = grid_out
    return out


def complete_tracks(result: dict) -> pd.DataFrame:
    """The long ``track`` table (:func:`track_table`) of a result of :func:`evaluate_walk` run with ``score_only``:
    the :data:`~ilocalg.track.estimators.STATES_USED_METHODS` tracks solved again on the whole problem, every state
    (the states the scoring computed are the same numbers); the result's own table when it has one."""
    if result.get("track") is not None:
        return result["track"]
    prob = result["problem"]
    tracks = dict(result["tracks"])
    if prob is not None and prob.states_used is not None:
        full = dataclasses.replace(prob, states_used=None)
        for m in STATES_USED_METHODS:
            if m in tracks:
                tracks[m] = ESTIMATORS[m].fn(full)
        for m, (tq, xy, _) in result.get("grid", {}).items():      # drawn from the whole base track
            if GRID_METHODS[m] in STATES_USED_METHODS:
                tracks[m] = bend_track(prob.state_t_s, ESTIMATORS[GRID_METHODS[m]].fn(full), tq, xy,
                                       causal=m in CAUSAL_METHODS)
    return track_table({**result, "tracks": tracks}, result["state_floor"])


def track_table(result: dict, state_floor: dict | None = None) -> pd.DataFrame:
    """Long table of every method's states: ``t_s, method, x_m, y_m, floor`` (the ``wifi`` rows are the
    fixes; ``floor`` NaN without floor numbers)."""
    ts = result["state_t_s"]
    fx = result["fixes"]
    sf = state_floor or {}
    parts = []
    for m, xy in result["tracks"].items():
        parts.append(pd.DataFrame({T_S: ts, "method": m, X_M: xy[:, 0], Y_M: xy[:, 1],
                                   FLOOR: sf.get(m, np.full(ts.size, np.nan))}))
    fl = fx.floor if fx.floor is not None else np.full(fx.t_s.size, np.nan)
    parts.append(pd.DataFrame({T_S: fx.t_s, "method": "wifi", X_M: fx.xy_m[:, 0], Y_M: fx.xy_m[:, 1], FLOOR: fl}))
    return pd.concat(parts, ignore_index=True)


def error_table(result: dict, floor_penalty_m: float = 15.0) -> pd.DataFrame:
    """Long per-point error table: ``waypoint, t_s, method, error_m``, and where floors exist
    ``floor_true, floor, floor_hit, penalised_error_m`` (+``floor_penalty_m`` per wrong floor)."""
    e = result["errors"]
    fl = result.get("floors")
    methods = [m for m in METHODS if m in e.columns]
    rows = []
    for m in methods:
        d = pd.DataFrame({"waypoint": e["waypoint"], T_S: e[T_S], "method": m, "error_m": e[m]})
        if fl is not None and np.isfinite(fl["floor_true"]).all():
            d["floor_true"] = fl["floor_true"].to_numpy()
            d["floor"] = fl[m].to_numpy()
            d["floor_hit"] = d["floor"] == d["floor_true"]
            e_xy = np.column_stack([d["error_m"].to_numpy(), np.zeros(len(d))])     # |(e, 0) - (0, 0)| = e
            d["penalised_error_m"] = penalised_error_m(e_xy, np.zeros_like(e_xy), d["floor"].to_numpy(),
                                                       d["floor_true"].to_numpy(), floor_penalty_m=floor_penalty_m)
        rows.append(d)
    return pd.concat(rows, ignore_index=True)


def summary_table(result: dict, floor_penalty_m: float = 15.0) -> pd.DataFrame:
    """Per method: ``n, mean_m, median_m, p75_m, p95_m`` of the horizontal error and, where floors exist,
    ``floor_hit_rate`` and ``penalised_mean_m`` (IPIN/EvAAL convention: +15 m per wrong floor).

    References
    ----------
    Torres-Sospedra et al. (2018), the IPIN competition metrics.
    """
    t = error_table(result, floor_penalty_m)
    g = t.groupby("method", sort=False)
    out = pd.DataFrame({"n": g["error_m"].size(), "mean_m": g["error_m"].mean(), "median_m": g["error_m"].median(),
                        "p75_m": g["error_m"].quantile(0.75), "p95_m": g["error_m"].quantile(0.95)})
    if "floor_hit" in t.columns:
        out["floor_hit_rate"] = g["floor_hit"].mean()
        out["penalised_mean_m"] = g["penalised_error_m"].mean()
    return out.reset_index()


def evaluate_track(trace, db_traces, floor_map=None, cfg: RealWalkConfig = DEFAULT_CONFIG, rng=0,
                   methods=METHODS, select: bool = True) -> dict:
    """:func:`evaluate_walk` with everything learned from ``db_traces`` (walks with ground truth).

    Builds the fingerprint database (all walks in the first one's frame, the scored walk moved into it),
    the step-length factor and heading offset (:func:`calibrate`) and the fix variance
    (:func:`calibrate_fix_var`; with ``select`` the Wi-Fi configuration too, :func:`select_wifi`) from
    ``db_traces`` only; ``floor_map`` (an :class:`~ilocalg.io.ilc.IlcFloorMap` or a walkable
    :class:`~ilocalg.fusion.particle_filter.OccupancyGrid`, optional, in the walks' shared frame)
    constrains the particle filter and enables map matching (without it the particle filter runs
    unconstrained). The walked-path graph of :data:`~ilocalg.track.PATH_METHODS` is built from ``db_traces``'
    waypoints (:meth:`~ilocalg.track.paths.WalkedPaths.from_recordings`). A fingerprint walk that is the
    scored walk (same name, or same sensor content under another name) raises. Their waypoints are also the
    marked points of :data:`~ilocalg.track.GRID_METHODS`.
    """
    items = list(db_traces.values() if isinstance(db_traces, dict) else db_traces)
    if not items:
        raise ValueError("no fingerprint walks given")
    if any(t is trace or (getattr(trace, "name", "") and t.name == trace.name) for t in items):
        raise ValueError(f"the fingerprint walks must not include the scored walk {trace.name!r}")
    rec = as_recording(trace)
    recs = [as_recording(t) for t in items]
    same = [r.name for r in recs if len(rec.imu) and r.content_id == rec.content_id]
    if same:
        raise ValueError(f"the fingerprint walks must not include the scored walk {rec.name!r}: {same[0]!r} has the "
                         "same sensor content")
    frame = common_frame(recs)
    recs = [r.in_frame(frame) for r in recs]
    # stale readings: masked per query
    db = WifiDatabase.from_recordings(recs, None, frame=frame, align_time=cfg.align_fix_time)
    label = "given"
    if len(set(db.walk)) < 2:
        var = cfg.fix_min_var_m2
    elif select:
        label, cfg, var, _ = select_wifi(db, cfg)
    else:
        var, _ = calibrate_fix_var(db, cfg)
    steps = {r.name: walk_steps(r, cfg) for r in recs}
    cal = calibrate(recs, steps, cfg=cfg)
    step_var = calibrate_step_var(recs, steps, cal)
    gain, gain_note = None, None
    if any(m in GAIN_METHODS for m in methods):
        try:
            gain = gain_stats(pd.concat([step_intervals(r, steps[r.name]) for r in recs], ignore_index=True), cal)
        except ValueError as e:               # too few walks with waypoints: the kf_gain variants are not run
            methods, gain_note = tuple(m for m in methods if m not in GAIN_METHODS), str(e)
    if floor_map is None or isinstance(floor_map, OccupancyGrid):
        grid = floor_map
    else:
        grid = OccupancyGrid.from_floor_map(floor_map, cfg.grid_cell_m)
    paths = (WalkedPaths.from_recordings(recs, frame) if any(m in PATH_METHODS or m in GRID_METHODS for m in methods)
             else None)
    r = evaluate_walk(rec, db, cal, var, cfg, grid=grid, rng=rng, methods=methods, step_var_m2=step_var, gain=gain,
                      paths=paths)
    r["info"]["wifi_config"] = label
    if gain_note:
        r["info"]["kf_gain_not_run"] = gain_note
    return r

