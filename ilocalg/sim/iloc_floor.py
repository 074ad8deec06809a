"""The i-Loc floor: a simulated Wi-Fi radio map of NCTU Engineering Building 3, 2nd floor.

The thesis's measured radio map is not published, so the toolkit simulates one with the geometry
and survey protocol the thesis states, and an indoor propagation model whose parameters come from
published propagation measurements (never from the positioning results to be reproduced). The test
session is not the survey: it happens on another day (per-AP drift), with the walker facing the
walking direction (body shadowing), possibly with another phone (device offset).

Geometry and survey (i-Loc thesis, Chiu 2013, L295, L515)
    Floor 75.46 m x 50.26 m; 63 training points 2 m apart; 300 scans per point taken at different
    times; 4-18 APs heard per scan; a test route of 28 points that are also training points, marked
    on the floor 4.11 m apart (L515); points near windows and corners drift more (Fig 2).
    The floor plan (Fig 2) is missing from the text. Assumed layout: a ring corridor 2.4 m wide
    around a block of offices (centre line 36 m x 20 m, 56 training points) with a 7-point corridor
    leading south to the stairs, offices (8 m bays) inside and outside the ring. The route is every
    second ring point, counter-clockwise from the south-west corner: 28 points 4 m apart (2 m grid
    of L295; the text's 4.11 m is not a multiple of it), 108 m long (thesis: 27 x 4.11 = 111 m).
Access points
    ``n_aps_floor`` APs in the offices of this floor and ``n_aps_other`` on the floors above and
    below (3.5 m storey), at seeded random positions off the corridors; the two counts and the
    detection inputs are calibrated to the thesis's 4-18 APs per scan (L295).
Mean field: COST 231 multi-wall model
    ``P0 - 10 n log10(max(d, 1 m)) - L_light k_light - L_heavy k_heavy - L_floor k_floor + shadow``
    with ``n = 2`` (free-space distance dependence: the walls are counted explicitly),
    ``L_light = 3.4 dB`` (plasterboard, light partitions), ``L_heavy = 6.9 dB`` (load-bearing
    concrete / brick: outer and corridor walls, an assumption on which walls are heavy) and
    ``L_floor = 18.3 dB`` (one floor), the COST 231 multi-wall fit at 1.8 GHz (COST 231 final
    report, Damosso 1999, sec. 4.7; Lott & Forkel 2001). Residual shadowing: Gaussian, 5 dB,
    exponential correlation 5 m (Rappaport 2002, table 4.6 range 3-8 dB; Gudmundson 1991), drawn
    as a random-Fourier-feature field so it can be evaluated anywhere on the floor.
Temporal variation
    A session is one visit (a day / time of day). Per session and AP: a floor-wide drift
    ``N(0, drift_sd_db = 3 dB)`` (day-to-day change of an AP's mean RSSI, 3-5 dB reported by
    Kaemarungsi & Krishnamurthy 2004 and Chapre et al. 2013; the lower end is the default);
    per session, point and AP a local change ``N(0, local_sd_db = 2 dB)`` (people, doors); per
    scan a fast fade ``N(0, fade_sd_db = 3 dB)`` at corridor points and 5 dB within ``edge_m`` of a
    window or a corner (Fig 2; static-phone spreads of 2-6 dB, Kaemarungsi & Krishnamurthy 2004).
    The drift is constant within a session and changes between sessions.
Body shadowing (Bahl & Padmanabhan 2000)
    The surveyor's / walker's body attenuates an AP behind it: ``body_loss_db (1 - cos a) / 2``,
    ``a`` the angle between the facing direction and the direction to the AP, ``body_loss_db =
    5 dB`` (RADAR's measurement of the user's orientation effect). Survey sessions face one of the
    four corridor directions at random (RADAR's survey protocol; the thesis is silent); test scans
    face the walking direction.
Device
    The test phone reads ``device_offset_db`` (default 0 dB: the thesis names one Android phone,
    L515; swept in notebook 15) above the survey phone.
Detection
    A reading is reported at or above ``detect_dbm``; a detectable AP is still missed with
    probability ``miss_p``. RSSI is rounded to integer dBm.
Scans while walking (thesis ch. 5)
    :func:`walking_scans`: one scan per fix; each AP is read at a uniform time within the scan
    (``scan_latency_s``, the channel sweep) at the walker's position then, facing the walking
    direction; the fix is tagged with the position and time at the scan's start and becomes
    available at its end.

Measured world (the default, ``simulate(world="measured")``)
    The path-loss P0 and exponent (fitted jointly), shadowing sd, survey-to-test drift sd, fast-fading sd, detection
    threshold and miss probability are rows of data/measured_parameters.csv measured on
    UJIIndoorLoc (:data:`MEASURED_ROWS`, :func:`world_sources`); walls count 0 dB there (the
    measured log-distance fit carries them). Where a copied value does not come back when the same
    statistic is measured on the simulated floor (shadowing sd, fast-fading sd, detection threshold:
    censoring by the threshold and the unknown AP positions bias the per-AP fit), the
    parameter takes its inverse calibration instead (:data:`CALIBRATED`,
    data/calibrated_parameters.csv, :mod:`ilocalg.measure.calibrate`), and the AP counts follow the
    thesis's 4-18 APs per scan (L295) for the calibrated propagation. ``world="copied"`` is the
    uncalibrated variant (measured values copied). Everything above is the ``"assumed"`` world.

Everything is deterministic from ``seed`` (same seed -> identical arrays).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 3.1 (environment, L295), 4.4 (test route, L515).
Damosso, E. (ed.) (1999). COST Action 231 final report: Digital mobile radio towards future
generation systems. Sec. 4.7 (multi-wall model).
Lott, M., Forkel, I. (2001). A multi-wall-and-floor model for indoor radio propagation. IEEE VTC Spring.
Bahl, P., Padmanabhan, V. N. (2000). RADAR: an in-building RF-based user location and tracking
system. IEEE INFOCOM.
Kaemarungsi, K., Krishnamurthy, P. (2004). Properties of indoor received signal strength for WLAN
location fingerprinting. MobiQuitous.
Chapre, Y., Mohapatra, P., Jha, S., Seneviratne, A. (2013). Received signal strength indicator and
its analysis in a typical WLAN system. IEEE LCN.
Rappaport, T. S. (2002). Wireless Communications, 2nd ed., table 4.6.
Gudmundson, M. (1991). Correlation model for shadow fading in mobile radio systems. Electronics
Letters 27(23).
Rahimi, A., Recht, B. (2007). Random features for large-scale kernel machines. NIPS.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.io.schema import FingerprintSet
from ilocalg.units import as_rng
from ilocalg.wifi.preprocessing import mean_fingerprints
from ilocalg.wifi.registry import paper_estimators

__all__ = [
    "FloorFixes",
    "floor_fixes",
    "FLOOR_W_M",
    "FLOOR_H_M",
    "N_TRAIN_POINTS",
    "N_TEST_POINTS",
    "SCANS_PER_POINT",
    "SPACING_M",
    "ROUTE_SPACING_M",
    "PARAMS",
    "PARAM_SOURCES",
    "WORLDS",
    "MEASURED_ROWS",
    "world_params",
    "world_sources",
    "IlocFloor",
    "training_points",
    "test_route_index",
    "route_xy_m",
    "walls",
    "wall_materials",
    "mean_rssi_dbm",
    "simulate",
    "simulate_device_offsets",
    "walking_scans",
    "session_drift_db",
    "walking_fixes",
    "back_to_back_scan_starts_s",
    "periodic_scan_starts_s",
    "fit_estimator",
    "standing_fix_variance_m2",
    "summary",
]

# Settings from the paper
# -----------------------
# Chiu (2013) L295 (inputs): FLOOR_W_M and FLOOR_H_M (floor length and width), N_TRAIN_POINTS
# (63 training points), SPACING_M (2 m apart), SCANS_PER_POINT (300 scans per training point),
# N_TEST_POINTS (a test route of 28 points that are also training points; L515: 4.11 m apart).
# ROUTE_SPACING_M: every second training point. RING_X_M, RING_Y_M, SPUR_X_M: the assumed layout
# (Fig 2 is missing from the text).
FLOOR_W_M = 75.46
FLOOR_H_M = 50.26
N_TRAIN_POINTS = 63
N_TEST_POINTS = 28
SCANS_PER_POINT = 300
SPACING_M = 2.0
ROUTE_SPACING_M = 2 * SPACING_M
RING_X_M = (20.0, 56.0)
RING_Y_M = (15.0, 35.0)
SPUR_X_M = 38.0
CORRIDOR_HALF_WIDTH_M = 1.2
BAY_M = 8.0
STOREY_M = 3.5

#: Radio-model parameters of the assumed world (see the module docstring and :data:`PARAM_SOURCES`);
#: the default world is the measured one, :func:`world_params`.
PARAMS = {
    "n_aps_floor": 16,
    "n_aps_other": 12,
    "p0_dbm": -40.0,
    "path_loss_exponent": 2.0,
    "light_wall_db": 3.4,
    "heavy_wall_db": 6.9,
    "floor_db": 18.3,
    "shadow_sd_db": 5.0,
    "shadow_corr_m": 5.0,
    "drift_sd_db": 3.0,
    "local_sd_db": 2.0,
    "scans_per_session": 30,
    "fade_sd_db": 3.0,
    "fade_sd_edge_db": 5.0,
    "edge_m": 6.0,
    "body_loss_db": 5.0,
    "device_offset_db": 0.0,
    "detect_dbm": -95.0,
    "miss_p": 0.1,
}

#: Where each default comes from (one line each; data/iloc_floor/README.md has the table).
PARAM_SOURCES = {
    "n_aps_floor": "calibrated to the thesis's 4-18 APs per scan (L295)",
    "n_aps_other": "calibrated to the thesis's 4-18 APs per scan (L295)",
    "p0_dbm": "RSSI at 1 m of a 2.4 GHz AP read by a phone, about -40 dBm (assumption; sets the AP counts with "
              "detect_dbm)",
    "path_loss_exponent": "COST 231 multi-wall model: free-space distance term, walls explicit (Damosso 1999)",
    "light_wall_db": "COST 231 multi-wall model, light wall 3.4 dB (Damosso 1999; Lott & Forkel 2001)",
    "heavy_wall_db": "COST 231 multi-wall model, heavy wall 6.9 dB (Damosso 1999; Lott & Forkel 2001)",
    "floor_db": "COST 231 multi-wall model, one floor 18.3 dB (Damosso 1999)",
    "shadow_sd_db": "indoor shadowing 3-8 dB (Rappaport 2002, table 4.6)",
    "shadow_corr_m": "exponential correlation (Gudmundson 1991), indoor decorrelation of a few metres",
    "drift_sd_db": "day-to-day change of an AP's mean RSSI 3-5 dB (Kaemarungsi & Krishnamurthy 2004; "
                   "Chapre et al. 2013), lower end",
    "local_sd_db": "slow local change (people, doors) within a survey visit (Kaemarungsi & Krishnamurthy 2004)",
    "scans_per_session": "assumption (the thesis: 300 scans 'at different times', L295)",
    "fade_sd_db": "static-phone RSSI spread 2-6 dB (Kaemarungsi & Krishnamurthy 2004)",
    "fade_sd_edge_db": "thesis Fig 2 (windows, corners drift more); value within the same range",
    "edge_m": "assumption (thesis Fig 2 is missing)",
    "body_loss_db": "user's body, AP behind: about 5 dB (Bahl & Padmanabhan 2000, RADAR)",
    "device_offset_db": "thesis names one Android phone (L515): same phone, 0 dB; swept in study_wifi",
    "detect_dbm": "smartphone scan sensitivity -90 to -100 dBm; calibrated to 4-18 APs per scan (L295)",
    "miss_p": "scans are not exhaustive (assumption)",
}

#: The radio worlds: "measured" (default: values from data/measured_parameters.csv where a row exists,
#: inverse-calibrated where the copied value does not come back, data/calibrated_parameters.csv),
#: "copied" (the measured values copied into the parameters, uncalibrated: the world of issue 24) and
#: "assumed" (:data:`PARAMS`, the published-value world kept for comparison).
WORLDS = ("measured", "copied", "assumed")

#: Measured world: parameter -> row of data/measured_parameters.csv (UJIIndoorLoc). The per-AP log-distance
#: fit behind path_loss_exponent and shadow_sd_db has no walls, so the measured world sets the wall losses
#: to 0 dB (their effect is inside the measured exponent and shadowing).
MEASURED_ROWS = {
    "p0_dbm": "path_loss_p0_dbm",
    "path_loss_exponent": "path_loss_exponent",
    "shadow_sd_db": "shadow_sd_db",
    "drift_sd_db": "drift_sd_db",
    "fade_sd_db": "fade_sd_db",
    "detect_dbm": "detect_m50_dbm",
    "miss_p": "detect_p_max",
}
#: Measured world: values fixed by the fit's form rather than read from a row, and the AP counts
#: recalibrated to the thesis's 4-18 APs per scan (L295) for the measured propagation: the largest
#: counts, stepping down from the assumed 16 + 12, whose 5th-95th percentile of APs per scan lies in
#: 4-18 (seed 0; 16 + 12 gives 14-21 with the measured P0 and exponent).
MEASURED_FIXED = {"light_wall_db": 0.0, "heavy_wall_db": 0.0, "n_aps_floor": 13, "n_aps_other": 10}


#: Calibrated world: parameters whose copied value does not come back when measured on the simulated
#: floor, replaced by their inverse calibration (data/calibrated_parameters.csv, :mod:`ilocalg.measure.calibrate`).
CALIBRATED = ("shadow_sd_db", "fade_sd_db", "detect_dbm", "n_aps_floor", "n_aps_other")


def world_params(world: str = "measured") -> dict:
    """The radio parameters of a world (a new dict; see :data:`MEASURED_ROWS` and :data:`CALIBRATED`)."""
    if world not in WORLDS:
        raise ValueError(f"unknown world {world!r}; known: {list(WORLDS)}")
    p = dict(PARAMS)
    if world in ("measured", "copied"):
        from ilocalg.sim.measured import param

        for k, row in MEASURED_ROWS.items():
            p[k] = 1.0 - param(row) if k == "miss_p" else param(row)
        # thesis Fig 2: window/corner points fade more; the assumed 2 dB excess over the corridor value is kept
        p.update(MEASURED_FIXED)
    if world == "measured":
        from ilocalg.sim.measured import calibrated

        for k in CALIBRATED:
            v = calibrated(f"iloc_floor.{k}")
            p[k] = int(round(v)) if k.startswith("n_aps") else v
    if world in ("measured", "copied"):
        p["fade_sd_edge_db"] = p["fade_sd_db"] + (PARAMS["fade_sd_edge_db"] - PARAMS["fade_sd_db"])
    return p


def world_sources(world: str = "measured") -> dict:
    """Where each parameter of a world comes from (one line each; measured rows cite the table)."""
    src = dict(PARAM_SOURCES)
    if world in ("measured", "copied"):
        from ilocalg.sim.measured import cite

        for k, row in MEASURED_ROWS.items():
            src[k] = cite(row) + (" (miss_p = 1 - p_max)" if k == "miss_p" else "")
        src["fade_sd_edge_db"] = ("fade_sd_db + 2 dB (the assumed world's excess at windows and corners, thesis "
                                  "Fig 2)")
        for k in ("light_wall_db", "heavy_wall_db"):
            src[k] = "0 dB: the measured log-distance fit (no walls) carries the wall losses in its exponent and sigma"
        for k in ("n_aps_floor", "n_aps_other"):
            src[k] = ("recalibrated for the measured propagation to the thesis's 4-18 APs per scan (L295): 13 + 10, "
                      "the largest counts below 16 + 12 whose 5th-95th percentile lies in 4-18")
    if world == "measured":
        from ilocalg.sim.measured import calibrated_cite

        for k in CALIBRATED:
            src[k] = calibrated_cite(f"iloc_floor.{k}")
        src["fade_sd_edge_db"] = "fade_sd_db (calibrated) + 2 dB (the assumed world's excess at windows and corners)"
    return src


_N_RFF = 256  # random Fourier features per AP for the shadowing field


@dataclass(frozen=True)
class IlocFloor:
    """A simulated i-Loc floor survey and test session.

    Attributes
    ----------
    train : FingerprintSet
        ``n_train_points * scans_per_point`` survey scans; ``meta`` has ``point``, ``session``
        and ``facing_rad`` (the surveyor's facing direction, from the x axis).
    test : FingerprintSet
        ``scans_per_test_point`` scans standing at each test-route point in the test session,
        facing the walking direction; ``meta`` as for ``train``.
    points_xy_m : ndarray (N_TRAIN_POINTS, 2)
    test_points : ndarray (N_TEST_POINTS,) indices into ``points_xy_m``, in walking order
    ap_xy_m : ndarray (n_aps, 2); ap_floor : ndarray (n_aps,) (0 = this floor, +/-1)
    mean_rssi_dbm : ndarray (N_TRAIN_POINTS, n_aps), the time-invariant mean (walls + shadowing)
    fade_sd_db : ndarray (N_TRAIN_POINTS,), the per-point fast-fading sd (drift level, Fig 2)
    detect_dbm : float, the detection threshold (the natural ``not_heard_dbm``)
    params : dict
    test_drift_db : ndarray (n_aps,), the test session's floor-wide per-AP drift
    """

    train: FingerprintSet
    test: FingerprintSet
    points_xy_m: np.ndarray
    test_points: np.ndarray
    ap_xy_m: np.ndarray
    ap_floor: np.ndarray
    mean_rssi_dbm: np.ndarray
    fade_sd_db: np.ndarray
    detect_dbm: float
    params: dict
    test_drift_db: np.ndarray = field(repr=False, default=None)
    shadow_field: dict = field(repr=False, default=None)


def _ring_points() -> np.ndarray:
    (x0, x1), (y0, y1) = RING_X_M, RING_Y_M
    s = SPACING_M
    south = np.column_stack([np.arange(x0, x1, s), np.full(int((x1 - x0) / s), y0)])
    east = np.column_stack([np.full(int((y1 - y0) / s), x1), np.arange(y0, y1, s)])
    north = np.column_stack([np.arange(x1, x0, -s), np.full(int((x1 - x0) / s), y1)])
    west = np.column_stack([np.full(int((y1 - y0) / s), x0), np.arange(y1, y0, -s)])
    return np.vstack([south, east, north, west])


def training_points() -> np.ndarray:
    """The 63 training points (x_m, y_m), 2 m apart (thesis L295) on the assumed layout: 56 on the
    ring corridor counter-clockwise from its south-west corner, then 7 on the corridor south to the
    stairs."""
    ring = _ring_points()
    n_spur = N_TRAIN_POINTS - len(ring)
    spur = np.column_stack([np.full(n_spur, SPUR_X_M), RING_Y_M[0] - SPACING_M * np.arange(1, n_spur + 1)])
    return np.vstack([ring, spur])


def test_route_index() -> np.ndarray:
    """Indices of the 28 test-route points in walking order: every second ring point,
    counter-clockwise from the south-west corner (4 m apart; thesis L515: 4.11 m)."""
    return np.arange(0, 2 * N_TEST_POINTS, 2)


def route_xy_m() -> np.ndarray:
    """The test route's 28 points (x_m, y_m) in walking order, shape (28, 2); consecutive points are
    ``ROUTE_SPACING_M`` apart along the corridor, corners included (a polyline for the gait simulator)."""
    return training_points()[test_route_index()]


def _route_heading_rad(idx: np.ndarray) -> np.ndarray:
    """Walking direction at test-route points (towards the next route point; the last keeps the last leg)."""
    r = route_xy_m()
    d = np.diff(r, axis=0)
    th = np.arctan2(d[:, 1], d[:, 0])
    th = np.concatenate([th, th[-1:]])
    pos = {int(j): k for k, j in enumerate(test_route_index())}
    return np.array([th[pos[int(i)]] for i in idx])


def walls() -> np.ndarray:
    """Wall segments (n, 4) = (x0, y0, x1, y1) in metres: outer walls, the ring corridor's walls, the
    stair corridor's walls, office partitions every ``BAY_M`` metres. :func:`wall_materials` gives the
    material of each."""
    return _walls()[0]


def wall_materials() -> np.ndarray:
    """The material (``"heavy"`` or ``"light"``) of each segment of :func:`walls` (COST 231 classes):
    outer and corridor walls heavy (load-bearing), office partitions light: an assumption."""
    return _walls()[1]


def _walls():
    W, H = FLOOR_W_M, FLOOR_H_M
    (x0, x1), (y0, y1) = RING_X_M, RING_Y_M
    hw = CORRIDOR_HALF_WIDTH_M
    heavy = [(0, 0, W, 0), (W, 0, W, H), (W, H, 0, H), (0, H, 0, 0)]
    # ring corridor: inner rectangle, outer rectangle with a gap for the stair corridor
    xi0, xi1, yi0, yi1 = x0 + hw, x1 - hw, y0 + hw, y1 - hw
    xo0, xo1, yo0, yo1 = x0 - hw, x1 + hw, y0 - hw, y1 + hw
    heavy += [(xi0, yi0, xi1, yi0), (xi1, yi0, xi1, yi1), (xi1, yi1, xi0, yi1), (xi0, yi1, xi0, yi0)]
    heavy += [(xo0, yo0, SPUR_X_M - hw, yo0), (SPUR_X_M + hw, yo0, xo1, yo0), (xo1, yo0, xo1, yo1),
              (xo1, yo1, xo0, yo1), (xo0, yo1, xo0, yo0)]
    heavy += [(SPUR_X_M - hw, 0, SPUR_X_M - hw, yo0), (SPUR_X_M + hw, 0, SPUR_X_M + hw, yo0)]
    light = []
    # partitions inside the ring
    for x in np.arange(xi0 + BAY_M, xi1 - 1.0, BAY_M):
        light.append((x, yi0, x, yi1))
    # partitions outside the ring: north and south bands (vertical), east and west bands (horizontal)
    for x in np.arange(BAY_M, W - 1.0, BAY_M):
        if abs(x - SPUR_X_M) > hw + 1.0:
            light.append((x, 0, x, yo0))
        light.append((x, yo1, x, H))
    for y in np.arange(yo0 + BAY_M, yo1 - 1.0, BAY_M):
        light += [(0, y, xo0, y), (xo1, y, W, y)]
    seg = np.asarray(heavy + light, dtype=np.float64)
    mat = np.array(["heavy"] * len(heavy) + ["light"] * len(light))
    return seg, mat


def _count_crossings(p: np.ndarray, q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Number of wall segments crossed by the segments p[i] -> q[j]; returns (len(p), len(q))."""
    if len(w) == 0:
        return np.zeros((len(p), len(q)), dtype=np.int64)
    P = p[:, None, None, :]
    Q = q[None, :, None, :]
    A = w[None, None, :, :2]
    B = w[None, None, :, 2:]

    def orient(a, b, c):
        return np.sign((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
                       - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))

    d1 = orient(A, B, P)
    d2 = orient(A, B, Q)
    d3 = orient(P, Q, A)
    d4 = orient(P, Q, B)
    return np.sum((d1 * d2 < 0) & (d3 * d4 < 0), axis=2)


def _edge_mask(xy: np.ndarray, edge_m: float) -> np.ndarray:
    """Within ``edge_m`` of an outer wall (windows) or of a corridor corner / junction (thesis Fig 2)."""
    near_outer = ((xy[:, 0] < edge_m) | (xy[:, 0] > FLOOR_W_M - edge_m)
                  | (xy[:, 1] < edge_m) | (xy[:, 1] > FLOOR_H_M - edge_m))
    (x0, x1), (y0, y1) = RING_X_M, RING_Y_M
    corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1], [SPUR_X_M, y0]])
    near_corner = np.hypot(xy[:, None, 0] - corners[None, :, 0], xy[:, None, 1] - corners[None, :, 1]).min(1) < edge_m
    return near_outer | near_corner


