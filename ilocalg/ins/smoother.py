"""RTS smoothing of a stored closed-loop error-state filter: whole run and online fixed windows.

The filter (:func:`ilocalg.ins.eskf.run_eskf`) feeds every estimated error back, so its updated
error state is zero about the corrected solution and its predicted error state is zero about the
predicted one. The correction fed back at epoch ``k+1`` (``dx[k+1]``) is therefore the updated
state expressed about the predicted solution, and eq. (8) becomes, about the corrected solution,

``xs_k = G_k (xs_{k+1} + dx_{k+1})``, ``xs_last = 0``, with
``G_k = P_k^update Phi_{k+1}^T (P_{k+1}^predict)^-1`` (eq. 10; the paper's printed eq. 10 omits the
transpose and the inverse, the standard RTS gain is used) and
``Ps_k = P_k^update + G_k (Ps_{k+1} - P_{k+1}^predict) G_k^T`` (eq. 9).

The smoothed solution is the corrected one plus ``xs`` (attitude through the small rotation).

The online smoother (sec. 3.3) runs the same recursion on consecutive fixed windows as soon as
each fills: inside a window the last epoch keeps its filtered value, so an epoch's smoothed value
is available at the end of its window (latency = window end - epoch time, at most the window).

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 3.3, eq. (8)-(10); Chiang et al. (2012) on-line smoothing;
Shin (2005), UCGE 20219, RTS smoother for INS.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.ins.eskf import ATT, N_STATES, POS, VEL, EskfResult, covariance_chunk
from ilocalg.ins.mechanisation import rotvecs_to_dcm

__all__ = ["EskfSmoothResult", "ErrorStateINS", "rts_gains", "rts_gains_shared", "eskf_rts_smooth",
           "eskf_rts_smooth_grids", "window_ends",
           "online_window_smooth"]


@dataclass(frozen=True)
class EskfSmoothResult:
    """Smoothed solution per epoch: ``pos_n_m`` (N, 3), ``vel_n_mps`` (N, 3), ``mat_nb`` (N, 3, 3),
    ``sensor`` (N, 12), ``xs`` (N, 21) the smoothed error about the filtered solution, ``sd`` (N, 21)
    smoothed standard deviations (NaN when the covariance was not smoothed), ``latency_s`` (N,) the
    wait from an epoch to the availability of its smoothed value (0 at a window's last epoch; for the
    whole-run RTS, the time to the end of the run)."""

    t_s: np.ndarray
    pos_n_m: np.ndarray
    vel_n_mps: np.ndarray
    mat_nb: np.ndarray
    sensor: np.ndarray
    xs: np.ndarray
    sd: np.ndarray
    latency_s: np.ndarray


def _gains(P_plus, P_minus, Phi) -> np.ndarray:
    """Gains of a chunk (L, 21, 21): ``G[i] = P_plus[i] Phi[i+1]^T P_minus[i+1]^-1`` for i < L-1, ``G[L-1] = 0``."""
    L = P_plus.shape[0]
    G = np.zeros((L, N_STATES, N_STATES))
    if L > 1:
        rhs = np.matmul(Phi[1:], P_plus[:-1])
        G[:-1] = np.swapaxes(np.linalg.solve(P_minus[1:], rhs), 1, 2)
    return G


def rts_gains(res: EskfResult) -> np.ndarray:
    """All smoother gains at once, (N, 21, 21); ``G[k]`` for k < N-1 (``G[N-1] = 0``).

    Batched: ``G_k^T = solve(P_{k+1}^predict, Phi_{k+1} P_k^update)`` (both covariances symmetric). Needs a
    filter run that kept its covariance history (``run_eskf(..., keep_covariance=True)``).
    """
    if res.P_plus is None:
        raise ValueError("rts_gains needs the covariance history: run the filter with keep_covariance=True, or "
                         "call eskf_rts_smooth, which recomputes it chunk by chunk")
    return _gains(res.P_plus, res.P_minus, res.Phi)


#: Epochs compared at a time by :func:`rts_gains_shared` while looking for the first difference.
_SHARED_BLOCK = 256


def _leading_same(a: np.ndarray, b: np.ndarray, n: int) -> int:
    """How many leading epochs (of the first ``n``) hold the same bits in the (N, 21, 21) stacks ``a`` and ``b``
    (compared a block at a time, stopping at the first block with a difference)."""
    for i in range(0, n, _SHARED_BLOCK):
        j = min(i + _SHARED_BLOCK, n)
        same = (a[i:j] == b[i:j]).reshape(j - i, -1).all(axis=1)
        if not same.all():
            return i + int(np.argmin(same))
    return n


def rts_gains_shared(res: EskfResult, ref: EskfResult, ref_gains: np.ndarray) -> np.ndarray:
    """:func:`rts_gains` of ``res``, the same bits, taking the gains of ``ref`` (``ref_gains = rts_gains(ref)``)
    over the leading epochs where both runs hold the same covariance history.

    ``G[k]`` reads ``P_plus[k]``, ``P_minus[k+1]`` and ``Phi[k+1]`` only (one solve per matrix), so where these
    three are bit for bit those of ``ref`` (checked here, e.g. a run that resumed from ``ref`` with ``prefix``:
    the same filter up to its first other measurement) its gain is ``ref``'s; the rest are solved.
    """
    if res.P_plus is None or ref.P_plus is None:
        raise ValueError("rts_gains_shared needs both runs' covariance histories (keep_covariance=True)")
    n = min(res.t_s.size, ref.t_s.size) - 1
    if ref_gains.shape != ref.P_plus.shape:
        raise ValueError(f"ref_gains must be rts_gains(ref), of shape {ref.P_plus.shape}, got {ref_gains.shape}")
    k = _leading_same(res.P_plus, ref.P_plus, n)
    k = _leading_same(res.P_minus[1:], ref.P_minus[1:], k)
    k = _leading_same(res.Phi[1:], ref.Phi[1:], k)
    if k == 0:
        return rts_gains(res)
    G = np.empty_like(res.P_plus)
    G[:k] = ref_gains[:k]
    G[k:] = _gains(res.P_plus[k:], res.P_minus[k:], res.Phi[k:])
    return G


def window_ends(t_s, window_s: float | None, offset_s: float = 0.0) -> np.ndarray:
    """Boolean (N,): True at the last epoch of each fixed window ``[t0 + o + j W, t0 + o + (j+1) W)``.

    ``window_s=None`` is one window over the whole run (the post-processing RTS smoother); ``offset_s`` (o, in
    [0, W)) shifts the window grid (the first window is then shorter), so that a result can be averaged over
    where the grid falls.
    """
    t_s = np.asarray(t_s, dtype=float)
    ends = np.zeros(t_s.size, dtype=bool)
    ends[-1] = True
    if window_s is None:
        return ends
    if not (np.isfinite(window_s) and window_s > 0):
        raise ValueError(f"window_s must be > 0 seconds or None, got {window_s}")
    if not (np.isfinite(offset_s) and 0 <= offset_s < window_s):
        raise ValueError(f"offset_s must lie in [0, window_s), got {offset_s}")
    idx = np.floor((t_s - t_s[0] - offset_s) / window_s).astype(np.int64)
    ends[:-1] |= idx[1:] != idx[:-1]
    return ends


def _chunks(res: EskfResult) -> list[tuple[int, int]]:
    """Stretches ``(a, b)`` whose covariances :func:`~ilocalg.ins.eskf.covariance_chunk` gives: the whole run when
    the filter kept its history, else the stretches between consecutive checkpoints."""
    n = res.t_s.size
    if res.P_plus is not None:
        return [(0, n - 1)]
    cp = res.cp_idx
    return list(zip(cp[:-1].tolist(), cp[1:].tolist(), strict=True)) or [(0, n - 1)]


def _backward(res: EskfResult, ends: np.ndarray, gains: np.ndarray | None = None, with_cov: bool = False):
    """Eq. (8) about the corrected solution for M window grids in one backward pass, and eq. (9) on the first.

    ``ends`` (M, N) bool: the window ends of each grid (:func:`window_ends`); at an end a grid's error restarts
    from zero (and its covariance from the filtered one). Each grid's ``xs_k = G_k (xs_{k+1} + dx_{k+1})`` is one
    matrix-vector product per epoch, done for all grids by one stacked ``matmul`` (the same product per grid as
    for one grid alone, so the same bits); the per-epoch Python work is shared by the grids.

    Returns ``xs`` (N, M, 21) and, with ``with_cov``, the smoothed variances (N, 21) of the first grid (else None).
    """
    n = res.t_s.size
    m = ends.shape[0]
    xs = np.zeros((n, m, N_STATES))
    var = np.full((n, N_STATES), np.nan) if with_cov else None
    dx = res.dx
    tmp = np.empty((m, N_STATES))
    tmp3 = tmp[:, :, None]
    # epochs where some grid's window ends -> those grids (xs stays zero there)
    end_k = np.flatnonzero(ends.any(axis=0)).tolist()
    resets = dict(zip(end_k, [np.flatnonzero(ends[:, k]) for k in end_k], strict=True))
    mm, add = np.matmul, np.add
    Ps = None
    for a, b in reversed(_chunks(res)):
        # gains given for every epoch are used as they are (also for a result kept without its covariance history)
        stored = gains is not None and (res.P_plus is not None or len(gains) == n)
        if with_cov or not stored:
            Pp, Pm, Ph = covariance_chunk(res, a, b)
        G = gains[a:b + 1] if stored else _gains(Pp, Pm, Ph)
        for k in range(b - 1, a - 1, -1):
            r = resets.get(k)
            if r is not None and r.size == m:
                continue  # every grid's window ends here: xs[k] stays zero
            add(xs[k + 1], dx[k + 1], out=tmp)
            mm(G[k - a], tmp3, out=xs[k][:, :, None])
            if r is not None:
                xs[k][r] = 0.0
        if with_cov:
            if Ps is None:
                Ps = Pp[-1].copy()
                var[b] = np.diag(Ps)
            end_l = ends[0, a:b].tolist()  # Python bools: read once per epoch
            for k in range(b - 1, a - 1, -1):
                i = k - a
                if end_l[i]:
                    Ps = Pp[i].copy()
                else:
                    Ps = Pp[i] + G[i] @ (Ps - Pm[i + 1]) @ G[i].T
                var[k] = np.diag(Ps)
    return xs, var


def _smooth_result(res: EskfResult, xs: np.ndarray, sd: np.ndarray, ends: np.ndarray) -> EskfSmoothResult:
    """The smoothed solution (corrected one plus ``xs`` (N, 21)) and each epoch's latency to its window end."""
    n = res.t_s.size
    pos = res.pos_n_m + xs[:, POS]
    vel = res.vel_n_mps + xs[:, VEL]
    mat = np.matmul(rotvecs_to_dcm(xs[:, ATT]), res.mat_nb)
    sensor = res.sensor + xs[:, 9:21]
    # latency: time from each epoch to the end of its window
    end_idx = np.flatnonzero(ends)
    which = np.searchsorted(end_idx, np.arange(n), side="left")
    latency = res.t_s[end_idx[which]] - res.t_s
    return EskfSmoothResult(t_s=res.t_s, pos_n_m=pos, vel_n_mps=vel, mat_nb=mat, sensor=sensor, xs=xs, sd=sd,
                            latency_s=latency)


