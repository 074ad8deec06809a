"""Simulated photos of the i-Loc PoI wall (thesis Figs 25-28), deterministic from a seed.

What is simulated
-----------------
Seven points of interest ``p1..p7`` on one wall and seven shooting points ``t1..t7`` one metre
apart on a line perpendicular to the wall through ``p4`` (``t1`` nearest to ``p4``, ``t7`` farthest),
as the thesis describes them (sec. 6.3: "seven PoIs, seven test points, one metre apart";
"for p4, t1 and t7 are the nearest and farthest"; "p1, p3, p4, p5 and p6 lie almost on one
horizontal line"). At each shooting point the user takes ``n_photos`` photos: the phone is held at
eye height and aimed at the middle of the PoIs; the PoIs are projected with a pinhole camera
(eq. 29-30); the user drags each PoI marker onto its image with a drag-to-match error; the phone's
accelerometer and magnetometer report the orientation ``T_E->AR`` with a tilt and a heading error.

Layout (an assumption: the thesis gives the coordinates only in Fig 28, which the text copy lacks)
    World frame: x along the wall, y into the room, z up; metres. PoIs on the wall ``y = 0`` at
    x = -1.2, -0.8, ..., 1.2 (0.4 m apart; the whole row fits the camera's field of view from ``t1``);
    ``p1, p3, p4, p5, p6`` at heights 1.60, 1.62, 1.58, 1.61, 1.59 m (within 2 cm of one horizontal
    line), ``p2`` above the line at 2.10 m and ``p7`` below it at 1.10 m. Shooting points at
    ``x = 0``, ``y = 2.5, 3.5, ..., 8.5`` m.

Every input parameter and its source
------------------------------------
``f_px = 1045``, ``1280 x 720`` px screen (landscape)
    A 2013 Android phone camera preview shown full screen: horizontal field of view about 63 deg
    (3.7 mm lens on a 1/3.2" sensor, 4.54 mm wide, e.g. Samsung Galaxy S III) on a 1280 x 720 px
    screen: ``f = 640 / tan(31.5 deg) = 1045 px``. The thesis does not name its phone.
``eye_height_m = 1.45``, ``eye_height_sd_m = 0.05``
    Phone held at eye height to take a photo (a standing adult's eye height is about 1.5-1.6 m, the
    phone slightly lower); the sd is the hand's height from photo to photo.
``aim_sd_deg = 1.5``, ``roll_sd_deg = 2.0``
    How far the optical axis strays from the middle of the PoIs and how far the screen is rolled
    (a hand-held phone); these change the true orientation only, which the sensors then measure.
``drag_sd_px = 12.0`` per axis
    The user's drag-to-match error (thesis Fig 25: the user drags each red PoI marker onto the black
    PoI in the photo). Touch studies bound it: with the finger already on the screen users can place
    it to about 0.17 mm (Berard & Rochet-Capellan, ITS 2012), while touch points land about 1.6 mm
    (projected-centre model) to 4 mm (contact-centre model) off the intended target (Holz & Baudisch,
    CHI 2011). We take 1.0 mm per axis between those, i.e. 12 px on a 4.8" 1280 x 720 screen
    (306 ppi = 12.05 px/mm).
``tilt_sd_deg = 1.0``
    Pitch/roll from the accelerometer of a phone held still: a residual zero-g offset of about
    20 mg (factory-trimmed consumer MEMS accelerometers, e.g. Bosch BMA2xx datasheets: up to
    +-60 mg before trimming) tilts gravity by atan(0.02) = 1.1 deg.
``yaw_sd_deg = 5.0``
    Heading from the magnetometer: a field study of 11 smartphone models found magnetic-azimuth
    errors of 1-3 deg right after calibration, growing 2-3 times without recalibration
    (Lviv Polytechnic, "Use of smartphones for determining orientation angles in the field"); indoor
    steel and electronics disturb the field further (Michel et al., "On attitude estimation with
    smartphones", PerCom 2017). 5 deg is the middle of that range. The walking-direction error the
    thesis reports for its WDM (13.87 deg mean, sec. 4) includes walking motion, not a static phone.
``good_guess_sd_m = 2.25`` (VAGIG)
    The rough position the user gives first (thesis sec. 6.2) is the i-Loc PTS + Wi-Fi Kalman fix,
    whose mean error the thesis reports as 2.82 m (sec. 5.2, Fig 23); a 2-D Gaussian with that mean
    radial error has ``sd = mean / sqrt(pi / 2) = 2.25 m`` per axis (thesis mean 2.82 m). Guesses
    are redrawn until they lie in the room (the user knows which side of the wall they stand on).
Bad initial guess (VABIG)
    Uniform over the room's floor ``x in [-3, 3]``, ``y in [0.5, 10]`` m: no knowledge of the position.
    Both guesses are at the nominal eye height.

Nothing here was adjusted to make an outcome table match the thesis.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 5.2 and 6.2-6.3, eq. (29)-(30), Figs 25-28.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.photo.camera import look_at, project, rot_x, rot_y, small_rotation
from ilocalg.units import as_rng

__all__ = ["DEFAULTS", "POIS_M", "POI_IDS", "SHOTS_XY_M", "SHOT_IDS", "ROOM_M", "PhotoPoiSet", "simulate",
           "pois_frame", "shots_frame"]

#: PoI world positions (7, 3), metres (layout assumption, see the module docstring).
POIS_M = np.array([
    [-1.2, 0.0, 1.60],
    [-0.8, 0.0, 2.10],
    [-0.4, 0.0, 1.62],
    [0.0, 0.0, 1.58],
    [0.4, 0.0, 1.61],
    [0.8, 0.0, 1.59],
    [1.2, 0.0, 1.10],
])
POI_IDS = tuple(f"p{i}" for i in range(1, 8))
#: Shooting points t1..t7 (x, y), metres: one metre apart, t1 nearest to p4.
SHOTS_XY_M = np.array([[0.0, 2.5 + k] for k in range(7)])
SHOT_IDS = tuple(f"t{i}" for i in range(1, 8))
#: Room floor (x_min, x_max, y_min, y_max), metres.
ROOM_M = (-3.0, 3.0, 0.5, 10.0)

#: Default simulation inputs; sources in the module docstring.
DEFAULTS = {
    "f_px": 1045.0,
    "width_px": 1280,
    "height_px": 720,
    "eye_height_m": 1.45,
    "eye_height_sd_m": 0.05,
    "aim_sd_deg": 1.5,
    "roll_sd_deg": 2.0,
    "drag_sd_px": 12.0,
    "tilt_sd_deg": 1.0,
    "yaw_sd_deg": 5.0,
    "good_guess_sd_m": 2.25,
}


@dataclass(frozen=True)
class PhotoPoiSet:
    """Simulated photos: ``N = 7 * n_photos`` rows, ordered by shooting point.

    Attributes
    ----------
    pois_m : (7, 3) PoI positions. shot_index : (N,) int, 0..6 for t1..t7.
    c_m : (N, 3) true camera centres. T_true, T_meas : (N, 3, 3) true and sensor-measured
    ``T_E->AR``. img_true_px, img_px : (N, 7, 2) exact and dragged screen points (pixels from the
    image centre). c0_good_m, c0_bad_m : (N, 3) VA initial guesses. params : the inputs used.
    """

    pois_m: np.ndarray
    shot_index: np.ndarray
    c_m: np.ndarray
    T_true: np.ndarray
    T_meas: np.ndarray
    img_true_px: np.ndarray
    img_px: np.ndarray
    c0_good_m: np.ndarray
    c0_bad_m: np.ndarray
    params: dict = field(default_factory=dict)

    @property
    def f_px(self) -> float:
        return float(self.params["f_px"])


def pois_frame() -> pd.DataFrame:
    """The PoIs as a DataFrame (``poi``, ``x_m``, ``y_m``, ``z_m``)."""
    return pd.DataFrame({"poi": list(POI_IDS), "x_m": POIS_M[:, 0], "y_m": POIS_M[:, 1], "z_m": POIS_M[:, 2]})


def shots_frame() -> pd.DataFrame:
    """The shooting points (``shot``, ``x_m``, ``y_m``, ``dist_to_p4_m``)."""
    d = np.hypot(SHOTS_XY_M[:, 0] - POIS_M[3, 0], SHOTS_XY_M[:, 1] - POIS_M[3, 1])
    return pd.DataFrame({"shot": list(SHOT_IDS), "x_m": SHOTS_XY_M[:, 0], "y_m": SHOTS_XY_M[:, 1],
                         "dist_to_p4_m": d})


def _in_room(xy: np.ndarray) -> np.ndarray:
    x0, x1, y0, y1 = ROOM_M
    return (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)


def simulate(seed=0, n_photos: int = 20, **params) -> PhotoPoiSet:
    """Simulate ``n_photos`` photos at each of the seven shooting points.

    Parameters
    ----------
    seed : int, numpy Generator or None
        Same seed, same arrays.
    n_photos : int
        Photos per shooting point (>= 1).
    **params
        Overrides of :data:`DEFAULTS` (unknown names raise ValueError).

    Returns
    -------
    PhotoPoiSet

    Raises
    ------
    ValueError
        Unknown or invalid parameters, or a PoI outside the screen in some photo (the layout or the
        camera does not fit; nothing is dropped silently).
    """
    unknown = sorted(set(params) - set(DEFAULTS))
    if unknown:
        raise ValueError(f"unknown simulation parameters {unknown}; known: {sorted(DEFAULTS)}")
    p = {**DEFAULTS, **params}
    for k, v in p.items():
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"parameter {k} must be finite and >= 0, got {v!r}")
    if int(n_photos) < 1:
        raise ValueError(f"n_photos must be >= 1, got {n_photos}")
    # one independent stream per random component, so changing one input leaves the others' draws alone
    r_height, r_aim, r_drag, r_sensor, r_good, r_bad = as_rng(seed).spawn(6)
    n = int(n_photos)
    N = 7 * n
    shot = np.repeat(np.arange(7), n)
    c = np.c_[SHOTS_XY_M[shot], p["eye_height_m"] + p["eye_height_sd_m"] * r_height.standard_normal(N)]
    target = POIS_M.mean(axis=0)
    aim = np.deg2rad(p["aim_sd_deg"]) * r_aim.standard_normal((N, 2))
    roll = np.deg2rad(p["roll_sd_deg"]) * r_aim.standard_normal(N)
    T0 = look_at(c, target, roll)
    # aim error: small rotations of the camera about its own x and y axes
    T_true = rot_x(aim[:, 0]) @ rot_y(aim[:, 1]) @ T0
    img_true = project(POIS_M, c, T_true, p["f_px"])
    half = np.array([p["width_px"], p["height_px"]]) / 2.0
    out = np.abs(img_true) > half
    if out.any():
        b, i, _ = np.argwhere(out)[0]
        raise ValueError(f"PoI {POI_IDS[i]} falls outside the screen in photo {b} (shot {SHOT_IDS[shot[b]]}); "
                         "widen the field of view or move the shooting points")
    img = img_true + p["drag_sd_px"] * r_drag.standard_normal(img_true.shape)
    tilt = np.deg2rad(p["tilt_sd_deg"]) * r_sensor.standard_normal((N, 2))
    yaw = np.deg2rad(p["yaw_sd_deg"]) * r_sensor.standard_normal(N)
    T_meas = T_true @ small_rotation(tilt[:, 0], tilt[:, 1], yaw)
    # VA initial guesses
    good = np.empty((N, 2))
    todo = np.arange(N)
    while todo.size:
        g = c[todo, :2] + p["good_guess_sd_m"] * r_good.standard_normal((todo.size, 2))
        ok = _in_room(g)
        good[todo[ok]] = g[ok]
        todo = todo[~ok]
    x0, x1, y0, y1 = ROOM_M
    bad = np.c_[r_bad.uniform(x0, x1, N), r_bad.uniform(y0, y1, N)]
    z0 = np.full((N, 1), p["eye_height_m"])
    return PhotoPoiSet(pois_m=POIS_M.copy(), shot_index=shot, c_m=c, T_true=T_true, T_meas=T_meas,
                       img_true_px=img_true, img_px=img, c0_good_m=np.c_[good, z0], c0_bad_m=np.c_[bad, z0],
                       params={**p, "n_photos": n})
