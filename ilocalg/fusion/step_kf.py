"""The i-Loc step Kalman filter: one predict per detected step, one update per Wi-Fi fix.

State ``s_k = [x_k, y_k]`` (metres, map frame) after step ``k``. Eq. (22) of the i-Loc thesis:
``s_k = s_{k-1} + [cos theta_k, sin theta_k]^T D_k + w_k`` (``F = I``, ``B_k`` the unit heading
vector, ``u_k = D_k`` the step length), ``w_k ~ N(0, Q_k)`` with
``Q_k = sigma_SL,k^2 [[cos^2, sin cos], [sin cos, sin^2]]`` (a rank-one covariance along the
heading: only the step *length* is uncertain in the paper's model). A Wi-Fi fix observes the
position directly (eq. 23, ``H = I``) with ``R_k = sigma_RF,k^2 I``; the update is eq. (24)-(25)
with the Joseph-form covariance (eq. 26).

Timeline used throughout the package: states ``k = 0..n`` (``k = 0`` is the start, before any
step); step ``k`` (``k = 1..n``) moves state ``k-1`` to ``k``; a fix may be attached to any state
``k = 0..n``. Inputs per step therefore have length ``n`` and fixes have ``n + 1`` rows; a row of
NaN in the fixes means "no fix at this state" (a row with a single NaN is an error).

Beyond the paper: innovation gating (a fix whose normalised innovation squared exceeds
``gate_nis`` is rejected and counted); an optional heading-error term in ``Q``
(``sigma_theta_rad``, default 0 = the paper's model); batched filtering of many walks at once
(:func:`filter_walks`, the fast path: vectorised across walks, and since ``F = I`` the
predictions between two fixes are cumulative sums, so the Python loop visits only the states that
carry a fix); and the filterpy-engined class :class:`StepKalmanFilter` (the per-step reference the
tests and ``benchmarks/bench_fusion.py`` compare against).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Ch. 5, eq. (20)-(26), Tables 4-5.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.fusion._linalg import inv2, matvec

__all__ = [
    "PAPER_TABLE4_STEP_M",
    "PAPER_TABLE4_SIGMA_SL_VAR_M2",
    "PAPER_TABLE5_SIGMA_RF_VAR_M2",
    "sigma_sl_paper_m",
    "nis_gate",
    "step_control",
    "step_process_noise",
    "kf_predict_step",
    "kf_update",
    "innovation",
    "StepKFResult",
    "filter_walks",
    "filter_walk",
    "StepKalmanFilter",
]

# Settings from the paper
# -----------------------
# Chiu (2013): PAPER_TABLE4_STEP_M and PAPER_TABLE4_SIGMA_SL_VAR_M2 are Table 4 (header and
# variances); PAPER_TABLE5_SIGMA_RF_VAR_M2 is Table 5, test points 1-28 in order.
#: Table 4 of the i-Loc thesis (paper): step lengths of the step-length experiment, metres (40-80 cm in the paper).
PAPER_TABLE4_STEP_M = (0.40, 0.50, 0.60, 0.70, 0.80)
#: Table 4 of the i-Loc thesis (paper, L602-605): step-length error variance sigma_SL^2 per step length. The paper
#: prints no unit. Read as a relative variance (of error / step length) it agrees with the thesis's mean SLM error
#: on the same walks (L478: 18.43 %; sqrt(0.054) sqrt(2 / pi) = 18.5 %): :func:`sigma_sl_paper_m`'s default. Read
#: as m^2 it means sigma 0.19-0.26 m at any length (about 32 % mean error): the labelled alternative. (The name
#: keeps its historical ``_M2`` suffix; the values are the paper's numbers, unit per ``reading``.)
PAPER_TABLE4_SIGMA_SL_VAR_M2 = (0.054, 0.054, 0.036, 0.053, 0.065)
#: Table 5 of the i-Loc thesis (paper): Wi-Fi position error variance sigma_RF^2 at the 28 test points (m^2).
PAPER_TABLE5_SIGMA_RF_VAR_M2 = (
    15.072, 8.184, 0.523, 5.995, 2.853, 0.899, 4.305,
    0.171, 11.219, 1.616, 1.891, 7.055, 1.960, 3.365,
    6.400, 8.238, 5.533, 2.054, 1.929, 2.883, 1.985,
    3.250, 1.789, 2.255, 3.453, 2.985, 1.145, 2.596,
)


def sigma_sl_paper_m(step_m, outside: str = "edge", reading: str = "relative") -> np.ndarray:
    """Step-length error standard deviation (m) from the paper's Table 4, per step.

    The variance is interpolated linearly between the table's step lengths (0.4-0.8 m).

    Parameters
    ----------
    step_m : array_like
        Step lengths, metres.
    outside : {"edge", "error"}
        Steps shorter than 0.4 m or longer than 0.8 m take the nearest table value (``"edge"``,
        a modelling choice: the paper gives no value there) or raise (``"error"``).
    reading : {"relative", "m2"}
        How Table 4's unitless variances read: ``"relative"`` (default; variance of the relative
        error, ``sigma = sqrt(var) * step``: it agrees with the mean SLM error of L478) or
        ``"m2"`` (``sigma = sqrt(var)`` metres at any step length).

    Returns
    -------
    ndarray, same shape as ``step_m``

    References
    ----------
    i-Loc thesis (Chiu 2013), Table 4 (L602-605), L478.
    """
    s = np.asarray(step_m, dtype=np.float64)
    if not np.isfinite(s).all() or (s < 0).any():
        raise ValueError("step_m must be finite and >= 0")
    lo, hi = PAPER_TABLE4_STEP_M[0], PAPER_TABLE4_STEP_M[-1]
    if outside == "error":
        bad = np.flatnonzero(((s < lo) | (s > hi)).ravel())
        if bad.size:
            raise ValueError(f"step_m[{bad[0]}] = {s.ravel()[bad[0]]} m is outside the paper's Table 4 range "
                             f"[{lo}, {hi}] m (pass outside='edge' to use the nearest table value)")
    elif outside != "edge":
        raise ValueError(f"outside must be 'edge' or 'error', got {outside!r}")
    sd = np.sqrt(np.interp(s, PAPER_TABLE4_STEP_M, PAPER_TABLE4_SIGMA_SL_VAR_M2))
    if reading == "relative":
        return sd * s
    if reading == "m2":
        return sd
    raise ValueError(f"reading must be 'relative' or 'm2', got {reading!r}")


def nis_gate(prob: float) -> float:
    """Gate on the normalised innovation squared for 2-D fixes: the chi-square(2) quantile ``-2 ln(1 - prob)``."""
    if not 0.0 < prob < 1.0:
        raise ValueError(f"prob must be in (0, 1), got {prob}")
    return float(-2.0 * np.log1p(-prob))


# ----------------------------------------------------------------------------------------------
# pure functions (broadcast over leading batch dimensions)
# ----------------------------------------------------------------------------------------------

def step_control(theta_rad) -> np.ndarray:
    """Control vector ``B_k = [cos theta_k, sin theta_k]`` (eq. 22), shape ``(..., 2)``."""
    t = np.asarray(theta_rad, dtype=np.float64)
    return np.stack([np.cos(t), np.sin(t)], axis=-1)


def step_process_noise(theta_rad, sigma_sl_m, step_m=0.0, sigma_theta_rad=0.0) -> np.ndarray:
    """Process noise ``Q_k = sigma_SL^2 b b^T`` with ``b = [cos, sin]`` (i-Loc, text after eq. 22).

    Beyond the paper, an optional heading error adds ``(D_k sigma_theta)^2 n n^T`` across the step
    (``n = [-sin, cos]``, first-order effect of a heading error on a step of length ``D_k``); the
    default ``sigma_theta_rad = 0`` is the paper's rank-one model.

    Parameters
    ----------
    theta_rad : array_like, shape (...)
        Heading of the step, from the map x axis, counter-clockwise.
    sigma_sl_m : array_like, broadcastable to ``theta_rad``
        Step-length error standard deviation, metres.
    step_m, sigma_theta_rad : array_like, broadcastable, optional
        Step length (m) and heading error standard deviation (rad) for the cross-step term.

    Returns
    -------
    ndarray, shape (..., 2, 2), m^2

    References
    ----------
    i-Loc thesis, Q_k below eq. (22).
    """
    b = step_control(theta_rad)
    s = np.asarray(sigma_sl_m, dtype=np.float64)
    Q = (s**2)[..., None, None] * (b[..., :, None] * b[..., None, :])
    st = np.asarray(sigma_theta_rad, dtype=np.float64)
    if np.any(st != 0):
        nv = np.stack([-b[..., 1], b[..., 0]], axis=-1)
        c = (np.asarray(step_m, dtype=np.float64) * st) ** 2
        Q = Q + c[..., None, None] * (nv[..., :, None] * nv[..., None, :])
    return Q


def kf_predict_step(x, P, theta_rad, step_m, sigma_sl_m, sigma_theta_rad=0.0):
    """Predict over one step (eq. 20/22 with ``F = I``): ``x + b D``, ``P + Q``.

    Parameters
    ----------
    x : ndarray, shape (..., 2)
        Position, metres.
    P : ndarray, shape (..., 2, 2)
        Covariance, m^2.
    theta_rad, step_m, sigma_sl_m : array_like, shape (...)
        Step heading (rad), length (m) and length standard deviation (m).
    sigma_theta_rad : array_like, optional
        Heading error standard deviation (beyond the paper; 0 = the paper's model).

    Returns
    -------
    x_prior, P_prior : ndarray, shapes (..., 2) and (..., 2, 2)

    References
    ----------
    i-Loc thesis, eq. (20), (22) and the Q_k below eq. (22).
    """
    x = np.asarray(x, dtype=np.float64)
    P = np.asarray(P, dtype=np.float64)
    b = step_control(theta_rad)
    d = np.asarray(step_m, dtype=np.float64)
    return x + b * d[..., None], P + step_process_noise(theta_rad, sigma_sl_m, d, sigma_theta_rad)


def innovation(x, P, z, R):
    """Innovation ``y = z - x``, its covariance ``S = P + R`` and ``NIS = y^T S^-1 y`` (``H = I``).

    Shapes: ``x, z`` (..., 2); ``P, R`` (..., 2, 2). Returns ``(y, S, nis)``.
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(z, dtype=np.float64) - x
    S = np.asarray(P, dtype=np.float64) + np.asarray(R, dtype=np.float64)
    nis = np.einsum("...i,...i->...", y, matvec(inv2(S), y))
    return y, S, nis


def kf_update(x, P, z, R):
    """Update with a position fix (eq. 24-26, ``H = I``, Joseph-form covariance).

    Parameters
    ----------
    x : ndarray, shape (..., 2)
    P : ndarray, shape (..., 2, 2)
    z : ndarray, shape (..., 2)
        The fix, metres. Must be finite (handle missing fixes by not calling this).
    R : ndarray, shape (..., 2, 2)
        Fix covariance, m^2, symmetric positive definite (``sigma_RF^2 I`` in the paper).

    Returns
    -------
    x_post, P_post

    References
    ----------
    i-Loc thesis, eq. (24)-(26); the Joseph form is eq. (26).
    """
    z = np.asarray(z, dtype=np.float64)
    if not np.isfinite(z).all():
        raise ValueError("kf_update: z must be finite (a missing fix is not an update)")
    x = np.asarray(x, dtype=np.float64)
    P = np.asarray(P, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    K = P @ inv2(P + R)  # eq. (25) with H = I
    ikh = np.eye(2) - K
    return x + matvec(K, z - x), ikh @ P @ np.swapaxes(ikh, -1, -2) + K @ R @ np.swapaxes(K, -1, -2)


# ----------------------------------------------------------------------------------------------
# whole walks
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StepKFResult:
    """Output of the step filter over one walk (or a batch of walks: a leading axis ``B``).

    Attributes
    ----------
    x_prior, P_prior : ndarray, shapes ([B,] n+1, 2) and ([B,] n+1, 2, 2)
        Predicted state and covariance at each state ``k`` (``k = 0``: the initial ``x0, P0``).
    x, P : ndarray, same shapes
        Filtered state and covariance (after the fix of state ``k``, if any was accepted).
    has_fix, accepted : ndarray of bool, shape ([B,] n+1)
        A fix was given / was used in an update (False where it was gated out).
    nis : ndarray, shape ([B,] n+1)
        Normalised innovation squared of each given fix (NaN where there was none).
    gate_nis : float or None
        The gate used.
    """

    x_prior: np.ndarray
    P_prior: np.ndarray
    x: np.ndarray
    P: np.ndarray
    has_fix: np.ndarray
    accepted: np.ndarray
    nis: np.ndarray
    gate_nis: float | None = None

    @property
    def rejected(self) -> np.ndarray:
        """Fixes given but rejected by the gate."""
        return self.has_fix & ~self.accepted

    @property
    def n_rejected(self):
        """Number of gated-out fixes (per walk for a batch)."""
        return self.rejected.sum(axis=-1)


def _as_batch(a, shape, name, dtype=np.float64):
    a = np.asarray(a, dtype=dtype)
    try:
        return np.broadcast_to(a, shape)
    except ValueError:
        raise ValueError(f"{name} has shape {a.shape}, expected something broadcastable to {shape}") from None


def _check_finite(a, name):
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{name} is not finite at index {tuple(int(i) for i in bad[0])}")


def _prepare(x0_m, P0_m2, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2, R_m2, sigma_theta_rad=0.0):
    theta = np.asarray(theta_rad, dtype=np.float64)
    if theta.ndim not in (1, 2):
        raise ValueError(f"theta_rad must have shape (n,) or (B, n), got {theta.shape}")
    batch = theta.ndim == 2
    if not batch:
        theta = theta[None]
    B, n = theta.shape
    theta = np.ascontiguousarray(theta)
    step = _as_batch(step_m if batch else np.asarray(step_m, dtype=np.float64)[None], (B, n), "step_m")
    sig = _as_batch(sigma_sl_m if batch or np.ndim(sigma_sl_m) == 0 else np.asarray(sigma_sl_m)[None],
                    (B, n), "sigma_sl_m")
    sth = _as_batch(sigma_theta_rad if batch or np.ndim(sigma_theta_rad) == 0 else
                    np.asarray(sigma_theta_rad)[None], (B, n), "sigma_theta_rad")
    for a, name in ((theta, "theta_rad"), (step, "step_m"), (sig, "sigma_sl_m"), (sth, "sigma_theta_rad")):
        _check_finite(a, name)
    if (step < 0).any():
        raise ValueError(f"step_m must be >= 0 (index {tuple(int(i) for i in np.argwhere(step < 0)[0])})")
    if (sig < 0).any() or (sth < 0).any():
        raise ValueError("sigma_sl_m and sigma_theta_rad must be >= 0")
    x0 = _as_batch(x0_m, (B, 2), "x0_m")
    P0 = _as_batch(P0_m2, (B, 2, 2), "P0_m2")
    _check_finite(x0, "x0_m")
    _check_finite(P0, "P0_m2")
    if not np.allclose(P0, np.swapaxes(P0, -1, -2)) or (np.linalg.eigvalsh(P0) <= 0).any():
        raise ValueError("P0_m2 must be symmetric positive definite")
    z = np.asarray(z_m, dtype=np.float64)
    z = _as_batch(z if batch else z[None], (B, n + 1, 2), "z_m (n+1 fixes for n steps)")
    nan = np.isnan(z)
    partial = nan[..., 0] != nan[..., 1]
    if partial.any():
        w, k = (int(i) for i in np.argwhere(partial)[0])
        raise ValueError(f"z_m row {k}{f' of walk {w}' if batch else ''} has one NaN coordinate; "
                         "a missing fix must be NaN in both")
    has_fix = ~nan[..., 0]
    if np.isinf(z[has_fix]).any():
        raise ValueError("z_m contains infinite values")
    if (r_var_m2 is None) == (R_m2 is None):
        raise ValueError("give exactly one of r_var_m2 (isotropic variance, R = var I) and R_m2 (full 2x2)")
    if R_m2 is None:
        r = np.asarray(r_var_m2, dtype=np.float64)
        r = _as_batch(r if batch or r.ndim == 0 else r[None], (B, n + 1), "r_var_m2")
        R = r[..., None, None] * np.eye(2)
    else:
        R = np.asarray(R_m2, dtype=np.float64)
        R = _as_batch(R if batch or R.ndim == 2 else R[None], (B, n + 1, 2, 2), "R_m2")
    Rf = R[has_fix]
    if Rf.size:
        if not np.isfinite(Rf).all():
            raise ValueError("R of a given fix is not finite (only states without a fix may have NaN R)")
        ev = np.linalg.eigvalsh(0.5 * (Rf + np.swapaxes(Rf, -1, -2)))
        asym = ~np.isclose(Rf, np.swapaxes(Rf, -1, -2)).all(axis=(-1, -2))
        bad = np.flatnonzero((ev <= 0).any(axis=-1) | asym)
        if bad.size:
            w, k = (int(i) for i in np.argwhere(has_fix)[bad[0]])
            raise ValueError(f"R of the fix at state {k}{f' of walk {w}' if batch else ''} must be symmetric "
                             "positive definite")
    return batch, B, n, theta, step, sig, sth, x0, P0, z, has_fix, R


def filter_walks(x0_m, P0_m2, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2=None, R_m2=None,
                 gate_nis: float | None = None, sigma_theta_rad=0.0) -> StepKFResult:
    """Run the step filter over one walk or a batch of walks, vectorised across walks.

    Parameters
    ----------
    x0_m : array_like, shape ([B,] 2)
        Initial position, metres.
    P0_m2 : array_like, shape ([B,] 2, 2)
        Initial covariance, symmetric positive definite, m^2.
    theta_rad, step_m, sigma_sl_m : array_like, shape ([B,] n)
        Heading, length and length standard deviation of each step (``sigma_sl_m`` may be a
        scalar; see :func:`sigma_sl_paper_m` for the paper's Table 4).
    z_m : array_like, shape ([B,] n+1, 2)
        Wi-Fi fix at each state; a row of NaN = no fix.
    r_var_m2 : array_like, shape ([B,] n+1) or scalar
        Isotropic fix variance (``R = sigma_RF^2 I``, the paper's model), or
    R_m2 : array_like, shape ([B,] n+1, 2, 2)
        full fix covariances (exactly one of the two). Ignored (may be NaN) where there is no fix.
    gate_nis : float or None
        Reject a fix whose normalised innovation squared exceeds this (see :func:`nis_gate`).
    sigma_theta_rad : array_like, shape ([B,] n) or scalar
        Heading error standard deviation per step (beyond the paper; 0 = the paper's Q).

    Returns
    -------
    StepKFResult
        Arrays with a leading batch axis only if ``theta_rad`` was 2-D.

    References
    ----------
    i-Loc thesis, eq. (20)-(26).
    """
    batch, B, n, theta, step, sig, sth, x0, P0, z, has_fix, R = _prepare(
        x0_m, P0_m2, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2, R_m2, sigma_theta_rad)
    # F = I: the prediction over steps j+1..k is x_j + sum(b d), P_j + sum(Q) (eq. 22 summed), so the
    # loop only visits states that carry a fix; every other state is filled in from cumulative sums.
    cx = np.zeros((B, n + 1, 2))
    cx[:, 1:] = np.cumsum(step_control(theta) * step[..., None], axis=1)
    cP = np.zeros((B, n + 1, 2, 2))
    cP[:, 1:] = np.cumsum(step_process_noise(theta, sig, step, sth), axis=1)
    rows = np.arange(B)
    xa, Pa, ja = np.array(x0), np.array(P0), np.zeros(B, dtype=np.int64)  # last anchor (state ja)
    ux = np.empty((B, n + 1, 2))
    uP = np.empty((B, n + 1, 2, 2))
    nis = np.full((B, n + 1), np.nan)
    acc = np.zeros((B, n + 1), dtype=bool)
    eye = np.eye(2)
    for k in np.flatnonzero(has_fix.any(axis=0)):
        x = xa + (cx[:, k] - cx[rows, ja])
        P = Pa + (cP[:, k] - cP[rows, ja])
        fix = has_fix[:, k]
        zk = np.where(fix[:, None], z[:, k], x)
        Rk = np.where(fix[:, None, None], R[:, k], eye)
        _, _, nk = innovation(x, P, zk, Rk)
        use = fix if gate_nis is None else fix & (nk <= gate_nis)
        nis[:, k] = np.where(fix, nk, np.nan)
        acc[:, k] = use
        if use.any():
            xu, Pu = kf_update(x, P, zk, Rk)
            ux[:, k] = xu
            uP[:, k] = Pu
            xa = np.where(use[:, None], xu, xa)
            Pa = np.where(use[:, None, None], Pu, Pa)
            ja = np.where(use, k, ja)
    # anchors: the initial state, then every accepted update
    ax = np.where(acc[..., None], ux, 0.0)
    aP = np.where(acc[..., None, None], uP, 0.0)
    ax[:, 0] = np.where(acc[:, :1], ux[:, 0], x0)
    aP[:, 0] = np.where(acc[:, :1, None], uP[:, 0], P0)
    states = np.arange(n + 1)
    last_le = np.maximum.accumulate(np.where(acc, states, 0), axis=1)  # last anchor at or before k
    r2 = rows[:, None]
    xf = ax[r2, last_le] + (cx - cx[r2, last_le])
    Pf = aP[r2, last_le] + (cP - cP[r2, last_le])
    xf[acc] = ux[acc]
    Pf[acc] = uP[acc]
    xp = np.empty_like(xf)
    Pp = np.empty_like(Pf)
    xp[:, 0], Pp[:, 0] = x0, P0
    last_lt = last_le[:, :-1]  # last anchor strictly before k (k >= 1)
    xp[:, 1:] = ax[r2, last_lt] + (cx[:, 1:] - cx[r2, last_lt])
    Pp[:, 1:] = aP[r2, last_lt] + (cP[:, 1:] - cP[r2, last_lt])
    out = (xp, Pp, xf, Pf, has_fix, acc, nis)
    if not batch:
        out = tuple(a[0] for a in out)
    return StepKFResult(*out, gate_nis=gate_nis)


def filter_walk(x0_m, P0_m2, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2=None, R_m2=None,
                gate_nis: float | None = None, sigma_theta_rad=0.0) -> StepKFResult:
    """:func:`filter_walks` for a single walk (1-D ``theta_rad``); same arguments and maths."""
    if np.ndim(theta_rad) != 1:
        raise ValueError(f"theta_rad must be 1-D for one walk, got shape {np.shape(theta_rad)}")
    return filter_walks(x0_m, P0_m2, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2=r_var_m2, R_m2=R_m2,
                        gate_nis=gate_nis, sigma_theta_rad=sigma_theta_rad)


# ----------------------------------------------------------------------------------------------
# thin class: filterpy's KalmanFilter as the engine
# ----------------------------------------------------------------------------------------------

class StepKalmanFilter:
    """The i-Loc step filter driven step by step, with :class:`filterpy.kalman.KalmanFilter` as engine.

    ``B`` and ``Q`` come from :func:`step_control` / :func:`step_process_noise`; filterpy does the
    predict (``x = F x + B u``, ``P = F P F^T + Q``) and the Joseph-form update. A test checks it
    against :func:`kf_predict_step` / :func:`kf_update` and :func:`filter_walks`.

    Parameters
    ----------
    x0_m : array_like, shape (2,)
    P0_m2 : array_like, shape (2, 2)
    gate_nis : float or None
        Innovation gate (see :func:`nis_gate`); rejected fixes are counted in ``n_rejected``.

    References
    ----------
    i-Loc thesis, eq. (20)-(26); R. Labbe, filterpy ``KalmanFilter``.
    """

    def __init__(self, x0_m, P0_m2, gate_nis: float | None = None):
        from filterpy.kalman import KalmanFilter

        self.gate_nis = gate_nis
        self.kf = KalmanFilter(dim_x=2, dim_z=2)
        self.kf.x = np.asarray(x0_m, dtype=np.float64).reshape(2, 1).copy()
        self.kf.P = np.asarray(P0_m2, dtype=np.float64).copy()
        self.kf.F = np.eye(2)
        self.kf.H = np.eye(2)
        self.n_rejected = 0

    @property
    def x(self) -> np.ndarray:
        """Current position, shape (2,), metres."""
        return self.kf.x[:, 0].copy()

    @property
    def P(self) -> np.ndarray:
        """Current covariance, shape (2, 2), m^2."""
        return self.kf.P.copy()

    def predict_step(self, theta_rad: float, step_m: float, sigma_sl_m: float, sigma_theta_rad: float = 0.0) -> None:
        """Predict over one detected step (eq. 22)."""
        b = step_control(theta_rad).reshape(2, 1)
        Q = step_process_noise(theta_rad, sigma_sl_m, step_m, sigma_theta_rad)
        self.kf.predict(u=np.array([[float(step_m)]]), B=b, Q=Q)

    def update(self, z_m, R_m2) -> bool:
        """Update with a fix (eq. 24-26); a NaN fix is "no fix". Returns whether the fix was used."""
        z = np.asarray(z_m, dtype=np.float64).reshape(2)
        if np.isnan(z).all():
            return False
        if np.isnan(z).any():
            raise ValueError("z_m has one NaN coordinate; a missing fix must be NaN in both")
        R = np.asarray(R_m2, dtype=np.float64)
        R = R * np.eye(2) if R.ndim == 0 else R
        if self.gate_nis is not None:
            _, _, nis = innovation(self.x, self.kf.P, z, R)
            if nis > self.gate_nis:
                self.n_rejected += 1
                return False
        self.kf.update(z.reshape(2, 1), R=R)
        return True

    def run(self, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2=None, R_m2=None, sigma_theta_rad=0.0) -> StepKFResult:
        """Filter a whole walk step by step (the per-step reference loop; same timeline as :func:`filter_walk`)."""
        batch, _, n, theta, step, sig, sth, x0, P0, z, has_fix, R = _prepare(
            self.x, self.kf.P, theta_rad, step_m, sigma_sl_m, z_m, r_var_m2, R_m2, sigma_theta_rad)
        if batch:
            raise ValueError("StepKalmanFilter.run takes one walk (1-D theta_rad)")
        theta, step, sig, sth, z, has_fix, R = theta[0], step[0], sig[0], sth[0], z[0], has_fix[0], R[0]
        xp = np.empty((n + 1, 2))
        Pp = np.empty((n + 1, 2, 2))
        xf = np.empty((n + 1, 2))
        Pf = np.empty((n + 1, 2, 2))
        nis = np.full(n + 1, np.nan)
        acc = np.zeros(n + 1, dtype=bool)
        for k in range(n + 1):
            if k > 0:
                self.predict_step(theta[k - 1], step[k - 1], sig[k - 1], sth[k - 1])
            xp[k] = self.kf.x[:, 0]
            Pp[k] = self.kf.P
            if has_fix[k]:
                nis[k] = innovation(xp[k], Pp[k], z[k], R[k])[2]
                acc[k] = self.update(z[k], R[k])
            xf[k] = self.kf.x[:, 0]
            Pf[k] = self.kf.P
        return StepKFResult(xp, Pp, xf, Pf, has_fix, acc, nis, gate_nis=self.gate_nis)