def eskf_rts_smooth(res: EskfResult, window_s: float | None = None, with_cov: bool = True,
                    gains: np.ndarray | None = None, offset_s: float = 0.0) -> EskfSmoothResult:
    """RTS smoother over the whole run (``window_s=None``) or over consecutive fixed windows.

    Parameters
    ----------
    res : EskfResult (the stored filter)
    window_s : float or None, window length for the online smoother (s)
    with_cov : also smooth the covariance (eq. 9) and return standard deviations
    gains : precomputed :func:`rts_gains` (reuse them across window sizes)
    offset_s : shift of the window grid (s), see :func:`window_ends`

    References
    ----------
    Liao et al. (2016), eq. (8)-(10), sec. 3.3.
    """
    ends = window_ends(res.t_s, window_s, offset_s)
    xs, var = _backward(res, ends[None], gains, with_cov)
    # variances -> standard deviations
    sd = np.sqrt(np.clip(var, 0.0, None)) if with_cov else np.full((res.t_s.size, N_STATES), np.nan)
    return _smooth_result(res, xs[:, 0], sd, ends)


def eskf_rts_smooth_grids(res: EskfResult, grids, gains: np.ndarray | None = None) -> list[EskfSmoothResult]:
    """:func:`eskf_rts_smooth` (state only, ``with_cov=False``) on several window grids in one backward pass.

    ``grids``: a sequence of ``(window_s, offset_s)`` (``window_s=None``: the whole run). Returns one
    :class:`EskfSmoothResult` per grid, the same bits as ``eskf_rts_smooth(res, window_s, False, gains,
    offset_s)`` each (``xs`` of each is a view into one (N, M, 21) array); the per-epoch Python work is shared by
    all grids.

    References
    ----------
    Liao et al. (2016), eq. (8) and (10), sec. 3.3.
    """
    grids = list(grids)
    if not grids:
        return []
    ends = np.array([window_ends(res.t_s, w, o) for w, o in grids])
    xs, _ = _backward(res, ends, gains)
    return [_smooth_result(res, xs[:, j], np.full((res.t_s.size, N_STATES), np.nan), ends[j])
            for j in range(len(grids))]


