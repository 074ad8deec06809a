"""The 21-state error-state EKF (closed loop) of the smartphone INS.

State (eq. 1), ``x = [dr, dv, dphi, b_acc, b_gyr, s_acc, s_gyr]``, each a 3-vector:
position error (m, ENU), velocity error (m/s, ENU), attitude error (rad, nav-frame small
rotation with ``mat_nb_true = (I + [dphi x]) mat_nb_est``), accelerometer bias (m/s^2), gyroscope
bias (rad/s), accelerometer and gyroscope scale-factor errors (dimensionless). Every error is
``true - estimated``.

Sensor model: ``f_raw = (1 + s_acc) f + b_acc + noise`` and ``w_raw = (1 + s_gyr) w + b_gyr + noise``
(per axis), so the corrected sensors are ``(raw - b) / (1 + s)``.

Closed loop: after every update the estimated errors are fed back into the mechanisation and
the sensor-error estimates (``correct_nav``) and the error state is reset to zero; prediction of a
zero error state (eq. 2) stays zero, only the covariance propagates (eq. 3). The feedback applied
at each epoch is stored so that the RTS smoother (:mod:`ilocalg.ins.smoother`) can run on the
stored filter.

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 3.1, eq. (1) state, (2)-(3) prediction, (4)-(6) update (Joseph
form), sec. 3.2 NHC / ZUPT / WVC; Shin (2005), "Estimation techniques for low-cost inertial
navigation", UCGE 20219 (the psi-angle error model and closed-loop feedback).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Protocol, runtime_checkable

import numpy as np

from ilocalg.ins._linalg import solve
from ilocalg.ins.mechanisation import GRAVITY_N_MPS2, _check_imu, rotvec_to_dcm, rotvecs_to_dcm, skew, strapdown

__all__ = [
    "N_STATES",
    "POS",
    "VEL",
    "ATT",
    "BA",
    "BG",
    "SA",
    "SG",
    "EskfConfig",
    "Measurement",
    "PositionFix",
    "NavVelocity",
    "BodyVelocity",
    "EskfResult",
    "initial_covariance",
    "transition_matrix",
    "transition_matrices",
    "process_noise_diag",
    "eskf_predict",
    "joseph_update",
    "joseph_update_stacked",
    "position_rows",
    "nav_velocity_rows",
    "body_velocity_rows",
    "correct_sensors",
    "correct_nav",
    "check_covariance",
    "covariance_chunk",
    "MAX_VARIANCE",
    "MIN_MEAS_VARIANCE",
    "CHECKPOINT_EPOCHS",
    "run_eskf",
    "run_eskf_batch",
    "BATCH_EPOCHS",
    "BATCH_MIN_RUNS",
    "same_run",
]

N_STATES = 21
POS, VEL, ATT = slice(0, 3), slice(3, 6), slice(6, 9)
BA, BG, SA, SG = slice(9, 12), slice(12, 15), slice(15, 18), slice(18, 21)

_I3 = np.eye(3)


@dataclass(frozen=True)
class EskfConfig:
    """Process-noise densities of the 21-state model (continuous time, per axis).

    Parameters
    ----------
    acc_vrw_mps_rsqrt_s : velocity random walk of the accelerometer, m/s/sqrt(s)
    gyr_arw_rad_rsqrt_s : angle random walk of the gyroscope, rad/sqrt(s)
    acc_bias_rw_mps2_rsqrt_s, gyr_bias_rw_radps_rsqrt_s : bias random-walk densities
    acc_sf_rw_rsqrt_s, gyr_sf_rw_rsqrt_s : scale-factor random-walk densities, 1/sqrt(s)
    """

    acc_vrw_mps_rsqrt_s: float = 0.05
    gyr_arw_rad_rsqrt_s: float = 0.005
    acc_bias_rw_mps2_rsqrt_s: float = 1e-3
    gyr_bias_rw_radps_rsqrt_s: float = 1e-4
    acc_sf_rw_rsqrt_s: float = 1e-4
    gyr_sf_rw_rsqrt_s: float = 1e-4

    def __post_init__(self):
        for name, v in self.__dict__.items():
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"EskfConfig.{name} must be finite and >= 0, got {v}")


@dataclass(frozen=True)
class EskfResult:
    """Everything the filter produced, per IMU epoch (N epochs).

    ``pos_n_m`` (N, 3), ``vel_n_mps`` (N, 3), ``mat_nb`` (N, 3, 3): the navigation solution after
    feedback; ``sensor`` (N, 12): estimated ``[b_acc, b_gyr, s_acc, s_gyr]``; ``dx`` (N, 21): the
    error estimate fed back at each epoch (zero without an update); ``P_plus`` / ``P_minus`` (N, 21, 21):
    updated / predicted covariance; ``Phi`` (N, 21, 21): ``Phi[k]`` maps epoch k-1 to k (``Phi[0] = I``);
    ``nis`` (N,): normalised innovation squared of the update at each epoch (NaN without one) and
    ``n_meas`` (N,) its number of rows.

    A run with ``keep_covariance=False`` stores no (N, 21, 21) history (``P_plus``, ``P_minus``, ``Phi`` are
    None) but checkpoints: ``cp_idx`` (K,) epochs (every update epoch and at least every
    :data:`CHECKPOINT_EPOCHS` epochs) and ``cp_P`` (K, 21, 21) the covariance there, with the raw sensors
    ``gyr_b_radps`` / ``acc_b_mps2`` (N, 3), from which :func:`covariance_chunk` recomputes any stretch exactly.

    ``inputs``: what :func:`run_eskf` was given (IMU log, initial state, covariance, measurement sets, configuration,
    history mode), by reference, so that a later run can reuse the epochs it shares with this one (``prefix``).
    """

    t_s: np.ndarray
    pos_n_m: np.ndarray
    vel_n_mps: np.ndarray
    mat_nb: np.ndarray
    sensor: np.ndarray
    dx: np.ndarray
    P_plus: np.ndarray
    P_minus: np.ndarray
    Phi: np.ndarray
    nis: np.ndarray
    n_meas: np.ndarray
    config: EskfConfig = field(default_factory=EskfConfig)
    cp_idx: np.ndarray | None = None
    cp_P: np.ndarray | None = None
    gyr_b_radps: np.ndarray | None = None
    acc_b_mps2: np.ndarray | None = None
    inputs: tuple | None = field(default=None, repr=False, compare=False)


def initial_covariance(pos_sd_m=1.0, vel_sd_mps=0.1, att_sd_rad=(0.03, 0.03, 0.2), acc_bias_sd_mps2=0.1,
                       gyr_bias_sd_radps=0.01, acc_sf_sd=0.02, gyr_sf_sd=0.02) -> np.ndarray:
    """Diagonal initial covariance (21, 21) from per-block standard deviations (scalars or 3-vectors)."""
    sds = [pos_sd_m, vel_sd_mps, att_sd_rad, acc_bias_sd_mps2, gyr_bias_sd_radps, acc_sf_sd, gyr_sf_sd]
    d = np.concatenate([np.broadcast_to(np.asarray(s, dtype=float), 3) for s in sds])
    if np.any(~np.isfinite(d)) or np.any(d <= 0):
        raise ValueError("initial_covariance: every standard deviation must be finite and > 0")
    return np.diag(d**2)


def correct_sensors(gyr_raw_radps, acc_raw_mps2, sensor):
    """Corrected rate and specific force ``(raw - b) / (1 + s)``; ``sensor`` = [b_acc, b_gyr, s_acc, s_gyr].

    ``gyr_raw_radps`` and ``acc_raw_mps2`` are (3,) or (L, 3) (one sensor-error estimate for all rows).
    """
    acc = (acc_raw_mps2 - sensor[0:3]) / (1.0 + sensor[6:9])
    gyr = (gyr_raw_radps - sensor[3:6]) / (1.0 + sensor[9:12])
    return gyr, acc


#: What every transition matrix holds before its epoch's terms are written: the identity.
_PHI_CONSTANT = np.eye(N_STATES)
#: Flat (row * 21 + column) positions of dt (``dr' = dv``) and of the terms of ``-[cf x]`` (``dv' = ... dphi``):
#: ``+cf[_CF_COMPONENTS]`` at ``_DV_DPHI``, ``-cf[_CF_COMPONENTS_NEG]`` at ``_DV_DPHI_NEG``.
_DR_DV = np.array([0 * N_STATES + 3, 1 * N_STATES + 4, 2 * N_STATES + 5])
_DV_DPHI = np.array([3 * N_STATES + 7, 4 * N_STATES + 8, 5 * N_STATES + 6])
_CF_COMPONENTS = np.array([2, 0, 1])
_DV_DPHI_NEG = np.array([3 * N_STATES + 8, 4 * N_STATES + 6, 5 * N_STATES + 7])
_CF_COMPONENTS_NEG = np.array([1, 2, 0])


def transition_matrices(mat_nb, f_b_mps2, omega_b_radps, dt_s, out=None) -> np.ndarray:
    """Batched first-order transition matrices ``Phi = I + F dt`` (L, 21, 21) of the error model (eq. 2).

    ``dr' = dv``; ``dv' = -[(C f) x] dphi - C db_a - C diag(f) ds_a``;
    ``dphi' = -C db_g - C diag(w) ds_g``; sensor errors are random walks (Earth rate neglected).

    Parameters
    ----------
    mat_nb : (L, 3, 3); f_b_mps2, omega_b_radps : (L, 3) corrected sensors; dt_s : (L,)
    out : optional C-contiguous (L, 21, 21) array to write into (the filter's history)
    """
    C = np.asarray(mat_nb, dtype=float)
    L = C.shape[0]
    dt = np.asarray(dt_s, dtype=float).reshape(L, 1, 1)
    cdt = C * dt
    ncdt = -cdt
    cf = np.einsum("lij,lj->li", cdt, f_b_mps2)
    if out is None:
        out = np.empty((L, N_STATES, N_STATES))
    out[:] = _PHI_CONSTANT  # identity; zeros where the error model has no term
    flat = out.reshape(L, N_STATES * N_STATES)
    flat[:, _DR_DV] = dt[:, :, 0]
    # -[cf x]
    flat[:, _DV_DPHI] = cf[:, _CF_COMPONENTS]
    flat[:, _DV_DPHI_NEG] = -cf[:, _CF_COMPONENTS_NEG]
    out[:, 3:6, 9:12] = ncdt
    np.multiply(ncdt, np.asarray(f_b_mps2)[:, None, :], out=out[:, 3:6, 15:18])
    out[:, 6:9, 12:15] = ncdt
    np.multiply(ncdt, np.asarray(omega_b_radps)[:, None, :], out=out[:, 6:9, 18:21])
    return out


def transition_matrix(mat_nb, f_b_mps2, omega_b_radps, dt_s) -> np.ndarray:
    """One transition matrix (21, 21); see :func:`transition_matrices` (eq. 2)."""
    return transition_matrices(np.asarray(mat_nb)[None], np.asarray(f_b_mps2)[None],
                               np.asarray(omega_b_radps)[None], np.array([dt_s]))[0]


def process_noise_diag(config: EskfConfig, dt_s) -> np.ndarray:
    """Diagonal of the discrete process noise ``Q`` over a step of ``dt_s`` (eq. 3): (21,); (L, 21) for (L,) steps."""
    c = config
    per = [0.0, c.acc_vrw_mps_rsqrt_s, c.gyr_arw_rad_rsqrt_s, c.acc_bias_rw_mps2_rsqrt_s,
           c.gyr_bias_rw_radps_rsqrt_s, c.acc_sf_rw_rsqrt_s, c.gyr_sf_rw_rsqrt_s]
    return np.multiply.outer(dt_s, np.repeat(np.square(per), 3))


def _add_diag(M: np.ndarray, d) -> None:
    """``M[np.diag_indices_from(M)] += d`` in place: the same elements and the same adds, through a view of the
    diagonal when ``M`` is C-contiguous (no index arrays built: the filter does this every epoch)."""
    n = M.shape[0]
    if M.flags.c_contiguous:
        diag = M.reshape(n * n)[::n + 1]
        diag += d
    else:
        M[np.diag_indices_from(M)] += d


def eskf_predict(P, Phi, q_diag, out=None, work=None):
    """Covariance prediction ``P = Phi P Phi^T + Q`` (eq. 3) over one step, (21, 21).

    Not symmetrised here: :func:`run_eskf` symmetrises once, ``0.5 (P + P^T)``, before each update. ``out``
    (21, 21), when given, receives the result and ``work`` (21, 21) the intermediate ``Phi P`` (the same
    products, without allocating: the filter predicts every epoch); neither may be ``P``.
    """
    P = np.matmul(np.matmul(Phi, P, out=work), Phi.T, out=out)
    _add_diag(P, q_diag)
    return P


def joseph_update(P, innov, H, R_diag):
    """Kalman update in Joseph form (eq. 4-6) with a diagonal measurement noise.

    Parameters
    ----------
    P : (n, n); innov : (m,) ``z - H x`` (here ``x = 0``, closed loop); H : (m, n); R_diag : (m,)

    Returns
    -------
    dx : (n,) the estimated error, P : (n, n) updated covariance, nis : float normalised innovation squared.
    """
    PHt = P @ H.T
    S = H @ PHt
    _add_diag(S, R_diag)
    Kt = solve(S, PHt.T)  # S symmetric: K^T = S^-1 H P
    K = Kt.T
    dx = K @ innov
    A = -K @ H
    _add_diag(A, 1.0)
    P = A @ P @ A.T + (K * R_diag) @ Kt
    nis = float(innov @ solve(S, innov))
    return dx, 0.5 * (P + P.T), nis



def joseph_update_stacked(P, innov, H, R_diag):
    """:func:`joseph_update` on B updates of the same size at once: ``P`` (B, n, n), ``innov`` (B, m), ``H``
    (B, m, n), ``R_diag`` (B, m). The same operations on stacked arrays (``np.matmul`` and the LAPACK gufuncs
    loop over the matrices with the same call per matrix as for one), so each update's ``dx`` (B, n), ``P``
    (B, n, n) and ``nis`` (B,) have the same bits as :func:`joseph_update` gives it alone."""
    B, m = innov.shape
    n = P.shape[-1]
    PHt = P @ H.swapaxes(1, 2)
    S = H @ PHt
    S.reshape(B, m * m)[:, ::m + 1] += R_diag
    Kt = solve(S, PHt.swapaxes(1, 2))
    K = Kt.swapaxes(1, 2)
    dx = (K @ innov[:, :, None])[:, :, 0]
    A = -K @ H
    A.reshape(B, n * n)[:, ::n + 1] += 1.0
    P = A @ P @ A.swapaxes(1, 2) + (K * R_diag[:, None, :]) @ Kt
    nis = (innov[:, None, :] @ solve(S, innov)[:, :, None])[:, 0, 0]
    return dx, 0.5 * (P + P.swapaxes(1, 2)), nis

def position_rows(pos_n_m, z_pos_n_m):
    """Innovation (3,) and H (3, 21) of an ENU position fix (GNSS or control point)."""
    H = np.zeros((3, N_STATES))
    H[:, POS] = _I3
    return z_pos_n_m - pos_n_m, H


def nav_velocity_rows(vel_n_mps, z_vel_n_mps):
    """Innovation (3,) and H (3, 21) of an ENU velocity measurement (ZUPT: ``z = 0``)."""
    H = np.zeros((3, N_STATES))
    H[:, VEL] = _I3
    return z_vel_n_mps - vel_n_mps, H


def body_velocity_rows(mat_nb, vel_n_mps, z_vel_b_mps):
    """Innovation (3,) and H (3, 21) of a body-frame velocity measurement (NHC / WVC).

    ``v_b = C^T v`` linearised: ``dv_b = C^T dv + C^T [v x] dphi``.

    References
    ----------
    Liao et al. (2016), sec. 3.2 (NHC: lateral and vertical body velocity zero; WVC adds the
    forward walking speed of eq. 7 and relaxes the lateral/vertical weights).
    """
    Ct = mat_nb.T
    H = np.zeros((3, N_STATES))
    H[:, VEL] = Ct
    H[:, ATT] = Ct @ skew(vel_n_mps)
    return z_vel_b_mps - Ct @ vel_n_mps, H


def correct_nav(pos_n_m, vel_n_mps, mat_nb, sensor, dx):
    """Closed-loop feedback of an estimated error ``dx`` (21,) (error = true - estimated).

    Returns the corrected ``pos_n_m``, ``vel_n_mps``, ``mat_nb = exp([dphi x]) mat_nb`` and ``sensor``
    (12,) = [b_acc, b_gyr, s_acc, s_gyr]; the error state is then zero.
    """
    return (pos_n_m + dx[POS], vel_n_mps + dx[VEL], rotvec_to_dcm(dx[ATT]) @ mat_nb, sensor + dx[9:21])


@runtime_checkable
class Measurement(Protocol):
    """What :func:`run_eskf` needs of a measurement set (any object with these members will do).

    ``t_s`` (M,): measurement times, each applied at the first IMU epoch at or after it; ``name``: a
    label for messages; ``rows(j, pos_n_m, vel_n_mps, mat_nb)``: for measurement ``j`` and the current
    navigation state, the innovation ``z - h(x)`` (m,), its Jacobian ``H`` (m, 21) with respect to the
    error state and the measurement noise variances ``R_diag`` (m,).

    References
    ----------
    The same split as pyins' ``Measurement.compute_matrices`` (innovation, H, R from the current state).
    """

    t_s: np.ndarray
    name: str

    def rows(self, j: int, pos_n_m, vel_n_mps, mat_nb) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


@dataclass(frozen=True)
class _ThreeAxisMeasurement:
    """M three-axis measurements ``z`` (M, 3) with standard deviations ``sd`` (M, 3) at times ``t_s`` (M,).

    A ``NaN`` standard deviation leaves that component unused (e.g. NHC's forward axis).
    """

    t_s: np.ndarray
    z: np.ndarray
    sd: np.ndarray
    name: str = ""

    def __post_init__(self):
        label = self.name or type(self).__name__
        t = np.asarray(self.t_s, dtype=float)
        z = np.asarray(self.z, dtype=float).reshape(-1, 3) if np.size(self.z) else np.zeros((0, 3))
        sd = np.asarray(self.sd, dtype=float).reshape(-1, 3) if np.size(self.sd) else np.zeros((0, 3))
        if t.ndim != 1 or z.shape != (t.size, 3) or sd.shape != (t.size, 3):
            raise ValueError(f"{label}: t_s (M,), z and sd (M, 3) expected, got {t.shape}, {z.shape}, {sd.shape}")
        if not np.all(np.isfinite(t)) or not np.all(np.isfinite(z[np.isfinite(sd)])):
            raise ValueError(f"{label}: non-finite time or used measurement")
        if np.any(sd[np.isfinite(sd)] <= 0):
            raise ValueError(f"{label}: sd must be > 0 (NaN = unused)")
        object.__setattr__(self, "t_s", t)
        object.__setattr__(self, "z", z)
        object.__setattr__(self, "sd", sd)

    def _model(self, z_j, pos_n_m, vel_n_mps, mat_nb):
        raise NotImplementedError

    def rows(self, j, pos_n_m, vel_n_mps, mat_nb):
        """Innovation, H and R of measurement ``j`` restricted to its used components (see :class:`Measurement`)."""
        e, H = self._model(self.z[j], pos_n_m, vel_n_mps, mat_nb)
        used = np.isfinite(self.sd[j])
        return e[used], H[used], self.sd[j][used] ** 2


class PositionFix(_ThreeAxisMeasurement):
    """ENU position fixes (GNSS, surveyed control points): ``z`` in m, ``sd`` in m (:func:`position_rows`)."""

    def _model(self, z_j, pos_n_m, vel_n_mps, mat_nb):
        return position_rows(pos_n_m, z_j)


class NavVelocity(_ThreeAxisMeasurement):
    """ENU velocity measurements, m/s; ZUPT is ``z = 0`` while standing (:func:`nav_velocity_rows`)."""

    def _model(self, z_j, pos_n_m, vel_n_mps, mat_nb):
        return nav_velocity_rows(vel_n_mps, z_j)


class BodyVelocity(_ThreeAxisMeasurement):
    """Body-frame velocity measurements, m/s: NHC (lateral and vertical zero, forward unused) and WVC
    (plus the forward walking speed of eq. 7) (:func:`body_velocity_rows`)."""

    def _model(self, z_j, pos_n_m, vel_n_mps, mat_nb):
        return body_velocity_rows(mat_nb, vel_n_mps, z_j)


def _schedule(t_s, updates):
    """Map every measurement to its IMU epoch: dict epoch -> list of (set index, measurement index)."""
    sched: dict[int, list] = {}
    for i, u in enumerate(updates):
        if u.t_s.size == 0:
            continue
        if u.t_s.min() < t_s[0] or u.t_s.max() > t_s[-1]:
            raise ValueError(f"measurements {u.name or type(u).__name__}: times must lie within the IMU log "
                             f"[{t_s[0]}, {t_s[-1]}] s")
        k = np.searchsorted(t_s, u.t_s, side="left")
        for row, kk in enumerate(k.tolist()):
            sched.setdefault(kk, []).append((i, row))
    return sched


#: Measurement sets whose rows :func:`_stacked_rows` lays out ahead (their ``rows`` read only ``z``, ``sd`` and the
#: state): where in ``[position, velocity, C^T velocity]`` each component's prediction sits.
_STACKED = {PositionFix: 0, NavVelocity: 3, BodyVelocity: 6}


def _stacked_rows(t_s, updates):
    """Every update epoch's stacked measurement rows laid out ahead, for the epochs whose sets are all of the
    :data:`_STACKED` classes: ``(plan, Z, R, H, src, body)`` with ``plan`` {epoch: (a, b)} the epoch's rows
    ``a:b`` of ``Z`` (M,) measured values, ``R`` (M,) variances ``sd**2`` and ``H`` (M, 21) Jacobians (constant
    entries written; the body-velocity rows' ``C^T`` and ``C^T [v x]`` are written at the update), ``src`` (M,)
    the index of each row's prediction in ``[pos, vel, C^T vel]`` and ``body`` {epoch: (local rows, components)}
    of its body-velocity rows. The rows are those :meth:`_ThreeAxisMeasurement.rows` returns (used components
    only), in the order :func:`run_eskf` stacks them (epoch, set, measurement, component): the same values as
    stacking them at the update."""
    recs, other = [], []
    for i, u in enumerate(updates):
        if np.size(u.t_s) == 0:
            continue
        k = np.searchsorted(t_s, u.t_s, side="left")
        off = _STACKED.get(type(u))
        if off is None:
            other.append(k)
            continue
        j, c = np.nonzero(np.isfinite(u.sd))  # row-major: measurement, then component
        recs.append((np.unique(k), k[j], np.full(j.size, i), j, c, u.z[j, c], (u.sd ** 2)[j, c], off + c))
    if not recs:
        return {}, None, None, None, None, {}
    epochs = np.unique(np.concatenate([r[0] for r in recs]))
    if other:
        epochs = np.setdiff1d(epochs, np.concatenate(other))
    kk, ii, jj, cc, Z, R, src = (np.concatenate([r[n] for r in recs]) for n in range(1, 8))
    order = np.lexsort((cc, jj, ii, kk))
    kk, cc, Z, R, src = kk[order], cc[order], Z[order], R[order], src[order]
    keep = np.isin(kk, epochs)
    kk, cc, Z, R, src = kk[keep], cc[keep], Z[keep], R[keep], src[keep]
    a = np.searchsorted(kk, epochs, side="left")
    b = np.searchsorted(kk, epochs, side="right")
    plan = dict(zip(epochs.tolist(), zip(a.tolist(), b.tolist(), strict=True), strict=True))
    H = np.zeros((kk.size, N_STATES))
    const = np.flatnonzero(src < 6)  # position rows: 1 at the position component; ENU velocity rows: at velocity
    H[const, src[const]] = 1.0
    body = {}
    ib = np.flatnonzero(src >= 6)
    if ib.size:
        eb, first = np.unique(kk[ib], return_index=True)
        for e, grp in zip(eb.tolist(), np.split(ib, first[1:]), strict=True):
            body[e] = (grp - plan[e][0], cc[grp])
    return plan, Z, R, H, src.astype(np.intp), body


def _same_bits(a, b) -> bool:
    """Whether two float arrays hold the same bits (NaN payloads and signed zeros included)."""
    if a is b:
        return True
    a, b = np.ascontiguousarray(a, dtype=float), np.ascontiguousarray(b, dtype=float)
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


def _rows_record(t_s, updates, codes: dict):
    """Every measurement row of ``updates`` in the order :func:`run_eskf` stacks them: ``(epoch (R,), content
    (R, 7))``, sorted by epoch, set and row. ``content`` is a code for what computes the row (the class of a
    :class:`PositionFix`-like set; the object itself for any other :class:`Measurement`, with its row index) and
    the bits of ``z`` and ``sd``: two rows with equal content give the same innovation, H and R."""
    ks, keys, contents = [], [], []
    for i, u in enumerate(updates):
        m = np.size(u.t_s)
        if m == 0:
            continue
        k = np.searchsorted(t_s, np.asarray(u.t_s, dtype=float), side="left")
        three = isinstance(u, _ThreeAxisMeasurement)
        c = np.empty((m, 7), dtype=np.int64)
        c[:, 0] = codes.setdefault(type(u) if three else ("object", id(u)), len(codes))
        if three:
            c[:, 1:4] = np.ascontiguousarray(u.z).view(np.int64)
            c[:, 4:7] = np.ascontiguousarray(u.sd).view(np.int64)
        else:
            c[:, 1:] = np.arange(m)[:, None]
        ks.append(k)
        keys.append(np.column_stack([k, np.full(m, i), np.arange(m)]))
        contents.append(c)
    if not ks:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 7), dtype=np.int64)
    key = np.concatenate(keys)
    order = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
    return np.concatenate(ks)[order], np.concatenate(contents)[order]


def _first_difference(old: tuple | None, inputs: tuple) -> tuple[int, np.ndarray]:
    """The first epoch where two runs' inputs (as stored in :attr:`EskfResult.inputs`) differ (N when they
    never do, -1 for another IMU log, initial state, configuration or history mode), and the update epochs of
    ``inputs`` before it."""
    if old is None:
        return -1, np.zeros(0, dtype=np.int64)
    t_s, updates, config, full = inputs[0], inputs[8], inputs[9], inputs[10]
    if old[9] != config or old[10] != full or not all(_same_bits(a, b) for a, b in zip(old[:8], inputs[:8],
                                                                                         strict=True)):
        return -1, np.zeros(0, dtype=np.int64)
    codes: dict = {}
    ka, ca = _rows_record(t_s, old[8], codes)
    kb, cb = _rows_record(t_s, updates, codes)
    m = min(ka.size, kb.size)
    same = (ka[:m] == kb[:m]) & np.all(ca[:m] == cb[:m], axis=1)
    p = int(np.argmin(same)) if m and not same.all() else m
    if p < ka.size or p < kb.size:
        first = min(ka[p] if p < ka.size else t_s.size, kb[p] if p < kb.size else t_s.size)
    else:
        first = t_s.size  # the same measurements throughout
    return int(first), kb[:p][kb[:p] < first]


def _resume_point(prev: EskfResult, inputs: tuple) -> int:
    """The last update epoch of ``prev`` before the first epoch where its inputs and ``inputs`` differ: every
    epoch up to it is the same computation on the same numbers in both runs (-1: none)."""
    _, before = _first_difference(prev.inputs, inputs)
    return int(before[-1]) if before.size else -1


def same_run(a: EskfResult, b: EskfResult) -> bool:
    """Whether two filter results come from the same inputs, bit for bit (IMU log, initial state, covariance,
    measurements, configuration, history mode): then every output is the same, and so is any smoothing of it."""
    return a is b or (b.inputs is not None and _first_difference(a.inputs, b.inputs)[0] == b.t_s.size)


#: Largest sane variance of any state of the 21-state model (a standard deviation of 1e6 in its unit).
MAX_VARIANCE = 1e12
#: Smallest measurement variance :func:`run_eskf` accepts (a standard deviation of 1 micrometre or
#: micrometre per second): below it the innovation covariance loses precision.
MIN_MEAS_VARIANCE = 1e-12
#: Longest stretch (epochs) kept in memory at once by a run without covariance history.
CHECKPOINT_EPOCHS = 2000


def check_covariance(name: str, P, n: int | None = None, max_variance: float = MAX_VARIANCE,
                     min_eig_rel: float = 1e-9) -> np.ndarray:
    """Check a covariance matrix at a filter's entry and return it as a float array.

    It must be square (``n`` x ``n`` when given), finite, symmetric (to 1e-9 relative), positive semi-definite
    (smallest eigenvalue >= ``-min_eig_rel`` x largest) and of a sane scale (every variance <= ``max_variance``).

    Raises
    ------
    ValueError naming ``name`` and what is wrong.
    """
    P = np.asarray(P, dtype=float)
    if P.ndim != 2 or P.shape[0] != P.shape[1] or (n is not None and P.shape != (n, n)):
        want = f"({n}, {n})" if n is not None else "square"
        raise ValueError(f"{name}: expected a {want} covariance matrix, got shape {P.shape}")
    if not np.all(np.isfinite(P)):
        i, j = np.argwhere(~np.isfinite(P))[0]
        raise ValueError(f"{name}: element [{i}, {j}] is {P[i, j]}; a covariance must be finite")
    d = np.diag(P)
    if np.any(d < 0):
        i = int(np.argmin(d))
        raise ValueError(f"{name}: variance [{i}, {i}] is negative ({d[i]:g}); a covariance has variances >= 0")
    if np.any(d > max_variance):
        i = int(np.argmax(d))
        raise ValueError(f"{name}: variance [{i}, {i}] = {d[i]:g} exceeds {max_variance:g} (a unit mistake?)")
    scale = max(float(np.max(np.abs(P))), 1e-300)
    asym = float(np.max(np.abs(P - P.T)))
    if asym > 1e-9 * scale:
        raise ValueError(f"{name}: not symmetric (largest |P - P^T| = {asym:g})")
    ev = np.linalg.eigvalsh(0.5 * (P + P.T))
    if ev[0] < -min_eig_rel * max(ev[-1], 0.0) - 1e-300:
        raise ValueError(f"{name}: not positive semi-definite (smallest eigenvalue {ev[0]:g})")
    return P


def _check_measurement_noise(name: str, R_diag) -> None:
    R = np.asarray(R_diag, dtype=float)
    bad = ~np.isfinite(R) | (R < MIN_MEAS_VARIANCE) | (R > MAX_VARIANCE)
    if np.any(bad):
        v = R[bad][0]
        raise ValueError(f"measurements {name}: noise variance {v:g} outside [{MIN_MEAS_VARIANCE:g}, "
                         f"{MAX_VARIANCE:g}] (R must be finite, > 0 and of a sane scale)")


def _predict_stretch(P, Ph, qd, P_minus_out=None, P_plus_out=None, cps=None, k0=0):
    """Covariance prediction over a stretch (eq. 3), one epoch at a time; stores histories or checkpoints.

    With histories, each epoch's prediction is written straight into ``P_minus_out`` (then copied to
    ``P_plus_out`` at once); without, two buffers take turns. Returns the last prediction (a view of
    ``P_minus_out`` or a buffer of this call).
    """
    work = np.empty((N_STATES, N_STATES))
    L = Ph.shape[0]
    if P_minus_out is not None and P_minus_out.flags.c_contiguous:
        # eskf_predict's products and adds, inlined: the diagonals of the whole stretch as one strided view
        # np.dot, not np.matmul: for two 2-D float64 operands both hand the same cblas_dgemm call (same
        # transposition flags, sizes and strides) to BLAS, so the same bits; np.dot skips the gufunc set-up
        diag = P_minus_out.reshape(L, N_STATES * N_STATES)[:, ::N_STATES + 1]
        dot = np.dot
        for j in range(L):
            Phj = Ph[j]
            P = dot(dot(Phj, P, out=work), Phj.T, out=P_minus_out[j])
            diag[j] += qd[j]
        P_plus_out[...] = P_minus_out
        return P
    if P_minus_out is not None:
        for j in range(L):
            P = eskf_predict(P, Ph[j], qd[j], out=P_minus_out[j], work=work)
        P_plus_out[...] = P_minus_out
        return P
    bufs = (np.empty((N_STATES, N_STATES)), np.empty((N_STATES, N_STATES)))
    for j in range(L):
        P = eskf_predict(P, Ph[j], qd[j], out=bufs[j & 1], work=work)
        if cps is not None and (k0 + 1 + j) % CHECKPOINT_EPOCHS == 0:
            cps.append((k0 + 1 + j, P.copy()))
    return P


class _Run:
    """One filter run between its epochs: what :func:`run_eskf` and :func:`run_eskf_batch` set up, update and
    return (the same code for both: the prediction between two update epochs is the only part they do apart).

    ``mode``: "full" (covariance histories), "cp" (checkpoints) or "nav" (no covariance kept: the navigation
    solution, sensor estimates, fed-back errors and NIS only; :func:`run_eskf_batch` only). The navigation
    solution never depends on it.
    """

    def __init__(self, t_s, gyr_b_radps, acc_b_mps2, pos0_n_m, vel0_n_mps, mat0_nb, P0, updates, config, sensor0,
                 mode, prefix, arrays=None):
        t_s, gyr, acc = _check_imu(t_s, gyr_b_radps, acc_b_mps2)
        config = config or EskfConfig()
        P0 = check_covariance("P0", P0, N_STATES)
        for name, v, shape in (("pos0_n_m", pos0_n_m, (3,)), ("vel0_n_mps", vel0_n_mps, (3,)),
                               ("mat0_nb", mat0_nb, (3, 3))):
            a = np.asarray(v, dtype=float)
            if a.shape != shape or not np.all(np.isfinite(a)):
                raise ValueError(f"{name} must be a finite array of shape {shape}, got {a.shape}")
        updates = list(updates)
        for u in updates:
            if not isinstance(u, Measurement):
                raise ValueError(f"updates must obey the Measurement protocol (t_s, name, rows), got "
                                 f"{type(u).__name__}")
            sd = getattr(u, "sd", None)
            if sd is not None:
                sdv = np.asarray(sd, dtype=float)
                _check_measurement_noise(u.name or type(u).__name__, np.square(sdv[np.isfinite(sdv)]))
        self.t_s, self.gyr, self.acc, self.config, self.mode = t_s, gyr, acc, config, mode
        self.updates = updates
        self.sched = _schedule(t_s, updates)
        self.plan, self.Z_all, self.R_all, self.H_all, self.src_all, self.body = _stacked_rows(t_s, updates)
        s0 = np.zeros(12) if sensor0 is None else np.asarray(sensor0, dtype=float).copy()
        P = 0.5 * (P0 + P0.T)
        full = mode == "full"
        self.full = full
        self.P0 = P0
        self.pos0, self.vel0, self.mat0, self.sensor0 = pos0_n_m, vel0_n_mps, mat0_nb, sensor0
        self.inputs = inputs = (t_s, gyr, acc, np.asarray(pos0_n_m, dtype=float), np.asarray(vel0_n_mps, dtype=float),
                                np.asarray(mat0_nb, dtype=float), P, s0, tuple(updates), config,
                                full if mode != "nav" else "nav")
        prev, k_start = None, -1
        for cand in ([prefix] if isinstance(prefix, EskfResult) else prefix):
            k_c = _resume_point(cand, inputs)
            if k_c > k_start:
                prev, k_start = cand, k_c
        n = t_s.size
        if arrays is None:
            pos, vel, mat, sens = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3, 3)), np.empty((n, 12))
        else:  # views into a batch's stacked arrays
            pos, vel, mat, sens = arrays[:4]
        dxs = np.zeros((n, N_STATES))
        if full:
            P_plus = np.empty((n, N_STATES, N_STATES)) if arrays is None else arrays[4]
            P_minus = np.empty((n, N_STATES, N_STATES)) if arrays is None else arrays[5]
            Phis = np.empty((n, N_STATES, N_STATES)) if arrays is None else arrays[6]
            Phis[0] = np.eye(N_STATES)
        else:
            P_plus = P_minus = Phis = None
        cps: list = []
        self.nis = np.full(n, np.nan)
        self.n_meas = np.zeros(n, dtype=np.int64)
        self.p = np.asarray(pos0_n_m, dtype=float).copy()
        self.v = np.asarray(vel0_n_mps, dtype=float).copy()
        self.C = np.asarray(mat0_nb, dtype=float).copy()
        self.s = s0.copy()
        if mode == "cp":
            cps.append((0, P.copy()))
        self.dt_all = np.diff(t_s)
        self.qd_all = process_noise_diag(config, self.dt_all)  # elementwise in dt: the same values as per segment
        # segment boundaries: every update epoch and the last epoch
        stops = sorted(set(self.sched) | {n - 1})
        k = 0
        if prev is not None:
            # epochs 0..k_start (k_start an update epoch) as the earlier run computed them; continue after its update
            k = k_start
            e = k + 1
            for a, b in ((pos, prev.pos_n_m), (vel, prev.vel_n_mps), (mat, prev.mat_nb), (sens, prev.sensor),
                         (dxs, prev.dx), (self.nis, prev.nis), (self.n_meas, prev.n_meas)):
                a[:e] = b[:e]
            if full:
                P_plus[:e], P_minus[:e], Phis[:e] = prev.P_plus[:e], prev.P_minus[:e], prev.Phi[:e]
                P = prev.P_plus[k].copy()
            else:
                j = int(np.searchsorted(prev.cp_idx, k, side="right"))
                cps = [(int(i), c.copy()) for i, c in zip(prev.cp_idx[:j], prev.cp_P[:j], strict=True)]
                P = cps[-1][1].copy()
            self.p, self.v, self.C, self.s = pos[k].copy(), vel[k].copy(), mat[k].copy(), sens[k].copy()
            stops = [kb for kb in stops if kb > k]
        self.P, self.k, self.stops, self.cps = P, k, stops, cps
        self.pos, self.vel, self.mat, self.sens, self.dxs = pos, vel, mat, sens, dxs
        self.P_plus, self.P_minus, self.Phis = P_plus, P_minus, Phis

    def planned(self, kb: int):
        """The rows laid out ahead (:func:`_stacked_rows`) of the epoch ``kb`` for the current state: ``(innovation,
        H, R)``, the same as stacking the sets' ``rows()``; None when the epoch has none laid out (no update, or a
        set of another class)."""
        ab = self.plan.get(kb)
        if ab is None or ab[1] <= ab[0]:
            return None
        a, b = ab
        p, v, C = self.p, self.v, self.C
        bo = self.body.get(kb)
        Hk = self.H_all[a:b]
        if bo is None:
            x = np.concatenate((p, v))
        else:
            Ct = C.T
            x = np.concatenate((p, v, Ct @ v))
            Hk[bo[0], 3:6] = Ct[bo[1]]
            Hk[bo[0], 6:9] = (Ct @ skew(v))[bo[1]]
        return self.Z_all[a:b] - x[self.src_all[a:b]], Hk, self.R_all[a:b]

    def feedback(self, kb: int, dx, P, nis, m: int) -> None:
        """Store the update of epoch ``kb`` (``dx``, updated ``P``, ``nis`` over ``m`` rows), feed it back
        (:func:`correct_nav`) and store the epoch."""
        self.nis[kb] = nis
        self.n_meas[kb] = m
        self.dxs[kb] = dx
        self.store(kb, *correct_nav(self.p, self.v, self.C, self.s, dx), P)

    def store(self, kb: int, p, v, C, s, P) -> None:
        """The state after epoch ``kb`` and what the run keeps of it."""
        self.k = kb
        self.pos[kb], self.vel[kb], self.mat[kb], self.sens[kb] = p, v, C, s
        self.p, self.v, self.C, self.s, self.P = p, v, C, s, P
        if self.full:
            self.P_plus[kb] = P
        elif self.mode == "cp":
            cps = self.cps
            if cps[-1][0] == kb:
                cps[-1] = (kb, P.copy())
            else:
                cps.append((kb, P.copy()))

    def update(self, kb: int) -> None:
        """The epoch ``kb`` after its prediction: every measurement due there (eq. 4-6), the closed-loop
        feedback, and what the run stores of the epoch."""
        p, v, C, s, P = self.p, self.v, self.C, self.s, self.P
        rows = self.sched.get(kb)
        if kb in self.plan:
            # the rows laid out ahead (_stacked_rows): the same innovation, H and R as stacking rows() below
            ihr = self.planned(kb)
            if ihr is not None:
                dx, P, nis = joseph_update(P, *ihr)
                self.feedback(kb, dx, P, nis, ihr[0].size)
                return
        elif rows:
            # update (eq. 4-6) with every measurement due at this epoch, then closed-loop feedback
            updates = self.updates
            innov, Hs, Rd = [], [], []
            for i, j in rows:
                e, H, R = updates[i].rows(j, p, v, C)
                innov.append(e)
                Hs.append(H)
                Rd.append(R)
            innov = np.concatenate(innov)
            if innov.size:
                Rc = np.concatenate(Rd)
                if not (np.all(Rc >= MIN_MEAS_VARIANCE) and np.all(Rc <= MAX_VARIANCE)):  # NaN fails too
                    _check_measurement_noise(", ".join(sorted({updates[i].name or type(updates[i]).__name__
                                                               for i, _ in rows})), Rc)
                dx, P, nis = joseph_update(P, innov, np.vstack(Hs), Rc)
                self.feedback(kb, dx, P, nis, innov.size)
                return
        self.store(kb, p, v, C, s, P)

    def result(self) -> EskfResult:
        """The run's :class:`EskfResult` once every stop is done."""
        full = self.full
        if 0 not in self.sched:
            if full:
                self.P_minus[0] = self.P_plus[0] = 0.5 * (self.P0 + self.P0.T)
            self.pos[0], self.vel[0], self.mat[0], self.sens[0] = (
                self.pos0, self.vel0, self.mat0, (np.zeros(12) if self.sensor0 is None else self.sensor0))
        extra = {}
        if self.mode == "cp":
            cps = self.cps
            extra = {"cp_idx": np.array([c[0] for c in cps], dtype=np.int64), "cp_P": np.array([c[1] for c in cps]),
                     "gyr_b_radps": self.gyr, "acc_b_mps2": self.acc}
        return EskfResult(t_s=self.t_s, pos_n_m=self.pos, vel_n_mps=self.vel, mat_nb=self.mat, sensor=self.sens,
                          dx=self.dxs, P_plus=self.P_plus, P_minus=self.P_minus, Phi=self.Phis, nis=self.nis,
                          n_meas=self.n_meas, config=self.config, inputs=self.inputs, **extra)


