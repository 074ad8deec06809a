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

import functools
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
    "run_hartmann_many",
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
#: The state-dependent entries of Phi (row-major within each block, in this order): the attitude block's first
#: two columns, the attitude-gyro-bias block, position-attitude, position-acc-bias, velocity-attitude,
#: velocity-acc-bias, the position-velocity diagonal.
_PHI_IDX = _flat(_N, [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)] + _block(range(3), range(9, 12))
                 + _block(range(3, 6), range(3)) + _block(range(3, 6), range(12, 15)) + _block(range(6, 9), range(3))
                 + _block(range(6, 9), range(12, 15)) + [(3, 6), (4, 7), (5, 8)])


def _terms(sf, cf, st, ct, sp, cp, w1, w2, w3, a1, a2, a3) -> tuple:
    """The state-dependent entries of :func:`_model_many`'s table for one state, from the sines and cosines of
    (phi, theta, psi) and the bias-corrected rates ``w`` and specific force ``a`` (Python floats).

    Returns 40 floats: ``E`` (eq. 7-9), ``C`` (the DCM of eq. 6), ``D = d(C a)/d(phi, theta, psi)`` (each
    row-major), d(E w)/d(phi), d(E w)/d(theta), ``w``, ``a`` and 1.0.

    Common products are taken once; where an entry reuses one with a sign, a negation is exact
    (``-(a b) == (-a) b``, ``p + (-q) == p - q``, ``-(p + q) == (-p) - q`` bit for bit), so each value is the one
    its own expression (e.g. d_psi[0] = ``-sp ct a1 + (-sp st sf - cp cf) a2 + (-sp st cf + cp sf) a3``) gives.
    """
    cpst, spst = cp * st, sp * st
    c00, c10 = cp * ct, sp * ct
    c01, c02 = cpst * sf - sp * cf, cpst * cf + sp * sf
    c11, c12 = spst * sf + cp * cf, spst * cf - cp * sf
    c21, c22 = ct * sf, ct * cf
    tt, sec = st / ct, 1.0 / ct
    q, r = cf * w2 - sf * w3, sf * w2 + cf * w3
    return (1.0, sf * tt, cf * tt, 0.0, cf, -sf, 0.0, sf * sec, cf * sec,
            c00, c01, c02, c10, c11, c12, -st, c21, c22,
            # D: columns d/d(phi), d/d(theta), d/d(psi)
            c02 * a2 - c01 * a3, -cpst * a1 + c00 * sf * a2 + c00 * cf * a3, -(c10 * a1 + c11 * a2 + c12 * a3),
            c12 * a2 - c11 * a3, -spst * a1 + c10 * sf * a2 + c10 * cf * a3, c00 * a1 + c01 * a2 + c02 * a3,
            c22 * a2 - c21 * a3, -ct * a1 - st * sf * a2 - st * cf * a3, 0.0,
            q * tt, -r, q * sec, r * sec * sec, 0.0, r * st * sec * sec,
            w1, w2, w3, a1, a2, a3, 1.0)


_E, _C, _D, _DEW = range(0, 9), range(9, 18), range(18, 27), range(27, 33)
#: The columns of :func:`_terms`' table behind Phi's entries (order of _PHI_IDX): d(E w)/d(phi, theta) (times dt,
#: plus the identity's 1), -dt E, h D, -h C, dt D, -dt C (h = dt^2 / 2); then dt on the diagonal (a column of 1).
_PHI_COLS = np.array([*_DEW, *_E, *_D, *_C, *_D, *_C, 39, 39, 39], dtype=np.intp)
_BASE6 = np.array([1.0, 0.0, 0.0, 0.0, 1.0, 0.0])
_GRAVITY = tuple(GRAVITY_N_MPS2.tolist())
_GRAVITY_V = np.array(_GRAVITY)


