"""Views of a square planar marker (a QR code on a wall): the scene of the survey's homography ranging.

A marker of side ``side_m`` hangs on the wall ``y = 0`` with its centre at ``centre_height_m``; a phone looks
at it from ``distance_m`` at a bearing uniform within ``+-bearing_max_deg`` of the wall's normal, its height
off by ``N(0, height_sd_m)`` and its roll by ``N(0, roll_sd_deg)``. Every value is an assumption, documented
in ``data/photo_poi/README.md`` ("Marker ranging").

References
----------
Ye, C.-H. and Huang, W.-L. Positioning by combining images and inertial sensors (a survey). Teaching
report, National Kaohsiung University of Applied Sciences. Sec. 4, eq. (3)-(5), Fig 8.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.photo.camera import look_at, project

__all__ = ["MARKER_DEFAULTS", "MarkerViews", "simulate_marker_views"]

#: The scene's assumed values (data/photo_poi/README.md).
MARKER_DEFAULTS = {
    "side_m": 0.18,
    "centre_height_m": 1.5,
    "bearing_max_deg": 30.0,
    "height_sd_m": 0.1,
    "roll_sd_deg": 2.0,
}


@dataclass(frozen=True)
class MarkerViews:
    """``n`` views of one marker: its corners on the plane (``corners_plane_m``, (4, 2): x and z about the
    centre) and in the world (``corners_m``, (4, 3)), its centre (``centre_m``), the camera centres (``c_m``,
    (n, 3)) and the exact corner images (``img_true_px``, (n, 4, 2), pixels from the image centre)."""

    corners_plane_m: np.ndarray
    corners_m: np.ndarray
    centre_m: np.ndarray
    c_m: np.ndarray
    img_true_px: np.ndarray


def simulate_marker_views(rng: np.random.Generator, distance_m: float, n: int, f_px: float,
                          **marker) -> MarkerViews:
    """``n`` views of the marker from ``distance_m`` (``marker`` overrides :data:`MARKER_DEFAULTS`)."""
    unknown = sorted(set(marker) - set(MARKER_DEFAULTS))
    if unknown:
        raise ValueError(f"unknown marker parameters {unknown}; known: {sorted(MARKER_DEFAULTS)}")
    if distance_m <= 0:
        raise ValueError(f"distances_m must be positive, got {distance_m}")
    m = {**MARKER_DEFAULTS, **marker}
    h = m["side_m"] / 2
    XY = np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
    centre = np.array([0.0, 0.0, m["centre_height_m"]])
    world = np.c_[XY[:, 0], np.zeros(4), centre[2] + XY[:, 1]]
    bearing = np.deg2rad(rng.uniform(-m["bearing_max_deg"], m["bearing_max_deg"], n))
    dz = m["height_sd_m"] * rng.standard_normal(n)
    horiz = np.sqrt(np.maximum(distance_m * distance_m - dz * dz, 0.0))
    c = np.c_[horiz * np.sin(bearing), horiz * np.cos(bearing), centre[2] + dz]
    T = look_at(c, centre, np.deg2rad(m["roll_sd_deg"]) * rng.standard_normal(n))
    return MarkerViews(XY, world, centre, c, project(world, c, T, f_px))
