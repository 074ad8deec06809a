"""Particle swarm optimisation exactly as the PSO pedestrian-navigation thesis states it.

Velocity and position update (eq. 4.1-4.2), for particle ``i`` at generation ``k``::

    v_i(k+1) = w v_i(k) + c1 rand1 (pbest_i(k) - S_i(k)) + c2 rand2 (gbest(k) - S_i(k))
    S_i(k+1) = S_i(k) + v_i(k+1)

with ``rand1``, ``rand2`` uniform on [0, 1) drawn afresh per particle and per dimension, the
velocity clamped element-wise to ``[-max_speed, max_speed]`` and the inertia weight falling from
``w_init`` to ``w_final`` as (eq. 4.3)::

    w_i = A / (i + 1) + B,   A = (w_init - w_final)(iters + 1) / iters,   B = w_init - A.

The thesis prints the first term as ``A / (iters + 1)``, which is a constant (``w_final``) and
contradicts its own sentence that ``w_i`` decreases with the iteration count; ``A / (i + 1)`` gives
``w_0 = w_init`` and ``w_iters = w_final``, the schedule the text describes. The update that makes
generation ``k+1`` uses ``w_k``.

Flow (Fig. 4.1-4.2): initialise positions uniformly in the bounds and velocities uniformly in
``[-max_speed, max_speed]``; then repeat: evaluate, update pbest and gbest, stop when
``gbest fitness < min_fitness`` or after ``max_iters`` updates, else update velocities and positions.
Positions are not confined to the bounds (the thesis does not), the bounds only seed the swarm.

Thesis settings (sec. 5.3): 10 particles, maxIters 100, maxSpeed 0.1, minFitness 0.1,
w_init 1.0, w_final 0.1, c1 = c2 = 2.0; they are this module's defaults.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Eq. 4.1-4.3, Figs. 4.1-4.2, sec. 5.3; J. Kennedy and
R. Eberhart, "Particle swarm optimization", Proc. ICNN 1995.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.units import as_rng

__all__ = ["PSOResult", "inertia_schedule", "pso_minimize", "pso_minimize_many", "ParticleSwarm"]


def inertia_schedule(max_iters: int, w_init: float = 1.0, w_final: float = 0.1) -> np.ndarray:
    """Inertia weights ``w_0 ... w_iters`` of eq. 4.3.

    Parameters
    ----------
    max_iters : int
        ``iters``, the maximum number of iterations (>= 1).
    w_init, w_final : float
        Initial and final weight.

    Returns
    -------
    ndarray, shape (max_iters + 1,)
        ``w_i = A/(i+1) + B`` with ``A = (w_init - w_final)(iters+1)/iters``, ``B = w_init - A``;
        ``w_0 = w_init``, ``w_iters = w_final``.

    References
    ----------
    PSO thesis, eq. 4.3.
    """
    if not isinstance(max_iters, (int, np.integer)) or isinstance(max_iters, bool) or max_iters < 1:
        raise ValueError(f"max_iters must be an int >= 1, got {max_iters!r}")
    A = (w_init - w_final) * (max_iters + 1) / max_iters
    B = w_init - A
    i = np.arange(max_iters + 1, dtype=float)
    return A / (i + 1.0) + B


@dataclass(frozen=True)
class PSOResult:
    """Outcome of :func:`pso_minimize`.

    Attributes
    ----------
    x_best : ndarray, shape (dim,)
        gbest position.
    f_best : float
        Its fitness.
    n_iters : int
        Generations after the initial one (the thesis's ``Iters``).
    converged : bool
        True when the run stopped because ``f_best < min_fitness``.
    best_particle : int
        Index of the particle that holds gbest (the thesis's ``Index``).
    positions : ndarray, shape (n_iters + 1, n_particles, dim)
        The swarm at every generation (generation 0 = initial).
    fitness : ndarray, shape (n_iters + 1, n_particles)
        Fitness of every particle at every generation.
    gbest_x : ndarray, shape (n_iters + 1, dim)
        gbest after evaluating each generation.
    gbest_f : ndarray, shape (n_iters + 1,)
        Its fitness (non-increasing).
    inertia : ndarray, shape (n_iters + 1,)
        ``w_k`` used to move from generation k to k+1 (last entry: the next weight, unused).
    """

    x_best: np.ndarray
    f_best: float
    n_iters: int
    converged: bool
    best_particle: int
    positions: np.ndarray = field(repr=False)
    fitness: np.ndarray = field(repr=False)
    gbest_x: np.ndarray = field(repr=False)
    gbest_f: np.ndarray = field(repr=False)
    inertia: np.ndarray = field(repr=False)

    def swarm_table(self) -> pd.DataFrame:
        """Long table of the swarm: ``iteration``, ``particle``, ``x0`` ... ``fitness``, ``is_gbest``."""
        n_gen, n_p, dim = self.positions.shape
        it = np.repeat(np.arange(n_gen), n_p)
        df = pd.DataFrame({"iteration": it, "particle": np.tile(np.arange(n_p), n_gen)})
        flat = self.positions.reshape(n_gen * n_p, dim)
        for d in range(dim):
            df[f"x{d}"] = flat[:, d]
        df["fitness"] = self.fitness.ravel()
        best = np.argmin(self.fitness, axis=1)
        df["is_gen_best"] = df["particle"].to_numpy() == best[it]
        return df

    def history_table(self) -> pd.DataFrame:
        """Per generation: ``iteration``, ``inertia``, ``gbest_fitness``, ``gbest_x0`` ..."""
        df = pd.DataFrame({"iteration": np.arange(self.gbest_f.size), "inertia": self.inertia,
                           "gbest_fitness": self.gbest_f})
        for d in range(self.gbest_x.shape[1]):
            df[f"gbest_x{d}"] = self.gbest_x[:, d]
        return df


def _check_bounds(bounds) -> tuple[np.ndarray, np.ndarray]:
    b = np.asarray(bounds, dtype=float)
    if b.ndim == 1 and b.size == 2:
        b = b[None, :]
    if b.ndim != 2 or b.shape[1] != 2 or b.shape[0] < 1:
        raise ValueError(f"bounds must be (low, high) or a sequence of (low, high) pairs, got shape {b.shape}")
    if not np.all(np.isfinite(b)) or np.any(b[:, 1] <= b[:, 0]):
        raise ValueError(f"bounds must be finite with low < high in every dimension, got {b.tolist()}")
    return b[:, 0], b[:, 1]


def _check_settings(bounds, n_particles, max_iters, max_speed, min_fitness, w_init, w_final, c1, c2):
    low, high = _check_bounds(bounds)
    if not isinstance(n_particles, (int, np.integer)) or isinstance(n_particles, bool) or n_particles < 1:
        raise ValueError(f"n_particles must be an int >= 1, got {n_particles!r}")
    w = inertia_schedule(max_iters, w_init, w_final)
    vmax = np.broadcast_to(np.asarray(max_speed, dtype=float), (low.size,)).copy()
    if not np.all(np.isfinite(vmax)) or np.any(vmax <= 0):
        raise ValueError(f"max_speed must be positive and finite, got {max_speed!r}")
    if not np.isfinite(c1) or not np.isfinite(c2) or c1 < 0 or c2 < 0:
        raise ValueError(f"c1 and c2 must be finite and >= 0, got {c1!r}, {c2!r}")
    if np.isnan(min_fitness):
        raise ValueError("min_fitness must not be NaN (use -inf to disable the early stop)")
    return low, high, w, vmax


def pso_minimize(fitness: Callable, bounds, n_particles: int = 10, max_iters: int = 100,
                 max_speed: float | np.ndarray = 0.1, min_fitness: float = 0.1, w_init: float = 1.0,
                 w_final: float = 0.1, c1: float = 2.0, c2: float = 2.0,
                 rng: np.random.Generator | int | None = None, vectorized: bool = False) -> PSOResult:
    """Minimise ``fitness`` with the thesis's particle swarm (eq. 4.1-4.3, Fig. 4.2).

    Parameters
    ----------
    fitness : callable
        ``fitness(x) -> float`` for ``x`` of shape (dim,); with ``vectorized=True``,
        ``fitness(X) -> (n_particles,)`` for ``X`` of shape (n_particles, dim).
    bounds : (low, high) or sequence of (low, high)
        Box in which the initial swarm is drawn uniformly; its length sets ``dim``.
    n_particles, max_iters : int
        Swarm size and maximum number of updates (thesis: 10, 100).
    max_speed : float or ndarray (dim,)
        Element-wise velocity clamp (thesis: 0.1).
    min_fitness : float
        Stop as soon as the gbest fitness is below this (thesis: 0.1); ``-inf`` disables it.
    w_init, w_final : float
        Inertia schedule ends (eq. 4.3; thesis: 1.0, 0.1).
    c1, c2 : float
        Learning factors (thesis: 2.0, 2.0).
    rng : Generator, int or None
        Random source; the same seed gives the same swarm.
    vectorized : bool
        Evaluate the whole swarm in one call.

    Returns
    -------
    PSOResult

    See Also
    --------
    pso_minimize_many : several independent swarms in one pass (the same swarms, bit for bit).

    References
    ----------
    PSO thesis, eq. 4.1-4.3, Figs. 4.1-4.2, settings of sec. 5.3.
    """
    return pso_minimize_many(fitness, bounds, [rng], n_particles=n_particles, max_iters=max_iters,
                             max_speed=max_speed, min_fitness=min_fitness, w_init=w_init, w_final=w_final,
                             c1=c1, c2=c2, vectorized=vectorized)[0]


def pso_minimize_many(fitness: Callable, bounds, rngs, n_particles: int = 10, max_iters: int = 100,
                      max_speed: float | np.ndarray = 0.1, min_fitness: float = 0.1, w_init: float = 1.0,
                      w_final: float = 0.1, c1: float = 2.0, c2: float = 2.0,
                      vectorized: bool = False) -> list[PSOResult]:
    """Independent runs of :func:`pso_minimize` on one fitness, one swarm per random source, moved in lockstep.

    Swarm ``r`` draws from ``rngs[r]`` alone and in the order :func:`pso_minimize` draws (initial positions,
    initial velocities, then ``rand1`` and ``rand2`` per update), and every update is element-wise, so each
    result equals ``pso_minimize(..., rng=rngs[r])`` bit for bit (with a vectorised fitness whose value for
    a particle does not depend on the other rows of the call). A swarm that stops (``min_fitness`` reached
    or ``max_iters`` done) is no longer evaluated nor moved; the others go on. The whole batch is one array
    per quantity, so the per-update cost of numpy's calls is paid once for all swarms.

    Parameters
    ----------
    fitness : callable
        As in :func:`pso_minimize`; with ``vectorized=True`` it is called on the particles of every
        running swarm at once, ``X`` of shape (n_running * n_particles, dim), swarm after swarm.
    bounds
        As in :func:`pso_minimize`.
    rngs : sequence of (Generator, int or None)
        One random source per swarm.
    n_particles, max_iters, max_speed, min_fitness, w_init, w_final, c1, c2, vectorized
        As in :func:`pso_minimize` (the same for every swarm).

    Returns
    -------
    list of PSOResult, one per entry of ``rngs``, in that order.

    References
    ----------
    PSO thesis, eq. 4.1-4.3, Figs. 4.1-4.2, settings of sec. 5.3.
    """
    low, high, w, vmax = _check_settings(bounds, n_particles, max_iters, max_speed, min_fitness, w_init, w_final,
                                         c1, c2)
    gens = [as_rng(r) for r in rngs]
    n_swarms, n_p, dim = len(gens), int(n_particles), low.size
    if n_swarms < 1:
        raise ValueError("rngs must hold at least one random source")

    def evaluate(S):
        if vectorized:
            f = np.asarray(fitness(S), dtype=float).reshape(-1)
            if f.size != S.shape[0]:
                raise ValueError(f"vectorized fitness must return {S.shape[0]} values, got {f.size}")
        else:
            f = np.array([float(fitness(s)) for s in S])
        if np.any(np.isnan(f)):
            raise ValueError(f"fitness returned NaN at {S[np.isnan(f)][0].tolist()}")
        return f

    u = np.empty((n_swarms, 2, n_p, dim))
    for j, g in enumerate(gens):  # per swarm: positions, then velocities (the draws of pso_minimize)
        g.random(out=u[j])
    S = low + (high - low) * u[:, 0]
    v = vmax * (2.0 * u[:, 1] - 1.0)
    n_gen = max_iters + 1
    pos = np.empty((n_gen, n_swarms, n_p, dim))
    fit = np.empty((n_gen, n_swarms, n_p))
    gx = np.empty((n_gen, n_swarms, dim))
    gf = np.empty((n_gen, n_swarms))
    n_iters = np.zeros(n_swarms, dtype=int)
    converged = np.zeros(n_swarms, dtype=bool)
    g_best = np.zeros(n_swarms, dtype=int)
    x_best = np.empty((n_swarms, dim))
    f_best = np.empty(n_swarms)
    active = np.arange(n_swarms)  # the swarms still running, in order; S, v, pbest hold their rows only
    sel = slice(None)  # their rows in the history arrays (a slice while all run)
    rows = np.arange(n_swarms)
    pbest = S.copy()
    pbest_f = np.full((n_swarms, n_p), np.inf)
    k = 0
    while True:
        f = evaluate(S.reshape(-1, dim)).reshape(-1, n_p)
        pos[k, sel] = S
        fit[k, sel] = f
        better = f < pbest_f
        np.copyto(pbest, S, where=better[:, :, None])
        np.copyto(pbest_f, f, where=better)
        g_idx = pbest_f.argmin(axis=1)
        gbx = pbest[rows, g_idx]
        gbf = pbest_f[rows, g_idx]
        gx[k, sel] = gbx
        gf[k, sel] = gbf
        conv = gbf < min_fitness
        stop = conv if k < max_iters else np.ones_like(conv)
        if stop.any():
            done = active[stop]
            n_iters[done] = k
            converged[done] = conv[stop]
            g_best[done] = g_idx[stop]
            x_best[done] = gbx[stop]
            f_best[done] = gbf[stop]
            keep = ~stop
            if not keep.any():
                break
            active, S, v, pbest, pbest_f, gbx = active[keep], S[keep], v[keep], pbest[keep], pbest_f[keep], gbx[keep]
            sel, rows = active, np.arange(active.size)
        r = np.empty((active.size, 2, n_p, dim))
        for i, j in enumerate(active.tolist()):  # rand1 then rand2, from the swarm's own source
            gens[j].random(out=r[i])
        v = w[k] * v + c1 * r[:, 0] * (pbest - S) + c2 * r[:, 1] * (gbx[:, None, :] - S)  # eq. 4.1
        np.clip(v, -vmax, vmax, out=v)
        S = S + v  # eq. 4.2
        k += 1
    return [PSOResult(x_best=x_best[j].copy(), f_best=float(f_best[j]), n_iters=int(n_iters[j]),
                      converged=bool(converged[j]), best_particle=int(g_best[j]),
                      positions=pos[:n_iters[j] + 1, j].copy(), fitness=fit[:n_iters[j] + 1, j].copy(),
                      gbest_x=gx[:n_iters[j] + 1, j].copy(), gbest_f=gf[:n_iters[j] + 1, j].copy(),
                      inertia=w[:n_iters[j] + 1].copy())
            for j in range(n_swarms)]


class ParticleSwarm:
    """Thin wrapper keeping the PSO settings; :meth:`minimize` calls :func:`pso_minimize`.

    Parameters are those of :func:`pso_minimize` (thesis defaults).
    """

    def __init__(self, n_particles: int = 10, max_iters: int = 100, max_speed: float = 0.1,
                 min_fitness: float = 0.1, w_init: float = 1.0, w_final: float = 0.1,
                 c1: float = 2.0, c2: float = 2.0):
        self.n_particles = n_particles
        self.max_iters = max_iters
        self.max_speed = max_speed
        self.min_fitness = min_fitness
        self.w_init = w_init
        self.w_final = w_final
        self.c1 = c1
        self.c2 = c2

    def get_params(self) -> dict:
        return {k: getattr(self, k) for k in ("n_particles", "max_iters", "max_speed", "min_fitness",
                                               "w_init", "w_final", "c1", "c2")}

    def minimize(self, fitness: Callable, bounds, rng=None, vectorized: bool = False) -> PSOResult:
        """Run :func:`pso_minimize` with the stored settings."""
        return pso_minimize(fitness, bounds, rng=rng, vectorized=vectorized, **self.get_params())
