"""Configuration and method names of the track pipeline (see :mod:`ilocalg.track`)."""

from __future__ import annotations

from dataclasses import dataclass

#: Keys of the scored tracks (the ``evaluate track`` command's ``errors_m`` keys).
METHODS = ("pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts", "pf", "pf_smooth", "map_align",
           "map_align_kf_rts", "lsq", "lsq_map", "lsq_online", "lsq_online_map", "kf_gain", "kf_gain_map",
           "kf_gain_lag5s", "kf_gain_map_lag5s", "kf_gain_map_start5s", "lsq_online_map_start5s", "lsq_paths",
           "lsq_grid", "map_align_grid", "lsq_online_map_grid", "kf_gain_map_grid")
#: The online methods (an estimate at time t uses the walk up to t only); the others use the whole walk. One
#: exception, shared by all of them and by the Wi-Fi-only track: a time before the walk's first Wi-Fi fix is
#: known has its estimate once that fix is (the first fix, or the PDR track placed through it).
CAUSAL_METHODS = ("pdr", "wifi", "kf", "pf", "lsq_online", "lsq_online_map", "kf_gain", "kf_gain_map",
                  "lsq_online_map_grid", "kf_gain_map_grid")
#: The methods that need the measured gain spread (:func:`ilocalg.track.motion.gain_stats`).
GAIN_METHODS = ("kf_gain", "kf_gain_map", "kf_gain_lag5s", "kf_gain_map_lag5s", "kf_gain_map_start5s",
                "kf_gain_map_grid")
#: The methods that need the walked-path graph of the database walks (:class:`ilocalg.track.paths.WalkedPaths`).
PATH_METHODS = ("lsq_paths",)
#: The variants located at the query times on the survey's marked points (:mod:`ilocalg.track.grid`): method -> its
#: base track. They use the times the walk is asked about (scored: its waypoints' times) and the database walks'
#: waypoints (the marked points the surveyors stood on); a query far from every marked point keeps the base's estimate.
GRID_METHODS = {"lsq_grid": "lsq", "map_align_grid": "map_align", "lsq_online_map_grid": "lsq_online_map",
                "kf_gain_map_grid": "kf_gain_map"}
#: The methods that need the floor map.
MAP_METHODS = ("pf", "pf_smooth", "map_align", "map_align_kf_rts", "lsq_map", "lsq_online_map", "kf_gain_map",
               "kf_gain_map_lag5s", "kf_gain_map_start5s", "lsq_online_map_start5s", "map_align_grid",
               "lsq_online_map_grid", "kf_gain_map_grid")
#: Online methods with a declared latency (not causal): method -> what waits for how long.
LATENCY_METHODS = {"kf_gain_lag5s": "every state 5 s", "kf_gain_map_lag5s": "every state 5 s",
                   "kf_gain_map_start5s": "the start-up, until 5 s after the first fix is known",
                   "lsq_online_map_start5s": "the start-up, until 5 s after the first fix is known"}


def latency_of(method: str) -> str:
    """What a method waits for before it reports: ``none`` (:data:`CAUSAL_METHODS`), its
    :data:`LATENCY_METHODS` text, or ``whole walk`` (offline)."""
    return "none" if method in CAUSAL_METHODS else LATENCY_METHODS.get(method, "whole walk")


