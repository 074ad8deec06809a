"""Seed and parameter sweeps of the experiments, on Dask.

An experiment is a module ``ilocalg.experiments.<name>`` (or any importable module given by its
dotted path, e.g. a researcher's own) with ``run(seed, fast, **params)``
returning named tables. A sweep runs it for every combination of parameter values and every seed
as independent tasks on a :mod:`dask.distributed` cluster (a :class:`~distributed.LocalCluster`
by default, or an existing scheduler), caches each task's result as parquet so an interrupted
sweep resumes, reports failed tasks with their seed and parameters without losing the others,
and aggregates the reproduced values into mean, standard deviation and 95 % confidence interval.

What is swept: the rows of the experiment's comparison tables (:func:`ilocalg.papers.paper_ref`
rows, :data:`PAPER_REF_COLUMNS`), i.e. every reproduced value the report shows,
plus any numeric ``value`` column of tables named ``sweep_*`` (for parameter studies) or ``measures*``
(named scalars an experiment exposes for the claims ledger, :mod:`ilocalg.papers.claims`).
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import inspect
import itertools
import json
import logging
import math
import os
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import REPO_ROOT
from ilocalg.papers import clip_interval
from ilocalg.papers.claims import RESULT_COLUMNS, long_columns, tables_to_long  # the long format the claims read

__all__ = [
    "RESULT_COLUMNS",
    "tables_to_long",
    "SweepTask",
    "SweepResult",
    "make_tasks",
    "run_task",
    "run_tasks",
    "batched",
    "run_batch",
    "batch_sizes",
    "sweep",
    "aggregate",
    "ci_agreement",
    "parse_param",
    "record_runs",
    "DEFAULT_CACHE",
]

DEFAULT_CACHE = REPO_ROOT / ".ilocalg-cache" / "sweeps"



@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """sha256 of every ``ilocalg`` source file: part of each cache key, so a cached result is never
    reused after the code that computed it has changed (a user's own experiment module outside
    ``ilocalg`` is not covered: clear the cache or pass ``--no-cache`` after editing it)."""
    h = hashlib.sha256()
    pkg = Path(__file__).resolve().parents[1]  # the whole ilocalg package, not only workflow/
    for f in sorted(pkg.rglob("*.py")):
        h.update(str(f.relative_to(pkg)).encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


@dataclass(frozen=True)
class SweepTask:
    """One (experiment, parameters, seed) run."""

    experiment: str
    params: tuple  # sorted (name, value) pairs
    seed: int
    fast: bool = False

    @property
    def key(self) -> str:
        blob = json.dumps([self.experiment, list(self.params), self.seed, self.fast, code_fingerprint()],
                          sort_keys=True, default=str)
        return hashlib.sha256(blob.encode()).hexdigest()[:20]

    def describe(self) -> str:
        ps = ", ".join(f"{k}={v!r}" for k, v in self.params)
        return f"{self.experiment}(seed={self.seed}{', ' + ps if ps else ''}{', fast' if self.fast else ''})"


@dataclass
class SweepResult:
    """Outcome of :func:`sweep`: per-task long results, failures and what came from cache."""

    results: pd.DataFrame
    failures: list = field(default_factory=list)
    n_tasks: int = 0
    n_cached: int = 0


def parse_param(text: str) -> tuple[str, list]:
    """``"k=3,5,7"`` -> ``("k", [3, 5, 7])``; values are parsed as JSON when possible, else strings."""
    if "=" not in text:
        raise ValueError(f"--param must look like NAME=V1,V2,... ; got {text!r}")
    name, vals = text.split("=", 1)
    name = name.strip()
    if not name.isidentifier():
        raise ValueError(f"parameter name {name!r} is not a Python identifier")
    out = []
    for v in vals.split(","):
        v = v.strip()
        if not v:
            raise ValueError(f"--param {name}: empty value in {vals!r}")
        try:
            out.append(json.loads(v))
        except json.JSONDecodeError:
            out.append(v)
    return name, out


def make_tasks(experiment: str, seeds: Iterable[int], grid: Mapping[str, list] | None = None,
               fast: bool = False) -> list[SweepTask]:
    """Every combination of the parameter ``grid`` crossed with every seed."""
    grid = dict(grid or {})
    names = sorted(grid)
    combos = list(itertools.product(*(grid[n] for n in names))) if names else [()]
    return [SweepTask(experiment, tuple(zip(names, combo, strict=True)), int(s), fast)
            for combo in combos for s in seeds]


def _experiment(name: str):
    """``name`` under ilocalg.experiments, or a dotted module path of the user's own experiment."""
    modname = name if "." in name else f"ilocalg.experiments.{name}"
    try:
        mod = importlib.import_module(modname)
    except ModuleNotFoundError as exc:
        raise ValueError(f"unknown experiment {name!r} (no module {modname})") from exc
    if not hasattr(mod, "run"):
        raise ValueError(f"ilocalg.experiments.{name} has no run() function")
    return mod