def _coefficients(dt_s: float) -> np.ndarray:
    """The factors of :data:`_PHI_COLS`' entries for a step of ``dt_s``."""
    h, mh = 0.5 * dt_s * dt_s, -0.5 * dt_s * dt_s
    return np.repeat([dt_s, -dt_s, h, mh, dt_s, -dt_s, dt_s], [6, 9, 9, 9, 9, 9, 3])


def _model_many(x, u, dt_s: float, cache: dict):
    """``f(x, u, 0)`` (eq. 18-19) for the rows of ``x`` (S, 15) with inputs ``u`` (S, 6) and its Jacobians ``Phi``
    (eq. 21, (S, 15, 15)) and ``W`` (eq. 22, (S, 15, 12)); ``cache`` keeps work arrays between calls (Phi and W
    among them: they hold until the next call with the same ``cache``).

    The Euler-angle maths (the DCM of eq. 6 and its partial derivatives in closed form, :func:`_terms`) and the
    state update run on Python floats, one state after the other: for the few states the filter moves together
    that is cheaper than numpy calls on arrays that short. The rest is a fixed number of numpy calls whatever
    the number of states: the products ``E w`` and ``C a`` as one stacked matmul (BLAS gemv on each (3, 3)
    slice, as for a single state), Phi's entries element by element from the table.
    """
    n_seq = x.shape[0]
    h = 0.5 * dt_s * dt_s
    g1, g2, g3 = _GRAVITY
    if n_seq >= _VECTOR_SEQS:
        return _model_arrays(x, u, dt_s, h, cache)
    sin, cos = math.sin, math.cos
    xls = x.tolist()
    tab: list[float] = []
    for xl, ul in zip(xls, u.tolist(), strict=True):
        phi, th, psi = xl[0], xl[1], xl[2]
        tab += _terms(sin(phi), cos(phi), sin(th), cos(th), sin(psi), cos(psi), ul[0] - xl[9], ul[1] - xl[10],
                      ul[2] - xl[11], ul[3] - xl[12], ul[4] - xl[13], ul[5] - xl[14])
    m = np.fromiter(tab, float, 40 * n_seq).reshape(n_seq, 40)
    # (E w, C a): E and C, w and a are adjacent in the table
    ew_ca = (m[:, 0:18].reshape(n_seq, 2, 3, 3) @ m[:, 33:39].reshape(n_seq, 2, 3, 1)).tolist()
    # x[0:3] + (E w) dt, x[3:6] + x[6:9] dt + (dt^2 / 2) acc_v, x[6:9] + dt acc_v with acc_v = C a + g
    new: list[float] = []
    for xl, ((ew1, ew2, ew3), (ca1, ca2, ca3)) in zip(xls, ew_ca, strict=True):
        av1, av2, av3 = ca1[0] + g1, ca2[0] + g2, ca3[0] + g3
        new += (xl[0] + ew1[0] * dt_s, xl[1] + ew2[0] * dt_s, xl[2] + ew3[0] * dt_s,
                xl[3] + xl[6] * dt_s + h * av1, xl[4] + xl[7] * dt_s + h * av2, xl[5] + xl[8] * dt_s + h * av3,
                xl[6] + dt_s * av1, xl[7] + dt_s * av2, xl[8] + dt_s * av3)
        new += xl[9:15]
    x_new = np.fromiter(new, float, 15 * n_seq).reshape(n_seq, 15)
    return x_new, *_jacobians(m, None, n_seq, dt_s, cache)


#: From this many sequences on, :func:`_model_many` computes its table with numpy on arrays of the sequences
#: (:func:`_model_arrays`) instead of on Python floats one sequence after the other: the same operations in the
#: same order on each element (IEEE float64 +, -, *, / give the same bits either way; sines and cosines from
#: :mod:`math` in both), cheaper once the per-sequence Python work outweighs numpy's per-call cost.
_VECTOR_SEQS = 16


