"""From a phone walk to a track: PDR + Wi-Fi fusion of one walk, everything learned from other walks.

A walk is a :class:`ilocalg.io.recording.Recording` (the IMU log, the Wi-Fi scans, optionally the
barometer and, for learning and scoring only, the ground truth), whatever file it came from: every
function here also takes a loader's own type (:class:`~ilocalg.io.ilc.IlcTrace`,
:class:`~ilocalg.io.ipin.IpinLog`), converted by :func:`ilocalg.io.recording.as_recording`. A walk
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
    interpolating its walk's ground truth in time, :func:`ilocalg.io.recording.recording_fingerprints`,
    all walks in one shared local frame: geographic walks, such as IPIN logfiles that each start
    their x/y at their own first point, are pooled through latitude/longitude) and the
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

Floors (:func:`estimate_floors`)
    When the fingerprints have floor numbers: each fix's floor by a distance-weighted vote of its
    WKNN neighbours' floors (Wi-Fi floor classification); with a barometer, the walk is cut where
    the barometric height changes by more than ``baro_change_m`` and each level segment takes the
    Wi-Fi floors' majority (causal methods: the votes so far; whole-walk methods: all the segment's
    votes); without one, a majority over the latest (causal) or surrounding (whole-walk) votes.
Scoring (:func:`error_table`, :func:`summary_table`)
    Horizontal error at every ground-truth point; mean / median / p75 / p95, the floor hit rate and
    the penalised error (+15 m per wrong floor, :func:`ilocalg.metrics.penalised_error_m`).

:func:`evaluate_track` runs the whole chain for one walk given the other walks (and optionally the
floor map); the ``evaluate track`` command and the real-walk experiment call it. In a notebook::

    db_walks = [load_recording(p) for p in paths]            # ILC, IPIN, simulated ... walks
    r = evaluate_track(load_recording(path), db_walks)       # or evaluate_walk with a built database
    r["track"], r["errors"], summary_table(r)                # per-state tracks, per-point errors, statistics

References
----------
Chiu P.-J., i-Loc M.S. thesis, NCTU (2013), eq. 18-19 (WDM heading) and eq. 20-26 (step Kalman
filter); Torres-Sospedra J. et al., "Off-line evaluation of mobile-centric indoor positioning systems:
the experiences from the 2017 IPIN competition", Sensors 18(2) (2018), the penalised error and floor
hit rate; Ye H. et al., "B-Loc: scalable floor localization using barometer on smartphone", IEEE
MASS (2014), barometric floor changes;
Luo S. et al. (罗思奇 et al.), Computer Systems & Applications (2017), KNN fingerprinting with
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
from ilocalg.io.recording import (
    PRESSURE_HPA,
    LocalFrame,
    as_recording,
    common_frame,
    recording_fingerprints,
    truth_at,
)
from ilocalg.io.scans import scan_matrix
from ilocalg.io.schema import ACC_COLS, FLOOR, GYR_COLS, MAG_COLS, T_S, X_M, Y_M
from ilocalg.metrics import penalised_error_m
from ilocalg.pdr.dead_reckoning import dead_reckon
from ilocalg.pdr.heading import gyr_heading_theta_rad, heading_theta_rad
from ilocalg.pdr.robust import detect_steps_robust
from ilocalg.pdr.signals import moving_mean
from ilocalg.pdr.step_length import weinberg_length_m
from ilocalg.units import as_rng, wrap_angle_rad
from ilocalg.wifi import KnnFingerprint
from ilocalg.wifi.knn import knn_predict, neighbour_weights
from ilocalg.wifi.preprocessing import shares_no_ap

__all__ = ["RealWalkConfig", "METHODS", "WIFI_CANDIDATES", "WalkSteps", "walk_steps", "Calibration", "calibrate",
           "WifiDatabase", "WifiFixes", "locate_wknn", "wifi_fixes", "calibrate_fix_var", "select_wifi",
           "evaluate_walk", "evaluate_track", "FloorEstimate", "barometric_segments", "estimate_floors",
           "track_table", "error_table", "summary_table", "CAUSAL_METHODS"]

#: Keys of the scored tracks (the ``evaluate track`` command's ``errors_m`` keys).
METHODS = ("pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts", "pf", "pf_smooth", "map_align",
           "map_align_kf_rts")
#: The online methods (an estimate at time t uses the walk up to t only); the others use the whole walk.
CAUSAL_METHODS = ("pdr", "wifi", "kf", "pf")


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
    baro_change_m, baro_smooth_s : a floor change is a barometric height change of more than
        ``baro_change_m`` (half a typical 3-4 m storey; smoothed over ``baro_smooth_s``).
    floor_votes : Wi-Fi floor votes in the majority without a barometer (latest ones for causal
        methods, centred for whole-walk ones).
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
    baro_change_m: float = 2.0
    baro_smooth_s: float = 2.0
    floor_votes: int = 5


@dataclass(frozen=True)
class WalkSteps:
    """Steps of one walk: ``state_t_s`` (n+1: the log start, then each step), ``a_range_mps2`` (n, the
    Weinberg input), ``theta_rel_rad`` (n, compass-aligned gyro heading, map convention, before the floor
    offset)."""

    state_t_s: np.ndarray
    a_range_mps2: np.ndarray
    theta_rel_rad: np.ndarray


def _n_samples(duration_s: float, rate_hz: float) -> int:
    """Samples in a window: ``floor(duration * rate)`` (at least 1), immune to the rounding of the rate
    estimated from timestamps (a 50 Hz log stored as Unix milliseconds gives 49.99999 or 50.00005 Hz)."""
    return max(int(duration_s * rate_hz + 1e-3), 1)


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
    g = np.column_stack([moving_mean(acc[:, j], _n_samples(0.5, rate)) for j in range(3)])
    m = np.column_stack([moving_mean(imu[list(MAG_COLS)].to_numpy()[:, j], _n_samples(0.25, rate))
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
    interpolated ground truth, NaN outside its span: for scoring only), ``floor`` (m,; the Wi-Fi floor
    vote, NaN when the database has no floors), ``true_floor`` (m,), and the scans left out:
    ``n_outside_walk`` (outside the walk's IMU time span), ``n_no_shared_ap`` (hearing no access
    point of the database)."""

    t_s: np.ndarray
    xy_m: np.ndarray
    R_m2: np.ndarray
    true_xy_m: np.ndarray
    floor: np.ndarray | None = None
    true_floor: np.ndarray | None = None
    n_outside_walk: int = 0
    n_no_shared_ap: int = 0


