"""Step-length models: Weinberg, Kim, the fingerprint+PDR paper's nonlinear model, and the i-Loc SLM.

All functions are vectorised over steps: pass one value per step (arrays of shape ``(n_steps,)``)
and get one length per step, in metres. Accelerations are in m/s^2.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Eq. (2.1) (Kim) and eq. (2.5) (Weinberg / Lei Fang).
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Eq. (4).
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.2, eq. (16)-(17) (SLM linear and quadratic regressions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = [
    "weinberg_length_m",
    "kim_length_m",
    "luo_length_m",
    "fit_weinberg_k",
    "k_from_distance",
    "fit_scale",
    "luo_steps",
    "fit_luo_k",
    "luo_lengths",
    "kim_mean_abs_mps2",
    "fit_step_length_models",
    "step_lengths_m",
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
    Chao (2008), eq. (2.5) (after Weinberg; Lei Fang et al.).
    """
    return float(k) * _range(a_max_mps2, a_min_mps2) ** 0.25


def luo_length_m(a_max_mps2, a_min_mps2, k: float):
    """Nonlinear step length ``k ((a_max - a_min) 3.5 + (a_max - a_min)^(1/4))``.

    References
    ----------
    Luo et al. (2017), sec. 3.4.2 (3), eq. (4).
    """
    d = _range(a_max_mps2, a_min_mps2)
    return float(k) * (d * 3.5 + d ** 0.25)


def kim_length_m(acc_abs_mean_mps2, c: float = 0.98):
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
    Chao (2008), eq. (2.1) (after Jeng Won Kim et al.).
    """
    a = _as_float("acc_abs_mean_mps2", acc_abs_mean_mps2)
    if a.size and np.any(a < 0):
        raise ValueError("acc_abs_mean_mps2 must be >= 0 (a mean of absolute values)")
    return float(c) * np.cbrt(a)


def fit_scale(unit_length_m, length_m) -> float:
    """Least-squares scale ``k`` of ``length = k unit_length`` through the origin, ``f.y / f.f``.

    Parameters
    ----------
    unit_length_m : array_like, shape (n_steps,)
        Each step's model length for ``k = 1`` (e.g. ``(a_max - a_min)^(1/4)``).
    length_m : array_like, shape (n_steps,)
        True step lengths, m.
    """
    f = _as_float("unit_length_m", unit_length_m).ravel()
    y = _as_float("length_m", length_m).ravel()
    if f.shape != y.shape or f.size == 0:
        raise ValueError(f"need one length_m per step, got {y.size} lengths for {f.size} steps")
    den = float(f @ f)
    if den <= 0:
        raise ValueError("cannot fit k: every step has a zero model length (a_max == a_min)")
    return float(f @ y) / den


def fit_weinberg_k(a_max_mps2, a_min_mps2, length_m) -> float:
    """Least-squares ``k`` of :func:`weinberg_length_m` from steps of known length (closed form)."""
    return fit_scale(_range(a_max_mps2, a_min_mps2).ravel() ** 0.25, length_m)


def k_from_distance(unit_length_m, distance_m: float) -> float:
    """Step-length factor from a walk of known length: ``k = D / sum_j f_j``.

    The ``k`` whose steps add up to the reference distance ``D`` (GPS track length, surveyed
    waypoints, a walk of known length): the zero of Chao (2008) eq. 4.4 read over the whole walk.

    Parameters
    ----------
    unit_length_m : array_like, shape (n_steps,) or scalar
        Each step's model length for ``k = 1`` (or their total), m.
    distance_m : float
        Reference distance, m.

    Raises
    ------
    ValueError
        When the distance is not positive and finite or the steps add up to zero (no steps).

    References
    ----------
    Chao, S.-H. (2008), eq. 4.4.
    """
    d = float(distance_m)
    if not np.isfinite(d) or d <= 0:
        raise ValueError(f"distance_m must be a positive distance, got {distance_m!r}")
    total = float(np.sum(_as_float("unit_length_m", unit_length_m)))
    if not total > 0:
        raise ValueError("unit_length_m adds up to zero: no step to scale to the distance")
    return d / total


def slm_design(A_mps2, X1_mps2, kind: str = "quadratic") -> np.ndarray:
    """Design matrix of the SLM regressions.

    ``linear``: columns ``[1, A, X1]`` (eq. 16); ``quadratic``: ``[1, A, X1, A X1, A^2, X1^2]`` (eq. 17).

    Returns
    -------
    ndarray, shape (n_steps, 3) or (n_steps, 6)

    References
    ----------
    Chiu (2013), eq. (16)-(17).
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
    Chiu (2013), eq. (16)-(17), Table 3.
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


