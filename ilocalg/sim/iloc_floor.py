"""The i-Loc floor: a simulated Wi-Fi radio map of NCTU Engineering Building 3, 2nd floor.

The thesis' measured radio map is not published, so the toolkit simulates one with the geometry
and survey protocol the thesis states, and a standard indoor propagation model whose parameters
come from the propagation literature (never from the positioning results to be reproduced).

Geometry and survey (i-Loc thesis, sec. 3.1, Fig 2)
    Thesis: floor 75.46 m x 50.26 m (3,292.62 m^2); thesis: 63 training points 2 m apart along the
    corridors; thesis: a test route of 28 points that are also training points; thesis: 300 scans
    per training point taken at different times; 4-18 APs heard per scan; points near windows and
    corners drift more (thesis Fig 2).
    The floor plan itself is not given in text; the model uses corridors 2.4 m wide with offices
    (8 m bays) on both sides: a 70 m corridor along the long axis (36 points), a branch crossing it
    at x = 39 m (12 points north, 11 south) and a short corridor at the branch's south end (4
    points). The thesis' test route is N_TEST_POINTS consecutive points: the long corridor from x = 15 m to the
    junction, south along the branch, west along the short corridor.
Access points
    ``n_aps_floor = 20`` APs in the offices (this floor) plus ``n_aps_other = 12`` APs on the
    floors above and below (one floor slab of extra loss), at seeded random positions.
Propagation: log-distance path loss with a wall-attenuation factor (multi-wall model)
    ``rssi = P0 - 10 n log10(max(d, 1 m)) - WAF * walls - FAF * floors + shadow + drift + fade``
    ``P0 = -40 dBm`` at 1 m, ``n = 3.0``, WAF 3 dB per crossed wall, FAF 13 dB per floor
    (Seidel & Rappaport 1992, multi-floor office buildings: n 2.8-3.3 on one floor, WAF ~3 dB,
    FAF ~13 dB for one floor); 2.4 GHz Wi-Fi AP EIRP ~ 15-20 dBm gives P0 ~ -40 dBm at 1 m.
Shadowing (spatially correlated, static in time)
    Gaussian, ``SHADOW_SD_DB = 5`` dB (indoor shadowing 3-8 dB, Rappaport, Wireless
    Communications, table 4.6), exponential correlation with distance ``SHADOW_CORR_M = 5`` m
    (Gudmundson 1991 model; indoor decorrelation distances of a few metres).
Temporal variation at a point (what the thesis calls drift, Fig 2)
    Per scan: a per-AP session offset (slowly varying conditions: people, doors) with sd
    ``DRIFT_SD_DB = 2`` dB, shared by the ``SCANS_PER_SESSION`` scans of one survey session, plus
    independent fast fading with sd ``FADE_SD_DB = 3`` dB at a corridor point and
    ``FADE_SD_EDGE_DB = 5`` dB at points within ``EDGE_M`` = 6 m of an outer wall (windows) or of a
    corridor corner/junction (Fig 2: those points drift most). Static-phone RSSI spreads of
    2-6 dB sd are typical (Kaemarungsi & Krishnamurthy 2004; Youssef & Agrawala 2005, Horus).
Detection
    A reading is reported when at or above ``detect_dbm = -95`` dBm (smartphone scan sensitivity
    ~ -90 to -100 dBm); a detectable AP is still missed in a scan with probability ``MISS_P = 0.1`` (scans are
    not exhaustive). These two and the AP counts are the inputs calibrated to the thesis' "4-18
    APs per scan"; :func:`summary` reports what a seed gives.

Everything is deterministic from ``seed`` (same seed -> identical arrays).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 3.1 (environment, Fig 2). Seidel S. Y., Rappaport T. S.,
"914 MHz path loss prediction models for indoor wireless communications in multifloored
buildings", IEEE Trans. Antennas Propag. 40(2), 1992. Gudmundson M., "Correlation model for
shadow fading in mobile radio systems", Electronics Letters 27(23), 1991.
"""

from __future__ import annotations

from dataclasses import dataclass

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
    "PARAMS",
    "IlocFloor",
    "training_points",
    "test_route_index",
    "walls",
    "simulate",
    "summary",
]

# Settings from the paper
# -----------------------
# Chiu (2013) sec. 3.1 (inputs): FLOOR_W_M and FLOOR_H_M (floor length and width),
# N_TRAIN_POINTS (63 training points 2 m apart), N_TEST_POINTS (a test route of 28 points) and
# SCANS_PER_POINT (300 scans per training point).
FLOOR_W_M = 75.46
FLOOR_H_M = 50.26
N_TRAIN_POINTS = 63
N_TEST_POINTS = 28
SCANS_PER_POINT = 300
SPACING_M = 2.0
CORRIDOR_Y_M = 25.0
BRANCH_X_M = 38.0
CORRIDOR_HALF_WIDTH_M = 1.2
BAY_M = 8.0

