"""Tests of ilocalg.workflow.manifest: one line per notebook, every experiment module listed."""

import importlib
import pkgutil

import pytest

import ilocalg.experiments
from ilocalg.workflow import manifest
from ilocalg.workflow.runner import NOTEBOOK_DIR


def _experiment_modules() -> set[str]:
    """Modules under ilocalg.experiments with a run() function (helpers without one are not experiments)."""
    names = set()
    for info in pkgutil.iter_modules(ilocalg.experiments.__path__):
        mod = importlib.import_module(f"ilocalg.experiments.{info.name}")
        if callable(getattr(mod, "run", None)):
            names.add(info.name)
    return names


def test_manifest_lists_every_notebook_on_disk():
    on_disk = {p.stem for p in NOTEBOOK_DIR.glob("[0-9][0-9]_*.py")}
    assert on_disk == set(manifest.MANIFEST)
    assert {p.stem for p in NOTEBOOK_DIR.glob("[0-9][0-9]_*.ipynb")} == set(manifest.MANIFEST)


def test_manifest_lists_every_experiment_module_and_nothing_else():
    listed = {e for exps in manifest.MANIFEST.values() for e in exps}
    assert listed == _experiment_modules()


def test_each_listed_experiment_is_imported_by_its_notebook():
    for stem, exps in manifest.MANIFEST.items():
        src = (NOTEBOOK_DIR / f"{stem}.py").read_text()
        for e in exps:
            assert e in src, f"{stem}.py does not mention {e}"


def test_an_experiment_is_swept_in_at_most_one_notebook_and_studies_never():
    swept = [e for exps in manifest.MANIFEST.values() for e, s in exps.items() if s]
    assert len(swept) == len(set(swept))
    assert not [e for e in swept if e.startswith("study_")]
    assert "data_tour" not in swept


def test_swept_experiments_in_notebook_order_and_unknown_notebook_named():
    assert manifest.swept_experiments(["10_pso_k_factor", "05_pdr_heading_trajectory"]) == [
        "pso_k_factor", "pdr_heading_trajectory"]
    assert manifest.swept_experiments(["06_pdr_real_steps"]) == []
    with pytest.raises(ValueError, match="99_new.*MANIFEST"):
        manifest.experiments_of("99_new")


def test_cost_hints_name_only_known_notebooks_and_swept_experiments():
    swept = set(manifest.swept_experiments(manifest.notebook_stems()))
    for key, seconds in manifest.COST_S.items():
        assert seconds > 0
        if key.startswith("sweep:"):
            assert key[len("sweep:"):] in swept, key
        else:
            assert key in manifest.MANIFEST, key


def test_sweep_kwargs_name_swept_experiments_and_keywords_of_their_run():
    """Each experiment's own tests check that its SWEEP_KWARGS leave the long results unchanged; here: a misspelt
    experiment or keyword would be silently ignored or fail every sweep task."""
    import inspect

    swept = set(manifest.swept_experiments(manifest.notebook_stems()))
    for exp, kwargs in manifest.SWEEP_KWARGS.items():
        assert exp in swept, exp
        params = inspect.signature(importlib.import_module(f"ilocalg.experiments.{exp}").run).parameters
        assert set(kwargs) <= set(params), (exp, set(kwargs) - set(params))


def test_measured_worlds_notebook_is_listed_and_not_swept():
    assert manifest.experiments_of("16_measured_worlds") == ["measured_worlds"]
    assert "measured_worlds" not in manifest.swept_experiments(["16_measured_worlds"])
