"""The reproduce runner: execute every notebook with parameters and write ``reports/``.

``python -m ilocalg reproduce [--fast] [--only PATTERN] [--seed N] [--seeds N] [--jobs J]`` executes
``notebooks/NN_*.ipynb`` with papermill (each notebook's cell tagged ``parameters`` receives ``SEED``,
``FAST`` and ``OUT_DIR``, relative to the notebook's folder; ``DATA_DIR`` keeps its default), ``J`` notebooks side
by side (independent processes, longest first), and exports each executed notebook, figures inline,
to ``reports/<name>.ipynb`` and ``.html`` (figures also as files: PNG and PDF, PNG only with ``--fast``).
With ``--seeds N`` the swept experiments of
:data:`ilocalg.workflow.manifest.MANIFEST` are re-run over seeds: the runs at the other seeds share the
same process pool as the notebooks, and the run at the base seed is the notebook's own (recorded into
the sweep cache by its kernel, see :func:`ilocalg.workflow.sweep.record_runs`), never repeated.
Afterwards ``reports/README.md``, ``reports/index.html`` (the landing page) and
``reports/provenance.json`` are built from what the notebooks wrote, and ``reports/timings.csv`` says where
the time went, as wall and CPU time (per notebook, per swept experiment, per stage; :func:`write_timings`).
A failing notebook stops the run (notebooks not yet started are cancelled) with its failing cell's error and a
non-zero exit code.
"""

from __future__ import annotations

import fnmatch
import json
import os
import sys
import time
from collections.abc import Mapping
from contextlib import contextmanager
from pathlib import Path

from ilocalg.io.paths import REPO_ROOT
from ilocalg.workflow.claims_step import n_samples_for, robustness_tasks
from ilocalg.workflow.manifest import COST_S, MANIFEST, experiments_of, swept_experiments
from ilocalg.workflow.reporting import FIGURE_FORMATS_ENV, build_index, build_readme, write_provenance, write_table
from ilocalg.workflow.runstore import run_store
from ilocalg.workflow.studies import NOTEBOOK_STUDIES, notebook_tasks

__all__ = ["NOTEBOOK_DIR", "discover_notebooks", "execute_notebook", "reproduce", "NotebookFailed",
           "sweep_experiments", "KERNEL_MPLBACKEND", "write_timings", "TIMINGS_COLUMNS", "cpu_seconds",
           "idle_wall_estimate", "study_jobs", "batch_jobs"]

NOTEBOOK_DIR = REPO_ROOT / "notebooks"

#: Matplotlib backend of the notebook kernels: inline, so every figure is in the executed notebook and its
#: HTML (the notebooks also save each figure as PNG + PDF under reports/figures/).
KERNEL_MPLBACKEND = "module://matplotlib_inline.backend_inline"


class NotebookFailed(RuntimeError):
    """A notebook raised; carries the notebook name and the failing cell's error."""


def discover_notebooks(notebook_dir: Path = NOTEBOOK_DIR, only: str | None = None) -> list[Path]:
    """Notebooks ``NN_*.ipynb`` in name order; ``only`` is a glob or substring on the stem."""
    nbs = sorted(p for p in Path(notebook_dir).glob("[0-9][0-9]_*.ipynb"))
    if only:
        pats = [p.strip() for p in only.split(",") if p.strip()]
        nbs = [p for p in nbs if any(fnmatch.fnmatch(p.stem, pat) or pat in p.stem for pat in pats)]
    return nbs


@contextmanager
def _environ(**values: str | None):
    """Set (or, with None, unset) environment variables for the block: a kernel started inside inherits them."""
    old = {k: os.environ.get(k) for k in values}
    try:
        for k, v in values.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _relative(path: str | Path, start: Path) -> str:
    """``path`` relative to ``start`` (POSIX separators), so executed notebooks show no machine's absolute paths."""
    try:
        return Path(os.path.relpath(Path(path).resolve(), Path(start).resolve())).as_posix()
    except ValueError:  # another drive (Windows): nothing relative exists
        return str(path)


