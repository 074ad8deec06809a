"""Benchmark: a sweep of 1,000 simulated walks on Dask, 2 workers against 1 worker in the same run.

Each task is one walk: :func:`ilocalg.experiments.study_kf_noise.run` with ``n_walks=1`` and
``N_STEPS`` steps (simulate the synthetic walk and its Wi-Fi fixes, run the i-Loc step Kalman
filter, the dead-reckoned track and the RTS smoother, score them): about 0.05-0.1 s of work.
The 1,000 tasks (seeds 0..999) are run through :func:`ilocalg.sweep.sweep` on a
:class:`~distributed.LocalCluster` with one single-threaded worker process, then with two, each
cluster started (and the experiment imported on every worker) before the clock starts; the ratio
of the two wall times is the scaling figure (issue target: <= 0.55). Both sweeps must give the
same results bit for bit.

Memory: the driver's peak Python allocation (tracemalloc, covering both sweeps and their result
frames), the driver's peak RSS and each worker's peak RSS (``getrusage`` in the worker). The
1-minute load average before each sweep is recorded: on a machine shared with other jobs the
ratio says more about them than about the sweep.

Run: ``PYTHONPATH=$PWD python benchmarks/bench_sweep.py`` (prints the numbers) or
``PYTHONPATH=$PWD python -m pytest benchmarks/bench_sweep.py -s``. The machine must be otherwise
idle for the ratio to mean anything: two workers on two cores shared with other jobs cannot scale.
"""

from __future__ import annotations

import os
import resource
import time
import tracemalloc

import pandas as pd

from ilocalg.sweep import make_tasks, sweep

N_WALKS = 1000
N_STEPS = 1000
TARGET_RATIO = 0.55
EXPERIMENT = "study_kf_noise"


def walk_tasks(n_walks: int = N_WALKS, n_steps: int = N_STEPS) -> list:
    """One task per simulated walk (seeds 0..n_walks-1)."""
    return make_tasks(EXPERIMENT, range(n_walks), {"n_walks": [1], "n_steps": [n_steps]})


def _peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def _warm(name: str) -> bool:
    import importlib

    importlib.import_module(f"ilocalg.experiments.{name}")
    return True


def timed_sweep(tasks: list, n_workers: int) -> dict:
    """Wall time of ``sweep(tasks)`` on a ready LocalCluster of ``n_workers`` single-threaded processes."""
    from dask.distributed import Client, LocalCluster

    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    try:
        client.wait_for_workers(n_workers, timeout=120)
        client.run(_warm, EXPERIMENT)
        startup = time.perf_counter() - t0
        t1 = time.perf_counter()
        res = sweep(tasks, client=client, cache_dir=None, progress=False)
        wall = time.perf_counter() - t1
        worker_rss = client.run(_peak_rss_mb)
    finally:
        client.close()
        cluster.close()
    return {"wall_s": wall, "startup_s": startup, "result": res, "worker_peak_rss_mb": max(worker_rss.values()),
            "load_before": load}


def measure(n_walks: int = N_WALKS, n_steps: int = N_STEPS) -> dict:
    """Run the sweep with 1 and 2 workers; return timings, ratio, memory and the result check."""
    tasks = walk_tasks(n_walks, n_steps)
    tracemalloc.start()
    one = timed_sweep(tasks, 1)
    two = timed_sweep(tasks, 2)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()

    def srt(df):
        return df.sort_values(["seed", "item", "quantity"]).reset_index(drop=True)

    r1, r2 = one["result"], two["result"]
    same = not r1.failures and not r2.failures and srt(r1.results).equals(srt(r2.results))
    kf = r2.results[(r2.results["quantity"] == "mean error") & (r2.results["item"] == "method=step KF")]
    return {
        "walks": n_walks, "steps_per_walk": n_steps, "failed": len(r1.failures) + len(r2.failures),
        "wall_1_worker_s": one["wall_s"], "wall_2_workers_s": two["wall_s"],
        "ratio_2_over_1": two["wall_s"] / one["wall_s"], "target_ratio": TARGET_RATIO,
        "s_per_walk_1_worker": one["wall_s"] / n_walks,
        "cluster_startup_1_s": one["startup_s"], "cluster_startup_2_s": two["startup_s"],
        "loadavg_1min_before_1": one["load_before"], "loadavg_1min_before_2": two["load_before"],
        "driver_peak_tracemalloc_mb": peak / 2**20, "driver_peak_rss_mb": _peak_rss_mb(),
        "worker_peak_rss_mb_1": one["worker_peak_rss_mb"], "worker_peak_rss_mb_2": two["worker_peak_rss_mb"],
        "results_rows": len(r2.results), "identical_results": bool(same),
        "step_kf_mean_error_m": float(kf["value"].mean()),
    }


def test_bench_sweep_1000_walks(benchmark):
    m = benchmark.pedantic(measure, rounds=1, iterations=1)
    benchmark.extra_info.update(m)
    print(pd.Series(m).to_string())
    assert m["failed"] == 0 and m["identical_results"]
    assert m["ratio_2_over_1"] <= TARGET_RATIO, m


if __name__ == "__main__":
    for k, v in measure().items():
        print(f"{k:>28}: {v:.4g}" if isinstance(v, float) else f"{k:>28}: {v}")
