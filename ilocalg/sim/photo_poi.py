"""Simulated photos of the i-Loc PoI wall (thesis Figs 25-28), deterministic from a seed.

What is simulated
-----------------
Seven points of interest ``p1..p7`` on the walls and seven shooting points ``t1..t7`` one metre
apart. At each shooting point the user takes ``n_photos`` photos: the phone is held at eye height
and aimed at the middle of the PoIs; the PoIs are projected with a pinhole camera (eq. 29-30); the
user drags each PoI marker onto its image with a drag-to-match error; the phone's accelerometer and
magnetometer report the orientation ``T_E->AR`` with a tilt and a heading error.

Layouts (built from the text; Fig 28, which holds the coordinates, is missing from the copy)
    Every constraint the text gives, checked by :func:`check_layout`:

    * "seven black PoIs distributed on the walls" (Chiu 2013, L658, Fig 25 caption);
    * "seven test points ... one metre apart" (L688, Fig 27 caption "test points and PoI map");
    * "for p4, t1 and t7 are the nearest and the farthest" and the VA error grows with the distance
      from p4 (L696): the distance from p4 increases from t1 to t7;
    * "the smallest view angles are angle p3 t7 p4 and angle p4 t7 p5" (L696): at t7 these two are
      the smallest of the 21 PoI-pair angles;
    * "{1,2}, {6,7} are nearer the test positions than {3,4}, {3,5}, {4,5}, {3,4,5}" (L707): the
      mean distance from the test points to the members of each of the first two combinations is
      below that of each of the last four;
    * "p1, p3, p4, p5 and p6 lie almost on one horizontal line" (L707, Fig 28): their heights agree
      within 5 cm, and p2 and p7 are off that line (by more than 0.3 m);
    * every PoI is on the screen from every test point (needed for the combinations of all seven).

    Two families satisfy them. (1) A room (:func:`make_layout`): an end wall holding p3, p4, p5 (p4 in
    front of the test line) and side walls holding p1, p2 (left) and p6, p7 (right), nearer to the
    test points, all ahead of ``t1``. (2) One straight wall (:func:`make_wall_layout`): the test line
    runs parallel to the wall, starting in front of p4 (so the distance from p4 grows t1 -> t7), with
    p3, p4, p5 close together at the t1 end and the pairs {p1, p2}, {p6, p7} further along the wall,
    nearer on average to the test points. (An earlier version of this docstring said the constraints
    rule out one wall: that holds only for a test line running straight away from the wall; a line
    along the wall satisfies them all.) :data:`LAYOUTS` holds several members of each family, each
    satisfying every constraint; the choice among them is an assumption that callers sweep (the
    spread is the uncertainty Fig 28's absence leaves); :func:`satisfying_layouts` builds every
    satisfying member of both grids. :data:`LAYOUTS` ``"row"`` is the toolkit's earlier layout (seven
    PoIs in a 2.4 m row on one wall, test line straight away from it), kept as a labelled
    sensitivity case: it violates L707's ordering.
    Frame: x across the room, y along the test line (away from the end wall), z up; metres.

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
    Uniform over the layout's room floor: no knowledge of the position.
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
           "pois_frame", "shots_frame", "Layout", "make_layout", "make_wall_layout", "check_layout", "LAYOUTS",
           "DEFAULT_LAYOUT", "LAYOUT_DIMENSIONS", "LAYOUT_GRID", "WALL_LAYOUT_DIMENSIONS", "WALL_LAYOUT_GRID",
           "satisfying_layouts"]

POI_IDS = tuple(f"p{i}" for i in range(1, 8))
SHOT_IDS = tuple(f"t{i}" for i in range(1, 8))
#: Heights of p1, p3, p4, p5, p6 about the line height (within 2 cm: "almost" on one line, L707).
_LINE_JITTER_M = np.array([0.00, 0.02, -0.02, 0.01, -0.01])


@dataclass(frozen=True)
class Layout:
    """A PoI / shooting-point layout.

    Attributes
    ----------
    name : str
    pois_m : (7, 3) PoI positions p1..p7, metres.
    shots_xy_m : (7, 2) shooting points t1..t7 on the floor, metres.
    room_m : (x_min, x_max, y_min, y_max) floor of the room, metres (VA guesses stay inside).
    dims : dict of the dimensions it was built from.
    """

    name: str
    pois_m: np.ndarray
    shots_xy_m: np.ndarray
    room_m: tuple
    dims: dict = field(default_factory=dict)


def make_layout(name: str, t1_to_end_wall_m: float, half_width_m: float, side_y_m: float,
                end_spacing_m: float, line_height_m: float = 1.6, off_line_m: float = 0.5,
                side_pair_dy_m: float = 0.5) -> Layout:
    """A room layout of the family described in the module docstring.

    Parameters
    ----------
    t1_to_end_wall_m : float
        Distance from ``t1`` to the end wall (``t1 = (0, t1_to_end_wall_m)``, ``t7`` 6 m further).
    half_width_m : float
        Side walls at ``x = +-half_width_m``.
    side_y_m : float
        Distance of the side-wall PoIs from the end wall (p1, p6 at ``side_y_m + dy/2``, p2, p7 at
        ``side_y_m - dy/2`` with ``dy = side_pair_dy_m``).
    end_spacing_m : float
        p3, p4, p5 on the end wall at ``x = -s, 0, s``.
    line_height_m : float
        Height of the line of p1, p3, p4, p5, p6; p2 is ``off_line_m`` above it, p7 below.
    """
    h, hw, sy, sp, dy = line_height_m, half_width_m, side_y_m, end_spacing_m, side_pair_dy_m
    z_line = h + _LINE_JITTER_M
    pois = np.array([
        [-hw, sy + dy / 2, z_line[0]],
        [-hw, sy - dy / 2, h + off_line_m],
        [-sp, 0.0, z_line[1]],
        [0.0, 0.0, z_line[2]],
        [sp, 0.0, z_line[3]],
        [hw, sy + dy / 2, z_line[4]],
        [hw, sy - dy / 2, h - off_line_m],
    ])
    shots = np.array([[0.0, t1_to_end_wall_m + k] for k in range(7)])
    room = (-hw, hw, 0.5, t1_to_end_wall_m + 7.5)
    dims = {"t1_to_end_wall_m": t1_to_end_wall_m, "half_width_m": hw, "side_y_m": sy, "end_spacing_m": sp,
            "line_height_m": h, "off_line_m": off_line_m, "side_pair_dy_m": dy}
    return Layout(name, pois, shots, room, dims)


def make_wall_layout(name: str, wall_dist_m: float, pair_centre_x_m: float, pair_gap_m: float,
                     end_spacing_m: float, t1_x_m: float = 0.0, line_height_m: float = 1.6,
                     off_line_m: float = 0.5, pair_dx_m: float = 0.5) -> Layout:
    """A one-wall layout (family 2 of the module docstring): every PoI on the wall ``y = 0``.

    Parameters
    ----------
    wall_dist_m : float
        Distance of the test line from the wall (``t_k = (t1_x_m + k - 1, wall_dist_m)``).
    pair_centre_x_m : float
        Along-wall position of the middle between the pairs {p1, p2} and {p6, p7}.
    pair_gap_m : float
        Distance between the two pairs' centres (p1, p2 at ``centre - gap/2 -+ dx/2``; p6, p7 at
        ``centre + gap/2 -+ dx/2``, ``dx = pair_dx_m``).
    end_spacing_m : float
        p3, p4, p5 at ``x = -s, 0, s``.
    t1_x_m : float
        Along-wall position of ``t1`` (p4 at ``x = 0``).
    """
    h, c, g, sp, dx = line_height_m, pair_centre_x_m, pair_gap_m, end_spacing_m, pair_dx_m
    z_line = h + _LINE_JITTER_M
    pois = np.array([
        [c - g / 2 - dx / 2, 0.0, z_line[0]],
        [c - g / 2 + dx / 2, 0.0, h + off_line_m],
        [-sp, 0.0, z_line[1]],
        [0.0, 0.0, z_line[2]],
        [sp, 0.0, z_line[3]],
        [c + g / 2 - dx / 2, 0.0, z_line[4]],
        [c + g / 2 + dx / 2, 0.0, h - off_line_m],
    ])
    shots = np.array([[t1_x_m + k, wall_dist_m] for k in range(7)])
    x_lo = min(float(pois[:, 0].min()), t1_x_m) - 1.5
    x_hi = max(float(pois[:, 0].max()), t1_x_m + 6.0) + 1.5
    room = (x_lo, x_hi, 0.5, wall_dist_m + 2.0)
    dims = {"family": "one wall", "wall_dist_m": wall_dist_m, "pair_centre_x_m": c, "pair_gap_m": g,
            "end_spacing_m": sp, "t1_x_m": t1_x_m, "line_height_m": h, "off_line_m": off_line_m,
            "pair_dx_m": dx}
    return Layout(name, pois, shots, room, dims)


def _row_layout() -> Layout:
    """The toolkit's earlier layout: seven PoIs in a 2.4 m row on one wall (violates L707)."""
    pois = np.array([[-1.2, 0.0, 1.60], [-0.8, 0.0, 2.10], [-0.4, 0.0, 1.62], [0.0, 0.0, 1.58],
                     [0.4, 0.0, 1.61], [0.8, 0.0, 1.59], [1.2, 0.0, 1.10]])
    shots = np.array([[0.0, 2.5 + k] for k in range(7)])
    return Layout("row", pois, shots, (-3.0, 3.0, 0.5, 10.0), {"note": "one wall, 0.4 m apart (earlier layout)"})