@dataclass(frozen=True)
class WifiDatabase:
    """Fingerprints of walks, one row per scan: ``rssi_dbm`` (n, n_aps), ``xy_m`` (n, 2) in ``frame``,
    ``walk`` (n,), ``floor`` (n,; NaN when unknown), the walks' content ids (``content_ids``, walk ->
    :attr:`ilocalg.io.recording.Recording.content_id`)."""

    rssi_dbm: np.ndarray
    xy_m: np.ndarray
    walk: np.ndarray
    ap_ids: tuple
    floor: np.ndarray | None = None
    frame: LocalFrame | None = None
    content_ids: dict = dataclasses.field(default_factory=dict, compare=False)

    @classmethod
    def from_recordings(cls, recordings, max_age_s: float | None = None,
                        frame: LocalFrame | None = None) -> WifiDatabase:
        """Every scan of ``recordings`` positioned by interpolating its walk's ground truth (outside: left
        out), all in one shared frame (``frame``, default the first walk's:
        :func:`ilocalg.io.recording.common_frame`)."""
        recs = [as_recording(r) for r in (recordings.values() if isinstance(recordings, dict) else recordings)]
        if not recs:
            raise ValueError("no fingerprint walks given")
        names = [r.name for r in recs]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"fingerprint walks must have distinct names; {dup[0]!r} appears twice")
        rf = recording_fingerprints(recs, frame=frame, max_age_s=max_age_s)
        fp = rf.fingerprints
        return cls(fp.rssi_dbm, fp.xy_m, fp.meta["walk"].to_numpy(dtype=object), tuple(fp.ap_ids),
                   np.asarray(fp.floor, dtype=np.float64), rf.frame, {r.name: r.content_id for r in recs})

    @classmethod
    def from_traces(cls, traces, max_age_s: float | None = None) -> WifiDatabase:
        """:meth:`from_recordings` (kept for walks of any loader type, e.g. ILC traces)."""
        return cls.from_recordings(traces, max_age_s)

    @property
    def has_floors(self) -> bool:
        return self.floor is not None and bool(np.isfinite(self.floor).all())

    def without(self, *walks) -> WifiDatabase:
        """The database without the rows of ``walks`` (leave-walks-out)."""
        keep = ~np.isin(self.walk, list(walks))
        if not keep.any():
            raise ValueError(f"no fingerprint left after removing {walks}")
        return WifiDatabase(self.rssi_dbm[keep], self.xy_m[keep], self.walk[keep], self.ap_ids,
                            None if self.floor is None else self.floor[keep], self.frame,
                            {k: v for k, v in self.content_ids.items() if k not in walks})


