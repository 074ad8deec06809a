"""A successful reproduce prints its progress and results, and nothing from the kernels' plumbing."""

from __future__ import annotations

import asyncio
import re
import signal
import subprocess
import sys

from ilocalg.io.paths import REPO_ROOT
from ilocalg.workflow.kernels import QuietKernelManager

_NOISE = re.compile(r"without encryption|ERROR|WARNING|Warning|KeyboardInterrupt|Traceback|\[IPKernelApp\]")


def test_fast_reproduce_of_one_notebook_logs_only_progress_and_results(tmp_path):
    """The captured log of ``reproduce --only 04 --fast``: one line per stage, no kernel or client noise (notebook
    04: a short one whose claims have robustness samples)."""
    out = tmp_path / "reports"
    proc = subprocess.run([sys.executable, "-m", "ilocalg", "reproduce", "--only", "04", "--fast", "--out", str(out),
                           "--jobs", "1"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=900, cwd=REPO_ROOT)
    log = proc.stdout.decode()  # stdout and stderr as one terminal shows them (bytes: keep a progress bar's \r)
    assert proc.returncode == 0, log[-2000:]
    assert not _NOISE.findall(log), log
    lines = [ln.rsplit("\r", 1)[-1] for ln in log.split("\n") if ln.strip()]  # a progress bar is one line
    assert lines[0].startswith("reproducing 1 notebook(s)") and lines[-1].startswith("wrote index.html")
    # header; notebook: [1/1], its bar, done; claims: base-run bar, robustness bar, verdict counts; wrote
    assert len(lines) <= 8, log
    assert (out / "04_pdr_step_length.html").is_file()


def test_quiet_kernels_talk_over_ipc_and_are_not_interrupted_on_shutdown():
    sent = []

    async def run():
        km = QuietKernelManager(kernel_name="python3")
        orig = km._async_signal_kernel

        async def record(signum):
            sent.append(signum)
            await orig(signum)

        km._async_signal_kernel = record
        await km.start_kernel()
        try:
            assert km.transport == "ipc"
            await km.interrupt_kernel()  # an interrupt asked for while running still goes through
        finally:
            await km.shutdown_kernel()
        assert not km.is_alive() if not asyncio.iscoroutinefunction(km.is_alive) else not await km.is_alive()

    asyncio.run(run())
    assert sent == [signal.SIGINT]  # the one asked for; none from the shutdown


def test_interval_line_tells_this_reproduces_runs_from_reused_ones(tmp_path, monkeypatch, capsys):
    """On a fresh clone the runs the notebooks and the pool just made are not reported as 'reused'."""
    import os
    import time
    import types
    from pathlib import Path

    from ilocalg.papers import comparison_table, paper_ref
    from ilocalg.workflow.runner import sweep_experiments

    fake = types.ModuleType("ilocalg.experiments.fake_quiet")
    fake.run = lambda seed=0, fast=False: {"comparison": comparison_table(
        [paper_ref("Fake paper", "Fig 1", "error", 1.0, 1.0 + seed, "m")])}
    monkeypatch.setitem(sys.modules, "ilocalg.experiments.fake_quiet", fake)
    args = dict(nbs=[Path("01_fake.ipynb")], out_dir=tmp_path / "out", seed=0, n_seeds=3, fast=False, workers=0,
                progress=False, cache_dir=tmp_path / "cache", manifest={"01_fake": {"fake_quiet": True}})
    t0 = time.time() - 1.0
    assert sweep_experiments(**args, since=t0)[0] == 0
    assert "= 3 runs (0 made by this reproduce's notebooks and pool, 0 reused from an earlier reproduce, 3 run now" \
        in capsys.readouterr().out
    assert sweep_experiments(**args, since=t0)[0] == 0  # as after the notebooks and the pool made them
    assert "(3 made by this reproduce's notebooks and pool, 0 reused" in capsys.readouterr().out
    for f in (tmp_path / "cache").rglob("*.parquet"):
        os.utime(f, (t0 - 3600, t0 - 3600))  # made by an earlier reproduce
    assert sweep_experiments(**args, since=t0)[0] == 0
    assert "(0 made by this reproduce's notebooks and pool, 3 reused from an earlier reproduce, 0 run now" \
        in capsys.readouterr().out
