"""ST: similar-triangle photo positioning (linear least squares with a conditioning report).

For PoI ``i`` at world position ``p_i`` seen at screen point ``p'_i = (u_i, v_i)`` (pixels from the
image centre) by a camera at ``c`` with known orientation ``T = T_E->AR``, eq. (29)-(30) say
``u_i : v_i : f = [T (p_i - c)]_x : [T (p_i - c)]_y : [T (p_i - c)]_z``. Cross-multiplying gives two
equations per PoI that are linear in ``c``::

    (T_x - (u_i / f) T_z) . c = (T_x - (u_i / f) T_z) . p_i
    (T_y - (v_i / f) T_z) . c = (T_y - (v_i / f) T_z) . p_i

with ``T_x, T_y, T_z`` the rows of ``T``. Each PoI constrains ``c`` to its back-projected ray; two
PoIs whose rays are not parallel fix ``c``; more PoIs are combined by least squares (the thesis's
LSM). The system is rank deficient exactly when all rays are parallel, i.e. when the camera lies
on the line through (collinear) PoIs; it becomes ill-conditioned as the angle the PoIs subtend
shrinks. :func:`st_solve` raises :class:`RankDeficientError` in the first case and warns with
:class:`IllConditionedWarning` in the second; the batch solver reports ``rank`` and ``cond``.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 6.2, eq. (29)-(30) and the LSM remark after them.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ilocalg.photo.camera import small_rotation, validate_points

__all__ = [
    "RankDeficientError",
    "IllConditionedWarning",
    "STResult",
    "st_system",
    "st_solve",
    "st_solve_batch",
    "st_error_propagation",
    "SimilarTriangles",
]

#: Relative singular-value tolerance below which the ST system counts as rank deficient.
RANK_RTOL = 1e-9

#: :func:`st_solve_batch` solves a photo in closed form when its ``T`` is a rotation to this tolerance (Frobenius
#: norm of ``T T^T - I``): the closed form's singular values and its ``T^T`` in place of ``T^-1`` assume it.
#: A tolerance of 1e-14 bounds their relative error from a non-orthogonal ``T`` at about 1e-14, the rounding of
#: the SVD itself; rotations built by products of a few rotations are orthogonal to ~1e-15.
ST_FAST_ORTHO_TOL = 1e-14

#: ... and when its condition number is at most this; larger ones (and rank-deficient systems) take the SVD,
#: so every photo that :func:`st_solve` calls ill-conditioned (at its default ``cond_warn``) or rejects gets
#: the SVD's answer unchanged.
ST_FAST_MAX_COND = 100.0


class RankDeficientError(ValueError):
    """The ST system does not determine the camera centre (rank < 3)."""


class IllConditionedWarning(UserWarning):
    """The ST system is solvable but badly conditioned (near-parallel rays)."""


@dataclass(frozen=True)
class STResult:
    """Result of :func:`st_solve`.

    Attributes
    ----------
    c_m : ndarray (3,)
        Camera centre in the world frame, metres.
    singular_values : ndarray (3,)
        Singular values of the (row-normalised) design matrix, descending.
    cond : float
        Condition number ``s_max / s_min`` (``inf`` when rank deficient).
    rank : int
        Numerical rank of the design matrix.
    residual_m : ndarray (2 n,)
        Algebraic residuals ``A c - b`` of the row-normalised system, metres (zero for exact data).
    """

    c_m: np.ndarray
    singular_values: np.ndarray
    cond: float
    rank: int
    residual_m: np.ndarray


def st_system(pois_m, img_px, f_px: float, T) -> tuple[np.ndarray, np.ndarray]:
    """Design matrix ``A`` (..., 2n, 3) and right-hand side ``b`` (..., 2n) of eq. (29)-(30).

    Works on single problems (``pois_m`` (n, 3), ``img_px`` (n, 2), ``T`` (3, 3)) and on batches
    (leading dimensions broadcast). Rows are divided by ``f_px`` so ``A`` is dimensionless.

    References
    ----------
    i-Loc thesis, eq. (29)-(30).
    """
    P = np.asarray(pois_m, dtype=float)
    U = np.asarray(img_px, dtype=float) / float(f_px)
    T = np.asarray(T, dtype=float)
    Tx, Ty, Tz = T[..., 0, :], T[..., 1, :], T[..., 2, :]
    ax = Tx[..., None, :] - U[..., 0:1] * Tz[..., None, :]  # (..., n, 3)
    ay = Ty[..., None, :] - U[..., 1:2] * Tz[..., None, :]
    A = np.stack([ax, ay], axis=-2)  # (..., n, 2, 3)
    A = A.reshape(A.shape[:-3] + (2 * A.shape[-3], 3))
    Pb = np.broadcast_to(P, A.shape[:-2] + (P.shape[-2], 3))
    Pr = np.repeat(Pb, 2, axis=-2)
    b = np.sum(A * Pr, axis=-1)
    return A, b


def _st_closed_form(P, U, T):
    """Least squares of eq. (29)-(30) in closed form for a rotation ``T``: ``(c (B, 3), s (B, 3), gap (B,))``.

    ``gap`` is the Frobenius norm of ``T T^T - I`` (the closed form holds for ``gap = 0``).

    ``U`` (B, n, 2) is already divided by ``f_px``; ``P`` (B, n, 3) and ``T`` (B, 3, 3) are broadcast to the batch.
    The design matrix of :func:`st_system` is ``A = D T`` with ``D`` the rows ``(1, 0, -u_i)`` and
    ``(0, 1, -v_i)``. For a rotation ``T`` the singular values of ``A`` are those of ``D``, and
    ``D^T D = [[n, 0, -n u_m], [0, n, -n v_m], [-n u_m, -n v_m, S + n r^2]]`` (``u_m, v_m`` the means of the
    screen points, ``r^2 = u_m^2 + v_m^2``, ``S`` the sum of squared deviations from the mean) has the eigenvalue
    ``n`` (eigenvector ``(v_m, -u_m, 0)``); its other two are those of ``[[n, -n r], [-n r, S + n r^2]]``, whose
    product is ``n S``. In ``y = T c`` the least-squares problem is a regression: with centred screen points and
    right-hand sides the columns are orthogonal, so ``y_3 = -sum(u'_i b'_xi + v'_i b'_yi) / S`` and
    ``y_{1,2} = mean(b_{x,y}) + (u_m, v_m) y_3``. Every quantity is a sum of squares or of products without
    cancellation beyond the centring, so the error is of the order of ``eps * cond`` (measured: smaller than the
    SVD's against an exact rational solution), not the normal equations' ``eps * cond**2``.
    """
    B, n, _ = U.shape
    q = np.matmul(P, np.swapaxes(T, -1, -2))  # T p_i, (B, n, 3)
    b2 = q[..., :2] - U * q[..., 2:3]  # right-hand sides of the x and y rows, (B, n, 2)
    um = np.einsum("bij->bj", U) / n  # (einsum: numpy's sum over the middle axis is several times slower)
    Uc = U - um[:, None, :]
    bm = np.einsum("bij->bj", b2) / n
    bc = b2 - bm[:, None, :]
    S = np.einsum("bij,bij->b", Uc, Uc)
    E = np.matmul(T, np.swapaxes(T, -1, -2)) - np.eye(3)
    gap = np.sqrt(np.einsum("bij,bij->b", E, E))
    with np.errstate(divide="ignore", invalid="ignore"):
        y3 = -np.einsum("bij,bij->b", Uc, bc) / S
        y = np.empty((B, 3))
        y[:, :2] = bm + um * y3[:, None]
        y[:, 2] = y3
        c = np.einsum("bj,bji->bi", y, T)  # T^T y
        r2 = np.einsum("bi,bi->b", um, um)
        g33 = S + n * r2
        lam1 = 0.5 * (n + g33 + np.sqrt((g33 - n) ** 2 + (4.0 * n * n) * r2))
        s = np.empty((B, 3))
        s[:, 0] = np.sqrt(lam1)
        s[:, 1] = np.sqrt(n)
        s[:, 2] = np.sqrt(n * S / lam1)
    return c, s, gap


def st_solve_batch(pois_m, img_px, f_px: float, T, rank_rtol: float = RANK_RTOL) -> dict[str, np.ndarray]:
    """Least-squares ST for a batch of photos.

    Parameters
    ----------
    pois_m : array (B, n, 3) or (n, 3)
        PoI world positions, metres.
    img_px : array (B, n, 2)
        Matched screen points, pixels from the image centre.
    f_px : float
        Focal length, pixels.
    T : array (B, 3, 3)
        ``T_E->AR`` from the phone's accelerometer + magnetometer.
    rank_rtol : float
        Singular values below ``rank_rtol * s_max`` count as zero.

    Returns
    -------
    dict with ``c_m`` (B, 3) (NaN rows where ``rank < 3``, never a silent answer), ``rank`` (B,),
    ``cond`` (B,) and ``singular_values`` (B, 3).

    Notes
    -----
    Photos whose ``T`` is a rotation (Frobenius norm of ``T T^T - I`` at most ``ST_FAST_ORTHO_TOL``) and whose
    system is well conditioned (``cond <= ST_FAST_MAX_COND`` and full rank at ``rank_rtol``) are solved in closed
    form (``_st_closed_form``: the design matrix is a rotation of a matrix whose Gram matrix has a known
    eigenvalue, so the singular values and the solution are a few sums per photo; they agree with the SVD to
    rounding, ~1e-14 relative). Every other photo (rank deficient, ill conditioned, ``T`` not a rotation,
    non-finite input) goes through the SVD of :func:`st_system`'s matrix, as before.

    References
    ----------
    i-Loc thesis, eq. (29)-(30), least squares (LSM).
    """
    U = np.asarray(img_px, dtype=float)
    if U.ndim != 3 or U.shape[-1] != 2:
        raise ValueError(f"img_px must have shape (B, n, 2), got {U.shape}")
    if U.shape[1] < 2:
        raise ValueError(f"ST needs at least 2 PoIs per photo, got {U.shape[1]}")
    B, n, _ = U.shape
    P = np.broadcast_to(np.asarray(pois_m, dtype=float), (B, n, 3))
    T = np.broadcast_to(np.asarray(T, dtype=float), (B, 3, 3))
    c, s, gap = _st_closed_form(P, U / float(f_px), T)
    with np.errstate(divide="ignore", invalid="ignore"):
        cond = s[:, 0] / s[:, 2]
    # NaN anywhere fails a comparison or the finiteness test, so such photos take the SVD too (which raises, as before)
    fast = ((gap <= ST_FAST_ORTHO_TOL) & (cond <= ST_FAST_MAX_COND) & (s[:, 2] > rank_rtol * s[:, 0])
            & np.isfinite(c @ np.ones(3)))
    rank = np.full(B, 3)
    slow = np.flatnonzero(~fast)
    if slow.size:
        A, b = st_system(P[slow], U[slow], f_px, T[slow])
        Uu, ss, Vt = np.linalg.svd(A, full_matrices=False)
        rk = np.sum(ss > rank_rtol * ss[:, :1], axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv_s = np.where(ss > rank_rtol * ss[:, :1], 1.0 / ss, 0.0)
            ub = np.matmul(b[:, None, :], Uu)[:, 0, :]  # U^T b, then V diag(1/s) U^T b: two small batched products
            ub *= inv_s
            cs = np.matmul(Vt.transpose(0, 2, 1), ub[..., None])[..., 0]
            cond[slow] = np.where(rk == 3, ss[:, 0] / ss[:, -1], np.inf)
        cs[rk < 3] = np.nan
        c[slow], s[slow], rank[slow] = cs, ss, rk
    return {"c_m": c, "rank": rank, "cond": cond, "singular_values": s}


def st_solve(pois_m, img_px, f_px: float, T, cond_warn: float = 100.0,
             rank_rtol: float = RANK_RTOL) -> STResult:
    """Camera centre from two or more matched PoIs and a known orientation (ST, least squares).

    Parameters
    ----------
    pois_m : array (n, 3)
        PoI positions in the world frame, metres; ``n >= 2``.
    img_px : array (n, 2)
        Screen points, pixels from the image centre (x right, y down).
    f_px : float
        Focal length in pixels.
    T : array (3, 3)
        ``T_E->AR``, world-to-AR rotation (from accelerometer and magnetometer).
    cond_warn : float
        Warn with :class:`IllConditionedWarning` when the condition number exceeds this.
    rank_rtol : float
        Relative singular-value threshold for the rank.

    Returns
    -------
    STResult

    Raises
    ------
    RankDeficientError
        (a ValueError) when the rays do not fix ``c``: fewer than two distinct ray directions,
        e.g. the camera on the line of collinear PoIs.

    References
    ----------
    i-Loc thesis, sec. 6.2, eq. (29)-(30).
    """
    P, U = validate_points(pois_m, img_px, f_px, min_points=2)
    T = np.asarray(T, dtype=float)
    if T.shape != (3, 3) or not np.allclose(T @ T.T, np.eye(3), atol=1e-6):
        raise ValueError("T must be a 3x3 rotation matrix (T_E->AR)")
    out = st_solve_batch(P[None], U[None], f_px, T[None], rank_rtol=rank_rtol)
    rank = int(out["rank"][0])
    s = out["singular_values"][0]
    if rank < 3:
        raise RankDeficientError(
            f"ST system has rank {rank} < 3 (singular values {np.array2string(s, precision=3)}): the PoIs' "
            "rays are parallel (camera on the line of collinear PoIs), so c is not determined")
    cond = float(out["cond"][0])
    if cond > cond_warn:
        warnings.warn(f"ST system is ill-conditioned (cond = {cond:.3g} > {cond_warn:g}): the PoIs subtend a "
                      "very small angle or are nearly in line with the camera; expect a large error",
                      IllConditionedWarning, stacklevel=2)
    c = out["c_m"][0]
    A, b = st_system(P, U, f_px, T)
    return STResult(c_m=c, singular_values=s, cond=cond, rank=rank, residual_m=A @ c - b)


def st_error_propagation(pois_m, img_px, f_px: float, T, tilt_sd_rad: float, yaw_sd_rad: float,
                         drag_sd_px: float, h_rad: float = 1e-6, h_px: float = 1e-3) -> dict[str, np.ndarray]:
    """First-order covariance of the ST centre from orientation and drag (pixel) errors, batched.

    The measured orientation is modelled as ``T @ small_rotation(rx, ry, rz)`` with independent
    tilt errors ``rx, ry ~ N(0, tilt_sd^2)`` and heading error ``rz ~ N(0, yaw_sd^2)``; screen points
    get independent ``N(0, drag_sd^2)`` errors per axis. The Jacobian of :func:`st_solve_batch` is
    taken by central differences.

    Parameters
    ----------
    pois_m : array (B, n, 3) or (n, 3)
    img_px : array (B, n, 2)
    f_px : float
    T : array (B, 3, 3)
    tilt_sd_rad, yaw_sd_rad : float
        Standard deviations of the sensor orientation errors, radians.
    drag_sd_px : float
        Standard deviation of the drag-to-match error per axis, pixels.

    Returns
    -------
    dict with ``cov_m2`` (B, 3, 3) total, ``cov_orientation_m2`` and ``cov_drag_m2`` (B, 3, 3), and
    ``rms_m`` (B,) = sqrt(trace(cov)), the predicted RMS 3-D error.

    References
    ----------
    Beyond the i-Loc thesis: linear error propagation through eq. (29)-(30).
    """
    U = np.asarray(img_px, dtype=float)
    T = np.asarray(T, dtype=float)
    B, n, _ = U.shape

    def solve(Tb, Ub):
        return st_solve_batch(pois_m, Ub, f_px, Tb)["c_m"]

    J_o = np.empty((B, 3, 3))
    for k in range(3):
        d = np.zeros(3)
        d[k] = h_rad
        Rp = small_rotation(*d)
        Rm = small_rotation(*(-d))
        J_o[:, :, k] = (solve(T @ Rp, U) - solve(T @ Rm, U)) / (2 * h_rad)
    J_p = np.empty((B, 3, 2 * n))
    for k in range(2 * n):
        d = np.zeros(2 * n)
        d[k] = h_px
        d = d.reshape(n, 2)
        J_p[:, :, k] = (solve(T, U + d) - solve(T, U - d)) / (2 * h_px)
    So = np.diag([tilt_sd_rad ** 2, tilt_sd_rad ** 2, yaw_sd_rad ** 2])
    cov_o = J_o @ So @ np.swapaxes(J_o, 1, 2)
    cov_p = drag_sd_px ** 2 * (J_p @ np.swapaxes(J_p, 1, 2))
    cov = cov_o + cov_p
    return {"cov_m2": cov, "cov_orientation_m2": cov_o, "cov_drag_m2": cov_p,
            "rms_m": np.sqrt(np.trace(cov, axis1=1, axis2=2))}


class SimilarTriangles:
    """Thin wrapper around :func:`st_solve` holding the camera's focal length.

    Parameters
    ----------
    f_px : float
        Focal length, pixels.
    cond_warn : float
        See :func:`st_solve`.
    """

    def __init__(self, f_px: float, cond_warn: float = 100.0):
        self.f_px = f_px
        self.cond_warn = cond_warn

    def locate(self, pois_m, img_px, T) -> STResult:
        """Camera centre of one photo; see :func:`st_solve`."""
        return st_solve(pois_m, img_px, self.f_px, T, cond_warn=self.cond_warn)
