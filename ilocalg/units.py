"""Unit conversions, angle helpers and the random-generator convention.

References
----------
Angles: headings ``theta_rad`` count counter-clockwise from the map x axis (east); compass yaw
``psi_rad`` counts clockwise from north. ``theta = pi/2 - psi``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "G0_MPS2",
    "as_rng",
    "deg2rad",
    "rad2deg",
    "wrap_angle_rad",
    "yaw_to_theta",
    "theta_to_yaw",
    "ns_to_s",
    "ms_to_s",
]

#: Standard gravity, m/s^2.
G0_MPS2 = 9.80665


def as_rng(rng: np.random.Generator | int | None) -> np.random.Generator:
    """Return a :class:`numpy.random.Generator` from a generator, a seed or ``None``.

    A generator is returned unchanged (so callers share its stream); an int seeds a new
    PCG64 generator; ``None`` gives fresh OS entropy (not reproducible).
    """
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None or isinstance(rng, (int, np.integer)):
        return np.random.default_rng(rng)
    raise ValueError(f"rng must be a numpy Generator, an int seed or None, got {type(rng).__name__}")


def deg2rad(a_deg):
    """Degrees to radians."""
    return np.deg2rad(a_deg)


def rad2deg(a_rad):
    """Radians to degrees."""
    return np.rad2deg(a_rad)


def wrap_angle_rad(a_rad):
    """Wrap angles to [-pi, pi)."""
    return (np.asarray(a_rad) + np.pi) % (2.0 * np.pi) - np.pi


def yaw_to_theta(psi_rad):
    """Compass yaw (from north, clockwise) to map heading (from east, counter-clockwise)."""
    return wrap_angle_rad(np.pi / 2.0 - np.asarray(psi_rad))


def theta_to_yaw(theta_rad):
    """Map heading (from east, counter-clockwise) to compass yaw (from north, clockwise)."""
    return wrap_angle_rad(np.pi / 2.0 - np.asarray(theta_rad))


def ns_to_s(t_ns):
    """Nanoseconds (int) to seconds (float64)."""
    return np.asarray(t_ns, dtype=np.float64) * 1e-9


def ms_to_s(t_ms):
    """Milliseconds (int) to seconds (float64)."""
    return np.asarray(t_ms, dtype=np.float64) * 1e-3
