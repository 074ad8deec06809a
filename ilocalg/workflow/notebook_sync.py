"""Keep ``notebooks/NN_topic.py`` (jupytext py:percent, the reviewed source) and its ``.ipynb`` paired.

The ``.py`` file is the source of truth; ``--sync`` writes the ``.ipynb`` from it with no outputs;
``--check`` fails when a pair is missing, out of step or an ``.ipynb`` holds outputs.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["sync", "check"]


def _pairs(notebook_dir: Path):
    return sorted(Path(notebook_dir).glob("[0-9][0-9]_*.py"))


def _from_py(py: Path):
    import jupytext

    nb = jupytext.read(py)
    nb.metadata = {
        "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
        "jupytext": {"formats": "ipynb,py:percent"},
        "language_info": {"name": "python"},
    }
    # Cell ids from position and content, so regenerating an unchanged notebook changes no byte.
    for i, cell in enumerate(nb.cells):
        cell.id = hashlib.sha1(f"{i}:{cell.cell_type}:{cell.source}".encode()).hexdigest()[:12]
    return nb


def sync(notebook_dir: Path) -> list[Path]:
    """Write every ``.ipynb`` from its ``.py`` (outputs stripped); returns the written paths."""
    import jupytext

    out = []
    for py in _pairs(notebook_dir):
        ipynb = py.with_suffix(".ipynb")
        jupytext.write(_from_py(py), ipynb, fmt="ipynb")
        out.append(ipynb)
    return out


def check(notebook_dir: Path) -> list[str]:
    """Problems with the notebook pairs (empty when all is well)."""
    import nbformat

    problems = []
    pys = _pairs(notebook_dir)
    for ipynb in sorted(Path(notebook_dir).glob("[0-9][0-9]_*.ipynb")):
        if not ipynb.with_suffix(".py").exists():
            problems.append(f"{ipynb.name} has no paired .py (py:percent) file")
    for py in pys:
        ipynb = py.with_suffix(".ipynb")
        if not ipynb.exists():
            problems.append(f"{py.name} has no paired .ipynb; run `make notebooks`")
            continue
        stored = nbformat.read(ipynb, as_version=4)
        expect = _from_py(py)
        if [c.source for c in stored.cells] != [c.source for c in expect.cells]:
            problems.append(f"{ipynb.name} is out of step with {py.name}; run `make notebooks`")
        for c in stored.cells:
            if c.cell_type == "code" and (c.get("outputs") or c.get("execution_count")):
                problems.append(f"{ipynb.name} holds outputs; strip them (`make notebooks`)")
                break
    return problems
