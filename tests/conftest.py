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


@pytest.fixture
def shared_data():
    """Call with a data-set name (``shared_data('ujiindoorloc')``) to get its folder."""
    return _require