def online_window_smooth(res: EskfResult, window_s: float, with_cov: bool = False,
                         gains: np.ndarray | None = None, offset_s: float = 0.0) -> EskfSmoothResult:
    """The paper's online smoother: RTS on each fixed window of ``window_s`` seconds as it fills.

    References
    ----------
    Liao et al. (2016), sec. 3.3 and Fig. 3 (windows of 5, 10, 20 s in Tables 8-11).
    """
    if window_s is None:
        raise ValueError("window_s must be a window length in seconds for the online smoother")
    return eskf_rts_smooth(res, window_s=window_s, with_cov=with_cov, gains=gains, offset_s=offset_s)


class ErrorStateINS:
    """Thin wrapper: run the 21-state filter once, then smooth it (whole run or online windows).

    Parameters
    ----------
    P0 : (21, 21) initial covariance; config : :class:`ilocalg.ins.eskf.EskfConfig`

    Attributes
    ----------
    result_ : EskfResult after :meth:`fit`
    """

    def __init__(self, P0, config=None):
        self.P0 = P0
        self.config = config

    def fit(self, t_s, gyr_b_radps, acc_b_mps2, pos0_n_m, vel0_n_mps, mat0_nb, updates=()) -> ErrorStateINS:
        from ilocalg.ins.eskf import run_eskf

        self.result_ = run_eskf(t_s, gyr_b_radps, acc_b_mps2, pos0_n_m, vel0_n_mps, mat0_nb, self.P0, updates,
                                self.config)
        self.gains_ = rts_gains(self.result_)
        return self

    def smooth(self, window_s: float | None = None, with_cov: bool = False) -> EskfSmoothResult:
        """:func:`eskf_rts_smooth` of the fitted filter (``window_s=None``: whole run)."""
        if not hasattr(self, "result_"):
            raise ValueError("call fit() before smooth()")
        return eskf_rts_smooth(self.result_, window_s=window_s, with_cov=with_cov, gains=self.gains_)
