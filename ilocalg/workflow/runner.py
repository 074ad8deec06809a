"""The reproduce runner: execute every notebook with parameters and write ``reports/``.

``python -m ilocalg reproduce [--fast] [--only PATTERN] [--seed N]`` executes ``notebooks/NN_*.ipynb``
in order with papermill (each notebook's cell tagged ``parameters`` receives ``SEED``, ``FAST``,
``OUT_DIR`` and ``DATA_DIR``), shows a progress bar per notebook, exports each executed notebook to
``reports/<name>.ipynb`` and ``.html``, then builds ``reports/README.md`` from the comparison tables
the notebooks wrote and ``reports/provenance.json``. The first failing notebook stops the run with
its failing cell's error and a non-zero exit code.
"""

from __future__ import annotations

import fnmatch
import os
import sys
import time
from pathlib import Path

from ilocalg.io.paths import REPO_ROOT, data_dir
from ilocalg.workflow.manifest import experiments_of, swept_experiments
from ilocalg.workflow.reporting import build_readme, write_provenance, write_table

__all__ = ["NOTEBOOK_DIR", "discover_notebooks", "execute_notebook", "reproduce", "NotebookFailed",
           "sweep_experiments"]

NOTEBOOK_DIR = REPO_ROOT / "notebooks"


class NotebookFailed(RuntimeError):
    """A notebook raised; carries the notebook name and the failing cell's error."""


def discover_notebooks(notebook_dir: Path = NOTEBOOK_DIR, only: str | None = None) -> list[Path]:
    """Notebooks ``NN_*.ipynb`` in name order; ``only`` is a glob or substring on the stem."""
    nbs = sorted(p for p in Path(notebook_dir).glob("[0-9][0-9]_*.ipynb"))
    if only:
        pats = [p.strip() for p in only.split(",") if p.strip()]
        nbs = [p for p in nbs if any(fnmatch.fnmatch(p.stem, pat) or pat in p.stem for pat in pats)]
    return nbs


def execute_notebook(nb: Path, out_dir: Path, parameters: dict, progress: bool = True,
                     html: bool = True) -> Path:
    """Execute one notebook with papermill into ``out_dir/<name>.ipynb`` (+ ``.html``)."""
    import papermill as pm  # heavy; imported only when notebooks run

    out_nb = out_dir / nb.name
    try:
        pm.execute_notebook(
            str(nb),
            str(out_nb),
            parameters=parameters,
            kernel_name="python3",
            progress_bar=progress,
            cwd=str(nb.parent),
            log_output=False,
        )
    except pm.PapermillExecutionError as exc:
        raise NotebookFailed(
            f"{nb.name}: cell {exc.exec_count} raised {exc.ename}: {exc.evalue}\n"
            f"executed copy with the traceback: {out_nb}"
        ) from None
    if html:
        import nbformat
        from nbconvert import HTMLExporter

        body, _ = HTMLExporter().from_notebook_node(nbformat.read(out_nb, as_version=4))
        out_nb.with_suffix(".html").write_text(body)
    return out_nb


def sweep_experiments(nbs: list[Path], out_dir: Path, seed: int, n_seeds: int, fast: bool, workers: int,
                      progress: bool, cache_dir=None) -> tuple[int, object]:
    """Re-run the notebooks' swept experiments (:data:`ilocalg.workflow.manifest.MANIFEST`) over ``n_seeds``
    seeds; write ``sweeps/summary`` and return it."""
    from ilocalg.workflow import sweep as sw

    exps = swept_experiments([nb.stem for nb in nbs])
    if not exps:
        return 0, None
    tasks = [t for e in exps for t in sw.make_tasks(e, range(seed, seed + n_seeds), fast=fast)]
    print(f"confidence intervals: {len(exps)} experiment(s) x {n_seeds} seeds on {workers} worker(s)", flush=True)
    res = sw.sweep(tasks, workers=workers, cache_dir=cache_dir or sw.DEFAULT_CACHE, progress=progress)
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


def reproduce(out_dir: str | Path = REPO_ROOT / "reports", fast: bool = False, only: str | None = None,
              seed: int = 0, notebook_dir: Path = NOTEBOOK_DIR, html: bool = True,
              progress: bool = True, n_seeds: int = 1, workers: int = 2, cache_dir: Path | None = None) -> int:
    """Run the notebooks and write the reports. Returns a process exit code.

    With ``n_seeds`` > 1 the experiments the notebooks call are re-run over seeds
    ``seed .. seed + n_seeds - 1`` on a Dask LocalCluster of ``workers`` processes, and every row
    of ``README.md`` carries N, the mean and the 95 % confidence interval. Each (experiment, seed)
    result is cached under ``cache_dir`` (default :data:`ilocalg.workflow.sweep.DEFAULT_CACHE`), keyed by the
    code's fingerprint, so a re-run after an interruption resumes.
    """
    if n_seeds < 1:
        raise ValueError(f"n_seeds must be >= 1, got {n_seeds}")
    out_dir = Path(out_dir).resolve()
    nbs = discover_notebooks(notebook_dir, only)
    if not nbs:
        print(f"no notebooks match {only!r} in {notebook_dir}", file=sys.stderr)
        return 2
    for nb in nbs:
        experiments_of(nb.stem)  # every notebook is in the manifest before anything runs
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "figures").mkdir(exist_ok=True)
    (out_dir / "tables").mkdir(exist_ok=True)
    inputs_dir = out_dir / ".inputs"
    params = {"SEED": int(seed), "FAST": bool(fast), "OUT_DIR": str(out_dir), "DATA_DIR": str(data_dir())}
    # Kernels inherit the environment: headless plots.
    os.environ.setdefault("MPLBACKEND", "Agg")
    print(f"reproducing {len(nbs)} notebook(s) into {out_dir} (seed={seed}, fast={fast})", flush=True)
    for i, nb in enumerate(nbs, 1):
        t0 = time.perf_counter()
        print(f"[{i}/{len(nbs)}] {nb.stem}", flush=True)
        _clear_outputs(out_dir, nb.stem)
        try:
            execute_notebook(nb, out_dir, params, progress=progress, html=html)
        except NotebookFailed as exc:
            print(f"FAILED {exc}", file=sys.stderr, flush=True)
            return 1
        print(f"    done in {time.perf_counter() - t0:.1f} s", flush=True)
    inputs = []
    if inputs_dir.is_dir():
        for f in sorted(inputs_dir.glob("*.txt")):
            inputs += [line for line in f.read_text().splitlines() if line]
    summary = None
    if n_seeds > 1:
        code, summary = sweep_experiments(nbs, out_dir, seed, n_seeds, fast, workers, progress, cache_dir)
        if code:
            return code
    build_readme(out_dir, seed=seed, fast=fast, sweep_summary=summary, n_seeds=n_seeds)
    write_provenance(out_dir, REPO_ROOT, seed=seed, fast=fast, inputs=inputs, notebooks=[p.stem for p in nbs],
                     n_seeds=n_seeds)
    print(f"wrote {out_dir / 'README.md'} and {out_dir / 'provenance.json'}", flush=True)
    return 0