def _import_jsonschema_lean() -> None:
    """Import jsonschema (nbformat's validator, loaded by papermill) without the optional ``rfc3987_syntax``.

    When ``rfc3987_syntax`` is installed, importing jsonschema compiles its 38 Lark grammars for the ``iri`` and
    ``iri-reference`` format checkers: about 2.5 of the 3.5 CPU-s that ``import papermill`` costs each process that
    runs notebooks. nbformat validates notebooks without a format checker, so those checkers are never used
    here; jsonschema skips them when the import fails. Nothing changes when jsonschema (or rfc3987_syntax) is
    already imported; afterwards ``rfc3987_syntax`` imports normally.
    """
    if "jsonschema" in sys.modules or "rfc3987_syntax" in sys.modules:
        return
    sys.modules["rfc3987_syntax"] = None  # type: ignore[assignment]  # "import rfc3987_syntax" raises ImportError
    try:
        import jsonschema  # noqa: F401
    finally:
        if sys.modules.get("rfc3987_syntax", 0) is None:
            del sys.modules["rfc3987_syntax"]


def execute_notebook(nb: Path, out_dir: Path, parameters: dict, progress: bool = True,
                     html: bool = True, record: tuple[str, list[str]] | None = None,
                     study_cache: str | Path | None = None) -> Path:
    """Execute one notebook with papermill into ``out_dir/<name>.ipynb`` (+ ``.html``), figures inline.

    ``record`` = (sweep cache folder, experiments): the kernel stores those experiments' runs in the
    sweep cache (:func:`ilocalg.workflow.sweep.record_runs`). ``study_cache``: the sweep cache in which the
    runner's pool ran a study notebook's tasks (:func:`ilocalg.workflow.studies.run_notebook_tasks` reads them).
    """
    _import_jsonschema_lean()
    import papermill as pm  # heavy; imported only when notebooks run

    from ilocalg.workflow import sweep as sw
    from ilocalg.workflow.kernels import QuietKernelManager
    from ilocalg.workflow.studies import STUDY_CACHE_ENV

    out_nb = out_dir / nb.name
    env = {"MPLBACKEND": KERNEL_MPLBACKEND,
           sw.RECORD_ENV: str(record[0]) if record and record[1] else None,
           sw.RECORD_EXPERIMENTS_ENV: ",".join(record[1]) if record and record[1] else None,
           STUDY_CACHE_ENV: str(study_cache) if study_cache is not None else None,
           # fast mode saves figures as PNG only (shown inline and on the pages); a full run adds the PDF
           FIGURE_FORMATS_ENV: "png" if parameters.get("FAST") else os.environ.get(FIGURE_FORMATS_ENV)}
    try:
        with _environ(**env):
            pm.execute_notebook(
                str(nb),
                str(out_nb),
                parameters=parameters,
                kernel_name="python3",
                progress_bar=progress,
                cwd=str(nb.parent),
                log_output=False,
                kernel_manager_class=QuietKernelManager,  # no transport warning, no SIGINT at shutdown
            )
    except pm.PapermillExecutionError as exc:
        raise NotebookFailed(
            f"{nb.name}: cell {exc.exec_count} raised {exc.ename}: {exc.evalue}\n"
            f"executed copy with the traceback: {_relative(out_nb, Path.cwd())}"
        ) from None
    import nbformat

    node = nbformat.read(out_nb, as_version=4)
    pmeta = node.metadata.get("papermill", {})
    base = Path(os.path.commonpath([Path(nb).resolve(), out_nb.resolve()]))  # the project, for its own notebooks
    for key in ("input_path", "output_path"):  # papermill records the paths it was given: keep them relative
        if pmeta.get(key):
            pmeta[key] = _relative(pmeta[key], base)
    nbformat.write(node, out_nb)
    if html:
        from ilocalg.workflow.html_export import export_html

        export_html(node, out_nb.with_suffix(".html"))  # equations typeset, no remote script
    return out_nb


