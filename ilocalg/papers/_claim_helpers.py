"""Small statistics and labels shared by the papers' claim modules.

Each helper returns a :class:`ilocalg.papers.claims.Stat` (a function of reproduced scalars) or a string;
nothing here reads a paper value.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ilocalg.papers.claims import Ref, Stat

__all__ = ["decided", "stat", "gmean_ratio", "mean_of", "max_of", "mean_spearman", "gmean", "rss"]


def decided(stem: str, heading: str) -> str:
    """``decided_in`` of a claim: notebook stem and the anchor of a Markdown heading in it (spaces -> '-',
    the anchor JupyterLab and nbconvert give a heading)."""
    return f"{stem}#{heading.strip().replace(' ', '-')}"


def stat(refs: Sequence[Ref], fn, label: str, unit: str = "") -> Stat:
    """A statistic ``fn(*values)`` of reproduced scalars."""
    return Stat(tuple(refs), fn, label, unit)


def gmean(values) -> float:
    """Geometric mean of positive values (NaN if any is not positive or finite)."""
    v = np.asarray(list(values), dtype=np.float64)
    if v.size == 0 or not np.all(np.isfinite(v)) or np.any(v <= 0):
        return math.nan
    return float(np.exp(np.mean(np.log(v))))


def gmean_ratio(pairs: Sequence[tuple[Sequence[Ref], Sequence[Ref]]], combine, label: str) -> Stat:
    """Geometric mean over ``pairs`` of ``combine(a values) / combine(b values)``.

    ``pairs`` is a sequence of ``(a_refs, b_refs)`` (e.g. one pair per phone: the N, E, H RMS errors of two
    methods) and ``combine`` turns one group of values into a scalar (e.g. the root sum of squares).
    """
    groups = []
    refs: list[Ref] = []
    for a, b in pairs:
        groups.append((len(a), len(b)))
        refs += list(a) + list(b)

    def fn(*v):
        out, i = [], 0
        for na, nb in groups:
            num = combine(v[i:i + na])
            den = combine(v[i + na:i + na + nb])
            i += na + nb
            out.append(num / den if den != 0 else math.nan)
        return gmean(out)

    return Stat(tuple(refs), fn, label, "ratio")


def mean_of(refs: Sequence[Ref], label: str, unit: str = "") -> Stat:
    """Arithmetic mean of reproduced scalars."""
    return Stat(tuple(refs), lambda *v: float(np.mean(v)), label, unit)


def max_of(refs: Sequence[Ref], label: str, unit: str = "") -> Stat:
    """Largest of several reproduced scalars."""
    return Stat(tuple(refs), lambda *v: float(np.max(v)), label, unit)


def mean_spearman(curves: Sequence[Sequence[Ref]], xs: Sequence[float], label: str) -> Stat:
    """Mean over ``curves`` of the Spearman correlation of each curve's values with ``xs`` (a trend over
    several curves, e.g. N, E and H of two phones against the window size)."""
    from scipy.stats import spearmanr

    xs = tuple(float(x) for x in xs)
    curves = [tuple(c) for c in curves]
    if any(len(c) != len(xs) for c in curves) or len(xs) < 3:
        raise ValueError("every curve needs one ref per abscissa and at least 3 abscissae")
    n = len(xs)

    def fn(*v):
        rhos = []
        for j in range(len(curves)):
            r = spearmanr(xs, v[j * n:(j + 1) * n]).statistic
            rhos.append(float(r) if np.isfinite(r) else math.nan)
        return float(np.mean(rhos))

    return Stat(tuple(r for c in curves for r in c), fn, label, "")


def rss(values) -> float:
    """Root sum of squares (e.g. a 3-D error from per-axis RMS errors)."""
    return float(np.sqrt(np.sum(np.square(np.asarray(values, dtype=np.float64)))))