def _shadow(xy: np.ndarray, fld: dict) -> np.ndarray:
    """Shadowing (n, n_aps) at positions ``xy`` from the random-Fourier-feature field."""
    om, b, sd = fld["omega"], fld["phase"], fld["sd_db"]  # (n_aps, M, 2), (n_aps, M)
    arg = np.einsum("nd,amd->nam", xy, om) + b[None, :, :]
    return sd * np.sqrt(2.0 / om.shape[1]) * np.cos(arg).sum(axis=2)


def mean_rssi_dbm(xy_m, ap_xy_m, ap_floor, params: dict, shadow_field: dict | None = None) -> np.ndarray:
    """Time-invariant mean RSSI (n, n_aps), dBm, at positions ``xy_m``: COST 231 multi-wall model.

    ``P0 - 10 n log10(max(d3, 1 m)) - L_light k_light - L_heavy k_heavy - L_floor |floor| + shadow``
    with ``d3`` the 3-D distance (``STOREY_M`` per floor) and ``k`` the walls of each material the
    straight path crosses (walls of this floor; other floors' APs see this floor's walls too).

    References
    ----------
    COST 231 final report (Damosso 1999), sec. 4.7; Lott & Forkel 2001.
    """
    xy = np.atleast_2d(np.asarray(xy_m, dtype=np.float64))
    ap = np.asarray(ap_xy_m, dtype=np.float64)
    fl = np.abs(np.asarray(ap_floor))
    d = np.hypot(xy[:, None, 0] - ap[None, :, 0], xy[:, None, 1] - ap[None, :, 1])
    d3 = np.sqrt(d**2 + (STOREY_M * fl)[None, :] ** 2)
    seg, mat = _walls()
    k_l = _count_crossings(xy, ap, seg[mat == "light"])
    k_h = _count_crossings(xy, ap, seg[mat == "heavy"])
    p = params
    m = (p["p0_dbm"] - 10.0 * p["path_loss_exponent"] * np.log10(np.maximum(d3, 1.0))
         - p["light_wall_db"] * k_l - p["heavy_wall_db"] * k_h - p["floor_db"] * fl[None, :])
    if shadow_field is not None:
        m = m + _shadow(xy, shadow_field)
    return m


