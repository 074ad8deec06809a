"""Step-detection throughput: the toolkit's detectors against a scipy.signal.find_peaks baseline.

Run: ``PYTHONPATH=$PWD python -m pytest benchmarks/bench_pdr.py --benchmark-only``. The goal of
issue 7 is >= 10 million samples/s for step detection (at 100 Hz: a real-time factor >= 1e5);
``test_throughput_ratio`` prints every detector's samples/s and its ratio to the baseline measured in the
same run, and records both for the gate (``benchmarks/goals.toml``).
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from conftest import size
from scipy import signal as ss

from ilocalg.pdr.peak_window import detect_steps_peak_window
from ilocalg.pdr.robust import detect_steps_robust, lowpass_magnitude
from ilocalg.pdr.sam import SAM_RANGES_PAPER, detect_steps_sam

N = size(2_000_000, 100_000)  # smoke run (ILOC_BENCH_SMOKE=1, benchmarks/conftest.py): the small size
RATE = 100.0


@pytest.fixture(scope="module")
def walk():
    rng = np.random.default_rng(0)
    t = np.arange(N) / RATE
    mag = 9.81 + 2.0 * np.sin(2 * np.pi * 1.9 * t) + 0.5 * np.sin(2 * np.pi * 0.95 * t) + rng.normal(0, 0.3, N)
    acc = np.column_stack([0.3 * rng.normal(size=N), 0.3 * rng.normal(size=N), mag])
    return t, mag, acc


def _baseline(mag):
    y = lowpass_magnitude(mag, RATE, 3.0)
    return ss.find_peaks(y, prominence=1.2, distance=25)[0]


def test_baseline_find_peaks(benchmark, walk):
    _, mag, _ = walk
    benchmark(_baseline, mag)


def test_robust(benchmark, walk):
    t, mag, _ = walk
    benchmark(detect_steps_robust, mag, t)


def test_peak_window(benchmark, walk):
    t, mag, _ = walk
    benchmark(detect_steps_peak_window, mag, t, 0.4, 2.0)


def test_sam(benchmark, walk):
    t, _, acc = walk
    benchmark(detect_steps_sam, acc, t, SAM_RANGES_PAPER)


def _best_of(f, *a, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f(*a)
        best = min(best, time.perf_counter() - t0)
    return best


def test_throughput_ratio(walk, bench_record):
    t, mag, acc = walk
    base = _best_of(_baseline, mag)
    rows = {"find_peaks baseline": base,
            "robust (|a| input)": _best_of(detect_steps_robust, mag, t),
            "robust (3-axis input)": _best_of(detect_steps_robust, acc, t),
            "peak_window": _best_of(detect_steps_peak_window, mag, t, 0.4, 2.0),
            "sam": _best_of(detect_steps_sam, acc, t, SAM_RANGES_PAPER)}
    for name, s in rows.items():
        print(f"{name:24s} {N / s / 1e6:8.1f} M samples/s   ratio to baseline {base / s:5.2f}")
    bench_record.update({
        "robust_realtime_factor": N / RATE / rows["robust (|a| input)"],
        "robust_3axis_realtime_factor": N / RATE / rows["robust (3-axis input)"],
        "peak_window_realtime_factor": N / RATE / rows["peak_window"],
        "sam_realtime_factor": N / RATE / rows["sam"],
        "robust_ratio_to_baseline": base / rows["robust (|a| input)"],
        "peak_window_ratio_to_baseline": base / rows["peak_window"],
        "sam_ratio_to_baseline": base / rows["sam"],
    })
    assert all(np.isfinite(v) and v > 0 for v in rows.values())
