"""From a phone walk to a track: PDR + Wi-Fi fusion of one walk, everything learned from other walks.

A walk (the IMU log, the Wi-Fi scans and, for learning and scoring only, the surveyor's waypoints:
the attributes ``imu``, ``wifi``, ``waypoints`` and ``name`` of :class:`ilocalg.io.ilc.IlcTrace`)
goes through:

Steps and headings (:func:`walk_steps`)
    Steps from the toolkit's robust detector (:func:`ilocalg.pdr.robust.detect_steps_robust`); the
    gyro-integrated heading (:func:`ilocalg.pdr.gyr_heading_theta_rad`) aligned on average to the
    compass heading of the same walk (WDM, Chiu 2013 eq. 18-19): the gyro's shape with the
    compass's mean. No waypoint is used.
What the other walks teach (:func:`calibrate`, :class:`WifiDatabase`, :func:`calibrate_fix_var`)
    The Weinberg factor ``k`` (their waypoint path length over their steps), the **floor offset**
    between the compass frame and the map frame (the circular mean of the rotation that best maps
    each walk's PDR track onto its waypoints), the fingerprint database (every scan positioned by
    interpolating its walk's waypoints in time, :func:`ilocalg.io.ilc.ilc_fingerprints`) and the
    Wi-Fi fix variance (leave-one-walk-out inside the database; :func:`select_wifi` also chooses the
    Wi-Fi configuration among :data:`WIFI_CANDIDATES` that way).
Wi-Fi fixes (:func:`wifi_fixes`)
    Each scan of the walk located by WKNN (:class:`ilocalg.wifi.KnnFingerprint`), with a covariance
    from the spread of its neighbours (:func:`ilocalg.fusion.fix_covariance_from_spread`) or the
    calibrated isotropic variance.
Tracks (:func:`evaluate_walk`), the keys of :data:`METHODS`
    Causal (online) ones: ``pdr``: PDR from the first Wi-Fi fix (as Luo et al. 2017 start it).
    ``wifi``: the latest fix at or before the time. ``kf``: the step Kalman filter (Chiu 2013 eq.
    20-26, Q with a heading term), started at the first fix with its covariance. ``pf``: the
    map-constrained particle filter (:mod:`ilocalg.fusion.particle_filter`), started likewise.
    Whole-walk (offline) ones: ``kf_rts``: the KF, RTS-smoothed. ``aligned``: the PDR track (floor
    offset) translated onto all fixes of the walk (Huber-robust). ``aligned_rot``: the same with the
    rotation fitted to the fixes too. ``aligned_kf_rts``: the KF + RTS started at the ``aligned``
    start. ``pf_smooth``: the particle filter's ancestral paths. ``map_align``: the whole-walk map
    matching (:mod:`ilocalg.fusion.map_align`). ``map_align_kf_rts``: the KF + RTS from that placement.

:func:`evaluate_track` runs the whole chain for one walk given the other walks (and optionally the
floor map); the ``evaluate track`` command and the real-walk experiment call it.

References
----------
Chiu P.-J., i-Loc M.S. thesis, NCTU (2013), eq. 18-19 (WDM heading) and eq. 20-26 (step Kalman
filter); Luo S. et al. (罗思奇 et al.), Computer Systems & Applications (2017), KNN fingerprinting with
the Manhattan distance and K = 5, PDR + Wi-Fi fusion; Weinberg H., Analog Devices AN-602 (2002), step
length; Rauch, Tung, Striebel, AIAA J. 3(8) (1965), smoothing; Woodman & Harle, UbiComp (2008),
map-constrained particle filters.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.fusion import filter_walk, fix_covariance_from_spread, fixes_at_states, rts_smooth
from ilocalg.fusion.heading_offset import circular_mean_rad, fit_track_to_fixes, rotate_xy
from ilocalg.fusion.map_align import map_align
from ilocalg.fusion.particle_filter import OccupancyGrid, map_particle_filter
from ilocalg.io.ilc import ilc_fingerprints, interpolate_waypoints
from ilocalg.io.scans import scan_matrix
from ilocalg.io.schema import ACC_COLS, GYR_COLS, MAG_COLS, T_S, X_M, Y_M
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import gyr_heading_theta_rad, heading_theta_rad
from ilocalg.pdr.robust import detect_steps_robust
from ilocalg.pdr.signals import moving_mean
from ilocalg.pdr.step_length import weinberg_length_m
from ilocalg.units import as_rng, wrap_angle_rad
from ilocalg.wifi import KnnFingerprint
from ilocalg.wifi.knn import knn_predict, neighbour_weights

__all__ = ["RealWalkConfig", "METHODS", "WIFI_CANDIDATES", "WalkSteps", "walk_steps", "Calibration", "calibrate",
           "WifiDatabase", "WifiFixes", "locate_wknn", "wifi_fixes", "calibrate_fix_var", "select_wifi",
           "evaluate_walk", "evaluate_track"]

#: Keys of the scored tracks (the ``evaluate track`` command's ``errors_m`` keys).
METHODS = ("pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts", "pf", "pf_smooth", "map_align",
           "map_align_kf_rts")


@dataclass(frozen=True)
class RealWalkConfig:
    """Parameters of the track pipeline (defaults: chosen a priori, documented here).

    k_neighbors, p, weights, metric, not_heard_dbm : WKNN (K = 5, Manhattan as in Luo et al. 2017; 1/d
        weights); :func:`evaluate_track` by default chooses among :data:`WIFI_CANDIDATES` by
        leave-one-walk-out inside the fingerprint walks (:func:`select_wifi`).
    max_age_s : stale AP readings older than this are left out of database and queries (None: keep).
    fix_min_var_m2, fix_scale : R = scale * neighbour scatter + min_var I.
    sigma_heading_rad : heading error sd per step in the KF's Q (beyond the papers).
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


