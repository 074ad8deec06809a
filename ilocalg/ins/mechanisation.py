"""Strapdown mechanisation in a local-level east-north-up frame, attitude helpers and the phone -> body rotation.

Frames are defined once in the :mod:`ilocalg` package docstring: navigation frame ``n`` (ENU), INS
body frame ``b`` (x forward, y left, z up), phone sensor frame ``p`` (Android axes). Attitude is the
direction-cosine matrix ``mat_nb`` (body -> nav) with Z-Y-X Euler angles
``mat_nb = Rz(yaw) Ry(pitch) Rx(roll)``; yaw counts counter-clockwise from east. A phone log is
brought into the body frame with :data:`MAT_PHONE_TO_BODY` (:func:`phone_to_body`).

Earth rotation (7.3e-5 rad/s) and transport rate are neglected: over an indoor walk of a few
minutes at walking speed they are far below a phone gyroscope's noise and bias (> 1e-3 rad/s),
and gravity is taken constant (``G0_MPS2``, pointing down) over the site.

References
----------
Liao, Chiang, Zhou, Li (2016), "Using the on-line smoothing and constraint algorithms to improve
the accuracy of pedestrian indoor navigation", sec. 3.1 (the INS that eq. 1-6 correct).
Yeh & Huang, image/inertial positioning survey, eq. (6), citing Hartmann et al. (2010) (the same Z-Y-X DCM).
"""

from __future__ import annotations

import math

import numpy as np

from ilocalg.units import G0_MPS2

__all__ = [
    "GRAVITY_N_MPS2",
    "MAT_PHONE_TO_BODY",
    "phone_to_body",
    "skew",
    "rotvec_to_dcm",
    "rotvecs_to_dcm",
    "dcm_to_rotvec",
    "euler_to_dcm",
    "dcm_to_euler",
    "strapdown",
    "mechanise",
    "coarse_level",
]

#: Gravity vector in the ENU navigation frame, m/s^2.
GRAVITY_N_MPS2 = np.array([0.0, 0.0, -G0_MPS2])

#: Rotation from the phone (Android sensor) frame to the INS body frame, ``v_b = MAT_PHONE_TO_BODY @ v_p``,
#: for a phone held flat in front of the walker, screen up, its top pointing along the walk:
#: forward ``x_b = y_p`` (up the screen), left ``y_b = -x_p``, up ``z_b = z_p`` (out of the screen);
#: a rotation of -90 deg about z.
MAT_PHONE_TO_BODY = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def phone_to_body(vec_p) -> np.ndarray:
    """Vectors (3,) or (N, 3) from the phone frame to the INS body frame (:data:`MAT_PHONE_TO_BODY`).

    Use it on the accelerometer and gyroscope columns of an IMU log (package data type, phone frame)
    before :func:`mechanise` or :func:`ilocalg.ins.eskf.run_eskf`.
    """
    v = np.asarray(vec_p, dtype=float)
    if v.shape[-1:] != (3,) or v.ndim > 2:
        raise ValueError(f"vec_p must have shape (3,) or (N, 3), got {v.shape}")
    return v @ MAT_PHONE_TO_BODY.T


def skew(v) -> np.ndarray:
    """Skew-symmetric (cross-product) matrix ``[v x]`` of a 3-vector, shape (3, 3)."""
    x, y, z = float(v[0]), float(v[1]), float(v[2])
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def rotvec_to_dcm(rotvec_rad) -> np.ndarray:
    """Rotation matrix of one rotation vector (Rodrigues), shape (3, 3); see :func:`rotvecs_to_dcm`.

    The same operations in the same order as :func:`rotvecs_to_dcm` on one row (so the same bits), on scalars:
    the filter calls this at every update, where array set-up would cost more than the arithmetic.
    """
    v = np.asarray(rotvec_rad, dtype=float).reshape(3)
    x, y, z = float(v[0]), float(v[1]), float(v[2])
    th2 = x * x + y * y + z * z
    if th2 < 1e-16:
        a, b = 1.0 - th2 / 6.0, 0.5 - th2 / 24.0
    else:
        th = np.sqrt(np.float64(th2))
        a, b = float(np.sin(th) / th), float((1.0 - np.cos(th)) / th2)
    return np.array([[1.0 - b * (y * y + z * z), -a * z + b * x * y, a * y + b * x * z],
                     [a * z + b * x * y, 1.0 - b * (x * x + z * z), -a * x + b * y * z],
                     [-a * y + b * x * z, a * x + b * y * z, 1.0 - b * (x * x + y * y)]])


