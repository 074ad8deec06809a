"""Input checks and signal helpers shared by the step detectors.

Accelerometer logs enter the detectors as arrays: ``acc_mps2`` of shape (n, 3) (specific force in
the phone frame, m/s^2) or a magnitude of shape (n,), with times ``t_s`` of shape (n,). The checks
here raise ValueError naming the parameter, the row and what was expected; nothing is dropped.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "check_acc",
    "check_times",
    "sample_rate_hz",
    "resample_uniform",
    "magnitude_mps2",
    "sliding_max",
    "sliding_min",
    "moving_mean",
]

#: Largest relative deviation of a sampling interval from the median interval accepted as "regular".
REGULAR_TOL = 0.5


def check_times(t_s, n: int | None = None, regular: bool = True, name: str = "t_s") -> np.ndarray:
    """Check times: finite, strictly increasing, optionally (nearly) uniformly sampled.

    Raises
    ------
    ValueError
        Naming the first offending row (NaN, non-increasing) or the irregular interval.
    """
    t = np.asarray(t_s, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {t.shape}")
    if n is not None and t.size != n:
        raise ValueError(f"{name} must have one time per sample ({n}), got {t.size}")
    if t.size < 2:
        raise ValueError(f"{name} needs at least 2 samples, got {t.size}")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ValueError(f"{name} is not finite at row {bad[0]}")
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise ValueError(f"{name} must be strictly increasing: row {i} ({t[i]!r}) follows {t[i - 1]!r}")
    if regular:
        med = float(np.median(d))
        dev = np.abs(d - med) / med
        bad = np.flatnonzero(dev > REGULAR_TOL)
        if bad.size:
            i = int(bad[0]) + 1
            raise ValueError(
                f"{name} is irregularly sampled: interval before row {i} is {d[bad[0]]:.6g} s against a "
                f"median of {med:.6g} s; resample first with ilocalg.pdr.resample_uniform"
            )
    return t


def check_acc(acc_mps2, min_samples: int = 2, name: str = "acc_mps2") -> np.ndarray:
    """Check an accelerometer array of shape (n, 3) or (n,): float, finite, long enough."""
    a = np.asarray(acc_mps2, dtype=np.float64)
    if a.ndim not in (1, 2) or (a.ndim == 2 and a.shape[1] != 3):
        raise ValueError(f"{name} must have shape (n, 3) or (n,), got {a.shape}")
    if a.shape[0] < min_samples:
        raise ValueError(f"{name} is too short: {a.shape[0]} samples, need at least {min_samples}")
    bad = ~np.isfinite(a)
    if bad.any():
        row = int(np.flatnonzero(bad.any(axis=1) if a.ndim == 2 else bad)[0])
        raise ValueError(f"{name} is not finite (NaN or inf) at row {row}")
    return a


def sample_rate_hz(t_s) -> float:
    """Sample rate from the median sampling interval, Hz."""
    t = np.asarray(t_s, dtype=np.float64)
    return float(1.0 / np.median(np.diff(t)))


def resample_uniform(t_s, x, rate_hz: float, t0_s: float | None = None):
    """Linearly interpolate samples ``x`` (shape (n,) or (n, k)) onto a uniform grid.

    Parameters
    ----------
    t_s : array_like, shape (n,)
        Strictly increasing sample times (any spacing), s.
    x : array_like, shape (n,) or (n, k)
    rate_hz : float
        Output rate, Hz.
    t0_s : float, optional
        First output time (default ``t_s[0]``).

    Returns
    -------
    t_out_s : ndarray, shape (m,)
    x_out : ndarray, shape (m,) or (m, k)
    """
    t = check_times(t_s, regular=False)
    xa = np.asarray(x, dtype=np.float64)
    if xa.shape[0] != t.size:
        raise ValueError(f"x must have one row per time ({t.size}), got {xa.shape[0]}")
    if not rate_hz > 0:
        raise ValueError(f"rate_hz must be > 0, got {rate_hz}")
    start = t[0] if t0_s is None else float(t0_s)
    m = int(np.floor((t[-1] - start) * rate_hz)) + 1
    t_out = start + np.arange(m) / rate_hz
    if xa.ndim == 1:
        return t_out, np.interp(t_out, t, xa)
    return t_out, np.column_stack([np.interp(t_out, t, xa[:, j]) for j in range(xa.shape[1])])


def magnitude_mps2(acc_mps2) -> np.ndarray:
    """Norm of each 3-axis sample, shape (n,) (fingerprint+PDR paper (004), eq. (3))."""
    a = np.asarray(acc_mps2, dtype=np.float64)
    return np.sqrt(np.einsum("ij,ij->i", a, a))


def sliding_max(x, left: int, right: int) -> np.ndarray:
    """Maximum of ``x[i-left : i+right+1]`` for every i (outside the log counts as -inf)."""
    from scipy.ndimage import maximum_filter1d

    x = np.asarray(x, dtype=np.float64)
    if left < 0 or right < 0:
        raise ValueError(f"left and right must be >= 0, got {left}, {right}")
    size = left + right + 1
    xp = np.concatenate([np.full(left, -np.inf), x, np.full(right, -np.inf)])
    # scipy's window at centre c starts at c - size // 2 (odd and even sizes alike)
    y = maximum_filter1d(xp, size=size, mode="nearest")
    return y[size // 2: size // 2 + x.size]


def sliding_min(x, left: int, right: int) -> np.ndarray:
    """Minimum of ``x[i-left : i+right+1]`` for every i (edges padded with +inf)."""
    return -sliding_max(-np.asarray(x, dtype=np.float64), left, right)


def moving_mean(x, n: int) -> np.ndarray:
    """Centred moving mean over ``2 n + 1`` samples (edges: mean of the available samples)."""
    x = np.asarray(x, dtype=np.float64)
    c = np.concatenate([[0.0], np.cumsum(x)])
    i = np.arange(x.size)
    lo = np.maximum(i - n, 0)
    hi = np.minimum(i + n + 1, x.size)
    return (c[hi] - c[lo]) / (hi - lo)
