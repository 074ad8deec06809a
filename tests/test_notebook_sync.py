import shutil

import nbformat
import pytest

from ilocalg.workflow import notebook_sync
from ilocalg.workflow.runner import NOTEBOOK_DIR


def test_sync_is_byte_stable_and_check_finds_problems(tmp_path):
    shutil.copy(NOTEBOOK_DIR / "00_data_tour.py", tmp_path / "00_data_tour.py")
    assert notebook_sync.check(tmp_path) == ["00_data_tour.py has no paired .ipynb; run `make notebooks`"]
    (nb_path,) = notebook_sync.sync(tmp_path)
    first = nb_path.read_bytes()
    notebook_sync.sync(tmp_path)
    assert nb_path.read_bytes() == first  # regenerating an unchanged notebook changes nothing
    assert notebook_sync.check(tmp_path) == []
    nb = nbformat.read(nb_path, as_version=4)
    code = next(c for c in nb.cells if c.cell_type == "code")
    code.outputs = [nbformat.v4.new_output("stream", text="hi")]
    nbformat.write(nb, nb_path)
    assert any("holds outputs" in p for p in notebook_sync.check(tmp_path))
    with open(tmp_path / "00_data_tour.py", "a") as fh:
        fh.write("\n# %%\nx = 1\n")
    assert any("out of step" in p for p in notebook_sync.check(tmp_path))


def test_stored_notebooks_render_as_their_py_and_carry_the_kernels_own_metadata():
    """What keeps an unchanged notebook from showing as modified in JupyterLab: jupytext renders the .ipynb
    exactly as the .py (no header), and the metadata equals what the kernel reports (kernelspec, language_info)."""
    import jupytext
    from jupyter_client.kernelspec import KernelSpecManager
    from jupyter_client.manager import start_new_kernel

    km, kc = start_new_kernel(kernel_name="python3")
    try:
        kc.kernel_info()
        reply = kc.get_shell_msg(timeout=30)
        while reply["msg_type"] != "kernel_info_reply":
            reply = kc.get_shell_msg(timeout=30)
        language_info = reply["content"]["language_info"]
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    spec = KernelSpecManager().get_kernel_spec("python3")
    for ipynb in sorted(NOTEBOOK_DIR.glob("[0-9][0-9]_*.ipynb")):
        nb = nbformat.read(ipynb, as_version=4)
        assert jupytext.writes(nb, fmt="py:percent") == ipynb.with_suffix(".py").read_text(), ipynb.name
        assert nb.metadata["kernelspec"] == {"display_name": spec.display_name, "language": spec.language,
                                             "name": "python3"}
        stored = dict(nb.metadata["language_info"])
        assert {k: v for k, v in stored.items() if k != "version"} == {
            k: v for k, v in language_info.items() if k != "version"}
    assert notebook_sync.check(NOTEBOOK_DIR) == []


def test_check_flags_metadata_jupyterlab_would_rewrite(tmp_path):
    shutil.copy(NOTEBOOK_DIR / "00_data_tour.py", tmp_path / "00_data_tour.py")
    (nb_path,) = notebook_sync.sync(tmp_path)
    nb = nbformat.read(nb_path, as_version=4)
    nb.metadata["kernelspec"]["display_name"] = "Python 3"
    nbformat.write(nb, nb_path)
    assert any("would show as modified" in p for p in notebook_sync.check(tmp_path))


def test_check_reports_an_unreadable_notebook_instead_of_raising(tmp_path):
    import shutil

    from ilocalg.workflow.runner import NOTEBOOK_DIR as src

    shutil.copy(src / "00_data_tour.py", tmp_path / "00_data_tour.py")
    notebook_sync.sync(tmp_path)
    (tmp_path / "00_data_tour.ipynb").write_text('{\n<<<<<<< HEAD\n "cells": []\n')
    assert any("not a readable notebook" in p for p in notebook_sync.check(tmp_path))


@pytest.mark.parametrize("text, hits", [
    ("The KF comes out at 4.9 m against Wi-Fi's 4.1 m.", ["'4.9 m'", "'4.1 m'"]),
    ("SAM misses 12 % of the steps.", ["'12 %'"]),
    ("The thesis reports 2.82 m (L1520).", []),                     # a line citation marks a quote
    ("Beside **Fig 23**: PTS 5.15 m -> KF 2.82 m.", []),             # the paper's item in bold
    ("> KF mean error 2.82 m", []),                                  # a blockquote
    ("Scan latency (an assumption: 1-3 s per scan).", []),           # a declared input
    ("The error is $\\sigma = 2\\,m$ and `window_s=2 s`.", []),       # maths and code
    ("Quoted 2.82 m (L1520). Measured 4.9 m.", ["'4.9 m'"]),         # the citation covers its sentence only
    ("Table 3 has 28 points and eq. (16) uses L2 norms.", []),       # numbers without units
])
def test_typed_numbers_flags_measured_numbers_not_quotes_inputs_or_code(text, hits):
    found = notebook_sync.typed_numbers(text)
    assert [h.split(" in ")[0] for h in found] == hits


def test_check_fails_on_a_typed_measured_number(tmp_path):
    shutil.copy(NOTEBOOK_DIR / "00_data_tour.py", tmp_path / "00_data_tour.py")
    with open(tmp_path / "00_data_tour.py", "a") as fh:
        fh.write("\n# %% [markdown]\n# ## Conclusion\n# The fused error is 4.9 m.\n")
    notebook_sync.sync(tmp_path)
    problems = notebook_sync.check(tmp_path)
    assert len(problems) == 1 and "types a measured number '4.9 m'" in problems[0]


def test_every_notebook_passes_the_words_from_numbers_check():
    problems = [p for p in notebook_sync.check(NOTEBOOK_DIR) if "measured number" in p]
    assert not problems, "\n".join(problems)
