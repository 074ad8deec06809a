"""The benchmark gate: every declared goal against the measures of the last bench run.

``benchmarks/goals.toml`` declares each goal once::

    [[goal]]
    bench = "bench_wifi.py::test_knn_euclidean"   # test id (file::test name, with parameters)
    measure = "fraction_of_gemm_bound"            # a key the test recorded (extra_info / bench_record)
    min = 0.90                                     # and/or max = ...
    why = "issue 28: ..."                          # where the number comes from

A goal is a ratio measured in one run (ours / a reference timed beside it) or a real-time factor,
never an absolute time. ``python benchmarks/gate.py [RESULTS.json] [GOALS.toml]`` prints one row per goal
(benchmark, measure, measured, goal, pass) and exits 1 when a goal is missed or its measure is missing
(a bench that failed or did not run), 0 otherwise. ``make bench`` runs it after the benches. A smoke run's
entries (marked ``smoke_run``, see ``conftest.py``) count as missing: their numbers measure nothing.

``--structure-only`` compares no value: one row per goal (benchmark, measure, recorded) and exit 1 when a goal's
bench did not record its measure. The test suite runs it after every bench at its smoke size
(``tests/test_bench_smoke.py``), so a bench that stops running or stops recording a goal's measure fails
``make test``, not only ``make bench``.
"""

from __future__ import annotations

import json
import sys
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_GOALS = HERE / "goals.toml"
DEFAULT_RESULTS = HERE.parent / ".benchmarks" / "results.json"
#: The key a smoke run adds to each test's entry (``conftest.SMOKE_KEY``).
SMOKE_KEY = "smoke_run"


def load_goals(path=DEFAULT_GOALS) -> list[dict]:
    """The goals of a goals file, checked: each has ``bench``, ``measure``, ``why`` and ``min`` or ``max``."""
    with open(path, "rb") as f:
        goals = tomllib.load(f).get("goal", [])
    for i, g in enumerate(goals):
        missing = [k for k in ("bench", "measure", "why") if not g.get(k)]
        if missing or ("min" not in g and "max" not in g):
            raise ValueError(f"{path}: goal {i + 1} ({g.get('bench', '?')}) needs bench, measure, why and min "
                             f"or max; missing {missing or ['min/max']}")
    return goals


def evaluate(goals: list[dict], results: dict) -> list[dict]:
    """One row per goal: bench, measure, measured (None if missing or from a smoke run), goal text, passed, smoke
    (whether the bench's entry comes from a smoke run)."""
    rows = []
    for g in goals:
        got = results.get(g["bench"], {})
        v = None if SMOKE_KEY in got else got.get(g["measure"])
        parts = []
        ok = v is not None
        if "min" in g:
            parts.append(f">= {g['min']:g}")
            ok = ok and v >= g["min"]
        if "max" in g:
            parts.append(f"<= {g['max']:g}")
            ok = ok and v <= g["max"]
        rows.append({"bench": g["bench"], "measure": g["measure"], "measured": v, "goal": " and ".join(parts),
                     "passed": bool(ok), "smoke": SMOKE_KEY in got})
    return rows


def check_structure(goals: list[dict], results: dict) -> list[dict]:
    """One row per goal: bench, measure, recorded (whether the bench recorded that measure, a smoke run's entries
    included; no value is compared)."""
    return [{"bench": g["bench"], "measure": g["measure"], "recorded": g["measure"] in results.get(g["bench"], {})}
            for g in goals]


def format_table(rows: list[dict]) -> str:
    if rows and "recorded" in rows[0]:
        head = ("benchmark", "measure", "recorded")
        body = [(r["bench"], r["measure"], "yes" if r["recorded"] else "MISSING") for r in rows]
    else:
        head = ("benchmark", "measure", "measured", "goal", "pass")
        body = [(r["bench"], r["measure"], "smoke run" if r.get("smoke") else "missing" if r["measured"] is None
                 else f"{r['measured']:.4g}", r["goal"], "yes" if r["passed"] else "NO") for r in rows]
    return _table(head, body)


def _table(head, body) -> str:
    w = [max(len(str(x[i])) for x in [head, *body]) for i in range(len(head))]
    lines = ["  ".join(str(x[i]).ljust(w[i]) for i in range(len(head))) for x in [head, *body]]
    lines.insert(1, "  ".join("-" * n for n in w))
    return "\n".join(lines)


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    structure_only = "--structure-only" in argv
    argv = [a for a in argv if a != "--structure-only"]
    results_path = Path(argv[0]) if argv else DEFAULT_RESULTS
    goals_path = Path(argv[1]) if len(argv) > 1 else DEFAULT_GOALS
    try:
        results = json.loads(results_path.read_text())
    except (OSError, ValueError) as exc:
        print(f"{results_path}: no bench results ({exc}); run the benches first (make bench)", file=sys.stderr)
        return 1
    if structure_only:
        rows = check_structure(load_goals(goals_path), results)
        print(format_table(rows))
        missing = [r for r in rows if not r["recorded"]]
        print(f"{len(rows) - len(missing)} of {len(rows)} goals' measures recorded (values not compared)"
              + (f"; MISSING: {len(missing)}" if missing else ""))
        return 1 if missing else 0
    rows = evaluate(load_goals(goals_path), results)
    print(format_table(rows))
    missed = [r for r in rows if not r["passed"]]
    print(f"{len(rows) - len(missed)} of {len(rows)} goals met" + (f"; MISSED: {len(missed)}" if missed else ""))
    return 1 if missed else 0


if __name__ == "__main__":
    raise SystemExit(main())
