"""Heading offset and start position of a dead-reckoned track, estimated from position fixes.

A PDR track computed with a heading from the phone's compass lives in a frame rotated from the
floor-map frame (magnetic north is not the map's y axis; the phone's forward axis is not exactly
the walking direction) and it starts at an unknown point. Given the relative track
``p_k`` (starting at the origin) and position fixes ``z_j`` (Wi-Fi) at some of its states, the
rigid transform ``z ~ R(alpha) p + t`` is found by weighted least squares (2-D Procrustes without
scale, closed form), made robust to outlying fixes by iteratively reweighted least squares with
Huber weights. ``alpha`` is the heading offset to add to every step heading and ``t`` the start
position.

Beyond the papers (the i-Loc thesis sets the start by hand or by Wi-Fi, and its WDM heading is
taken as already in the map frame).

References
----------
Umeyama S., "Least-squares estimation of transformation parameters between two point patterns",
IEEE TPAMI 13(4), 1991 (the rotation + translation case); Huber P. J., Robust Statistics, 1981.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.units import wrap_angle_rad

__all__ = ["RigidFit", "fit_rigid_2d", "fit_translation_2d", "fit_track_to_fixes", "circular_mean_rad", "rotate_xy"]


@dataclass(frozen=True)
class RigidFit:
    """``dst ~ R(angle_rad) src + t_m``.

    Attributes
    ----------
    angle_rad : float
    t_m : ndarray (2,)
    weights : ndarray (n,)
        Final robust weights of the pairs (1 = fully used).
    rms_m : float
        Weighted RMS residual, metres.
    n_iter : int
    """

    angle_rad: float
    t_m: np.ndarray
    weights: np.ndarray
    rms_m: float
    n_iter: int


def rotate_xy(xy_m, angle_rad) -> np.ndarray:
    """Rotate points (..., 2) counter-clockwise by ``angle_rad`` about the origin."""
    xy = np.asarray(xy_m, dtype=np.float64)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.stack([c * xy[..., 0] - s * xy[..., 1], s * xy[..., 0] + c * xy[..., 1]], axis=-1)


def _check_pairs(src, dst, w):
    src = np.asarray(src, dtype=np.float64)
    dst = np.asarray(dst, dtype=np.float64)
    if src.ndim != 2 or src.shape[1] != 2 or src.shape != dst.shape:
        raise ValueError(f"src_xy_m and dst_xy_m must both have shape (n, 2), got {src.shape} and {dst.shape}")
    if src.shape[0] < 2:
        raise ValueError(f"need at least 2 point pairs, got {src.shape[0]}")
    if not (np.isfinite(src).all() and np.isfinite(dst).all()):
        raise ValueError("src_xy_m and dst_xy_m must be finite")
    w = np.ones(src.shape[0]) if w is None else np.asarray(w, dtype=np.float64)
    if w.shape != (src.shape[0],) or not np.isfinite(w).all() or (w < 0).any() or w.sum() <= 0:
        raise ValueError(f"weights must be finite, >= 0, shape ({src.shape[0]},) with a positive sum")
    return src, dst, w


def fit_rigid_2d(src_xy_m, dst_xy_m, weights=None) -> tuple[float, np.ndarray]:
    """Weighted least-squares rotation + translation mapping ``src`` onto ``dst`` (closed form).

    Parameters
    ----------
    src_xy_m, dst_xy_m : array_like, shape (n >= 2, 2)
    weights : array_like, shape (n,), optional

    Returns
    -------
    angle_rad : float
        In [-pi, pi).
    t_m : ndarray (2,)

    References
    ----------
    Umeyama (1991), rotation + translation.
    """
    src, dst, w = _check_pairs(src_xy_m, dst_xy_m, weights)
    w = w / w.sum()
    ms, md = w @ src, w @ dst
    a, b = src - ms, dst - md
    # maximise sum w (a . R^T b): angle of the weighted cross-covariance
    sxx = np.sum(w * (a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]))
    sxy = np.sum(w * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
    ang = float(np.arctan2(sxy, sxx))
    return float(wrap_angle_rad(ang)), md - rotate_xy(ms, ang)


def fit_translation_2d(src_xy_m, dst_xy_m, weights=None) -> np.ndarray:
    """Weighted least-squares translation mapping ``src`` onto ``dst`` (rotation held at 0).

    Parameters
    ----------
    src_xy_m, dst_xy_m : array_like, shape (n >= 2, 2)
    weights : array_like, shape (n,), optional

    Returns
    -------
    t_m : ndarray (2,)
        The weighted mean of ``dst - src``.
    """
    src, dst, w = _check_pairs(src_xy_m, dst_xy_m, weights)
    return (w / w.sum()) @ (dst - src)


def fit_track_to_fixes(track_xy_m, fix_xy_m, huber_m: float | None = 5.0, n_iter: int = 20,
                       weights=None, rotation: bool = True) -> RigidFit:
    """Robust rigid fit of a relative track (at the fix states) to the fixes (IRLS, Huber weights).

    Parameters
    ----------
    track_xy_m : array_like, shape (n, 2)
        Dead-reckoned positions (from the origin) at the states that carry the fixes.
    fix_xy_m : array_like, shape (n, 2)
        The fixes, map frame, metres.
    huber_m : float or None
        Huber threshold on the residual distance (metres); ``None``: plain least squares.
    n_iter : int
        Maximum number of reweighting iterations.
    weights : array_like, shape (n,), optional
        Prior weights (e.g. inverse fix variances), multiplied by the robust weights.
    rotation : bool
        Fit the rotation too (:func:`fit_rigid_2d`); ``False``: the translation only
        (:func:`fit_translation_2d`, heading held fixed, ``angle_rad`` 0).

    Returns
    -------
    RigidFit

    References
    ----------
    Umeyama (1991), rotation + translation; Huber (1981), the robust weights.
    """
    src, dst, w0 = _check_pairs(track_xy_m, fix_xy_m, weights)
    if huber_m is not None and not huber_m > 0:
        raise ValueError(f"huber_m must be > 0 or None, got {huber_m!r}")

    def fit(w):
        return fit_rigid_2d(src, dst, w) if rotation else (0.0, fit_translation_2d(src, dst, w))

    rw = np.ones(src.shape[0])
    ang, t = fit(w0)
    it = 0
    if huber_m is not None:
        while it < n_iter:
            it += 1
            r = np.hypot(*(rotate_xy(src, ang) + t - dst).T)
            new = np.where(r <= huber_m, 1.0, huber_m / np.maximum(r, 1e-12))
            ang, t = fit(w0 * new)
            if np.allclose(new, rw, atol=1e-6):
                rw = new
                break
            rw = new
    r = np.hypot(*(rotate_xy(src, ang) + t - dst).T)
    ww = w0 * rw
    return RigidFit(ang, t, rw, float(np.sqrt(np.sum(ww * r**2) / ww.sum())), it)


def circular_mean_rad(angles_rad, weights=None) -> float:
    """Weighted circular mean of angles, rad in [-pi, pi)."""
    a = np.asarray(angles_rad, dtype=np.float64).ravel()
    if a.size == 0 or not np.isfinite(a).all():
        raise ValueError("angles_rad must be a non-empty finite array")
    w = np.ones(a.size) if weights is None else np.asarray(weights, dtype=np.float64).ravel()
    if w.shape != a.shape or (w < 0).any() or w.sum() <= 0:
        raise ValueError("weights must be >= 0 with a positive sum, one per angle")
    return float(wrap_angle_rad(np.arctan2(w @ np.sin(a), w @ np.cos(a))))
