"""`make lab`: the file browser lists each notebook once (its .py), and the .py opens with a kernel."""

from __future__ import annotations

import fnmatch
import json

from ilocalg.io.paths import REPO_ROOT
from ilocalg.workflow.notebook_sync import kernelspec


def test_file_browser_hides_the_ipynb_side_of_each_pair_only():
    cfg = json.loads((REPO_ROOT / ".jupyter" / "jupyter_server_config.json").read_text())
    globs = cfg["ContentsManager"]["hide_globs"]
    nbs = sorted((REPO_ROOT / "notebooks").glob("[0-9][0-9]_*"))
    shown = [p.name for p in nbs if not any(fnmatch.fnmatch(p.name, g) for g in globs)]
    assert shown == sorted(p.name for p in nbs if p.suffix == ".py") and len(shown) >= 16
    assert "__pycache__" in globs  # jupyter_server's own defaults are kept
    for name in ("runner.py", "README.md", "index.html", "environment.txt"):
        assert not any(fnmatch.fnmatch(name, g) for g in globs)


def test_lab_opens_the_py_files_as_notebooks_with_the_project_kernel():
    over = json.loads((REPO_ROOT / ".jupyter" / "labconfig" / "default_setting_overrides.json").read_text())
    assert over["@jupyterlab/docmanager-extension:plugin"]["defaultViewers"]["python"] == "Jupytext Notebook"
    import nbformat

    for ipynb in sorted((REPO_ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")):  # jupytext reads the pair's metadata
        assert nbformat.read(ipynb, as_version=4).metadata["kernelspec"] == kernelspec(), ipynb.name