def sweep_experiments(nbs: list[Path], out_dir: Path, seed: int, n_seeds: int, fast: bool, workers: int,
                      progress: bool, cache_dir=None,
                      manifest: Mapping[str, Mapping[str, bool]] | None = None,
                      since: float | None = None) -> tuple[int, object]:
    """Re-run the notebooks' swept experiments (:data:`ilocalg.workflow.manifest.MANIFEST`) over ``n_seeds``
    seeds; write ``sweeps/summary`` and return it. Runs already in the cache (the notebooks' own, at the
    base seed, and those the runner's pool made) are read, not repeated; ``since`` (a ``time.time()``) tells
    the runs of this reproduce (cached after it) from those reused from an earlier one."""
    from ilocalg.workflow import sweep as sw

    exps = swept_experiments([nb.stem for nb in nbs], manifest=manifest)
    if not exps:
        return 0, None
    tasks = [t for e in exps for t in sw.make_tasks(e, range(seed, seed + n_seeds), fast=fast)]
    cached = [sw._cache_path(cache_dir or sw.DEFAULT_CACHE, t) for t in tasks]
    n_fresh = sum(1 for p in cached if p.exists() and since is not None and p.stat().st_mtime >= since)
    res = sw.sweep(tasks, workers=workers, cache_dir=cache_dir or sw.DEFAULT_CACHE, progress=progress)
    print(f"confidence intervals: {len(exps)} experiment(s) x {n_seeds} seeds = {res.n_tasks} runs ("
          f"{n_fresh} made by this reproduce's notebooks and pool, {res.n_cached - n_fresh} reused from an "
          f"earlier reproduce, {res.n_tasks - res.n_cached} run now on {workers} worker(s))", flush=True)
    for f in res.failures:
        print(f"FAILED {f['task']}: {f['error']}", file=sys.stderr, flush=True)
    if res.results.empty:
        return (1 if res.failures else 0), None
    summary = sw.aggregate(res.results)
    write_table(summary, out_dir / "sweeps" / "summary")
    return (1 if res.failures else 0), summary


def _clear_outputs(out_dir: Path, stem: str) -> None:
    """Remove what an earlier run of this notebook wrote, so the reports never mix two runs."""
    for pattern in (f"tables/{stem}__*", f"tables/timing/{stem}__*", f"figures/{stem}_*", f".inputs/{stem}.txt",
                    f"{stem}.ipynb", f"{stem}.html"):
        for f in out_dir.glob(pattern):
            if f.is_file():
                f.unlink()


def cpu_seconds() -> float:
    """CPU time (user + system) of this process and of every child process it has waited for, in seconds.

    A notebook's kernel, a Dask worker and a pool worker are child processes: their time counts once they have
    ended (``getrusage(RUSAGE_CHILDREN)``, which also holds their own children's). On a shared machine the wall
    time of a job grows with the load; its CPU time does not, so the CPU column of ``timings.csv`` still says
    where the work went. Without ``resource`` (Windows): this process's time only.
    """
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows
        return time.process_time()
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def _notebook_job(nb: Path, out_dir: Path, params: dict, html: bool, record, progress: bool = False,
                  study_cache: Path | None = None) -> dict:
    """One notebook as a pool job: never raises, returns its name, wall and CPU time and error (or None)."""
    t0, c0 = time.perf_counter(), cpu_seconds()
    try:
        execute_notebook(nb, out_dir, params, progress=progress, html=html, record=record, study_cache=study_cache)
        err = None
    except NotebookFailed as exc:
        err = str(exc)
    except Exception as exc:  # noqa: BLE001 - a kernel that dies is a failed notebook, reported by name
        err = f"{nb.name}: {type(exc).__name__}: {exc}"
    return {"name": nb.stem, "seconds": time.perf_counter() - t0, "cpu_seconds": cpu_seconds() - c0, "error": err}


def _sweep_job(task, cache_dir: Path) -> dict:
    """One seed-sweep run, robustness sample or study task (or a list of study tasks, :func:`study_jobs`) as a pool
    job: results into the cache; failures are reported by whoever reads the cache later (the sweep, the claims
    step, the study notebook)."""
    from ilocalg.workflow import sweep as sw

    tasks = task if isinstance(task, list) else [task]
    t0, c0 = time.perf_counter(), cpu_seconds()
    sw.sweep(tasks, workers=0, cache_dir=cache_dir, progress=False)
    return {"name": tasks[0].describe(), "seconds": time.perf_counter() - t0, "cpu_seconds": cpu_seconds() - c0,
            "error": None, "runs": len(tasks)}


def study_jobs(tasks: list) -> list[list]:
    """A study notebook's tasks grouped into pool jobs: one job per (experiment, seed), tasks in their order; every
    task of a study that runs several together (:func:`ilocalg.workflow.sweep.batched`, e.g. study_ins_window,
    whose walks' filters then advance in lockstep) in one job.

    The tasks of one seed share what a study caches in its process (the simulated floor and surveys of
    ``study_wifi``, the walks of ``study_pso``), so one process computes them once instead of each pool process
    computing its own copy; and some 50 jobs of a few seconds instead of ~900 of a fraction of one keep the pool's
    per-job cost small while still filling both cores. The results (one cache entry per task) are the same.
    """
    from ilocalg.workflow import sweep as sw

    groups: dict[tuple, list] = {}
    for t in tasks:
        groups.setdefault((t.experiment,) if sw.batched(t.experiment) else (t.experiment, t.seed), []).append(t)
    return list(groups.values())