def run_eskf(t_s, gyr_b_radps, acc_b_mps2, pos0_n_m, vel0_n_mps, mat0_nb, P0, updates=(),
             config: EskfConfig | None = None, sensor0=None, keep_covariance: bool = True,
             prefix=()) -> EskfResult:
    """Run the closed-loop 21-state EKF over an IMU log with the given measurement sets.

    Between two update epochs the driver propagates with constant sensor-error estimates, vectorised
    over the segment: :func:`correct_sensors`, :func:`~ilocalg.ins.mechanisation.strapdown`,
    :func:`transition_matrices` and :func:`process_noise_diag`, then :func:`eskf_predict` per epoch.
    At an update epoch it stacks the rows of every measurement due there (:class:`Measurement`),
    calls :func:`joseph_update` once and feeds the estimate back (:func:`correct_nav`).

    Parameters
    ----------
    t_s : (N,) IMU sample times (s), strictly increasing, any (irregular) spacing
    gyr_b_radps, acc_b_mps2 : (N, 3) raw sensor samples; sample k is the mean over [t_k, t_{k+1})
    pos0_n_m, vel0_n_mps, mat0_nb : initial navigation state at ``t_s[0]``
    P0 : (21, 21) initial covariance (see :func:`initial_covariance`); checked by :func:`check_covariance`
    updates : sequence of :class:`Measurement` objects (:class:`PositionFix`, :class:`NavVelocity`,
        :class:`BodyVelocity` or any other object obeying the protocol); every noise variance R must lie in
        [:data:`MIN_MEAS_VARIANCE`, :data:`MAX_VARIANCE`]
    config : :class:`EskfConfig` process noise (Q)
    sensor0 : (12,) initial sensor-error estimates (default zeros)
    keep_covariance : True stores the (N, 21, 21) histories ``P_plus``, ``P_minus`` and ``Phi`` (what
        :func:`~ilocalg.ins.smoother.eskf_rts_smooth` reads fastest); False stores only checkpoints (memory
        O(N) instead of O(441 N); the smoother recomputes each stretch from them)
    prefix : earlier results (an :class:`EskfResult` or a sequence of them) of runs that may share a beginning
        with this one: when one had the same IMU log, initial state, covariance, configuration and history mode
        and the same measurements up to some epoch (compared bit for bit), the epochs up to its last update
        before the first difference are copied from it instead of recomputed (the same numbers: the filter is
        deterministic); the run continues from there. E.g. the filter with control points after the same filter
        without them (the same until the first control point).

    Returns
    -------
    EskfResult

    References
    ----------
    Liao et al. (2016), eq. (1)-(6).
    """
    r = _Run(t_s, gyr_b_radps, acc_b_mps2, pos0_n_m, vel0_n_mps, mat0_nb, P0, updates, config, sensor0,
             "full" if keep_covariance else "cp", prefix)
    full = r.full
    gyr, acc, dt_all, qd_all = r.gyr, r.acc, r.dt_all, r.qd_all
    pos, vel, mat, sens = r.pos, r.vel, r.mat, r.sens
    for kb in r.stops:
        k = r.k
        if kb > k:
            # predict k -> kb with constant sensor-error estimates (eq. 2-3)
            seg = slice(k, kb)
            dt = dt_all[seg]
            s = r.s
            w_c, f_c = correct_sensors(gyr[seg], acc[seg], s)
            strapdown(r.p, r.v, r.C, w_c, f_c, dt, out=(pos[k:kb + 1], vel[k:kb + 1], mat[k:kb + 1]))
            sens[k + 1:kb + 1] = s
            qd = qd_all[seg]
            P = r.P
            if full:
                Ph = transition_matrices(mat[k:kb], f_c, w_c, dt, out=r.Phis[k + 1:kb + 1])
                P = _predict_stretch(P, Ph, qd, r.P_minus[k + 1:kb + 1], r.P_plus[k + 1:kb + 1])
            else:
                # bounded memory: transition matrices a stretch at a time, checkpoints every CHECKPOINT_EPOCHS
                for a in range(0, kb - k, CHECKPOINT_EPOCHS):
                    b = min(a + CHECKPOINT_EPOCHS, kb - k)
                    Ph = transition_matrices(mat[k + a:k + b], f_c[a:b], w_c[a:b], dt[a:b])
                    P = _predict_stretch(P, Ph, qd[a:b], cps=r.cps, k0=k + a)
            r.p, r.v, r.C = pos[kb].copy(), vel[kb].copy(), mat[kb].copy()
            r.P = 0.5 * (P + P.T)
        elif kb == 0 and full:
            r.P_minus[0] = r.P
        r.update(kb)
    return r.result()


