"""GNSS helpers on latitude/longitude: haversine distance and great-circle dead reckoning.

Latitudes and longitudes are degrees (east positive), bearings are degrees from north, clockwise
(compass yaw), distances metres on a sphere of radius :data:`EARTH_RADIUS_M`.

Great-circle dead reckoning (PSO thesis eq. 3.1-3.3, after Williams' Aviation Formulary): from
``(phi1, lam1)`` along bearing ``theta`` for the angular distance ``d = dist / R``::

    phi2 = asin(sin phi1 cos d + cos phi1 sin d cos theta)                   (3.1)
    dlam = atan2(sin theta sin d cos phi1, cos d - sin phi1 sin phi2)        (3.2)
    lam2 = mod(lam1 + dlam + pi, 2 pi) - pi                                  (3.3)

The thesis (like the Formulary) writes ``lam1 - dlam`` because the Formulary counts longitude
positive to the WEST; with east-positive longitudes the sign is ``+``.

References
----------
趙士賢, "Pedestrian navigation based on particle swarm optimization", M.S. thesis, Tunghai
University, 2008 (the PSO thesis), eq. 3.1-3.3 and ref. [25]; E. Williams, "Aviation Formulary".
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

__all__ = [
    "EARTH_RADIUS_M",
    "haversine_m",
    "destination",
    "dead_reckon_latlon",
    "path_length_m",
    "latlon_to_local_m",
    "local_to_latlon",
    "gps_track_length_m",
]

#: Mean Earth radius (IUGG), m.
EARTH_RADIUS_M = 6_371_008.8


def _finite(name, x):
    x = np.asarray(x, dtype=float)
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite")
    return x


def _check_lat(name, lat):
    lat = _finite(name, lat)
    if np.any(np.abs(lat) > 90):
        raise ValueError(f"{name} must be within [-90, 90] degrees")
    return lat


def haversine_m(lat1_deg, lon1_deg, lat2_deg, lon2_deg, radius_m: float = EARTH_RADIUS_M):
    """Great-circle distance by the haversine formula.

    Parameters
    ----------
    lat1_deg, lon1_deg, lat2_deg, lon2_deg : array_like
        Points (degrees, broadcastable).
    radius_m : float
        Sphere radius.

    Returns
    -------
    ndarray or float
        Distance, m.

    References
    ----------
    R. W. Sinnott, "Virtues of the haversine", Sky and Telescope 68(2), 1984; PSO thesis ref. [25].
    """
    p1 = np.deg2rad(_check_lat("lat1_deg", lat1_deg))
    p2 = np.deg2rad(_check_lat("lat2_deg", lat2_deg))
    dl = np.deg2rad(_finite("lon2_deg", lon2_deg) - _finite("lon1_deg", lon1_deg))
    h = np.sin((p2 - p1) / 2) ** 2 + np.cos(p1) * np.cos(p2) * np.sin(dl / 2) ** 2
    return 2.0 * radius_m * np.arcsin(np.sqrt(np.clip(h, 0.0, 1.0)))


def destination(lat_deg, lon_deg, bearing_deg, dist_m, radius_m: float = EARTH_RADIUS_M):
    """Point reached along a great circle (eq. 3.1-3.3).

    Parameters
    ----------
    lat_deg, lon_deg : array_like
        Start (degrees, east-positive longitude).
    bearing_deg : array_like
        Initial bearing, degrees from north clockwise.
    dist_m : array_like
        Distance travelled, m (>= 0).

    Returns
    -------
    lat2_deg, lon2_deg : ndarray
        End point; longitude wrapped to [-180, 180).

    References
    ----------
    PSO thesis, eq. 3.1-3.3.
    """
    p1 = np.deg2rad(_check_lat("lat_deg", lat_deg))
    l1 = np.deg2rad(_finite("lon_deg", lon_deg))
    th = np.deg2rad(_finite("bearing_deg", bearing_deg))
    dist = _finite("dist_m", dist_m)
    if np.any(dist < 0):
        raise ValueError("dist_m must be >= 0")
    d = dist / radius_m
    p2 = np.arcsin(np.clip(np.sin(p1) * np.cos(d) + np.cos(p1) * np.sin(d) * np.cos(th), -1, 1))  # eq. 3.1
    dl = np.arctan2(np.sin(th) * np.sin(d) * np.cos(p1), np.cos(d) - np.sin(p1) * np.sin(p2))  # eq. 3.2
    l2 = np.mod(l1 + dl + np.pi, 2 * np.pi) - np.pi  # eq. 3.3 (east-positive)
    return np.rad2deg(p2), np.rad2deg(l2)


def dead_reckon_latlon(lat0_deg: float, lon0_deg: float, bearing_deg, step_m):
    """Chain :func:`destination` over steps: the pedestrian dead-reckoning path.

    Parameters
    ----------
    lat0_deg, lon0_deg : float
        Start fix (degrees).
    bearing_deg, step_m : array_like, shape (n,)
        Heading (degrees from north, clockwise) and length (m) of every step.

    Returns
    -------
    lat_deg, lon_deg : ndarray, shape (n + 1,)
        Start followed by the position after each step.

    References
    ----------
    PSO thesis, sec. 3.2.1 (dead reckoning, Fig. 3.4) with eq. 3.1-3.3.
    """
    b = _finite("bearing_deg", bearing_deg)
    s = _finite("step_m", step_m)
    if b.ndim != 1 or b.shape != s.shape:
        raise ValueError(f"bearing_deg and step_m must be 1-D of equal length, got {b.shape} and {s.shape}")
    if np.any(s < 0):
        raise ValueError("step_m must be >= 0")
    _check_lat("lat0_deg", lat0_deg)
    _finite("lon0_deg", lon0_deg)
    th = np.deg2rad(b)
    sin_t, cos_t = np.sin(th), np.cos(th)
    d = s / EARTH_RADIUS_M
    sin_d, cos_d = np.sin(d), np.cos(d)
    lat = np.empty(b.size + 1)
    lon = np.empty(b.size + 1)
    p1, l1 = math.radians(float(lat0_deg)), math.radians(float(lon0_deg))
    lat[0], lon[0] = p1, l1
    for i in range(b.size):  # eq. 3.1-3.3, scalar maths (same formulas as destination())
        sp1, cp1 = math.sin(p1), math.cos(p1)
        p2 = math.asin(max(-1.0, min(1.0, sp1 * cos_d[i] + cp1 * sin_d[i] * cos_t[i])))
        dl = math.atan2(sin_t[i] * sin_d[i] * cp1, cos_d[i] - sp1 * math.sin(p2))
        l1 = (l1 + dl + math.pi) % (2 * math.pi) - math.pi
        p1 = p2
        lat[i + 1], lon[i + 1] = p2, l1
    return np.rad2deg(lat), np.rad2deg(lon)


def path_length_m(lat_deg, lon_deg) -> float:
    """Sum of haversine distances between consecutive points, m."""
    lat = np.asarray(lat_deg, dtype=float)
    lon = np.asarray(lon_deg, dtype=float)
    if lat.ndim != 1 or lat.shape != lon.shape:
        raise ValueError(f"lat_deg and lon_deg must be 1-D of equal length, got {lat.shape} and {lon.shape}")
    if lat.size < 2:
        return 0.0
    return float(np.sum(haversine_m(lat[:-1], lon[:-1], lat[1:], lon[1:])))


def latlon_to_local_m(lat_deg, lon_deg, lat0_deg: float, lon0_deg: float, radius_m: float = EARTH_RADIUS_M):
    """Local east/north metres about ``(lat0, lon0)`` (equirectangular; for plots and small areas).

    Returns
    -------
    x_m, y_m : ndarray
        East and north offsets, m.
    """
    lat = _check_lat("lat_deg", lat_deg)
    lon = _finite("lon_deg", lon_deg)
    dlon = (lon - lon0_deg + 180.0) % 360.0 - 180.0
    x = radius_m * np.deg2rad(dlon) * np.cos(np.deg2rad(lat0_deg))
    y = radius_m * np.deg2rad(lat - lat0_deg)
    return x, y


def local_to_latlon(x_m, y_m, lat0_deg: float, lon0_deg: float, radius_m: float = EARTH_RADIUS_M):
    """Inverse of :func:`latlon_to_local_m`."""
    x = _finite("x_m", x_m)
    y = _finite("y_m", y_m)
    lat = lat0_deg + np.rad2deg(y / radius_m)
    lon = lon0_deg + np.rad2deg(x / (radius_m * np.cos(np.deg2rad(lat0_deg))))
    return lat, lon


def gps_track_length_m(fixes: pd.DataFrame, max_gap_s: float = 3.0) -> float:
    """Length of a GPS track (sum of haversine distances between consecutive fixes), m.

    Parameters
    ----------
    fixes : DataFrame
        Columns ``t_s``, ``lat_deg``, ``lon_deg``; rows in time order.
    max_gap_s : float
        Largest time between consecutive fixes accepted; a longer gap raises (the distance across
        it is unknown, the thesis learns only from well-covered walks).

    Raises
    ------
    ValueError
        Missing columns, fewer than 2 fixes, NaN fixes, time not increasing, or a gap > ``max_gap_s``.
    """
    for c in ("t_s", "lat_deg", "lon_deg"):
        if c not in fixes.columns:
            raise ValueError(f"GPS fixes lack column {c!r}")
    if len(fixes) < 2:
        raise ValueError(f"GPS track needs at least 2 fixes, got {len(fixes)}")
    t = fixes["t_s"].to_numpy(float)
    lat = fixes["lat_deg"].to_numpy(float)
    lon = fixes["lon_deg"].to_numpy(float)
    bad = ~(np.isfinite(lat) & np.isfinite(lon) & np.isfinite(t))
    if bad.any():
        raise ValueError(f"GPS fix at row {int(np.flatnonzero(bad)[0])} is not finite (no fix); "
                         "drop or bridge fix gaps explicitly before measuring the track")
    dt = np.diff(t)
    if np.any(dt <= 0):
        raise ValueError(f"GPS t_s must be strictly increasing (row {int(np.flatnonzero(dt <= 0)[0]) + 1})")
    if np.any(dt > max_gap_s):
        i = int(np.flatnonzero(dt > max_gap_s)[0])
        raise ValueError(f"GPS gap of {dt[i]:.1f} s between rows {i} and {i + 1} exceeds max_gap_s={max_gap_s}")
    return path_length_m(lat, lon)