def _wknn(db: WifiDatabase, cfg: RealWalkConfig):
    return KnnFingerprint(n_neighbors=min(cfg.k_neighbors, db.xy_m.shape[0]), p=cfg.p, weights=cfg.weights,
                          not_heard_dbm=cfg.not_heard_dbm, kernel="dense", metric=cfg.metric).fit(db.rssi_dbm, db.xy_m)


def locate_wknn(db: WifiDatabase, X, cfg: RealWalkConfig = RealWalkConfig(), return_floor: bool = False):
    """WKNN fixes (m, 2) of queries ``X`` (m, n_aps in ``db.ap_ids`` order) and their spread covariances.

    With ``return_floor`` also each query's floor: the distance-weighted (``cfg.weights``) majority of
    its neighbours' floors (NaN when the database has no floors). A query sharing no access point with
    the database gets NaN (the estimators' documented no-AP result).

    References
    ----------
    Luo et al. (2017), eq. 1-2 (KNN fingerprinting).
    """
    est = _wknn(db, cfg)
    X = np.asarray(X, dtype=np.float64)
    miss = shares_no_ap(X, est.heard_aps_)
    n = X.shape[0]
    xy, C, fl_out = np.full((n, 2), np.nan), np.full((n, 2, 2), np.nan), np.full(n, np.nan)
    if (~miss).any():
        dist, idx = est.kneighbors(X[~miss])
        xy[~miss] = knn_predict(est.y_, idx, neighbour_weights(dist, cfg.weights))
        w = 1.0 / np.maximum(dist, 1e-9) if cfg.weights == "distance" else None
        C[~miss] = fix_covariance_from_spread(db.xy_m[idx], w, min_var_m2=1.0)
        if return_floor and db.has_floors:
            wv = np.ones(idx.shape) if w is None else w
            fl = db.floor[idx]
            levels = np.unique(fl)
            score = np.stack([(wv * (fl == f)).sum(axis=1) for f in levels], axis=1)
            fl_out[~miss] = levels[np.argmax(score, axis=1)]
    return (xy, C, fl_out) if return_floor else (xy, C)


def wifi_fixes(trace, db: WifiDatabase, cfg: RealWalkConfig = RealWalkConfig(),
               fix_var_m2: float | None = None) -> WifiFixes:
    """WKNN fixes of every scan of ``trace`` against ``db``, which must not contain the walk.

    ``R`` of each fix: ``fix_var_m2 I`` (isotropic, e.g. calibrated on other walks by
    :func:`calibrate_fix_var`) or, when None, the neighbour spread plus ``cfg.fix_min_var_m2``.
    Scans outside the walk's IMU time span and scans hearing no access point of the database are left
    out and counted (``n_outside_walk``, ``n_no_shared_ap``). The walk's ground truth (for
    ``true_xy_m``) is moved into the database's frame.
    """
    rec = as_recording(trace)
    if rec.name and rec.name in set(db.walk):
        raise ValueError(f"the fingerprint database must not contain the scored walk {rec.name!r}")
    same = [k for k, v in db.content_ids.items() if len(rec.imu) and v == rec.content_id]
    if same:
        raise ValueError(f"the fingerprint database must not contain the scored walk {rec.name!r}: its walk "
                         f"{same[0]!r} has the same sensor content")
    if db.frame is not None and len(rec.truth):
        rec = rec.in_frame(db.frame)
    w = rec.wifi
    if not len(w):
        raise ValueError(f"{rec.source or rec.name}: the walk has no Wi-Fi scan")
    fresh = None if cfg.max_age_s is None else ((w[T_S] - w["last_seen_s"]) <= cfg.max_age_s).to_numpy()
    _, t, X = scan_matrix(w, db.ap_ids, keep=fresh)
    t0, t1 = rec.t_span_s
    inside = (t >= t0) & (t <= t1)
    heard = ~np.isnan(X).all(axis=1)          # scans sharing no AP with the database cannot be located
    keep = inside & heard
    t, X = t[keep], X[keep]
    if not t.size:
        raise ValueError(f"{rec.source or rec.name}: no scan inside the walk's time span shares an access point "
                         f"with the database ({int((~inside).sum())} outside the span, "
                         f"{int((inside & ~heard).sum())} hearing none of its {len(db.ap_ids)} APs)")
    xy, C, fl = locate_wknn(db, X, cfg, return_floor=True)
    R = (fix_var_m2 * np.broadcast_to(np.eye(2), C.shape).copy() if fix_var_m2 is not None
         else C + (cfg.fix_min_var_m2 - 1.0) * np.eye(2))
    if len(rec.truth) >= 2:
        true, tfl = truth_at(rec.truth, t, outside="nan")
    else:
        true, tfl = np.full((t.size, 2), np.nan), np.full(t.size, np.nan)
    return WifiFixes(t, xy, R, true, fl, tfl, int((~inside).sum()), int((inside & ~heard).sum()))


