"""PDR + Wi-Fi fusion on the real Indoor Location Competition 2.0 walks (site 2, floor F4).

Every walk is scored leave-one-walk-out: everything learned (the Wi-Fi fingerprint database,
the step-length factor, the offset between the compass frame and the map frame) comes from the
*other* walks; the scored walk contributes only its own sensor logs and Wi-Fi scans. Its
waypoints are used for nothing but the errors.

Pipeline for one walk
---------------------
Wi-Fi fixes
    The database is every scan of the other walks, positioned by interpolating their waypoints in
    time (:func:`ilocalg.io.ilc.ilc_fingerprints`); the scored walk's scans are located by WKNN
    (:class:`ilocalg.wifi.KnnFingerprint`), and each fix's covariance comes from the spread of its
    neighbours (:func:`ilocalg.fusion.fix_covariance_from_spread`).
PDR
    Steps from the toolkit's robust detector (:mod:`ilocalg.pdr.robust`); Weinberg lengths with
    ``k`` fitted on the other walks (their waypoint path length over their steps); heading: the
    gyro-integrated heading (:func:`ilocalg.pdr.gyro_heading_theta_rad`) aligned on average to
    the compass heading of the same walk (WDM, eq. 18-19), i.e. the gyro's shape with the
    compass's mean, plus the **floor offset**: the circular mean, over the other walks, of the
    rotation that best maps their PDR track onto their waypoints.
Variants scored at every waypoint (position at the waypoint's time)
    Causal (online) ones: ``pdr``: PDR from the first Wi-Fi fix (as 罗思奇 et al. start it).
    ``wifi``: the latest fix at or before the waypoint (the first fix before it). ``kf``: the step
    Kalman filter (eq. 20-26, Q with a heading term), started at the first fix with its covariance.
    ``pf``: the map-constrained particle filter (:mod:`ilocalg.fusion.particle_filter`), started
    likewise. Whole-walk (offline) ones: ``kf_rts``: the KF, RTS-smoothed. ``aligned``: the PDR
    track (floor offset) translated onto all fixes of the walk (Huber-robust). ``aligned_rot``: the
    same with the rotation fitted to the fixes too. ``aligned_kf_rts``: the KF + RTS started at the
    ``aligned`` start. ``pf_smooth``: the particle filter's ancestral paths. ``map_align``: the
    whole-walk map matching (:mod:`ilocalg.fusion.map_align`: every rigid placement on the walkable
    raster scored by the fixes and the map). ``map_align_kf_rts``: the KF + RTS from that placement.
Wi-Fi configuration
    By default chosen per held-out walk among :data:`WIFI_CANDIDATES` by leave-one-walk-out inside
    the other walks (:func:`select_wifi`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.fusion import filter_walk, fix_covariance_from_spread, fixes_at_states, rts_smooth
from ilocalg.fusion.heading_offset import circular_mean_rad, fit_track_to_fixes, rotate_xy
from ilocalg.fusion.map_align import map_align
from ilocalg.fusion.particle_filter import OccupancyGrid, map_particle_filter
from ilocalg.io.ilc import IlcTrace, ilc_fingerprints, interpolate_waypoints
from ilocalg.io.schema import ACC_COLS, GYR_COLS, MAG_COLS, SCAN_ID, T_S, X_M, Y_M
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import gyro_heading_theta_rad, heading_theta_rad
from ilocalg.pdr.robust import detect_steps_robust
from ilocalg.pdr.signals import moving_mean
from ilocalg.pdr.step_length import weinberg_length_m
from ilocalg.units import as_rng, wrap_angle_rad
from ilocalg.wifi import KnnFingerprint
from ilocalg.wifi.knn import knn_predict, neighbour_weights

__all__ = ["RealWalkConfig", "WalkSteps", "walk_steps", "Calibration", "calibrate", "WifiFixes", "WifiDatabase",
           "locate", "wifi_fixes", "calibrate_fix_var", "evaluate_walk", "evaluate_track", "floor_grid", "run",
           "METHODS", "WIFI_CANDIDATES", "select_wifi", "DATASET", "load_floor", "findings", "example"]

DATASET = "ilc2020_site2_F4"
#: Keys of the scored variants (the ``evaluate track`` command's ``errors_m`` keys).
METHODS = ("pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts", "pf", "pf_smooth", "map_align",
           "map_align_kf_rts")


@dataclass(frozen=True)
class RealWalkConfig:
    """Parameters of the real-walk pipeline (defaults: chosen a priori, documented here).

    k_neighbors, p, weights, metric, not_heard_dbm : WKNN (K = 5, Manhattan as in 罗思奇 et al.; 1/d
        weights); :func:`run` and :func:`evaluate_track` by default choose among :data:`WIFI_CANDIDATES`
        by leave-one-walk-out inside the fingerprint walks (:func:`select_wifi`).
    max_age_s : stale AP readings older than this are left out of database and queries (None: keep).
    fix_min_var_m2, fix_scale : R = scale * neighbour scatter + min_var I.
    sigma_heading_rad : heading error sd per step in the KF's Q (beyond the paper).
    sigma_sl_m : step-length error sd.
    min_bout_steps : robust detector's bout gate (short walks have short bouts).
    huber_m : robust threshold of the track-to-fixes fit.
    n_particles, pf_* : particle filter (see :func:`ilocalg.fusion.particle_filter.map_particle_filter`).
    grid_cell_m : walkable raster resolution.
    """

    k_neighbors: int = 5
    p: int = 1
    weights: str = "distance"
    metric: str = "minkowski"
    not_heard_dbm: float = -100.0
    max_age_s: float | None = None
    fix_min_var_m2: float = 25.0
    fix_scale: float = 1.0
    sigma_heading_rad: float = 0.1
    sigma_sl_m: float = 0.15
    min_bout_steps: int = 4
    huber_m: float = 10.0
    n_particles: int = 1000
    pf_sigma_heading_rad: float = 0.1
    pf_sigma_offset0_rad: float = 0.35
    pf_outlier_prob: float = 0.2
    pf_blocked_weight: float = 1e-3
    grid_cell_m: float = 0.5


@dataclass(frozen=True)
class WalkSteps:
    """Steps of one walk: ``state_t_s`` (n+1: the log start, then each step), ``a_range_mps2`` (n, the
    Weinberg input), ``theta_rel_rad`` (n, compass-aligned gyro heading, map convention, before the floor
    offset)."""

    state_t_s: np.ndarray
    a_range_mps2: np.ndarray
    theta_rel_rad: np.ndarray


def walk_steps(trace: IlcTrace, cfg: RealWalkConfig = RealWalkConfig()) -> WalkSteps:
    """Detect the steps of a walk and their heading (gyro shape, compass mean); uses no waypoint."""
    imu = trace.imu
    if len(imu) < 50:
        raise ValueError(f"{trace.name}: too few IMU samples ({len(imu)})")
    t = imu.index.to_numpy()
    acc = imu[list(ACC_COLS)].to_numpy()
    rate = 1.0 / float(np.median(np.diff(t)))
    st = detect_steps_robust(acc, t, min_bout_steps=cfg.min_bout_steps)
    g = np.column_stack([moving_mean(acc[:, j], max(int(0.5 * rate), 1)) for j in range(3)])
    m = np.column_stack([moving_mean(imu[list(MAG_COLS)].to_numpy()[:, j], max(int(0.25 * rate), 1))
                         for j in range(3)])
    wdm = heading_theta_rad(g, m)
    gyro = gyro_heading_theta_rad(imu[list(GYR_COLS)].to_numpy(), g, t, 0.0)
    th = wrap_angle_rad(gyro + circular_mean_rad(wdm - gyro))
    i = st["i_peak"].to_numpy()
    return WalkSteps(np.concatenate([[t[0]], st["t_s"].to_numpy()]),
                     (st["a_max_mps2"] - st["a_min_mps2"]).to_numpy(), th[i])


def _track_at(state_t_s, xy, t_s):
    """Positions at times ``t_s`` by linear interpolation between states (held outside)."""
    return np.column_stack([np.interp(t_s, state_t_s, xy[:, 0]), np.interp(t_s, state_t_s, xy[:, 1])])


@dataclass(frozen=True)
class Calibration:
    """What the other walks teach: Weinberg ``k``, the floor heading offset, per-walk fits."""

    k_weinberg: float
    offset_rad: float
    per_walk: pd.DataFrame


def calibrate(traces, steps: dict | None = None, cfg: RealWalkConfig = RealWalkConfig()) -> Calibration:
    """Fit ``k`` and the compass-to-map heading offset on walks with waypoints (never the scored one)."""
    items = list(traces.values() if isinstance(traces, dict) else traces)
    if not items:
        raise ValueError("calibrate: no walks given")
    rows, f_tot, l_tot = [], 0.0, 0.0
    for tr in items:
        ws = (steps or {}).get(tr.name) or walk_steps(tr, cfg)
        wp = tr.waypoints
        tw = wp[T_S].to_numpy()
        inside = (ws.state_t_s[1:] >= tw[0]) & (ws.state_t_s[1:] <= tw[-1])
        path_m = float(np.hypot(*np.diff(wp[[X_M, Y_M]].to_numpy(), axis=0).T).sum())
        f = float((ws.a_range_mps2[inside] ** 0.25).sum())
        row = {"walk": tr.name, "steps": int(ws.a_range_mps2.size), "path_m": path_m, "angle_rad": np.nan,
               "rms_m": np.nan}
        if inside.sum() >= 2 and len(wp) >= 2:
            f_tot += f
            l_tot += path_m
            rel = dead_reckon(np.full(ws.theta_rel_rad.size, 0.7), ws.theta_rel_rad)[["x_m", "y_m"]].to_numpy()
            fit = fit_track_to_fixes(_track_at(ws.state_t_s, rel, tw), wp[[X_M, Y_M]].to_numpy(), huber_m=None)
            row.update(angle_rad=fit.angle_rad, rms_m=fit.rms_m)
        rows.append(row)
    pw = pd.DataFrame(rows)
    ok = pw["angle_rad"].notna()
    if f_tot <= 0 or not ok.any():
        raise ValueError("calibrate: no walk with steps inside its waypoint span")
    off = circular_mean_rad(pw.loc[ok, "angle_rad"].to_numpy(), pw.loc[ok, "path_m"].to_numpy())
    return Calibration(l_tot / f_tot, off, pw)


@dataclass(frozen=True)
class WifiFixes:
    """Fixes of the scored walk: ``t_s`` (m,), ``xy_m`` (m, 2), ``R_m2`` (m, 2, 2), ``true_xy_m`` (m, 2;
    interpolated waypoints, NaN outside their span: for scoring only)."""

    t_s: np.ndarray
    xy_m: np.ndarray
    R_m2: np.ndarray
    true_xy_m: np.ndarray


def _query_matrix(trace: IlcTrace, ap_ids, max_age_s):
    w = trace.wifi
    if max_age_s is not None:
        w = w[(w[T_S] - w["last_seen_s"]) <= max_age_s]
    col = {a: j for j, a in enumerate(ap_ids)}
    sids = np.sort(trace.wifi[SCAN_ID].unique())
    t = trace.wifi.groupby(SCAN_ID)[T_S].first().loc[sids].to_numpy()
    X = np.full((sids.size, len(ap_ids)), np.nan)
    rowof = {s: i for i, s in enumerate(sids)}
    j = w["bssid"].map(col)
    ok = j.notna().to_numpy()
    X[w[SCAN_ID].map(rowof).to_numpy()[ok], j.to_numpy()[ok].astype(np.int64)] = w["rssi_dbm"].to_numpy()[ok]
    return t, X


@dataclass(frozen=True)
class WifiDatabase:
    """Fingerprints of walks, one row per scan: ``rssi_dbm`` (n, n_aps), ``xy_m`` (n, 2), ``walk`` (n,)."""

    rssi_dbm: np.ndarray
    xy_m: np.ndarray
    walk: np.ndarray
    ap_ids: tuple

    @classmethod
    def from_traces(cls, traces, max_age_s: float | None = None) -> WifiDatabase:
        """Every scan of ``traces`` positioned by interpolating its walk's waypoints (outside: left out)."""
        fp = ilc_fingerprints(traces, outside="drop", max_age_s=max_age_s).fingerprints
        return cls(fp.rssi_dbm, fp.xy_m, fp.meta["trace"].to_numpy(dtype=object), tuple(fp.ap_ids))

    def without(self, *walks) -> WifiDatabase:
        """The database without the rows of ``walks`` (leave-walks-out)."""
        keep = ~np.isin(self.walk, list(walks))
        if not keep.any():
            raise ValueError(f"no fingerprint left after removing {walks}")
        return WifiDatabase(self.rssi_dbm[keep], self.xy_m[keep], self.walk[keep], self.ap_ids)