def walk_steps(trace, cfg: RealWalkConfig = RealWalkConfig()) -> WalkSteps:
    """Detect the steps of a walk and their heading (gyro shape, compass mean); uses no waypoint.

    Gravity is the 1 s moving mean of the accelerometer, the magnetic field the 0.5 s one
    (:func:`ilocalg.pdr.signals.moving_mean`).

    References
    ----------
    Chiu (2013), eq. 18-19 (WDM heading from gravity and the magnetic field).
    """
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
    gyro = gyr_heading_theta_rad(imu[list(GYR_COLS)].to_numpy(), g, t, 0.0)
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
    """Fit ``k`` and the compass-to-map heading offset on walks with waypoints (never the scored one).

    ``steps`` (walk name -> :class:`WalkSteps`, optional) saves re-detecting the steps.

    References
    ----------
    Weinberg (2002), the step length ``k * (a_max - a_min)^(1/4)``; Umeyama (1991), the rotation of
    each walk's track onto its waypoints.
    """
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


def locate_wknn(db: WifiDatabase, X, cfg: RealWalkConfig = RealWalkConfig()):
    """WKNN fixes (m, 2) of queries ``X`` (m, n_aps in ``db.ap_ids`` order) and their spread covariances.

    References
    ----------
    Luo et al. (2017), eq. 1-2 (KNN fingerprinting).
    """
    est = KnnFingerprint(n_neighbors=min(cfg.k_neighbors, db.xy_m.shape[0]), p=cfg.p, weights=cfg.weights,
                         not_heard_dbm=cfg.not_heard_dbm, kernel="dense", metric=cfg.metric).fit(db.rssi_dbm, db.xy_m)
    dist, idx = est.kneighbors(X)
    xy = knn_predict(est.y_, idx, neighbour_weights(dist, cfg.weights))
    w = 1.0 / np.maximum(dist, 1e-9) if cfg.weights == "distance" else None
    return xy, fix_covariance_from_spread(db.xy_m[idx], w, min_var_m2=1.0)