#: Radio-model parameters (see the module docstring for each source).
PARAMS = {
    "n_aps_floor": 20,
    "n_aps_other": 12,
    "p0_dbm": -40.0,
    "path_loss_exponent": 3.0,
    "waf_db": 3.0,
    "faf_db": 13.0,
    "shadow_sd_db": 5.0,
    "shadow_corr_m": 5.0,
    "drift_sd_db": 2.0,
    "scans_per_session": 30,
    "fade_sd_db": 3.0,
    "fade_sd_edge_db": 5.0,
    "edge_m": 6.0,
    "detect_dbm": -95.0,
    "miss_p": 0.1,
}


@dataclass(frozen=True)
class IlocFloor:
    """A simulated i-Loc floor survey.

    Attributes
    ----------
    train : FingerprintSet
        ``n_train_points * scans_per_point`` scans; ``meta`` has ``point`` and ``session``.
    test : FingerprintSet
        ``scans_per_test_point`` new scans at each test-route point (later sessions).
    points_xy_m : ndarray (N_TRAIN_POINTS, 2)
    test_points : ndarray (N_TEST_POINTS,) indices into ``points_xy_m``
    ap_xy_m : ndarray (n_aps, 2); ap_floor : ndarray (n_aps,) (0 = this floor, +/-1)
    mean_rssi_dbm : ndarray (N_TRAIN_POINTS, n_aps), the noise-free mean (path loss + shadowing)
    fade_sd_db : ndarray (N_TRAIN_POINTS,), the per-point fast-fading sd (drift level, Fig 2)
    detect_dbm : float, the detection threshold (the natural ``not_heard_dbm``)
    params : dict
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


def training_points() -> np.ndarray:
    """The thesis' 63 training points (x_m, y_m), 2 m apart: 36 on the long corridor (y = 25 m), 12 on the
    branch north of the junction, 11 south of it, and 4 along a short corridor at its south end."""
    xs = 3.0 + SPACING_M * np.arange(36)  # 3 .. 73 m
    long = np.column_stack([xs, np.full(xs.size, CORRIDOR_Y_M)])
    bx = BRANCH_X_M + 1.0
    north = np.column_stack([np.full(12, bx), CORRIDOR_Y_M + SPACING_M * np.arange(1, 13)])  # 27 .. 49
    south = np.column_stack([np.full(11, bx), CORRIDOR_Y_M - SPACING_M * np.arange(1, 12)])  # 23 .. 3
    stub = np.column_stack([bx - SPACING_M * np.arange(1, 5), np.full(4, south[-1, 1])])  # x 37 .. 31
    return np.vstack([long, north, south, stub])


def test_route_index() -> np.ndarray:
    """Indices of the thesis' 28 test-route points, a walk of consecutive points: the long corridor from
    x = 15 m east to the junction (13 points), south along the branch (11), west along the stub (4)."""
    pts = training_points()
    on_long = (pts[:, 1] == CORRIDOR_Y_M) & (pts[:, 0] >= 15.0) & (pts[:, 0] <= BRANCH_X_M + 1.0)
    south = np.flatnonzero((pts[:, 0] == BRANCH_X_M + 1.0) & (pts[:, 1] < CORRIDOR_Y_M))
    stub = np.arange(len(pts) - 4, len(pts))
    return np.concatenate([np.flatnonzero(on_long), south, stub])


def walls() -> np.ndarray:
    """Wall segments (n, 4) = (x0, y0, x1, y1) in metres: outer walls, corridor walls, office
    partitions every ``BAY_M`` metres."""
    W, H = FLOOR_W_M, FLOOR_H_M
    seg = [(0, 0, W, 0), (W, 0, W, H), (W, H, 0, H), (0, H, 0, 0)]
    cy, hw, bx = CORRIDOR_Y_M, CORRIDOR_HALF_WIDTH_M, BRANCH_X_M + 1.0
    seg += [(0, cy - hw, bx - hw, cy - hw), (bx + hw, cy - hw, W, cy - hw),
            (0, cy + hw, bx - hw, cy + hw), (bx + hw, cy + hw, W, cy + hw),
            (bx - hw, 0, bx - hw, cy - hw), (bx + hw, 0, bx + hw, cy - hw),
            (bx - hw, cy + hw, bx - hw, H), (bx + hw, cy + hw, bx + hw, H)]
    for x in np.arange(BAY_M, W, BAY_M):
        if abs(x - bx) > hw + 1.0:
            seg += [(x, 0, x, cy - hw), (x, cy + hw, x, H)]
    for y in np.arange(BAY_M, H, BAY_M):
        if abs(y - cy) > hw + 1.0:
            seg += [(0, y, bx - hw, y), (bx + hw, y, W, y)]
    return np.asarray(seg, dtype=np.float64)


def _count_crossings(p: np.ndarray, q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Number of wall segments crossed by the segments p[i] -> q[j]; returns (len(p), len(q))."""
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


