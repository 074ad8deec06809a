"""Small seeded synthetic walks for testing and benchmarking the step filter.

Not a simulator of any paper's data (the i-Loc floor and walks are simulated by
:mod:`ilocalg.sim.iloc_floor` and :mod:`ilocalg.sim.gait`): a pedestrian walks a polyline at constant
step length; the "detected" steps get
Gaussian step-length errors (standard deviation ``sigma_sl_m``) and heading errors
(``sigma_heading_rad``, optionally a constant heading bias); Wi-Fi fixes arrive every
``fix_every`` states with isotropic Gaussian errors (``sigma_rf_m``) and, optionally, a fraction of
gross outliers (uniform direction, ``outlier_m`` away). Every parameter is an input of the call.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.units import as_rng

__all__ = ["SyntheticWalk", "straight_walk"]


@dataclass(frozen=True)
class SyntheticWalk:
    """Truth and measurements of a synthetic walk (``n`` steps, ``n + 1`` states).

    Attributes
    ----------
    truth_xy_m : ndarray (n+1, 2)
    theta_rad, step_m : ndarray (n,)
        Measured heading and step length of each step.
    z_m : ndarray (n+1, 2)
        Wi-Fi fixes; NaN rows where there is none.
    is_outlier : ndarray of bool (n+1,)
    """

    truth_xy_m: np.ndarray
    theta_rad: np.ndarray
    step_m: np.ndarray
    z_m: np.ndarray
    is_outlier: np.ndarray


def straight_walk(n_steps: int = 100, rng=None, step_true_m: float = 0.7, heading_true_rad: float = 0.3,
                  sigma_sl_m: float = 0.2, sigma_heading_rad: float = 0.05, heading_bias_rad: float = 0.0,
                  sigma_rf_m: float = 3.0, fix_every: int = 3, outlier_fraction: float = 0.0,
                  outlier_m: float = 40.0, turn_every: int | None = None) -> SyntheticWalk:
    """A seeded walk along a straight line (or a zig-zag with a 90 degree turn every ``turn_every`` steps).

    Parameters are described in the module docstring; ``rng`` is a Generator, a seed or None.
    """
    if n_steps < 1 or fix_every < 1:
        raise ValueError("n_steps and fix_every must be >= 1")
    if not 0.0 <= outlier_fraction <= 1.0:
        raise ValueError("outlier_fraction must be in [0, 1]")
    rng = as_rng(rng)
    k = np.arange(n_steps)
    heading = np.full(n_steps, heading_true_rad)
    if turn_every:
        heading = heading + (np.pi / 2) * ((k // turn_every) % 2)
    d = np.column_stack([np.cos(heading), np.sin(heading)]) * step_true_m
    truth = np.vstack([[0.0, 0.0], np.cumsum(d, axis=0)])
    step_m = step_true_m + sigma_sl_m * rng.standard_normal(n_steps)
    theta = heading + heading_bias_rad + sigma_heading_rad * rng.standard_normal(n_steps)
    z = truth + sigma_rf_m * rng.standard_normal(truth.shape)
    has = (np.arange(n_steps + 1) % fix_every) == 0
    out = has & (rng.random(n_steps + 1) < outlier_fraction)
    ang = rng.uniform(0.0, 2.0 * np.pi, n_steps + 1)
    z[out] = truth[out] + outlier_m * np.column_stack([np.cos(ang), np.sin(ang)])[out]
    z[~has] = np.nan
    return SyntheticWalk(truth, theta, np.abs(step_m), z, out)