#: Grid of dimensions searched for layouts (t1 to end wall, half width, side PoIs' distance from the
#: end wall, end-wall spacing), m: plausible corridor/room sizes (2-4 m wide, t1 4-6 m from the end wall).
LAYOUT_GRID = {"t1_to_end_wall_m": (4.0, 5.0, 6.0), "half_width_m": (1.0, 1.5, 2.0),
               "side_y_m": (1.0, 1.4, 1.8, 2.2, 2.6, 3.0), "end_spacing_m": (0.4, 0.6, 0.8, 1.0)}
#: Grid of the one-wall family (:func:`make_wall_layout`): test line 2.5-4 m from the wall, the pairs'
#: middle 2-4 m along it, the pairs 1-2 m apart, p3-p5 spacing 0.4-0.6 m (as the room family's).
WALL_LAYOUT_GRID = {"wall_dist_m": (2.5, 3.0, 3.5, 4.0), "pair_centre_x_m": (2.0, 2.5, 3.0, 3.5, 4.0),
                    "pair_gap_m": (1.0, 1.5, 2.0), "end_spacing_m": (0.4, 0.6)}
#: Layouts of the family, from the grid above: 33 of its 216 members satisfy every constraint of
#: :func:`check_layout` (the L696 smallest-angle constraint keeps the end-wall spacing at 0.4-0.6 m).
#: "A" (default) is the satisfying member nearest the grid's middle; "B".."G" are the members at six
#: evenly spaced positions (0, 6, 13, 19, 26, 32) of the satisfying list in grid order. Chosen from
#: the constraints alone, before any positioning was run; ``tests/test_sim_photo_poi.py`` re-derives them.
LAYOUT_DIMENSIONS = {
    "A": (5.0, 1.5, 1.8, 0.4),
    "B": (4.0, 1.0, 1.0, 0.4),
    "C": (5.0, 1.0, 1.8, 0.4),
    "D": (5.0, 2.0, 1.0, 0.4),
    "E": (6.0, 1.0, 2.6, 0.6),
    "F": (6.0, 1.5, 2.6, 0.4),
    "G": (6.0, 2.0, 1.8, 0.4),
}
#: One-wall members: 9 of the 120 members of :data:`WALL_LAYOUT_GRID` satisfy every constraint (the screen
#: constraint binds: the PoIs span a wide angle from t1); "W1".."W4" are those at four evenly spaced positions
#: (0, 3, 5, 8) of the satisfying list in grid order (chosen from the constraints alone; the test re-derives
#: them).
WALL_LAYOUT_DIMENSIONS = {
    "W1": (3.5, 2.0, 1.0, 0.4),
    "W2": (4.0, 2.0, 1.0, 0.6),
    "W3": (4.0, 2.5, 1.0, 0.4),
    "W4": (4.0, 2.5, 1.5, 0.6),
}
#: The layouts: the room members, the one-wall members and the earlier one-wall ``"row"`` (sensitivity only).
LAYOUTS = {k: make_layout(k, *v) for k, v in LAYOUT_DIMENSIONS.items()}
LAYOUTS.update({k: make_wall_layout(k, *v) for k, v in WALL_LAYOUT_DIMENSIONS.items()})
LAYOUTS["row"] = _row_layout()
#: Default layout (the first of the family; the others are swept).
DEFAULT_LAYOUT = "A"
#: PoI world positions (7, 3), shooting points (7, 2) and room floor of the default layout.
POIS_M = LAYOUTS[DEFAULT_LAYOUT].pois_m
SHOTS_XY_M = LAYOUTS[DEFAULT_LAYOUT].shots_xy_m
ROOM_M = LAYOUTS[DEFAULT_LAYOUT].room_m

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


