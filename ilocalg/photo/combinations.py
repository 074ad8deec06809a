"""Every positioning method on a batch of photos of one PoI combination (i-Loc thesis sec. 6.3, Figs 29-32).

:func:`locate_methods` runs ST with the measured and the true orientation, VA from each initial guess
given and, for combinations of at least four PoIs, OpenCV's SQPnP and a wall homography (only where all
the PoIs lie on the end wall ``y = 0``). :func:`horizontal_error_cm` scores a centre on the floor map.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU. Sec. 6.3.
Ye, C.-H. and Huang, W.-L. Positioning by combining images and inertial sensors (a survey), eq. (3)-(5).
"""

from __future__ import annotations

import numpy as np

from ilocalg.photo.homography import homography_dlt_batch, homography_pose_batch
from ilocalg.photo.pnp import pnp_solve_batch
from ilocalg.photo.similar_triangles import st_solve_batch
from ilocalg.photo.view_angle import measured_view_angles_rad, va_solve_batch

__all__ = ["combo_label", "horizontal_error_cm", "wall_homography_batch", "on_end_wall", "locate_methods"]


def combo_label(combo) -> str:
    """``(0, 2)`` -> ``"{1,3}"`` (1-based PoI numbers, as in the thesis)."""
    return "{" + ",".join(str(i + 1) for i in combo) + "}"


def horizontal_error_cm(c_est, c_true) -> np.ndarray:
    """Horizontal (floor-map) distance between centres (..., 3), cm."""
    return 100.0 * np.hypot(c_est[..., 0] - c_true[..., 0], c_est[..., 1] - c_true[..., 1])


def wall_homography_batch(pois_m, img_px, f_px) -> np.ndarray:
    """World centres (B, 3) by the homography from PoIs (B, n, 3) on the wall y = 0 (plane axes x and z)."""
    XY = pois_m[..., [0, 2]]
    cp = homography_pose_batch(homography_dlt_batch(XY, img_px), f_px).c_plane_m
    # plane frame (e1 = x, e2 = z, e3 = e1 x e2 = -y) -> world
    return np.stack([cp[:, 0], -cp[:, 2], cp[:, 1]], axis=1)


def on_end_wall(P) -> np.ndarray:
    """(B,) True where every PoI of a combination (B, n, 3) lies on the end wall y = 0 (the homography's plane)."""
    return np.all(np.abs(P[..., 1]) < 1e-9, axis=-1)


def locate_methods(P, U, f_px: float, T_meas, T_true, c0_m: dict, va_max_iter: int, va_free_z: bool = False,
                   others: bool = True):
    """Every method on photos of PoIs ``P`` (B, k, 3) seen at screen points ``U`` (B, k, 2).

    Parameters
    ----------
    T_meas, T_true : (B, 3, 3)
        Sensor-measured and true orientation ``T_E->AR`` (ST uses each).
    c0_m : dict
        VA's initial guesses by method name, each (B, 3).
    others : bool
        False: ST with the measured orientation and VA only (no ST with the true orientation, SQPnP or homography).

    Returns
    -------
    (estimates, st, convergence)
        ``estimates``: method name -> centres (B, 3) (NaN where a homography has no planar PoIs); ``st``: the
        ST result with the measured orientation (``rank``, ``cond``); ``convergence``: one dict per VA method
        (``method``, ``converged_share``, ``mean_iterations``).

    Raises
    ------
    ValueError
        The ST system is rank deficient (a degenerate layout).
    """
    est = {}
    st = st_solve_batch(P, U, f_px, T_meas)
    if np.any(st["rank"] < 3):
        raise ValueError("ST system rank deficient in the simulated set-up; the layout is degenerate")
    est["ST"] = st["c_m"]
    if others:
        est["ST_true_orientation"] = st_solve_batch(P, U, f_px, T_true)["c_m"]
    ang = measured_view_angles_rad(U, f_px)
    conv = []
    if c0_m:
        # every start in one batch (the photos' descents are independent: the same result as one batch per start)
        names, B = list(c0_m), P.shape[0]
        va = va_solve_batch(np.concatenate([P] * len(names)), np.concatenate([ang] * len(names)),
                            np.concatenate([c0_m[n] for n in names]), max_iter=va_max_iter, free_z=va_free_z,
                            step_tol_m=1e-6)
        for i, name in enumerate(names):
            part = slice(i * B, (i + 1) * B)
            est[name] = va["c_m"][part]
            conv.append({"method": name, "converged_share": float(va["converged"][part].mean()),
                         "mean_iterations": float(va["n_iter"][part].mean())})
    if others and P.shape[1] >= 4:
        est["PnP_SQPnP"] = pnp_solve_batch(P, U, f_px)
        hom = np.full((P.shape[0], 3), np.nan)
        planar = on_end_wall(P)
        if planar.any():
            hom[planar] = wall_homography_batch(P[planar], U[planar], f_px)
        est["homography"] = hom
    return est, st, conv
