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
    "moving_mean",
    "moving_mean_time",
    "acc_from_log",
    "gravity_lowpass_mps2",
    "along_gravity_mps2",
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


def resample_uniform(x, t_s, rate_hz: float, t0_s: float | None = None):
    """Linearly interpolate samples ``x`` (shape (n,) or (n, k)) onto a uniform grid.

    Parameters
    ----------
    x : array_like, shape (n,) or (n, k)
    t_s : array_like, shape (n,)
        Strictly increasing sample times (any spacing), s.
    rate_hz : float
        Output rate, Hz.
    t0_s : float, optional
        First output time (default ``t_s[0]``).

    Returns
    -------
    x_out : ndarray, shape (m,) or (m, k)
    t_out_s : ndarray, shape (m,)
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
        return np.interp(t_out, t, xa), t_out
    return np.column_stack([np.interp(t_out, t, xa[:, j]) for j in range(xa.shape[1])]), t_out


def magnitude_mps2(acc_mps2) -> np.ndarray:
    """Norm of each 3-axis sample, shape (n,) (Luo et al. (2017), eq. (3))."""
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


def moving_mean(x, n: int) -> np.ndarray:
    """Centred moving mean over ``2 n + 1`` samples (edges: mean of the available samples).

    The toolkit's one moving mean over a sample count; :func:`moving_mean_time` is the same mean
    over a time window for irregular samples. (The PSO thesis's MA pre-filter,
    :func:`ilocalg.pdr.filters.moving_average`, is a Savitzky-Golay filter of order 0 with the
    thesis's edge rule, not a second copy of this.)
    """
    x = np.asarray(x, dtype=np.float64)
    c = np.concatenate([[0.0], np.cumsum(x)])
    i = np.arange(x.size)
    lo = np.maximum(i - n, 0)
    hi = np.minimum(i + n + 1, x.size)
    return (c[hi] - c[lo]) / (hi - lo)


def moving_mean_time(x, t_s, window_s: float) -> np.ndarray:
    """Centred moving mean over a time window of ``window_s`` seconds (irregular samples allowed).

    Sample ``i`` averages every sample with ``|t_j - t_i| <= window_s / 2`` (edges: the available
    samples), via cumulative sums.

    Parameters
    ----------
    x : array_like, shape (n,)
    t_s : array_like, shape (n,)
        Non-decreasing times, s.
    window_s : float
        Window width, s (>= 0; 0 returns ``x``: each window holds only its own sample).
    """
    x = np.asarray(x, dtype=np.float64)
    t = np.asarray(t_s, dtype=np.float64)
    if t.shape != x.shape:
        raise ValueError(f"t_s must have the shape of x {x.shape}, got {t.shape}")
    if not (np.isfinite(window_s) and window_s >= 0):
        raise ValueError(f"window_s must be finite and >= 0 seconds, got {window_s}")
    cs = np.concatenate([[0.0], np.cumsum(x)])
    lo = np.searchsorted(t, t - window_s / 2, side="left")
    hi = np.searchsorted(t, t + window_s / 2, side="right")
    return (cs[hi] - cs[lo]) / (hi - lo)


def acc_from_log(imu) -> tuple[np.ndarray, np.ndarray]:
    """Accelerometer array and times of a sensor log (the package's DataFrame indexed by time, s).

    Returns
    -------
    acc_mps2 : ndarray, shape (n, 3)
        Columns :data:`ilocalg.io.schema.ACC_COLS`, m/s^2.
    t_s : ndarray, shape (n,)
        The log's index, s.
    """
    from ilocalg.io.schema import ACC_COLS

    missing = [c for c in ACC_COLS if c not in imu.columns]
    if missing:
        raise ValueError(f"sensor log lacks accelerometer columns {missing}")
    return imu[list(ACC_COLS)].to_numpy(), imu.index.to_numpy()


def gravity_lowpass_mps2(acc_mps2, half_width: int) -> np.ndarray:
    """Gravity in the phone frame as the moving mean of each accelerometer axis, shape (n, 3).

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3)
    half_width : int
        Samples either side (:func:`moving_mean` over ``2 half_width + 1`` samples; about 1 s
        of data is the usual choice).
    """
    a = check_acc(acc_mps2, min_samples=1)
    if a.ndim != 2:
        raise ValueError(f"acc_mps2 must have shape (n, 3), got {a.shape}")
    if int(half_width) != half_width or half_width < 0:
        raise ValueError(f"half_width must be a non-negative int, got {half_width!r}")
    return np.column_stack([moving_mean(a[:, j], int(half_width)) for j in range(3)])


def along_gravity_mps2(acc_mps2, g_mps2) -> np.ndarray:
    """Specific force along the gravity direction, ``a_i . g_i / |g_i|``, shape (n,).

    Positive (about +9.8 m/s^2) for a phone at rest. ``g_mps2`` is one vector (3,) or one per
    sample (n, 3), e.g. :func:`gravity_lowpass_mps2`.
    """
    a = check_acc(acc_mps2, min_samples=1)
    if a.ndim != 2:
        raise ValueError(f"acc_mps2 must have shape (n, 3), got {a.shape}")
    g = np.asarray(g_mps2, dtype=np.float64)
    if g.shape not in ((3,), a.shape):
        raise ValueError(f"g_mps2 must have shape (3,) or {a.shape}, got {g.shape}")
    n0 = np.linalg.norm(g, axis=-1)
    if np.any(~np.isfinite(n0)) or np.any(n0 <= 0):
        raise ValueError("g_mps2 must be a finite non-zero vector")
    if g.ndim == 1:
        return a @ (g / n0)
    return np.einsum("ij,ij->i", a, g / n0[:, None])