def _edge_points(pts: np.ndarray, edge_m: float) -> np.ndarray:
    near_outer = ((pts[:, 0] < edge_m) | (pts[:, 0] > FLOOR_W_M - edge_m)
                  | (pts[:, 1] < edge_m) | (pts[:, 1] > FLOOR_H_M - edge_m))
    junction = np.hypot(pts[:, 0] - (BRANCH_X_M + 1.0), pts[:, 1] - CORRIDOR_Y_M) < edge_m
    return near_outer | junction


def _scans(mean, fade_sd, n_scans, session_len, p, rng, first_session=0):
    """``n_scans`` scans at each point: mean + session drift + fast fade, thresholded, with misses."""
    n_pts, n_aps = mean.shape
    n_sess = int(np.ceil(n_scans / session_len))
    drift = rng.normal(0.0, p["drift_sd_db"], (n_pts, n_sess, n_aps))
    sess = np.arange(n_scans) // session_len
    fade = rng.normal(0.0, 1.0, (n_pts, n_scans, n_aps)) * fade_sd[:, None, None]
    rssi = mean[:, None, :] + drift[:, sess, :] + fade
    miss = rng.random((n_pts, n_scans, n_aps)) < p["miss_p"]
    rssi = np.round(rssi)  # phones report integer dBm
    rssi[(rssi < p["detect_dbm"]) | miss] = np.nan
    point = np.repeat(np.arange(n_pts), n_scans)
    session = first_session + np.tile(sess, n_pts)
    return rssi.reshape(n_pts * n_scans, n_aps), point, session


def simulate(seed=0, scans_per_point: int = SCANS_PER_POINT, scans_per_test_point: int = 10,
             **overrides) -> IlocFloor:
    """Simulate the i-Loc floor survey.

    Parameters
    ----------
    seed : int, Generator or None
        Everything is drawn from this (same seed -> identical arrays).
    scans_per_point : int
        Training scans per point (300 in the thesis; fewer for fast runs).
    scans_per_test_point : int
        New scans at each test-route point, from sessions after the training survey.
    **overrides
        Any key of :data:`PARAMS`.

    Returns
    -------
    IlocFloor
    """
    unknown = set(overrides) - set(PARAMS)
    if unknown:
        raise ValueError(f"unknown simulator parameters {sorted(unknown)}; known: {sorted(PARAMS)}")
    p = {**PARAMS, **overrides}
    if scans_per_point < 1 or scans_per_test_point < 1:
        raise ValueError("scans_per_point and scans_per_test_point must be >= 1")
    rng = as_rng(seed)
    pts = training_points()
    n_f, n_o = int(p["n_aps_floor"]), int(p["n_aps_other"])
    # APs in offices: uniform over the floor, off the corridors
    ap = rng.uniform([2.0, 2.0], [FLOOR_W_M - 2.0, FLOOR_H_M - 2.0], size=(n_f + n_o, 2))
    in_corr = np.abs(ap[:, 1] - CORRIDOR_Y_M) < 3.0
    ap[in_corr, 1] += np.where(ap[in_corr, 1] >= CORRIDOR_Y_M, 3.0, -3.0)
    ap_floor = np.concatenate([np.zeros(n_f, dtype=np.int64), rng.choice([-1, 1], size=n_o)])
    d = np.hypot(pts[:, None, 0] - ap[None, :, 0], pts[:, None, 1] - ap[None, :, 1])
    d3 = np.sqrt(d**2 + (3.5 * np.abs(ap_floor))[None, :] ** 2)  # 3.5 m storey height
    n_walls = _count_crossings(pts, ap, walls())
    mean = (p["p0_dbm"] - 10.0 * p["path_loss_exponent"] * np.log10(np.maximum(d3, 1.0))
            - p["waf_db"] * n_walls - p["faf_db"] * np.abs(ap_floor)[None, :])
    # spatially correlated shadowing per AP: exponential covariance over the points
    dp = np.hypot(pts[:, None, 0] - pts[None, :, 0], pts[:, None, 1] - pts[None, :, 1])
    cov = p["shadow_sd_db"] ** 2 * np.exp(-dp / p["shadow_corr_m"])
    L = np.linalg.cholesky(cov + 1e-9 * np.eye(len(pts)))
    mean = mean + L @ rng.normal(size=(len(pts), n_f + n_o))
    fade_sd = np.where(_edge_points(pts, p["edge_m"]), p["fade_sd_edge_db"], p["fade_sd_db"])
    sl = int(p["scans_per_session"])
    tr_rssi, tr_point, tr_sess = _scans(mean, fade_sd, scans_per_point, sl, p, rng)
    test_idx = test_route_index()
    n_tr_sess = int(np.ceil(scans_per_point / sl))
    te_rssi, te_local, te_sess = _scans(mean[test_idx], fade_sd[test_idx], scans_per_test_point,
                                        max(1, scans_per_test_point), p, rng, first_session=n_tr_sess)
    te_point = test_idx[te_local]
    ap_ids = tuple(f"AP{i:02d}" for i in range(n_f + n_o))
    src = f"ilocalg.sim.iloc_floor.simulate(seed={seed if not isinstance(seed, np.random.Generator) else 'rng'})"
    train = FingerprintSet(tr_rssi, ap_ids, pts[tr_point, 0].copy(), pts[tr_point, 1].copy(),
                           meta=pd.DataFrame({"point": tr_point, "session": tr_sess}), source=src)
    test = FingerprintSet(te_rssi, ap_ids, pts[te_point, 0].copy(), pts[te_point, 1].copy(),
                          meta=pd.DataFrame({"point": te_point, "session": te_sess}), source=src)
    return IlocFloor(train=train, test=test, points_xy_m=pts, test_points=test_idx, ap_xy_m=ap,
                     ap_floor=ap_floor, mean_rssi_dbm=mean, fade_sd_db=fade_sd, detect_dbm=float(p["detect_dbm"]),
                     params=p)