def luo_steps(acc_mps2, t_s, k: float, detector: dict | None = None) -> pd.DataFrame:
    """Luo et al. (2017) PDR steps: peak-window detection (sec. 3.4.2) and eq. (4) lengths.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3) or (n,)
    t_s : array_like, shape (n,)
    k : float
        Factor of :func:`luo_length_m`.
    detector : dict, optional
        Parameters of :func:`ilocalg.pdr.peak_window.detect_steps_peak_window`.

    Returns
    -------
    DataFrame
        The detector's steps with ``length_m`` added.

    References
    ----------
    Luo et al. (2017), sec. 3.4.2, eq. (4).
    """
    from ilocalg.pdr.peak_window import detect_steps_peak_window

    return luo_lengths(detect_steps_peak_window(acc_mps2, t_s, **(detector or {})), k)


def luo_lengths(steps: pd.DataFrame, k: float) -> pd.DataFrame:
    """The peak-window detector's ``steps`` with eq. (4)'s ``length_m`` added (a new frame; :func:`luo_steps`)."""
    return steps.assign(length_m=luo_length_m(steps["a_max_mps2"], steps["a_min_mps2"], k))


def fit_luo_k(walks, detector: dict | None = None, steps=None) -> tuple[float, float]:
    """``k`` of eq. (4) from walks of known length, and the per-step length error sd.

    ``k`` = total true length over total eq. (4) length at ``k = 1``
    (:func:`k_from_distance`). The error sd is the standard deviation, over every detected step,
    of ``k f_j`` minus the walk's true mean step (the step-length noise of a filter).

    Parameters
    ----------
    walks : iterable of (acc_mps2, t_s, true_step_length_m)
        Training walks: accelerometer log, times and the true length of every step taken.
    detector : dict, optional
        Parameters of the peak-window detector.
    steps : sequence of DataFrame, optional
        Each walk's steps already detected, ``luo_steps(acc, t, 1.0, detector)`` (in ``walks``' order; the
        walks' accelerometer logs are then not read).

    Returns
    -------
    k : float
    sigma_step_m : float

    References
    ----------
    Luo et al. (2017), eq. (4).
    """
    f_tot, l_tot = 0.0, 0.0
    per_walk = []
    for i, (acc, t, true_m) in enumerate(walks):
        st = luo_steps(acc, t, 1.0, detector) if steps is None else steps[i]
        if not len(st):
            continue
        true_m = np.asarray(true_m, dtype=np.float64)
        f_tot += float(st["length_m"].sum())
        l_tot += float(true_m.sum())
        per_walk.append((st["length_m"].to_numpy(), float(true_m.mean())))
    if f_tot <= 0:
        raise ValueError("fit_luo_k: no step detected in the training walks")
    k = k_from_distance(f_tot, l_tot)
    res = [k * f - mean_true for f, mean_true in per_walk]
    return k, float(np.std(np.concatenate(res)))


