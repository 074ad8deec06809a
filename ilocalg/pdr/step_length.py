"""Step-length models: Weinberg, Kim, the fingerprint+PDR paper's nonlinear model, and the i-Loc SLM.

All functions are vectorised over steps: pass one value per step (arrays of shape ``(n_steps,)``)
and get one length per step, in metres. Accelerations are in m/s^2.

References
----------
PSO thesis (003), eq. (2.1) (Kim) and eq. (2.5) (Weinberg / Lei Fang);
fingerprint+PDR paper (004), eq. (4);
i-Loc thesis (000), sec. 4.2, eq. (16)-(17) (SLM linear and quadratic regressions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "weinberg_length_m",
    "kim_length_m",
    "luo_length_m",
    "fit_weinberg_k",
    "slm_design",
    "fit_slm",
    "slm_length_m",
    "SLM",
    "StepLengthFit",
]


def _as_float(name: str, x) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64)
    if a.size and not np.all(np.isfinite(a)):
        bad = int(np.flatnonzero(~np.isfinite(a.ravel()))[0])
        raise ValueError(f"{name} must be finite; element {bad} is {a.ravel()[bad]}")
    return a


def _range(a_max_mps2, a_min_mps2) -> np.ndarray:
    hi = _as_float("a_max_mps2", a_max_mps2)
    lo = _as_float("a_min_mps2", a_min_mps2)
    if hi.shape != lo.shape:
        raise ValueError(f"a_max_mps2 and a_min_mps2 must have the same shape, got {hi.shape} and {lo.shape}")
    d = hi - lo
    if d.size and np.any(d < 0):
        bad = int(np.flatnonzero(d.ravel() < 0)[0])
        raise ValueError(f"a_max_mps2 must be >= a_min_mps2; step {bad} has max {hi.ravel()[bad]} < min "
                         f"{lo.ravel()[bad]}")
    return d


def weinberg_length_m(a_max_mps2, a_min_mps2, k: float):
    """Weinberg step length ``k (a_max - a_min)^(1/4)``.

    Parameters
    ----------
    a_max_mps2, a_min_mps2 : array_like, shape (n_steps,)
        Largest and smallest (vertical) acceleration within each step, m/s^2.
    k : float
        Walker-specific constant, m / (m/s^2)^(1/4) (about 0.4-0.55 for adults).

    Returns
    -------
    ndarray, shape (n_steps,)
        Step length, m.

    References
    ----------
    PSO thesis (003), eq. (2.5) (after Weinberg; Lei Fang et al.).
    """
    return float(k) * _range(a_max_mps2, a_min_mps2) ** 0.25


def luo_length_m(a_max_mps2, a_min_mps2, k: float):
    """Nonlinear step length ``k ((a_max - a_min) 3.5 + (a_max - a_min)^(1/4))``.

    References
    ----------
    Fingerprint+PDR paper (004), sec. 3.4.2 (3), eq. (4).
    """
    d = _range(a_max_mps2, a_min_mps2)
    return float(k) * (d * 3.5 + d ** 0.25)  # the paper's eq. (4)


def kim_length_m(acc_abs_mean_mps2, c: float = 0.98):  # 0.98: paper eq. (2.1)
    """Kim step length ``c (mean |A|)^(1/3)`` with the step's mean absolute acceleration.

    Parameters
    ----------
    acc_abs_mean_mps2 : array_like, shape (n_steps,)
        Mean of ``|A_k|`` over the samples of each step, m/s^2 (for a handheld phone use the
        gravity-removed acceleration; the original used a foot-mounted sensor).
    c : float
        Scale, m / (m/s^2)^(1/3); 0.98 in the original (the PSO thesis's eq. 2.1).

    References
    ----------
    PSO thesis (003), eq. (2.1) (after Jeng Won Kim et al.).
    """
    a = _as_float("acc_abs_mean_mps2", acc_abs_mean_mps2)
    if a.size and np.any(a < 0):
        raise ValueError("acc_abs_mean_mps2 must be >= 0 (a mean of absolute values)")
    return float(c) * np.cbrt(a)


def fit_weinberg_k(a_max_mps2, a_min_mps2, length_m) -> float:
    """Least-squares ``k`` of :func:`weinberg_length_m` from steps of known length (closed form)."""
    f = _range(a_max_mps2, a_min_mps2).ravel() ** 0.25
    y = _as_float("length_m", length_m).ravel()
    if f.shape != y.shape or f.size == 0:
        raise ValueError(f"need one length_m per step, got {y.size} lengths for {f.size} steps")
    den = float(f @ f)
    if den <= 0:
        raise ValueError("cannot fit k: every step has a_max == a_min")
    return float(f @ y) / den


def slm_design(A_mps2, X1_mps2, kind: str = "quadratic") -> np.ndarray:
    """Design matrix of the SLM regressions.

    ``linear``: columns ``[1, A, X1]`` (eq. 16); ``quadratic``: ``[1, A, X1, A X1, A^2, X1^2]`` (eq. 17).

    Returns
    -------
    ndarray, shape (n_steps, 3) or (n_steps, 6)

    References
    ----------
    i-Loc thesis (000), eq. (16)-(17).
    """
    A = _as_float("A_mps2", A_mps2).ravel()
    X = _as_float("X1_mps2", X1_mps2).ravel()
    if A.shape != X.shape:
        raise ValueError(f"A_mps2 and X1_mps2 must have the same length, got {A.size} and {X.size}")
    one = np.ones_like(A)
    if kind == "linear":
        return np.column_stack([one, A, X])
    if kind == "quadratic":
        return np.column_stack([one, A, X, A * X, A * A, X * X])
    raise ValueError(f"kind must be 'linear' or 'quadratic', got {kind!r}")


@dataclass(frozen=True)
class StepLengthFit:
    """A fitted SLM regression: coefficients ``p`` (p1, p2, ...) and the training RMSE (m)."""

    kind: str
    p: tuple
    rmse_m: float
    n_steps: int


def fit_slm(A_mps2, X1_mps2, length_m, kind: str = "quadratic") -> StepLengthFit:
    """Least-squares fit of the SLM regression ``D = M p`` (eq. 16 or 17).

    Parameters
    ----------
    A_mps2, X1_mps2 : array_like, shape (n_steps,)
        SAM features A (eq. 13) and X1 (eq. 15) of each step.
    length_m : array_like, shape (n_steps,)
        True step length, m.
    kind : {"linear", "quadratic"}

    References
    ----------
    i-Loc thesis (000), eq. (16)-(17), Table 3.
    """
    M = slm_design(A_mps2, X1_mps2, kind)
    y = _as_float("length_m", length_m).ravel()
    if y.size != M.shape[0]:
        raise ValueError(f"need one length_m per step, got {y.size} lengths for {M.shape[0]} steps")
    if y.size < M.shape[1]:
        raise ValueError(f"{kind} SLM needs at least {M.shape[1]} steps, got {y.size}")
    p, *_ = np.linalg.lstsq(M, y, rcond=None)
    rmse = float(np.sqrt(np.mean((M @ p - y) ** 2)))
    return StepLengthFit(kind=kind, p=tuple(float(v) for v in p), rmse_m=rmse, n_steps=int(y.size))


def slm_length_m(A_mps2, X1_mps2, p, kind: str = "quadratic"):
    """Step length from the SLM regression with coefficients ``p`` (eq. 16 or 17), m."""
    M = slm_design(A_mps2, X1_mps2, kind)
    p = np.asarray(p, dtype=np.float64)
    if p.shape != (M.shape[1],):
        raise ValueError(f"{kind} SLM needs {M.shape[1]} coefficients, got shape {p.shape}")
    return M @ p


class SLM:
    """Thin estimator around :func:`fit_slm` / :func:`slm_length_m`.

    Parameters
    ----------
    kind : {"linear", "quadratic"}
    """

    def __init__(self, kind: str = "quadratic"):
        self.kind = kind

    def fit(self, A_mps2, X1_mps2, length_m) -> SLM:
        self.fit_ = fit_slm(A_mps2, X1_mps2, length_m, self.kind)
        self.p_ = np.asarray(self.fit_.p)
        return self

    def predict(self, A_mps2, X1_mps2):
        if not hasattr(self, "p_"):
            raise ValueError("SLM is not fitted; call fit() first")
        return slm_length_m(A_mps2, X1_mps2, self.p_, self.kind)
