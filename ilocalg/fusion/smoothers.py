"""Smoothers for the step filter: Rauch-Tung-Striebel over a whole walk and a fixed-lag smoother.

With ``F = I`` the RTS recursion (backwards, ``k = n-1 .. 0``) is

``C_k = P_k P_{k+1}^{-1,-}``,  ``xs_k = x_k + C_k (xs_{k+1} - x_{k+1}^-)``,
``Ps_k = P_k + C_k (Ps_{k+1} - P_{k+1}^-) C_k^T``,

using the filtered ``x_k, P_k`` and the next prediction ``x_{k+1}^-, P_{k+1}^-`` that the filter
stored (so the step control input ``B u`` is accounted for). The fixed-lag smoother with lag ``L``
estimates state ``j`` from the fixes up to state ``min(j + L, n)``: the RTS recursion run back
from the filtered state at ``j + L`` (what an online system can output ``L`` steps late).

Beyond the paper (the i-Loc thesis filters only); the smoothing equations are the classical
Rauch, Tung & Striebel (1965) ones, as in the smartphone-INS paper of this toolkit (eq. 8-10).

References
----------
H. E. Rauch, F. Tung, C. T. Striebel, "Maximum likelihood estimates of linear dynamic systems",
AIAA J. 3(8), 1965. Liao et al. (2016), eq. (8)-(10).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.fusion._linalg import inv2, matvec
from ilocalg.fusion.step_kf import StepKFResult

__all__ = ["SmoothResult", "rts_smooth", "fixed_lag_smooth"]


@dataclass(frozen=True)
class SmoothResult:
    """Smoothed states ``x`` (([B,] n+1, 2), m) and covariances ``P`` (([B,] n+1, 2, 2), m^2); ``lag`` (None = RTS)."""

    x: np.ndarray
    P: np.ndarray
    lag: int | None = None


def _rts_gain(P_f, P_prior_next):
    return P_f @ inv2(P_prior_next)


def rts_smooth(result: StepKFResult) -> SmoothResult:
    """Rauch-Tung-Striebel smoothing of a whole walk (or batch of walks) filtered by the step filter.

    Parameters
    ----------
    result : StepKFResult
        From :func:`ilocalg.fusion.filter_walk`, :func:`~ilocalg.fusion.filter_walks` or
        :meth:`ilocalg.fusion.StepKalmanFilter.run`.

    Returns
    -------
    SmoothResult
        Same shapes as ``result.x`` / ``result.P``; the last state equals the filtered one.

    References
    ----------
    Rauch, Tung & Striebel (1965); Liao et al. 2016, eq. (8)-(10).
    """
    xf, Pf, xp, Pp = result.x, result.P, result.x_prior, result.P_prior
    xs = np.array(xf, dtype=np.float64)
    Ps = np.array(Pf, dtype=np.float64)
    n1 = xs.shape[-2]
    for k in range(n1 - 2, -1, -1):
        C = _rts_gain(Pf[..., k, :, :], Pp[..., k + 1, :, :])
        xs[..., k, :] = xf[..., k, :] + matvec(C, xs[..., k + 1, :] - xp[..., k + 1, :])
        Ps[..., k, :, :] = Pf[..., k, :, :] + C @ (Ps[..., k + 1, :, :] - Pp[..., k + 1, :, :]) @ np.swapaxes(C, -1, -2)
    return SmoothResult(xs, Ps, None)


def fixed_lag_smooth(result: StepKFResult, lag: int) -> SmoothResult:
    """Fixed-lag smoothing: state ``j`` estimated from the fixes up to state ``min(j + lag, n)``.

    ``lag = 0`` returns the filtered states; ``lag >= n`` equals :func:`rts_smooth`. Vectorised
    over ``j`` (``lag`` backward passes over all states at once).

    Parameters
    ----------
    result : StepKFResult
    lag : int >= 0
        Lag in steps.

    References
    ----------
    Rauch, Tung & Striebel (1965) recursion applied over a sliding window.
    """
    if int(lag) != lag or lag < 0:
        raise ValueError(f"lag must be an integer >= 0, got {lag!r}")
    lag = int(lag)
    xf, Pf, xp, Pp = result.x, result.P, result.x_prior, result.P_prior
    n1 = xf.shape[-2]
    j = np.arange(n1)
    end = np.minimum(j + lag, n1 - 1)
    xs = np.array(xf[..., end, :], dtype=np.float64)
    Ps = np.array(Pf[..., end, :, :], dtype=np.float64)
    for i in range(lag, 0, -1):
        m = j + i - 1  # step from state m to m + 1, applied where m + 1 <= end
        active = m < end
        if not active.any():
            continue
        mm = np.minimum(m, n1 - 2)
        C = _rts_gain(Pf[..., mm, :, :], Pp[..., mm + 1, :, :])
        xn = xf[..., mm, :] + matvec(C, xs - xp[..., mm + 1, :])
        Pn = Pf[..., mm, :, :] + C @ (Ps - Pp[..., mm + 1, :, :]) @ np.swapaxes(C, -1, -2)
        xs = np.where(active[:, None], xn, xs)
        Ps = np.where(active[:, None, None], Pn, Ps)
    return SmoothResult(xs, Ps, lag)
