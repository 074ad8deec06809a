"""Keep ``notebooks/NN_topic.py`` (jupytext py:percent, the reviewed source) and its ``.ipynb`` paired.

The ``.py`` file is the source of truth; ``--sync`` writes the ``.ipynb`` from it with no outputs and
the metadata JupyterLab itself writes (the kernel's ``kernelspec`` and ``language_info``, jupytext's
filters), so an unchanged notebook opens unmodified; ``--check`` fails when a pair is missing, out of
step, holds outputs or carries other metadata.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["sync", "check", "notebook_metadata", "kernel_language_info", "kernelspec", "JUPYTEXT_METADATA"]


def _pairs(notebook_dir: Path):
    return sorted(Path(notebook_dir).glob("[0-9][0-9]_*.py"))


def kernel_language_info() -> dict:
    """``language_info`` exactly as the project's Python kernel (ipykernel) reports it on start.

    JupyterLab writes the kernel's ``language_info`` into an open notebook; stored as the kernel gives
    it, an unchanged notebook does not show as modified on open (with the Python of environment.txt).
    """
    import copy

    from ipykernel.ipkernel import IPythonKernel

    return copy.deepcopy(dict(IPythonKernel.language_info))


def kernelspec() -> dict:
    """``kernelspec`` as JupyterLab writes it for ipykernel's ``python3`` kernel (from its kernel.json)."""
    from ipykernel.kernelspec import KERNEL_NAME, get_kernel_dict

    spec = get_kernel_dict()
    return {"display_name": spec["display_name"], "language": spec["language"], "name": KERNEL_NAME}


#: Notebook-level jupytext metadata: the filters of jupytext.toml, also inside each notebook, so any
#: jupytext (command line, JupyterLab) renders the ``.ipynb`` exactly as its ``.py``.
JUPYTEXT_METADATA = {"formats": "ipynb,py:percent", "notebook_metadata_filter": "-all",
                     "cell_metadata_filter": "tags,-all"}


def notebook_metadata() -> dict:
    """Metadata of every stored ``.ipynb``: what JupyterLab itself writes on save with the project's
    kernel, so an unchanged notebook does not show as modified when it opens."""
    return {"kernelspec": kernelspec(), "jupytext": dict(JUPYTEXT_METADATA),
            "language_info": kernel_language_info()}


def _from_py(py: Path):
    import jupytext

    nb = jupytext.read(py)
    nb.metadata = notebook_metadata()
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
        try:
            stored = nbformat.read(ipynb, as_version=4)
        except (nbformat.reader.NotJSONError, ValueError) as exc:  # e.g. merge-conflict markers
            problems.append(f"{ipynb.name} is not a readable notebook ({str(exc).splitlines()[0][:80]}); "
                            "run `make notebooks`")
            continue
        expect = _from_py(py)
        if [c.source for c in stored.cells] != [c.source for c in expect.cells]:
            problems.append(f"{ipynb.name} is out of step with {py.name}; run `make notebooks`")
        meta = {k: dict(v) for k, v in stored.metadata.items()}
        want = {k: dict(v) for k, v in expect.metadata.items()}
        for m in (meta, want):  # the Python patch version may differ between machines
            m.get("language_info", {}).pop("version", None)
        if meta != want:
            problems.append(f"{ipynb.name}: notebook metadata differs from what JupyterLab writes (it would show "
                            f"as modified on open); run `make notebooks`")
        for c in stored.cells:
            if c.cell_type == "code" and (c.get("outputs") or c.get("execution_count")):
                problems.append(f"{ipynb.name} holds outputs; strip them (`make notebooks`)")
                break
    return problems
