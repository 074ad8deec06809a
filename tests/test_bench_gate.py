"""The benchmark gate (benchmarks/gate.py) on fake results: no timing here, only its logic."""

import importlib.util
import json
import re
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture(scope="module")
def gate():
    spec = importlib.util.spec_from_file_location("bench_gate", BENCH / "gate.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _files(tmp_path, goals: str, results: dict):
    g = tmp_path / "goals.toml"
    g.write_text(goals)
    r = tmp_path / "results.json"
    r.write_text(json.dumps(results))
    return [str(r), str(g)]


GOALS = '''
[[goal]]
bench = "bench_x.py::test_a"
measure = "speedup"
min = 10.0
why = "test"

[[goal]]
bench = "bench_x.py::test_b"
measure = "ratio"
max = 2.0
why = "test"
'''


def test_met_goals_pass_and_the_table_says_so(gate, tmp_path, capsys):
    args = _files(tmp_path, GOALS, {"bench_x.py::test_a": {"speedup": 12.0}, "bench_x.py::test_b": {"ratio": 1.5}})
    assert gate.main(args) == 0
    out = capsys.readouterr().out
    assert "benchmark" in out and "measured" in out and "pass" in out
    assert "2 of 2 goals met" in out


def test_an_unreachable_goal_fails_the_gate(gate, tmp_path, capsys):
    unreachable = GOALS.replace("min = 10.0", "min = 1e12")
    args = _files(tmp_path, unreachable, {"bench_x.py::test_a": {"speedup": 12.0},
                                          "bench_x.py::test_b": {"ratio": 1.5}})
    assert gate.main(args) == 1
    out = capsys.readouterr().out
    assert re.search(r"bench_x.py::test_a\s+speedup\s+12\s+>= 1e\+12\s+NO", out)
    assert "MISSED: 1" in out


def test_a_max_goal_and_a_missing_measure_fail(gate, tmp_path):
    rows = gate.evaluate(gate.load_goals(_files(tmp_path, GOALS, {})[1]),
                         {"bench_x.py::test_b": {"ratio": 2.5}})
    assert [(r["measured"], r["passed"]) for r in rows] == [(None, False), (2.5, False)]
    assert gate.main(_files(tmp_path, GOALS, {})) == 1  # a bench that did not run misses its goals


def test_no_results_file_fails(gate, tmp_path):
    assert gate.main([str(tmp_path / "absent.json"), _files(tmp_path, GOALS, {})[1]]) == 1


def test_a_goal_without_bound_or_reason_is_refused(gate, tmp_path):
    bad = '[[goal]]\nbench = "bench_x.py::test_a"\nmeasure = "speedup"\nwhy = "x"\n'
    with pytest.raises(ValueError, match="min or max"):
        gate.load_goals(_files(tmp_path, bad, {})[1])


def test_the_projects_goals_name_benches_that_exist(gate):
    goals = gate.load_goals(BENCH / "goals.toml")
    assert goals
    for g in goals:
        file, test = g["bench"].split("::")
        src = (BENCH / file).read_text()
        assert f"def {test.split('[')[0]}(" in src, g["bench"]
        assert g["measure"] in src or "bench_record" in src, g  # the bench records that measure
    files = {g["bench"].split("::")[0] for g in goals}
    assert files == {p.name for p in BENCH.glob("bench_*.py")}, "every bench declares a goal"


def test_structure_only_checks_that_each_measure_was_recorded_not_its_value(gate, tmp_path, capsys):
    # values that miss both goals: the structure check compares none
    results = {"bench_x.py::test_a": {"speedup": 0.1, "smoke_run": 1.0}, "bench_x.py::test_b": {"ratio": 99.0}}
    assert gate.main(["--structure-only", *_files(tmp_path, GOALS, results)]) == 0
    assert "2 of 2 goals' measures recorded (values not compared)" in capsys.readouterr().out
    results["bench_x.py::test_b"] = {"ratio_renamed": 1.0}  # the bench ran but no longer records the goal's key
    assert gate.main(["--structure-only", *_files(tmp_path, GOALS, results)]) == 1
    out = capsys.readouterr().out
    assert re.search(r"bench_x.py::test_b\s+ratio\s+MISSING", out) and "MISSING: 1" in out
    del results["bench_x.py::test_a"]  # a bench that did not run (or failed before recording)
    assert gate.main(["--structure-only", *_files(tmp_path, GOALS, results)]) == 1


def test_a_smoke_runs_numbers_are_no_measure(gate, tmp_path, capsys):
    results = {"bench_x.py::test_a": {"speedup": 12.0, "smoke_run": 1.0}, "bench_x.py::test_b": {"ratio": 1.5}}
    assert gate.main(_files(tmp_path, GOALS, results)) == 1
    assert re.search(r"bench_x.py::test_a\s+speedup\s+smoke run\s+>= 10\s+NO", capsys.readouterr().out)
