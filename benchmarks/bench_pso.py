"""Speed of the thesis PSO and of the great-circle DR, as ratios to scipy / vectorised references."""

import numpy as np
from conftest import best_time_s
from scipy.optimize import minimize_scalar

from ilocalg import gnss
from ilocalg.optim import pso_minimize

Q = np.random.default_rng(0).uniform(1.3, 1.7, 200)
D = 0.47 * Q.sum()


def _fit(K):
    return np.abs(D - K[:, 0] * Q.sum())


def _pso():
    return pso_minimize(_fit, (0, 1), rng=0, vectorized=True, min_fitness=-np.inf)


def _scipy():
    return minimize_scalar(lambda k: abs(D - k * Q.sum()), bounds=(0, 5), method="bounded")


def test_pso_1d_thesis_settings(benchmark):
    benchmark(_pso)
    ratio = best_time_s(_pso) / best_time_s(_scipy)
    benchmark.extra_info["ratio_to_scipy_minimize_scalar"] = ratio


def test_dead_reckon_400_steps(benchmark):
    b = np.random.default_rng(1).uniform(0, 360, 400)
    s = np.full(400, 0.75)
    benchmark(gnss.dead_reckon_latlon, 24.18, 120.6, b, s)

    def one_by_one():
        la, lo = 24.18, 120.6
        for i in range(400):
            la, lo = gnss.destination(la, lo, b[i], s[i])

    benchmark.extra_info["ratio_to_chained_destination"] = (
        best_time_s(lambda: gnss.dead_reckon_latlon(24.18, 120.6, b, s)) / best_time_s(one_by_one))
