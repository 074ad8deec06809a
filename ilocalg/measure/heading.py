"""Phone heading against the walking direction between surveyed waypoints (ILC walks).

For each waypoint-to-waypoint segment (straight walking assumed, as the ILC survey protocol does)
the walking direction is ``atan2(dy, dx)`` in the floor-map frame. The phone's heading is the yaw of
its y axis (up the screen: phone held flat in front) from the rotation vector (Android
``TYPE_ROTATION_VECTOR``, a fused gyro/accelerometer/magnetometer attitude, east-north-up) and from
the WDM (gravity + raw magnetometer, :func:`ilocalg.pdr.heading.heading_theta_rad`), both as
theta (from the map x axis, counter-clockwise), averaged circularly over the segment.

The floor map is not aligned with magnetic north, so ``heading - direction`` carries a constant
rotation per floor (map rotation plus declination): :func:`misalignment` removes the floor's
circular median and returns what is left (the misalignment of the phone with the walking direction
plus the heading error). Magnetic disturbance is the spread of the field magnitude about the floor's
median.

References
----------
Chiu (2013), eq. (18)-(19) (WDM heading).
Android SensorManager.getRotationMatrixFromVector (rotation vector -> rotation matrix).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.pdr.heading import heading_theta_rad

__all__ = ["rotvec_theta_rad", "segment_headings", "misalignment", "wrap_rad", "circ_mean_rad"]


def wrap_rad(a):
    """Wrap angles to (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(a, dtype=np.float64)))


def circ_mean_rad(a) -> float:
    return float(np.angle(np.mean(np.exp(1j * np.asarray(a, dtype=np.float64)))))


def rotvec_theta_rad(rv) -> np.ndarray:
    """Theta (from east, counter-clockwise) of the phone's y axis from rotation-vector rows (x, y, z)."""
    q = np.asarray(rv, dtype=np.float64)
    x, y, z = q[:, 0], q[:, 1], q[:, 2]
    w = np.sqrt(np.clip(1.0 - x * x - y * y - z * z, 0.0, None))
    # world (E, N) components of the device y axis: second column of R(q)
    e = 2.0 * (x * y - z * w)
    n = 1.0 - 2.0 * (x * x + z * z)
    return np.arctan2(n, e)


def segment_headings(imu: pd.DataFrame, rotvec: pd.DataFrame, waypoints: pd.DataFrame,
                     min_dist_m: float = 2.0, g_window_s: float = 1.0) -> pd.DataFrame:
    """Per segment: ``dir_rad`` (walking direction), ``rv_rad`` and ``wdm_rad`` (mean phone headings),
    ``dist_m``, ``dt_s``, ``mag_norm_ut`` (mean field magnitude). ``rotvec`` may be None (``rv_rad`` NaN)."""
    t = imu.index.to_numpy(dtype=np.float64)
    acc = imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
    mag = imu[["mag_x_ut", "mag_y_ut", "mag_z_ut"]].to_numpy()
    k = max(int(round(g_window_s / np.median(np.diff(t)))), 1)
    g = pd.DataFrame(acc).rolling(k, center=True, min_periods=1).mean().to_numpy()
    wdm = heading_theta_rad(g, mag)
    if rotvec is not None and len(rotvec):
        trv = rotvec.index.to_numpy(dtype=np.float64)
        rvt = rotvec_theta_rad(rotvec.to_numpy())
    else:  # no rotation vector (simulated logs): the WDM heading only
        trv, rvt = t, np.full(t.size, np.nan)
    wt = waypoints["t_s"].to_numpy()
    wxy = waypoints[["x_m", "y_m"]].to_numpy()
    rows = []
    for i in range(len(wt) - 1):
        d = wxy[i + 1] - wxy[i]
        dist = float(np.hypot(*d))
        if dist < min_dist_m:
            continue
        s = (t >= wt[i]) & (t < wt[i + 1])
        sr = (trv >= wt[i]) & (trv < wt[i + 1])
        if s.sum() < 10 or sr.sum() < 10:
            continue
        rows.append({"dir_rad": float(np.arctan2(d[1], d[0])),
                     "rv_rad": circ_mean_rad(rvt[sr]) if np.isfinite(rvt[sr]).all() else np.nan,
                     "wdm_rad": circ_mean_rad(wdm[s]), "dist_m": dist, "dt_s": float(wt[i + 1] - wt[i]),
                     "mag_norm_ut": float(np.linalg.norm(mag[s], axis=1).mean())})
    return pd.DataFrame(rows, columns=["dir_rad", "rv_rad", "wdm_rad", "dist_m", "dt_s", "mag_norm_ut"])


def misalignment(heading_rad, dir_rad, floor) -> np.ndarray:
    """``heading - direction`` with each floor's circular median removed, wrapped, rad."""
    d = wrap_rad(np.asarray(heading_rad) - np.asarray(dir_rad))
    fl = np.asarray(floor)
    out = np.empty_like(d)
    for f in np.unique(fl):
        s = fl == f
        # circular median: the sample minimising the summed absolute wrapped distance
        cand = d[s]
        cost = np.abs(wrap_rad(cand[:, None] - cand[None, :])).sum(axis=1)
        out[s] = wrap_rad(cand - cand[np.argmin(cost)])
    return out