def _body_db(xy: np.ndarray, facing_rad: np.ndarray, ap: np.ndarray, loss_db: float) -> np.ndarray:
    """Body shadowing (n, n_aps), dB (<= 0): ``-loss (1 - cos a) / 2``, ``a`` facing vs direction to the AP."""
    to_ap = np.arctan2(ap[None, :, 1] - xy[:, None, 1], ap[None, :, 0] - xy[:, None, 0])
    return -loss_db * 0.5 * (1.0 - np.cos(to_ap - facing_rad[:, None]))


def _detect(rssi: np.ndarray, p: dict, rng) -> np.ndarray:
    return _detect_with(rssi, p, _miss(rssi.shape, p, rng))


def _miss(shape: tuple, p: dict, rng) -> np.ndarray:
    """Which readings a scan misses although detectable (probability ``miss_p``): one uniform draw per reading."""
    return rng.random(shape) < p["miss_p"]


def _detect_with(rssi: np.ndarray, p: dict, miss: np.ndarray) -> np.ndarray:
    """Readings as reported: integer dBm, NaN below ``detect_dbm`` or missed."""
    out = np.round(rssi)  # phones report integer dBm
    out[(out < p["detect_dbm"]) | miss] = np.nan
    return out


def _check_params(overrides: dict, world: str = "measured") -> dict:
    unknown = set(overrides) - set(PARAMS)
    if unknown:
        raise ValueError(f"unknown simulator parameters {sorted(unknown)}; known: {sorted(PARAMS)}")
    p = {**world_params(world), **overrides}
    for k in ("shadow_sd_db", "drift_sd_db", "local_sd_db", "fade_sd_db", "fade_sd_edge_db", "body_loss_db"):
        if not p[k] >= 0:
            raise ValueError(f"{k} must be >= 0 dB, got {p[k]}")
    if not 0 <= p["miss_p"] < 1:
        raise ValueError(f"miss_p must lie in [0, 1), got {p['miss_p']}")
    if int(p["scans_per_session"]) < 1:
        raise ValueError(f"scans_per_session must be >= 1, got {p['scans_per_session']}")
    return p


