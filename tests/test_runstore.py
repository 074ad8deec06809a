"""The store shared by the processes of one reproduce run (ilocalg.workflow.runstore)."""

import os

import numpy as np

from ilocalg.workflow import runstore


def test_nothing_is_stored_outside_a_run_and_a_run_leaves_nothing(monkeypatch):
    monkeypatch.delenv(runstore.RUN_STORE_ENV, raising=False)
    runstore.put("ns", ("a", 1), 5)
    assert runstore.get("ns", ("a", 1)) is None and runstore.store_dir() is None
    with runstore.run_store() as d:
        assert os.environ[runstore.RUN_STORE_ENV] == str(d) and runstore.store_dir() == d
        runstore.put("ns", ("a", 1.0), {"x": np.arange(3)})
        got = runstore.get("ns", ("a", 1.0))
        assert np.array_equal(got["x"], np.arange(3))
        assert runstore.get("ns", ("a", 1)) is None  # another key (1 is not 1.0)
        assert runstore.get("other", ("a", 1.0)) is None
    assert not d.exists() and runstore.RUN_STORE_ENV not in os.environ
    assert runstore.get("ns", ("a", 1.0)) is None
