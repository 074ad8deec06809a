"""Optimisers: the particle swarm of the PSO pedestrian-navigation thesis (eq. 4.1-4.3)."""

from ilocalg.optim.pso import ParticleSwarm, PSOResult, inertia_schedule, pso_minimize, pso_minimize_many

__all__ = ["ParticleSwarm", "PSOResult", "inertia_schedule", "pso_minimize", "pso_minimize_many"]
