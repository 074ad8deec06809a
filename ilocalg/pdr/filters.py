"""Sensor pre-filters: moving average and Savitzky-Golay smoothing.

Both are linear smoothers ``g(t) = sum_{i=-nL}^{nR} c_i f(t+i)`` (PSO thesis eq. 3.5). The moving
average is the special case ``c_i = 1/(nL+nR+1)`` (eq. 3.6), i.e. a Savitzky-Golay filter of order 0.
The Savitzky-Golay weights are the least-squares polynomial-fit weights (Numerical Recipes sec. 14.8,
the source of the thesis's Table 3-2).

Edges: a sample closer than ``n_left`` to the start (``n_right`` to the end) has no full window. It
gets the value, at its own position, of the polynomial fitted to the first (last) full window, the
same rule as ``scipy.signal.savgol_filter(mode="interp")``; for the moving average (order 0) this is
the mean of the first (last) full window. No sample is dropped, the output has the input's length.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Eq. 3.5-3.6 and Table 3-2; W. H. Press et al., Numerical Recipes,
sec. 14.8 (Savitzky-Golay smoothing filters).
"""

from __future__ import annotations

import numpy as np

__all__ = ["savitzky_golay_coeffs", "savitzky_golay", "moving_average", "smoother_gain", "rms"]


def _check_window(n_left: int, n_right: int, order: int) -> None:
    for name, v in (("n_left", n_left), ("n_right", n_right), ("order", order)):
        if not isinstance(v, (int, np.integer)) or isinstance(v, bool) or v < 0:
            raise ValueError(f"{name} must be a non-negative int, got {v!r}")
    if order > n_left + n_right:
        raise ValueError(f"order must be <= n_left + n_right = {n_left + n_right} "
                         f"(the window has {n_left + n_right + 1} samples), got {order}")


def _fit_matrix(window: int, order: int) -> np.ndarray:
    """``pinv(V)`` of the Vandermonde matrix over offsets 0..window-1, shape (order+1, window)."""
    offs = np.arange(window, dtype=float)
    V = np.vander(offs, order + 1, increasing=True)
    return np.linalg.pinv(V)


def savitzky_golay_coeffs(n_left: int = 2, n_right: int = 2, order: int = 2) -> np.ndarray:
    """Savitzky-Golay smoothing weights ``c_{-nL} ... c_{nR}``.

    Parameters
    ----------
    n_left, n_right : int
        Samples before and after the smoothed sample (``n_L``, ``n_R``).
    order : int
        Polynomial order ``m`` (0 gives the moving average, eq. 3.6).

    Returns
    -------
    ndarray, shape (n_left + n_right + 1,)
        Weights in time order, applied as ``g(t) = sum_i c_i f(t + i)``; they sum to 1.

    References
    ----------
    PSO thesis, eq. 3.5 and Table 3-2 (m = 2, n_L = n_R = 2: -0.086, 0.343, 0.486, 0.343, -0.086).
    """
    _check_window(n_left, n_right, order)
    window = n_left + n_right + 1
    P = _fit_matrix(window, order)
    powers = float(n_left) ** np.arange(order + 1)
    return powers @ P


def _smooth(x, n_left: int, n_right: int, order: int, name: str) -> np.ndarray:
    _check_window(n_left, n_right, order)
    x = np.asarray(x, dtype=float)
    if x.ndim != 1:
        raise ValueError(f"{name}: x must be 1-D, got shape {x.shape}")
    window = n_left + n_right + 1
    if x.size < window:
        raise ValueError(f"{name}: x has {x.size} samples, fewer than the window n_left + n_right + 1 = {window}")
    if not np.all(np.isfinite(x)):
        bad = int(np.flatnonzero(~np.isfinite(x))[0])
        raise ValueError(f"{name}: x must be finite, sample {bad} is {x[bad]}")
    P = _fit_matrix(window, order)
    c = savitzky_golay_coeffs(n_left, n_right, order)
    out = np.empty_like(x)
    # interior: full windows, g(t) = sum_i c_i f(t+i)  (eq. 3.5)
    n_full = x.size - window + 1
    out[n_left:n_left + n_full] = np.correlate(x, c, mode="valid")
    # edges: polynomial of the first / last full window evaluated at the sample's own position
    pw = np.arange(order + 1)
    if n_left:
        beta = P @ x[:window]
        out[:n_left] = (np.arange(n_left, dtype=float)[:, None] ** pw) @ beta
    if n_right:
        beta = P @ x[-window:]
        pos = np.arange(n_left + 1, window, dtype=float)
        out[-n_right:] = (pos[:, None] ** pw) @ beta
    return out