class _Traced:
    """A value of :func:`_terms` while it is traced (:func:`_terms_program`): each arithmetic operation on it is
    recorded as a node ``(op, left, right)``; operands are node numbers or ``("const", value)``."""

    __slots__ = ("node", "tape")

    def __init__(self, node: int, tape: list):
        self.node, self.tape = node, tape

    def _op(self, op: str, a, b=None) -> _Traced:
        self.tape.append((op, _operand(a), None if b is None else _operand(b)))
        return _Traced(len(self.tape) - 1, self.tape)

    def __mul__(self, o):
        return self._op("mul", self, o)

    def __rmul__(self, o):
        return self._op("mul", o, self)

    def __add__(self, o):
        return self._op("add", self, o)

    def __radd__(self, o):
        return self._op("add", o, self)

    def __sub__(self, o):
        return self._op("sub", self, o)

    def __rsub__(self, o):
        return self._op("sub", o, self)

    def __truediv__(self, o):
        return self._op("div", self, o)

    def __rtruediv__(self, o):
        return self._op("div", o, self)

    def __neg__(self):
        return self._op("neg", self)


def _operand(v):
    if isinstance(v, _Traced):
        return v.node
    if isinstance(v, int | float):
        return ("const", float(v))
    raise TypeError(f"_terms traced with an operand of type {type(v).__name__}")


_UFUNCS = {"mul": np.multiply, "add": np.add, "sub": np.subtract, "div": np.true_divide, "neg": np.negative}


@dataclass(frozen=True)
class _Program:
    """:func:`_terms` as numpy calls on a work table (S, ``n_cols``): columns 0-11 its arguments, then
    ``consts`` (column, value), then each group's results; a group is ``(ufunc, operand columns, start, stop)``
    with the left operands' columns before the right ones'; ``out_cols`` the 40 results' columns."""

    n_cols: int
    consts: tuple
    groups: tuple
    out_cols: np.ndarray


@functools.cache
def _terms_program() -> _Program:
    """Trace :func:`_terms` once and schedule its operations: every operation whose operands are known by level
    L (longest chain from an argument) runs at level L, and the operations of one kind at one level are one
    numpy call on the columns of every sequence. Each element then sees the operations Python applies to the
    floats, with the same operands: the same bits (IEEE float64, no contraction)."""
    tape: list = []
    args = [_Traced(i, tape) for i in range(12)]
    tape.extend(("arg", None, None) for _ in range(12))
    out = _terms(*args)
    level = [0] * len(tape)
    consts: dict[str, tuple[int, float]] = {}  # by float.hex, which tells -0.0 from 0.0
    for i, (op, a, b) in enumerate(tape):
        if op != "arg":
            level[i] = 1 + max(level[v] if isinstance(v, int) else 0 for v in (a, b) if v is not None)
    for v in (*(x for _, a, b in tape for x in (a, b)), *(_operand(o) for o in out if not isinstance(o, _Traced))):
        if isinstance(v, tuple):
            consts.setdefault(v[1].hex(), (12 + len(consts), v[1]))
    col = {i: i for i in range(12)}
    groups, n_cols = [], 12 + len(consts)
    order: dict[tuple, list[int]] = {}
    for i, (op, _a, _b) in enumerate(tape):
        if op != "arg":
            order.setdefault((level[i], op), []).append(i)
    for (_lv, op), nodes in sorted(order.items()):
        for j, i in enumerate(nodes):
            col[i] = n_cols + j

        def place(v):
            return col[v] if isinstance(v, int) else consts[v[1].hex()][0]

        left = [place(tape[i][1]) for i in nodes]
        right = [place(tape[i][2]) for i in nodes] if op != "neg" else []
        groups.append((_UFUNCS[op], np.array(left + right, dtype=np.intp), n_cols, n_cols + len(nodes)))
        n_cols += len(nodes)
    out_cols = np.array([col[o.node] if isinstance(o, _Traced) else consts[float(o).hex()][0] for o in out],
                        dtype=np.intp)
    return _Program(n_cols, tuple(consts.values()), tuple(groups), out_cols)