def locate(db: WifiDatabase, X, cfg: RealWalkConfig = RealWalkConfig()):
    """WKNN fixes (m, 2) of queries ``X`` (m, n_aps in ``db.ap_ids`` order) and their spread covariances."""
    est = KnnFingerprint(n_neighbors=min(cfg.k_neighbors, db.xy_m.shape[0]), p=cfg.p, weights=cfg.weights,
                         not_heard_dbm=cfg.not_heard_dbm, kernel="dense", metric=cfg.metric).fit(db.rssi_dbm, db.xy_m)
    dist, idx = est.kneighbors(X)
    xy = knn_predict(est.y_, idx, neighbour_weights(dist, cfg.weights))
    w = 1.0 / np.maximum(dist, 1e-9) if cfg.weights == "distance" else None
    return xy, fix_covariance_from_spread(db.xy_m[idx], w, min_var_m2=1.0)


def wifi_fixes(trace: IlcTrace, db: WifiDatabase, cfg: RealWalkConfig = RealWalkConfig(),
               fix_var_m2: float | None = None) -> WifiFixes:
    """WKNN fixes of every scan of ``trace`` against ``db``, which must not contain the walk.

    ``R`` of each fix: ``fix_var_m2 I`` (isotropic, e.g. calibrated on other walks by
    :func:`calibrate_fix_var`) or, when None, the neighbour spread plus ``cfg.fix_min_var_m2``.
    """
    if trace.name and trace.name in set(db.walk):
        raise ValueError(f"the fingerprint database must not contain the scored walk {trace.name!r}")
    t, X = _query_matrix(trace, db.ap_ids, cfg.max_age_s)
    keep = ~np.isnan(X).all(axis=1)          # scans sharing no AP with the database cannot be located
    t, X = t[keep], X[keep]
    if not t.size:
        raise ValueError(f"{trace.name}: no scan shares an access point with the database")
    xy, C = locate(db, X, cfg)
    R = (fix_var_m2 * np.broadcast_to(np.eye(2), C.shape).copy() if fix_var_m2 is not None
         else C + (cfg.fix_min_var_m2 - 1.0) * np.eye(2))
    true = interpolate_waypoints(trace.waypoints, t, outside="nan")
    return WifiFixes(t, xy, R, true)