def _task_result(task: SweepTask, tables: Mapping[str, pd.DataFrame]) -> pd.DataFrame:
    columns = long_columns(tables)
    if columns is not None:  # one frame built, not one per table and column (the same frame)
        n = len(columns["value"])
        return pd.DataFrame({"experiment": [task.experiment] * n,
                             "params": [json.dumps(dict(task.params), sort_keys=True, default=str)] * n,
                             "seed": np.full(n, task.seed, dtype=np.int64), **columns})
    out = tables_to_long(tables)
    out.insert(0, "seed", task.seed)
    out.insert(0, "params", json.dumps(dict(task.params), sort_keys=True, default=str))
    out.insert(0, "experiment", task.experiment)
    return out


def run_task(task: SweepTask) -> pd.DataFrame:
    """Run one task and return its long-format result (importable by Dask workers); the experiment's
    :data:`ilocalg.workflow.manifest.SWEEP_KWARGS` (side studies the result does not keep) apply unless the
    task's parameters set them."""
    return _task_result(task, _experiment(task.experiment).run(**_run_kwargs(task)))


def _run_kwargs(task: SweepTask) -> dict:
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    return {**SWEEP_KWARGS.get(task.experiment, {}), **dict(task.params), "seed": task.seed, "fast": task.fast}


def batched(experiment: str) -> bool:
    """Whether the experiment's module has ``run_many(runs)``: :func:`run` for each mapping of keywords in
    ``runs``, computed together, each result the one ``run`` gives alone. Its tasks of one sweep then run in one
    call (:func:`run_batch`), and reproduce gives its seed sweep and its robustness samples one pool job each."""
    return callable(getattr(_experiment(experiment), "run_many", None))


def run_batch(tasks: list[SweepTask]) -> list[tuple[bool, object]]:
    """:func:`run_tasks` with the tasks of each :func:`batched` experiment in one ``run_many`` call (in their
    order); if that call raises, its tasks run one by one, so that a failure is still reported per task."""
    out: dict[int, tuple[bool, object]] = {}
    groups: dict[str, list[int]] = {}
    for i, t in enumerate(tasks):
        groups.setdefault(t.experiment if batched(t.experiment) else f"\0{i}", []).append(i)
    for idx in groups.values():
        if len(idx) > 1:
            try:
                tables = _experiment(tasks[idx[0]].experiment).run_many([_run_kwargs(tasks[i]) for i in idx])
                for i, tb in zip(idx, tables, strict=True):
                    out[i] = (True, _task_result(tasks[i], tb))
                continue
            except Exception:  # noqa: BLE001 - the tasks run one by one below and report their own failures
                pass
        for i, r in zip(idx, run_tasks([tasks[i] for i in idx]), strict=True):
            out[i] = r
    return [out[i] for i in range(len(tasks))]