def _model_arrays(x, u, dt_s: float, h: float, cache: dict):
    """:func:`_model_many` with :func:`_terms` and the state update evaluated on arrays of the sequences instead
    of Python floats (:func:`_terms_program`, on a work table (columns, S)): each expression is the same, element
    by element."""
    n_seq = x.shape[0]
    prog = _terms_program()
    work = cache.get(("terms", n_seq))
    if work is None:
        buf = np.empty((prog.n_cols, n_seq))
        for c, v in prog.consts:
            buf[c] = v
        rows = prog.out_cols[:, None] * n_seq + np.arange(n_seq)  # (40, S): the table's entry of each sequence
        # E and C, then w and a, of each sequence as (S, 2, 3, 3) and (S, 2, 3, 1) C-contiguous (as from an
        # (S, 40) table), and the Jacobians' entries (:func:`_jacobians`)
        work = cache[("terms", n_seq)] = (buf, rows[0:18].T.ravel(), rows[33:39].T.ravel(), rows.T.copy())
    buf, ec_idx, wa_idx, m_idx = work
    sin, cos = math.sin, math.cos
    a1, a2, a3 = x[:, 0:3].T.tolist()
    buf[0:6] = [list(map(sin, a1)), list(map(cos, a1)), list(map(sin, a2)), list(map(cos, a2)),
                list(map(sin, a3)), list(map(cos, a3))]
    np.subtract(u.T, x[:, 9:15].T, buf[6:12])  # ul[i] - xl[9 + i]
    take = buf.take
    for ufunc, cols, start, stop in prog.groups:
        n = stop - start
        g = take(cols, 0)
        if cols.size == n:
            ufunc(g, buf[start:stop])
        else:
            ufunc(g[:n], g[n:], buf[start:stop])
    ew_ca = buf.take(ec_idx).reshape(n_seq, 2, 3, 3) @ buf.take(wa_idx).reshape(n_seq, 2, 3, 1)
    ew, ca = ew_ca[:, 0, :, 0], ew_ca[:, 1, :, 0]
    av = ca + _GRAVITY_V
    x_new = np.empty((n_seq, 15))
    np.add(x[:, 0:3], ew * dt_s, x_new[:, 0:3])
    np.add(x[:, 3:6] + x[:, 6:9] * dt_s, h * av, x_new[:, 3:6])
    np.add(x[:, 6:9], dt_s * av, x_new[:, 6:9])
    x_new[:, 9:15] = x[:, 9:15]
    return x_new, *_jacobians(buf, m_idx, n_seq, dt_s, cache)


def _jacobians(m, m_idx, n_seq: int, dt_s: float, cache: dict):
    """Phi (S, 15, 15) and W (S, 15, 12) of :func:`_model_many` from its table, the entry j of sequence s at
    ``m.flat[m_idx[s, j]]`` (m_idx (S, 40); None: ``m`` is the table (S, 40), C-contiguous)."""
    key = (n_seq, dt_s, m_idx is None)
    plan = cache.get(key)
    if plan is None:
        idx = (40 * np.arange(n_seq)[:, None] + np.arange(40)) if m_idx is None else m_idx
        plan = cache[key] = (idx[:, _PHI_COLS].ravel(), np.tile(_coefficients(dt_s), n_seq),
                             (_N * _N * np.arange(n_seq)[:, None] + _PHI_IDX).ravel())
    take_idx, coef, put_idx = plan
    Phi, W = cache.get("Phi"), cache.get("W")
    if Phi is None or Phi.shape[0] != n_seq:
        Phi = cache["Phi"] = np.repeat(np.eye(_N)[None], n_seq, axis=0)
        W = cache["W"] = np.zeros((n_seq, _N, 12))
        W[:, 9:15, 6:12] = np.eye(6)
    vals = m.take(take_idx)
    vals *= coef
    base = vals.reshape(n_seq, _PHI_COLS.size)[:, 0:6]
    base += _BASE6  # 1 or 0 + d(E w) dt
    Phi.reshape(-1)[put_idx] = vals
    # W (eq. 22) is Phi's last six columns in rows 0-8 (the identity below them set once)
    W[:, 0:9, 0:6] = Phi[:, 0:9, 9:15]
    return Phi, W