def wifi_fixes(trace, db: WifiDatabase, cfg: RealWalkConfig = RealWalkConfig(),
               fix_var_m2: float | None = None) -> WifiFixes:
    """WKNN fixes of every scan of ``trace`` against ``db``, which must not contain the walk.

    ``R`` of each fix: ``fix_var_m2 I`` (isotropic, e.g. calibrated on other walks by
    :func:`calibrate_fix_var`) or, when None, the neighbour spread plus ``cfg.fix_min_var_m2``.
    """
    if trace.name and trace.name in set(db.walk):
        raise ValueError(f"the fingerprint database must not contain the scored walk {trace.name!r}")
    w = trace.wifi
    fresh = None if cfg.max_age_s is None else ((w[T_S] - w["last_seen_s"]) <= cfg.max_age_s).to_numpy()
    _, t, X = scan_matrix(w, db.ap_ids, keep=fresh)
    keep = ~np.isnan(X).all(axis=1)          # scans sharing no AP with the database cannot be located
    t, X = t[keep], X[keep]
    if not t.size:
        raise ValueError(f"{trace.name}: no scan shares an access point with the database")
    xy, C = locate_wknn(db, X, cfg)
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
        xy, _ = locate_wknn(rest, db.rssi_dbm[m], cfg)
        e = np.hypot(*(xy - db.xy_m[m]).T)
        errs.append(e)
        rows.append({"walk": v, "n": int(m.sum()), "mean_error_m": float(e.mean())})
    e = np.concatenate(errs)
    return float(np.mean(e**2) / 2.0), pd.DataFrame(rows)


#: Wi-Fi configurations :func:`select_wifi` chooses from (label -> RealWalkConfig fields).
WIFI_CANDIDATES = {
    "KNN Manhattan K=5 (Luo et al. 2017)": {"k_neighbors": 5, "p": 1, "weights": "uniform", "metric": "minkowski"},
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


def evaluate_walk(trace, db: WifiDatabase, calibration: Calibration, fix_var_m2: float,
                  cfg: RealWalkConfig = RealWalkConfig(), grid: OccupancyGrid | None = None,
                  steps: WalkSteps | None = None, rng=None, methods=METHODS) -> dict:
    """Score every track of :data:`METHODS` at the waypoints of ``trace``.

    ``db``, ``calibration`` and ``fix_var_m2`` must come from other walks (see :func:`evaluate_track`,
    which builds them from walk files); ``db`` containing the walk raises. ``grid``: the floor's
    walkable raster (:meth:`OccupancyGrid.from_floor_map`), needed by ``map_align``; the particle filter
    runs unconstrained without it.

    Returns
    -------
    dict
        ``errors`` (DataFrame: one row per waypoint, one column per method, metres), ``tracks``
        (method -> (n+1, 2) states), ``state_t_s``, ``fixes`` (WifiFixes), ``info`` (dict). ``errors``
        also has ``oracle_shape_m``: a diagnostic (the track fitted onto the walk's own waypoints), never
        a method.

    References
    ----------
    Chiu (2013), eq. 20-26 (the step Kalman filter); Rauch, Tung, Striebel (1965); Huber (1981), the
    robust placement of the track on the fixes.
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
    if fx.t_s.size >= 2:            # Huber-robust start with the heading held fixed
        t0 = fit_track_to_fixes(at_fix, fx.xy_m, huber_m=cfg.huber_m, rotation=False).t_m
    else:
        t0 = fx.xy_m[0] - at_fix[0]
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
        g1 = grid.coarsen(1.0)
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


def evaluate_track(trace, db_traces, floor_map=None, cfg: RealWalkConfig = RealWalkConfig(), rng=0,
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
    grid = OccupancyGrid.from_floor_map(floor_map, cfg.grid_cell_m) if floor_map is not None else None
    r = evaluate_walk(trace, db, cal, var, cfg, grid=grid, rng=rng, methods=methods)
    r["info"]["wifi_config"] = label
    return r
