"""A store shared by the processes of one reproduce run, gone when the run ends.

The reproduce runner (:func:`ilocalg.workflow.runner.reproduce`) makes a fresh temporary folder for the run, names it
in :data:`RUN_STORE_ENV` for its pool processes and the notebook kernels they start, and removes it when the pool is
done; outside a reproduce run (a notebook run by hand, a test) the variable is unset and nothing is stored. An
experiment may leave there a costly intermediate result that another stage of the same run recomputes (e.g. the
filtered walks of study_ins_window, which ins_online's notebook and seed sweep filter again), keyed on every input
the result depends on; a reader that finds nothing computes the result itself, so the tables never depend on the
store, only the time does. Nothing persists between two runs.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

__all__ = ["RUN_STORE_ENV", "store_dir", "get", "put", "run_store"]

#: Environment variable naming the run's store folder (unset: no store).
RUN_STORE_ENV = "ILOCALG_RUN_STORE"


def store_dir() -> Path | None:
    """This run's store folder, or None outside a reproduce run."""
    d = os.environ.get(RUN_STORE_ENV)
    return Path(d) if d and Path(d).is_dir() else None


def _path(namespace: str, key) -> Path | None:
    d = store_dir()
    if d is None:
        return None
    return d / namespace / (hashlib.sha256(repr(key).encode()).hexdigest()[:32] + ".pkl")


def get(namespace: str, key):
    """The value stored under ``key`` (any object whose ``repr`` names every input) in ``namespace``, else None."""
    p = _path(namespace, key)
    if p is None or not p.exists():
        return None
    try:
        with open(p, "rb") as f:
            stored_key, value = pickle.load(f)
    except (OSError, EOFError, pickle.UnpicklingError):
        return None
    return value if stored_key == repr(key) else None


def put(namespace: str, key, value) -> None:
    """Store ``value`` under ``key`` in ``namespace`` (nothing outside a reproduce run); written atomically, so a
    reader in another process sees the whole value or none."""
    p = _path(namespace, key)
    if p is None:
        return
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.with_suffix(f".{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        pickle.dump((repr(key), value), f, protocol=pickle.HIGHEST_PROTOCOL)
    tmp.replace(p)


@contextmanager
def run_store():
    """A fresh store for the block (:data:`RUN_STORE_ENV` set for it, and for the processes started in it), removed
    afterwards with everything in it."""
    old = os.environ.get(RUN_STORE_ENV)
    d = tempfile.mkdtemp(prefix="ilocalg-run-")
    os.environ[RUN_STORE_ENV] = d
    try:
        yield Path(d)
    finally:
        if old is None:
            os.environ.pop(RUN_STORE_ENV, None)
        else:
            os.environ[RUN_STORE_ENV] = old
        shutil.rmtree(d, ignore_errors=True)
