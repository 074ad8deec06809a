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
(a bench that failed or did not run), 0 otherwise. ``make bench`` runs it after the benches.
"""

from __future__ import annotations

import json
import sys
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_GOALS = HERE / "goals.toml"
DEFAULT_RESULTS = HERE.parent / ".benchmarks" / "results.json"


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
    """One row per goal: bench, measure, measured (None if missing), goal text, passed."""
    rows = []
    for g in goals:
        v = results.get(g["bench"], {}).get(g["measure"])
        parts = []
        ok = v is not None
        if "min" in g:
            parts.append(f">= {g['min']:g}")
            ok = ok and v >= g["min"]
        if "max" in g:
            parts.append(f"<= {g['max']:g}")
            ok = ok and v <= g["max"]
        rows.append({"bench": g["bench"], "measure": g["measure"], "measured": v, "goal": " and ".join(parts),
                     "passed": bool(ok)})
    return rows


def format_table(rows: list[dict]) -> str:
    head = ("benchmark", "measure", "measured", "goal", "pass")
    body = [(r["bench"], r["measure"], "missing" if r["measured"] is None else f"{r['measured']:.4g}", r["goal"],
             "yes" if r["passed"] else "NO") for r in rows]
    w = [max(len(str(x[i])) for x in [head, *body]) for i in range(len(head))]
    lines = ["  ".join(str(x[i]).ljust(w[i]) for i in range(len(head))) for x in [head, *body]]
    lines.insert(1, "  ".join("-" * n for n in w))
    return "\n".join(lines)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    results_path = Path(argv[0]) if argv else DEFAULT_RESULTS
    goals_path = Path(argv[1]) if len(argv) > 1 else DEFAULT_GOALS
    try:
        results = json.loads(results_path.read_text())
    except (OSError, ValueError) as exc:
        print(f"{results_path}: no bench results ({exc}); run the benches first (make bench)", file=sys.stderr)
        return 1
    rows = evaluate(load_goals(goals_path), results)
    print(format_table(rows))
    missed = [r for r in rows if not r["passed"]]
    print(f"{len(rows) - len(missed)} of {len(rows)} goals met" + (f"; MISSED: {len(missed)}" if missed else ""))
    return 1 if missed else 0


if __name__ == "__main__":
    raise SystemExit(main())
