"""Every benchmark runs once at its smoke size, and records every measure benchmarks/goals.toml names.

``make test`` does not run ``make bench`` (its timings need an idle machine and minutes). This runs the benches in
a fresh process with ``ILOC_BENCH_SMOKE=1`` (the small problem sizes of ``benchmarks/conftest.py``) and
``--benchmark-disable`` (no pytest-benchmark timing), then the gate with ``--structure-only``: each goal's bench
ran and recorded its measure. No value is compared (a smoke run's timings measure nothing). So an API change
that breaks a bench, or a bench that stops recording a goal's measure, fails the suite. About 20 CPU-s.

A bench that skips for want of the shared real data (``bench_track.py::test_site1_floor_real``) leaves its goals
unrecorded: this test then skips on a developer machine and fails under CI=true, as the real-data tests do.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"


def _gate():
    spec = importlib.util.spec_from_file_location("bench_gate_smoke", BENCH / "gate.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _skipped(junit: Path) -> dict[str, str]:
    """Skipped benches of the run (``bench_x.py::test[params]`` -> reason) from its JUnit XML report."""
    out = {}
    for case in ET.parse(junit).getroot().iter("testcase"):
        skip = case.find("skipped")
        if skip is not None:
            out[f"{case.get('classname').rsplit('.', 1)[-1]}.py::{case.get('name')}"] = skip.get("message", "")
    return out


@pytest.mark.realdata
def test_every_bench_runs_and_records_its_goals_measures(tmp_path):
    results, junit = tmp_path / "results.json", tmp_path / "junit.xml"
    # a clean pytest in a fresh process: none of this run's (xdist worker) settings, the smoke sizes, its own results
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_") and k != "ILOC_BENCH_IO_MB"}
    env.update(ILOC_BENCH_SMOKE="1", ILOC_BENCH_RESULTS=str(results),
               PYTHONPATH=os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]))
    cmd = [sys.executable, "-m", "pytest", "benchmarks", "-o", "python_files=bench_*.py", "--benchmark-disable",
           "-p", "no:cacheprovider", "-q", "--tb=short", "-rfEs", f"--basetemp={tmp_path / 'tmp'}",
           f"--junitxml={junit}"]
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    log = (run.stdout + run.stderr)[-6000:]
    if run.returncode != 0:
        pytest.fail(f"a bench failed at its smoke size (ILOC_BENCH_SMOKE=1, exit {run.returncode}):\n{log}",
                    pytrace=False)

    gate = _gate()  # what `python benchmarks/gate.py --structure-only RESULTS` prints and checks
    rows = gate.check_structure(gate.load_goals(BENCH / "goals.toml"), json.loads(results.read_text()))
    table = gate.format_table(rows)
    missing = [r for r in rows if not r["recorded"]]
    skipped = _skipped(junit)
    unexcused = [r for r in missing if r["bench"] not in skipped]
    if unexcused:
        pytest.fail(f"goals whose bench ran but did not record the measure (benchmarks/goals.toml):\n{table}\n"
                    f"{len(unexcused)} missing: {[(r['bench'], r['measure']) for r in unexcused]}", pytrace=False)
    if missing:
        msg = "; ".join(f"{r['bench']} {r['measure']} (skipped: {skipped[r['bench']]})" for r in missing)
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"benches skipped under CI, their goals unchecked: {msg}")
        pytest.skip(f"every bench ran, but these goals' benches skipped: {msg}")
