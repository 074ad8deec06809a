"""The reproduce runner on small notebooks: failures, seed sweeps, reruns, figures, side by side runs. Separate from
tests/test_notebooks.py, whose module fixture runs every notebook (and checks their figures), so that a parallel run
(``make test``, one file per worker) can run these beside it.
"""

from __future__ import annotations

import json
import os
import sys

import nbformat
import pytest

from ilocalg.io.paths import REPO_ROOT
from ilocalg.workflow.runner import NOTEBOOK_DIR, reproduce

pytestmark = pytest.mark.notebooks

def test_failing_notebook_stops_the_run_with_its_error(tmp_path, capsys):
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("SEED = 0", metadata={"tags": ["parameters"]}),
                nbformat.v4.new_code_cell("raise ValueError('boom in cell')")]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, nbdir / "01_fails.ipynb")
    nbformat.write(nb, nbdir / "02_never_runs.ipynb")
    code = reproduce(tmp_path / "out", notebook_dir=nbdir, html=False, progress=False, jobs=1)
    assert code == 1
    err = capsys.readouterr().err
    assert "01_fails.ipynb" in err and "ValueError" in err and "boom in cell" in err
    assert not (tmp_path / "out" / "02_never_runs.ipynb").exists()


def test_seed_sweep_adds_n_mean_and_interval_to_every_row(tmp_path, monkeypatch):
    """reproduce(n_seeds=N) re-runs the notebooks' experiments over seeds and the README shows N and the CI."""
    import sys
    import types

    import pandas as pd

    from ilocalg.papers import comparison_table, paper_ref

    fake = types.ModuleType("ilocalg.experiments.fake_exp")

    def run(seed=0, fast=False):
        val = 1.0 + 0.1 * seed
        return {"comparison": comparison_table([paper_ref("Fake paper", "Fig 1", "error", 1.05, val, "m")])}

    fake.run = run
    monkeypatch.setitem(sys.modules, "ilocalg.experiments.fake_exp", fake)
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_code_cell("SEED = 0\nOUT_DIR = None", metadata={"tags": ["parameters"]}),
        nbformat.v4.new_code_cell(
            "from ilocalg.papers import paper_ref\nfrom ilocalg.workflow.reporting import Report\n"
            "Report(OUT_DIR, '01_fake').compare([paper_ref('Fake paper', 'Fig 1', 'error', 1.05, 1.0, 'm')])"),
    ]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, nbdir / "01_fake.ipynb")
    out = tmp_path / "out"
    # workers=0 runs the sweep in this process (the monkeypatched module is visible there)
    code = reproduce(out, notebook_dir=nbdir, html=False, progress=False, n_seeds=3, workers=0,
                     cache_dir=tmp_path / "cache", manifest={"01_fake": {"fake_exp": True}})
    assert code == 0
    summary = pd.read_csv(out / "sweeps" / "summary.csv")
    assert summary["n"].tolist() == [3]
    assert summary["mean"].iloc[0] == pytest.approx(1.1)
    readme = (out / "README.md").read_text()
    assert "N = 3" in readme
    row = next(line for line in readme.splitlines() if line.startswith("| Fake paper"))
    assert "| 3 | 1.1 |" in row and "inside CI" in row
    assert json.loads((out / "provenance.json").read_text())["n_seeds_for_intervals"] == 3
    timings = pd.read_csv(out / "timings.csv")  # where the wall time went, written by reproduce itself
    assert list(timings.columns) == ["stage", "name", "seconds", "cpu_seconds", "runs"]
    got = set(zip(timings["stage"], timings["name"], strict=True))
    assert {("notebook", "01_fake"), ("run", "notebooks"), ("run", "sweep after notebooks"), ("run", "report build"),
            ("run", "total"), ("run", "idle wall estimate")} <= got
    assert (timings["seconds"] >= 0).all() and (timings["cpu_seconds"] >= 0).all()
    cpu = timings.set_index(["stage", "name"])["cpu_seconds"]
    # the kernel (a child process) counts: starting it and importing ilocalg alone costs well over 0.2 s of CPU
    assert cpu[("notebook", "01_fake")] > 0.2
    assert cpu[("run", "total")] >= cpu[("notebook", "01_fake")]


