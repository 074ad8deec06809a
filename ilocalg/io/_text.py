"""Parsing helpers shared by the text-log loaders (private to :mod:`ilocalg.io`).

Every loader reports bad content the same way: ``FILE: line N: what is wrong`` or
``FILE: line N, column COL: what is wrong``, where N is the 1-based line of the file a person
opens in an editor, never a table row.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NoReturn

import numpy as np

__all__ = ["fail", "to_float", "first_not_increasing", "check_increasing"]


def fail(source, lineno, msg: str, column: str | None = None) -> NoReturn:
    """Raise ``ValueError("SOURCE: line N[, column COL]: MSG")``."""
    where = f"line {lineno}" if column is None else f"line {lineno}, column {column}"
    raise ValueError(f"{source}: {where}: {msg}")


def to_float(rows: Sequence[Sequence[str]], linenos: Sequence[int], source, label: Callable[[int], str],
             ncols: int, finite: bool = False) -> np.ndarray:
    """Text cells as a float64 array ``(len(rows), ncols)``, naming the first bad cell's line.

    Parameters
    ----------
    rows : sequence of sequences of str
        The cells, one inner sequence (of length ``ncols``) per record.
    linenos : sequence of int
        The file line of each record.
    source : str
        File name for the message.
    label : callable
        ``label(j)`` describes cell ``j`` of a record in the message (e.g. ``"ACCE field 3 (X)"``).
    ncols : int
    finite : bool
        Also refuse ``nan`` / ``inf`` (the message then says "a finite number").

    Raises
    ------
    ValueError
        ``SOURCE: line N: LABEL must be numeric, got 'abc'`` (or "must be a finite number").
    """
    try:
        out = np.asarray(rows, dtype=np.float64).reshape(len(rows), ncols)
    except ValueError:
        out = None
    if out is not None and (not finite or np.isfinite(out).all()):
        return out
    need = "a finite number" if finite else "numeric"
    for ln, r in zip(linenos, rows, strict=True):
        for j, v in enumerate(r):
            try:
                ok = np.isfinite(float(v)) or not finite
            except ValueError:
                ok = False
            if not ok:
                fail(source, ln, f"{label(j)} must be {need}, got {v!r}")
    raise AssertionError("unreachable")  # pragma: no cover


def first_not_increasing(t: np.ndarray, strict: bool = True) -> tuple[int, str] | None:
    """Index of the first time that does not increase, and ``"duplicate"`` or ``"decreasing"``.

    ``strict=False`` accepts equal consecutive times (only a decrease is reported).
    Returns ``None`` when the times increase throughout.
    """
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0 if strict else d < 0)
    if not bad.size:
        return None
    return int(bad[0]) + 1, ("duplicate" if d[bad[0]] == 0 else "decreasing")


def check_increasing(t: np.ndarray, linenos, source, message: Callable[[int, str], str], strict: bool = True,
                     column: str | None = None) -> None:
    """Raise naming the line of the first non-increasing time; ``message(i, kind)`` says what is wrong."""
    hit = first_not_increasing(t, strict)
    if hit is not None:
        i, kind = hit
        fail(source, linenos[i], message(i, kind), column)
