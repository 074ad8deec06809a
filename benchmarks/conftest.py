"""Benchmarks: a helper to time ratios, and the collection of every bench's measures for the gate.

Each test's measures are what it puts in pytest-benchmark's ``benchmark.extra_info`` or in the
``bench_record`` fixture (a dict, for tests that do not use ``benchmark``); numeric values are written,
at the end of the session, to ``$ILOC_BENCH_RESULTS`` (default ``.benchmarks/results.json``) under the
test's id (``bench_wifi.py::test_knn_euclidean``), where :mod:`gate` compares them with
``benchmarks/goals.toml``. Works with and without ``--benchmark-disable`` (``extra_info`` exists either
way; nothing here reads pytest-benchmark's own statistics, which a disabled run does not have).

Smoke run: with ``ILOC_BENCH_SMOKE=1`` every bench runs at a small problem size (:func:`size`), so that the
test suite can run them all in seconds (``tests/test_bench_smoke.py``, with ``--benchmark-disable``) and find a
bench that no longer runs or no longer records a goal's measure. Its numbers measure nothing: they are written
to ``.benchmarks/results-smoke.json`` unless ``$ILOC_BENCH_RESULTS`` says otherwise, each test's entry is
marked ``smoke_run``, and :mod:`gate` refuses such an entry as a measure. Without the variable (``make bench``)
every size is the full one.
"""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path

import pytest

RESULTS_ENV = "ILOC_BENCH_RESULTS"
SMOKE_ENV = "ILOC_BENCH_SMOKE"
#: Whether this is a smoke run (``ILOC_BENCH_SMOKE`` set to anything but empty or ``0``).
SMOKE = os.environ.get(SMOKE_ENV, "").strip() not in ("", "0")
#: The key that marks a smoke run's entries in the results file (:mod:`gate` refuses them as measures).
SMOKE_KEY = "smoke_run"
_RESULTS: dict[str, dict[str, float]] = {}


def _best(fn, repeat: int, clock) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = clock()
        fn()
        best = min(best, clock() - t0)
    return best


def size(full, smoke):
    """A bench's problem size: ``full`` in a real run (``make bench``), ``smoke`` when :data:`SMOKE` is set."""
    return smoke if SMOKE else full


def best_time_s(fn, repeat: int = 5) -> float:
    """Best wall time of ``repeat`` calls of ``fn()`` (for ratio measurements in one run)."""
    return _best(fn, repeat, time.perf_counter)


def best_cpu_s(fn, repeat: int = 3) -> float:
    """Best process CPU time (user + sys) of ``repeat`` calls of ``fn()``: immune to other jobs on a shared
    machine when every computation runs in this process."""
    return _best(fn, repeat, time.process_time)


def results_path() -> Path:
    """Where the session's measures are written (``$ILOC_BENCH_RESULTS``, else ``.benchmarks/results.json``, or
    ``.benchmarks/results-smoke.json`` in a smoke run)."""
    name = "results-smoke.json" if SMOKE else "results.json"
    return Path(os.environ.get(RESULTS_ENV) or Path(__file__).resolve().parents[1] / ".benchmarks" / name)


def _test_id(node) -> str:
    return f"{Path(node.fspath).name}::{node.name}"


@pytest.fixture
def bench_record(request):
    """A dict of this test's measures (name -> number), collected for the gate."""
    return _RESULTS.setdefault(_test_id(request.node), {})


@pytest.fixture(autouse=True)
def _collect_measures(request):
    bm = request.getfixturevalue("benchmark") if "benchmark" in request.fixturenames else None
    yield
    if bm is not None:
        got = _RESULTS.setdefault(_test_id(request.node), {})
        for k, v in bm.extra_info.items():
            if isinstance(v, (bool, int, float)) and not (isinstance(v, float) and math.isnan(v)):
                got[k] = float(v)


def pytest_sessionfinish(session, exitstatus):
    """Merge this session's measures into the results file (a bench file run alone keeps the others')."""
    if not _RESULTS:
        return
    path = results_path()
    try:
        old = json.loads(path.read_text())
    except (OSError, ValueError):
        old = {}
    old.update({k: {**v, SMOKE_KEY: 1.0} if SMOKE else v for k, v in _RESULTS.items() if v})
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(old, indent=1, sort_keys=True) + "\n")