def savitzky_golay(x, n_left: int = 2, n_right: int = 2, order: int = 2) -> np.ndarray:
    """Savitzky-Golay smoothing of a 1-D signal (eq. 3.5 with the Table 3-2 weights).

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal, finite, ``n >= n_left + n_right + 1``.
    n_left, n_right : int
        Window half-widths ``n_L``, ``n_R`` (samples).
    order : int
        Polynomial order ``m``.

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal (edges: see the module docstring).

    References
    ----------
    PSO thesis, eq. 3.5, Table 3-2; Numerical Recipes sec. 14.8.
    """
    return _smooth(x, n_left, n_right, order, "savitzky_golay")


def moving_average(x, n_left: int = 2, n_right: int = 2) -> np.ndarray:
    """Moving-average filter ``g(t) = mean(f(t-nL) ... f(t+nR))`` (eq. 3.6).

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal, finite, ``n >= n_left + n_right + 1``.
    n_left, n_right : int
        Samples before and after (the thesis uses ``n_L = n_R = 2``).

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal; the first ``n_left`` (last ``n_right``) samples get the mean of the first
        (last) full window.

    References
    ----------
    PSO thesis, eq. 3.6 (MA filter, used for the experiments in ch. 5).
    """
    return _smooth(x, n_left, n_right, 0, "moving_average")


def smoother_gain(f_hz, rate_hz: float, n_left: int = 2, n_right: int = 2, order: int = 0) -> np.ndarray:
    """Amplitude gain ``|H(f)|`` of the interior smoother ``g(t) = sum_i c_i f(t+i)`` (eq. 3.5-3.6).

    ``H(f) = sum_{i=-nL}^{nR} c_i exp(2 pi j f i / rate)``. For the moving average (``order = 0``)
    with ``N = nL + nR + 1`` samples, ``|H(f)| = |sin(pi f N / rate) / (N sin(pi f / rate))|``: its
    first zero is at ``rate / N``, e.g. 1.6 Hz for ``nL = nR = 2`` at the thesis's 8 Hz, inside the
    band of walking step rates (about 1.5-2.2 Hz). This is why the moving average, which the thesis
    specifies (``nL = nR = 2``) only for its static compass and accelerometer calibration (sec. 5.1.3,
    Figs 5.4, 5.6-5.8), is not applied to the walking acceleration by default.

    Parameters
    ----------
    f_hz : array_like
        Frequencies, Hz.
    rate_hz : float
        Sampling rate, Hz.
    n_left, n_right, order : int
        Window and polynomial order, as :func:`savitzky_golay_coeffs`.

    Returns
    -------
    ndarray
        ``|H(f)|``, the shape of ``f_hz``.

    References
    ----------
    PSO thesis, eq. 3.5-3.6; Numerical Recipes sec. 14.8.
    """
    if not np.isfinite(rate_hz) or rate_hz <= 0:
        raise ValueError(f"rate_hz must be a positive number, got {rate_hz!r}")
    f = np.asarray(f_hz, dtype=float)
    c = savitzky_golay_coeffs(n_left, n_right, order)
    i = np.arange(-n_left, n_right + 1, dtype=float)
    H = np.exp(2j * np.pi * np.multiply.outer(f, i) / rate_hz) @ c
    return np.abs(H)


def rms(x) -> float:
    """Root-mean-square deviation about the mean, ``sqrt(sum (x_i - mean)^2 / n)`` (eq. 3.4).

    References
    ----------
    PSO thesis, eq. 3.4 (static calibration error measure).
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"rms: x must be a non-empty 1-D array, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("rms: x must be finite")
    return float(np.sqrt(np.mean((x - x.mean()) ** 2)))