def batch_jobs(tasks: list) -> list[list]:
    """Seed-sweep runs or robustness samples as pool jobs: one job per task, except that the tasks of an
    experiment that runs several together (:func:`ilocalg.workflow.sweep.batched`: e.g. ins_hartmann, whose
    sequences of all seeds then share one lockstep filter) are one job, in their order. The results (one cache
    entry per task) are the same."""
    from ilocalg.workflow import sweep as sw

    jobs: list[list] = []
    together: dict[str, list] = {}
    for t in tasks:
        if sw.batched(t.experiment):
            if t.experiment not in together:
                together[t.experiment] = []
                jobs.append(together[t.experiment])
            together[t.experiment].append(t)
        else:
            jobs.append([t])
    return jobs


#: Thread-count variables of the numerical libraries, set to 1 for notebooks run side by side.
_BLAS_THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _timings_path(cache_dir: Path) -> Path:
    return Path(cache_dir).parent / "timings.json"


def _timing_key(name: str, fast: bool) -> str:
    return f"{name} (fast)" if fast else name


def _load_timings(cache_dir: Path) -> dict:
    try:
        return {**COST_S, **json.loads(_timings_path(cache_dir).read_text())}
    except (OSError, ValueError):
        return dict(COST_S)


#: Columns of ``reports/timings.csv`` (see :func:`write_timings`).
TIMINGS_COLUMNS = ("stage", "name", "seconds", "cpu_seconds", "runs")


def idle_wall_estimate(job_cpu_s: list[float], slots: int, serial_cpu_s: float = 0.0) -> float:
    """Wall time the run would take on an idle machine with ``slots`` cores, estimated from CPU times.

    The jobs that ran side by side (notebooks and seed-sweep runs, ``job_cpu_s``) are placed longest first on
    ``slots`` cores, each on the core that frees first (the runner's own order), taking as long as their CPU
    time; the stages after them (``serial_cpu_s``) are added as if run on one core. A job's wall time on an idle
    machine is at least its CPU time (less only for a job that runs processes of its own in parallel, such as
    a study notebook run alone on its Dask workers) and more by what it waits for (kernel start, disk), so this
    is an estimate of the order of the wall time, not a bound either way.
    """
    import heapq

    if slots < 1:
        raise ValueError(f"slots must be >= 1, got {slots}")
    free = [0.0] * slots
    for c in sorted((float(c) for c in job_cpu_s), reverse=True):
        heapq.heapreplace(free, free[0] + c)
    return max(free) + float(serial_cpu_s)


def write_timings(out_dir: Path, rows: list[dict]) -> Path:
    """Write ``out_dir/timings.csv``: where reproduce spent its wall time and its CPU time.

    One row per notebook (stage ``notebook``), per swept experiment (stage ``sweep``: the summed times of
    its runs at the other seeds, ``runs`` of them, run beside the notebooks or after them), per experiment of
    the claims' robustness samples (stage ``robustness``) and of a study notebook's tasks run in the pool (stage
    ``study``: notebook 15's own row is then the time it took to read and draw them), and per step of
    the run (stage ``run``: ``notebooks`` from the first notebook started to the last finished, ``sweep after
    notebooks``, ``claims ledger``, ``report build``, ``total``, and ``idle wall estimate``:
    :func:`idle_wall_estimate` of the CPU times, in both columns). ``seconds`` are wall times of jobs that may
    have run side by side, so the stages overlap and do not add up to the total; ``cpu_seconds`` are CPU times
    (user + system) of the process and of its children (kernels, Dask workers; :func:`cpu_seconds`), which a
    loaded machine does not inflate: the CPU of ``notebooks`` and ``total`` sums every process of the run.
    """
    import csv

    path = Path(out_dir) / "timings.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(TIMINGS_COLUMNS)
        for r in rows:
            cpu = r.get("cpu_seconds", float("nan"))
            w.writerow([r["stage"], r["name"], f"{float(r['seconds']):.2f}", f"{float(cpu):.2f}",
                        int(r.get("runs", 1))])
    return path


