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
    calibrated isotropic variance. A scan's readings are older than its time stamp (their
    ``last_seen``): each fix also carries the time its readings were taken
    (:func:`ilocalg.track.database.effective_age_s`), where the database can position its scans and
    the least-squares estimators can tie the fix (``align_fix_time``, off: no measurable gain on site1).
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

Least squares (:mod:`ilocalg.track.estimators`), the floor model built once (:mod:`ilocalg.track.floor`)
    ``lsq`` / ``lsq_map`` (offline) and ``lsq_online`` / ``lsq_online_map`` (causal): one sparse system
    of Wi-Fi fixes and PDR steps per walk, weighted by the fix variance (leave-one-walk-out on the
    database) and the step variance (PDR vs waypoints on the database walks), then the map step.
    The online ones start, before the first fix is known, from the PDR track placed through that fix.
Online Kalman filter with the walk's own gain (:mod:`ilocalg.track.online_kf`)
    ``kf_gain`` (causal): a Kalman filter whose state carries, beside the position, the walk's own step
    scale and heading offset as one complex gain on every PDR step (a linear model: the exact filter), each
    late fix applied at the time it describes, Huber-weighted; every noise measured on the other walks
    (:func:`ilocalg.track.motion.gain_stats`). ``kf_gain_map``: each state then moved onto the map.
    ``kf_gain_lag5s``: the same smoothed over a fixed 5 s lag (not causal; its own variant).
    Start-up with a declared latency (:data:`LATENCY_METHODS`, not causal): ``kf_gain_map_lag5s`` (the lag
    smoother moved onto the map), ``kf_gain_map_start5s`` / ``lsq_online_map_start5s`` (a delayed start: the
    states until 5 s after the first fix is known re-estimated from the data known then, later ones causal).
The Wi-Fi fix model (:mod:`ilocalg.track.fixes`, :class:`RealWalkConfig` ``fix_var``, ``fix_corr``, ``map_start``)
    Each fix's own variance (``fix_var="per_fix"``, :class:`~ilocalg.track.fixes.FixVarModel`): log-linear in what
    the fix knows about itself (its neighbours' spread, the access points heard, its readings' age), fitted on the
    database walks' leave-one-walk-out errors. Fix errors that persist from fix to fix (``fix_corr``,
    :func:`~ilocalg.track.fixes.fix_error_correlation`): a Gauss-Markov bias carried by the ``kf_gain*`` filters as
    two states and by the least squares as unknowns. The map at start-up (``map_start``): the online map variants
    start from the first fix's walkable posterior (:func:`~ilocalg.track.estimators.walkable_posterior`).
On the survey's marked points, at the query times (:mod:`ilocalg.track.grid`, :data:`GRID_METHODS`)
    ``lsq_grid``, ``map_align_grid`` (offline) and ``lsq_online_map_grid``, ``kf_gain_map_grid`` (causal): not
    tracks but positions at the times the walk is asked about (scored: its waypoints' times, given as in the 2021
    competition), each a database walk's waypoint (where the surveyors stand) decoded by a hidden Markov model over
    them from the base track and the PDR (Viterbi offline, the forward filter online), or the base's own estimate
    where no marked point is near or "no marked point" is more probable (always, where the database walks share no
    waypoint).
Floor model
    :func:`build_floor_model` / :func:`cached_floor_model` build a floor's database and calibration
    rows once and save them, with the floor-level Wi-Fi configuration (what a walk from outside the floor
    gets); :meth:`FloorModel.for_walk` leaves the scored walk out, and :meth:`FloorModel.select_wifi` makes
    and keeps the nested Wi-Fi choices of the floor's own walks.

Modules: ``database`` (fingerprints, save/load), ``fixes`` (Wi-Fi), ``motion`` (steps, calibration),
``estimators`` (least squares, map step), ``online_kf`` (the gain-augmented Kalman filter), ``floor`` (the
cached floor model), ``grid`` (the survey's marked points and the ``*_grid`` variants), ``paths`` (the
walked-path graph of the database walks' waypoints and ``lsq_paths``, the least squares pulled towards it),
``evaluation``, ``lowo`` (leave-one-walk-out pooling over floors, the Wi-Fi
ablation, a floor's files), ``online_pf`` (a particle filter with ``kf_gain``'s model; tested, not a method).
Diagnostics of issue 26, no method: ``error_sources`` (oracle ablations: which error source the online tracks
keep), ``surface`` (the walk placed on its scans' likelihood surface) and ``walk_align`` (its scan sequence
aligned to the database walks'); each module's docstring gives what it measured on the development walks.

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
from ilocalg.track._config import (
    CAUSAL_METHODS,
    GRID_METHODS,
    LATENCY_METHODS,
    MAP_METHODS,
    METHODS,
    PATH_METHODS,
    RealWalkConfig,
)
from ilocalg.track.database import WifiDatabase
from ilocalg.track.estimators import ESTIMATORS, Estimator, TrackProblem
from ilocalg.track.evaluation import error_table, evaluate_track, evaluate_walk, summary_table, track_table
from ilocalg.track.fixes import (
    WIFI_CANDIDATES,
    FloorEstimate,
    WifiFixes,
    barometric_segments,
    calibrate_fix_var,
    classify_floor,
    estimate_floors,
    locate_wknn,
    select_wifi,
    wifi_fixes,
)
from ilocalg.track.floor import FloorModel, WalkModel, build_floor_model, cached_floor_model
from ilocalg.track.motion import Calibration, WalkSteps, calibrate, calibrate_step_var, walk_steps

__all__ = ["RealWalkConfig", "METHODS", "WIFI_CANDIDATES", "WalkSteps", "walk_steps", "Calibration", "calibrate",
           "WifiDatabase", "WifiFixes", "locate_wknn", "wifi_fixes", "calibrate_fix_var", "select_wifi",
           "evaluate_walk", "evaluate_track", "FloorEstimate", "barometric_segments", "estimate_floors",
           "track_table", "error_table", "summary_table", "CAUSAL_METHODS", "LATENCY_METHODS", "MAP_METHODS",
           "PATH_METHODS", "GRID_METHODS", "ESTIMATORS", "Estimator", "TrackProblem",
           "FloorModel", "WalkModel", "build_floor_model", "cached_floor_model", "calibrate_step_var",
           "classify_floor"]
