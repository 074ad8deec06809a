"""Shared plumbing of the parameter studies (``study_*`` experiments): task grids and tidy curves.

A study is an experiment whose ``run(seed, fast, **params)`` returns a ``sweep_<name>`` table
(columns ``quantity``, ``value``, ``unit``, ``item``) that :func:`ilocalg.workflow.sweep.sweep` collects
and :func:`ilocalg.workflow.sweep.aggregate` turns into mean / sd / 95 % CI per (parameters, item,
quantity). Within a run, a curve's abscissa that is cheaper to compute in one go (window sizes of
one filtered walk, say) is written into ``item`` as ``"name=value;name2=value2"``; a swept
parameter lives in the task's ``params``. :func:`curves` turns both back into columns.

Studies live in ``ilocalg.experiments.study_*``; this plumbing is workflow code (it builds sweep tasks).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping

import numpy as np
import pandas as pd

from ilocalg.workflow.sweep import SweepTask, make_tasks

__all__ = ["item_label", "parse_item", "study_row", "study_tasks", "curves", "select", "NOTEBOOK_STUDIES",
           "study_seeds", "notebook_tasks", "run_notebook_tasks", "STUDY_CACHE_ENV"]

#: Notebook stem -> the studies it sweeps (``ilocalg.experiments.<name>``), in the notebook's order.
NOTEBOOK_STUDIES: dict[str, tuple[str, ...]] = {
    "15_sweep_studies": ("study_wifi", "study_ins_window", "study_kf_noise", "study_pso"),
}

#: Environment variable through which the reproduce runner tells a study notebook's kernel the sweep cache
#: its process pool has filled with the notebook's tasks (:func:`run_notebook_tasks`).
STUDY_CACHE_ENV = "ILOCALG_STUDY_CACHE"


def item_label(**context) -> str:
    """``item_label(method="RADAR", window_s=5)`` -> ``"method=RADAR;window_s=5"`` (order kept)."""
    for k, v in context.items():
        if ";" in str(v) or ";" in k or "=" in k:
            raise ValueError(f"item context {k}={v!r} must not contain ';' (nor '=' in the name)")
    return ";".join(f"{k}={v}" for k, v in context.items())


def parse_item(item: str) -> dict:
    """Inverse of :func:`item_label` (values stay strings); ``""`` -> ``{}``."""
    out = {}
    for part in str(item).split(";"):
        if not part:
            continue
        if "=" not in part:
            raise ValueError(f"item part {part!r} is not NAME=VALUE")
        k, v = part.split("=", 1)
        out[k] = v
    return out


def study_row(quantity: str, value: float, unit: str, **context) -> dict:
    """One row of a ``sweep_*`` table: a measured ``value`` with its context in ``item``."""
    return {"quantity": quantity, "value": float(value), "unit": unit, "item": item_label(**context)}


def study_tasks(experiment: str, grids: Iterable[Mapping[str, list]], seeds: Iterable[int],
                fast: bool = False) -> list[SweepTask]:
    """Tasks of several one-factor grids (each crossed with ``seeds``), duplicates removed in order.

    Each grid should name every swept parameter (with the base value for the fixed ones) so the
    grids share their common point instead of running it twice.
    """
    seeds = list(seeds)
    out, seen = [], set()
    for g in grids:
        for t in make_tasks(experiment, seeds, g, fast=fast):
            if t.key not in seen:
                seen.add(t.key)
                out.append(t)
    return out


def study_seeds(seed: int, fast: bool) -> range:
    """Seeds of a study notebook: ``seed .. seed + N - 1``, N = 12 (fast mode: 3)."""
    return range(int(seed), int(seed) + (3 if fast else 12))


def notebook_tasks(stem: str, seed: int, fast: bool) -> list[SweepTask]:
    """Every sweep task of study notebook ``stem`` (:data:`NOTEBOOK_STUDIES`), the notebook's order."""
    import importlib

    if stem not in NOTEBOOK_STUDIES:
        raise ValueError(f"{stem!r} is not a study notebook (have {sorted(NOTEBOOK_STUDIES)})")
    seeds = study_seeds(seed, fast)
    return [t for name in NOTEBOOK_STUDIES[stem]
            for t in importlib.import_module(f"ilocalg.experiments.{name}").tasks(seeds, fast)]


def run_notebook_tasks(tasks: list[SweepTask], workers: int = 2):
    """Run a study notebook's tasks: on a LocalCluster of ``workers`` processes when the notebook runs alone;
    under ``reproduce`` (:data:`STUDY_CACHE_ENV` set), read from the sweep cache its process pool filled
    beside the other notebooks, any task not there yet running in this process.

    Returns (:class:`ilocalg.workflow.sweep.SweepResult`, how it ran: ``"LocalCluster"`` or ``"reproduce pool"``).
    """
    import os

    from ilocalg.workflow.sweep import sweep

    cache = os.environ.get(STUDY_CACHE_ENV)
    if cache:
        return sweep(tasks, workers=0, cache_dir=cache, progress=False), "reproduce pool"
    return sweep(tasks, workers=workers, cache_dir=None, progress=False), "LocalCluster"


def _numeric(s: pd.Series) -> pd.Series:
    try:
        return pd.to_numeric(s)
    except (ValueError, TypeError):
        return s


def curves(agg: pd.DataFrame, experiment: str | None = None) -> pd.DataFrame:
    """Aggregated sweep rows with the parameters and item context expanded into columns.

    Parameters
    ----------
    agg : DataFrame
        :func:`ilocalg.workflow.sweep.aggregate` output (columns experiment, params, item, quantity, unit,
        n, mean, std, ci95_low, ci95_high, ...).
    experiment : str, optional
        Keep only this experiment's rows.

    Returns
    -------
    DataFrame
        One column per parameter name and per item context name (numeric where they parse),
        plus quantity, unit, n, mean, std, ci95_low, ci95_high; sorted by those columns (numbers
        numerically).
    """
    df = agg if experiment is None else agg[agg["experiment"] == experiment]
    if df.empty:
        raise ValueError(f"no aggregated rows{f' for experiment {experiment!r}' if experiment else ''}")
    params = [json.loads(p) for p in df["params"]]
    items = [parse_item(i) for i in df["item"]]
    ctx = pd.DataFrame([{**p, **i} for p, i in zip(params, items, strict=True)], index=df.index)
    for c in ctx.columns:
        ctx[c] = _numeric(ctx[c])
    keep = ["quantity", "unit", "n", "mean", "std", "ci95_low", "ci95_high"]
    out = pd.concat([ctx, df[keep]], axis=1)
    return out.sort_values([*ctx.columns, "quantity"], kind="stable").reset_index(drop=True)


def select(cv: pd.DataFrame, quantity: str, **fixed) -> pd.DataFrame:
    """Rows of ``curves`` output for one quantity with some columns held at given values."""
    m = cv["quantity"] == quantity
    for k, v in fixed.items():
        if k not in cv.columns:
            raise ValueError(f"no column {k!r} in the study curves (have {list(cv.columns)})")
        col = cv[k]
        m &= np.isclose(col.astype(float), float(v)) if isinstance(v, (int, float)) else (col == v)
    return cv[m]
