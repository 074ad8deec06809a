"""Tests of ilocalg.optim.pso (PSO thesis eq. 4.1-4.3)."""

import numpy as np
import pytest

from ilocalg.optim import ParticleSwarm, inertia_schedule, pso_minimize, pso_minimize_many


def sphere(x):
    return float(np.sum(x**2))


def rosenbrock(x):
    return float(100 * (x[1] - x[0] ** 2) ** 2 + (1 - x[0]) ** 2)


def rastrigin(X):
    X = np.atleast_2d(X)
    return 10 * X.shape[1] + np.sum(X**2 - 10 * np.cos(2 * np.pi * X), axis=1)


@pytest.mark.parametrize("iters", [1, 9, 100])
def test_inertia_schedule_ends_and_monotone(iters):
    w = inertia_schedule(iters, 1.0, 0.1)
    assert w.shape == (iters + 1,)
    assert w[0] == pytest.approx(1.0) and w[-1] == pytest.approx(0.1)
    assert np.all(np.diff(w) < 0)


def test_inertia_schedule_formula():
    iters, wi, wf = 100, 0.9, 0.4
    A = (wi - wf) * (iters + 1) / iters
    B = wi - A
    np.testing.assert_allclose(inertia_schedule(iters, wi, wf), A / (np.arange(iters + 1) + 1) + B)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_sphere_minimum(seed):
    res = pso_minimize(sphere, [(-5, 5)] * 3, n_particles=20, max_iters=300, max_speed=1.0,
                       min_fitness=-np.inf, w_init=0.9, w_final=0.4, c1=1.5, c2=1.5, rng=seed)
    assert res.f_best < 1e-6
    np.testing.assert_allclose(res.x_best, 0, atol=1e-3)


def test_rosenbrock_minimum():
    res = pso_minimize(rosenbrock, [(-2, 2), (-1, 3)], n_particles=30, max_iters=600, max_speed=0.5,
                       min_fitness=-np.inf, w_init=0.9, w_final=0.4, c1=1.5, c2=1.5, rng=0)
    np.testing.assert_allclose(res.x_best, [1, 1], atol=2e-2)


def test_rastrigin_global_minimum_vectorized():
    res = pso_minimize(rastrigin, [(-5.12, 5.12)] * 2, n_particles=40, max_iters=300, max_speed=1.0,
                       min_fitness=-np.inf, w_init=0.9, w_final=0.4, c1=1.5, c2=1.5, rng=3, vectorized=True)
    assert res.f_best < 1e-4
    np.testing.assert_allclose(res.x_best, 0, atol=1e-3)


def test_thesis_settings_on_a_1d_distance_fitness():
    # |S_gps - k * sum amp^(1/4)|, minimum at k = 0.47: the thesis PSO stops once fitness < 0.1
    s = 300.0
    res = pso_minimize(lambda k: abs(100.0 - k[0] * s / 1.0), (0.0, 1.0), rng=5)
    assert res.converged and res.f_best < 0.1
    assert res.x_best[0] == pytest.approx(100.0 / s, abs=0.1 / s + 1e-12)
    assert res.n_iters < 100


def test_history_and_velocity_clamp():
    res = pso_minimize(sphere, [(-5, 5)] * 2, max_iters=20, max_speed=0.1, min_fitness=-np.inf, rng=0)
    assert res.positions.shape == (21, 10, 2) and res.fitness.shape == (21, 10)
    assert np.all(np.abs(np.diff(res.positions, axis=0)) <= 0.1 + 1e-12)
    assert np.all(np.diff(res.gbest_f) <= 0)
    assert res.gbest_f[-1] == res.f_best
    assert res.fitness.min() == pytest.approx(res.f_best)
    np.testing.assert_allclose(res.inertia, inertia_schedule(20)[:21])
    tab = res.swarm_table()
    assert len(tab) == 21 * 10 and tab.is_gen_best.sum() == 21
    assert list(res.history_table().columns) == ["iteration", "inertia", "gbest_fitness", "gbest_x0", "gbest_x1"]


def test_same_seed_same_swarm_and_class_agrees():
    a = pso_minimize(sphere, [(-1, 1)] * 2, rng=7, min_fitness=1e-3)
    b = ParticleSwarm(min_fitness=1e-3).minimize(sphere, [(-1, 1)] * 2, rng=7)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert a.f_best == b.f_best and a.n_iters == b.n_iters
    c = pso_minimize(sphere, [(-1, 1)] * 2, rng=8, min_fitness=1e-3)
    assert not np.array_equal(a.positions[0], c.positions[0])


