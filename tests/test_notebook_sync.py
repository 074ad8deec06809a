import shutil

import nbformat

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
