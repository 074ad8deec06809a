"""Study: PSO convergence (iterations to minFitness, success rate) vs swarm size and inertia schedule.

The fitness is the PSO thesis' eq. 4.4 in the per-step reading the PSO experiment uses by default
(:func:`ilocalg.pdr.k_factor.per_step_fitness`, ``mean_j |D_gps / N - k q_j|`` in metres; Fig. 5.12 of
the thesis supports it) on the six simulated phase-1 walks of that experiment
(:func:`ilocalg.sim.pso_walks.simulate_pso_walks`; steps by the sign-change detector after MA(nL = nR = 2)
and with the +-RMS band from the static-noise RMS of the simulated static log after the same filter, as
the PSO experiment's default (thesis L692, L718); GPS distance by
:func:`ilocalg.gnss.gps_track_length_m`). ``k*`` is that
fitness's closed-form minimiser. In this 1-D problem the PSO stops as soon as one particle's fitness
is below minFitness, often already in the initial swarm, so "iterations" here measure the stop
rule and the initial box (k in [0, 1], not in the thesis) as much as the swarm dynamics. The
optimiser is :func:`ilocalg.optim.pso_minimize` (the runs of a walk in one pass,
:func:`ilocalg.optim.pso_minimize_many`) with the thesis' settings (maxIters 100, maxSpeed
0.1, minFitness 0.1 m, c1 = c2 = 2; swarm seeded in k in [0, 1]) except the two studied: the
number of particles and the inertia schedule.

Inertia schedules (:data:`SCHEDULES`; all through eq. 4.3, ``w_i = A / (i + 1) + B`` from
``w_init`` to ``w_final``; equal ends give a constant weight):
``paper`` 1.0 -> 0.1 (the thesis), ``w0.9to0.4`` 0.9 -> 0.4 (the range of Shi & Eberhart 1998),
``const0.7`` and ``const0.4``.

Each run of a task repeats the PSO ``n_runs`` times per walk from independent random swarms.
Quantities: ``success rate`` (% of runs reaching minFitness within maxIters), ``iterations to
minFitness`` (mean over the successful runs), ``iterations`` (mean over all runs, failures count
as maxIters), ``fitness evaluations per success`` (all evaluations of all runs, ``(iters + 1) *
particles`` each, divided by the number of successful runs: the expected cost of reaching
minFitness when a failed run is restarted, which compares swarm sizes fairly) and ``final |k - k*|`` (median
distance of the returned k from the closed-form minimiser).

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Eq. 4.1-4.4, sec. 5.3.
Shi, Y. and Eberhart, R. (1998). A modified particle swarm optimizer. IEEE ICEC.
"""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd

from ilocalg.gnss import gps_track_length_m
from ilocalg.optim import pso_minimize_many
from ilocalg.pdr.k_factor import K_BOUNDS, PSO_SETTINGS_PAPER, closed_form_k, per_step_fitness, step_factors
from ilocalg.pdr.registry import detect_steps
from ilocalg.pdr.sign_change import static_rms_mps2
from ilocalg.sim.pso_walks import simulate_pso_walks, simulate_static_acc
from ilocalg.workflow.studies import select, study_row, study_tasks

__all__ = ["run", "SCHEDULES", "GRIDS", "BASE", "tasks", "findings"]

EXPERIMENT = "study_pso"
#: Inertia schedules (w_init, w_final) of eq. 4.3; "paper" is the thesis' setting.
SCHEDULES = {
    "paper": (PSO_SETTINGS_PAPER["w_init"], PSO_SETTINGS_PAPER["w_final"]),
    "w0.9to0.4": (0.9, 0.4),
    "const0.7": (0.7, 0.7),
    "const0.4": (0.4, 0.4),
}
BASE = {"n_particles": 10, "schedule": "paper"}
GRIDS = {
    False: {"n_particles": [2, 3, 5, 10, 20, 40], "schedule": list(SCHEDULES)},
    True: {"n_particles": [3, 10], "schedule": ["paper", "const0.7"]},
}


@functools.lru_cache(maxsize=16)
def _walk_factors(seed: int) -> tuple[tuple[np.ndarray, float, float], ...]:
    """``(q, D, k*)`` of each phase-1 walk of ``seed`` (``q`` read-only): every task of a seed shares them, so a
    worker process that runs several (swarm size, schedule) points of one seed simulates its walks once."""
    band = static_rms_mps2(simulate_static_acc(np.random.default_rng([int(seed), 54]))["acc_z_mps2"].to_numpy(),
                           2, 2, smooth=True)
    out = []
    for walk in simulate_pso_walks(seed)["1"]:
        q = step_factors(detect_steps("sign_change", walk.imu["acc_z_mps2"].to_numpy(), walk.imu["t_s"].to_numpy(),
                                      n_left=2, n_right=2, smooth=True, rms_mps2=band))
        q.flags.writeable = False
        d = gps_track_length_m(walk.gps)
        out.append((q, d, closed_form_k(q, d, "per_step")["k_min"]))
    return tuple(out)


