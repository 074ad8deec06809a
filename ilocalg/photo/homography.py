"""Plane-to-plane homography ranging: ``H = K [r1 r2 t]`` from a planar target.

A planar target (a QR code's four corners, or PoIs on one wall) with plane coordinates
``(X, Y)`` (``Z = 0``) maps to the image by ``lambda (x, y, 1)^T = H (X, Y, 1)^T`` with
``H = K [r1 r2 t]`` (eq. 3-5). :func:`homography_dlt` estimates ``H`` from >= 4 correspondences
(normalised DLT); :func:`homography_pose` recovers ``r1, r2, t`` and from them the camera centre and
its distance ``l`` to the target's origin (the survey's Fig 8 "distance from the 2-D code to the
camera").

References
----------
葉濟賢, 黃偉立, "Positioning by combining images and inertial sensors" (survey), sec. 4, eq. (1)-(5).
R. Hartley and A. Zisserman, Multiple View Geometry, 2nd ed., alg. 4.2 (normalised DLT) and
Z. Zhang, "A flexible new technique for camera calibration", IEEE TPAMI 22(11), 2000, sec. 2.2
(``r1 = lambda K^-1 h1``, ``r2 = lambda K^-1 h2``, ``r3 = r1 x r2``, ``t = lambda K^-1 h3``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.photo.camera import intrinsics

__all__ = ["homography_dlt", "HomographyPose", "homography_pose", "homography_locate", "wall_plane_coords"]


def _normaliser(x: np.ndarray) -> np.ndarray:
    m = x.mean(axis=0)
    d = np.sqrt(np.sum((x - m) ** 2, axis=1)).mean()
    s = np.sqrt(2.0) / max(d, 1e-300)
    return np.array([[s, 0.0, -s * m[0]], [0.0, s, -s * m[1]], [0.0, 0.0, 1.0]])


def homography_dlt(plane_xy, img_px) -> np.ndarray:
    """Homography ``H`` (3, 3), ``||H||_F = 1``, mapping plane points to image points (normalised DLT).

    Parameters
    ----------
    plane_xy : array (n, 2)
        Target points in the target plane, metres, ``n >= 4``, no three collinear for n = 4.
    img_px : array (n, 2)
        Their image points, pixels (any origin, used consistently with ``K``).

    References
    ----------
    Ye and Huang (survey), eq. (3)-(5); Hartley & Zisserman alg. 4.2.
    """
    X = np.asarray(plane_xy, dtype=float)
    x = np.asarray(img_px, dtype=float)
    if X.ndim != 2 or X.shape[1] != 2 or x.shape != X.shape:
        raise ValueError(f"plane_xy and img_px must both have shape (n, 2), got {X.shape} and {x.shape}")
    if X.shape[0] < 4:
        raise ValueError(f"a homography needs at least 4 points, got {X.shape[0]}")
    if not (np.isfinite(X).all() and np.isfinite(x).all()):
        raise ValueError("plane_xy and img_px must be finite")
    TX, Tx = _normaliser(X), _normaliser(x)
    Xh = np.column_stack([X, np.ones(len(X))]) @ TX.T
    xh = np.column_stack([x, np.ones(len(x))]) @ Tx.T
    # two rows per point: [0, -w X, v X] and [w X, 0, -u X], X = (X1, Y1, W1), (u, v, w) its image point
    u, v, w = xh[:, :1], xh[:, 1:2], xh[:, 2:]
    A = np.zeros((2 * len(X), 9))
    A[0::2, 3:6] = -w * Xh
    A[0::2, 6:] = v * Xh
    A[1::2, :3] = w * Xh
    A[1::2, 6:] = -u * Xh
    _, s, Vt = np.linalg.svd(A)
    if s.size >= 8 and s[7] < 1e-10 * s[0]:
        raise ValueError("degenerate point configuration for a homography (collinear target points?)")
    Hn = Vt[-1].reshape(3, 3)
    H = np.linalg.inv(Tx) @ Hn @ TX
    return H / np.linalg.norm(H)


@dataclass(frozen=True)
class HomographyPose:
    """Pose from a homography.

    Attributes
    ----------
    R : ndarray (3, 3)
        Rotation target-plane frame -> camera frame, columns ``r1, r2, r3``.
    t_m : ndarray (3,)
        Target origin in the camera frame, metres.
    c_plane_m : ndarray (3,)
        Camera centre in the target frame (``X, Y`` in the plane, ``Z`` along ``r1 x r2``), metres.
    distance_m : float
        Camera-to-target-origin distance ``l = ||t||``, metres.
    """

    R: np.ndarray
    t_m: np.ndarray
    c_plane_m: np.ndarray
    distance_m: float


def homography_pose(H, f_px: float, cx_px: float = 0.0, cy_px: float = 0.0) -> HomographyPose:
    """Decompose ``H = lambda K [r1 r2 t]`` (eq. 4) into a rotation, translation and distance.

    The scale is ``lambda = 2 / (||K^-1 h1|| + ||K^-1 h2||)`` with its sign chosen so the target lies
    in front of the camera (``t_z > 0``); ``[r1 r2 r1 x r2]`` is projected onto the nearest rotation.

    References
    ----------
    Ye and Huang (survey), eq. (4) and Fig 8; Zhang (2000), sec. 2.2 and appendix C.
    """
    H = np.asarray(H, dtype=float)
    if H.shape != (3, 3) or not np.isfinite(H).all():
        raise ValueError(f"H must be a finite 3x3 matrix, got shape {H.shape}")
    M = np.linalg.solve(intrinsics(f_px, cx_px, cy_px), H)
    lam = 2.0 / (np.linalg.norm(M[:, 0]) + np.linalg.norm(M[:, 1]))
    if M[2, 2] * lam < 0:
        lam = -lam
    r1, r2, t = lam * M[:, 0], lam * M[:, 1], lam * M[:, 2]
    r3 = np.array([r1[1] * r2[2] - r1[2] * r2[1], r1[2] * r2[0] - r1[0] * r2[2], r1[0] * r2[1] - r1[1] * r2[0]])
    Q = np.column_stack([r1, r2, r3])                         # r3 = r1 x r2 (np.cross's products, one call less)
    U, _, Vt = np.linalg.svd(Q)
    R = U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt
    c = -R.T @ t
    return HomographyPose(R=R, t_m=t, c_plane_m=c, distance_m=float(np.linalg.norm(t)))


def wall_plane_coords(pois_m, origin_m, e1, e2) -> np.ndarray:
    """Plane coordinates (n, 2) of world points on a plane with origin ``origin_m`` and unit axes ``e1, e2``."""
    d = np.asarray(pois_m, dtype=float) - np.asarray(origin_m, dtype=float)
    return np.c_[d @ np.asarray(e1, dtype=float), d @ np.asarray(e2, dtype=float)]


def homography_locate(pois_m, img_px, f_px: float, origin_m, e1, e2) -> np.ndarray:
    """World camera centre (3,) from >= 4 coplanar PoIs on the plane ``(origin_m, e1, e2)``.

    ``e1`` and ``e2`` are orthonormal world vectors spanning the plane; the plane frame's third axis
    is ``e1 x e2``. Screen points are pixels from the image centre.

    References
    ----------
    Ye and Huang (survey), eq. (3)-(5), applied to the thesis's wall of PoIs.
    """
    e1 = np.asarray(e1, dtype=float)
    e2 = np.asarray(e2, dtype=float)
    if abs(np.linalg.norm(e1) - 1) > 1e-9 or abs(np.linalg.norm(e2) - 1) > 1e-9 or abs(e1 @ e2) > 1e-9:
        raise ValueError("e1 and e2 must be orthonormal")
    XY = wall_plane_coords(pois_m, origin_m, e1, e2)
    off = np.abs((np.asarray(pois_m, dtype=float) - origin_m) @ np.cross(e1, e2))
    if np.any(off > 1e-6):
        raise ValueError(f"pois_m are not on the plane (largest offset {off.max():.3g} m)")
    pose = homography_pose(homography_dlt(XY, img_px), f_px)
    Rpw = np.c_[e1, e2, np.cross(e1, e2)]
    return np.asarray(origin_m, dtype=float) + Rpw @ pose.c_plane_m
