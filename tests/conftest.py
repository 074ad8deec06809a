"""Shared fixtures.

Real data: tests that read ../shared/data take the ``shared_data`` fixture. When a set is missing
they skip on a developer machine and FAIL under CI=true (CI must never pass by skipping them).
"""

from __future__ import annotations

import os

import pytest

from ilocalg.io.paths import dataset_path


def _require(name: str):
    p = dataset_path(name)
    if not p.is_dir():
        msg = f"real data set {name!r} not found at {p} (set ILOC_DATA_DIR or see README 'Real data')"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return p


@pytest.fixture(scope="session")  # stateless: module fixtures may take it
def shared_data():
    """Call with a data-set name (``shared_data('ujiindoorloc')``) to get its folder."""
    return _require


# ---- parallel runs (``make test``: ``pytest -n 2 --dist loadfile``, pytest-xdist) ---------------------------------
#: Test files whose tests share one process's caches, run by one worker like a single file: the claims tests
#: share their experiments' fast runs (tests/claims_checks.py caches them per process).
_SAME_WORKER = ("tests/test_claims_",)
#: The longest test files (CPU seconds of a serial run), handed out first so that the two workers end together;
#: the others follow in name order. Only the order of a parallel run depends on this list.
_LONGEST_FIRST = ("test_notebooks", "test_measure_calibrate", "test_experiment_ins_constraints", "test_runner",
                  "test_evaluate_track", "test_experiment_photo")


def _scope(path: str) -> str:
    return next((p for p in _SAME_WORKER if path.startswith(p)), path)


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` with the files of :data:`_SAME_WORKER` as one unit (each file's module fixtures, and
    their shared caches, are built once)."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class _Scheduling(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _scope(super()._split_scope(nodeid))

    return _Scheduling(config, log)


def pytest_collection_modifyitems(config, items):
    """In an xdist worker: the files of :data:`_LONGEST_FIRST` first (the scheduler hands units out in collection
    order under ``--no-loadscope-reorder``). A serial run keeps pytest's order."""
    if not hasattr(config, "workerinput"):
        return
    rank = {f"tests/{name}.py": i for i, name in enumerate(_LONGEST_FIRST)}
    items.sort(key=lambda it: rank.get(it.nodeid.split("::", 1)[0], len(rank)))  # stable: name order otherwise
