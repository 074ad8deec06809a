"""Text loaders against ``pandas.read_csv`` on the same bytes: time ratio and peak memory / file size.

Run: ``PYTHONPATH=$PWD python -m pytest benchmarks/bench_io.py -o python_files='bench_*.py' -s``.
Each loader reads a generated file of about ``SIZE_MB`` megabytes (IPIN logfile, ILC trace,
Oxford validation CSV, Oxford recording folder, UJIIndoorLoc CSV); ``pandas.read_csv`` parses the
same bytes with the C engine into a plain numeric/object table (no validation) in the same run.
Goals: every loader within 2x of ``read_csv``, peak traced memory at most 3x the file size.
The summary table is printed at the end (``-s``); pytest-benchmark also times each loader.
"""

from __future__ import annotations

import io
import os
import time
import tracemalloc

import numpy as np
import pandas as pd
import pytest
from conftest import size

from ilocalg.io.ilc import load_ilc_trace
from ilocalg.io.ipin import load_ipin_logfile
from ilocalg.io.oxford import load_oxford_step_counter
from ilocalg.io.ujiindoorloc import WAP_COLUMNS, load_ujiindoorloc

#: Target size of every generated file, megabytes (kept small: the benchmark machine is shared); ``$ILOC_BENCH_IO_MB``,
#: else 30, or 0.5 in a smoke run (ILOC_BENCH_SMOKE=1, benchmarks/conftest.py).
SIZE_MB = float(os.environ.get("ILOC_BENCH_IO_MB") or size(30.0, 0.5))
RESULTS: list[dict] = []


def _ipin(n_epochs: int, rng) -> str:
    t = np.arange(n_epochs) * 0.01
    out = ["% IPIN logfile (generated)"]
    acc = rng.normal(0, 1, (n_epochs, 3)) + [0, 0, 9.81]
    gyr = rng.normal(0, 0.1, (n_epochs, 3))
    mag = rng.normal(0, 5, (n_epochs, 3)) + [20, -5, -40]
    for i in range(n_epochs):
        ti = t[i]
        out.append(f"ACCE;{ti:.3f};{ti + 1000:.3f};{acc[i, 0]:.5f};{acc[i, 1]:.5f};{acc[i, 2]:.5f};3")
        out.append(f"GYRO;{ti + 0.001:.3f};{ti + 1000.001:.3f};{gyr[i, 0]:.5f};{gyr[i, 1]:.5f};{gyr[i, 2]:.5f};3")
        out.append(f"MAGN;{ti + 0.002:.3f};{ti + 1000.002:.3f};{mag[i, 0]:.3f};{mag[i, 1]:.3f};{mag[i, 2]:.3f};3")
        if i % 10 == 0:
            out.append(f"AHRS;{ti + 0.003:.3f};{ti + 1000.003:.3f};10.1;2.2;130.5;0.1;0.2;0.3;3")
        if i % 100 == 50:
            for k in range(8):
                out.append(f"WIFI;{ti + 0.004:.3f};{ti + 1000:.3f};net{k};aa:bb:cc:dd:ee:{k:02x};"
                           f"{2412 + 5 * k};{-40 - 5 * k}")
        if i % 500 == 0:
            out.append(f"POSI;{ti + 0.005:.3f};{i // 500};39.99{i % 1000:03d};-0.06{i % 1000:03d};0;1")
    return "\n".join(out) + "\n"


def _ilc(n_epochs: int, rng) -> str:
    out = ["#\tstartTime:1574149352216", "#\tSiteID:site\tSiteName:mall\tFloorId:fl\tFloorName:F4"]
    t0 = 1574149352216
    acc = rng.normal(0, 1, (n_epochs, 3)) + [0, 0, 9.81]
    for i in range(n_epochs):
        t = t0 + 20 * i
        a = acc[i]
        out.append(f"{t}\tTYPE_ACCELEROMETER\t{a[0]:.5f}\t{a[1]:.5f}\t{a[2]:.5f}\t3")
        out.append(f"{t}\tTYPE_MAGNETIC_FIELD\t20.1\t-5.2\t-30.3\t3")
        out.append(f"{t}\tTYPE_GYROSCOPE\t0.01\t0.02\t{a[0] / 100:.5f}\t3")
        out.append(f"{t}\tTYPE_ROTATION_VECTOR\t0.1\t0.0\t0.5\t3")
        if i % 100 == 0:
            out.append(f"{t}\tTYPE_WAYPOINT\t{i / 100:.3f}\t{i / 200:.3f}")
        if i % 150 == 75:
            for k in range(8):
                out.append(f"{t + 1}\tTYPE_WIFI\tnet{k}\taa:bb:cc:dd:ee:{k:02x}\t{-40 - 5 * k}\t2412\t{t}")
    return "\n".join(out) + "\n"


