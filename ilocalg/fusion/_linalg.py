"""Batched 2 x 2 linear algebra shared by the step Kalman filter and its smoothers (private helpers)."""

from __future__ import annotations

import numpy as np

__all__ = ["inv2", "matvec"]


def inv2(S):
    """Inverse of each 2 x 2 matrix of ``S`` (shape (..., 2, 2)) in closed form."""
    a, b, c, d = S[..., 0, 0], S[..., 0, 1], S[..., 1, 0], S[..., 1, 1]
    det = a * d - b * c
    out = np.empty_like(S)
    out[..., 0, 0] = d / det
    out[..., 0, 1] = -b / det
    out[..., 1, 0] = -c / det
    out[..., 1, 1] = a / det
    return out


def matvec(A, v):
    """``A @ v`` over leading batch axes: shapes (..., i, j) and (..., j) -> (..., i)."""
    return np.einsum("...ij,...j->...i", A, v)
