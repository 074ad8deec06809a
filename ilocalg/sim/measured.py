"""The simulators' measured defaults: read ``data/measured_parameters.csv``.

The table is written by ``python -m ilocalg measure`` (:mod:`ilocalg.measure.table`) from the public
recordings in ``../shared/data``; every simulator default that is measured names its row here, e.g.
``param("wifi_scan_interval_s")``.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import pandas as pd

from ilocalg.io.paths import REPO_ROOT

__all__ = ["TABLE_PATH", "table", "row", "param", "ci", "cite"]

TABLE_PATH = REPO_ROOT / "data" / "measured_parameters.csv"
_COLUMNS = ("parameter", "value", "ci_low", "ci_high", "unit", "dataset", "method")


@lru_cache(maxsize=4)
def _load(path: str) -> pd.DataFrame:
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"{p}: measured-parameter table not found (run `python -m ilocalg measure`)")
    df = pd.read_csv(p)
    missing = [c for c in _COLUMNS if c not in df.columns]
    if missing:
        raise ValueError(f"{p}: line 1: missing column(s) {missing}")
    dup = df["parameter"][df["parameter"].duplicated()]
    if len(dup):
        raise ValueError(f"{p}: line {int(dup.index[0]) + 2}: parameter {dup.iloc[0]!r} listed twice")
    return df.set_index("parameter", drop=False)


def table(path=TABLE_PATH) -> pd.DataFrame:
    """The whole table (a copy), indexed by parameter name."""
    return _load(str(path)).copy()


def row(name: str, path=TABLE_PATH) -> dict:
    """One parameter's row: ``{parameter, value, ci_low, ci_high, unit, dataset, method}``."""
    df = _load(str(path))
    if name not in df.index:
        raise ValueError(f"unknown measured parameter {name!r} in {Path(path).name}; known: {sorted(df.index)}")
    r = df.loc[name]
    return {c: (float(r[c]) if c in ("value", "ci_low", "ci_high") else str(r[c])) for c in _COLUMNS}


def param(name: str, path=TABLE_PATH) -> float:
    """A parameter's measured value (float)."""
    return row(name, path)["value"]


def ci(name: str, path=TABLE_PATH) -> tuple[float, float]:
    """A parameter's 95 % bootstrap interval ``(low, high)``."""
    r = row(name, path)
    return r["ci_low"], r["ci_high"]


def cite(name: str, path=TABLE_PATH) -> str:
    """A one-line source for readings tables: ``measured_parameters.csv: NAME = V [lo, hi] UNIT (DATASET)``."""
    r = row(name, path)
    return (f"data/measured_parameters.csv: {name} = {r['value']:.4g} [{r['ci_low']:.4g}, {r['ci_high']:.4g}] "
            f"{r['unit']} ({r['dataset']})")
