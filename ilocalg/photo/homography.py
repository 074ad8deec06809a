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

__all__ = ["homography_dlt", "homography_dlt_batch", "HomographyPose", "homography_pose", "homography_pose_batch",
           "homography_locate", "wall_plane_coords"]


def _normalisers(x: np.ndarray) -> np.ndarray:
    """Hartley's normalising similarities (B, 3, 3) of point sets ``x`` (B, n, 2): centroid to the origin, mean
    distance sqrt(2)."""
    m = x.mean(axis=1)
    d = np.sqrt(np.sum((x - m[:, None, :]) ** 2, axis=2)).mean(axis=1)
    s = np.sqrt(2.0) / np.maximum(d, 1e-300)
    T = np.zeros((x.shape[0], 3, 3))
    T[:, 0, 0] = T[:, 1, 1] = s
    T[:, 0, 2] = -s * m[:, 0]
    T[:, 1, 2] = -s * m[:, 1]
    T[:, 2, 2] = 1.0
    return T


def _norms(x: np.ndarray) -> np.ndarray:
    """Euclidean (Frobenius) norm of each item of ``x`` (B, ...), each as ``np.linalg.norm`` computes it for one
    item (the dot product of its contiguous copy with itself: a sum over the batch axis would add in another
    order)."""
    flat = np.ascontiguousarray(x.reshape(x.shape[0], -1))
    return np.sqrt(np.array([v.dot(v) for v in flat]))


def _with_ones(x: np.ndarray) -> np.ndarray:
    return np.concatenate([x, np.ones(x.shape[:-1] + (1,))], axis=-1)


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
    return homography_dlt_batch(X, x[None])[0]


def homography_dlt_batch(plane_xy, img_px) -> np.ndarray:
    """:func:`homography_dlt` of a batch: ``H`` (B, 3, 3) for image points ``img_px`` (B, n, 2) of the target
    points ``plane_xy`` ((n, 2), shared, or (B, n, 2)). Each ``H`` has the bits of :func:`homography_dlt` on
    that item alone (every step is a per-item LAPACK call or an element-wise operation).

    References
    ----------
    Ye and Huang (survey), eq. (3)-(5); Hartley & Zisserman alg. 4.2.
    """
    x = np.asarray(img_px, dtype=float)
    if x.ndim != 3 or x.shape[2] != 2:
        raise ValueError(f"img_px must have shape (B, n, 2), got {x.shape}")
    X = np.broadcast_to(np.asarray(plane_xy, dtype=float), x.shape) if np.ndim(plane_xy) == 2 else \
        np.asarray(plane_xy, dtype=float)
    if X.shape != x.shape:
        raise ValueError(f"plane_xy must have shape (n, 2) or {x.shape}, got {np.shape(plane_xy)}")
    if X.shape[1] < 4:
        raise ValueError(f"a homography needs at least 4 points, got {X.shape[1]}")
    if not (np.isfinite(X).all() and np.isfinite(x).all()):
        raise ValueError("plane_xy and img_px must be finite")
    B, n = x.shape[:2]
    TX, Tx = _normalisers(X), _normalisers(x)
    Xh = _with_ones(X) @ TX.transpose(0, 2, 1)
    xh = _with_ones(x) @ Tx.transpose(0, 2, 1)
    # two rows per point: [0, -w X, v X] and [w X, 0, -u X], X = (X1, Y1, W1), (u, v, w) its image point
    u, v, w = xh[..., :1], xh[..., 1:2], xh[..., 2:]
    A = np.zeros((B, 2 * n, 9))
    A[:, 0::2, 3:6] = -w * Xh
    A[:, 0::2, 6:] = v * Xh
    A[:, 1::2, :3] = w * Xh
    A[:, 1::2, 6:] = -u * Xh
    _, s, Vt = np.linalg.svd(A)
    if s.shape[1] >= 8 and np.any(s[:, 7] < 1e-10 * s[:, 0]):
        raise ValueError("degenerate point configuration for a homography (collinear target points?)")
    Hn = Vt[:, -1].reshape(B, 3, 3)
    H = np.linalg.inv(Tx) @ Hn @ TX
    return H / _norms(H)[:, None, None]


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
    p = homography_pose_batch(H[None], f_px, cx_px, cy_px)
    return HomographyPose(R=p.R[0], t_m=p.t_m[0], c_plane_m=p.c_plane_m[0], distance_m=float(p.distance_m[0]))


def homography_pose_batch(H, f_px: float, cx_px: float = 0.0, cy_px: float = 0.0) -> HomographyPose:
    """:func:`homography_pose` of a batch ``H`` (B, 3, 3): a :class:`HomographyPose` whose fields have a leading
    batch axis (``R`` (B, 3, 3), ``t_m`` and ``c_plane_m`` (B, 3), ``distance_m`` (B,)), each item with the bits of
    :func:`homography_pose` on that ``H`` alone.

    References
    ----------
    Ye and Huang (survey), eq. (4) and Fig 8; Zhang (2000), sec. 2.2 and appendix C.
    """
    H = np.asarray(H, dtype=float)
    if H.ndim != 3 or H.shape[1:] != (3, 3) or not np.isfinite(H).all():
        raise ValueError(f"H must be finite 3x3 matrices (B, 3, 3), got shape {H.shape}")
    B = H.shape[0]
    M = np.linalg.solve(np.broadcast_to(intrinsics(f_px, cx_px, cy_px), (B, 3, 3)), H)
    lam = 2.0 / (_norms(M[:, :, 0]) + _norms(M[:, :, 1]))
    lam = np.where(M[:, 2, 2] * lam < 0, -lam, lam)
    r1, r2, t = lam[:, None] * M[:, :, 0], lam[:, None] * M[:, :, 1], lam[:, None] * M[:, :, 2]
    Q = np.empty((B, 3, 3))                                   # [r1 r2 r1 x r2] (np.cross's products, one call less)
    Q[:, :, 0], Q[:, :, 1] = r1, r2
    Q[:, 0, 2] = r1[:, 1] * r2[:, 2] - r1[:, 2] * r2[:, 1]
    Q[:, 1, 2] = r1[:, 2] * r2[:, 0] - r1[:, 0] * r2[:, 2]
    Q[:, 2, 2] = r1[:, 0] * r2[:, 1] - r1[:, 1] * r2[:, 0]
    U, _, Vt = np.linalg.svd(Q)
    D = np.zeros((B, 3, 3))
    D[:, 0, 0] = D[:, 1, 1] = 1.0
    D[:, 2, 2] = np.linalg.det(U @ Vt)
    R = U @ D @ Vt
    c = (-R.transpose(0, 2, 1) @ t[:, :, None])[:, :, 0]
    return HomographyPose(R=R, t_m=t, c_plane_m=c, distance_m=_norms(t))


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
