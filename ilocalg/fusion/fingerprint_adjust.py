"""Fingerprint adjustment of a PDR track: the combination of Luo et al. (2017).

The paper combines Wi-Fi fingerprinting and PDR as follows: the walk's initial position comes from
Wi-Fi fingerprinting (sec. 3.4.4, "the pedestrian's initial position is obtained by the Wi-Fi
based indoor positioning"), PDR carries the position from step to step (eq. 5-6), and "the
absoluteness of fingerprint positioning adjusts the position, eliminating PDR's accumulated error"
(abstract; sec. 4 closing paragraph). It gives no filter, no noise model and no weight for the
adjustment (its sec. 3.1 describes a generic Kalman filter for KF-based inertial navigation, which
its sec. 3.2 argues against on phones).

This module reads "adjusts the position" as a fixed-gain correction: between fixes the position is
dead-reckoned, ``x_k = x_{k-1} + d_k [cos theta_k, sin theta_k]``; at a state with a fingerprint
fix ``z_k`` it moves a fraction ``weight`` of the way to the fix, ``x_k <- x_k + weight (z_k - x_k)``.
``weight = 1`` resets the track to every fix, ``weight = 0`` is PDR alone. The paper gives no value:
``weight`` is an assumption its callers sweep.

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications. Abstract, sec. 3.4.4 eq. (5)-(6), sec. 4.
"""

from __future__ import annotations

import numpy as np

from ilocalg.fusion.align import fixes_at_states
from ilocalg.fusion.budget import FusionInputs, steady_state_weight
from ilocalg.pdr.dead_reckoning import dead_reckon

__all__ = ["fingerprint_adjusted_track", "principled_weight", "combined_method", "pdr_true_start_method"]


def fingerprint_adjusted_track(x0_m, theta_rad, step_m, z_m, weight: float) -> np.ndarray:
    """Dead-reckon from ``x0_m`` and pull the position towards each fingerprint fix.

    Parameters
    ----------
    x0_m : array_like, shape (2,)
        Initial position (the first Wi-Fi fix in the paper's scheme), metres.
    theta_rad, step_m : array_like, shape (n,)
        Heading (from the map x axis, counter-clockwise) and length (m) of each detected step.
    z_m : array_like, shape (n+1, 2)
        Fingerprint fix at each state (state 0 = start, state k = after step k); a row of NaN means
        no fix at that state.
    weight : float
        Fraction of the gap to the fix closed at each fix, in [0, 1].

    Returns
    -------
    ndarray, shape (n+1, 2)
        The adjusted track, metres.

    References
    ----------
    Luo et al. 2017, abstract, sec. 3.4.4, eq. (5)-(6).
    """
    x0 = np.asarray(x0_m, dtype=float)
    th = np.asarray(theta_rad, dtype=float)
    d = np.asarray(step_m, dtype=float)
    z = np.asarray(z_m, dtype=float)
    if x0.shape != (2,) or not np.all(np.isfinite(x0)):
        raise ValueError(f"x0_m must be a finite (2,) position, got {x0!r}")
    if th.ndim != 1 or d.shape != th.shape:
        raise ValueError(f"theta_rad and step_m must be 1-D of one length, got {th.shape} and {d.shape}")
    if not (np.all(np.isfinite(th)) and np.all(np.isfinite(d))):
        raise ValueError("theta_rad and step_m must be finite")
    if z.shape != (th.size + 1, 2):
        raise ValueError(f"z_m must have shape (n+1, 2) = ({th.size + 1}, 2), got {z.shape}")
    if not (np.isfinite(weight) and 0.0 <= weight <= 1.0):
        raise ValueError(f"weight must be in [0, 1], got {weight!r}")
    has = np.all(np.isfinite(z), axis=1)
    if np.any(np.isfinite(z).any(axis=1) & ~has):
        bad = int(np.flatnonzero(np.isfinite(z).any(axis=1) & ~has)[0])
        raise ValueError(f"z_m row {bad} has one coordinate NaN: a fix needs both or none")
    inc = d[:, None] * np.stack([np.cos(th), np.sin(th)], axis=-1)
    x = np.empty((th.size + 1, 2))
    x[0] = x0
    if has[0]:
        x[0] = x0 + weight * (z[0] - x0)
    # between fixes the track is the cumulative sum of the step increments; visit fix states only
    cs = np.vstack([np.zeros((1, 2)), np.cumsum(inc, axis=0)])
    fixes = np.flatnonzero(has[1:]) + 1
    start = 0
    for k in np.r_[fixes, th.size + 1]:
        seg = slice(start + 1, min(k, th.size) + 1)
        x[seg] = x[start] + cs[seg] - cs[start]
        if k <= th.size:
            x[k] = x[k] + weight * (z[k] - x[k])
            start = k
    return x


def principled_weight(sig_sl_m: float, sig_theta_rad: float, step_m: float, step_s: float, scan_interval_s: float,
                      r_var_m2: float) -> tuple[float, float]:
    """The adjustment weight from variances measured on the training data (not from the test outcome).

    Between two fixes (``scan_interval_s``) the walker takes ``scan_interval_s / step_s`` steps, each adding
    a position variance of ``(sig_sl^2 + (step_m sig_theta)^2) / 2`` per axis (length along, heading across
    the walk); a fix has variance ``r_var_m2`` per axis. The steady-state inverse-variance weight of the two
    (:func:`ilocalg.fusion.budget.steady_state_weight`). Returns ``(weight, q_var_m2)``.
    """
    q = scan_interval_s / step_s * 0.5 * (sig_sl_m**2 + (step_m * sig_theta_rad) ** 2)
    return steady_state_weight(q, r_var_m2), float(q)


def combined_method(weight: float):
    """Luo's combination (Wi-Fi start, fixes pull the track by ``weight``) as an error-budget method."""
    def comb(inp: FusionInputs) -> np.ndarray:
        fxy = np.asarray(inp.fix_xy_m, dtype=np.float64)
        z = fixes_at_states(inp.state_t_s, inp.fix_t_s, fxy, before_start="drop", same_state="last").z_m
        return fingerprint_adjusted_track(inp.start_xy_m, inp.theta_rad, inp.step_m, z, weight)
    return comb


def pdr_true_start_method(inp: FusionInputs) -> np.ndarray:
    """PDR only from the true start (L235) as an error-budget method."""
    x0 = inp.truth_at([inp.t0_s])[0]
    return dead_reckon(np.asarray(inp.step_m), np.asarray(inp.theta_rad), *x0)[["x_m", "y_m"]].to_numpy()
