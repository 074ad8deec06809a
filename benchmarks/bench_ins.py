"""Speed of the 21-state ESKF + RTS smoother against real time and against filterpy.

Scenario: 60 s of a 100 Hz IMU (6000 epochs) on a level circle, a position fix every second and a
body-velocity (NHC-like) update every 0.5 s. Reported: real-time factor (log duration / compute time)
of filter + RTS (state only, as the online smoother needs it) and with the smoothed covariance, and the
ratio to filterpy's KalmanFilter + rts_smoother fed the same 21x21 transition matrices (a linear filter
with precomputed matrices, i.e. a lower bound of what a per-step Python EKF costs).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import best_time_s
from filterpy.kalman import KalmanFilter

from ilocalg import ins

DURATION_S = 60.0
RATE_HZ = 100.0


def _scenario():
    n = int(DURATION_S * RATE_HZ)
    dt = 1.0 / RATE_HZ
    t = np.arange(n) * dt
    v, w = 1.2, 0.25
    rng = np.random.default_rng(0)
    f = np.tile([0.0, v * w, 9.80665], (n, 1)) + rng.normal(0, 0.05, (n, 3))
    g = np.tile([0.0, 0.0, w], (n, 1)) + rng.normal(0, 0.005, (n, 3))
    pos, _, _ = ins.mechanise(t, np.tile([0.0, 0.0, w], (n, 1)), np.tile([0.0, v * w, 9.80665], (n, 1)),
                              np.zeros(3), np.array([v, 0, 0]), np.eye(3))
    i1 = np.arange(100, n, 100)
    i2 = np.arange(50, n, 50)
    ups = [ins.PositionFix(t[i1], pos[i1] + rng.normal(0, 0.3, (i1.size, 3)), np.full((i1.size, 3), 0.3)),
           ins.BodyVelocity(t[i2], np.zeros((i2.size, 3)), np.tile([np.nan, 0.1, 0.1], (i2.size, 1)))]
    return t, g, f, np.array([v, 0, 0]), ups


def _run(with_cov):
    t, g, f, v0, ups = _scenario_cache
    res = ins.run_eskf(t, g, f, np.zeros(3), v0, np.eye(3), ins.initial_covariance(), ups)
    return ins.eskf_rts_smooth(res, with_cov=with_cov)


_scenario_cache = _scenario()


def _filterpy_reference():
    t, g, f, v0, ups = _scenario_cache
    res = ins.run_eskf(t, g, f, np.zeros(3), v0, np.eye(3), ins.initial_covariance(), ups)
    q = ins.process_noise_diag(res.config, 1.0 / RATE_HZ)
    kf = KalmanFilter(dim_x=21, dim_z=3)
    kf.P = ins.initial_covariance()
    kf.Q = np.diag(q)
    kf.H = np.zeros((3, 21))
    kf.H[:, 0:3] = np.eye(3)
    kf.R = np.eye(3) * 0.09
    n = t.size
    xs, Ps = np.zeros((n, 21, 1)), np.zeros((n, 21, 21))
    has = np.zeros(n, bool)
    has[np.arange(100, n, 100)] = True

    def run():
        kf.x = np.zeros((21, 1))
        kf.P = ins.initial_covariance()
        for k in range(n):
            kf.predict(F=res.Phi[k])
            if has[k]:
                kf.update(np.zeros((3, 1)))
            xs[k], Ps[k] = kf.x, kf.P
        kf.rts_smoother(xs, Ps, Fs=res.Phi, Qs=[kf.Q] * n)

    return run


@pytest.mark.parametrize("with_cov", [False, True], ids=["state", "state+cov"])
def test_eskf_rts_realtime_factor(benchmark, with_cov):
    benchmark.pedantic(_run, args=(with_cov,), rounds=3, iterations=1)
    best = benchmark.stats.stats.min
    benchmark.extra_info["realtime_factor"] = DURATION_S / best
    ref = best_time_s(_filterpy_reference(), repeat=1)
    benchmark.extra_info["filterpy_kf_rts_s"] = ref
    benchmark.extra_info["speedup_vs_filterpy"] = ref / best
    print(f"\nESKF+RTS ({'with' if with_cov else 'without'} smoothed covariance): {DURATION_S / best:.0f}x real "
          f"time at {RATE_HZ:g} Hz; filterpy KF+RTS reference {DURATION_S / ref:.0f}x; ratio {ref / best:.1f}")
