"""Hartmann et al. (2010): 15-state EKF fusing a MEMS IMU with a marker-based video tracker.

Total-state EKF in the video-tracker frame ``v`` (z up, gravity ``[0, 0, -g]``; Earth rotation neglected).
State (eq. 12): ``x = [phi, theta, psi, p (3), v (3), b_w (3), b_a (3)]`` - Euler angles (rad, Z-Y-X, the
DCM of eq. 6), position (m), velocity (m/s), gyroscope bias (rad/s), accelerometer bias (m/s^2).
Input (eq. 13): ``u = [w_IMU (3), a_IMU (3)]`` with ``w_IMU = w + b_w + n_w`` and ``a_IMU = a + b_a + n_a``
(eq. 14-15). Measurement (eq. 20): yaw and position from the video tracker (roll and pitch of a camera
looking down its z axis are unreliable and not used).

Process noise ``w = [n_w, n_a, n_bw, n_ba]`` (12): white sensor noise per IMU sample and bias random walks.

References
----------
Yeh & Huang (葉濟賢, 黃偉立), image/inertial positioning survey (teaching report), sec. 5.2, eq. (6)-(29),
citing B. Hartmann, N. Link, G. F. Trommer (2010), "Indoor 3D position estimation using low-cost inertial
sensors and marker-based video-tracking", IEEE/ION PLANS 2010, pp. 319-326.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ilocalg.ins.eskf import check_covariance
from ilocalg.ins.mechanisation import GRAVITY_N_MPS2
from ilocalg.units import wrap_angle_rad

__all__ = [
    "HARTMANN_N_STATES",
    "euler_rate_matrix",
    "hartmann_f",
    "hartmann_jacobians",
    "hartmann_h",
    "HARTMANN_H",
    "hartmann_predict",
    "hartmann_correct",
    "repair_psd",
    "HartmannResult",
    "run_hartmann",
    "HartmannEKF",
]

HARTMANN_N_STATES = 15
#: Measurement Jacobian of eq. (23): rows (yaw, x, y, z).
HARTMANN_H = np.zeros((4, HARTMANN_N_STATES))
HARTMANN_H[0, 2] = 1.0
HARTMANN_H[1:4, 3:6] = np.eye(3)


def euler_rate_matrix(phi_rad: float, theta_rad: float) -> np.ndarray:
    """``E`` with ``d(phi, theta, psi)/dt = E w_b`` (eq. 7-9), shape (3, 3)."""
    sf, cf = math.sin(phi_rad), math.cos(phi_rad)
    ct, tt = math.cos(theta_rad), math.tan(theta_rad)
    return np.array([[1.0, sf * tt, cf * tt], [0.0, cf, -sf], [0.0, sf / ct, cf / ct]])


def _flat(n_cols: int, cells) -> np.ndarray:
    return np.array([i * n_cols + j for i, j in cells], dtype=np.intp)


def _block(rows, cols):
    return [(i, j) for i in rows for j in cols]


_N = HARTMANN_N_STATES
#: Where :func:`_model` writes the state-dependent entries of Phi (row-major within each block, in its order).
_PHI_IDX = _flat(_N, [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)] + _block(range(3), range(9, 12))
                 + _block(range(3, 6), range(3)) + _block(range(3, 6), range(12, 15)) + _block(range(6, 9), range(3))
                 + _block(range(6, 9), range(12, 15)) + [(3, 6), (4, 7), (5, 8)])
_PHI_ONES = np.eye(_N)
#: W's blocks taken from Phi: W[0:3, 0:3] = Phi[0:3, 9:12], W[3:9, 3:6] = Phi[3:9, 12:15]; W[9:15, 6:12] = I.
_W_IDX = _flat(12, _block(range(3), range(3)) + _block(range(3, 9), range(3, 6)))
_W_FROM_PHI = _flat(_N, _block(range(3), range(9, 12)) + _block(range(3, 9), range(12, 15)))
_W_ONES = np.zeros((_N, 12))
_W_ONES[9:15, 6:12] = np.eye(6)


def _model(x, u, dt_s: float):
    """``f(x, u, 0)`` (eq. 18-19) and its Jacobians ``Phi`` (eq. 21) and ``W`` (eq. 22) in one pass.

    Written with scalar maths on the Euler angles (the DCM of eq. 6 and its partial derivatives in closed
    form) because the filter calls it at 400 Hz.
    """
    # Python floats from here on (the same IEEE operations as on numpy scalars, without their overhead)
    xl = np.asarray(x, dtype=float).tolist()
    ul = u if type(u) is list else np.asarray(u, dtype=float).tolist()
    phi, th, psi = xl[0], xl[1], xl[2]
    sf, cf, st, ct, sp, cp = math.sin(phi), math.cos(phi), math.sin(th), math.cos(th), math.sin(psi), math.cos(psi)
    w1, w2, w3 = ul[0] - xl[9], ul[1] - xl[10], ul[2] - xl[11]
    a1, a2, a3 = ul[3] - xl[12], ul[4] - xl[13], ul[5] - xl[14]
    tt, sec = st / ct, 1.0 / ct
    c = [[cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
         [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
         [-st, ct * sf, ct * cf]]
    e = [[1.0, sf * tt, cf * tt], [0.0, cf, -sf], [0.0, sf * sec, cf * sec]]
    # d(C a)/d(phi, theta, psi), columns
    d_phi = ((cp * st * cf + sp * sf) * a2 + (-cp * st * sf + sp * cf) * a3,
             (sp * st * cf - cp * sf) * a2 + (-sp * st * sf - cp * cf) * a3,
             ct * cf * a2 - ct * sf * a3)
    d_th = (-cp * st * a1 + cp * ct * sf * a2 + cp * ct * cf * a3,
            -sp * st * a1 + sp * ct * sf * a2 + sp * ct * cf * a3,
            -ct * a1 - st * sf * a2 - st * cf * a3)
    d_psi = (-sp * ct * a1 + (-sp * st * sf - cp * cf) * a2 + (-sp * st * cf + cp * sf) * a3,
             cp * ct * a1 + (cp * st * sf - sp * cf) * a2 + (cp * st * cf + sp * sf) * a3,
             0.0)
    # d(E w)/d(phi, theta)
    dEw_phi = ((cf * w2 - sf * w3) * tt, -sf * w2 - cf * w3, (cf * w2 - sf * w3) * sec)
    dEw_th = ((sf * w2 + cf * w3) * sec * sec, 0.0, (sf * w2 + cf * w3) * st * sec * sec)
    # the two products stay numpy matmuls (BLAS: their rounding); the rest element by element, in the order
    # of the array expressions x[0:3] + (E w) dt, x[3:6] + x[6:9] dt + (0.5 dt dt) acc_v, x[6:9] + dt acc_v
    av = (np.array(c) @ np.array([a1, a2, a3]) + GRAVITY_N_MPS2).tolist()
    ew = (np.array(e) @ np.array([w1, w2, w3])).tolist()
    h = 0.5 * dt_s * dt_s
    x_new = np.array([xl[0] + ew[0] * dt_s, xl[1] + ew[1] * dt_s, xl[2] + ew[2] * dt_s,
                      xl[3] + xl[6] * dt_s + h * av[0], xl[4] + xl[7] * dt_s + h * av[1],
                      xl[5] + xl[8] * dt_s + h * av[2],
                      xl[6] + dt_s * av[0], xl[7] + dt_s * av[1], xl[8] + dt_s * av[2], *xl[9:15]])
    # Phi (eq. 21) and W (eq. 22): the identity / zeros with the entries below written in one assignment each
    # (scalar products in the order the block-wise array expressions used, so the same bits; the filter calls
    # this at 400 Hz, where one small array operation per block cost more than the arithmetic)
    h2, mh2, mdt = h, -0.5 * dt_s * dt_s, -dt_s
    dca = (d_phi, d_th, d_psi)  # columns of d(C a)/d(phi, theta, psi)
    vals = ([1.0 + dEw_phi[0] * dt_s, 0.0 + dEw_phi[1] * dt_s, 0.0 + dEw_phi[2] * dt_s,
             0.0 + dEw_th[0] * dt_s, 1.0 + dEw_th[1] * dt_s, 0.0 + dEw_th[2] * dt_s]
            + [-e[i][j] * dt_s for i in range(3) for j in range(3)]
            + [h2 * dca[j][i] for i in range(3) for j in range(3)]
            + [mh2 * c[i][j] for i in range(3) for j in range(3)]
            + [dt_s * dca[j][i] for i in range(3) for j in range(3)]
            + [mdt * c[i][j] for i in range(3) for j in range(3)]
            + [dt_s, dt_s, dt_s])
    Phi = _PHI_ONES.copy()
    Phi.reshape(-1)[_PHI_IDX] = vals
    W = _W_ONES.copy()
    W.reshape(-1)[_W_IDX] = Phi.reshape(-1)[_W_FROM_PHI]
    return x_new, Phi, W


def hartmann_f(x, u, dt_s: float) -> np.ndarray:
    """State transition ``f(x, u, 0)`` (eq. 18-19), noise-free; input ``u = [w_IMU, a_IMU]`` (eq. 13)."""
    return _model(x, u, dt_s)[0]


def hartmann_jacobians(x, u, dt_s: float):
    """``Phi = df/dx`` (15, 15) and ``W = df/dw`` (15, 12) at ``(x, u, 0)`` (eq. 21-22)."""
    _, Phi, W = _model(x, u, dt_s)
    return Phi, W


def hartmann_h(x) -> np.ndarray:
    """Measurement function ``h(x, 0) = [psi, p]`` (eq. 20)."""
    return np.array([x[2], x[3], x[4], x[5]])


def hartmann_predict(x, P, u, dt_s: float, Qw):
    """EKF prediction (eq. 25-26): ``x = f(x, u, 0)``, ``P = Phi P Phi^T + W Q W^T``.

    ``Qw`` (12, 12): covariance of ``w`` over the step (sensor noise per sample, bias random-walk increments).
    """
    x_new, Phi, W = _model(x, u, dt_s)
    P = Phi @ P @ Phi.T + W @ Qw @ W.T
    return x_new, 0.5 * (P + P.T)


def hartmann_correct(x, P, z, R):
    """EKF correction (eq. 27-29) with ``V = I``; the yaw innovation is wrapped to [-pi, pi).

    The covariance update is written in Joseph form, ``(I - K H) P (I - K H)^T + K R K^T`` - algebraically eq.
    (29)'s ``(I - K H) P`` with the optimal gain, but symmetric and positive semi-definite under rounding
    (which matters after a long tracker outage, when P is ill-conditioned).

    Returns ``x, P, innovation``.
    """
    H = HARTMANN_H
    innov = np.asarray(z, dtype=float) - hartmann_h(x)
    innov[0] = wrap_angle_rad(innov[0])
    S = H @ P @ H.T + R
    K = np.linalg.solve(S, H @ P).T
    x = x + K @ innov
    x[0:3] = wrap_angle_rad(x[0:3])
    A = np.eye(HARTMANN_N_STATES) - K @ H
    P = A @ P @ A.T + K @ R @ K.T
    return x, 0.5 * (P + P.T), innov


def repair_psd(P, rel_floor: float = 1e-15):
    """``(P, repaired)``: P itself when a Cholesky factorisation succeeds; otherwise P with its eigenvalues
    raised to ``rel_floor`` x the largest (the symmetric positive-definite matrix nearest P at that floor)."""
    try:
        np.linalg.cholesky(P)
        return P, False
    except np.linalg.LinAlgError:
        w, V = np.linalg.eigh(0.5 * (P + P.T))
        w = np.maximum(w, rel_floor * max(w[-1], 1e-300))
        return (V * w) @ V.T, True


@dataclass(frozen=True)
class HartmannResult:
    """``x`` (N, 15) and ``sd`` (N, 15) after each IMU epoch; ``vt_idx`` (M,) IMU epoch of each
    video-tracker measurement, ``prior_at_vt`` (M, 15) the predicted state just before its correction;
    ``n_psd_repairs`` how often the predicted covariance failed a Cholesky test during an outage and was
    repaired (:func:`repair_psd`)."""

    t_s: np.ndarray
    x: np.ndarray
    sd: np.ndarray
    vt_idx: np.ndarray
    prior_at_vt: np.ndarray
    n_psd_repairs: int = 0


def _noise_cov(gyr_sd_radps, acc_sd_mps2, gyr_bias_rw, acc_bias_rw, dt_s):
    return np.diag(np.concatenate([np.full(3, gyr_sd_radps**2), np.full(3, acc_sd_mps2**2),
                                   np.full(3, gyr_bias_rw**2 * dt_s), np.full(3, acc_bias_rw**2 * dt_s)]))


#: Default video-tracker measurement sd: yaw (rad), x, y, z (m) (assumption: millimetre tracking, see
#: ``data/hartmann/README.md``).
VT_SD_DEFAULT = (float(np.deg2rad(1.0)), 0.003, 0.003, 0.008)

# ---- published values: Yeh & Huang's survey, sec. 5.1, the ADIS16350 set-up of Hartmann et al. (2010) -------
#: Gyroscope white-noise sd per IMU sample, deg/s.
GYR_SD_DEFAULT_DPS = 0.4
#: Accelerometer white-noise sd per IMU sample, m/s^2.
ACC_SD_DEFAULT_MPS2 = 0.05
# ---- end of published values -------------------------------------------------------------------------------
#: :data:`GYR_SD_DEFAULT_DPS` in rad/s.
GYR_SD_DEFAULT_RADPS = float(np.deg2rad(GYR_SD_DEFAULT_DPS))


#: During an outage the predicted covariance is tested for positive definiteness every this many IMU epochs.
_PSD_CHECK_EPOCHS = 400


def run_hartmann(t_s, gyr_b_radps, acc_b_mps2, t_vt_s, z_vt, x0, P0, gyr_sd_radps=GYR_SD_DEFAULT_RADPS,
                 acc_sd_mps2=ACC_SD_DEFAULT_MPS2, gyr_bias_rw_radps_rsqrt_s=1e-4, acc_bias_rw_mps2_rsqrt_s=1e-3,
                 vt_sd=VT_SD_DEFAULT) -> HartmannResult:
    """Run the 15-state EKF over an IMU log (input u) with video-tracker measurements (yaw, x, y, z).

    Parameters
    ----------
    t_s : (N,) IMU times; gyr_b_radps, acc_b_mps2 : (N, 3); sample k drives the step k -> k+1
    t_vt_s : (M,) video-tracker times (each applied at the first IMU epoch at or after it)
    z_vt : (M, 4) yaw (rad) and position (m)
    x0 : (15,) initial state; P0 : (15, 15)
    gyr_sd_radps, acc_sd_mps2 : white noise sd per IMU sample (the paper: 0.4 deg/s, 0.05 m/s^2)
    vt_sd : sd of the video measurement (yaw rad, x, y, z m)

    References
    ----------
    Yeh & Huang (survey), sec. 5.2, eq. (12)-(29), citing Hartmann et al. (2010).
    """
    t_s = np.asarray(t_s, dtype=float)
    gyr = np.asarray(gyr_b_radps, dtype=float)
    acc = np.asarray(acc_b_mps2, dtype=float)
    n = t_s.size
    if gyr.shape != (n, 3) or acc.shape != (n, 3):
        raise ValueError(f"gyr_b_radps and acc_b_mps2 must have shape ({n}, 3)")
    t_vt = np.asarray(t_vt_s, dtype=float)
    z_vt = np.asarray(z_vt, dtype=float)
    if z_vt.shape != (t_vt.size, 4):
        raise ValueError(f"z_vt must have shape ({t_vt.size}, 4) (yaw, x, y, z), got {z_vt.shape}")
    if t_vt.size and (t_vt.min() < t_s[0] or t_vt.max() > t_s[-1]):
        raise ValueError("t_vt_s must lie within the IMU log")
    x0 = np.asarray(x0, dtype=float)
    if x0.shape != (HARTMANN_N_STATES,) or not np.all(np.isfinite(x0)):
        raise ValueError(f"x0 must be a finite array of shape (15,), got {x0.shape}")
    P0 = check_covariance("P0", P0, HARTMANN_N_STATES)
    for name, v in (("gyr_sd_radps", gyr_sd_radps), ("acc_sd_mps2", acc_sd_mps2),
                    ("gyr_bias_rw_radps_rsqrt_s", gyr_bias_rw_radps_rsqrt_s),
                    ("acc_bias_rw_mps2_rsqrt_s", acc_bias_rw_mps2_rsqrt_s)):
        if not (np.isfinite(v) and 0 <= v < 1e6):
            raise ValueError(f"{name} (process noise Q) must be finite and in [0, 1e6), got {v}")
    vt = np.asarray(vt_sd, dtype=float)
    if vt.shape != (4,) or not np.all(np.isfinite(vt)) or np.any(vt < 1e-6) or np.any(vt > 1e6):
        raise ValueError(f"vt_sd (measurement noise R) must be 4 finite sds in [1e-6, 1e6], got {vt_sd!r}")
    R = np.diag(np.square(vt))
    vt_idx = np.searchsorted(t_s, t_vt, side="left")
    vt_at = {}
    for j, k in enumerate(vt_idx.tolist()):
        vt_at.setdefault(k, []).append(j)
    xs = np.empty((n, HARTMANN_N_STATES))
    sds = np.empty((n, HARTMANN_N_STATES))
    prior = np.empty((t_vt.size, HARTMANN_N_STATES))
    x, P = x0.copy(), np.asarray(P0, dtype=float).copy()
    dt_all = np.diff(t_s).tolist()  # Python floats: the loop reads one value at a time
    u_all = np.hstack([gyr, acc]).tolist()
    Qw_cache: dict[float, np.ndarray] = {}
    n_rep = 0
    since_fix = 0
    for k in range(n):
        if k > 0:
            dt = dt_all[k - 1]
            Qw = Qw_cache.get(dt)
            if Qw is None:
                Qw = Qw_cache[dt] = _noise_cov(gyr_sd_radps, acc_sd_mps2, gyr_bias_rw_radps_rsqrt_s,
                                               acc_bias_rw_mps2_rsqrt_s, dt)
            x, P = hartmann_predict(x, P, u_all[k - 1], dt, Qw)
            since_fix += 1
            if since_fix % _PSD_CHECK_EPOCHS == 0:
                # long prediction without a fix: keep P positive definite at rounding level
                P, rep = repair_psd(P)
                n_rep += rep
        if k in vt_at:
            since_fix = 0
        for j in vt_at.get(k, ()):
            prior[j] = x
            x, P, _ = hartmann_correct(x, P, z_vt[j], R)
        xs[k] = x
        sds[k] = P.diagonal()  # variances; the square roots are taken at once below
    return HartmannResult(t_s=t_s, x=xs, sd=np.sqrt(sds), vt_idx=vt_idx, prior_at_vt=prior, n_psd_repairs=n_rep)


class HartmannEKF:
    """Thin stateful wrapper over :func:`hartmann_predict` / :func:`hartmann_correct`.

    Parameters
    ----------
    x0 : (15,) initial state; P0 : (15, 15); Qw : (12, 12) noise covariance per step; R : (4, 4)
    """

    def __init__(self, x0, P0, Qw, R):
        self.x = np.asarray(x0, dtype=float).copy()
        self.P = check_covariance("P0", P0, HARTMANN_N_STATES).copy()
        self.Qw = check_covariance("Qw", Qw, 12)
        self.R = check_covariance("R", R, 4)
        if np.linalg.eigvalsh(self.R)[0] <= 0:
            raise ValueError("R: the video-tracker noise covariance must be positive definite")

    def predict(self, u, dt_s: float) -> HartmannEKF:
        self.x, self.P = hartmann_predict(self.x, self.P, np.asarray(u, dtype=float), dt_s, self.Qw)
        return self

    def correct(self, z) -> HartmannEKF:
        self.x, self.P, _ = hartmann_correct(self.x, self.P, z, self.R)
        return self
