"""Benchmark: the batched step filter (ilocalg.fusion.filter_walks) against filterpy's per-step loop.

Same inputs, same run: ``N_WALKS`` seeded walks of ``N_STEPS`` steps (a fix every 3 states, 5 %
outliers, innovation gate on). The reference is :class:`ilocalg.fusion.StepKalmanFilter`, i.e.
filterpy's ``KalmanFilter.predict`` / ``update`` called once per step and fix, walk after walk.
The results must agree (1e-9) and the speed-up is recorded in ``extra_info`` (target >= 10x).
``speedup`` is against the leanest filterpy loop (B and Q precomputed, no gate: pure filterpy
predict + update cost); ``gated_speedup`` is against the full per-step class with the gate.

Run: ``PYTHONPATH=$PWD python -m pytest benchmarks/bench_fusion.py --benchmark-only`` or
``PYTHONPATH=$PWD python benchmarks/bench_fusion.py`` (prints the ratio).
"""

from __future__ import annotations

import time

import numpy as np
from conftest import size

from ilocalg import fusion as fu

N_WALKS = size(128, 8)  # smoke run (ILOC_BENCH_SMOKE=1, benchmarks/conftest.py): the small size
N_STEPS = size(300, 60)
TARGET_SPEEDUP = 10.0


def make_inputs(n_walks: int = N_WALKS, n_steps: int = N_STEPS, seed: int = 0) -> dict:
    walks = [fu.straight_walk(n_steps, rng=seed + i, fix_every=3, outlier_fraction=0.05, turn_every=40)
             for i in range(n_walks)]
    step = np.stack([w.step_m for w in walks])
    return {
        "x0_m": np.stack([w.truth_xy_m[0] for w in walks]),
        "P0_m2": 4.0 * np.eye(2),
        "theta_rad": np.stack([w.theta_rad for w in walks]),
        "step_m": step,
        "sigma_sl_m": fu.sigma_sl_paper_m(step),
        "z_m": np.stack([w.z_m for w in walks]),
        "r_var_m2": 9.0,
        "gate_nis": fu.nis_gate(0.999),
    }


def run_batched(inp: dict) -> fu.StepKFResult:
    return fu.filter_walks(**inp)


def run_filterpy_loop(inp: dict) -> list[fu.StepKFResult]:
    out = []
    for i in range(inp["theta_rad"].shape[0]):
        kf = fu.StepKalmanFilter(inp["x0_m"][i], inp["P0_m2"], gate_nis=inp["gate_nis"])
        out.append(kf.run(inp["theta_rad"][i], inp["step_m"][i], inp["sigma_sl_m"][i], inp["z_m"][i],
                          r_var_m2=inp["r_var_m2"]))
    return out


def run_filterpy_raw(inp: dict) -> tuple[np.ndarray, np.ndarray]:
    """The leanest filterpy loop: B and Q precomputed, one predict per step and one update per fix, no gate."""
    from filterpy.kalman import KalmanFilter

    th, st, sig, z = inp["theta_rad"], inp["step_m"], inp["sigma_sl_m"], inp["z_m"]
    Bs = fu.step_control(th)[..., None]
    Qs = fu.step_process_noise(th, sig)
    R = inp["r_var_m2"] * np.eye(2)
    has = ~np.isnan(z[..., 0])
    n_w, n = th.shape
    xs = np.empty((n_w, n + 1, 2))
    Ps = np.empty((n_w, n + 1, 2, 2))
    for i in range(n_w):
        kf = KalmanFilter(dim_x=2, dim_z=2)
        kf.x = inp["x0_m"][i].reshape(2, 1).copy()
        kf.P = np.array(inp["P0_m2"], dtype=float)
        kf.F = np.eye(2)
        kf.H = np.eye(2)
        for k in range(n + 1):
            if k > 0:
                kf.predict(u=st[i, k - 1], B=Bs[i, k - 1], Q=Qs[i, k - 1])
            if has[i, k]:
                kf.update(z[i, k].reshape(2, 1), R=R)
            xs[i, k] = kf.x[:, 0]
            Ps[i, k] = kf.P
    return xs, Ps


def _best_of(fn, arg, repeat):
    best, res = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = fn(arg)
        best = min(best, time.perf_counter() - t0)
    return best, res


def measure(repeat: int = 3) -> dict:
    """Time both paths on the same inputs, check they agree, return the timings and the ratio."""
    inp = make_inputs()
    t_ref, ref = _best_of(run_filterpy_loop, inp, 1)
    t_fast, fast = _best_of(run_batched, inp, repeat)
    max_dx = max(float(np.abs(fast.x[i] - r.x).max()) for i, r in enumerate(ref))
    max_dp = max(float(np.abs(fast.P[i] - r.P).max()) for i, r in enumerate(ref))
    same_gate = all(np.array_equal(fast.accepted[i], r.accepted) for i, r in enumerate(ref))
    # without the gate: the leanest filterpy loop against the batched path
    plain = {k: v for k, v in inp.items() if k != "gate_nis"}
    t_raw, (xr, Pr) = _best_of(run_filterpy_raw, plain, 1)
    t_fast_plain, fp = _best_of(run_batched, plain, repeat)
    return {"n_walks": N_WALKS, "n_steps": N_STEPS,
            "gated_filterpy_class_s": t_ref, "gated_batched_s": t_fast, "gated_speedup": t_ref / t_fast,
            "gated_max_abs_dx_m": max_dx, "gated_max_abs_dP_m2": max_dp, "same_gating": same_gate,
            "n_rejected": int(fast.n_rejected.sum()),
            "raw_filterpy_loop_s": t_raw, "plain_batched_s": t_fast_plain, "speedup": t_raw / t_fast_plain,
            "max_abs_dx_m": float(np.abs(fp.x - xr).max()), "max_abs_dP_m2": float(np.abs(fp.P - Pr).max())}


def test_bench_batched_vs_filterpy(benchmark):
    m = measure()
    benchmark.extra_info.update(m)
    assert m["max_abs_dx_m"] < 1e-9 and m["max_abs_dP_m2"] < 1e-9
    assert m["gated_max_abs_dx_m"] < 1e-9 and m["gated_max_abs_dP_m2"] < 1e-9 and m["same_gating"]
    # the speed-up goal (TARGET_SPEEDUP) is checked by the gate (benchmarks/goals.toml), not here
    inp = make_inputs()
    benchmark.pedantic(run_batched, args=(inp,), rounds=3, iterations=1)


if __name__ == "__main__":
    for k, v in measure().items():
        print(f"{k:>16}: {v}")
