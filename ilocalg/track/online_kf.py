"""A causal Kalman filter that learns the walk's own heading offset and step-length scale from the fixes.

The floor calibration (:func:`ilocalg.track.motion.calibrate`) gives every walk the same step-length
factor and compass-to-map heading offset; a walk's own offset and scale differ from them (the phone
held differently, another gait). Written as one complex gain ``g = s exp(i b)`` (scale ``s``, heading
bias ``b``) that multiplies each PDR step ``d_k`` (map frame, floor calibration applied), the walk's
displacement ``g d_k`` is *linear* in ``g`` (a similarity transform), so the state

    x = [p_x, p_y, g_re, g_im]
    p_{k+1} = p_k + D_k [g_re, g_im]^T + w_k,   D_k = [[d_x, -d_y], [d_y, d_x]]
    g_{k+1} = g_k + u_k

is a linear Gaussian model: an exact Kalman filter (no linearisation), which carries the covariance
between the position and the gain instead of re-solving the walk at every fix. A Wi-Fi fix ``z``
describes the position at its readings' time ``t_z``, at or before the state ``k`` it is applied to;
since ``p(t_z) = p_k - D(t_z, t_k) g`` (the PDR displacement between the two times, interpolated within
a step), its row is ``H = [I, -D(t_z, t_k)]``: late fixes are applied exactly, not as if current.
Each fix is down-weighted by Huber's weight of its normalised innovation (``R / w``, ``w = min(1, c /
r)``, ``r = sqrt(nu^T S^-1 nu)``, c = 1.345; a one-step robust Kalman update in the sense of Karlgaard
& Schaub 2007), as the least-squares estimators weight their fixes.

Every noise is measured on the other walks of the floor (:func:`ilocalg.track.motion.gain_stats`): the
prior spread of ``g`` around 1 (the per-walk similarity fitted to each walk's waypoints), its random
walk per step (between the two halves of each walk) and the step noise that remains once a walk's own
``g`` is known; the fix variance is the leave-one-walk-out fix error of the database, as elsewhere.

:func:`gain_kf` is the filter (the state at every step uses the data up to that step's time only);
:func:`gain_kf_lag` adds a fixed-lag Rauch-Tung-Striebel smoother (each state re-estimated from the
data up to ``lag_s`` seconds after it: not causal, a labelled variant of its own).

References
----------
Kalman R. E., J. Basic Eng. 82 (1960); Rauch, Tung, Striebel, AIAA J. 3(8) (1965), the smoother (here
over a fixed lag: Moore J. B., "Discrete-time fixed-lag smoothing algorithms", Automatica 9 (1973));
Huber P. J., Robust Statistics, Wiley (1981); Karlgaard C. D., Schaub H., "Huber-based divided
difference filtering", J. Guid. Control Dyn. 30(3) (2007), the Huber-weighted measurement update;
Umeyama S., IEEE PAMI 13(4) (1991), the similarity fit of a track onto points.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["GainKFResult", "gain_kf", "gain_kf_lag", "gain_kf_delayed_start", "gain_kf_smooth_to", "HUBER_C"]

#: Huber's constant (in standard deviations of the normalised innovation), as the least squares use.
HUBER_C = 1.345


@dataclass(frozen=True)
class GainKFResult:
    """The filter over ``n + 1`` states: ``x`` (n+1, 4) ``[p_x, p_y, g_re, g_im]`` after each state's
    fixes, ``P`` (n+1, 4, 4), ``x_pred`` / ``P_pred`` before them, ``F`` (n+1, 4, 4) the transition into
    each state (identity for state 0), ``n_fixes`` fixes used."""

    x: np.ndarray
    P: np.ndarray
    x_pred: np.ndarray
    P_pred: np.ndarray
    F: np.ndarray
    n_fixes: int

    @property
    def xy_m(self) -> np.ndarray:
        return self.x[:, :2]


def _jmat(v):
    """``[[v_x, -v_y], [v_y, v_x]]``: the matrix of ``g -> g v`` in complex terms."""
    return np.array([[v[0], -v[1]], [v[1], v[0]]])


def walk_inputs(state_t_s, disp_m, fix_t_s, fix_xy_m, fix_var_m2, fix_avail_t_s=None):
    """The filters' walk arrays checked: ``(ts, d, ft, fz, known, fv)`` (state times, (n, 2) steps, fix times,
    (m, 2) fixes, when each fix is known, (m,) per-axis fix variances)."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    d = np.asarray(disp_m, dtype=np.float64).reshape(-1, 2)
    ft = np.asarray(fix_t_s, dtype=np.float64)
    fz = np.asarray(fix_xy_m, dtype=np.float64).reshape(-1, 2)
    known = ft if fix_avail_t_s is None else np.asarray(fix_avail_t_s, dtype=np.float64)
    if d.shape[0] != ts.size - 1 or ft.size < 1 or fz.shape[0] != ft.size or known.shape != ft.shape:
        raise ValueError("need disp_m of shape (n, 2) for n+1 states and at least one fix with matching shapes")
    fv = np.broadcast_to(np.asarray(fix_var_m2, dtype=np.float64), ft.shape)
    if not np.all(fv > 0):
        raise ValueError("fix_var_m2, step_var_m2 must be > 0 and gain_var, gain_walk_var >= 0")
    return ts, d, ft, fz, known, fv