def _model(x, u, dt_s: float):
    """:func:`_model_many` on one state: ``x_new`` (15,), ``Phi`` (15, 15), ``W`` (15, 12)."""
    x_new, Phi, W = _model_many(np.asarray(x, dtype=float)[None], np.asarray(u, dtype=float)[None], dt_s, {})
    return x_new[0], Phi[0], W[0]


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


def _checked_run(t_s, gyr_b_radps, acc_b_mps2, t_vt_s, z_vt, x0, P0, gyr_sd_radps, acc_sd_mps2,
                 gyr_bias_rw_radps_rsqrt_s, acc_bias_rw_mps2_rsqrt_s, vt_sd):
    """:func:`run_hartmann`'s inputs checked and as float arrays: ``t_s, gyr, acc, t_vt, z_vt, x0, P0, R``."""
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
    return t_s, gyr, acc, t_vt, z_vt, x0, P0, R


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
    return run_hartmann_many(t_s, [gyr_b_radps], [acc_b_mps2], [t_vt_s], [z_vt], [x0], [P0], gyr_sd_radps, acc_sd_mps2,
                             gyr_bias_rw_radps_rsqrt_s, acc_bias_rw_mps2_rsqrt_s, vt_sd)[0]


def _correct_many(x, P, z, R):
    """:func:`hartmann_correct` on each row of ``x`` (m, 15), ``P`` (m, 15, 15), ``z`` (m, 4), ``R`` (m, 4, 4)."""
    H = HARTMANN_H
    innov = z - x[:, 2:6]
    innov[:, 0] = wrap_angle_rad(innov[:, 0])
    HP = H @ P
    S = HP @ H.T + R
    K = np.linalg.solve(S, HP).transpose(0, 2, 1)
    x = x + (K @ innov[:, :, None])[:, :, 0]
    x[:, 0:3] = wrap_angle_rad(x[:, 0:3])
    A = np.eye(HARTMANN_N_STATES) - K @ H
    P = A @ P @ A.transpose(0, 2, 1) + K @ R @ K.transpose(0, 2, 1)
    return x, 0.5 * (P + P.transpose(0, 2, 1))


def _psd_check_epochs(fix_epochs, n: int) -> list[int]:
    """The epochs at which :func:`run_hartmann` tests P (:data:`_PSD_CHECK_EPOCHS` predictions after the last
    fix, or after the start, and every as many after that) for a sequence with fixes at ``fix_epochs``."""
    out = []
    last = 0
    for f in [*sorted(set(fix_epochs) - {0}), n - 1]:
        out.extend(range(last + _PSD_CHECK_EPOCHS, min(f, n - 1) + 1, _PSD_CHECK_EPOCHS))
        last = f
    return out


