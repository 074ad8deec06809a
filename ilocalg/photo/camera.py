"""Pinhole camera helpers shared by the photo-positioning methods.

Frames and conventions
----------------------
World frame ``E``
    Metres; x along the PoI wall, y into the room (away from the wall), z up.
AR (camera) frame
    The frame of the thesis's eq. (29)-(30): x to the right of the screen, y down the screen,
    z along the optical axis into the scene (OpenCV's camera convention). A world point ``p``
    has AR coordinates ``[p]_AR = T (p - c)`` with ``T = T_E->AR`` (3, 3), a rotation matrix,
    and ``c`` the camera centre in ``E``.
Screen points
    ``p' = (p'_x, p'_y)`` in pixels, measured from the image centre (x right, y down); the
    focal length ``f_px`` is in pixels. OpenCV pixel coordinates are ``p' + (cx, cy)``.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
sec. 6.1-6.2, eq. (27)-(30), Fig 24 and Fig 26.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "thin_lens_image_distance_m",
    "intrinsics",
    "look_at",
    "rot_x",
    "rot_y",
    "rot_z",
    "small_rotation",
    "project",
    "ray_angle_rad",
    "validate_points",
]


def thin_lens_image_distance_m(d_o_m, f_m):
    """Image distance ``d_i`` of the thin-lens law ``1/d_o + 1/d_i = 1/f``, eq. (27)-(28).

    ``d_i = f / (1 - f / d_o)``; for ``d_o >> f``, ``d_i ~ f``, which is why the photo-positioning
    equations use the focal length as the image distance (pinhole model).

    Parameters
    ----------
    d_o_m : array_like
        Object distances, metres (must exceed ``f_m``).
    f_m : float
        Focal length, metres.

    References
    ----------
    i-Loc thesis, sec. 6.1, eq. (27)-(28).
    """
    d_o = np.asarray(d_o_m, dtype=float)
    if not np.isfinite(f_m) or f_m <= 0:
        raise ValueError(f"f_m must be a positive focal length in metres, got {f_m!r}")
    if np.any(~np.isfinite(d_o)) or np.any(d_o <= f_m):
        raise ValueError("d_o_m must be finite and larger than the focal length (a real image)")
    return f_m / (1.0 - f_m / d_o)


def intrinsics(f_px: float, cx_px: float = 0.0, cy_px: float = 0.0) -> np.ndarray:
    """Camera matrix ``K`` (3, 3) for focal length ``f_px`` and principal point ``(cx, cy)`` in pixels."""
    if not np.isfinite(f_px) or f_px <= 0:
        raise ValueError(f"f_px must be a positive focal length in pixels, got {f_px!r}")
    return np.array([[f_px, 0.0, cx_px], [0.0, f_px, cy_px], [0.0, 0.0, 1.0]])


def rot_x(a_rad) -> np.ndarray:
    """Rotation matrices about x, shape ``(..., 3, 3)`` for angles of shape ``(...)``."""
    a = np.asarray(a_rad, dtype=float)
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2)


def rot_y(a_rad) -> np.ndarray:
    """Rotation matrices about y, shape ``(..., 3, 3)``."""
    a = np.asarray(a_rad, dtype=float)
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)


def rot_z(a_rad) -> np.ndarray:
    """Rotation matrices about z, shape ``(..., 3, 3)``."""
    a = np.asarray(a_rad, dtype=float)
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def small_rotation(rx_rad, ry_rad, rz_rad) -> np.ndarray:
    """World-frame rotation ``Rz(rz) @ Ry(ry) @ Rx(rx)``, shape ``(..., 3, 3)``.

    Used to perturb ``T_E->AR`` as ``T @ small_rotation(...)``: ``rz`` is a heading (yaw) error
    about the world vertical, ``rx`` and ``ry`` are tilt errors about the horizontal world axes.
    """
    return rot_z(rz_rad) @ rot_y(ry_rad) @ rot_x(rx_rad)


def look_at(c_m, target_m, roll_rad=0.0) -> np.ndarray:
    """``T_E->AR`` (..., 3, 3) of a camera at ``c_m`` whose optical axis points at ``target_m``.

    The screen's x axis is horizontal (then rotated by ``roll_rad`` about the optical axis);
    world up is +z. ``c_m`` and ``target_m`` broadcast, shape ``(..., 3)``.
    """
    c = np.asarray(c_m, dtype=float)
    t = np.asarray(target_m, dtype=float)
    zc = t - c
    n = np.linalg.norm(zc, axis=-1, keepdims=True)
    if np.any(n < 1e-12):
        raise ValueError("target_m must differ from c_m")
    zc = zc / n
    up = np.array([0.0, 0.0, 1.0])
    xc = np.cross(zc, up)
    nx = np.linalg.norm(xc, axis=-1, keepdims=True)
    if np.any(nx < 1e-9):
        raise ValueError("look_at: the optical axis is vertical; heading undefined")
    xc = xc / nx
    yc = np.cross(zc, xc)
    T = np.stack([xc, yc, zc], axis=-2)
    roll = np.asarray(roll_rad, dtype=float)
    if np.any(roll != 0.0):
        T = rot_z(roll) @ T
    return T


def validate_points(pois_m, img_px, f_px=None, min_points: int = 1):
    """Check PoI world points ``(n, 3)`` and screen points ``(n, 2)``; return them as float arrays."""
    P = np.asarray(pois_m, dtype=float)
    U = np.asarray(img_px, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3:
        raise ValueError(f"pois_m must have shape (n, 3), got {P.shape}")
    if U.shape != (P.shape[0], 2):
        raise ValueError(f"img_px must have shape ({P.shape[0]}, 2) to match pois_m, got {U.shape}")
    if P.shape[0] < min_points:
        raise ValueError(f"need at least {min_points} PoIs, got {P.shape[0]}")
    if not (np.isfinite(P).all() and np.isfinite(U).all()):
        raise ValueError("pois_m and img_px must be finite (no NaN)")
    if f_px is not None and (not np.isfinite(f_px) or f_px <= 0):
        raise ValueError(f"f_px must be a positive focal length in pixels, got {f_px!r}")
    return P, U


def project(pois_m, c_m, T, f_px: float) -> np.ndarray:
    """Screen points ``p'`` (..., n, 2) in pixels from the image centre, eq. (29)-(30).

    Parameters
    ----------
    pois_m : array (n, 3) or (..., n, 3)
        PoI positions in the world frame, metres.
    c_m : array (..., 3)
        Camera centres, metres.
    T : array (..., 3, 3)
        ``T_E->AR`` rotation matrices.
    f_px : float
        Focal length in pixels.

    Raises
    ------
    ValueError
        If a PoI is on or behind the camera plane (``[p]_AR,z <= 0``).

    References
    ----------
    i-Loc thesis, eq. (29) ``p'_x : p'_y : f = [p]_AR,x : [p]_AR,y : [p]_AR,z`` and eq. (30).
    """
    P = np.asarray(pois_m, dtype=float)
    c = np.asarray(c_m, dtype=float)
    T = np.asarray(T, dtype=float)
    q = np.einsum("...ij,...nj->...ni", T, P - c[..., None, :])
    if np.any(q[..., 2] <= 0):
        raise ValueError("a PoI lies on or behind the camera (its AR z coordinate is <= 0)")
    return f_px * q[..., :2] / q[..., 2:3]


def ray_angle_rad(img_px_a, img_px_b, f_px: float) -> np.ndarray:
    """Angle (rad) between the viewing rays of two screen points ``(..., 2)``; needs no orientation."""
    a = np.asarray(img_px_a, dtype=float)
    b = np.asarray(img_px_b, dtype=float)
    ra = np.concatenate([a, np.full(a.shape[:-1] + (1,), float(f_px))], axis=-1)
    rb = np.concatenate([b, np.full(b.shape[:-1] + (1,), float(f_px))], axis=-1)
    cr = np.linalg.norm(np.cross(ra, rb), axis=-1)
    return np.arctan2(cr, np.sum(ra * rb, axis=-1))