def _reference_swarm(fitness, low, high, rng, n_particles, max_iters, min_fitness, w_init, w_final,
                     max_speed=0.1, c1=2.0, c2=2.0):
    """Eq. 4.1-4.3 and Fig. 4.2 written out for one swarm, one generation at a time (the pre-batch code)."""
    w = inertia_schedule(max_iters, w_init, w_final)
    S = low + (high - low) * rng.random((n_particles, 1))
    v = max_speed * (2.0 * rng.random((n_particles, 1)) - 1.0)
    pbest, pbest_f, k, hist = S.copy(), np.full(n_particles, np.inf), 0, []
    while True:
        f = np.array([fitness(s) for s in S])
        hist.append(S.copy())
        better = f < pbest_f
        pbest[better], pbest_f[better] = S[better], f[better]
        g = int(np.argmin(pbest_f))
        if pbest_f[g] < min_fitness or k >= max_iters:
            return np.stack(hist), pbest[g], pbest_f[g], k, bool(pbest_f[g] < min_fitness)
        r1, r2 = rng.random((n_particles, 1)), rng.random((n_particles, 1))
        v = np.clip(w[k] * v + c1 * r1 * (pbest - S) + c2 * r2 * (pbest[g] - S), -max_speed, max_speed)
        S = S + v
        k += 1


@pytest.mark.parametrize("vectorized", [True, False])
def test_many_swarms_equal_single_runs_bit_for_bit(vectorized):
    # 1-D distance fitness whose stop rule ends the swarms at different iterations, some at maxIters
    q = np.random.default_rng(4).uniform(1.2, 1.8, 57)
    d = 0.52 * q.sum()

    def fit(K):
        return np.mean(np.abs(d / q.size - np.atleast_2d(K)[:, :1] * q[None, :]), axis=1)

    def fit1(k):
        return float(fit(k)[0])

    kw = {"n_particles": 2, "max_iters": 3, "min_fitness": 0.1, "w_init": 0.7, "w_final": 0.7}
    seeds = [[9, r] for r in range(12)]
    many = pso_minimize_many(fit if vectorized else fit1, (0.0, 1.0), [np.random.default_rng(s) for s in seeds],
                             vectorized=vectorized, **kw)
    assert len({r.n_iters for r in many}) > 2 and any(r.converged for r in many) and not all(r.converged for r in many)
    for s, m in zip(seeds, many, strict=True):
        one = pso_minimize(fit if vectorized else fit1, (0.0, 1.0), rng=np.random.default_rng(s),
                           vectorized=vectorized, **kw)
        for name in ("x_best", "positions", "fitness", "gbest_x", "gbest_f", "inertia"):
            assert getattr(m, name).tobytes() == getattr(one, name).tobytes(), name
        assert (m.f_best, m.n_iters, m.converged, m.best_particle) == (
            one.f_best, one.n_iters, one.converged, one.best_particle)
        pos, x, f, k, conv = _reference_swarm(fit1, 0.0, 1.0, np.random.default_rng(s), **kw)
        assert (pos.tobytes(), x.tobytes(), f, k, conv) == (m.positions.tobytes(), m.x_best.tobytes(), m.f_best,
                                                            m.n_iters, m.converged)


def test_bad_input():
    with pytest.raises(ValueError, match="bounds"):
        pso_minimize(sphere, [(1, 0)])
    with pytest.raises(ValueError, match="max_iters"):
        pso_minimize(sphere, [(0, 1)], max_iters=0)
    with pytest.raises(ValueError, match="max_speed"):
        pso_minimize(sphere, [(0, 1)], max_speed=0)
    with pytest.raises(ValueError, match="n_particles"):
        pso_minimize(sphere, [(0, 1)], n_particles=0)
    with pytest.raises(ValueError, match="NaN"):
        pso_minimize(lambda x: np.nan, [(0, 1)])
    with pytest.raises(ValueError, match="vectorized"):
        pso_minimize(lambda X: np.zeros(3), [(0, 1)], vectorized=True)
    with pytest.raises(ValueError, match="rngs"):
        pso_minimize_many(sphere, [(0, 1)], [])