def simulate(seed=0, scans_per_point: int = SCANS_PER_POINT, scans_per_test_point: int = 10,
             world: str = "measured", **overrides) -> IlocFloor:
    """Simulate the i-Loc floor survey and a later test session.

    Parameters
    ----------
    seed : int, Generator or None
        Everything is drawn from this (same seed -> identical arrays).
    scans_per_point : int
        Survey scans per training point (300 in the thesis, L295; fewer for fast runs), in sessions
        of ``scans_per_session``, each facing one of the four corridor directions.
    scans_per_test_point : int
        Scans standing at each test-route point in the test session (one session, another day),
        facing the walking direction.
    world : {"measured", "assumed"}
        Where the defaults come from (:func:`world_params`): data/measured_parameters.csv, or the
        published-value world :data:`PARAMS`.
    **overrides
        Any key of :data:`PARAMS`.

    Returns
    -------
    IlocFloor
    """
    p = _check_params(overrides, world)
    return _simulate(seed, scans_per_point, scans_per_test_point, p, (p["device_offset_db"],))[0]


def simulate_device_offsets(device_offsets_db, seed=0, scans_per_point: int = SCANS_PER_POINT,
                            scans_per_test_point: int = 10, world: str = "measured", **overrides) -> tuple:
    """:func:`simulate` for several test phones: the survey and the test session are drawn once.

    The device offset is added to the test session's RSSI only (the survey phone reads 0 dB), after every
    draw, so the floors returned are exactly those of :func:`simulate` with ``device_offset_db`` set to each
    value (same seed, same random numbers, identical arrays); they share one ``train`` set (read it, do not
    modify it), and a Generator passed as ``seed`` ends in the state one :func:`simulate` call leaves.

    Parameters
    ----------
    device_offsets_db : sequence of float
        The test phone's offsets above the survey phone, dB.
    seed, scans_per_point, scans_per_test_point, world, **overrides
        As :func:`simulate` (``overrides`` without ``device_offset_db``).

    Returns
    -------
    tuple of IlocFloor, one per offset, in the order given
    """
    if "device_offset_db" in overrides:
        raise ValueError("give the device offsets as device_offsets_db, not as the device_offset_db override")
    offsets = tuple(device_offsets_db)
    if not offsets or not all(np.isfinite(float(o)) for o in offsets):
        raise ValueError(f"device_offsets_db must be one or more finite offsets in dB, got {device_offsets_db!r}")
    return _simulate(seed, scans_per_point, scans_per_test_point, _check_params(overrides, world), offsets)


