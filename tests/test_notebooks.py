"""Every notebook runs in fast mode through the reproduce runner; same seed -> byte-identical tables.

This is the suite's end-to-end check: the runner executes notebooks/NN_*.ipynb exactly as
`make reproduce` does (with FAST=True) into a temporary reports folder.
"""

from __future__ import annotations

import filecmp
import json

import nbformat
import pytest

from ilocalg.workflow.runner import NOTEBOOK_DIR, discover_notebooks, reproduce

pytestmark = pytest.mark.notebooks

NOTEBOOKS = discover_notebooks()


@pytest.fixture(scope="module")
def fast_reports(tmp_path_factory):
    out = tmp_path_factory.mktemp("reports_a")
    code = reproduce(out, fast=True, seed=0, html=False, progress=False)
    return code, out


def test_there_are_notebooks():
    assert NOTEBOOKS, f"no notebooks in {NOTEBOOK_DIR}"


def test_all_notebooks_run_in_fast_mode(fast_reports):
    code, out = fast_reports
    assert code == 0, "a notebook failed; see the output above"
    for nb in NOTEBOOKS:
        assert (out / nb.name).exists(), f"{nb.name} was not executed"
    assert (out / "README.md").exists()
    prov = json.loads((out / "provenance.json").read_text())
    assert prov["seed"] == 0 and prov["fast"] is True
    assert prov["notebooks"] == [nb.stem for nb in NOTEBOOKS]


def test_every_notebook_has_parameters_cell_and_writes_a_table(fast_reports):
    code, out = fast_reports
    assert code == 0
    for nb in NOTEBOOKS:
        cells = nbformat.read(nb, as_version=4).cells
        assert any("parameters" in c.metadata.get("tags", []) for c in cells), f"{nb.name}: no parameters cell"
        assert list((out / "tables").glob(f"{nb.stem}__*.csv")), f"{nb.name} wrote no table"


def test_same_seed_gives_byte_identical_tables(fast_reports, tmp_path):
    code, out_a = fast_reports
    assert code == 0
    out_b = tmp_path / "reports_b"
    assert reproduce(out_b, fast=True, seed=0, html=False, progress=False) == 0
    a = sorted(p.name for p in (out_a / "tables").glob("*.csv"))
    b = sorted(p.name for p in (out_b / "tables").glob("*.csv"))
    assert a == b and a
    _, mismatch, errors = filecmp.cmpfiles(out_a / "tables", out_b / "tables", a, shallow=False)
    assert not mismatch and not errors, f"tables differ between two runs with the same seed: {mismatch}"


def test_failing_notebook_stops_the_run_with_its_error(tmp_path, capsys):
    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("SEED = 0", metadata={"tags": ["parameters"]}),
                nbformat.v4.new_code_cell("raise ValueError('boom in cell')")]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, nbdir / "01_fails.ipynb")
    nbformat.write(nb, nbdir / "02_never_runs.ipynb")
    code = reproduce(tmp_path / "out", notebook_dir=nbdir, html=False, progress=False)
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
    (nbdir / "01_fake.py").write_text("from ilocalg.experiments import fake_exp\n")
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
                     cache_dir=tmp_path / "cache")
    assert code == 0
    summary = pd.read_csv(out / "sweeps" / "summary.csv")
    assert summary["n"].tolist() == [3]
    assert summary["mean"].iloc[0] == pytest.approx(1.1)
    readme = (out / "README.md").read_text()
    assert "N = 3" in readme
    row = next(line for line in readme.splitlines() if line.startswith("| Fake paper"))
    assert "| 3 | 1.1 |" in row and "inside CI" in row
    assert json.loads((out / "provenance.json").read_text())["n_seeds_for_intervals"] == 3


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
