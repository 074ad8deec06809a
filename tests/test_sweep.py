"""Sweeps: Dask cluster results equal a serial run bit for bit; caching, failures, aggregation."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from ilocalg.workflow import sweep as sw
from ilocalg.workflow.cli import main

TOY = "tests.sweep_toy"
ROOT = Path(__file__).resolve().parents[1]


def _sorted(df):
    return df.sort_values(["params", "seed", "table", "quantity"]).reset_index(drop=True)


def test_parse_param_and_grid():
    assert sw.parse_param("k=3,5,7") == ("k", [3, 5, 7])
    assert sw.parse_param("metric=manhattan,euclidean") == ("metric", ["manhattan", "euclidean"])
    with pytest.raises(ValueError, match="NAME=V1"):
        sw.parse_param("k3")
    with pytest.raises(ValueError, match="empty value"):
        sw.parse_param("k=1,,2")
    tasks = sw.make_tasks(TOY, range(3), {"scale": [1.0, 2.0], "n": [10]})
    assert len(tasks) == 6 and len({t.key for t in tasks}) == 6
    assert tasks[0].params == (("n", 10), ("scale", 1.0))


def test_sweep_kwargs_apply_to_tasks_unless_the_task_sets_them(monkeypatch):
    from ilocalg.workflow import manifest

    plain = sw.run_task(sw.SweepTask(TOY, (), 3, False))
    monkeypatch.setitem(manifest.SWEEP_KWARGS, TOY, {"scale": 10.0})
    lite = sw.run_task(sw.SweepTask(TOY, (), 3, False))
    own = sw.run_task(sw.SweepTask(TOY, (("scale", 1.0),), 3, False))
    value = {n: d.loc[d["table"] == "sweep_std", "value"].iloc[0] for n, d in (("plain", plain), ("lite", lite),
                                                                             ("own", own))}
    assert value["lite"] == pytest.approx(10.0 * value["plain"]) and value["own"] == value["plain"]


def test_unknown_experiment_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown experiment 'nope'"):
        sw._experiment("nope")


def test_local_cluster_equals_serial_bit_for_bit(tmp_path):
    tasks = sw.make_tasks(TOY, range(6), {"scale": [1.0, 3.0]})
    serial = sw.sweep(tasks, workers=0, cache_dir=None, progress=False)
    dask2 = sw.sweep(tasks, workers=2, cache_dir=None, progress=False)
    assert not serial.failures and not dask2.failures
    assert len(serial.results) == 12 * 2  # comparison row + sweep_std row per task
    pd.testing.assert_frame_equal(_sorted(serial.results), _sorted(dask2.results), check_exact=True)


def test_failed_task_is_reported_and_others_are_kept_and_cached(tmp_path):
    tasks = sw.make_tasks(TOY, range(5), {"fail_seed": [3]})
    res = sw.sweep(tasks, workers=0, cache_dir=tmp_path, progress=False)
    assert len(res.failures) == 1
    f = res.failures[0]
    assert f["seed"] == 3 and f["params"] == {"fail_seed": 3} and "toy failure at seed 3" in f["error"]
    assert sorted(res.results["seed"].unique()) == [0, 1, 2, 4]
    again = sw.sweep(tasks, workers=0, cache_dir=tmp_path, progress=False)
    assert again.n_cached == 4  # the interrupted/failed sweep resumes from the cache
    pd.testing.assert_frame_equal(_sorted(res.results), _sorted(again.results), check_exact=True)


def test_batches_shrink_to_single_tasks_and_cover_every_task():
    for n, w in ((100, 2), (100, 1), (7, 2), (1, 3), (900, 2)):
        b = sw.batch_sizes(n, w)
        assert sum(b) == n and all(x >= y for x, y in zip(b, b[1:], strict=False)) and max(b) <= 16
        assert b[-1] == 1 and (len(b) < n / 3 if n >= 100 else len(b) == n)
    assert sw.batch_sizes(0, 2) == []


def test_on_dask_a_failed_task_of_a_batch_is_reported_alone_and_the_rest_cached(tmp_path):
    tasks = sw.make_tasks(TOY, range(12), {"fail_seed": [3]})
    assert max(sw.batch_sizes(len(tasks), 2)) > 1  # some batches hold several tasks
    res = sw.sweep(tasks, workers=2, cache_dir=tmp_path, progress=False)
    assert [f["seed"] for f in res.failures] == [3] and "toy failure at seed 3" in res.failures[0]["error"]
    assert sorted(res.results["seed"].unique()) == [s for s in range(12) if s != 3]
    serial = sw.sweep(tasks, workers=0, cache_dir=None, progress=False)
    pd.testing.assert_frame_equal(res.results, serial.results, check_exact=True)  # same rows, task order
    assert sw.sweep(tasks, workers=0, cache_dir=tmp_path, progress=False).n_cached == 11


def test_aggregate_mean_sd_and_t_interval():
    tasks = sw.make_tasks(TOY, range(8))
    res = sw.sweep(tasks, workers=0, cache_dir=None, progress=False)
    agg = sw.aggregate(res.results)
    row = agg[agg["quantity"] == "mean of normals"].iloc[0]
    vals = res.results.loc[res.results["quantity"] == "mean of normals", "value"].to_numpy()
    lo, hi = stats.t.interval(0.95, len(vals) - 1, loc=vals.mean(), scale=stats.sem(vals))
    assert row["n"] == 8
    assert row["mean"] == pytest.approx(vals.mean())
    assert row["std"] == pytest.approx(vals.std(ddof=1))
    assert (row["ci95_low"], row["ci95_high"]) == pytest.approx((lo, hi))
    assert row["ci_agreement"] in ("agrees (inside CI)", "close (beside CI)", "differs (far from CI)")
    assert (agg["quantity"] == "std of normals").any()


def test_ci_agreement_classes():
    assert sw.ci_agreement(1.0, 0.9, 1.1, 1.0) == "agrees (inside CI)"
    assert sw.ci_agreement(1.15, 0.9, 1.1, 1.0) == "close (beside CI)"
    assert sw.ci_agreement(5.0, 0.9, 1.1, 1.0) == "differs (far from CI)"


def test_cli_sweep_writes_summary_and_reports_failures(tmp_path, capsys):
    code = main(["sweep", TOY, "--seeds", "4", "--param", "fail_seed=2", "--workers", "0", "--no-cache",
                 "--out", str(tmp_path)])
    assert code == 1  # one task failed; the others' results are still written
    fails = json.loads((tmp_path / "failures.json").read_text())
    assert fails[0]["seed"] == 2
    summary = pd.read_csv(tmp_path / "summary.csv")
    assert set(summary["n"]) == {3}
    assert main(["sweep", "no_such_experiment", "--seeds", "2"]) == 2


def test_sweep_against_a_separately_started_scheduler_and_worker(tmp_path):
    bindir = Path(sys.executable).parent
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    sched_file = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([str(bindir / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", str(sched_file)],
                              env=env, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        for _ in range(300):
            if sched_file.exists() and sched_file.stat().st_size:
                break
            time.sleep(0.1)
        address = json.loads(sched_file.read_text())["address"]
        procs.append(subprocess.Popen([str(bindir / "dask"), "worker", address, "--nthreads", "1",
                                       "--no-dashboard", "--nworkers", "1"],
                                      env=env, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        from dask.distributed import Client

        with Client(address, timeout=30) as client:
            client.wait_for_workers(1, timeout=60)
        tasks = sw.make_tasks(TOY, range(4))
        remote = sw.sweep(tasks, scheduler=address, cache_dir=None, progress=False)
        serial = sw.sweep(tasks, workers=0, cache_dir=None, progress=False)
        assert not remote.failures
        pd.testing.assert_frame_equal(_sorted(remote.results), _sorted(serial.results), check_exact=True)
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
    assert np.isfinite(remote.results["value"]).all()


def test_paper_ref_rows_without_agreement_are_swept_too():
    from ilocalg.papers import paper_ref

    raw = pd.DataFrame([paper_ref("P", "T", "q", 1.0, 2.0, "m")])  # no agreement column
    long = sw.tables_to_long({"comparison": raw, "other": pd.DataFrame({"x": [1]})})
    assert long[["quantity", "value", "paper_value", "unit"]].values.tolist() == [["q", 2.0, 1.0, "m"]]


def test_record_runs_stores_default_calls_in_the_cache_and_returns_the_same_tables(tmp_path, monkeypatch):
    import importlib

    toy = importlib.import_module(TOY)
    monkeypatch.setattr(toy, "run", toy.run)  # restored after the test
    plain = toy.run(seed=4, fast=True)
    assert sw.record_runs([TOY, "no_such_experiment"], tmp_path) == [TOY]
    assert sw.record_runs([TOY], tmp_path) == []  # never wrapped twice
    got = toy.run(seed=4, fast=True)
    pd.testing.assert_frame_equal(got["comparison"], plain["comparison"])
    task = sw.SweepTask(TOY, (), 4, True)
    pd.testing.assert_frame_equal(pd.read_parquet(sw._cache_path(tmp_path, task)), sw.run_task(task))
    toy.run(seed=5, fast=True, n=10)  # not the sweep's task (n differs): not recorded
    assert not sw._cache_path(tmp_path, sw.SweepTask(TOY, (), 5, True)).exists()
    res = sw.sweep([task], workers=0, cache_dir=tmp_path, progress=False)
    assert res.n_cached == 1


def test_aggregate_clips_intervals_to_the_physical_range_and_flags_them():
    vals = [99.0, 100.0, 96.0, 100.0]
    res = pd.DataFrame({"experiment": "x", "params": "{}", "seed": range(4), "table": "comparison", "paper": "P",
                        "item": "T", "quantity": "accuracy", "unit": "%", "paper_value": 98.0, "value": vals})
    res = pd.concat([res, res.assign(quantity="error", unit="m", value=[0.1, 0.0, 0.5, 0.0]),
                     res.assign(quantity="error difference", unit="m", value=[0.1, 0.0, -0.5, 0.0])])
    agg = sw.aggregate(res).set_index("quantity")
    assert agg.loc["accuracy", "ci95_high"] == 100.0 and agg.loc["accuracy", "ci_clipped"]
    assert agg.loc["error", "ci95_low"] == 0.0 and agg.loc["error", "ci_clipped"]
    assert agg.loc["error difference", "ci95_low"] < 0 and not agg.loc["error difference", "ci_clipped"]


def test_cached_results_read_as_arrow_give_the_frame_read_parquet_and_concat_give(tmp_path):
    """Tables of one schema joined in Arrow, a different schema (an empty result) and a fresh DataFrame between
    them: the same frame, dtypes and index as reading every file with pandas and concatenating."""
    full = pd.DataFrame({"experiment": ["e"] * 3, "params": ["{}"] * 3, "seed": [0, 0, 0],
                         "table": ["t", "t", "m"], "item": ["a", "", "b"], "quantity": ["q", "q", "r"],
                         "value": [1.5, np.nan, -2.0]})
    empty = pd.DataFrame({"experiment": pd.Series([], dtype=object), "seed": pd.Series([], dtype=np.int64),
                          "value": pd.Series([], dtype=np.float64)})
    parts = [full, full.assign(seed=1), empty, full.assign(seed=2), full.assign(seed=3)]
    paths = []
    for i, df in enumerate(parts):
        paths.append(tmp_path / f"{i}.parquet")
        df.to_parquet(paths[-1], index=False)
    fresh = full.assign(seed=9)
    want = pd.concat([pd.read_parquet(p) for p in paths[:3]] + [fresh] + [pd.read_parquet(p) for p in paths[3:]],
                     ignore_index=True)
    got = sw._results_frame([sw._read_cache(p) for p in paths[:3]] + [fresh] + [sw._read_cache(p) for p in paths[3:]])
    pd.testing.assert_frame_equal(got, want, check_exact=True)
    assert got.dtypes.to_dict() == want.dtypes.to_dict() and isinstance(got.index, pd.RangeIndex)
    assert sw._results_frame([]).empty


def test_a_batched_experiments_tasks_run_together_with_each_tasks_result_and_failure(tmp_path):
    """An experiment with run_many gets its tasks of one sweep in one call; each cached result is the one
    run_task gives; when the call raises, the tasks run one by one and only the failing one is reported."""
    from tests import sweep_toy_batched as bt

    batched = "tests.sweep_toy_batched"
    assert sw.batched(batched) and not sw.batched(TOY)
    tasks = sw.make_tasks(batched, range(3)) + sw.make_tasks(TOY, range(2))
    bt.CALLS.clear()
    res = sw.sweep(tasks, workers=0, cache_dir=tmp_path, progress=False)
    assert bt.CALLS == [3] and not res.failures
    for t in tasks:
        pd.testing.assert_frame_equal(pd.read_parquet(sw._cache_path(tmp_path, t)), sw.run_task(t), check_exact=True)
    failing = sw.make_tasks(batched, range(3), {"fail_seed": [1]})
    bt.CALLS.clear()
    res = sw.sweep(failing, workers=0, cache_dir=None, progress=False)
    assert bt.CALLS == [3]  # the batch raised; its tasks then ran one by one
    assert [f["seed"] for f in res.failures] == [1] and "toy failure at seed 1" in res.failures[0]["error"]


@pytest.mark.parametrize("tables", [
    {"comparison": pd.DataFrame({"paper": ["i-Loc", None], "item": ["Fig 23", 5], "quantity": ["KF", "PTS"],
                                 "paper_value": [2.82, None], "reproduced_value": [2.9, 3], "unit": ["m", np.nan]}),
     "other": pd.DataFrame({"x": [1]}), "note": "not a table"},
    {"comparison": pd.DataFrame({"paper": ["p"], "item": [1.5], "quantity": ["q"], "paper_value": [1],
                                 "reproduced_value": [np.float32(0.1)]})},
    {"sweep_kf": pd.DataFrame({"quantity": ["rmse", "mean"], "value": [1.25, np.nan], "unit": ["m", "m"],
                               "item": ["window_s=5", "window_s=10"]})},
    {"measures": pd.DataFrame({"quantity": ["a"], "value": [2], "paper": ["x"], "paper_value": [None]})},
    {"sweep_a": pd.DataFrame({"quantity": ["a"], "value": [1.0], "item": [3]}),
     "sweep_b": pd.DataFrame({"quantity": ["b"], "value": [2.0], "item": [0.5]})},  # two tables: concatenated
    {"sweep_empty": pd.DataFrame({"quantity": pd.Series(dtype=object), "value": pd.Series(dtype=float)})},
], ids=["paper-rows", "paper-one", "sweep", "measures", "two-tables", "empty"])
def test_task_result_from_one_frame_equals_the_per_table_concatenation(tables):
    """The one-frame path (``long_columns``, one non-empty sweepable table) gives the frame of the per-table
    concatenation, dtypes and parquet bytes included; other inputs go the concatenation's way."""
    import io

    from ilocalg.papers.claims import _tables_to_long, long_columns

    task = sw.SweepTask("demo", (("k", 2), ("mode", "a")), 3)
    ref = _tables_to_long(tables)
    for name, value in (("seed", task.seed), ("params", json.dumps(dict(task.params), sort_keys=True)),
                        ("experiment", task.experiment)):
        ref.insert(0, name, value)
    got = sw._task_result(task, tables)
    assert got.equals(ref) and list(got.dtypes) == list(ref.dtypes) and got.index.equals(ref.index)
    assert sw.tables_to_long(tables).equals(_tables_to_long(tables))
    a, b = io.BytesIO(), io.BytesIO()
    ref.to_parquet(a, index=False)
    got.to_parquet(b, index=False)
    assert a.getvalue() == b.getvalue()
    assert (long_columns(tables) is None) == ("sweep_b" in tables or "sweep_empty" in tables)