def fix_corr_parts(fix_corr) -> tuple[float, float, float]:
    """``(c0, rho, var_b_m2)`` of a ``fix_corr`` (None: ``(0, 0, 0)``, all white), checked."""
    c0, rho, var_b = (0.0, 0.0, 0.0) if fix_corr is None else tuple(float(v) for v in fix_corr)
    if not (0.0 <= c0 < 1.0 and 0.0 <= rho < 1.0 and var_b >= 0.0):
        raise ValueError(f"fix_corr must be (c0, rho, var_b_m2) in [0, 1) x [0, 1) x [0, inf), got {fix_corr!r}")
    return c0, rho, var_b


def gain_kf(state_t_s, disp_m, fix_t_s, fix_xy_m, fix_var_m2, step_var_m2: float, gain_var: float,
            gain_walk_var: float, fix_avail_t_s=None, huber_c: float | None = HUBER_C,
            snap=None, fix_corr: tuple[float, float, float] | None = None) -> GainKFResult:
    """Run the gain-augmented Kalman filter over one walk (module docstring).

    Parameters
    ----------
    state_t_s : (n+1,) state times; disp_m : (n, 2) PDR steps (map frame, floor calibration applied).
    fix_t_s, fix_xy_m : (m,), (m, 2) the fixes and the times they describe.
    fix_var_m2, step_var_m2 : per-axis variance of a fix (scalar, or (m,) one per fix) and of one step's
        residual error.
    gain_var, gain_walk_var : prior variance of each component of ``g`` around ``1 + 0i`` and its
        random-walk variance per step.
    fix_avail_t_s : (m,) when each fix becomes known (default ``fix_t_s``); a fix is applied at the
        first state at or after it.
    huber_c : Huber's constant, None for the plain Kalman update.
    fix_corr : ``(c0, rho, var_b_m2)`` (:func:`ilocalg.track.fixes.fix_error_correlation`): a share ``c0``
        of the fix error is correlated from fix to fix, a first-order Gauss-Markov bias ``b_i = rho b_{i-1} +
        w_i`` (stationary per-axis variance ``var_b_m2``) carried as two more states, the rest (``(1 - c0)``
        times each fix's variance) white (Bryson & Henrikson 1968). None: all white.

    The filter starts at state 0 from the first fix moved back along the PDR steps to the log start
    (covariance from the fix's and the gain's), as the other online variants start; that fix is then
    not used again.
    """
    ts, d, ft, fz, known, fv = walk_inputs(state_t_s, disp_m, fix_t_s, fix_xy_m, fix_var_m2, fix_avail_t_s)
    n = ts.size
    if not (step_var_m2 > 0 and gain_var >= 0 and gain_walk_var >= 0):
        raise ValueError("fix_var_m2, step_var_m2 must be > 0 and gain_var, gain_walk_var >= 0")
    # cumulative PDR displacement, to interpolate the displacement between a fix's time and its state
    cum = np.vstack([[0.0, 0.0], np.cumsum(d, axis=0)])
    cum_at = np.column_stack([np.interp(ft, ts, cum[:, 0]), np.interp(ft, ts, cum[:, 1])])
    at_state = np.searchsorted(ts, known, side="left")      # first state at or after the fix is known
    order = np.argsort(at_state, kind="stable")
    # start: the first fix moved back to state 0 along the PDR steps, p_0 = z_0 - D(t_0, t_z0) g, with the
    # covariance that follows from the fix's and the gain's (the fix is then not used again)
    D0 = _jmat(cum_at[0] - cum[0])
    Pg = np.eye(2) * gain_var
    c0, rho, var_b = fix_corr_parts(fix_corr)
    nb = 0 if fix_corr is None else 2                      # the correlated fix error's two states
    ns = 4 + nb
    white = (1.0 - c0) * fv
    x = np.concatenate([fz[0] - D0 @ [1.0, 0.0], [1.0, 0.0], np.zeros(nb)])
    P = np.zeros((ns, ns))
    P[:2, :2] = np.eye(2) * (white[0] + var_b) + D0 @ Pg @ D0.T
    P[:2, 2:4] = -D0 @ Pg
    P[2:4, :2] = P[:2, 2:4].T
    P[2:4, 2:4] = Pg + np.eye(2) * 1e-12
    if nb:                                                 # p_0 = z_0 - D0 g - b_0 - v_0
        P[:2, 4:] = P[4:, :2] = -np.eye(2) * var_b
        P[4:, 4:] = np.eye(2) * (var_b + 1e-12)
    Q = np.zeros((ns, ns))
    Q[:4, :4] = np.diag([step_var_m2, step_var_m2, gain_walk_var, gain_walk_var])
    xs, Ps = np.empty((n, ns)), np.empty((n, ns, ns))
    xp, Pp = np.empty((n, ns)), np.empty((n, ns, ns))
    Fs = np.broadcast_to(np.eye(ns), (n, ns, ns)).copy()
    q = 1                                                   # fix 0 started the filter
    while q < ft.size and at_state[order[q]] < 0:
        q += 1
    used = 0
    # fixes applied at each state (the bias moves on once per fix, in the state's prediction)
    n_at = np.bincount(np.clip(at_state[order[q:]], 0, None), minlength=n)[:n] if nb else np.zeros(n, dtype=int)
    for k in range(n):
        F = np.eye(ns)
        Qk = Q.copy()
        if k > 0:
            F[:2, 2:4] = _jmat(d[k - 1])
        if n_at[k]:
            a = rho ** int(n_at[k])
            F[4:, 4:] *= a
            Qk[4:, 4:] = np.eye(2) * var_b * (1.0 - a * a)
        if k > 0 or n_at[k]:
            x = F @ x
            P = F @ P @ F.T + (Qk if k > 0 else Qk * np.pad(np.ones(nb), (4, 0)))
            Fs[k] = F
        xp[k], Pp[k] = x, P
        while q < ft.size and at_state[order[q]] <= k:
            i = order[q]
            q += 1
            H = np.zeros((2, ns))
            H[:, :2] = np.eye(2)
            H[:, 2:4] = -_jmat(cum[k] - cum_at[i])          # p(t_fix) = p_k - D(t_fix, t_k) g
            if nb:
                H[:, 4:] = np.eye(2)
            nu = fz[i] - H @ x
            R0 = np.eye(2) * white[i]
            S = H @ P @ H.T + R0
            R = R0
            if huber_c is not None:
                r = float(np.sqrt(nu @ np.linalg.solve(S, nu)))
                w = min(1.0, huber_c / max(r, 1e-12))
                if w < 1.0:
                    R = R0 / w
                    S = H @ P @ H.T + R
            K = np.linalg.solve(S, H @ P).T
            x = x + K @ nu
            IKH = np.eye(ns) - K @ H
            P = IKH @ P @ IKH.T + K @ R @ K.T                # Joseph form
            used += 1
        if snap is not None:                                # estimate projection onto the walkable map
            xy, moved = snap(x[:2])
            if moved[0]:
                x = np.concatenate([xy[0], x[2:]])
        xs[k], Ps[k] = x, P
    return GainKFResult(xs, Ps, xp, Pp, Fs, used)


