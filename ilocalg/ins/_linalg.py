"""Small dense linear algebra shared by the INS filters, without per-call overhead.

The filters solve a few-by-few system at every update (3 to 9 rows); :func:`numpy.linalg.solve` spends most of
its time there on argument checks and on entering an ``errstate`` context, not in LAPACK. :func:`solve` calls
the same LAPACK gufunc (``gesv``) with the same signature, so its result has the same bits.
"""

from __future__ import annotations

import numpy as np

try:  # numpy's own gufuncs behind np.linalg.solve (private module; numpy >= 1.8, still there in 2.x)
    from numpy.linalg import _umath_linalg as _ul

    _SOLVE1, _SOLVE = _ul.solve1, _ul.solve
except (ImportError, AttributeError):  # pragma: no cover - another numpy layout: the public function
    _SOLVE1 = _SOLVE = None

__all__ = ["solve"]


def solve(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.linalg.solve(a, b)`` for a float64 square ``a`` (n, n) and float64 ``b`` (n,) or (n, k): the same bits
    (a stack ``a`` (B, n, n) with ``b`` (B, n) or (B, n, k): each system as alone, see :func:`_solve_stacked`).

    A singular ``a`` (or any non-finite result) goes through :func:`numpy.linalg.solve` again, which raises its
    ``LinAlgError`` (numpy warns about the invalid value of the first attempt before that).
    """
    if a.ndim == 3:
        return _solve_stacked(a, b)
    if _SOLVE is None or a.dtype != np.float64 or b.dtype != np.float64 or a.ndim != 2 or b.ndim > 2:
        return np.linalg.solve(a, b)
    r = (_SOLVE1 if b.ndim == 1 else _SOLVE)(a, b, signature="dd->d")
    if not np.isfinite(r).all():
        return np.linalg.solve(a, b)
    return r


def _solve_stacked(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`solve` of each ``a[i]`` (B, n, n) with ``b[i]``, ``b`` (B, n) (vectors) or (B, n, k): the same gufuncs,
    looping over the matrices, so each result has the bits :func:`solve` gives it alone; a singular system is
    raised by :func:`solve` on that matrix."""
    if _SOLVE is None or a.dtype != np.float64 or b.dtype != np.float64:
        return np.array([solve(ai, bi) for ai, bi in zip(a, b, strict=True)])
    r = (_SOLVE1 if b.ndim == 2 else _SOLVE)(a, b, signature="dd->d")
    if not np.isfinite(r).all():
        bad = int(np.flatnonzero(~np.isfinite(r.reshape(r.shape[0], -1)).all(axis=1))[0])
        solve(a[bad], b[bad])  # raises numpy's LinAlgError for a singular matrix
        return np.array([solve(ai, bi) for ai, bi in zip(a, b, strict=True)])
    return r