def _layout(layout) -> Layout:
    if isinstance(layout, Layout):
        return layout
    if layout not in LAYOUTS:
        raise ValueError(f"layout must be a Layout or one of {sorted(LAYOUTS)}, got {layout!r}")
    return LAYOUTS[layout]


def pois_frame(layout=DEFAULT_LAYOUT) -> pd.DataFrame:
    """The PoIs as a DataFrame (``poi``, ``x_m``, ``y_m``, ``z_m``)."""
    P = _layout(layout).pois_m
    return pd.DataFrame({"poi": list(POI_IDS), "x_m": P[:, 0], "y_m": P[:, 1], "z_m": P[:, 2]})


def shots_frame(layout=DEFAULT_LAYOUT) -> pd.DataFrame:
    """The shooting points (``shot``, ``x_m``, ``y_m``, ``dist_to_p4_m``)."""
    lay = _layout(layout)
    S, P = lay.shots_xy_m, lay.pois_m
    d = np.hypot(S[:, 0] - P[3, 0], S[:, 1] - P[3, 1])
    return pd.DataFrame({"shot": list(SHOT_IDS), "x_m": S[:, 0], "y_m": S[:, 1], "dist_to_p4_m": d})


def _pair_angles(c, P):
    """View angles (21,) between all PoI pairs seen from ``c`` (3,), with the pair list."""
    pairs = [(i, j) for i in range(7) for j in range(i + 1, 7)]
    u = P - c
    u = u / np.linalg.norm(u, axis=1, keepdims=True)
    return np.array([np.arccos(np.clip(u[i] @ u[j], -1, 1)) for i, j in pairs]), pairs