def gain_kf_lag(res: GainKFResult, state_t_s, lag_s: float) -> np.ndarray:
    """Fixed-lag RTS smoothing of :func:`gain_kf`'s output: each state's position re-estimated from the
    data up to ``lag_s`` seconds after it (the RTS recursion run back from the last state within the
    lag); (n+1, 2). Not causal: the estimate at ``t`` waits until ``t + lag_s``."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    if not lag_s >= 0:
        raise ValueError(f"lag_s must be >= 0, got {lag_s!r}")
    return gain_kf_smooth_to(res, np.searchsorted(ts, ts + lag_s, side="right") - 1)


def gain_kf_delayed_start(res: GainKFResult, state_t_s, until_t_s: float) -> np.ndarray:
    """The filter's positions, those of the states up to ``until_t_s`` replaced by their RTS-smoothed values
    given the data up to ``until_t_s`` (a delayed start: the start-up is reported at ``until_t_s``, every later
    state as the filter has it); (n+1, 2)."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    k = np.arange(ts.size)
    j = int(np.searchsorted(ts, until_t_s, side="right")) - 1
    return gain_kf_smooth_to(res, np.where(k <= j, max(j, 0), k))


def gain_kf_smooth_to(res: GainKFResult, end) -> np.ndarray:
    """Each state ``k``'s position given the data up to state ``end[k]`` (>= k): the RTS recursion run back from
    ``end[k]``; ``end[k] == k`` is the filter's own estimate. (n+1, 2)."""
    end = np.asarray(end, dtype=np.int64)
    n = res.x.shape[0]
    if end.shape != (n,) or np.any(end < np.arange(n)) or np.any(end >= n):
        raise ValueError(f"end must have shape ({n},) with k <= end[k] < {n}")
    out = res.x[:, :2].copy()
    # the RTS gain of state i does not depend on where the recursion started: each computed once, when first needed
    # (the smoothed covariances are not needed for the positions)
    gains = [None] * n
    for k in range(n):
        j = int(end[k])
        xs = res.x[j]
        for i in range(j - 1, k - 1, -1):
            C = gains[i]
            if C is None:
                C = gains[i] = np.linalg.solve(res.P_pred[i + 1], res.F[i + 1] @ res.P[i]).T
            xs = res.x[i] + C @ (xs - res.x_pred[i + 1])
        out[k] = xs[:2]
    return out
