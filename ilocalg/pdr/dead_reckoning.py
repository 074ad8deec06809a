"""Dead reckoning: positions from step lengths and headings.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Eq. (22) (without the noise term).
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Eq. (5)-(6).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["dead_reckon", "PDR"]


def dead_reckon(length_m, theta_rad, x0_m: float = 0.0, y0_m: float = 0.0) -> pd.DataFrame:
    """Accumulate steps: ``x += d cos(theta)``, ``y += d sin(theta)``.

    Parameters
    ----------
    length_m, theta_rad : array_like, shape (n_steps,)
        Step lengths (m, >= 0) and headings (rad, from the map x axis, counter-clockwise).
    x0_m, y0_m : float
        Start position.

    Returns
    -------
    DataFrame, shape (n_steps + 1, 2)
        Columns ``x_m``, ``y_m``, index ``step`` (0 = start).

    References
    ----------
    Chiu (2013), eq. (22); Luo et al. (2017), eq. (5)-(6).
    """
    d = np.asarray(length_m, dtype=np.float64).ravel()
    th = np.asarray(theta_rad, dtype=np.float64).ravel()
    if d.shape != th.shape:
        raise ValueError(f"length_m and theta_rad must have the same length, got {d.size} and {th.size}")
    for name, a in (("length_m", d), ("theta_rad", th)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} is not finite at step {int(np.flatnonzero(~np.isfinite(a))[0])}")
    if np.any(d < 0):
        raise ValueError(f"length_m must be >= 0; step {int(np.flatnonzero(d < 0)[0])} is negative")
    x = x0_m + np.concatenate([[0.0], np.cumsum(d * np.cos(th))])
    y = y0_m + np.concatenate([[0.0], np.cumsum(d * np.sin(th))])
    return pd.DataFrame({"x_m": x, "y_m": y}, index=pd.RangeIndex(x.size, name="step"))


class PDR:
    """Thin wrapper holding the start position; ``track(length_m, theta_rad)`` calls :func:`dead_reckon`."""

    def __init__(self, x0_m: float = 0.0, y0_m: float = 0.0):
        self.x0_m = x0_m
        self.y0_m = y0_m

    def track(self, length_m, theta_rad) -> pd.DataFrame:
        return dead_reckon(length_m, theta_rad, self.x0_m, self.y0_m)