def _simulate(seed, scans_per_point: int, scans_per_test_point: int, p: dict, offsets: tuple) -> tuple:
    """The floors of :func:`simulate` for each device offset in ``offsets`` (``p`` checked; its offset unused)."""
    if scans_per_point < 1 or scans_per_test_point < 1:
        raise ValueError("scans_per_point and scans_per_test_point must be >= 1")
    rng = as_rng(seed)
    pts = training_points()
    n_f, n_o = int(p["n_aps_floor"]), int(p["n_aps_other"])
    n_ap = n_f + n_o
    # APs in offices: uniform over the floor, at least 2.5 m from a corridor's centre line
    ap = np.empty((0, 2))
    while len(ap) < n_ap:
        c = rng.uniform([2.0, 2.0], [FLOOR_W_M - 2.0, FLOOR_H_M - 2.0], size=(4 * n_ap, 2))
        ap = np.vstack([ap, c[_corridor_distance_m(c) >= 2.5]])
    ap = ap[:n_ap]
    ap_floor = np.concatenate([np.zeros(n_f, dtype=np.int64), rng.choice([-1, 1], size=n_o)])
    # shadowing field: exponential covariance sd^2 exp(-r / l) <-> 2-D Cauchy (t, 1 dof) spectrum
    z = rng.normal(size=(n_ap, _N_RFF, 2))
    u = rng.chisquare(1.0, size=(n_ap, _N_RFF, 1))
    shadow = {"omega": z / (p["shadow_corr_m"] * np.sqrt(u)), "phase": rng.uniform(0, 2 * np.pi, (n_ap, _N_RFF)),
              "sd_db": float(p["shadow_sd_db"])}
    mean = mean_rssi_dbm(pts, ap, ap_floor, p, shadow)
    fade_sd = np.where(_edge_mask(pts, p["edge_m"]), p["fade_sd_edge_db"], p["fade_sd_db"])

    # --- survey: sessions of scans_per_session scans, floor-wide drift per session and AP
    sl = int(p["scans_per_session"])
    n_sess = int(np.ceil(scans_per_point / sl))
    n_pts = len(pts)
    drift = rng.normal(0.0, p["drift_sd_db"], (n_sess, n_ap))
    local = rng.normal(0.0, p["local_sd_db"], (n_pts, n_sess, n_ap))
    facing = rng.integers(0, 4, (n_pts, n_sess)) * (np.pi / 2)
    sess = np.arange(scans_per_point) // sl
    body = np.stack([_body_db(pts, facing[:, s], ap, p["body_loss_db"]) for s in range(n_sess)], axis=1)
    fade = rng.normal(0.0, 1.0, (n_pts, scans_per_point, n_ap)) * fade_sd[:, None, None]
    rssi = mean[:, None, :] + drift[None, sess, :] + local[:, sess, :] + body[:, sess, :] + fade
    tr_rssi = _detect(rssi, p, rng).reshape(n_pts * scans_per_point, n_ap)
    tr_point = np.repeat(np.arange(n_pts), scans_per_point)
    tr_sess = np.tile(sess, n_pts)
    tr_facing = facing[:, sess].reshape(-1)

    # --- test session: another day, facing the walking direction, test phone (its offset added last but the
    # fast fade, as one expression did: (mean + drift + local + body) + offset + fade, for each offset)
    test_idx = test_route_index()
    te_drift = rng.normal(0.0, p["drift_sd_db"], n_ap)
    te_local = rng.normal(0.0, p["local_sd_db"], (len(test_idx), n_ap))
    te_face = _route_heading_rad(test_idx)
    te_body = _body_db(pts[test_idx], te_face, ap, p["body_loss_db"])
    n_t = scans_per_test_point
    te_fade = rng.normal(0.0, 1.0, (len(test_idx), n_t, n_ap)) * fade_sd[test_idx, None, None]
    te_part = mean[test_idx, None, :] + te_drift[None, None, :] + te_local[:, None, :] + te_body[:, None, :]
    te_miss = _miss(te_fade.shape, p, rng)  # (points, scans, APs): te_part broadcasts over the scans
    te_point = np.repeat(test_idx, n_t)
    ap_ids = tuple(f"AP{i:02d}" for i in range(n_ap))
    src = f"ilocalg.sim.iloc_floor.simulate(seed={seed if not isinstance(seed, np.random.Generator) else 'rng'})"
    train = FingerprintSet(tr_rssi, ap_ids, pts[tr_point, 0].copy(), pts[tr_point, 1].copy(),
                           meta=pd.DataFrame({"point": tr_point, "session": tr_sess, "facing_rad": tr_facing}),
                           source=src)
    out = []
    for off in offsets:
        te_rssi = _detect_with(te_part + off + te_fade, p, te_miss).reshape(len(test_idx) * n_t, n_ap)
        test = FingerprintSet(te_rssi, ap_ids, pts[te_point, 0].copy(), pts[te_point, 1].copy(),
                              meta=pd.DataFrame({"point": te_point, "session": n_sess,
                                                 "facing_rad": np.repeat(te_face, n_t)}), source=src)
        out.append(IlocFloor(train=train, test=test, points_xy_m=pts, test_points=test_idx, ap_xy_m=ap,
                             ap_floor=ap_floor, mean_rssi_dbm=mean, fade_sd_db=fade_sd,
                             detect_dbm=float(p["detect_dbm"]), params={**p, "device_offset_db": off},
                             test_drift_db=te_drift, shadow_field=shadow))
    return tuple(out)


