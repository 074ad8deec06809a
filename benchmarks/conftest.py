"""Benchmarks: pytest-benchmark fixtures plus a helper to report speed ratios."""

from __future__ import annotations

import time


def best_time_s(fn, repeat: int = 5) -> float:
    """Best wall time of ``repeat`` calls of ``fn()`` (for ratio measurements in one run)."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best