def calibrate_fix_var(db: WifiDatabase, cfg: RealWalkConfig = RealWalkConfig()) -> tuple[float, pd.DataFrame]:
    """Isotropic Wi-Fi fix variance (per axis, m^2) by leave-one-walk-out *inside* ``db``.

    Each walk of ``db`` is located against the others; ``var = mean(error^2) / 2``. Returns the variance
    and the per-walk errors table (``walk, n, mean_error_m``).
    """
    walks = list(dict.fromkeys(db.walk))
    errs, rows = [], []
    for v in walks:
        rest = db.without(v)
        m = db.walk == v
        xy, _ = locate(rest, db.rssi_dbm[m], cfg)
        e = np.hypot(*(xy - db.xy_m[m]).T)
        errs.append(e)
        rows.append({"walk": v, "n": int(m.sum()), "mean_error_m": float(e.mean())})
    e = np.concatenate(errs)
    return float(np.mean(e**2) / 2.0), pd.DataFrame(rows)


#: Wi-Fi configurations :func:`select_wifi` chooses from (label -> RealWalkConfig fields).
WIFI_CANDIDATES = {
    "KNN Manhattan K=5 (004)": {"k_neighbors": 5, "p": 1, "weights": "uniform", "metric": "minkowski"},
    "WKNN Manhattan K=5": {"k_neighbors": 5, "p": 1, "weights": "distance", "metric": "minkowski"},
    "WKNN Euclidean K=5": {"k_neighbors": 5, "p": 2, "weights": "distance", "metric": "minkowski"},
    "WKNN Sorensen K=5": {"k_neighbors": 5, "p": 1, "weights": "distance", "metric": "sorensen"},
    "WKNN Manhattan K=10": {"k_neighbors": 10, "p": 1, "weights": "distance", "metric": "minkowski"},
}