def _corridor_distance_m(xy: np.ndarray) -> np.ndarray:
    """Distance from each position to the nearest corridor centre line (ring and stair corridor)."""
    (x0, x1), (y0, y1) = RING_X_M, RING_Y_M
    segs = np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0],
                     [SPUR_X_M, y0, SPUR_X_M, 0.0]])
    a, b = segs[None, :, :2], segs[None, :, 2:]
    ab = b - a
    t = np.clip(np.einsum("nkd,nkd->nk", xy[:, None, :] - a, ab) / np.einsum("nkd,nkd->nk", ab, ab), 0, 1)
    proj = a + t[..., None] * ab
    return np.hypot(*(xy[:, None, :] - proj).transpose(2, 0, 1)).min(axis=1)


def walking_scans(sim: IlocFloor, track_t_s, track_xy_m, scan_start_t_s, scan_latency_s: float = 2.0,
                  rng=None, session_drift_db=None, read_age_s=None, return_read_times: bool = False):
    """Wi-Fi scans taken while walking (one scan per fix), in the test session of ``sim``.

    Each AP of a scan is read at a uniform time within ``[start, start + scan_latency_s]`` (the
    channel sweep), at the walker's position then, facing the walking direction; floor-wide drift,
    a local change per scan, the fast fade of the nearest training point, body shadowing and the
    device offset are added as in :func:`simulate`'s test session.

    Parameters
    ----------
    sim : IlocFloor
    track_t_s : array_like (n,)
        Increasing times of the walker's true track, s.
    track_xy_m : array_like (n, 2)
        True positions, m.
    scan_start_t_s : array_like (n_scans,)
        Scan start times, within the track.
    scan_latency_s : float
        Scan duration, s (phones: 1-3 s; an assumption, swept in fusion_iloc_kf).
    rng : Generator, int or None
    session_drift_db : array_like (n_aps,), optional
        The session's per-AP drift; default ``sim.test_drift_db`` (the test session).
    read_age_s : array_like (n_scans, n_aps), optional
        The age of each AP's reading when the scan's result is ready (``t_ready_s``): the AP is read
        at ``t_ready_s - age`` (within the track). Default: uniform read times within the scan.
    return_read_times : bool
        Also return the (n_scans, n_aps) time at which each AP was read, s.

    Returns
    -------
    DataFrame
        One row per scan: ``t_start_s``, ``t_ready_s`` (= start + latency: the scan's end, when its
        result is available), ``x_m``, ``y_m`` (true position at the scan's start, the tag),
        ``t_ref_s`` (the mean read time of the APs heard: the time the scan describes) and one column
        per AP id (dBm, NaN = not heard).
    """
    r = as_rng(rng)
    t = np.asarray(track_t_s, dtype=np.float64)
    xy = np.asarray(track_xy_m, dtype=np.float64)
    ts = np.asarray(scan_start_t_s, dtype=np.float64).reshape(-1)
    if t.ndim != 1 or xy.shape != (t.size, 2) or t.size < 2 or np.any(np.diff(t) <= 0):
        raise ValueError("track_t_s must be increasing (n >= 2) and track_xy_m of shape (n, 2)")
    if not scan_latency_s >= 0:
        raise ValueError(f"scan_latency_s must be >= 0, got {scan_latency_s}")
    if ts.size and (ts.min() < t[0] or ts.max() > t[-1]):
        raise ValueError(f"scan_start_t_s must lie within the track [{t[0]:.3f}, {t[-1]:.3f}] s")
    p = sim.params
    ap = sim.ap_xy_m
    n_ap = ap.shape[0]
    drift = sim.test_drift_db if session_drift_db is None else np.asarray(session_drift_db, dtype=np.float64)
    if drift.shape != (n_ap,):
        raise ValueError(f"session_drift_db must have shape ({n_ap},), got {drift.shape}")
    n = ts.size
    if read_age_s is None:
        t_read = np.minimum(ts[:, None] + r.uniform(0.0, scan_latency_s, (n, n_ap)), t[-1])
    else:
        age = np.asarray(read_age_s, dtype=np.float64)
        if age.shape != (n, n_ap) or not (np.isfinite(age).all() and (age >= 0).all()):
            raise ValueError(f"read_age_s must be finite, >= 0 and of shape ({n}, {n_ap}), got {age.shape}")
        t_read = np.clip(ts[:, None] + scan_latency_s - age, t[0], t[-1])
    x_read = np.interp(t_read, t, xy[:, 0])
    y_read = np.interp(t_read, t, xy[:, 1])
    # walking direction from the track (finite difference over 0.5 s)
    t_hi, t_lo = np.minimum(t_read + 0.25, t[-1]), np.maximum(t_read - 0.25, t[0])
    dx = np.interp(t_hi, t, xy[:, 0]) - np.interp(t_lo, t, xy[:, 0])
    dy = np.interp(t_hi, t, xy[:, 1]) - np.interp(t_lo, t, xy[:, 1])
    face = np.arctan2(dy, dx)
    rssi = np.empty((n, n_ap))
    pts = sim.points_xy_m
    for j in range(n_ap):
        pos = np.column_stack([x_read[:, j], y_read[:, j]])
        m = mean_rssi_dbm(pos, ap[j:j + 1], sim.ap_floor[j:j + 1], p, _one_ap(sim.shadow_field, j))[:, 0]
        body = _body_db(pos, face[:, j], ap[j:j + 1], p["body_loss_db"])[:, 0]
        near = np.argmin(np.hypot(pos[:, None, 0] - pts[None, :, 0], pos[:, None, 1] - pts[None, :, 1]), axis=1)
        rssi[:, j] = m + body + drift[j] + p["device_offset_db"] + sim.fade_sd_db[near] * r.normal(size=n)
    rssi += r.normal(0.0, p["local_sd_db"], (n, n_ap))
    rssi = _detect(rssi, p, r)
    heard = ~np.isnan(rssi)
    # the time the scan describes: the mean read time of the APs it heard (the start when it heard none)
    t_ref = np.where(heard.any(axis=1), np.nansum(np.where(heard, t_read, 0.0), axis=1)
                     / np.maximum(heard.sum(axis=1), 1), ts)
    out = pd.DataFrame(rssi, columns=list(sim.train.ap_ids))
    out.insert(0, "t_ref_s", t_ref)
    out.insert(0, "y_m", np.interp(ts, t, xy[:, 1]))
    out.insert(0, "x_m", np.interp(ts, t, xy[:, 0]))
    out.insert(0, "t_ready_s", ts + scan_latency_s)
    out.insert(0, "t_start_s", ts)
    return (out, t_read) if return_read_times else out