def _oxford_validation(n: int, rng) -> str:
    t = 10**12 + np.arange(n, dtype=np.int64) * 5_000_000
    acc = rng.normal(0, 1, (n, 3)) + [0, 0, 9.81]
    steps = np.arange(n) // 100
    df = pd.DataFrame({"t": t, "ax": acc[:, 0].round(5), "ay": acc[:, 1].round(5), "az": acc[:, 2].round(5),
                       "app": steps, "true": steps, "hw": steps + 1000})
    return df.to_csv(header=False, index=False)


def _uji(n: int, rng) -> str:
    rssi = np.where(rng.random((n, len(WAP_COLUMNS))) < 0.95, 100, rng.integers(-104, 0, (n, len(WAP_COLUMNS))))
    df = pd.DataFrame(rssi, columns=list(WAP_COLUMNS))
    df["LONGITUDE"] = -7600 + rng.random(n) * 300
    df["LATITUDE"] = 4864800 + rng.random(n) * 200
    for c, hi in (("FLOOR", 5), ("BUILDINGID", 3), ("SPACEID", 250), ("RELATIVEPOSITION", 3), ("USERID", 19),
                  ("PHONEID", 25)):
        df[c] = rng.integers(0, hi, n)
    df["TIMESTAMP"] = 1371713733 + np.arange(n)
    return df.to_csv(index=False)


def _scaled(make, unit_bytes_per_item: float):
    rng = np.random.default_rng(0)
    n = max(1000, int(SIZE_MB * 1e6 / unit_bytes_per_item))
    return make(n, rng)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bench_io")
    out = {}
    p = d / "walk_ipin.txt"
    p.write_text(_scaled(_ipin, 200.0), encoding="utf-8")
    out["ipin"] = (p, lambda p=p: load_ipin_logfile(p),
                   lambda b: pd.read_csv(io.BytesIO(b), sep=";", header=None, names=range(10), comment="%"))
    p = d / "walk_ilc.txt"
    p.write_text(_scaled(_ilc, 190.0), encoding="utf-8")
    out["ilc"] = (p, lambda p=p: load_ilc_trace(p),
                  lambda b: pd.read_csv(io.BytesIO(b), sep="\t", header=None, names=range(9), comment="#"))
    p = d / "oxford_validation.csv"
    p.write_text(_scaled(_oxford_validation, 60.0), encoding="utf-8")
    out["oxford_csv"] = (p, lambda p=p: load_oxford_step_counter(p),
                         lambda b: pd.read_csv(io.BytesIO(b), header=None))
    rec = d / "Pixel_Bench_Hard_InHand_1"
    rec.mkdir()
    n = int(SIZE_MB * 1e6 / 60.0)
    rng = np.random.default_rng(1)
    t = 10**12 + np.arange(n, dtype=np.int64) * 2_500_000
    acc = (rng.normal(0, 1, (n, 3)) + [0, 0, 9.81]).round(5)
    pd.DataFrame({"t": t, "a": 3, "x": acc[:, 0], "y": acc[:, 1], "z": acc[:, 2]}).to_csv(
        rec / "accelerometer.csv", header=False, index=False)
    feet = (np.arange(n // 40) // 10) % 2
    pd.DataFrame({"t": t[::40][: n // 40], "l": feet, "r": 1 - feet}).to_csv(
        rec / "stepcounter.csv", header=False, index=False)
    out["oxford_folder"] = (rec / "accelerometer.csv", lambda: load_oxford_step_counter(rec),
                            lambda b: pd.read_csv(io.BytesIO(b), header=None))
    p = d / "uji.csv"
    p.write_text(_scaled(_uji, 2100.0), encoding="utf-8")
    out["ujiindoorloc"] = (p, lambda p=p: load_ujiindoorloc(p), lambda b: pd.read_csv(io.BytesIO(b)))
    return out


def _peak_mb(fn) -> float:
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1] / 1e6
    finally:
        tracemalloc.stop()


def _best(fn, repeat=2) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


@pytest.mark.parametrize("name", ["ipin", "ilc", "oxford_csv", "oxford_folder", "ujiindoorloc"])
def test_loader_vs_read_csv(benchmark, files, name, bench_record):
    path, load, ref = files[name]
    data = path.read_bytes()
    size_mb = len(data) / 1e6
    t_ref = _best(lambda: ref(data))
    benchmark.pedantic(load, rounds=1, iterations=1)
    t_load = _best(load)
    peak = _peak_mb(load)
    peak_ref = _peak_mb(lambda: ref(data))
    RESULTS.append({"loader": name, "file_mb": round(size_mb, 1), "load_s": round(t_load, 2),
                    "read_csv_s": round(t_ref, 2), "time_ratio": round(t_load / t_ref, 2),
                    "peak_mb": round(peak, 1), "peak_over_file": round(peak / size_mb, 2),
                    "read_csv_peak_over_file": round(peak_ref / size_mb, 2)})
    bench_record.update({"time_ratio_to_read_csv": t_load / t_ref, "peak_over_file_size": peak / size_mb,
                         "read_csv_peak_over_file_size": peak_ref / size_mb})
    assert t_load > 0


def test_zz_summary():
    """Print the table (runs last in this module)."""
    if RESULTS:
        print("\n" + pd.DataFrame(RESULTS).to_string(index=False))