def summary(sim: IlocFloor) -> pd.DataFrame:
    """The calibrated inputs as simulated: APs heard per scan and RSSI spread at a point."""
    x = sim.train.rssi_dbm
    heard = np.sum(~np.isnan(x), axis=1)
    pt = sim.train.meta["point"].to_numpy()
    sd = []
    for j in np.unique(pt):
        xj = x[pt == j]
        ok = np.sum(~np.isnan(xj), axis=0) >= 10
        if ok.any():
            sd.append(np.nanstd(xj[:, ok], axis=0))
    sd = np.concatenate(sd)
    return pd.DataFrame([
        {"quantity": "APs heard per scan, min", "value": float(heard.min())},
        {"quantity": "APs heard per scan, 5th percentile", "value": float(np.percentile(heard, 5))},
        {"quantity": "APs heard per scan, median", "value": float(np.median(heard))},
        {"quantity": "APs heard per scan, 95th percentile", "value": float(np.percentile(heard, 95))},
        {"quantity": "APs heard per scan, max", "value": float(heard.max())},
        {"quantity": "RSSI sd at a point per AP, median [dB]", "value": float(np.median(sd))},
        {"quantity": "scans", "value": float(x.shape[0])},
        {"quantity": "training points", "value": float(len(sim.points_xy_m))},
        {"quantity": "test points", "value": float(len(sim.test_points))},
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
    ests = paper_estimators(sim.detect_dbm, k_aps)
    if method not in ests:
        raise ValueError(f"method must be one of {sorted(ests)}, got {method!r}")
    est = ests[method]
    if method == "Simplified-Horus":
        est.fit(sim.train.rssi_dbm, sim.train.xy_m)
    else:
        fp, pts, _ = mean_fingerprints(sim.train.rssi_dbm, sim.train.xy_m, min_heard_fraction=0.5)
        est.fit(fp, pts)
    n_pts = sim.test_points.size
    # test scans are stored point by point (spt consecutive rows per test point, in route order)
    fix = est.predict(sim.test.rssi_dbm).reshape(n_pts, spt, 2)
    route = sim.points_xy_m[sim.test_points]
    err2 = ((fix[:, :n_cal] - route[:, None]) ** 2).sum(-1)
    # floor: the quantisation variance of a 2 m reference grid (spacing^2 / 12 per axis), so a point whose
    # calibration fixes all hit it exactly does not get R = 0
    var = np.maximum(0.5 * err2.mean(axis=1), SPACING_M**2 / 12.0)
    return FloorFixes(sim, route, fix, var, n_cal, method)