def rotvecs_to_dcm(rotvec_rad) -> np.ndarray:
    """Rotation matrices (N, 3, 3) of rotation vectors (N, 3) (Rodrigues' formula).

    ``exp([v x]) = I + a [v x] + b [v x]^2`` with ``a = sin(t) / t``, ``b = (1 - cos(t)) / t^2``,
    ``t = |v|`` (series below ``t^2 = 1e-16``). Agrees with
    :meth:`scipy.spatial.transform.Rotation.as_matrix` to rounding (tested).
    """
    v = np.asarray(rotvec_rad, dtype=float)
    x, y, z = v[:, 0], v[:, 1], v[:, 2]
    xx, yy, zz = x * x, y * y, z * z
    th2 = xx + yy + zz
    small = th2 < 1e-16
    if small.any():
        th = np.sqrt(np.where(small, 1.0, th2))
        a = np.where(small, 1.0 - th2 / 6.0, np.sin(th) / th)
        b = np.where(small, 0.5 - th2 / 24.0, (1.0 - np.cos(th)) / np.where(small, 1.0, th2))
    else:  # the same values without the selections (the filter's strapdown calls this on short stretches)
        th = np.sqrt(th2)
        a = np.sin(th) / th
        b = (1.0 - np.cos(th)) / th2
    # each product once; -a z + b x y is computed as (b x) y - a z, the same IEEE result
    bx = b * x
    bxy, bxz, byz = bx * y, bx * z, (b * y) * z
    ax, ay, az = a * x, a * y, a * z
    out = np.empty((v.shape[0], 3, 3))
    out[:, 0, 0] = 1.0 - b * (yy + zz)
    out[:, 0, 1] = bxy - az
    out[:, 0, 2] = ay + bxz
    out[:, 1, 0] = az + bxy
    out[:, 1, 1] = 1.0 - b * (xx + zz)
    out[:, 1, 2] = byz - ax
    out[:, 2, 0] = bxz - ay
    out[:, 2, 1] = ax + byz
    out[:, 2, 2] = 1.0 - b * (xx + yy)
    return out