def calibrate_fix_var(db: WifiDatabase, cfg: RealWalkConfig = RealWalkConfig()) -> tuple[float, pd.DataFrame]:
    """Isotropic Wi-Fi fix variance (per axis, m^2) by leave-one-walk-out *inside* ``db``.

    Each walk of ``db`` is located against the others; ``var = mean(error^2) / 2``. Scans sharing no
    access point with the other walks are not located and not counted (``n_unlocated``). Returns the
    variance and the per-walk errors table (``walk, n, mean_error_m, n_unlocated``; ``n`` located scans).
    """
    walks = list(dict.fromkeys(db.walk))
    errs, rows = [], []
    for v in walks:
        rest = db.without(v)
        m = db.walk == v
        xy, _ = locate_wknn(rest, db.rssi_dbm[m], cfg)
        e = np.hypot(*(xy - db.xy_m[m]).T)
        ok = np.isfinite(e)
        errs.append(e[ok])
        rows.append({"walk": v, "n": int(ok.sum()), "mean_error_m": float(e[ok].mean()) if ok.any() else np.nan,
                     "n_unlocated": int((~ok).sum())})
    e = np.concatenate(errs)
    if not e.size:
        raise ValueError("calibrate_fix_var: no scan of any fingerprint walk shares an access point with the other "
                         "walks; the Wi-Fi fix variance cannot be learned")
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
        per = per[per["n"] > 0]
        e = float(np.average(per["mean_error_m"], weights=per["n"]))
        rows.append({"label": label, "mean_error_m": e, "fix_sd_m": float(np.sqrt(var))})
        if best is None or e < best[0]:
            best = (e, label, c, var)
    return best[1], best[2], best[3], pd.DataFrame(rows)