def select_wifi(db: WifiDatabase, cfg: RealWalkConfig = RealWalkConfig(), candidates=None):
    """Choose the Wi-Fi configuration with the lowest leave-one-walk-out mean error inside ``db``.

    Returns ``(label, cfg_with_it, fix_var_m2, table)``; ``table`` has one row per candidate
    (``label, mean_error_m, fix_sd_m``). Uses only the walks of ``db`` (model selection nested inside
    the outer leave-one-walk-out).
    """
    import dataclasses

    cands = WIFI_CANDIDATES if candidates is None else candidates
    rows, best = [], None
    for label, kw in cands.items():
        c = dataclasses.replace(cfg, **kw)
        var, per = calibrate_fix_var(db, c)
        e = float(np.average(per["mean_error_m"], weights=per["n"]))
        rows.append({"label": label, "mean_error_m": e, "fix_sd_m": float(np.sqrt(var))})
        if best is None or e < best[0]:
            best = (e, label, c, var)
    return best[1], best[2], best[3], pd.DataFrame(rows)


def _latest_fix(fix_t, fix_xy, t_s):
    i = np.clip(np.searchsorted(fix_t, t_s, side="right") - 1, 0, fix_t.size - 1)
    return fix_xy[i]


def _robust_translation(src, dst, huber_m, n_iter: int = 20):
    """Huber-robust mean of ``dst - src`` (the start offset with the heading held fixed)."""
    r = dst - src
    t = np.median(r, axis=0)
    for _ in range(n_iter):
        dist = np.hypot(*(r - t).T)
        w = np.where(dist <= huber_m, 1.0, huber_m / np.maximum(dist, 1e-12))
        t_new = w @ r / w.sum()
        if np.allclose(t_new, t, atol=1e-6):
            return t_new
        t = t_new
    return t