def reproduce(out_dir: str | Path = REPO_ROOT / "reports", fast: bool = False, only: str | None = None,
              seed: int = 0, notebook_dir: Path = NOTEBOOK_DIR, html: bool = True,
              progress: bool = True, n_seeds: int = 1, workers: int = 2, cache_dir: Path | None = None,
              jobs: int = 2, manifest: Mapping[str, Mapping[str, bool]] | None = None) -> int:
    """Run the notebooks and write the reports. Returns a process exit code.

    Parameters
    ----------
    jobs : int
        Notebooks (and seed-sweep runs) executed side by side, each in its own process; 1 runs the
        notebooks one after another in name order.
    n_seeds : int
        With more than 1, the swept experiments of the notebooks (``manifest``) are re-run over seeds
        ``seed .. seed + n_seeds - 1`` and every row of ``README.md`` carries N, the mean and the 95 %
        confidence interval. Each (experiment, seed) result is cached under ``cache_dir`` (default
        :data:`ilocalg.workflow.sweep.DEFAULT_CACHE`), keyed by the code's fingerprint; the base seed's
        result is the one the notebook itself computed.
    workers : int
        Processes for seed-sweep runs that remain after the notebooks (0: in this process, no pool).
    manifest : mapping, optional
        Notebook stem -> {experiment: swept}; default :data:`ilocalg.workflow.manifest.MANIFEST`, where
        every notebook of the project's folder must be listed.
    """
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from multiprocessing import get_context

    from ilocalg.workflow import sweep as sw

    if n_seeds < 1:
        raise ValueError(f"n_seeds must be >= 1, got {n_seeds}")
    if jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    out_dir = Path(out_dir).resolve()
    nbs = discover_notebooks(notebook_dir, only)
    if not nbs:
        print(f"no notebooks match {only!r} in {notebook_dir}", file=sys.stderr)
        return 2
    if manifest is None:
        manifest = MANIFEST if Path(notebook_dir).resolve() == NOTEBOOK_DIR.resolve() else {}
        if manifest:
            for nb in nbs:
                experiments_of(nb.stem)  # every project notebook is in the manifest before anything runs
    cache_dir = Path(cache_dir) if cache_dir is not None else sw.DEFAULT_CACHE
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "figures").mkdir(exist_ok=True)
    (out_dir / "tables").mkdir(exist_ok=True)
    inputs_dir = out_dir / ".inputs"
    t_start, c_start = time.perf_counter(), cpu_seconds()
    t_wall = time.time() - 1.0  # runs cached after this are this reproduce's (file times may be coarse)
    timings = _load_timings(cache_dir)
    stage_rows: list[dict] = []
    sweep_s: dict[str, list[tuple[float, float]]] = {}
    sample_s: dict[str, list[tuple[float, float]]] = {}
    stage_runs: dict[tuple[str, str], int] = {}  # tasks run per (stage, experiment)
    study_s: dict[str, list[tuple[float, float]]] = {}  # per pool job
    study_runs: dict[str, int] = {}  # tasks per study (a study job runs several)
    swept = {nb.stem: [e for e, s in manifest.get(nb.stem, {}).items() if s] for nb in nbs}
    print(f"reproducing {len(nbs)} notebook(s) into {_relative(out_dir, Path.cwd())} (seed={seed}, fast={fast}, "
          f"{jobs} side by side)", flush=True)
    for nb in nbs:
        _clear_outputs(out_dir, nb.stem)

    def params_for(nb: Path) -> dict:
        # relative to the notebook's folder (the kernel's working directory): no absolute paths in the reports
        # DATA_DIR stays the notebook's None (= ilocalg.io.paths.data_dir() in the kernel, which inherits
        # ILOC_DATA_DIR): the reports show no machine's folder layout
        return {"SEED": int(seed), "FAST": bool(fast), "OUT_DIR": _relative(out_dir, nb.parent)}

    def record_for(nb: Path):  # every run at the base seed: the sweep and the claims step read them
        return (str(cache_dir), list(manifest.get(nb.stem, {})))

    failed = None
    if jobs == 1:
        for i, nb in enumerate(nbs, 1):
            print(f"[{i}/{len(nbs)}] {nb.stem}", flush=True)
            r = _notebook_job(nb, out_dir, params_for(nb), html, record_for(nb), progress=progress)
            timings[_timing_key(nb.stem, fast)] = r["seconds"]
            stage_rows.append({"stage": "notebook", "name": nb.stem, "seconds": r["seconds"],
                               "cpu_seconds": r["cpu_seconds"]})
            if r["error"]:
                failed = r["error"]
                break
            print(f"    done in {r['seconds']:.1f} s", flush=True)
    else:
        # every job (notebooks, then the sweep's other seeds) longest first, so the last to finish is short
        extra = []
        if n_seeds > 1 and workers > 0:
            exps = swept_experiments([nb.stem for nb in nbs], manifest=manifest)
            extra = [t for e in exps for t in sw.make_tasks(e, range(seed + 1, seed + n_seeds), fast=fast)
                     if not sw._cache_path(cache_dir, t).exists()]
        # the claims step's robustness samples (fast-mode runs at the base seed) fill the cores beside the notebooks
        samples = [t for t in robustness_tasks([nb.stem for nb in nbs], seed, manifest, n_samples=n_samples_for(fast))
                   if not sw._cache_path(cache_dir, t).exists()] if manifest else []
        # a study notebook's tasks (notebook 15: some 900 short runs, one job per experiment and seed: study_jobs) are
        # jobs of this pool too, run before the notebook (which then reads them from the cache) instead of a second
        # pool of its own inside one job
        study_nbs = [nb.stem for nb in nbs if nb.stem in NOTEBOOK_STUDIES]
        studies = [t for stem in study_nbs for t in notebook_tasks(stem, seed, fast)
                   if not sw._cache_path(cache_dir, t).exists()]
        owner = {e: nb.stem for nb in nbs for e in swept[nb.stem]}
        first = float("inf")  # the study tasks, then their notebook, then everything else longest first
        jobs_list = [(first if nb.stem in study_nbs else timings.get(_timing_key(nb.stem, fast), 60.0), 0, i, "nb", nb)
                     for i, nb in enumerate(nbs)]
        jobs_list += [(first, -1, i, "study", job) for i, job in enumerate(study_jobs(studies))]
        jobs_list += [(len(job) * timings.get(_timing_key(f"sweep:{job[0].experiment}", fast),
                                              timings.get(_timing_key(owner.get(job[0].experiment, ""), fast), 60.0)),
                       1, i, "sweep", job if len(job) > 1 else job[0]) for i, job in enumerate(batch_jobs(extra))]
        jobs_list += [(len(job) * timings.get(f"sample:{job[0].experiment}", 10.0), 2, i, "sample",
                       job if len(job) > 1 else job[0]) for i, job in enumerate(batch_jobs(samples))]
        jobs_list.sort(key=lambda j: (-j[0], j[1], j[2]))
        # one process per core is the parallelism: single-threaded BLAS in the processes and their kernels
        # (as Dask does for its workers), unless the caller set these; the tables are the same bytes
        blas = {k: os.environ.get(k, "1") for k in _BLAS_THREADS}
        # the pool's processes and kernels share one store for this run only (ilocalg.workflow.runstore)
        with run_store(), _environ(**blas), ProcessPoolExecutor(max_workers=jobs,
                                                                 mp_context=get_context("spawn")) as pool:
            futs = {}
            for _, _, _, kind, item in jobs_list:
                if kind == "nb":
                    study_cache = cache_dir if item.stem in study_nbs else None
                    futs[pool.submit(_notebook_job, item, out_dir, params_for(item), html, record_for(item),
                                     study_cache=study_cache)] = (kind, item.stem)
                else:  # a seed-sweep run, a robustness sample or a study job: tasks into the cache
                    futs[pool.submit(_sweep_job, item, cache_dir)] = (
                        kind, (item[0] if isinstance(item, list) else item).experiment)
            n_done = 0
            pending = set(futs)
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for f in done:
                    if f.cancelled():
                        continue
                    r = f.result()
                    kind, name = futs[f]
                    if kind == "sweep":  # per task: a batched experiment's job holds several
                        timings[_timing_key(f"sweep:{name}", fast)] = r["seconds"] / r["runs"]
                        sweep_s.setdefault(name, []).append((r["seconds"], r["cpu_seconds"]))
                        stage_runs[("sweep", name)] = stage_runs.get(("sweep", name), 0) + r["runs"]
                        continue
                    if kind == "sample":
                        timings[f"sample:{name}"] = r["seconds"] / r["runs"]
                        sample_s.setdefault(name, []).append((r["seconds"], r["cpu_seconds"]))
                        stage_runs[("robustness", name)] = stage_runs.get(("robustness", name), 0) + r["runs"]
                        continue
                    if kind == "study":
                        study_s.setdefault(name, []).append((r["seconds"], r["cpu_seconds"]))
                        study_runs[name] = study_runs.get(name, 0) + r["runs"]
                        continue
                    n_done += 1
                    timings[_timing_key(name, fast)] = r["seconds"]
                    stage_rows.append({"stage": "notebook", "name": name, "seconds": r["seconds"],
                                       "cpu_seconds": r["cpu_seconds"]})
                    if r["error"] and failed is None:
                        failed = r["error"]
                        for other in pending:
                            other.cancel()  # jobs not yet started never run
                    elif not r["error"]:
                        print(f"[{n_done}/{len(nbs)}] {name} done in {r['seconds']:.1f} s", flush=True)
    t_notebooks, c_notebooks = time.perf_counter() - t_start, cpu_seconds() - c_start
    job_cpu = [r["cpu_seconds"] for r in stage_rows] + [c for d in (sweep_s, sample_s, study_s) for v in d.values()
                                                         for _, c in v]
    stage_rows.sort(key=lambda r: r["name"])
    for stage_name, runs in (("sweep", sweep_s), ("robustness", sample_s), ("study", study_s)):
        stage_rows += [{"stage": stage_name, "name": e, "seconds": sum(w for w, _ in v),
                        "cpu_seconds": sum(c for _, c in v),
                        "runs": study_runs[e] if runs is study_s else stage_runs.get((stage_name, e), len(v))}
                       for e, v in sorted(runs.items())]
    stage_rows.append({"stage": "run", "name": "notebooks", "seconds": t_notebooks, "cpu_seconds": c_notebooks})

    def stage(name: str, t0: float, c0: float) -> None:
        stage_rows.append({"stage": "run", "name": name, "seconds": time.perf_counter() - t0,
                           "cpu_seconds": cpu_seconds() - c0})
    try:
        _timings_path(cache_dir).parent.mkdir(parents=True, exist_ok=True)
        _timings_path(cache_dir).write_text(json.dumps(timings, indent=1, sort_keys=True) + "\n")
    except OSError:
        pass
    if failed:
        print(f"FAILED {failed}", file=sys.stderr, flush=True)
        write_timings(out_dir, stage_rows)
        return 1
    inputs = []
    if inputs_dir.is_dir():
        for f in sorted(inputs_dir.glob("*.txt")):
            inputs += [line for line in f.read_text().splitlines() if line]
    summary = None
    if n_seeds > 1:
        t0, c0 = time.perf_counter(), cpu_seconds()
        code, summary = sweep_experiments(nbs, out_dir, seed, n_seeds, fast, workers, progress, cache_dir, manifest,
                                          since=t_wall)
        stage("sweep after notebooks", t0, c0)
        if code:
            write_timings(out_dir, stage_rows)
            return code
    from ilocalg.workflow.claims_step import claims_step  # reports/claims.csv, read by the pages below
    t0, c0 = time.perf_counter(), cpu_seconds()
    failed = claims_step(out_dir, [nb.stem for nb in nbs], seed, n_seeds, fast, workers, cache_dir, progress, manifest)
    stage("claims ledger", t0, c0)
    if failed:
        write_timings(out_dir, stage_rows)
        return 1
    t0, c0 = time.perf_counter(), cpu_seconds()
    build_readme(out_dir, seed=seed, fast=fast, sweep_summary=summary, n_seeds=n_seeds)
    build_index(out_dir, seed=seed, fast=fast, sweep_summary=summary, n_seeds=n_seeds, notebook_dir=notebook_dir)
    write_provenance(out_dir, REPO_ROOT, seed=seed, fast=fast, inputs=inputs, notebooks=[p.stem for p in nbs],
                     n_seeds=n_seeds)
    stage("report build", t0, c0)
    stage("total", t_start, c_start)
    serial = sum(r["cpu_seconds"] for r in stage_rows
                 if r["stage"] == "run" and r["name"] not in ("notebooks", "total"))
    est = idle_wall_estimate(job_cpu, jobs, serial)
    stage_rows.append({"stage": "run", "name": "idle wall estimate", "seconds": est, "cpu_seconds": est})
    write_timings(out_dir, stage_rows)
    print(f"wrote index.html, README.md and provenance.json in {_relative(out_dir, Path.cwd())} "
          f"({time.perf_counter() - t_start:.0f} s in all)", flush=True)
    return 0