def run(seed: int = 0, fast: bool = False, n_particles: int = 10, schedule: str = "paper",
        n_runs: int | None = None) -> dict[str, pd.DataFrame]:
    """PSO convergence statistics for one (swarm size, schedule) on the walks of ``seed``.

    Parameters
    ----------
    seed : int
        Seed of the simulated walks and of the swarms.
    fast : bool
        4 PSO runs per walk instead of 20 (default of ``n_runs``).
    n_particles : int, >= 1
    schedule : str
        A key of :data:`SCHEDULES`.
    n_runs : int, optional
        PSO runs per walk.
    """
    if schedule not in SCHEDULES:
        raise ValueError(f"schedule must be one of {sorted(SCHEDULES)}, got {schedule!r}")
    if int(n_particles) != n_particles or n_particles < 1:
        raise ValueError(f"n_particles must be an integer >= 1, got {n_particles!r}")
    n_runs = int(n_runs or (4 if fast else 20))
    w_init, w_final = SCHEDULES[schedule]
    settings = {k: PSO_SETTINGS_PAPER[k] for k in ("max_iters", "max_speed", "min_fitness", "c1", "c2")}
    max_iters = settings["max_iters"]
    iters, ok, dk = [], [], []
    for i, (q, d, k_star) in enumerate(_walk_factors(int(seed))):
        def fit(K, q=q, d=d):
            return per_step_fitness(K[:, 0], q, d)

        # the walk's n_runs swarms in one lockstep pass: each is the run pso_minimize gives on its own seed
        for res in pso_minimize_many(fit, K_BOUNDS, [np.random.default_rng([int(seed), 71, i, r])
                                                     for r in range(n_runs)],
                                     n_particles=int(n_particles), w_init=w_init, w_final=w_final,
                                     vectorized=True, **settings):
            iters.append(res.n_iters)
            ok.append(res.converged)
            dk.append(abs(float(res.x_best[0]) - k_star))
    iters, ok = np.asarray(iters, dtype=float), np.asarray(ok)
    conv = iters[ok]
    nan = float("nan")
    rows = [
        study_row("success rate", 100.0 * ok.mean(), "%"),
        study_row("iterations to minFitness", conv.mean() if conv.size else nan, "iterations"),
        study_row("iterations", np.where(ok, iters, max_iters).mean(), "iterations"),
        study_row("fitness evaluations per success", ((iters + 1) * n_particles).sum() / ok.sum() if ok.any() else nan,
                  "evaluations"),
        study_row("final |k - k*|", np.median(dk), "m/(m/s^2)^0.25"),
    ]
    return {"sweep_pso": pd.DataFrame(rows)}


def tasks(seeds, fast: bool = False) -> list:
    """Sweep tasks: every swarm size under every schedule (a full factorial; both are small)."""
    return study_tasks(EXPERIMENT, [GRIDS[fast]], seeds, fast=fast)


def findings(cv: pd.DataFrame) -> str:
    """Sentences computed from the study's curves (:func:`ilocalg.workflow.studies.curves`)."""
    out = []
    for sch in sorted(cv["schedule"].unique(), key=list(SCHEDULES).index):
        sr = select(cv, "success rate", schedule=sch).sort_values("n_particles")
        it = select(cv, "iterations to minFitness", schedule=sch).sort_values("n_particles")
        ev = select(cv, "fitness evaluations per success", schedule=sch).sort_values("n_particles")
        best = ev.loc[ev["mean"].idxmin()] if ev["mean"].notna().any() else None
        w0, w1 = SCHEDULES[sch]
        s = (f"Inertia {w0:g}->{w1:g} ({sch}): success {sr['mean'].iloc[0]:.0f} % with "
             f"{int(sr['n_particles'].iloc[0])} particles, {sr['mean'].iloc[-1]:.0f} % with "
             f"{int(sr['n_particles'].iloc[-1])}; iterations to minFitness {it['mean'].iloc[0]:.1f} -> "
             f"{it['mean'].iloc[-1]:.1f}")
        if best is not None:
            s += (f"; fewest fitness evaluations per success ({best['mean']:.0f}) with "
                  f"{int(best['n_particles'])} particles")
        out.append(s + f" (N={int(sr['n'].min())} seeds).")
    return "\n".join(out)
