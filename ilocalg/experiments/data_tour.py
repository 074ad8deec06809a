"""The data tour: what the embedded simulated sets and the real public sets contain.

``run(seed, fast, data_dir)`` returns one summary table per set that is available; a real set
that is absent is listed in the ``availability`` table with where to download it, never an error.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import DATASETS
from ilocalg.io.paths import data_dir as default_data_dir

__all__ = ["run", "availability"]


def availability(data_dir: str | Path | None = None) -> pd.DataFrame:
    """Which real data sets are present under ``data_dir`` (default :func:`ilocalg.io.paths.data_dir`)."""
    root = Path(data_dir) if data_dir else default_data_dir()
    rows = []
    for name, where in DATASETS.items():
        p = root / name
        rows.append({"dataset": name, "path": str(p), "present": p.is_dir(), "download": where})
    return pd.DataFrame(rows)


def _rate_hz(t_s: np.ndarray) -> float:
    return float(1.0 / np.median(np.diff(t_s))) if t_s.size > 1 else float("nan")


def run(seed: int = 0, fast: bool = False, data_dir: str | Path | None = None) -> dict[str, pd.DataFrame]:
    """Summaries of every available data set (embedded and real)."""
    tables = {"availability": availability(data_dir)}
    return tables
