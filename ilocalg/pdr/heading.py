"""WDM, the i-Loc walking direction module (accelerometer + magnetometer), and gyro-integrated heading.

Frames: the phone (sensor) frame of Android (x right, y up the screen, z out of the screen); the
thesis's earth frame is north-east-down. ``T_S->E`` rotates sensor coordinates to earth
coordinates; its rows are the north, east and down axes written in the sensor frame.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.3, eq. (18)-(19), Fig 16.
"""

from __future__ import annotations

import numpy as np

from ilocalg.pdr.signals import acc_from_log, gravity_lowpass_mps2, moving_mean
from ilocalg.units import wrap_angle_rad, yaw_to_theta

__all__ = [
    "wdm_rotation",
    "wdm_yaw_rad",
    "axis_yaw_rad",
    "heading_theta_rad",
    "gyr_heading_theta_rad",
    "log_headings_rad",
    "WDM",
]


def _vec3(name: str, x) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64)
    if a.shape[-1:] != (3,) or a.ndim not in (1, 2):
        raise ValueError(f"{name} must have shape (3,) or (n, 3), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or inf")
    return a


def _unit(name: str, v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    if np.any(n < 1e-12):
        raise ValueError(f"{name} is degenerate (zero vector: the magnetic field is parallel to gravity "
                         "or a reading is zero)")
    return v / n


def wdm_rotation(g_mps2, m_ut) -> np.ndarray:
    """``T_S->E`` from gravity and magnetic field in the sensor frame.

    Columns ``g x (m x g)``, ``m x g``, ``-g`` (normalised) form ``T^-1``; ``T`` is its transpose.

    Parameters
    ----------
    g_mps2 : array_like, shape (3,) or (n, 3)
        Accelerometer reading at rest (points up, away from the Earth), m/s^2.
    m_ut : array_like, shape (3,) or (n, 3)
        Magnetic field, microtesla.

    Returns
    -------
    ndarray, shape (3, 3) or (n, 3, 3)
        Rows: north, east, down axes in sensor coordinates.

    References
    ----------
    Chiu (2013), sec. 4.3 (the matrix before eq. (18)).
    """
    g = _vec3("g_mps2", g_mps2)
    m = _vec3("m_ut", m_ut)
    g, m = np.broadcast_arrays(g, m)
    mxg = np.cross(m, g)
    east = _unit("m x g", mxg)
    north = _unit("g x (m x g)", np.cross(g, mxg))
    down = -_unit("g", g)
    return np.stack([north, east, down], axis=-2)


def axis_yaw_rad(T, axis=(1.0, 0.0, 0.0)):
    """Yaw (from north, clockwise) of a phone axis given ``T_S->E``.

    With ``axis = x`` this is eq. (19): ``psi = atan2(T[2,1], T[1,1])`` (1-based).
    """
    T = np.asarray(T, dtype=np.float64)
    ax = np.asarray(axis, dtype=np.float64)
    v = T @ ax
    return np.arctan2(v[..., 1], v[..., 0])


def wdm_yaw_rad(g_mps2, m_ut):
    """Eq. (19): yaw of the phone's x axis, ``psi = atan2(T[2,1], T[1,1])``, rad (north = 0, clockwise).

    References
    ----------
    Chiu (2013), eq. (18)-(19).
    """
    return axis_yaw_rad(wdm_rotation(g_mps2, m_ut), (1.0, 0.0, 0.0))


def heading_theta_rad(g_mps2, m_ut, forward_axis=(0.0, 1.0, 0.0), declination_rad: float = 0.0,
                      hard_iron_ut=None):
    """Walking heading in the map convention (from east, counter-clockwise), rad.

    The yaw of ``forward_axis`` (default the phone's y axis, up the screen: a phone held in front
    while walking) from :func:`wdm_rotation`, plus the magnetic declination, converted with
    :func:`ilocalg.units.yaw_to_theta`. The thesis's eq. (19) is the yaw of the x axis; the two
    differ by the fixed handheld angle between the axes. The thesis applies neither a declination
    nor a hard-iron correction (eq. 18-19: magnetic north, raw field).

    Parameters
    ----------
    declination_rad : float
        Magnetic declination of the site (east positive), added to the magnetic yaw.
    hard_iron_ut : array_like (3,), optional
        A known hard-iron offset in the sensor frame, microtesla, subtracted from ``m_ut``.
    """
    if hard_iron_ut is not None:
        m_ut = _vec3("m_ut", m_ut) - _vec3("hard_iron_ut", hard_iron_ut)
    psi = axis_yaw_rad(wdm_rotation(g_mps2, m_ut), forward_axis) + declination_rad
    return yaw_to_theta(psi)


def gyr_heading_theta_rad(gyr_radps, g_mps2, t_s, theta0_rad: float = 0.0):
    """Heading by integrating the angular rate about the vertical (beyond the paper).

    ``theta_k = theta0 + sum_{j<k} (w_j . u_j) dt_j`` with ``u = g / |g|`` (up), trapezoid-free
    rectangle rule; counter-clockwise positive, so it matches the map heading convention.

    Parameters
    ----------
    gyr_radps : array_like, shape (n, 3)
    g_mps2 : array_like, shape (3,) or (n, 3)
        Gravity direction (accelerometer low-pass), sensor frame.
    t_s : array_like, shape (n,)
    """
    w = _vec3("gyr_radps", gyr_radps)
    u = _unit("g_mps2", _vec3("g_mps2", g_mps2))
    t = np.asarray(t_s, dtype=np.float64)
    if w.ndim != 2 or t.shape != (w.shape[0],):
        raise ValueError(f"t_s must have one time per gyro sample ({w.shape[0]}), got shape {t.shape}")
    if np.any(np.diff(t) <= 0):
        raise ValueError("t_s must be strictly increasing")
    rate = (w * u).sum(axis=-1) if u.ndim == 2 else w @ u
    dt = np.diff(t, prepend=t[0])
    return wrap_angle_rad(theta0_rad + np.cumsum(rate * dt))


def log_headings_rad(imu, rest_s: float, g_window_s: float = 1.0, m_window_s: float = 0.5) -> dict[str, np.ndarray]:
    """Per-sample WDM and gyro-integrated headings of a sensor log (rad, map convention).

    Gravity is the moving mean of the accelerometer over ``g_window_s`` and the magnetic field the
    moving mean of the magnetometer over ``m_window_s``; WDM is :func:`heading_theta_rad` of the two.
    The gyro heading (:func:`gyr_heading_theta_rad`) starts from the circular mean of the WDM
    heading over the first ``rest_s`` seconds (the phone held still); the gyro bias is not estimated
    (over one second of hand jitter its estimate is worse than the bias itself).

    Parameters
    ----------
    imu : DataFrame
        Sensor log indexed by time, s, with the accelerometer, gyroscope and magnetometer columns
        of :mod:`ilocalg.io.schema`.
    rest_s : float
        Duration at rest at the start of the log, s (0: start from the first WDM heading).
    g_window_s, m_window_s : float
        Moving-mean windows, s.

    Returns
    -------
    dict
        ``"WDM"`` and ``"gyro"``: arrays of shape (n,).

    References
    ----------
    Chiu (2013), sec. 4.3, eq. (18)-(19).
    """
    from ilocalg.io.schema import GYR_COLS, MAG_COLS

    acc, t = acc_from_log(imu)
    rate = 1.0 / np.median(np.diff(t))
    mag = imu[list(MAG_COLS)].to_numpy()
    gyr = imu[list(GYR_COLS)].to_numpy()
    ng, nm = int(round(0.5 * g_window_s * rate)), int(round(0.5 * m_window_s * rate))
    g = gravity_lowpass_mps2(acc, ng)
    m = np.column_stack([moving_mean(mag[:, j], nm) for j in range(3)])
    wdm = heading_theta_rad(g, m)
    rest = t < rest_s
    th0 = float(np.angle(np.mean(np.exp(1j * wdm[rest])))) if rest.any() else float(wdm[0])
    return {"WDM": wdm, "gyro": gyr_heading_theta_rad(gyr, g, t, th0)}


class WDM:
    """Thin wrapper: per-step heading from gravity and magnetic field (see :func:`heading_theta_rad`)."""

    def __init__(self, forward_axis=(0.0, 1.0, 0.0), declination_rad: float = 0.0):
        self.forward_axis = forward_axis
        self.declination_rad = declination_rad

    def heading(self, g_mps2, m_ut):
        return heading_theta_rad(g_mps2, m_ut, self.forward_axis, self.declination_rad)