#: Largest (members x epochs) of one stacked prediction in :func:`run_eskf_batch` (bounds its buffers: each
#: (members, epochs, 21, 21) array of the group is this many 21 x 21 matrices at most, 14 MB at 4096).
BATCH_EPOCHS = 4096


def _predict_group(runs, kbs, big):
    """The prediction of every run in ``runs`` from its epoch ``r.k`` to ``kbs`` (each at least one step), all
    stacked: the operations of :func:`run_eskf`'s prediction (correct_sensors, strapdown, transition_matrices,
    the per-epoch ``Phi P Phi^T + Q``) on (members, epochs, ...) arrays, sorted by stretch length so that the
    members still stepping at epoch ``j`` of the stretch are the first ``cnt[j]``: elementwise operations and one
    BLAS call per matrix (``np.matmul`` on stacked float64 matrices hands each to the same ``cblas_dgemm`` as
    ``np.dot``), so every member's numbers have the same bits as its own :func:`run_eskf`."""
    GY, AC, DT, QD, POS, VEL, MAT, SENS, PP, PM, PH = big
    n = len(runs)
    ks = np.array([r.k for r in runs])
    kbs = np.asarray(kbs)
    offs = np.array([r.off for r in runs])
    L = kbs - ks
    Lm = int(L[0])
    jj = np.arange(Lm)
    cnt = np.count_nonzero(L[None, :] > jj[:, None], axis=1).tolist()
    src = np.minimum((offs + ks)[:, None] + jj, (offs + kbs - 1)[:, None])  # pads repeat the last sample
    S = np.array([r.s for r in runs])[:, None, :]
    dt = DT[src]
    # correct_sensors
    f_c = (AC[src] - S[:, :, 0:3]) / (1.0 + S[:, :, 6:9])
    w_c = (GY[src] - S[:, :, 3:6]) / (1.0 + S[:, :, 9:12])
    # strapdown
    dC = rotvecs_to_dcm((w_c * dt[:, :, None]).reshape(n * Lm, 3)).reshape(n, Lm, 3, 3)
    mat = np.zeros((n, Lm + 1, 3, 3))
    mat[:, 0] = np.array([r.C for r in runs])
    mm = np.matmul
    for j in range(Lm):
        m = cnt[j]
        mm(mat[:m, j], dC[:m, j], out=mat[:m, j + 1])
    half_dt = 0.5 * dt[:, :, None]
    dv = half_dt * np.einsum("lij,lj->li", (mat[:, :-1] + mat[:, 1:]).reshape(n * Lm, 3, 3),
                             f_c.reshape(n * Lm, 3)).reshape(n, Lm, 3)
    dv += GRAVITY_N_MPS2 * dt[:, :, None]
    v0 = np.array([r.v for r in runs])
    vel = np.empty((n, Lm + 1, 3))
    np.add(v0, 0.0, out=vel[:, 0])
    np.cumsum(dv, axis=1, out=vel[:, 1:])
    np.add(v0[:, None], vel[:, 1:], out=vel[:, 1:])
    dp = vel[:, :-1] + vel[:, 1:]
    dp *= half_dt
    p0 = np.array([r.p for r in runs])
    pos = np.empty((n, Lm + 1, 3))
    np.add(p0, 0.0, out=pos[:, 0])
    np.cumsum(dp, axis=1, out=pos[:, 1:])
    np.add(p0[:, None], pos[:, 1:], out=pos[:, 1:])
    # transition matrices and covariance prediction
    Ph = transition_matrices(mat[:, :Lm].reshape(n * Lm, 3, 3), f_c.reshape(n * Lm, 3), w_c.reshape(n * Lm, 3),
                             dt.reshape(n * Lm)).reshape(n, Lm, N_STATES, N_STATES)
    PhT = Ph.swapaxes(2, 3)
    qd = QD[src]
    hist = np.empty((n, Lm, N_STATES, N_STATES))
    work = np.empty((n, N_STATES, N_STATES))
    prev = np.array([r.P for r in runs])
    for j in range(Lm):
        m = cnt[j]
        o = hist[:m, j]
        mm(mm(Ph[:m, j], prev[:m], out=work[:m]), PhT[:m, j], out=o)
        o.reshape(m, N_STATES * N_STATES)[:, ::N_STATES + 1] += qd[:m, j]
        prev = hist[:, j]
    # what each run stores of the stretch, and its state at the stretch's end
    valid = jj[None, :] < L[:, None]
    dst = ((offs + ks)[:, None] + 1 + jj)[valid]
    SENS[dst] = np.broadcast_to(S, (n, Lm, 12))[valid]
    if PP is not None:
        PM[dst] = PP[dst] = hist[valid]
        PH[dst] = Ph[valid]
    j1 = np.arange(Lm + 1)
    valid1 = j1[None, :] <= L[:, None]
    dst1 = ((offs + ks)[:, None] + j1)[valid1]
    POS[dst1], VEL[dst1], MAT[dst1] = pos[valid1], vel[valid1], mat[valid1]
    ar = np.arange(n)
    Pend = hist[ar, L - 1]
    Pend = 0.5 * (Pend + Pend.swapaxes(1, 2))
    pe, ve, Ce = pos[ar, L], vel[ar, L], mat[ar, L]
    for i, r in enumerate(runs):
        r.p, r.v, r.C, r.P = pe[i], ve[i], Ce[i], Pend[i]