def run_hartmann_many(t_s, gyr_b_radps, acc_b_mps2, t_vt_s, z_vt, x0, P0, gyr_sd_radps=GYR_SD_DEFAULT_RADPS,
                      acc_sd_mps2=ACC_SD_DEFAULT_MPS2, gyr_bias_rw_radps_rsqrt_s=1e-4,
                      acc_bias_rw_mps2_rsqrt_s=1e-3, vt_sd=VT_SD_DEFAULT) -> list[HartmannResult]:
    """:func:`run_hartmann` on several sequences on one IMU clock (or on prefixes of one), moved in lockstep.

    One Python pass over the epochs moves every sequence: the states are an (S, 15) array, the covariances
    (S, 15, 15). Each result equals the step-by-step filter (:func:`hartmann_predict`, :func:`hartmann_correct`,
    :func:`repair_psd` every :data:`_PSD_CHECK_EPOCHS` predictions without a fix) on that sequence alone, bit
    for bit: the element-wise arithmetic is the same, and the stacked ``np.matmul`` / ``np.linalg.solve`` calls
    hand each slice to the BLAS / LAPACK routine the two-dimensional call uses, with the same layout (the
    tests compare the two). The per-epoch cost of the numpy calls, which dominates a run on one sequence, is
    then paid once per epoch for all of them. A sequence on a shorter clock leaves the batch after its last epoch.

    Parameters
    ----------
    t_s : (N,) IMU times shared by every sequence, or one clock per sequence (N_s,), each the first N_s times of
        the longest
    gyr_b_radps, acc_b_mps2 : one (N_s, 3) array per sequence (S of them)
    t_vt_s, z_vt : per sequence, its tracker times (M_s,) and fixes (M_s, 4)
    x0, P0 : per sequence, (15,) and (15, 15)
    gyr_sd_radps, acc_sd_mps2, gyr_bias_rw_radps_rsqrt_s, acc_bias_rw_mps2_rsqrt_s : as in :func:`run_hartmann`,
        the same for every sequence
    vt_sd : four sds (yaw rad, x, y, z m) for every sequence, or one such row per sequence

    Returns
    -------
    list of S :class:`HartmannResult`, in the order of the inputs.
    """
    n_seq = len(gyr_b_radps)
    if n_seq < 1:
        raise ValueError("run_hartmann_many: no sequences given")
    for name, v in (("acc_b_mps2", acc_b_mps2), ("t_vt_s", t_vt_s), ("z_vt", z_vt), ("x0", x0), ("P0", P0)):
        if len(v) != n_seq:
            raise ValueError(f"run_hartmann_many: {name} holds {len(v)} sequences, gyr_b_radps {n_seq}")
    per_seq = np.ndim(vt_sd) == 2
    if per_seq and len(vt_sd) != n_seq:
        raise ValueError(f"run_hartmann_many: vt_sd holds {len(vt_sd)} rows for {n_seq} sequences")
    clocks = isinstance(t_s, list | tuple)
    if clocks and len(t_s) != n_seq:
        raise ValueError(f"run_hartmann_many: t_s holds {len(t_s)} clocks for {n_seq} sequences")
    checked = []
    for s in range(n_seq):
        try:
            checked.append(_checked_run(t_s[s] if clocks else t_s, gyr_b_radps[s], acc_b_mps2[s], t_vt_s[s],
                                        z_vt[s], x0[s], P0[s], gyr_sd_radps, acc_sd_mps2, gyr_bias_rw_radps_rsqrt_s,
                                        acc_bias_rw_mps2_rsqrt_s, vt_sd[s] if per_seq else vt_sd))
        except ValueError as err:
            raise ValueError(f"sequence {s}: {err}" if n_seq > 1 else str(err)) from None
    # longest clock first: the sequences still running at an epoch are the first rows
    order = sorted(range(n_seq), key=lambda s: -checked[s][0].size)
    seqs = [checked[s] for s in order]
    t_s = seqs[0][0]
    n = t_s.size
    n_each = [q[0].size for q in seqs]
    for s, q in zip(order, seqs, strict=True):
        if not np.array_equal(q[0], t_s[:q[0].size]):
            raise ValueError(f"run_hartmann_many: sequence {s}'s t_s is not the start of the longest clock")
    # active[k]: how many sequences have an epoch k
    active = np.searchsorted(-np.asarray(n_each), -np.arange(n), side="left").tolist()
    u_all = np.zeros((n, n_seq, 6))
    for s, (_, gyr, acc, *_rest) in enumerate(seqs):
        u_all[:gyr.shape[0], s, 0:3], u_all[:acc.shape[0], s, 3:6] = gyr, acc
    R_all = np.stack([q[7] for q in seqs])
    vt_idx = [np.searchsorted(q[0], q[3], side="left") for q in seqs]
    # the fixes of epoch k in rounds: round r holds the r-th fix of that epoch of each sequence that has one
    events: dict[int, list] = {}
    for s, idx in enumerate(vt_idx):
        for j, k in enumerate(idx.tolist()):
            events.setdefault(k, []).append((s, j))
    rounds_at = {}
    for k, ev in events.items():
        rounds: list[tuple[list, list]] = []
        count: dict[int, int] = {}
        for s, j in ev:
            r = count[s] = count.get(s, -1) + 1
            if r == len(rounds):
                rounds.append(([], []))
            rounds[r][0].append(s)
            rounds[r][1].append(j)
        rounds_at[k] = [(np.array(ss), ss, jj) for ss, jj in rounds]
    check_at: dict[int, list] = {}
    for s, idx in enumerate(vt_idx):
        for k in _psd_check_epochs(idx.tolist(), n_each[s]):
            check_at.setdefault(k, []).append(s)
    xs = np.empty((n_seq, n, HARTMANN_N_STATES))
    sds = np.zeros((n_seq, n, HARTMANN_N_STATES))  # zeros past a shorter sequence's end (for the square root)
    priors = [np.empty((q[3].size, HARTMANN_N_STATES)) for q in seqs]
    z_all = [q[4] for q in seqs]
    x = np.stack([q[5] for q in seqs])
    P = np.stack([q[6] for q in seqs])
    dt_all = np.diff(t_s).tolist()
    Qw_cache: dict[float, np.ndarray] = {}
    cache: dict = {}
    n_rep = [0] * n_seq
    work: dict[int, tuple] = {}  # per batch size: the buffers of the covariance prediction
    for k in range(n):
        m = active[k]
        if k > 0:
            if m < x.shape[0]:  # the shortest sequences have ended
                x, P = x[:m], P[:m]
            dt = dt_all[k - 1]
            Qw = Qw_cache.get(dt)
            if Qw is None:
                Qw = Qw_cache[dt] = _noise_cov(gyr_sd_radps, acc_sd_mps2, gyr_bias_rw_radps_rsqrt_s,
                                               acc_bias_rw_mps2_rsqrt_s, dt)
            x, Phi, W = _model_many(x, u_all[k - 1, :m], dt, cache)
            bufs = work.get(m)
            if bufs is None:
                bufs = work[m] = (np.empty((m, _N, _N)), np.empty((m, _N, _N)), np.empty((m, _N, 12)),
                                  np.empty((m, _N, _N)), Phi.transpose(0, 2, 1), W.transpose(0, 2, 1))
            A, B, C, D, PhiT, WT = bufs
            # P = Phi P Phi^T + W Q W^T, then 0.5 (P + P^T): the same products and sums, into kept buffers
            np.matmul(Phi, P, A)
            np.matmul(A, PhiT, B)
            np.matmul(W, Qw, C)
            np.matmul(C, WT, D)
            np.add(B, D, B)
            np.add(B, B.transpose(0, 2, 1), P)
            np.multiply(P, 0.5, P)
            for s in check_at.get(k, ()):
                P[s], rep = repair_psd(P[s])
                n_rep[s] += rep
        for J, ss, jj in rounds_at.get(k, ()):
            for s, j in zip(ss, jj, strict=True):
                priors[s][j] = x[s]
            z = np.stack([z_all[s][j] for s, j in zip(ss, jj, strict=True)])
            x[J], P[J] = _correct_many(x[J], P[J], z, R_all[J])
        xs[:m, k] = x
        sds[:m, k] = P.diagonal(axis1=1, axis2=2)
    np.sqrt(sds, out=sds)
    out = [None] * n_seq
    for s, i in enumerate(order):
        out[i] = HartmannResult(t_s=seqs[s][0], x=xs[s, :n_each[s]], sd=sds[s, :n_each[s]], vt_idx=vt_idx[s],
                                prior_at_vt=priors[s], n_psd_repairs=n_rep[s])
    return out


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
