"""Learning the Weinberg step-length factor ``k`` of one walker from a walk of known length.

A walk of ``N`` detected steps with ``q_j = (Amax_j - Amin_j)^(1/4)`` (the Weinberg length for
``k = 1``) and a reference distance ``D`` (GPS track length, surveyed waypoints) gives ``k`` by
minimising the fitness of Chao (2008) eq. 4.4 with the PSO of :func:`ilocalg.optim.pso_minimize`.
Eq. 4.4 is written per step ("S_gps is the step length computed from GPS, S_ins the step length
estimated by inertial navigation", Chao 2008, L632-634); how the terms combine over a walk is not
written. Two readings:

``"per_step"`` (default)
    ``mean_j |D / N - k q_j|``; its minimiser is the weighted median of ``(D / N) / q_j`` with
    weights ``q_j``; the least-squares analogue is ``k = (D / N) sum q / sum q^2``. The thesis's own
    result block (Fig. 5.12, L834 and L840) reports Fitness = 0.0939 with the PSO distance 2.0996 m
    off the GPS distance, which this reading allows and the walk-total reading does not.
``"total"`` (alternative)
    ``|D - k sum_j q_j|``; its zero is the closed form ``k = D / sum q_j``
    (:func:`ilocalg.pdr.step_length.k_from_distance`, also the least-squares solution). Under it
    the thesis's Fitness 0.0939 would mean a distance difference below 0.1 m.

In this one-parameter problem the PSO's answer is set by its stop rule: it stops at the first
iteration whose best fitness is below ``minFitness`` (0.1, L811), anywhere in the interval of k
where the fitness is below 0.1 (:func:`stop_interval`), not at the minimiser; the closed forms give
the minimiser itself.

The closed forms and ``scipy.optimize.minimize_scalar`` (bounded) on the same fitness are
returned beside the PSO's ``k`` as references.

This lives in ``pdr`` (beside :func:`ilocalg.pdr.step_length.fit_weinberg_k`), not in ``optim``:
it is a step-length calibration written against the step detectors' table; ``optim`` keeps the
generic optimiser it calls.

Settings from the paper
-----------------------
:data:`PSO_SETTINGS_PAPER`: Chao (2008) sec. 5.3, L807-812 (10 particles, 100 iterations,
maxSpeed 0.1, minFitness 0.1 m, inertia 1.0 -> 0.1, c1 = c2 = 2). :data:`K_BOUNDS` (the initial
swarm's box) is not in the thesis: it is this toolkit's choice.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Eq. 2.5, 4.1-4.4, sec. 5.3.
Weinberg, H. (2002). Using the ADXL202 in pedometer and personal navigation applications.
Analog Devices AN-602.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.optimize import minimize_scalar

from ilocalg.optim import PSOResult, pso_minimize, pso_minimize_many
from ilocalg.pdr.step_length import k_from_distance, weinberg_length_m

__all__ = [
    "PSO_SETTINGS_PAPER",
    "K_BOUNDS",
    "FITNESSES",
    "step_factors",
    "distance_fitness",
    "per_step_fitness",
    "closed_form_k",
    "stop_interval",
    "learn_k",
    "learn_k_repeats",
]

#: PSO settings of Chao (2008), sec. 5.3.
PSO_SETTINGS_PAPER = {"n_particles": 10, "max_iters": 100, "max_speed": 0.1, "min_fitness": 0.1,
                      "w_init": 1.0, "w_final": 0.1, "c1": 2.0, "c2": 2.0}
#: Search box for the initial swarm (k, m / (m/s^2)^(1/4)): not in the thesis, the toolkit's choice.
K_BOUNDS = (0.0, 1.0)
#: The two readings of eq. 4.4 (the first is the default).
FITNESSES = ("per_step", "total")


def step_factors(steps: pd.DataFrame) -> np.ndarray:
    """``q_j = (Amax_j - Amin_j)^(1/4)`` of every detected step (the Weinberg length for k = 1).

    Raises
    ------
    ValueError
        When ``steps`` is empty (no steps detected: k cannot be learned) or lacks the columns.
    """
    for c in ("a_max_mps2", "a_min_mps2"):
        if c not in steps.columns:
            raise ValueError(f"steps lack column {c!r} (use a step detector's output)")
    if len(steps) == 0:
        raise ValueError("no steps detected: the walk gives nothing to learn k from")
    return weinberg_length_m(steps["a_max_mps2"].to_numpy(float), steps["a_min_mps2"].to_numpy(float), 1.0)


def distance_fitness(k, q: np.ndarray, d_gps_m: float) -> np.ndarray:
    """Eq. 4.4 over a walk: ``|D_gps - k sum q|`` (vectorised over ``k``), m."""
    k = np.asarray(k, dtype=float)
    return np.abs(d_gps_m - k * float(np.sum(q)))


def per_step_fitness(k, q: np.ndarray, d_gps_m: float) -> np.ndarray:
    """Eq. 4.4 per step, averaged: ``mean_j |D_gps / N - k q_j|`` (vectorised over ``k``), m."""
    k = np.atleast_1d(np.asarray(k, dtype=float))
    s_gps = d_gps_m / q.size
    out = np.mean(np.abs(s_gps - k[:, None] * q[None, :]), axis=1)
    return out


def closed_form_k(q: np.ndarray, d_gps_m: float, fitness: str = "per_step") -> dict:
    """Closed-form references: the fitness minimiser and the least-squares k.

    Returns
    -------
    dict
        ``k_min``: exact minimiser of the chosen fitness (total: ``D/sum q``; per_step: weighted
        median of ``(D/N)/q_j`` with weights ``q_j``); ``k_ls``: least squares (total: ``D/sum q``;
        per_step: ``(D/N) sum q / sum q^2``).
    """
    q = np.asarray(q, dtype=float)
    if fitness == "total":
        k = k_from_distance(q, d_gps_m)
        return {"k_min": k, "k_ls": k}
    if fitness == "per_step":
        s = d_gps_m / q.size
        r = s / q
        order = np.argsort(r)
        cw = np.cumsum(q[order])
        k_med = float(r[order][np.searchsorted(cw, 0.5 * cw[-1])])
        return {"k_min": k_med, "k_ls": float(s * q.sum() / (q @ q))}
    raise ValueError(f"fitness must be 'total' or 'per_step', got {fitness!r}")


def stop_interval(q: np.ndarray, d_gps_m: float, fitness: str = "per_step",
                  min_fitness: float = PSO_SETTINGS_PAPER["min_fitness"]) -> tuple[float, float]:
    """The interval of k whose fitness is below ``min_fitness``: where the PSO may stop (m, m).

    Both readings are convex in ``k``, so the set is one interval around the minimiser; ``(nan,
    nan)`` when even the minimiser's fitness is not below ``min_fitness`` (the PSO then runs to
    maxIters).
    """
    q = np.asarray(q, dtype=float)
    f = _fitness_fn(fitness, q, d_gps_m)
    k0 = closed_form_k(q, d_gps_m, fitness)["k_min"]

    def g(k):
        return float(f(np.array([[k]]))[0]) - min_fitness

    if g(k0) >= 0:
        return float("nan"), float("nan")
    from scipy.optimize import brentq

    lo, hi = k0, k0
    step = max(abs(k0), 1e-3)
    while g(lo) < 0:
        lo -= step
    while g(hi) < 0:
        hi += step
    return float(brentq(g, lo, k0)), float(brentq(g, k0, hi))


def _fitness_fn(fitness: str, q, d):
    if fitness == "total":
        return lambda K: distance_fitness(K[:, 0], q, d)
    if fitness == "per_step":
        return lambda K: per_step_fitness(K[:, 0], q, d)
    raise ValueError(f"fitness must be 'total' or 'per_step', got {fitness!r}")


def learn_k(steps: pd.DataFrame, d_gps_m: float, fitness: str = "per_step", rng=None,
            pso_settings: dict | None = None) -> tuple[dict, PSOResult]:
    """Learn the Weinberg factor of one walk by PSO, with the closed-form and scipy references.

    Parameters
    ----------
    steps : DataFrame
        Detected steps (``a_max_mps2``, ``a_min_mps2``).
    d_gps_m : float
        GPS distance of the walk, m.
    fitness : {"per_step", "total"}
        Reading of eq. 4.4 (module docstring); ``"per_step"`` by default.
    rng : Generator, int or None
        PSO random source.
    pso_settings : dict, optional
        Overrides of :data:`PSO_SETTINGS_PAPER`.

    Returns
    -------
    summary : dict
        ``k_pso``, ``fitness_pso``, ``iters``, ``best_particle``, ``k_closed``, ``k_ls``,
        ``k_scipy``, ``fitness_closed``, ``n_steps``, ``sum_q``, ``k_stop_lo``, ``k_stop_hi`` (the
        interval where the stop rule may end the PSO, :func:`stop_interval`).
    result : PSOResult
    """
    if not np.isfinite(d_gps_m) or d_gps_m <= 0:
        raise ValueError(f"d_gps_m must be a positive distance, got {d_gps_m!r}")
    q = step_factors(steps)
    f = _fitness_fn(fitness, q, d_gps_m)
    settings = {**PSO_SETTINGS_PAPER, **(pso_settings or {})}
    res = pso_minimize(f, K_BOUNDS, rng=rng, vectorized=True, **settings)
    ref = closed_form_k(q, d_gps_m, fitness)
    sp = minimize_scalar(lambda k: float(f(np.array([[k]]))[0]), bounds=(0.0, 5.0), method="bounded",
                         options={"xatol": 1e-8})
    summary = {
        "k_pso": float(res.x_best[0]),
        "fitness_pso_m": res.f_best,
        "iters": res.n_iters,
        "best_particle": res.best_particle,
        "k_closed": float(ref["k_min"]),
        "k_ls": float(ref["k_ls"]),
        "k_scipy": float(sp.x),
        "fitness_closed_m": float(f(np.array([[ref["k_min"]]]))[0]),
        "n_steps": int(q.size),
        "sum_q": float(q.sum()),
        **dict(zip(("k_stop_lo", "k_stop_hi"), stop_interval(q, d_gps_m, fitness, settings["min_fitness"]),
                   strict=True)),
    }
    return summary, res


def learn_k_repeats(steps: pd.DataFrame, d_gps_m: float, fitness: str = "per_step", rngs=(),
                    pso_settings: dict | None = None) -> tuple[dict, list[PSOResult]]:
    """:func:`learn_k` of one walk from several random sources: the PSO once per source, the references once.

    The closed-form minimiser and the stop interval do not depend on the random source, so they are computed once
    (``k_closed``, ``k_ls``, ``k_stop_lo``, ``k_stop_hi``, ``n_steps``, ``sum_q``); the swarms run in one lockstep
    pass (:func:`ilocalg.optim.pso_minimize_many`), each the one ``learn_k(..., rng=rngs[r])`` runs, bit for bit.

    Returns
    -------
    summary : dict
        The seed-independent entries of :func:`learn_k`'s summary.
    results : list of PSOResult, one per entry of ``rngs`` (``x_best[0]`` is that run's ``k_pso``).
    """
    if not np.isfinite(d_gps_m) or d_gps_m <= 0:
        raise ValueError(f"d_gps_m must be a positive distance, got {d_gps_m!r}")
    q = step_factors(steps)
    f = _fitness_fn(fitness, q, d_gps_m)
    settings = {**PSO_SETTINGS_PAPER, **(pso_settings or {})}
    results = pso_minimize_many(f, K_BOUNDS, list(rngs), vectorized=True, **settings)
    ref = closed_form_k(q, d_gps_m, fitness)
    summary = {"k_closed": float(ref["k_min"]), "k_ls": float(ref["k_ls"]), "n_steps": int(q.size),
               "sum_q": float(q.sum()),
               **dict(zip(("k_stop_lo", "k_stop_hi"), stop_interval(q, d_gps_m, fitness, settings["min_fitness"]),
                          strict=True))}
    return summary, results