def back_to_back_scan_starts_s(t0_s: float, t1_s: float, scan_latency_s: float) -> np.ndarray:
    """Start times (s) of scans taken back to back from ``t0_s``, each ``scan_latency_s`` long and
    ending by ``t1_s``: a phone that starts a new scan as soon as the last one is done."""
    if not scan_latency_s > 0:
        raise ValueError(f"scan_latency_s must be > 0 s for back-to-back scans, got {scan_latency_s}")
    if not t1_s >= t0_s:
        raise ValueError(f"t1_s must be >= t0_s, got {t0_s}, {t1_s}")
    n = int(np.floor((t1_s - t0_s) / scan_latency_s + 1e-9))
    return t0_s + scan_latency_s * np.arange(n)


def periodic_scan_starts_s(t0_s: float, t1_s: float, scan_interval_s: float, scan_latency_s: float) -> np.ndarray:
    """Start times (s) of periodic scans from ``t0_s``: one every ``scan_interval_s``, each
    ``scan_latency_s`` long and ending by ``t1_s``. A phone scanning periodically while its user walks
    (i-Loc thesis, Chiu 2013, L777: the phone detects the Wi-Fi signals periodically)."""
    if not scan_interval_s > 0 or not scan_latency_s >= 0:
        raise ValueError(f"need scan_interval_s > 0 and scan_latency_s >= 0, got {scan_interval_s}, {scan_latency_s}")
    if scan_latency_s > scan_interval_s:
        raise ValueError(f"a scan ({scan_latency_s} s) cannot last longer than the scan interval ({scan_interval_s} s)")
    if not t1_s >= t0_s:
        raise ValueError(f"t1_s must be >= t0_s, got {t0_s}, {t1_s}")
    n = int(np.floor((t1_s - t0_s - scan_latency_s) / scan_interval_s + 1e-9)) + 1
    return t0_s + scan_interval_s * np.arange(max(n, 0))


def session_drift_db(sim: IlocFloor, rng=None) -> np.ndarray:
    """A new session's floor-wide per-AP drift ``N(0, drift_sd_db)``, shape (n_aps,), dB (another day)."""
    return as_rng(rng).normal(0.0, sim.params["drift_sd_db"], sim.ap_xy_m.shape[0])


def walking_fixes(sim: IlocFloor, estimator, track_t_s, track_xy_m, scan_start_t_s, scan_latency_s: float = 2.0,
                  rng=None, session_drift_db=None) -> pd.DataFrame:
    """Wi-Fi fixes from scans taken while walking: :func:`walking_scans`, then ``estimator.predict``.

    Parameters
    ----------
    sim : IlocFloor
    estimator : fitted estimator with ``predict(X) -> (n, 2)`` (columns in ``sim.train.ap_ids`` order)
    track_t_s, track_xy_m, scan_start_t_s, scan_latency_s, rng, session_drift_db
        As :func:`walking_scans`.

    Returns
    -------
    DataFrame
        One row per scan: ``t_start_s``, ``t_ready_s``, ``x_m``, ``y_m`` (true position at the scan's
        start, the fix's tag), ``t_ref_s``, ``fix_x_m``, ``fix_y_m``, ``n_heard``. A scan that hears no
        AP has a NaN fix.
    """
    scans = walking_scans(sim, track_t_s, track_xy_m, scan_start_t_s, scan_latency_s, rng, session_drift_db)
    X = scans[list(sim.train.ap_ids)].to_numpy()
    heard = ~np.isnan(X).all(axis=1)
    fix = np.full((X.shape[0], 2), np.nan)
    if heard.any():
        fix[heard] = estimator.predict(X[heard])
    out = scans[["t_start_s", "t_ready_s", "x_m", "y_m", "t_ref_s"]].copy()
    out["fix_x_m"], out["fix_y_m"] = fix[:, 0], fix[:, 1]
    out["n_heard"] = (~np.isnan(X)).sum(axis=1)
    return out


def _one_ap(fld: dict | None, j: int) -> dict | None:
    if fld is None:
        return None
    return {"omega": fld["omega"][j:j + 1], "phase": fld["phase"][j:j + 1], "sd_db": fld["sd_db"]}