def run_tasks(tasks: list[SweepTask]) -> list[tuple[bool, object]]:
    """Run several tasks in one call (one Dask task): per task ``(True, long result)`` or ``(False, "Type:
    message")`` for a task that raised, so one failure never loses the others."""
    out = []
    for t in tasks:
        try:
            out.append((True, run_task(t)))
        except Exception as exc:  # noqa: BLE001 - reported per task by sweep()
            out.append((False, f"{type(exc).__name__}: {exc}"))
    return out


def batch_sizes(n_tasks: int, n_workers: int, per_worker: int = 4, max_batch: int = 16) -> list[int]:
    """Tasks per Dask task when ``n_tasks`` run on ``n_workers`` (guided self-scheduling).

    Each batch takes ``ceil(left / (per_worker * n_workers))`` of the tasks left, at most ``max_batch``, so
    batches shrink to single tasks at the end: the scheduler and the client (in the driver process, where
    their cost per Dask task competes with the workers for the cores) handle a few dozen Dask tasks for a
    hundred sweep tasks, while no worker is left alone with a long last batch, and an interrupted sweep
    loses at most ``max_batch`` uncached results per worker.
    """
    out, left, div = [], int(n_tasks), max(1, int(per_worker) * max(1, int(n_workers)))
    while left > 0:
        b = min(-(-left // div), int(max_batch))
        out.append(b)
        left -= b
    return out


def _cache_path(cache_dir: Path, task: SweepTask) -> Path:
    return Path(cache_dir) / task.experiment / f"{task.key}.parquet"


def _read_cache(path: Path):
    """A cached result as an Arrow table (:func:`_results_frame` turns the tables into one DataFrame): a study
    notebook reads some 900 of them, and reading each with ``pd.read_parquet`` cost ~4 ms, ~7x this."""
    import pyarrow.parquet as pq

    with pq.ParquetFile(path) as f:
        return f.read(use_threads=False)


def _results_frame(parts: list) -> pd.DataFrame:
    """``pd.concat(frames, ignore_index=True)`` of task results given as DataFrames or cached Arrow tables
    (:func:`_read_cache`): consecutive tables of one schema are joined in Arrow and converted once; each
    converted part has the dtypes its tables have one by one, so the frame is the one ``pd.read_parquet`` of
    every file and ``pd.concat`` gave."""
    import pyarrow as pa

    frames, run = [], []

    def flush():
        if run:
            frames.append((pa.concat_tables(run) if len(run) > 1 else run[0]).to_pandas())
            run.clear()

    for p in parts:
        if isinstance(p, pa.Table):
            if run and not p.schema.equals(run[0].schema, check_metadata=True):
                flush()
            run.append(p)
        else:
            flush()
            frames.append(p)
    flush()
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()


def _write_cache(cache_dir: Path, task: SweepTask, df: pd.DataFrame) -> None:
    cp = _cache_path(cache_dir, task)
    cp.parent.mkdir(parents=True, exist_ok=True)
    tmp = cp.with_suffix(f".{os.getpid()}.tmp")
    df.to_parquet(tmp, index=False)
    tmp.replace(cp)


#: Environment variables through which the reproduce runner asks a notebook's kernel to record its runs.
RECORD_ENV = "ILOCALG_RECORD_RUNS_CACHE"
RECORD_EXPERIMENTS_ENV = "ILOCALG_RECORD_RUNS_EXPERIMENTS"


def _default_call(sig: inspect.Signature, arguments: Mapping) -> bool:
    """True when every argument but ``seed`` and ``fast`` is its default (``data_dir``: the default folder)."""
    from ilocalg.io.paths import data_dir

    for name, value in arguments.items():
        if name in ("seed", "fast"):
            continue
        if name == "data_dir":
            if value is not None and Path(value).resolve() != data_dir():
                return False
            continue
        default = sig.parameters[name].default
        if value is default:
            continue
        try:
            if default is inspect.Parameter.empty or not bool(value == default):
                return False
        except (TypeError, ValueError):
            return False
    return True


def record_runs(experiments: Iterable[str], cache_dir: str | Path) -> list[str]:
    """Make each experiment's ``run`` also store its result in the sweep cache, as a sweep task would.

    The reproduce runner calls this (through :class:`ilocalg.workflow.reporting.Report`) in a
    notebook's kernel, so the seed sweep that follows reuses the notebook's own run at its seed
    instead of repeating it. Only calls with every other argument at its default are recorded
    (those are the sweep's tasks); what ``run`` returns is unchanged, and a result that cannot be
    recorded is simply recomputed by the sweep. Returns the experiments wrapped.
    """
    wrapped = []
    for name in experiments:
        try:
            mod = _experiment(name)
        except (ValueError, ImportError):
            continue
        orig = mod.run
        if getattr(orig, "_ilocalg_records_to", None) is not None:
            continue
        sig = inspect.signature(orig)

        def run(*args, _orig=orig, _name=name, _sig=sig, **kwargs):
            tables = _orig(*args, **kwargs)
            try:
                bound = _sig.bind(*args, **kwargs)
                if _default_call(_sig, bound.arguments):
                    bound.apply_defaults()
                    task = SweepTask(_name, (), int(bound.arguments["seed"]), bool(bound.arguments["fast"]))
                    _write_cache(Path(cache_dir), task, _task_result(task, tables))
            except Exception as exc:  # noqa: BLE001 - recording never changes what the notebook gets
                warnings.warn(f"{_name}.run result not recorded for the sweep ({type(exc).__name__}: {exc}); "
                              f"the sweep recomputes it", stacklevel=2)
            return tables

        functools.update_wrapper(run, orig)
        run._ilocalg_records_to = str(cache_dir)
        mod.run = run
        wrapped.append(name)
    return wrapped


def sweep(tasks: list[SweepTask], scheduler: str | None = None, workers: int = 2,
          cache_dir: str | Path | None = DEFAULT_CACHE, progress: bool = True,
          client=None) -> SweepResult:
    """Run ``tasks`` on Dask, caching each result; failed tasks are collected, never fatal.

    Parameters
    ----------
    tasks : list of SweepTask
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``); None starts a LocalCluster
        with ``workers`` single-threaded worker processes.
    workers : int
        Worker processes of the LocalCluster (ignored with ``scheduler``); 0 runs serially
        in this process without Dask (the reference the cluster must match bit for bit). On Dask the
        tasks travel in batches (:func:`batch_sizes`, :func:`run_tasks`); each task's result is still
        cached and each failure reported on its own.
    cache_dir : path or None
        Where each task's parquet result is cached (None: no cache).
    """
    from tqdm import tqdm  # plain text bar: works in terminals, notebooks and logs alike

    if workers < 0:
        raise ValueError(f"workers must be >= 0, got {workers}")
    cache = Path(cache_dir) if cache_dir is not None else None
    done: dict[str, pd.DataFrame] = {}
    todo = []
    for t in tasks:
        cp = _cache_path(cache, t) if cache else None
        if cp is not None and cp.exists():
            done[t.key] = _read_cache(cp)  # an Arrow table until _results_frame
        else:
            todo.append(t)
    n_cached = len(done)
    failures = []

    def _store(t: SweepTask, df: pd.DataFrame):
        done[t.key] = df
        if cache is not None:
            _write_cache(cache, t, df)

    bar = tqdm(total=len(tasks), initial=n_cached, desc="sweep", unit="run", disable=not progress)
    if todo and workers == 0 and scheduler is None and client is None:
        for t, (ok, val) in zip(todo, run_batch(todo), strict=True):
            if ok:
                _store(t, val)
            else:  # a failed task is reported, not fatal
                failures.append({"task": t.describe(), "seed": t.seed, "params": dict(t.params), "error": val})
            bar.update(1)
    elif todo:
        from dask.distributed import Client, LocalCluster, as_completed

        own_cluster = own_client = None
        try:
            if client is None:
                if scheduler is None:
                    # dashboard on any free port: never clashes with another cluster on this machine
                    own_cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                               dashboard_address=":0", silence_logs=logging.ERROR)
                    own_client = client = Client(own_cluster)
                else:
                    own_client = client = Client(scheduler)
            n_workers = len(client.nthreads()) or workers  # a remote scheduler: the workers it has now
            futs, i = {}, 0
            for b in batch_sizes(len(todo), n_workers):
                batch = todo[i:i + b]
                i += b
                key = hashlib.sha256("".join(t.key for t in batch).encode()).hexdigest()[:20]
                futs[client.submit(run_tasks, batch, key=f"ilocalg-{batch[0].experiment}-{key}", pure=False)] = batch
            for fut in as_completed(futs):
                batch = futs[fut]
                try:
                    outcome = fut.result()
                except Exception as exc:  # noqa: BLE001 - the whole batch is lost (e.g. its worker died)
                    outcome = [(False, f"{type(exc).__name__}: {exc}")] * len(batch)
                for t, (ok, value) in zip(batch, outcome, strict=True):
                    if ok:
                        _store(t, value)
                    else:
                        failures.append({"task": t.describe(), "seed": t.seed, "params": dict(t.params),
                                         "error": value})
                bar.update(len(batch))
        finally:
            if own_client is not None:
                own_client.close()
            if own_cluster is not None:
                own_cluster.close()
    bar.close()
    results = _results_frame([done[t.key] for t in tasks if t.key in done])
    return SweepResult(results=results, failures=failures, n_tasks=len(tasks), n_cached=n_cached)


def ci_agreement(paper_value: float, lo: float, hi: float, mean: float) -> str:
    """Where the paper's value lies relative to the reproduced 95 % CI, in the project's one vocabulary.

    ``agrees (inside CI)``: inside the interval; ``close (beside CI)``: outside it but within one
    interval width of it or within 10 % of the mean; ``differs (far from CI)`` otherwise.
    """
    if not all(math.isfinite(v) for v in (paper_value, mean)):
        return "n/a"
    if math.isfinite(lo) and lo <= paper_value <= hi:
        return "agrees (inside CI)"
    width = (hi - lo) if math.isfinite(hi - lo) else 0.0
    dist = min(abs(paper_value - lo), abs(paper_value - hi)) if math.isfinite(lo) else abs(paper_value - mean)
    if dist <= width or abs(paper_value - mean) <= 0.10 * abs(mean):
        return "close (beside CI)"
    return "differs (far from CI)"


def aggregate(results: pd.DataFrame, level: float = 0.95) -> pd.DataFrame:
    """Mean, sample standard deviation and a Student-t confidence interval per reported quantity.

    The interval is clipped to the quantity's physical range (:func:`ilocalg.papers.physical_range`: a
    length or count is not negative, a percentage lies in [0, 100]); ``ci_clipped`` flags an interval
    that had to be clipped (the t interval is then a poor model of the spread: few seeds, skewed values)."""
    from scipy import stats

    if results.empty:
        raise ValueError("no sweep results to aggregate")
    keys = ["experiment", "params", "table", "paper", "item", "quantity", "unit"]
    rows = []
    for k, g in results.groupby(keys, sort=True, dropna=False):
        v = g["value"].to_numpy(dtype=np.float64)
        v = v[np.isfinite(v)]
        n = v.size
        mean = float(v.mean()) if n else float("nan")
        sd = float(v.std(ddof=1)) if n > 1 else float("nan")
        half = float(stats.t.ppf(0.5 + level / 2, n - 1) * sd / math.sqrt(n)) if n > 1 else float("nan")
        pv = float(g["paper_value"].iloc[0])
        rec = dict(zip(keys, k, strict=True))
        lo, hi, clipped = clip_interval(mean - half, mean + half, rec["unit"], rec["quantity"])
        rows.append(dict(rec, n=n, mean=mean, std=sd, ci95_low=lo, ci95_high=hi, ci_clipped=clipped,
                         paper_value=pv, ci_agreement=ci_agreement(pv, lo, hi, mean)))
    return pd.DataFrame(rows)