def check_layout(layout=DEFAULT_LAYOUT, f_px: float = 1045.0, width_px: int = 1280, height_px: int = 720,
                 eye_height_m: float = 1.45, screen_margin: float = 0.9) -> pd.DataFrame:
    """Check a layout against every constraint the thesis's text gives (module docstring).

    Returns
    -------
    DataFrame
        One row per constraint: ``constraint``, ``paper_line`` (i-Loc thesis line), ``text_says``,
        ``value`` (the measured quantity), ``satisfied`` (bool).
    """
    lay = _layout(layout)
    P, S = lay.pois_m, lay.shots_xy_m
    C = np.c_[S, np.full(7, eye_height_m)]
    rows = []
    walls = (np.isclose(P[:, 1], 0.0) | np.isclose(np.abs(P[:, 0]), abs(lay.room_m[0]))
             | np.isclose(np.abs(P[:, 0]), abs(lay.room_m[1])))
    rows.append(("PoIs on the walls", "L658", "seven black PoIs distributed on the walls",
                 f"{int(walls.sum())} of 7 on a wall", bool(walls.all())))
    gaps = np.hypot(*np.diff(S, axis=0).T)
    rows.append(("test points 1 m apart", "L688", "each test position 1 m from the next",
                 f"gaps {gaps.min():.3f}-{gaps.max():.3f} m", bool(np.allclose(gaps, 1.0))))
    d4 = np.hypot(S[:, 0] - P[3, 0], S[:, 1] - P[3, 1])
    rows.append(("distance from p4 grows t1 -> t7", "L696", "for p4, t1 is the nearest and t7 the farthest",
                 " < ".join(f"{v:.2f}" for v in d4), bool(np.all(np.diff(d4) > 0))))
    ang, pairs = _pair_angles(C[6], P)
    two = {pairs[k] for k in np.argsort(ang)[:2]}
    rows.append(("smallest view angles at t7: p3-p4, p4-p5", "L696",
                 "the smallest view angles are angle p3 t7 p4 and angle p4 t7 p5",
                 "smallest: " + ", ".join(f"p{i + 1}-p{j + 1}" for i, j in sorted(two)), two == {(2, 3), (3, 4)}))
    dist = np.linalg.norm(P[None, :, :2] - S[:, None, :], axis=2).mean(axis=0)   # mean over test points

    def mean_d(combo):
        return float(np.mean([dist[i - 1] for i in combo]))

    near = [mean_d(c) for c in ((1, 2), (6, 7))]
    far = [mean_d(c) for c in ((3, 4), (3, 5), (4, 5), (3, 4, 5))]
    rows.append(("{1,2}, {6,7} nearer than {3,4}, {3,5}, {4,5}, {3,4,5}", "L707",
                 "{1,2}, {6,7} nearer the test positions than {3,4}, {3,5}, {4,5}, {3,4,5}",
                 f"max near {max(near):.2f} m, min far {min(far):.2f} m", max(near) < min(far)))
    z = P[:, 2]
    line = z[[0, 2, 3, 4, 5]]
    off = np.abs(z[[1, 6]] - line.mean())
    rows.append(("p1, p3, p4, p5, p6 on one horizontal line; p2, p7 off it", "L707",
                 "p1, p3, p4, p5 and p6 almost on one horizontal line (Fig 28)",
                 f"line heights spread {np.ptp(line):.3f} m; p2, p7 off by {off.min():.2f} m or more",
                 bool(np.ptp(line) < 0.05 and off.min() > 0.3)))
    T = look_at(C, P.mean(axis=0))
    img = project(P, C, T, f_px)
    half = screen_margin * np.array([width_px, height_px]) / 2.0
    rows.append(("every PoI on the screen from every test point", "L696",
                 "each test point is evaluated with combinations of the seven PoIs (simulator requirement)",
                 f"largest |u|/half-width {np.max(np.abs(img) / (np.array([width_px, height_px]) / 2)):.2f}",
                 bool(np.all(np.abs(img) <= half))))
    return pd.DataFrame(rows, columns=["constraint", "paper_line", "text_says", "value", "satisfied"])