@dataclass(frozen=True)
class FloorEstimate:
    """Floors of one walk: ``causal`` and ``offline`` (functions of time, see :func:`estimate_floors`) are
    given as values at ``t_s`` of the queries; ``segments`` (DataFrame ``t0_s, t1_s, height_m``: the
    barometric level segments, one row when there is no barometer); ``source`` ("wifi" or
    "wifi+barometer")."""

    segments: pd.DataFrame
    source: str
    vote_t_s: np.ndarray
    vote_floor: np.ndarray

    def _segment(self, t_s):
        """Segment of each time; a time during a level change belongs to the level it is nearer in time
        (the change's midpoint splits it)."""
        seg = self.segments
        cut = 0.5 * (seg["t1_s"].to_numpy()[:-1] + seg["t0_s"].to_numpy()[1:])
        return np.searchsorted(cut, t_s, side="right")

    def at(self, t_s, causal: bool, n_votes: int = 5) -> np.ndarray:
        """Floor at times ``t_s`` (NaN before the first vote of a causal estimate without a barometer)."""
        t = np.atleast_1d(np.asarray(t_s, dtype=np.float64))
        out = np.full(t.size, np.nan)
        vt, vf = self.vote_t_s, self.vote_floor
        if not vt.size:
            return out
        if self.source == "wifi":
            for i, ti in enumerate(t):
                if causal:
                    sel = vf[max(0, np.searchsorted(vt, ti, side="right") - n_votes):
                             np.searchsorted(vt, ti, side="right")]
                    if not sel.size:
                        sel = vf[:1]            # before the first scan: the first scan's floor
                else:
                    c = int(np.argmin(np.abs(vt - ti)))
                    sel = vf[max(0, c - n_votes // 2): c + n_votes // 2 + 1]
                out[i] = _majority(sel)
            return out
        seg = self._segment(t)
        vseg = self._segment(vt)
        h = self.segments["height_m"].to_numpy()
        for i, (ti, si) in enumerate(zip(t, seg, strict=True)):
            # every vote, referred to this segment by the barometric height difference
            m = (vt <= ti) if causal else np.ones(vt.size, dtype=bool)
            if not m.any():
                m = np.zeros(vt.size, dtype=bool)
                m[0] = True
            here = m & (vseg == si)
            if here.any():
                out[i] = _majority(vf[here])
            else:          # no vote on this level yet: the nearest level's floor + the height change in storeys
                j = vseg[m][np.argmin(np.abs(vseg[m] - si))]
                base = _majority(vf[m & (vseg == j)])
                dz = (h[si] - h[j]) / _STOREY_M
                out[i] = base + (np.sign(dz) * max(1.0, round(abs(dz))) if abs(dz) > 0 else 0.0)
        return out


#: Storey height (m) used only to count storeys of a barometric level change that no Wi-Fi vote covers.
_STOREY_M = 3.5


def _majority(v) -> float:
    v = np.asarray(v, dtype=np.float64)
    v = v[np.isfinite(v)]
    if not v.size:
        return np.nan
    u, c = np.unique(v, return_counts=True)
    return float(u[np.argmax(c)])        # ties: the lowest floor


def barometric_segments(pressure: pd.DataFrame, change_m: float = 2.0, smooth_s: float = 2.0) -> pd.DataFrame:
    """Cut a walk into level segments where the barometric height changes by more than ``change_m``.

    Height from pressure by the ICAO standard atmosphere, ``h = 44330.8 (1 - (p / p_ref)^0.190263)`` m,
    relative to the walk's start, after a moving mean over ``smooth_s``. A segment ends when the height
    leaves its level by more than ``change_m``; the next starts when the height is level again (changes
    by less than ``change_m / 4`` over ``smooth_s``).

    Returns
    -------
    DataFrame
        ``t0_s, t1_s, height_m`` (mean height of the segment), one row per level segment.

    References
    ----------
    ICAO, Manual of the ICAO Standard Atmosphere, Doc 7488 (1993); Ye H. et al., B-Loc, IEEE MASS (2014).
    """
    t = pressure.index.to_numpy(dtype=np.float64)
    p = pressure[PRESSURE_HPA].to_numpy(dtype=np.float64)
    if t.size < 2:
        raise ValueError(f"barometer: need at least 2 pressure samples, got {t.size}")
    if not np.all((p > 300) & (p < 1100)):
        raise ValueError("barometer: pressure outside (300, 1100) hPa")
    rate = 1.0 / float(np.median(np.diff(t)))
    h = 44330.8 * (1.0 - (p / p[0]) ** 0.190263)
    hs = moving_mean(h, max(int(round(smooth_s * rate)), 1))
    lag = max(int(round(smooth_s * rate)), 1)
    rows, start, ref, moving = [], 0, hs[0], False
    for i in range(t.size):
        if not moving and abs(hs[i] - ref) > change_m:
            moving = True
            end = i
            while end > start and abs(hs[end] - ref) > change_m / 4:
                end -= 1
            rows.append((t[start], t[end], float(np.mean(hs[start:end + 1]))))
        elif moving and i >= lag and abs(hs[i] - hs[i - lag]) < change_m / 4:
            moving, start, ref = False, i, hs[i]
    last = (t[start], t[-1], float(np.mean(hs[start:]))) if not moving else (t[end + 1], t[-1], float(hs[-1]))
    rows.append(last)
    return pd.DataFrame(rows, columns=["t0_s", "t1_s", "height_m"])


def estimate_floors(fixes: WifiFixes, pressure: pd.DataFrame | None = None,
                    cfg: RealWalkConfig = RealWalkConfig()) -> FloorEstimate | None:
    """The walk's floors from its Wi-Fi floor votes (and barometric level changes when ``pressure`` is given).

    None when the fixes carry no floor (a database without floor numbers).
    """
    if fixes.floor is None or not np.isfinite(fixes.floor).any():
        return None
    if pressure is not None and len(pressure) >= 2:
        seg = barometric_segments(pressure, cfg.baro_change_m, cfg.baro_smooth_s)
        return FloorEstimate(seg, "wifi+barometer", fixes.t_s, fixes.floor)
    seg = pd.DataFrame({"t0_s": [-np.inf], "t1_s": [np.inf], "height_m": [0.0]})
    return FloorEstimate(seg, "wifi", fixes.t_s, fixes.floor)


def _latest_fix(fix_t, fix_xy, t_s):
    i = np.clip(np.searchsorted(fix_t, t_s, side="right") - 1, 0, fix_t.size - 1)
    return fix_xy[i]


def evaluate_walk(trace, db: WifiDatabase, calibration: Calibration, fix_var_m2: float,
                  cfg: RealWalkConfig = RealWalkConfig(), grid: OccupancyGrid | None = None,
                  steps: WalkSteps | None = None, rng=None, methods=METHODS) -> dict:
    """Score every track of :data:`METHODS` at the ground-truth points of ``trace``.

    ``db``, ``calibration`` and ``fix_var_m2`` must come from other walks (see :func:`evaluate_track`,
    which builds them from walk files); ``db`` containing the walk (by name or sensor content) raises.
    ``grid``: the floor's walkable raster (:meth:`OccupancyGrid.from_floor_map`), needed by
    ``map_align``; the particle filter runs unconstrained without it.

    Returns
    -------
    dict
        ``errors`` (DataFrame: one row per ground-truth point, one column per method, metres),
        ``tracks`` (method -> (n+1, 2) states), ``state_t_s``, ``fixes`` (WifiFixes), ``info`` (dict),
        ``scans`` (counts of the scans left out), ``floors`` (DataFrame per ground-truth point:
        ``floor_true`` and one column per method, or None without floor numbers), ``track`` (long
        DataFrame ``t_s, method, x_m, y_m, floor`` of every state, :func:`track_table`). ``errors``
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
    cal = calibration
    fx = wifi_fixes(rec, db, cfg, fix_var_m2=fix_var_m2)
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
    out = {"errors": pd.DataFrame(err), "tracks": tracks, "state_t_s": ts, "fixes": fx, "info": info,
           "scans": scans, "floors": floors}
    out["track"] = track_table(out, state_floor)
    return out


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


def evaluate_track(trace, db_traces, floor_map=None, cfg: RealWalkConfig = RealWalkConfig(), rng=0,
                   methods=METHODS, select: bool = True) -> dict:
    """:func:`evaluate_walk` with everything learned from ``db_traces`` (walks with ground truth).

    Builds the fingerprint database (all walks in the first one's frame, the scored walk moved into it),
    the step-length factor and heading offset (:func:`calibrate`) and the fix variance
    (:func:`calibrate_fix_var`; with ``select`` the Wi-Fi configuration too, :func:`select_wifi`) from
    ``db_traces`` only; ``floor_map`` (an :class:`~ilocalg.io.ilc.IlcFloorMap` or a walkable
    :class:`~ilocalg.fusion.particle_filter.OccupancyGrid`, optional, in the walks' shared frame)
    constrains the particle filter and enables map matching (without it the particle filter runs
    unconstrained). A fingerprint walk that is the scored walk (same name, or same sensor content
    under another name) raises.
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
    db = WifiDatabase.from_recordings(recs, cfg.max_age_s, frame=frame)
    label = "given"
    if len(set(db.walk)) < 2:
        var = cfg.fix_min_var_m2
    elif select:
        label, cfg, var, _ = select_wifi(db, cfg)
    else:
        var, _ = calibrate_fix_var(db, cfg)
    cal = calibrate(recs, cfg=cfg)
    if floor_map is None or isinstance(floor_map, OccupancyGrid):
        grid = floor_map
    else:
        grid = OccupancyGrid.from_floor_map(floor_map, cfg.grid_cell_m)
    r = evaluate_walk(rec, db, cal, var, cfg, grid=grid, rng=rng, methods=methods)
    r["info"]["wifi_config"] = label
    return r
