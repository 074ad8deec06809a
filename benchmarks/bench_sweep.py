"""Benchmark: a sweep of 1,000 simulated walks on Dask, 2 workers against 1 worker in the same run.

Each task is one walk: :func:`ilocalg.experiments.study_kf_noise.run` with ``n_walks=1`` and
``N_STEPS`` steps (simulate the synthetic walk and its Wi-Fi fixes, run the i-Loc step Kalman
filter, the dead-reckoned track and the RTS smoother, score them): about 0.1 s of work on an idle core.
The 1,000 tasks (seeds 0..999) are run through :func:`ilocalg.workflow.sweep.sweep` on a
:class:`~distributed.LocalCluster` with one single-threaded worker process and on one with two,
both clusters started (and the experiment imported on every worker) before the clock starts. To
give both the same background load on a shared machine, the walks are swept in ten blocks, each
block on both clusters in alternating order; the ratio of the two summed wall times is the
scaling figure (issue target: <= 0.55). Both must give the same results bit for bit.

Memory: the peak RSS of the driver (client, scheduler and all results) and of each worker
(``getrusage`` in the worker), and the size of the collected results. (tracemalloc is not used:
it would slow the scheduler, which runs in the driver process, and distort the timing.) The
1-minute load average before each sweep is recorded: on a machine shared with other jobs the
ratio says more about them than about the sweep. CPU seconds of the workers and of the driver
(the client plus the LocalCluster's scheduler, which runs in the driver process) are recorded per
configuration: the driver's share competes with the two workers for the two cores.

Run: ``PYTHONPATH=$PWD python benchmarks/bench_sweep.py`` (prints the numbers) or
``PYTHONPATH=$PWD python -m pytest benchmarks/bench_sweep.py -s``. The machine must be otherwise
idle for the ratio to mean anything: two workers on two cores shared with other jobs cannot scale.
"""

from __future__ import annotations

import logging
import os
import resource
import time

import pandas as pd
from conftest import size

from ilocalg.workflow.sweep import make_tasks, sweep

# smoke run (ILOC_BENCH_SMOKE=1, benchmarks/conftest.py): both clusters, a few short walks in two blocks
N_WALKS = size(1000, 4)
N_STEPS = size(2000, 100)
N_BLOCKS = size(10, 2)
TARGET_RATIO = 0.55
EXPERIMENT = "study_kf_noise"


def walk_tasks(n_walks: int = N_WALKS, n_steps: int = N_STEPS) -> list:
    """One task per simulated walk (seeds 0..n_walks-1)."""
    return make_tasks(EXPERIMENT, range(n_walks), {"n_walks": [1], "n_steps": [n_steps]})


def _peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def _cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _warm(name: str) -> bool:
    import importlib

    importlib.import_module(f"ilocalg.experiments.{name}")
    return True


def start_cluster(n_workers: int):
    """A ready LocalCluster of ``n_workers`` single-threaded processes with the experiment imported."""
    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    # dashboard_address ":0": a free port, as the sweep workflow; None still binds the scheduler's HTTP server to
    # the default 8787 and warns when another process holds it
    cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    client = Client(cluster)
    client.wait_for_workers(n_workers, timeout=120)
    client.run(_warm, EXPERIMENT)
    return cluster, client, time.perf_counter() - t0


def measure(n_walks: int = N_WALKS, n_steps: int = N_STEPS, n_blocks: int = N_BLOCKS) -> dict:
    """Sweep the walks on 1 and on 2 workers; return timings, ratio, memory and the result check.

    Both clusters are started first; the walks are then split into ``n_blocks`` blocks and each
    block is swept on both clusters, in alternating order (1-2, 2-1, ...), so that both see the
    same background load. Each configuration's wall time is the sum over its blocks.
    """
    tasks = walk_tasks(n_walks, n_steps)
    blocks = [tasks[i::n_blocks] for i in range(n_blocks)]
    clusters = {w: start_cluster(w) for w in (1, 2)}
    wall = {1: 0.0, 2: 0.0}
    driver_cpu = {1: 0.0, 2: 0.0}
    worker_cpu0 = {w: sum(clusters[w][1].run(_cpu_s).values()) for w in (1, 2)}
    results = {1: [], 2: []}
    failed = 0
    loads = []
    try:
        for b, block in enumerate(blocks):
            for w in ((1, 2) if b % 2 == 0 else (2, 1)):
                loads.append(os.getloadavg()[0])
                t0, c0 = time.perf_counter(), _cpu_s()
                res = sweep(block, client=clusters[w][1], cache_dir=None, progress=False)
                wall[w] += time.perf_counter() - t0
                driver_cpu[w] += _cpu_s() - c0  # client + the LocalCluster's scheduler (in this process)
                failed += len(res.failures)
                results[w].append(res.results)
        worker_rss = {w: max(clusters[w][1].run(_peak_rss_mb).values()) for w in (1, 2)}
        worker_cpu = {w: sum(clusters[w][1].run(_cpu_s).values()) - worker_cpu0[w] for w in (1, 2)}
    finally:
        for cluster, client, _ in clusters.values():
            client.close()
            cluster.close()

    def srt(frames):
        return pd.concat(frames, ignore_index=True).sort_values(["seed", "item", "quantity"]).reset_index(drop=True)

    r1, r2 = srt(results[1]), srt(results[2])
    kf = r2[(r2["quantity"] == "mean error") & (r2["item"] == "method=step KF")]
    return {
        "walks": n_walks, "steps_per_walk": n_steps, "blocks": n_blocks, "failed": failed,
        "wall_1_worker_s": wall[1], "wall_2_workers_s": wall[2],
        "ratio_2_over_1": wall[2] / wall[1], "target_ratio": TARGET_RATIO,
        "s_per_walk_1_worker": wall[1] / n_walks,
        "worker_cpu_s_1": worker_cpu[1], "worker_cpu_s_2": worker_cpu[2],
        "driver_cpu_s_1": driver_cpu[1], "driver_cpu_s_2": driver_cpu[2],
        "driver_cpu_ms_per_walk_2": 1e3 * driver_cpu[2] / n_walks,
        # cores the workers actually got (worker CPU s / wall s): 2 workers on an idle 2-core
        # machine should get close to 2; much less means other jobs held the cores
        "worker_cores_used_1": worker_cpu[1] / wall[1], "worker_cores_used_2": worker_cpu[2] / wall[2],
        "cluster_startup_1_s": clusters[1][2], "cluster_startup_2_s": clusters[2][2],
        "loadavg_1min_min": min(loads), "loadavg_1min_max": max(loads),
        "driver_peak_rss_mb": _peak_rss_mb(), "results_mb": float(r1.memory_usage(deep=True).sum() / 2**20),
        "worker_peak_rss_mb_1": worker_rss[1], "worker_peak_rss_mb_2": worker_rss[2],
        "results_rows": len(r2), "identical_results": bool(failed == 0 and r1.equals(r2)),
        "step_kf_mean_error_m": float(kf["value"].mean()),
    }


def test_bench_sweep_1000_walks(benchmark):
    m = benchmark.pedantic(measure, rounds=1, iterations=1)
    benchmark.extra_info.update(m)
    print(pd.Series(m).to_string())
    assert m["failed"] == 0 and m["identical_results"]
    # the scaling goal (TARGET_RATIO) is checked by the gate (benchmarks/goals.toml), not here


if __name__ == "__main__":
    for k, v in measure().items():
        print(f"{k:>28}: {v:.4g}" if isinstance(v, float) else f"{k:>28}: {v}")
