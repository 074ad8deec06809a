"""The simulators' measured defaults: read ``data/measured_parameters.csv`` and ``data/calibrated_parameters.csv``.

The measured table is written by ``python -m ilocalg measure`` (:mod:`ilocalg.measure.table`) from the
public recordings in ``../shared/data``; every simulator default that is measured names its row here,
e.g. ``param("wifi_scan_interval_s")``.

The calibrated table is written by ``python -m ilocalg measure --calibrate``
(:mod:`ilocalg.measure.calibrate`): for a simulator parameter whose statistic does not come back when
measured on the simulated world, the value at which it does (``calibrated("iloc_floor.shadow_sd_db")``),
with the target statistic and the interval carried from the target's interval.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import pandas as pd

from ilocalg.io.paths import REPO_ROOT

__all__ = ["TABLE_PATH", "CALIBRATED_PATH", "table", "row", "param", "ci", "cite", "calibrated_table",
           "calibrated_row", "calibrated", "calibrated_cite"]

TABLE_PATH = REPO_ROOT / "data" / "measured_parameters.csv"
CALIBRATED_PATH = REPO_ROOT / "data" / "calibrated_parameters.csv"
_COLUMNS = ("parameter", "value", "ci_low", "ci_high", "unit", "dataset", "method")
#: columns of data/calibrated_parameters.csv
CALIBRATED_COLUMNS = ("parameter", "value", "ci_low", "ci_high", "unit", "statistic", "target", "target_ci_low",
                      "target_ci_high", "copied", "at_copied", "at_value", "method")


@lru_cache(maxsize=8)
def _load(path: str, columns: tuple = _COLUMNS) -> pd.DataFrame:
    p = Path(path)
    if not p.is_file():
        cmd = "measure --calibrate" if columns == CALIBRATED_COLUMNS else "measure"
        raise ValueError(f"{p}: parameter table not found (run `python -m ilocalg {cmd}`)")
    df = pd.read_csv(p)
    missing = [c for c in columns if c not in df.columns]
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
    return dict(_row(name, str(path)))


@lru_cache(maxsize=256)
def _row(name: str, path: str) -> tuple:
    """:func:`row`'s items, read once per process like the table (:func:`_load`)."""
    df = _load(path)
    if name not in df.index:
        raise ValueError(f"unknown measured parameter {name!r} in {Path(path).name}; known: {sorted(df.index)}")
    r = df.loc[name]
    return tuple((c, float(r[c]) if c in ("value", "ci_low", "ci_high") else str(r[c])) for c in _COLUMNS)


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


def calibrated_table(path=CALIBRATED_PATH) -> pd.DataFrame:
    """data/calibrated_parameters.csv (a copy), indexed by ``simulator.parameter``."""
    return _load(str(path), CALIBRATED_COLUMNS).copy()


def calibrated_row(name: str, path=CALIBRATED_PATH) -> dict:
    """One calibrated parameter's row (``CALIBRATED_COLUMNS``; numbers as floats)."""
    return dict(_calibrated_row(name, str(path)))


@lru_cache(maxsize=256)
def _calibrated_row(name: str, path: str) -> tuple:
    """:func:`calibrated_row`'s items, read once per process like the table (:func:`_load`): every simulated walk
    asks for five of them (and two of :func:`row`'s)."""
    df = _load(path, CALIBRATED_COLUMNS)
    if name not in df.index:
        raise ValueError(f"unknown calibrated parameter {name!r} in {Path(path).name}; known: {sorted(df.index)}")
    r = df.loc[name]
    return tuple((c, str(r[c]) if c in ("parameter", "unit", "statistic", "method") else float(r[c]))
                 for c in CALIBRATED_COLUMNS)


def calibrated(name: str, path=CALIBRATED_PATH) -> float:
    """A calibrated simulator parameter's value, e.g. ``calibrated("gait.amp_sd_rel")``."""
    return calibrated_row(name, path)["value"]


def calibrated_cite(name: str, path=CALIBRATED_PATH) -> str:
    """One line for readings tables: the value, its interval and the statistic it brings back."""
    r = calibrated_row(name, path)
    return (f"data/calibrated_parameters.csv: {name} = {r['value']:.4g} [{r['ci_low']:.4g}, {r['ci_high']:.4g}] "
            f"{r['unit']}, the value at which the simulated {r['statistic']} equals the real "
            f"{r['target']:.4g} [{r['target_ci_low']:.4g}, {r['target_ci_high']:.4g}]")