def evaluate_walk(trace: IlcTrace, db: WifiDatabase, calibration: Calibration, fix_var_m2: float,
                  cfg: RealWalkConfig = RealWalkConfig(), grid: OccupancyGrid | None = None,
                  steps: WalkSteps | None = None, rng=None, methods=METHODS) -> dict:
    """Score every variant at the waypoints of ``trace``.

    ``db``, ``calibration`` and ``fix_var_m2`` must come from other walks (see :func:`evaluate_track`,
    which builds them from walk files); ``db`` containing the walk raises.

    Returns
    -------
    dict
        ``errors`` (DataFrame: one row per waypoint, one column per method, metres), ``tracks``
        (method -> (n+1, 2) states), ``state_t_s``, ``fixes`` (WifiFixes), ``info`` (dict). ``errors``
        also has ``oracle_shape_m``: a diagnostic (the track fitted onto the walk's own waypoints), never
        a method.
    """
    unknown = set(methods) - set(METHODS)
    if unknown:
        raise ValueError(f"unknown methods {sorted(unknown)}; known: {METHODS}")
    cal = calibration
    fx = wifi_fixes(trace, db, cfg, fix_var_m2=fix_var_m2)
    ws = steps or walk_steps(trace, cfg)
    if ws.a_range_mps2.size < 1:
        raise ValueError(f"{trace.name}: no step detected")
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
    wp = trace.waypoints
    tw = wp[T_S].to_numpy()
    true = wp[[X_M, Y_M]].to_numpy()
    tracks = {"pdr": dead_reckon(d, th, *x0)[["x_m", "y_m"]].to_numpy()}
    res = filter_walk(x0, P0, th, d, cfg.sigma_sl_m, z_kf, R_m2=R, sigma_theta_rad=cfg.sigma_heading_rad)
    tracks["kf"] = res.x
    tracks["kf_rts"] = rts_smooth(res).x
    rel = dead_reckon(d, th)[["x_m", "y_m"]].to_numpy()       # floor offset, from the origin
    at_fix = _track_at(ts, rel, fx.t_s)
    t0 = _robust_translation(at_fix, fx.xy_m, cfg.huber_m)
    tracks["aligned"] = rel + t0
    ra = filter_walk(t0, P0, th, d, cfg.sigma_sl_m, z, R_m2=R, sigma_theta_rad=cfg.sigma_heading_rad)
    tracks["aligned_kf_rts"] = rts_smooth(ra).x
    info = {"n_steps": int(d.size), "n_fixes": int(fx.t_s.size), "k_weinberg": cal.k_weinberg,
            "floor_offset_deg": float(np.degrees(cal.offset_rad)), "fix_sd_m": float(np.sqrt(fix_var_m2))}
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
                                 blocked_weight=cfg.pf_blocked_weight)
        tracks["pf"], tracks["pf_smooth"] = pf.x, pf.x_smooth
        info.update(pf_resamples=pf.n_resample, pf_resets=pf.n_reset)
    if "map_align" in methods or "map_align_kf_rts" in methods:
        if grid is None:
            raise ValueError("map_align needs the floor map (grid)")
        g1 = grid if grid.cell_m >= 1.0 else _coarse(grid)
        used = al.used
        ma = map_align(rel, al.state_index[used], fx.xy_m[used], fix_var_m2, g1,
                       sigma_angle_rad=cfg.pf_sigma_offset0_rad, outlier_prob=cfg.pf_outlier_prob,
                       blocked_weight=cfg.pf_blocked_weight)
        tracks["map_align"] = ma.track_m
        th_m = wrap_angle_rad(th + ma.angle_rad)
        rm = filter_walk(ma.t_m, P0, th_m, d, cfg.sigma_sl_m, z, R_m2=R, sigma_theta_rad=cfg.sigma_heading_rad)
        tracks["map_align_kf_rts"] = rts_smooth(rm).x
        info.update(map_align_offset_deg=float(np.degrees(ma.angle_rad)), map_align_off_map=ma.off_map)
    err = {"waypoint": np.arange(len(wp)), "t_s": tw}
    # diagnostic only, not a method: the PDR track rigidly fitted onto this walk's own waypoints (how good
    # the track's shape is; the remaining error of every method is mostly its placement)
    if len(wp) >= 2:
        ofit = fit_track_to_fixes(_track_at(ts, rel, tw), true, huber_m=None)
        err["oracle_shape_m"] = np.hypot(*(_track_at(ts, rotate_xy(rel, ofit.angle_rad) + ofit.t_m, tw) - true).T)
    else:
        err["oracle_shape_m"] = np.zeros(len(wp))
    for m in methods:
        est = _latest_fix(fx.t_s, fx.xy_m, tw) if m == "wifi" else _track_at(ts, tracks[m], tw)
        err[m] = np.hypot(*(est - true).T)
    fe = np.hypot(*(fx.xy_m - fx.true_xy_m).T)
    info["fix_mean_error_m"] = float(np.nanmean(fe)) if np.isfinite(fe).any() else np.nan
    info["first_fix_error_m"] = float(fe[0])
    return {"errors": pd.DataFrame(err), "tracks": tracks, "state_t_s": ts, "fixes": fx, "info": info}