def test_idle_wall_estimate_places_jobs_longest_first_on_the_free_core():
    from ilocalg.workflow.runner import idle_wall_estimate

    assert idle_wall_estimate([3, 3, 2, 2, 2], 2) == pytest.approx(7.0)  # 3+2+2 | 3+2
    assert idle_wall_estimate([10, 1, 1], 2, serial_cpu_s=5) == pytest.approx(15.0)
    assert idle_wall_estimate([4, 4], 1) == pytest.approx(8.0)
    with pytest.raises(ValueError, match="slots"):
        idle_wall_estimate([1], 0)


def test_rerun_replaces_a_notebooks_old_outputs(tmp_path):
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("OUT_DIR = None", metadata={"tags": ["parameters"]}),
                nbformat.v4.new_code_cell("import pandas as pd\nfrom ilocalg.workflow.reporting import Report\n"
                                          "Report(OUT_DIR, '01_x').table(pd.DataFrame({'a': [1]}), 'new')")]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, nbdir / "01_x.ipynb")
    out = tmp_path / "out"
    (out / "tables").mkdir(parents=True)
    (out / "tables" / "01_x__stale.csv").write_text("a\n1\n")
    (out / "tables" / "02_other__kept.csv").write_text("a\n1\n")
    assert reproduce(out, notebook_dir=nbdir, html=False, progress=False) == 0
    names = sorted(p.name for p in (out / "tables").glob("*.csv"))
    assert names == ["01_x__new.csv", "02_other__kept.csv"]


def _nb(cells: list[str]) -> nbformat.NotebookNode:
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("SEED = 0\nFAST = False\nOUT_DIR = None\nDATA_DIR = None",
                                          metadata={"tags": ["parameters"]})]
    nb.cells += [nbformat.v4.new_code_cell(c) for c in cells]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    return nb


def _png_cells(path) -> list[int]:
    nb = nbformat.read(path, as_version=4)
    return [i for i, c in enumerate(nb.cells) if c.cell_type == "code"
            and any("image/png" in o.get("data", {}) for o in c.get("outputs", []))]


def test_figures_are_inline_after_a_styled_one_and_saved_and_paths_are_relative(tmp_path):
    """Figures appear in the executed notebook and its HTML (a plain figure after a styled one too), are
    saved as PNG + PDF, and the injected parameters hold no absolute path."""
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nbformat.write(_nb([
        "import matplotlib.pyplot as plt\nimport ilocviz\n"
        "with ilocviz.style():\n    fig, ax = plt.subplots()\n    ax.plot([0, 1], [0, 1])\n"
        "    ilocviz.savefig(fig, '01_plots_line', OUT_DIR)",
        "fig, ax = plt.subplots()\nax.plot([1, 0])",
        "print(OUT_DIR, DATA_DIR)",
    ]), nbdir / "01_plots.ipynb")
    out = tmp_path / "out"
    assert reproduce(out, notebook_dir=nbdir, html=True, progress=False, jobs=1) == 0
    cells = nbformat.read(out / "01_plots.ipynb", as_version=4).cells
    assert [i for i, c in enumerate(cells) if "plt.subplots" in c.source] == _png_cells(out / "01_plots.ipynb")
    assert (out / "01_plots.html").read_text().count("<img") == 2
    assert sorted(p.name for p in (out / "figures").iterdir()) == ["01_plots_line.pdf", "01_plots_line.png"]
    text = (out / "01_plots.ipynb").read_text()
    assert str(tmp_path) not in text and str(NOTEBOOK_DIR.parent) not in text
    injected = next(c.source for c in cells if "injected-parameters" in c.metadata.get("tags", []))
    assert 'OUT_DIR = "../out"' in injected
    assert str(tmp_path) not in (out / "01_plots.html").read_text()


def test_side_by_side_run_reuses_the_notebooks_own_base_seed_runs(tmp_path, monkeypatch):
    """jobs=2: two notebooks in parallel; the sweep's base-seed run is the one the notebook's kernel made
    (the sweep cache holds it before the sweep starts), the other seeds ran in the same pool."""
    import os

    import pandas as pd

    from ilocalg.workflow import sweep as sw

    root = NOTEBOOK_DIR.parent
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")]))
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    for stem in ("01_a", "02_b"):
        nbformat.write(_nb([
            "import importlib\nfrom ilocalg.workflow.reporting import Report\n"
            f"report = Report(OUT_DIR, '{stem}')\ntoy = importlib.import_module('tests.sweep_toy')\n"
            "tables = toy.run(seed=SEED, fast=FAST)\nreport.compare(tables['comparison'].to_dict('records'))",
        ]), nbdir / f"{stem}.ipynb")
    cache = tmp_path / "cache"
    out = tmp_path / "out"
    manifest = {"01_a": {"tests.sweep_toy": True}, "02_b": {}}
    assert reproduce(out, notebook_dir=nbdir, html=False, progress=False, n_seeds=3, workers=2, jobs=2,
                     cache_dir=cache, manifest=manifest) == 0
    recorded = sw._cache_path(cache, sw.SweepTask("tests.sweep_toy", (), 0, False))
    assert recorded.exists()
    expected = sw.run_task(sw.SweepTask("tests.sweep_toy", (), 0, False))
    pd.testing.assert_frame_equal(pd.read_parquet(recorded), expected)
    summary = pd.read_csv(out / "sweeps" / "summary.csv")
    assert set(summary["n"]) == {3}
    assert (out / "01_a.ipynb").exists() and (out / "02_b.ipynb").exists()


