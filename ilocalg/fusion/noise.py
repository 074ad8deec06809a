"""Wi-Fi fix covariance from the fingerprint estimator's own spread.

The i-Loc thesis uses a fixed table of per-test-point variances (Table 5) for ``R_k``. Beyond the
paper, a (W)KNN estimator already says how uncertain it is: the weighted scatter of its ``K``
neighbours' positions around the estimate. :func:`fix_covariance_from_spread` turns that scatter
into ``R_k`` (plus a floor, so that ``K`` coincident neighbours never give a zero covariance).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Eq. (23) and Table 5 (the fixed-table alternative).
"""

from __future__ import annotations

import numpy as np

__all__ = ["fix_covariance_from_spread"]


def fix_covariance_from_spread(neighbour_xy_m, weights=None, min_var_m2: float = 1.0, scale: float = 1.0):
    """Covariance of a KNN fix from the weighted spread of its neighbours.

    Parameters
    ----------
    neighbour_xy_m : array_like, shape (n, K, 2)
        Positions of the ``K`` reference points used for each of ``n`` fixes, metres.
    weights : array_like, shape (n, K), optional
        Non-negative neighbour weights (``None``: equal weights, plain KNN). Each row must have a
        positive sum.
    min_var_m2 : float
        Added to both variances (``R = scale * C + min_var I``), m^2; must be > 0.
    scale : float
        Multiplies the scatter (> 0), e.g. to calibrate on held-out data.

    Returns
    -------
    R_m2 : ndarray, shape (n, 2, 2)
        Symmetric positive definite.
    """
    xy = np.asarray(neighbour_xy_m, dtype=np.float64)
    if xy.ndim != 3 or xy.shape[-1] != 2 or xy.shape[1] < 1:
        raise ValueError(f"neighbour_xy_m must have shape (n, K>=1, 2), got {xy.shape}")
    if not np.isfinite(xy).all():
        raise ValueError("neighbour_xy_m must be finite")
    if not (min_var_m2 > 0 and scale > 0):
        raise ValueError(f"min_var_m2 and scale must be > 0, got {min_var_m2}, {scale}")
    n, k, _ = xy.shape
    w = np.ones((n, k)) if weights is None else np.asarray(weights, dtype=np.float64)
    if w.shape != (n, k):
        raise ValueError(f"weights has shape {w.shape}, expected {(n, k)}")
    if not np.isfinite(w).all() or (w < 0).any():
        raise ValueError("weights must be finite and >= 0")
    s = w.sum(axis=1)
    bad = np.flatnonzero(s <= 0)
    if bad.size:
        raise ValueError(f"weights of fix {bad[0]} sum to zero")
    w = w / s[:, None]
    mean = np.einsum("nk,nki->ni", w, xy)
    d = xy - mean[:, None, :]
    C = np.einsum("nk,nki,nkj->nij", w, d, d)
    return scale * C + min_var_m2 * np.eye(2)