#: Fewest runs :func:`run_eskf_batch` advances together (fewer run one by one: with one or two, the stacking costs
#: more than it shares).
BATCH_MIN_RUNS = 3


def _without_covariance(r: EskfResult) -> EskfResult:
    """A checkpointed result (``keep_covariance=False``) as :func:`run_eskf_batch` returns one without covariance."""
    return replace(r, cp_idx=None, cp_P=None, gyr_b_radps=None, acc_b_mps2=None, inputs=r.inputs[:10] + ("nav",))


def run_eskf_batch(runs, keep_covariance: bool = True) -> list[EskfResult]:
    """:func:`run_eskf` on several runs advanced together: the same results, bit for bit, in less time.

    Each run's prediction between two of its update epochs is stacked with the other runs' (their own IMU logs,
    epochs and measurement sets: the k-th stretch of every run at once, whatever its length); the updates stay
    per run. The Python work per stretch is shared by the runs, which is where a single run spends its time
    (stretches of a few epochs between updates).

    Parameters
    ----------
    runs : sequence of dicts of :func:`run_eskf` keyword arguments (``t_s``, ``gyr_b_radps``, ``acc_b_mps2``,
        ``pos0_n_m``, ``vel0_n_mps``, ``mat0_nb``, ``P0`` and optionally ``updates``, ``config``, ``sensor0``,
        ``prefix``); every check of :func:`run_eskf` applies to each
    keep_covariance : True keeps the covariance histories as ``run_eskf(..., keep_covariance=True)``; False keeps
        no covariance at all (``P_plus``, ``P_minus``, ``Phi`` and the checkpoints are None: the navigation
        solution, sensor estimates, fed-back errors and NIS only, e.g. to score the filter without smoothing it;
        ``prefix`` is then not used)

    Returns
    -------
    list of :class:`EskfResult`, one per run, in order (their arrays are views into arrays shared by the batch;
    fewer than :data:`BATCH_MIN_RUNS` runs are run one by one).
    """
    keys = {"t_s", "gyr_b_radps", "acc_b_mps2", "pos0_n_m", "vel0_n_mps", "mat0_nb", "P0", "updates", "config",
            "sensor0", "prefix"}
    runs = [dict(r) for r in runs]
    for i, r in enumerate(runs):
        bad = sorted(set(r) - keys)
        if bad:
            raise ValueError(f"run_eskf_batch: run {i} has unknown arguments {bad}")
    if not runs:
        return []
    full = bool(keep_covariance)
    if len(runs) < BATCH_MIN_RUNS:  # too few to share the work: one by one (the same results)
        return [run_eskf(**r) if full else _without_covariance(run_eskf(**r, keep_covariance=False)) for r in runs]
    Ns = [np.asarray(r["t_s"]).size for r in runs]
    T = int(np.sum(Ns))
    POS, VEL, MAT, SENS = np.empty((T, 3)), np.empty((T, 3)), np.empty((T, 3, 3)), np.empty((T, 12))
    PP = PM = PH = None
    if full:
        PP, PM, PH = (np.empty((T, N_STATES, N_STATES)) for _ in range(3))
    members = []
    off = 0
    for i, (r, N) in enumerate(zip(runs, Ns, strict=True)):
        sl = slice(off, off + N)
        arrays = (POS[sl], VEL[sl], MAT[sl], SENS[sl]) + ((PP[sl], PM[sl], PH[sl]) if full else ())
        m = _Run(r["t_s"], r["gyr_b_radps"], r["acc_b_mps2"], r["pos0_n_m"], r["vel0_n_mps"], r["mat0_nb"], r["P0"],
                 r.get("updates", ()), r.get("config"), r.get("sensor0"), "full" if full else "nav",
                 r.get("prefix", ()) if full else (), arrays=arrays)
        if m.t_s.size != N:
            raise ValueError(f"run_eskf_batch: run {i} t_s has {m.t_s.size} samples, expected {N}")
        m.off = off
        members.append(m)
        off += N
    GY = np.concatenate([m.gyr for m in members])
    AC = np.concatenate([m.acc for m in members])
    DT = np.concatenate([np.append(m.dt_all, 0.0) for m in members])
    QD = np.concatenate([np.vstack((m.qd_all, np.zeros((1, N_STATES)))) for m in members])
    big = (GY, AC, DT, QD, POS, VEL, MAT, SENS, PP, PM, PH)
    todo = [(m, iter(m.stops)) for m in members]
    while todo:
        cur, nxt = [], []
        for m, it in todo:
            kb = next(it, None)
            if kb is not None:
                cur.append((m, kb))
                nxt.append((m, it))
        todo = nxt
        pred = sorted(((kb - m.k, i) for i, (m, kb) in enumerate(cur) if kb > m.k), reverse=True)
        a = 0
        while a < len(pred):  # groups of at most BATCH_EPOCHS (members x longest stretch)
            b = a + max(1, BATCH_EPOCHS // pred[a][0])
            grp = [cur[i] for _, i in pred[a:b]]
            _predict_group([m for m, _ in grp], [kb for _, kb in grp], big)
            a = b
        planned: dict = {}
        for m, kb in cur:
            if kb == 0 and m.k == 0 and full:
                m.P_minus[0] = m.P
            ihr = m.planned(kb)
            if ihr is None:
                m.update(kb)
            else:
                planned.setdefault(ihr[0].size, []).append((m, kb, ihr))
        for size, grp in planned.items():  # the updates of one size stacked (joseph_update_stacked)
            if len(grp) == 1:
                m, kb, ihr = grp[0]
                m.feedback(kb, *joseph_update(m.P, *ihr), size)
                continue
            dx, P, nis = joseph_update_stacked(np.array([m.P for m, _, _ in grp]), np.array([i[0] for _, _, i in grp]),
                                               np.array([i[1] for _, _, i in grp]), np.array([i[2] for _, _, i in grp]))
            for j, (m, kb, _) in enumerate(grp):
                m.feedback(kb, dx[j], P[j], float(nis[j]), size)
    return [m.result() for m in members]


def covariance_chunk(res: EskfResult, a: int, b: int):
    """``(P_plus, P_minus, Phi)`` over epochs ``a..b`` (each (b - a + 1, 21, 21)) of a stored filter.

    From the histories when the run kept them (views, no copy); otherwise recomputed exactly from the
    checkpoint at ``a`` (``a`` must be one of ``res.cp_idx`` and no update may fall strictly inside (a, b)),
    the stored navigation solution and sensor estimates and the raw sensors. ``Phi[0]`` and ``P_minus[0]`` of a
    recomputed chunk are NaN (not needed by the smoother).
    """
    if res.P_plus is not None:
        return res.P_plus[a:b + 1], res.P_minus[a:b + 1], res.Phi[a:b + 1]
    if res.cp_P is None:
        raise ValueError("the filter result holds neither covariance histories nor checkpoints")
    i = int(np.searchsorted(res.cp_idx, a))
    if i >= res.cp_idx.size or res.cp_idx[i] != a:
        raise ValueError(f"epoch {a} is not a covariance checkpoint")
    m = b - a
    Pp = np.empty((m + 1, N_STATES, N_STATES))
    Pm = np.full((m + 1, N_STATES, N_STATES), np.nan)
    Ph = np.full((m + 1, N_STATES, N_STATES), np.nan)
    Pp[0] = res.cp_P[i]
    if m:
        dt = np.diff(res.t_s[a:b + 1])
        w_c, f_c = correct_sensors(res.gyr_b_radps[a:b], res.acc_b_mps2[a:b], res.sensor[a])
        Ph[1:] = transition_matrices(res.mat_nb[a:b], f_c, w_c, dt)
        _predict_stretch(res.cp_P[i], Ph[1:], process_noise_diag(res.config, dt), Pm[1:], Pp[1:])
        j = int(np.searchsorted(res.cp_idx, b))
        if j < res.cp_idx.size and res.cp_idx[j] == b:
            Pp[m] = res.cp_P[j]  # after the update at b (or the symmetrised prediction)
    return Pp, Pm, Ph