def test_side_by_side_failure_is_reported_and_exits_1(tmp_path, capsys):
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nbformat.write(_nb(["raise ValueError('boom side by side')"]), nbdir / "01_fails.ipynb")
    nbformat.write(_nb(["x = 1"]), nbdir / "02_ok.ipynb")
    assert reproduce(tmp_path / "out", notebook_dir=nbdir, html=False, progress=False, jobs=2) == 1
    err = capsys.readouterr().err
    assert "01_fails.ipynb" in err and "boom side by side" in err
    assert not (tmp_path / "out" / "README.md").exists()


def test_batch_jobs_give_a_batched_experiments_tasks_one_job():
    """Seed-sweep runs and robustness samples: one pool job per task, except one job for all the tasks of an
    experiment with run_many (in their order)."""
    from ilocalg.workflow import sweep as sw
    from ilocalg.workflow.runner import batch_jobs

    tasks = sw.make_tasks("tests.sweep_toy", range(2)) + sw.make_tasks("tests.sweep_toy_batched", range(3))
    tasks.insert(1, tasks.pop())  # interleaved
    jobs = batch_jobs(tasks)
    assert [len(j) for j in jobs] == [1, 3, 1]
    assert [t.seed for t in jobs[1]] == [2, 0, 1] and {t.experiment for t in jobs[1]} == {"tests.sweep_toy_batched"}
    assert batch_jobs([]) == []


def test_study_jobs_group_a_study_notebooks_tasks_by_experiment_and_seed():
    """The pool runs a study notebook's tasks as one job per (experiment, seed), and a study with ``run_many`` as one
    job: every task once, in its order."""
    from ilocalg.workflow import sweep as sw
    from ilocalg.workflow.runner import study_jobs
    from ilocalg.workflow.studies import notebook_tasks

    tasks = notebook_tasks("15_sweep_studies", 0, True)
    jobs = study_jobs(tasks)
    assert sorted(t.key for j in jobs for t in j) == sorted(t.key for t in tasks)
    together = {t.experiment for t in tasks if sw.batched(t.experiment)}
    assert together == {"study_ins_window"}
    assert len(jobs) == len({(t.experiment, t.seed) for t in tasks if t.experiment not in together}) + len(together)
    for j in jobs:
        if j[0].experiment in together:
            assert {t.experiment for t in j} == {j[0].experiment} and len({t.seed for t in j}) == len(j) > 1
        else:
            assert len({(t.experiment, t.seed) for t in j}) == 1
        pos = [tasks.index(t) for t in j]
        assert pos == sorted(pos)


def test_jsonschema_is_imported_without_the_iri_grammars_and_nbformat_still_validates():
    """In a fresh process: jsonschema without rfc3987_syntax's grammars; nbformat still rejects an invalid
    notebook; rfc3987_syntax (when installed) imports normally afterwards."""
    import subprocess

    code = """
import importlib.util, sys
from ilocalg.workflow.runner import _import_jsonschema_lean
_import_jsonschema_lean()
assert "jsonschema" in sys.modules and "rfc3987_syntax" not in sys.modules
import nbformat
nb = nbformat.v4.new_notebook()
nbformat.validate(nb)
nb.cells = [{"cell_type": "code", "source": 1}]
try:
    nbformat.validate(nb)
except nbformat.ValidationError:
    pass
else:
    raise SystemExit("an invalid notebook passed")
if importlib.util.find_spec("rfc3987_syntax") is not None:
    import rfc3987_syntax  # noqa: F401
print("ok")
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO_ROOT,
                       env={**os.environ, "PYTHONPATH": str(REPO_ROOT)})
    assert r.returncode == 0 and r.stdout.strip() == "ok", r.stderr