def kim_mean_abs_mps2(acc_mps2, steps: pd.DataFrame) -> np.ndarray:
    """Mean ``|a_perp|`` over each SAM wave (left valley to right valley), the input of :func:`kim_length_m`.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3)
    steps : DataFrame
        SAM steps (columns ``i_left``, ``i_right``).
    """
    from ilocalg.pdr.sam import vertical_horizontal_mps2

    for c in ("i_left", "i_right"):
        if c not in steps.columns:
            raise ValueError(f"steps lack column {c!r} (use SAM steps)")
    v, _ = vertical_horizontal_mps2(acc_mps2)
    c = np.concatenate([[0.0], np.cumsum(np.abs(v))])
    lo, hi = steps["i_left"].to_numpy(), steps["i_right"].to_numpy() + 1
    return (c[hi] - c[lo]) / (hi - lo)


#: Name of the Luo et al. (2017) eq. (4) model in :func:`fit_step_length_models` (the label earlier result
#: tables carry; kept so they stay byte-identical).
LUO_MODEL = "Luo et al. 2017 eq. 4"


def fit_step_length_models(features: pd.DataFrame) -> tuple[dict, pd.DataFrame]:
    """Fit the SLM (linear, quadratic), Weinberg and Luo models on training steps of known length.

    Parameters
    ----------
    features : DataFrame
        One row per training step: SAM features ``A``, ``X1``, ``a_max_mps2``, ``a_min_mps2`` and
        the true ``length_m``.

    Returns
    -------
    models : dict
        ``"SLM linear"``, ``"SLM quadratic"`` (coefficient arrays, m), ``"Weinberg"`` and
        :data:`LUO_MODEL` (factors ``k``, least squares).
    fits : DataFrame
        The SLM fits: ``model``, ``rmse_cm`` and coefficients ``p1_cm ...`` in centimetres.

    References
    ----------
    Chiu (2013) eq. (16)-(17), Table 3; Chao (2008) eq. 2.5; Luo et al. (2017) eq. (4).
    """
    missing = [c for c in ("A", "X1", "length_m", "a_max_mps2", "a_min_mps2") if c not in features.columns]
    if missing:
        raise ValueError(f"features lack columns {missing}")
    A, X1, L = features["A"].to_numpy(), features["X1"].to_numpy(), features["length_m"].to_numpy()
    hi, lo = features["a_max_mps2"].to_numpy(), features["a_min_mps2"].to_numpy()
    lin, quad = fit_slm(A, X1, L, "linear"), fit_slm(A, X1, L, "quadratic")
    kw = fit_weinberg_k(hi, lo, L)
    kl = fit_scale(luo_length_m(hi, lo, 1.0), L)
    models = {"SLM linear": np.array(lin.p), "SLM quadratic": np.array(quad.p), "Weinberg": kw, LUO_MODEL: kl}
    return models, pd.DataFrame([
        {"model": "SLM linear", "rmse_cm": lin.rmse_m * 100, **{f"p{i + 1}_cm": v * 100 for i, v in enumerate(lin.p)}},
        {"model": "SLM quadratic", "rmse_cm": quad.rmse_m * 100,
         **{f"p{i + 1}_cm": v * 100 for i, v in enumerate(quad.p)}},
    ])


def step_lengths_m(acc_mps2, steps: pd.DataFrame, models: dict) -> pd.DataFrame:
    """Per-step lengths (m) of every model of :func:`fit_step_length_models` (plus ``"Kim"``) for SAM steps."""
    A, X1 = steps["A"].to_numpy(), steps["X1"].to_numpy()
    hi, lo = steps["a_max_mps2"].to_numpy(), steps["a_min_mps2"].to_numpy()
    return pd.DataFrame({
        "SLM linear": slm_length_m(A, X1, models["SLM linear"], "linear"),
        "SLM quadratic": slm_length_m(A, X1, models["SLM quadratic"], "quadratic"),
        "Weinberg": weinberg_length_m(hi, lo, models["Weinberg"]),
        LUO_MODEL: luo_length_m(hi, lo, models[LUO_MODEL]),
        "Kim": kim_length_m(kim_mean_abs_mps2(acc_mps2, steps), models["Kim"]),
    })