def dcm_to_rotvec(mat) -> np.ndarray:
    """Rotation vector (rad) of one (3, 3) or many (N, 3, 3) rotation matrices (angles below pi): (3,) or (N, 3).

    ``theta = acos((trace - 1) / 2)`` and ``rotvec = theta / (2 sin theta) vee(M - M^T)``, with the series
    ``1/2 + theta^2 / 12`` below 1e-6 rad. Agrees with :meth:`scipy.spatial.transform.Rotation.as_rotvec`
    to rounding (tested); kept hand-written because the simulators' sensor data are built from it.
    """
    m = np.asarray(mat, dtype=float)
    if m.shape[-2:] != (3, 3) or m.ndim not in (2, 3):
        raise ValueError(f"mat must have shape (3, 3) or (N, 3, 3), got {m.shape}")
    mats = m.reshape(-1, 3, 3)
    c = np.clip((np.trace(mats, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    th = np.arccos(c)
    w = np.stack([mats[:, 2, 1] - mats[:, 1, 2], mats[:, 0, 2] - mats[:, 2, 0], mats[:, 1, 0] - mats[:, 0, 1]], 1)
    s = np.sin(th)
    scale = np.where(th < 1e-6, 0.5 + th**2 / 12.0, th / (2.0 * np.where(th < 1e-6, 1.0, s)))
    out = w * scale[:, None]
    return out[0] if m.ndim == 2 else out


def euler_to_dcm(roll_rad, pitch_rad, yaw_rad) -> np.ndarray:
    """``mat_nb = Rz(yaw) Ry(pitch) Rx(roll)``; scalars give (3, 3), arrays of shape (N,) give (N, 3, 3).

    References
    ----------
    Yeh & Huang, image/inertial positioning survey, sec. 5.2, eq. (6), citing Hartmann et al. (2010).
    """
    r, p, y = (np.asarray(a, dtype=float) for a in (roll_rad, pitch_rad, yaw_rad))
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    m = np.stack([
        np.stack([cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr], -1),
        np.stack([sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], -1),
        np.stack([-sp, cp * sr, cp * cr], -1),
    ], -2)
    return m


def dcm_to_euler(mat_nb) -> np.ndarray:
    """Z-Y-X Euler angles ``(roll, pitch, yaw)`` in rad of one (3, 3) or many (N, 3, 3) DCMs."""
    m = np.asarray(mat_nb, dtype=float)
    roll = np.arctan2(m[..., 2, 1], m[..., 2, 2])
    pitch = -np.arcsin(np.clip(m[..., 2, 0], -1.0, 1.0))
    yaw = np.arctan2(m[..., 1, 0], m[..., 0, 0])
    return np.stack([roll, pitch, yaw], -1)


def strapdown(pos0_n_m, vel0_n_mps, mat0_nb, gyr_b_radps, acc_b_mps2, dt_s, out=None):
    """Strapdown integration over L steps from mean rates: the one copy of the mechanisation equations.

    Step ``j`` uses the angular rate ``gyr[j]`` and specific force ``acc[j]`` held over ``dt[j]``:
    ``mat_nb(j+1) = mat_nb(j) exp([gyr[j] dt[j] x])``; the velocity increment is rotated with the mean
    of the two attitudes, ``vel(j+1) = vel(j) + dt/2 (mat(j) + mat(j+1)) acc[j] + g dt``; position
    integrates the mean velocity (trapezoid), which is exact for constant acceleration.

    Parameters
    ----------
    pos0_n_m, vel0_n_mps : (3,) ENU position (m) and velocity (m/s) at the start
    mat0_nb : (3, 3) body -> nav DCM at the start
    gyr_b_radps, acc_b_mps2 : (L, 3) angular rate (rad/s) and specific force (m/s^2), body frame
    dt_s : (L,) step lengths (s)

    out : optional ``(pos, vel, mat)`` C-contiguous arrays of those shapes to write into (the filter's histories)

    Returns
    -------
    pos_n_m (L+1, 3), vel_n_mps (L+1, 3), mat_nb (L+1, 3, 3): the start and the state after every step.

    References
    ----------
    Liao et al. (2016), sec. 3.1 (the INS that eq. 1-6 correct); Shin (2005), UCGE 20219, ch. 2.
    """
    dt = np.asarray(dt_s, dtype=float)
    L = dt.size
    pos, vel, mat = out if out is not None else (np.empty((L + 1, 3)), np.empty((L + 1, 3)), np.empty((L + 1, 3, 3)))
    dC = rotvecs_to_dcm(np.asarray(gyr_b_radps, dtype=float) * dt[:, None])
    mat[0] = mat0_nb
    # mat[j] @ dC[j], written in place; np.dot hands two 3x3 float64 matrices to the same cblas_dgemm call as
    # np.matmul (the same bits) without the gufunc set-up, but needs a C-contiguous output
    mm = np.dot if mat.flags.c_contiguous and mat.dtype == np.float64 else np.matmul
    for j in range(L):
        mm(mat[j], dC[j], out=mat[j + 1])
    half_dt = 0.5 * dt[:, None]
    dv = half_dt * np.einsum("lij,lj->li", mat[:-1] + mat[1:], acc_b_mps2)
    dv += GRAVITY_N_MPS2 * dt[:, None]
    # vel0 + [0, cumsum(dv)] and pos0 + [0, cumsum(dt/2 (vel_j + vel_j+1))], written in place
    np.add(vel0_n_mps, 0.0, out=vel[0])
    np.cumsum(dv, axis=0, out=vel[1:])
    np.add(vel0_n_mps, vel[1:], out=vel[1:])
    dp = vel[:-1] + vel[1:]
    dp *= half_dt
    np.add(pos0_n_m, 0.0, out=pos[0])
    np.cumsum(dp, axis=0, out=pos[1:])
    np.add(pos0_n_m, pos[1:], out=pos[1:])
    return pos, vel, mat


def _check_imu(t_s, gyr_b_radps, acc_b_mps2):
    t_s = np.asarray(t_s, dtype=float)
    gyr = np.asarray(gyr_b_radps, dtype=float)
    acc = np.asarray(acc_b_mps2, dtype=float)
    if t_s.ndim != 1 or t_s.size < 2:
        raise ValueError(f"t_s must be 1-D with at least 2 samples, got shape {t_s.shape}")
    if np.any(np.diff(t_s) <= 0):
        raise ValueError("t_s must be strictly increasing")
    for name, a in (("gyr_b_radps", gyr), ("acc_b_mps2", acc)):
        if a.shape != (t_s.size, 3):
            raise ValueError(f"{name} must have shape ({t_s.size}, 3), got {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} contains non-finite values")
    return t_s, gyr, acc


def mechanise(t_s, gyr_b_radps, acc_b_mps2, pos0_n_m, vel0_n_mps, mat0_nb):
    """Pure strapdown integration of an IMU log.

    Sample ``k`` holds the mean rate / specific force over ``[t_k, t_{k+1})`` (increments divided
    by the interval), so the increments of step ``k`` are ``gyr[k] * dt_k`` and ``acc[k] * dt_k``.

    Parameters
    ----------
    t_s : (N,) strictly increasing sample times, s
    gyr_b_radps, acc_b_mps2 : (N, 3) angular rate (rad/s) and specific force (m/s^2), body frame
    pos0_n_m, vel0_n_mps : (3,) initial ENU position and velocity at ``t_s[0]``
    mat0_nb : (3, 3) initial attitude

    Returns
    -------
    pos_n_m (N, 3), vel_n_mps (N, 3), mat_nb (N, 3, 3) at the sample times.
    """
    t_s, gyr, acc = _check_imu(t_s, gyr_b_radps, acc_b_mps2)
    return strapdown(pos0_n_m, vel0_n_mps, mat0_nb, gyr[:-1], acc[:-1], np.diff(t_s))


def coarse_level(acc_b_mps2) -> tuple[float, float]:
    """Roll and pitch (rad) of a static device from its mean specific force (N, 3) or (3,).

    ``f_b = mat_nb^T [0, 0, g]`` gives ``roll = atan2(f_y, f_z)``, ``pitch = atan2(-f_x, hypot(f_y, f_z))``.
    """
    f = np.asarray(acc_b_mps2, dtype=float)
    f = f.mean(axis=0) if f.ndim == 2 else f
    if f.shape != (3,) or not np.all(np.isfinite(f)) or np.linalg.norm(f) < 1.0:
        raise ValueError("acc_b_mps2 must be finite (3,) or (N, 3) specific force of a static device")
    return float(math.atan2(f[1], f[2])), float(math.atan2(-f[0], math.hypot(f[1], f[2])))
