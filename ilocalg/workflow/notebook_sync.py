"""Keep ``notebooks/NN_topic.py`` (jupytext py:percent, the reviewed source) and its ``.ipynb`` paired.

The ``.py`` file is the source of truth; ``--sync`` writes the ``.ipynb`` from it with no outputs and
the metadata JupyterLab itself writes (the kernel's ``kernelspec`` and ``language_info``, jupytext's
filters), so an unchanged notebook opens unmodified; ``--check`` fails when a pair is missing, out of
step, holds outputs or carries other metadata, or when a Markdown cell types a measured number.

Words from numbers (:func:`typed_numbers`): a Markdown cell must not state a number with a unit or a
percent sign (``4.9 m``, ``12 %``, ``0.25 s``, ``50 Hz``, ``13.87 deg``) that no code computed; a measured
number reaches the reader through code (a printed table, or generated text such as
:func:`ilocalg.papers.claims.claims_markdown` displayed as Markdown). Allowed, and how to mark them:

- a quote of the paper: in a blockquote (a line starting with ``>``), or in a sentence that cites the
  paper: a line citation ``L<number>`` (``the thesis reports 2.82 m (L1520)``), a paper item (``Fig 23``,
  ``Table 2``, ``eq. (16)``, ``sec. 5``: the notebooks number none of their own, so these always name the
  paper's) or a sentence reporting the paper's words (``the thesis reports ...``, ``the paper gives ...``);
- an input, not a result: a sentence that says so with the word ``assumption``/``assumed`` or ``input``
  or ``setting`` (``scan latency (an assumption: phones take 1-3 s per scan)``);
- anything inside LaTeX math (``$...$``) or inline code (`` `...` ``).
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path

__all__ = ["sync", "check", "typed_numbers", "notebook_metadata", "kernel_language_info", "kernelspec",
           "JUPYTEXT_METADATA"]


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


_UNIT = r"(?:%|percent|m/s\^?2|m/s²|m/s|km|cm|mm|m\^2|m²|m|ms|s|min|Hz|dBm|dB|deg|°|rad)"
#: A number (or a range of two) followed by a unit or %, as prose states a measured value; a percentage
#: that names a level or a quantile ("95 % CI", "the 5 % and 95 % points") is not a measurement.
NUMBER_WITH_UNIT = re.compile(
    rf"(?<![\w.$^_\-/])[-+±]?\d+(?:\.\d+)?(?:\s?(?:-|–|to)\s?\d+(?:\.\d+)?)?\s?{_UNIT}(?![\w/^²])"
    r"(?!\s*(?:CIs?\b|confidence|intervals?\b|levels?\b|points?\b|quantiles?\b|ranges?\b|,\s*\d+\s*%\]|\]))")
_QUOTE = re.compile(r"(?<![A-Za-z])L\d+|\b(?:Figs?\.?|Figures?|Tables?|eqs?\.|Eqs?\.|[Ss]ec\.)\s*\(?\d"
                    r"|\b(?:paper|thesis|survey|text)s? (?:reports|gives|says|prints)|data set's own report")
_INPUT = re.compile(r"assum|\binputs?\b|\bsettings?\b", re.IGNORECASE)
_SPANS = re.compile(r"\$\$.*?\$\$|\$[^$\n]*\$|`[^`\n]*`", re.DOTALL)
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+(?=[A-Z*(\[\-])|\n\s*\n|\n\s*[-*]\s")


def typed_numbers(markdown: str) -> list[str]:
    """Numbers with a unit typed in ``markdown`` that are neither marked quotes of the paper nor declared
    inputs (the rules are in the module docstring); each as ``'4.9 m' in "<its sentence>"``."""
    blocks, cur = [], []
    for line in markdown.splitlines():
        if line.lstrip().startswith(">"):  # a blockquote: the paper's words
            continue
        if line.lstrip().startswith("#"):  # a heading is a sentence of its own
            blocks += ["\n".join(cur), line]
            cur = []
        else:
            cur.append(line)
    blocks.append("\n".join(cur))
    out = []
    sentences = [x for b in blocks for x in _SENTENCE_END.split(_SPANS.sub(" ", b))]
    for sentence in sentences:
        if _QUOTE.search(sentence) or _INPUT.search(sentence):
            continue
        for m in NUMBER_WITH_UNIT.finditer(sentence):
            out.append(f"{m.group(0)!r} in \"{' '.join(sentence.split())[:100]}\"")
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
        for i, c in enumerate(expect.cells):
            if c.cell_type == "markdown":
                for hit in typed_numbers(c.source):
                    problems.append(f"{py.name}: markdown cell {i} types a measured number {hit}: generate it "
                                    f"from code, or mark a quote of the paper / an input (see "
                                    f"ilocalg.workflow.notebook_sync)")
    return problems