#: The fix-variance models of :attr:`RealWalkConfig.fix_var`.
FIX_VARS = ("isotropic", "per_fix")


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
    min_stride_nac : robust detector's walk detection at bout ends; None (off): chosen on the Oxford
        recordings, not measured on tracks; on ILC walks, which start with their recording, it drops first
        peaks (site1 F1: 98 peaks in 59 of 100 walks).
    huber_m : robust threshold of the track-to-fixes fit.
    n_particles, pf_* : particle filter (see :func:`ilocalg.fusion.particle_filter.map_particle_filter`).
    pf_recovery : the particle filter's recovery (``recovery`` of
        :func:`~ilocalg.fusion.particle_filter.map_particle_filter`; None: none). Augmented MCL by default:
        leave-one-walk-out with the nested Wi-Fi selection, every 5th walk of site1 F1 and F2 (309
        waypoints), pf 8.22 -> 4.75 m mean (1.37 -> 0.79 x Wi-Fi only), pf_smooth 7.47 -> 3.99 m; F2 pf
        12.74 -> 5.56 m, F1 pf 3.73 -> 3.94 m (seed 1: pooled pf 6.52 -> 4.85 m, F1 3.93 -> 4.00 m, so the
        F1 change is within the seed-to-seed spread). ``"amcl"`` (averages restarted after an injection),
        seed 0: pooled pf 4.94 m, F1 3.75 m, F2 6.13 m.
    grid_cell_m : walkable raster resolution.
    baro_change_m, baro_smooth_s : a floor change is a barometric height change of more than
        ``baro_change_m`` (half a typical 3-4 m storey; smoothed over ``baro_smooth_s``).
    floor_votes : Wi-Fi floor votes in the majority without a barometer (latest ones for causal
        methods, centred for whole-walk ones).
    fix_var : the Wi-Fi fix variance every method weights a fix by: ``"isotropic"``, one variance for all
        fixes (leave-one-walk-out on the database, :func:`ilocalg.track.calibrate_fix_var`), or ``"per_fix"``,
        each fix's own, predicted from what the fix knows about itself (its neighbours' spread, the access
        points heard, its readings' age) by a model fitted leave-one-walk-out on the database walks
        (:func:`ilocalg.track.fixes.fit_fix_var_model`). Default ``"per_fix"``: on the development walks of site1
        F1 (the even ones, leave-one-walk-out) it lowered every least-squares and ``kf_gain`` error a little
        (``lsq_map`` 0.615 -> 0.603 x Wi-Fi only, ``lsq_online_map`` 0.776 -> 0.772; notebook 09's ablation).
        With ``fix_corr`` and ``map_start`` too, on the held-out walks (scored once): F2 better (``lsq_map``
        0.659 -> 0.618, ``lsq_online_map`` 0.775 -> 0.737), F1 odd slightly worse (0.625 -> 0.635, 0.764 -> 0.774).
    map_start : the online map variants (``lsq_online_map``, ``kf_gain_map``) start from the first fix's
        walkable posterior (the fix's Gaussian times a uniform prior over the walkable cells,
        :func:`ilocalg.track.estimators.map_first_fix`) instead of the fix itself (on by default; on the
        development walks the start-up error of the online map variants fell from 5.42 to 5.30 m).
    fix_corr : the ``kf_gain*`` filters carry the part of the Wi-Fi fix error that persists from fix to fix
        (a first-order Gauss-Markov state; share and correlation measured on the database walks'
        leave-one-walk-out fixes, :func:`ilocalg.track.fixes.fix_error_correlation`) instead of taking every
        fix's error as independent; the least-squares estimators as unknowns. On by default: on site1 F1 about
        56 % of the fix error variance persists, with a fix-to-fix correlation of 0.87.
    align_fix_time : the least-squares estimators tie each Wi-Fi fix to the time its readings were taken
        (:attr:`ilocalg.track.WifiFixes.t_read_s`) rather than the scan's time stamp. Off: with the
        database positioned likewise (the floor model and evaluate_track pass it as ``align_time``) it changed nothing
        measurable on site1 (leave-one-walk-out, every 25th walk of F1 and F2: lsq 5.72 -> 5.82 m, Wi-Fi
        only 7.66 -> 7.78 m).
    """

    k_neighbors: int = 5
    p: int = 2
    weights: str = "distance"
    metric: str = "minkowski"
    not_heard_dbm: float = -100.0
    max_age_s: float | None = 2.0
    fix_min_var_m2: float = 25.0
    fix_scale: float = 1.0
    sigma_heading_rad: float = 0.1
    sigma_sl_m: float = 0.15
    min_bout_steps: int = 4
    min_stride_nac: float | None = None
    huber_m: float = 10.0
    n_particles: int = 1000
    pf_sigma_heading_rad: float = 0.1
    pf_sigma_offset0_rad: float = 0.35
    pf_outlier_prob: float = 0.2
    pf_blocked_weight: float = 1e-3
    pf_recovery: str | None = "augmented"
    grid_cell_m: float = 0.5
    baro_change_m: float = 2.0
    baro_smooth_s: float = 2.0
    floor_votes: int = 5
    align_fix_time: bool = False
    fix_var: str = "per_fix"
    map_start: bool = True
    fix_corr: bool = True

    def __post_init__(self):
        if self.fix_var not in FIX_VARS:
            raise ValueError(f"RealWalkConfig.fix_var must be one of {FIX_VARS}, got {self.fix_var!r}")




#: The default configuration (module-level, frozen).
DEFAULT_CONFIG = RealWalkConfig()