def _in_room(xy: np.ndarray, room) -> np.ndarray:
    x0, x1, y0, y1 = room
    return (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)


def simulate(seed=0, n_photos: int = 20, layout=DEFAULT_LAYOUT, **params) -> PhotoPoiSet:
    """Simulate ``n_photos`` photos at each of the seven shooting points.

    Parameters
    ----------
    seed : int, numpy Generator or None
        Same seed, same arrays.
    n_photos : int
        Photos per shooting point (>= 1).
    layout : str or Layout
        A key of :data:`LAYOUTS` (default :data:`DEFAULT_LAYOUT`) or a :class:`Layout`.
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
    lay = _layout(layout)
    POIS, SHOTS, ROOM = lay.pois_m, lay.shots_xy_m, lay.room_m
    # one independent stream per random component, so changing one input leaves the others' draws alone
    r_height, r_aim, r_drag, r_sensor, r_good, r_bad = as_rng(seed).spawn(6)
    n = int(n_photos)
    N = 7 * n
    shot = np.repeat(np.arange(7), n)
    c = np.c_[SHOTS[shot], p["eye_height_m"] + p["eye_height_sd_m"] * r_height.standard_normal(N)]
    target = POIS.mean(axis=0)
    aim = np.deg2rad(p["aim_sd_deg"]) * r_aim.standard_normal((N, 2))
    roll = np.deg2rad(p["roll_sd_deg"]) * r_aim.standard_normal(N)
    T0 = look_at(c, target, roll)
    # aim error: small rotations of the camera about its own x and y axes
    T_true = rot_x(aim[:, 0]) @ rot_y(aim[:, 1]) @ T0
    img_true = project(POIS, c, T_true, p["f_px"])
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
        ok = _in_room(g, ROOM)
        good[todo[ok]] = g[ok]
        todo = todo[~ok]
    x0, x1, y0, y1 = ROOM
    bad = np.c_[r_bad.uniform(x0, x1, N), r_bad.uniform(y0, y1, N)]
    z0 = np.full((N, 1), p["eye_height_m"])
    return PhotoPoiSet(pois_m=POIS.copy(), shot_index=shot, c_m=c, T_true=T_true, T_meas=T_meas,
                       img_true_px=img_true, img_px=img, c0_good_m=np.c_[good, z0], c0_bad_m=np.c_[bad, z0],
                       params={**p, "n_photos": n, "layout": lay.name})


def satisfying_layouts() -> dict[str, Layout]:
    """Every member of :data:`LAYOUT_GRID` (rooms, ``"R<i>"``) and :data:`WALL_LAYOUT_GRID` (one wall,
    ``"W<i>"`` numbered over the whole wall grid) that satisfies every constraint of :func:`check_layout`."""
    import itertools

    out = {}
    for prefix, grid, maker in (("R", LAYOUT_GRID, make_layout), ("Wg", WALL_LAYOUT_GRID, make_wall_layout)):
        for i, d in enumerate(itertools.product(*grid.values())):
            lay = maker(f"{prefix}{i}", *d)
            if check_layout(lay)["satisfied"].all():
                out[lay.name] = lay
    return out