def _coarse(grid: OccupancyGrid, cell_m: float = 1.0) -> OccupancyGrid:
    """A coarser raster: a coarse cell is walkable if any fine cell in it is."""
    f = int(round(cell_m / grid.cell_m))
    if f <= 1:
        return grid
    m = grid.walkable_mask
    ny, nx = (m.shape[0] // f) * f, (m.shape[1] // f) * f
    c = m[:ny, :nx].reshape(ny // f, f, nx // f, f).any(axis=(1, 3))
    return OccupancyGrid(c, grid.x0_m, grid.y0_m, grid.cell_m * f)


def evaluate_track(trace: IlcTrace, db_traces, floor_map=None, cfg: RealWalkConfig = RealWalkConfig(), rng=0,
                   methods=METHODS, select: bool = True) -> dict:
    """:func:`evaluate_walk` with everything learned from ``db_traces`` (walks with waypoints).

    Builds the fingerprint database, the step-length factor and heading offset (:func:`calibrate`)
    and the fix variance (:func:`calibrate_fix_var`; with ``select`` the Wi-Fi configuration too,
    :func:`select_wifi`) from ``db_traces`` only; ``floor_map`` (an
    :class:`~ilocalg.io.ilc.IlcFloorMap`, optional) constrains the particle filter (without it the
    particle filter runs unconstrained).
    """
    items = list(db_traces.values() if isinstance(db_traces, dict) else db_traces)
    if not items:
        raise ValueError("no fingerprint walks given")
    if any(t is trace or (trace.name and t.name == trace.name) for t in items):
        raise ValueError(f"the fingerprint walks must not include the scored walk {trace.name!r}")
    db = WifiDatabase.from_traces(items, cfg.max_age_s)
    label = "given"
    if len(set(db.walk)) < 2:
        var = cfg.fix_min_var_m2
    elif select:
        label, cfg, var, _ = select_wifi(db, cfg)
    else:
        var, _ = calibrate_fix_var(db, cfg)
    cal = calibrate(items, cfg=cfg)
    grid = floor_grid(floor_map, cfg.grid_cell_m) if floor_map is not None else None
    r = evaluate_walk(trace, db, cal, var, cfg, grid=grid, rng=rng, methods=methods)
    r["info"]["wifi_config"] = label
    return r


def load_floor(data_dir=None):
    """The site2/F4 floor (traces and map) from ``data_dir`` (None: the toolkit's data folder)."""
    from ilocalg.io.ilc import load_ilc_floor
    from ilocalg.io.paths import data_dir as default_dir

    root = (default_dir() if data_dir is None else data_dir)
    from pathlib import Path

    p = Path(root)
    if (p / DATASET).exists():
        p = p / DATASET
    return load_ilc_floor(p, duplicate_bssid="keep_latest")


def floor_grid(floor_map, cell_m: float = 0.5) -> OccupancyGrid:
    """Walkable raster of an :class:`~ilocalg.io.ilc.IlcFloorMap`."""
    return OccupancyGrid.from_polygons(floor_map.outline, floor_map.obstacles, (0.0, floor_map.width_m),
                                       (0.0, floor_map.height_m), cell_m)


def run(seed: int = 0, fast: bool = False, data_dir=None, floor=None, cfg: RealWalkConfig | None = None,
        names=None, select: bool | None = None) -> dict[str, pd.DataFrame]:
    """Leave-one-walk-out over the floor's walks; every variant at every waypoint.

    ``fast`` scores every fifth walk with fewer particles, a coarser map raster and the default Wi-Fi
    configuration. ``select`` (default: not ``fast``): choose the Wi-Fi configuration per held-out walk
    by leave-one-walk-out inside the other walks.

    Returns
    -------
    dict of DataFrame
        ``waypoints`` (walk, waypoint, one error column per method), ``per_walk`` (mean per walk and
        method + what was learned from the other walks), ``summary`` (mean over all waypoints, median,
        p90, mean of the walk means, ratio to Wi-Fi only, goal met), ``diagnostics`` (what limits the
        fusion: the error of the PDR track's shape alone, fitted onto the walk's own waypoints as an
        oracle, beside the Wi-Fi fix errors).
    """
    cfg = cfg or RealWalkConfig(n_particles=300 if fast else 1000, grid_cell_m=1.0 if fast else 0.5)
    select = (not fast) if select is None else select
    fl = floor or load_floor(data_dir)
    all_names = fl.names
    scored = list(names) if names is not None else (all_names[::5] if fast else all_names)
    grid = floor_grid(fl.floor_map, cfg.grid_cell_m)
    steps = {n: walk_steps(fl.traces[n], cfg) for n in all_names}
    db_all = WifiDatabase.from_traces(fl.traces, cfg.max_age_s)
    rng = as_rng(seed)
    wrows, prow = [], []
    for name in scored:
        others = {k: v for k, v in fl.traces.items() if k != name}
        db = db_all.without(name)
        if select:
            label, wcfg, var, _ = select_wifi(db, cfg)
        else:
            label, wcfg, (var, _) = "given", cfg, calibrate_fix_var(db, cfg)
        cal = calibrate(others, steps, wcfg)
        r = evaluate_walk(fl.traces[name], db, cal, var, wcfg, grid=grid, steps=steps[name], rng=rng)
        e = r["errors"].assign(walk=name)
        wrows.append(e)
        prow.append({"walk": name, "waypoints": len(e), **{m: float(e[m].mean()) for m in METHODS},
                     "wifi_config": label, **r["info"]})
    wp = pd.concat(wrows, ignore_index=True)
    wp = wp[["walk"] + [c for c in wp.columns if c != "walk"]]
    pw = pd.DataFrame(prow)
    wifi_mean = float(wp["wifi"].mean())
    summ = pd.DataFrame([{"method": m, "mean_error_m": float(wp[m].mean()), "median_error_m": float(wp[m].median()),
                          "p90_error_m": float(wp[m].quantile(0.9)), "mean_of_walk_means_m": float(pw[m].mean()),
                          "ratio_to_wifi": float(wp[m].mean()) / wifi_mean, "meets_goal_half_wifi":
                          bool(float(wp[m].mean()) <= 0.5 * wifi_mean)} for m in METHODS])
    diag = pd.DataFrame([
        {"quantity": "PDR track fitted onto the walk's own waypoints (oracle, diagnostic only), mean error [m]",
         "value": float(wp["oracle_shape_m"].mean())},
        {"quantity": "Wi-Fi fix error, mean over walks [m]", "value": float(pw["fix_mean_error_m"].mean())},
        {"quantity": "first Wi-Fi fix error, mean over walks [m]", "value": float(pw["first_fix_error_m"].mean())},
        {"quantity": "waypoints scored", "value": float(len(wp))},
        {"quantity": "walks scored", "value": float(len(pw))},
    ])
    return {"waypoints": wp, "per_walk": pw, "summary": summ, "diagnostics": diag}


def example(floor, name: str | None = None, cfg: RealWalkConfig | None = None, seed: int = 0,
            select: bool = True) -> pd.DataFrame:
    """Tracks of one walk (default: the one with the most waypoints), leave-one-walk-out, as a long table
    ``method, x_m, y_m``: ``waypoints`` (truth), ``Wi-Fi fixes`` and every variant's states."""
    cfg = cfg or RealWalkConfig()
    if name is None:
        name = max(floor.names, key=lambda n: (len(floor.traces[n].waypoints), n))
    others = {k: v for k, v in floor.traces.items() if k != name}
    r = evaluate_track(floor.traces[name], others, floor_map=floor.floor_map, cfg=cfg, rng=seed, select=select)
    wp = floor.traces[name].waypoints
    out = [pd.DataFrame({"method": "waypoints", "x_m": wp[X_M].to_numpy(), "y_m": wp[Y_M].to_numpy()}),
           pd.DataFrame({"method": "Wi-Fi fixes", "x_m": r["fixes"].xy_m[:, 0], "y_m": r["fixes"].xy_m[:, 1]})]
    out += [pd.DataFrame({"method": m, "x_m": xy[:, 0], "y_m": xy[:, 1]}) for m, xy in r["tracks"].items()]
    return pd.concat(out, ignore_index=True).assign(walk=name)


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    s = tables["summary"].set_index("method")
    w = s.loc["wifi", "mean_error_m"]
    best = s.drop("wifi")["mean_error_m"].idxmin()
    met = [m for m in s.index if s.loc[m, "meets_goal_half_wifi"]]
    return "\n".join([
        f"Wi-Fi only: {w:.2f} m mean waypoint error over {len(tables['waypoints'])} waypoints of "
        f"{len(tables['per_walk'])} walks (leave-one-walk-out).",
        f"Best variant: {best}, {s.loc[best, 'mean_error_m']:.2f} m ({s.loc[best, 'ratio_to_wifi']:.2f} x Wi-Fi only).",
        f"Goal (at most half the Wi-Fi-only error, {0.5 * w:.2f} m) met by: {', '.join(met) if met else 'none'}; "
        f"KF {s.loc['kf', 'mean_error_m']:.2f} m, KF + RTS {s.loc['kf_rts', 'mean_error_m']:.2f} m, "
        f"PF {s.loc['pf', 'mean_error_m']:.2f} m, PF smoothed {s.loc['pf_smooth', 'mean_error_m']:.2f} m.",
    ])
