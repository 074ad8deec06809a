"""Layering: ilocalg computes and never imports matplotlib; importing has no side effects."""

import subprocess
import sys

CODE = r"""
import importlib, pkgutil, sys
import ilocalg
names = [m.name for m in pkgutil.walk_packages(ilocalg.__path__, "ilocalg.") if m.name != "ilocalg.__main__"]
for n in names:
    importlib.import_module(n)
bad = sorted(m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib."))
print(len(names), "modules;", "matplotlib loaded" if bad else "no matplotlib")
sys.exit(1 if bad else 0)
"""


def test_no_module_of_ilocalg_imports_matplotlib():
    res = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "no matplotlib" in res.stdout


def test_importing_ilocviz_leaves_rcparams_alone():
    code = (
        "import matplotlib as mpl; before = dict(mpl.rcParams); import ilocviz; "
        "import sys; sys.exit(0 if dict(mpl.rcParams) == before else 1)"
    )
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0
