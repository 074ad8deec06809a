"""Plots of the parameter studies: means with 95 % confidence intervals over simulation seeds.

Inputs are :func:`ilocalg.workflow.studies.curves` frames (one row per parameter point
with ``mean``, ``ci95_low``, ``ci95_high``, ``n`` and the parameters as columns).
"""

from __future__ import annotations

import matplotlib.ticker as mticker
import numpy as np
import pandas as pd

from ilocviz.core import new_axes

__all__ = ["ci_curve", "ci_curves", "ci_reference"]


def _yerr(df: pd.DataFrame) -> np.ndarray:
    m = df["mean"].to_numpy(float)
    lo = np.nan_to_num(m - df["ci95_low"].to_numpy(float), nan=0.0)
    hi = np.nan_to_num(df["ci95_high"].to_numpy(float) - m, nan=0.0)
    return np.vstack([lo, hi])


def ci_curve(df: pd.DataFrame, x: str, ax=None, label: str | None = None, marker: str = "o", **kw):
    """One curve: ``mean`` against column ``x`` with 95 % CI error bars (rows sorted by ``x``).

    Rows with a NaN mean (no finite value in any seed) are left out; a NaN interval (N = 1) is
    drawn without a bar.
    """
    ax = new_axes(ax)
    if x not in df.columns:
        raise ValueError(f"no column {x!r} to plot against (have {list(df.columns)})")
    d = df[df["mean"].notna()].sort_values(x)
    ax.errorbar(d[x].to_numpy(float), d["mean"].to_numpy(float), yerr=_yerr(d), marker=marker, ms=4,
                capsize=3, label=label, **kw)
    return ax


def ci_curves(df: pd.DataFrame, x: str, by: str | None = None, ax=None, xlabel: str | None = None,
              ylabel: str | None = None, logx: bool = False, title: str | None = None):
    """Curves of ``mean`` vs ``x`` with 95 % CI bars, one per value of column ``by``.

    Parameters
    ----------
    df : DataFrame
        Study curves of a single quantity (columns ``x``, ``by``, ``mean``, ``ci95_low``,
        ``ci95_high``, ``unit``, ``n``).
    xlabel, ylabel : str, optional
        Axis labels; they should carry units (``ylabel`` defaults to the quantity and its unit).
    logx : bool
        Logarithmic x axis.
    """
    ax = new_axes(ax)
    if df.empty:
        raise ValueError("nothing to plot: the study curves are empty")
    groups = [(None, df)] if by is None else list(df.groupby(by, sort=True))
    for key, g in groups:
        ci_curve(g, x, ax=ax, label=None if key is None else str(key))
    if logx:
        ax.set_xscale("log")
        xs = np.unique(df[x].to_numpy(float))
        ax.set_xticks(xs)
        ax.xaxis.set_major_formatter(mticker.FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(mticker.NullFormatter())
    unit = str(df["unit"].iloc[0]) if "unit" in df.columns else ""
    q = str(df["quantity"].iloc[0]) if "quantity" in df.columns else "value"
    ax.set_xlabel(xlabel or x)
    ax.set_ylabel(ylabel or (f"{q} [{unit}]" if unit else q))
    n = df["n"].to_numpy()
    if title is not None:
        ax.set_title(title)
    note = f"mean, 95 % CI, N = {int(n.min())}" + (f"-{int(n.max())}" if n.max() != n.min() else "") + " seeds"
    if by is not None:
        ax.legend(loc="best", fontsize=8, title=note, title_fontsize=8)
    else:
        ax.text(0.99, 0.98, note, transform=ax.transAxes, ha="right", va="top", fontsize=8, color="0.35")
    return ax


def ci_reference(row, ax=None, label: str | None = None, color: str = "0.4", linestyle: str = "--"):
    """A reference level (e.g. the unsmoothed filter) as a horizontal line with its 95 % CI band."""
    ax = new_axes(ax)
    m = float(row["mean"])
    ax.axhline(m, color=color, linestyle=linestyle, lw=1.2, label=label)
    lo, hi = float(row["ci95_low"]), float(row["ci95_high"])
    if np.isfinite(lo) and np.isfinite(hi):
        ax.axhspan(lo, hi, color=color, alpha=0.12, lw=0)
    return ax
