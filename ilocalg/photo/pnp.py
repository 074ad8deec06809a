"""OpenCV's solvePnP (SQPnP) as a modern reference for photo positioning.

Unlike ST, PnP does not need the phone's orientation sensors: it estimates the rotation and the
centre together from the PoI correspondences. It needs at least 4 PoIs here (SQPnP accepts 3 but
then has up to four solutions) that are not collinear (collinear PoIs leave the rotation about
their line free).

References
----------
G. Terzakis and M. Lourakis, "A Consistently Fast and Globally Optimal Solution to the
Perspective-n-Point Problem", ECCV 2020 (SQPnP), as implemented by ``cv2.solvePnP`` with
``cv2.SOLVEPNP_SQPNP``. Beyond the i-Loc thesis (which assumes a known orientation, eq. (30)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.photo.camera import intrinsics, validate_points
from ilocalg.photo.homography import HomographyPose

__all__ = ["PnPResult", "pnp_solve", "pnp_solve_batch", "square_marker_pose"]


@dataclass(frozen=True)
class PnPResult:
    """Camera centre ``c_m`` (3,) and ``T`` (3, 3) = ``T_E->AR`` estimated by SQPnP."""

    c_m: np.ndarray
    T: np.ndarray


def pnp_solve(pois_m, img_px, f_px: float) -> PnPResult:
    """Camera pose from >= 4 PoIs by ``cv2.solvePnP(..., flags=cv2.SOLVEPNP_SQPNP)``.

    Parameters
    ----------
    pois_m : array (n, 3)
        PoI world positions, metres, ``n >= 4``.
    img_px : array (n, 2)
        Screen points, pixels from the image centre (the principal point is at 0, 0).
    f_px : float
        Focal length, pixels.

    Raises
    ------
    ValueError
        Fewer than 4 PoIs, collinear PoIs, or OpenCV reports failure.
    """
    import cv2  # imported here so that `import ilocalg` stays light

    P, U = validate_points(pois_m, img_px, f_px, min_points=4)
    s = np.linalg.svd(P - P.mean(axis=0), compute_uv=False)
    if s[1] < 1e-9 * max(s[0], 1e-300):
        raise ValueError("pois_m are collinear: PnP cannot determine the rotation about their line")
    K = intrinsics(f_px)
    ok, rvec, tvec = cv2.solvePnP(np.ascontiguousarray(P).reshape(-1, 1, 3), np.ascontiguousarray(U).reshape(-1, 1, 2),
                                  K, None, flags=cv2.SOLVEPNP_SQPNP)
    if not ok:
        raise ValueError("cv2.solvePnP (SQPnP) failed")
    R, _ = cv2.Rodrigues(rvec)
    t = np.asarray(tvec, dtype=float).reshape(3)
    return PnPResult(c_m=-R.T @ t, T=R)


def pnp_solve_batch(pois_m, img_px, f_px: float) -> np.ndarray:
    """Centres (B, 3) of :func:`pnp_solve` over a batch ``img_px`` (B, n, 2); ``pois_m`` (n, 3) or (B, n, 3)."""
    U = np.asarray(img_px, dtype=float)
    P = np.broadcast_to(np.asarray(pois_m, dtype=float), U.shape[:2] + (3,))
    return np.stack([pnp_solve(P[b], U[b], f_px).c_m for b in range(U.shape[0])])


def square_marker_pose(img_px, side_m: float, f_px: float) -> HomographyPose:
    """Pose of a square planar marker from its four corners by OpenCV's IPPE (``SOLVEPNP_IPPE_SQUARE``).

    A modern reference for :func:`ilocalg.photo.homography_pose` on the same corners.

    Parameters
    ----------
    img_px : array (4, 2)
        Screen points (pixels from the image centre) of the corners at plane coordinates
        ``(-s, -s), (s, -s), (s, s), (-s, s)`` with ``s = side_m / 2`` (the order used by
        :func:`ilocalg.experiments.photo_positioning.marker_ranging`).
    side_m : float
        Marker side, metres.
    f_px : float
        Focal length, pixels.

    Returns
    -------
    HomographyPose
        Same frames as :func:`ilocalg.photo.homography_pose`.

    References
    ----------
    T. Collins and A. Bartoli, "Infinitesimal Plane-Based Pose Estimation", IJCV 109, 2014 (IPPE).
    """
    import cv2  # imported here so that `import ilocalg` stays light

    U = np.asarray(img_px, dtype=float)
    if U.shape != (4, 2) or not np.isfinite(U).all():
        raise ValueError(f"img_px must be 4 finite corners of shape (4, 2), got {U.shape}")
    if not np.isfinite(side_m) or side_m <= 0:
        raise ValueError(f"side_m must be positive, got {side_m!r}")
    h = side_m / 2.0
    # IPPE_SQUARE's corner order: (-h, h), (h, h), (h, -h), (-h, -h)
    obj = np.array([[-h, h, 0.0], [h, h, 0.0], [h, -h, 0.0], [-h, -h, 0.0]])
    img = np.ascontiguousarray(U[[3, 2, 1, 0]])
    ok, rvec, tvec = cv2.solvePnP(obj, img, intrinsics(f_px), None, flags=cv2.SOLVEPNP_IPPE_SQUARE)
    if not ok:
        raise ValueError("cv2.solvePnP (IPPE_SQUARE) failed")
    R, _ = cv2.Rodrigues(rvec)
    t = np.asarray(tvec, dtype=float).reshape(3)
    return HomographyPose(R=R, t_m=t, c_plane_m=-R.T @ t, distance_m=float(np.linalg.norm(t)))
