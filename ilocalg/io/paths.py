"""Where the real public data sets are looked for.

The toolkit never ships or copies the real recordings. Loaders take explicit paths; notebooks
and tests find the shared copies through :func:`data_dir`: the ``ILOC_DATA_DIR`` environment
variable if set, otherwise ``../shared/data`` next to the repository.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["REPO_ROOT", "data_dir", "dataset_path", "DATASETS"]

REPO_ROOT = Path(__file__).resolve().parents[2]

#: Folder names of the real data sets under the data directory, with where to get them.
DATASETS = {
    "ujiindoorloc": "UJIIndoorLoc, UCI Machine Learning Repository dataset 310 (trainingData.csv, validationData.csv)",
    "oxford_step_counter": "Oxford step counter DataSet, GitHub Oxford-step-counter/DataSet (optimisation/)",
    "ilc2020_site1": "Indoor Location Competition 2.0, GitHub location-competition/indoor-location-competition-20 "
                     "(data/site1/F1 and F2, one archive site1_F1_F2.tar.xz)",
    "ilc2020_site2_F4": "Indoor Location Competition 2.0, GitHub location-competition/indoor-location-competition-20 "
                        "(data/site2/F4)",
}


def data_dir() -> Path:
    """The folder holding the real data sets (may not exist)."""
    env = os.environ.get("ILOC_DATA_DIR")
    if env:
        return Path(env).expanduser().resolve()
    return (REPO_ROOT.parent / "shared" / "data").resolve()


def dataset_path(name: str) -> Path:
    """Path of one real data set's folder under :func:`data_dir` (existence not checked)."""
    if name not in DATASETS:
        raise ValueError(f"unknown data set {name!r}; known: {sorted(DATASETS)}")
    return data_dir() / name