def summary(sim: IlocFloor) -> pd.DataFrame:
    """The calibrated inputs as simulated: APs heard per scan and RSSI spread at a point."""
    x = sim.train.rssi_dbm
    heard = np.sum(~np.isnan(x), axis=1)
    heard_t = np.sum(~np.isnan(sim.test.rssi_dbm), axis=1)
    pt = sim.train.meta["point"].to_numpy()
    sd = []
    for j in np.unique(pt):
        xj = x[pt == j]
        ok = np.sum(~np.isnan(xj), axis=0) >= 10
        if ok.any():
            sd.append(np.nanstd(xj[:, ok], axis=0))
    sd = np.concatenate(sd) if sd else np.array([np.nan])
    return pd.DataFrame([
        {"quantity": "APs heard per scan, min", "value": float(heard.min())},
        {"quantity": "APs heard per scan, 5th percentile", "value": float(np.percentile(heard, 5))},
        {"quantity": "APs heard per scan, median", "value": float(np.median(heard))},
        {"quantity": "APs heard per scan, 95th percentile", "value": float(np.percentile(heard, 95))},
        {"quantity": "APs heard per scan, max", "value": float(heard.max())},
        {"quantity": "APs heard per test scan, median", "value": float(np.median(heard_t))},
        {"quantity": "RSSI sd at a point per AP, median [dB]", "value": float(np.median(sd))},
        {"quantity": "scans", "value": float(x.shape[0])},
        {"quantity": "training points", "value": float(len(sim.points_xy_m))},
        {"quantity": "test points", "value": float(len(sim.test_points))},
        {"quantity": "test-route spacing [m]", "value": ROUTE_SPACING_M},
    ])


@dataclass(frozen=True)
class FloorFixes:
    """Wi-Fi fixes at the test-route points of a simulated floor.

    Attributes
    ----------
    sim : IlocFloor
    route_xy_m : ndarray (28, 2)
        The test-route points in walking order.
    fix_xy_m : ndarray (28, n_scans, 2)
        The estimator's fix for every new scan at every point.
    cal_var_m2 : ndarray (28,)
        Per-point variance of the fix error over the calibration scans (per axis: mean squared
        error / 2, so ``R = var I`` has the measured total error power; the thesis' Table 5 analogue),
        at least the quantisation variance of the 2 m grid (``2^2 / 12`` m^2).
    n_cal : int
    method : str
    """

    sim: IlocFloor
    route_xy_m: np.ndarray
    fix_xy_m: np.ndarray
    cal_var_m2: np.ndarray
    n_cal: int
    method: str


def floor_fixes(rng, n_walkers: int, n_cal: int = 10, method: str = "Simplified-Horus", scans_per_point: int = 300,
                k_aps: int = 5) -> FloorFixes:
    """Simulate the floor, fit ``method`` (a key of :data:`ilocalg.wifi.registry.PAPER_ESTIMATORS`) and
    estimate every new scan at the test-route points (``n_cal + n_walkers`` per point)."""
    if n_cal < 2 or n_walkers < 1:
        raise ValueError(f"need n_cal >= 2 and n_walkers >= 1, got {n_cal}, {n_walkers}")
    spt = n_cal + n_walkers
    sim = simulate(rng, scans_per_point=scans_per_point, scans_per_test_point=spt)
    est = fit_estimator(sim, method, k_aps)
    n_pts = sim.test_points.size
    # test scans are stored point by point (spt consecutive rows per test point, in route order)
    fix = est.predict(sim.test.rssi_dbm).reshape(n_pts, spt, 2)
    route = sim.points_xy_m[sim.test_points]
    return FloorFixes(sim, route, fix, _fix_variance_m2(fix[:, :n_cal], route), n_cal, method)


def _fix_variance_m2(fix_xy_m: np.ndarray, true_xy_m: np.ndarray) -> np.ndarray:
    """Per point: half the mean squared fix error (per axis), at least the 2 m grid's quantisation variance.

    ``fix_xy_m`` (n_points, n_scans, 2), ``true_xy_m`` (n_points, 2). The floor (spacing^2 / 12 per axis)
    keeps a point whose calibration fixes all hit it exactly from getting R = 0.
    """
    err2 = ((fix_xy_m - true_xy_m[:, None]) ** 2).sum(-1)
    return np.maximum(0.5 * err2.mean(axis=1), SPACING_M**2 / 12.0)


def fit_estimator(sim: IlocFloor, method: str = "Simplified-Horus", k_aps: int = 5):
    """Fit ``method`` (a key of :data:`ilocalg.wifi.registry.PAPER_ESTIMATORS`) on the survey of ``sim``.

    Simplified-Horus and Simplified-RADAR are fitted on every survey scan (the thesis compares a query
    with every stored scan, L283, L287); the other estimators on the per-point mean fingerprints (APs
    heard in at least half of a point's scans).

    Returns
    -------
    The fitted estimator (``predict(X) -> (n, 2)``, columns in ``sim.train.ap_ids`` order).
    """
    ests = paper_estimators(sim.detect_dbm, k_aps)
    if method not in ests:
        raise ValueError(f"method must be one of {sorted(ests)}, got {method!r}")
    est = ests[method]
    if method in ("Simplified-Horus", "Simplified-RADAR"):  # every stored scan (Chiu 2013, L283, L287, Fig 4)
        return est.fit(sim.train.rssi_dbm, sim.train.xy_m)
    fp, pts, _ = mean_fingerprints(sim.train.rssi_dbm, sim.train.xy_m, min_heard_fraction=0.5)
    est.fit(fp, pts)
    return est


def standing_fix_variance_m2(sim: IlocFloor, estimator) -> np.ndarray:
    """Per test-route point: the fix-error variance per axis (m^2) of the standing scans of ``sim.test``.

    Half the mean squared error of ``estimator``'s fixes over the point's standing test-session scans
    (another day than the survey), at least the quantisation variance of the 2 m grid
    (``SPACING_M^2 / 12``); shape (N_TEST_POINTS,), in walking order. A calibration of a filter's
    measurement noise, as the i-Loc thesis made its Table 5 (Chiu 2013, L588).
    """
    X = sim.test.rssi_dbm
    heard = ~np.isnan(X).all(axis=1)  # a scan hearing no AP gives no fix and is left out of the mean
    fix = np.full((X.shape[0], 2), np.nan)
    fix[heard] = estimator.predict(X[heard])
    pt = sim.test.meta["point"].to_numpy()
    err2 = ((fix - sim.test.xy_m) ** 2).sum(axis=1)
    var = np.array([np.nanmean(err2[pt == j]) for j in sim.test_points]) * 0.5
    return np.maximum(var, SPACING_M**2 / 12.0)
