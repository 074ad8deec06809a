"""Step detection by slope sign change with the +-RMS rejection band (PSO thesis Fig. 3.9).

The vertical acceleration is optionally smoothed with the moving average (eq. 3.6), then

A. step detection: where the sign of ``g(t) - g(t-1)`` changes, ``g(t-1)`` is a local maximum
   (``+`` to ``-``) or a local minimum (``-`` to ``+``);
B. false detection: (1) no sign change means no extremum; (2) a maximum or minimum whose value lies
   inside ``[-RMS, +RMS]`` (about the signal mean, RMS by eq. 3.4) is eliminated.

Readings (Chao 2008, line numbers of the thesis's text copy). The thesis specifies MA(nL = nR = 2)
only for its static compass and accelerometer calibration (L713, L735-743; "MA is used in the
experiments", L718, gives no width for the walking signal). At the thesis's 8 Hz, MA(2,2) has its
first zero at 1.6 Hz, inside the walking step-rate band (:func:`ilocalg.pdr.filters.smoother_gain`),
so by default no moving average is applied (``smooth=False``); widths 1 and 2 are options. RMS
(eq. 3.4, L440-444) is defined for the static calibration (L699-701: the static experiment gives
"the error range for the correction of eq. 4.4"), so the band's half-width is by default the RMS of
a static log (:func:`static_rms_mps2`, passed as ``rms_mps2``); without it the RMS of the walking
signal itself is used (the alternative reading).

One step is one surviving maximum followed by a surviving minimum. Fig. 3.9 does not say what to do
when two maxima survive with no minimum between them; here the larger one is kept (likewise the
smaller of two minima), so that each step counts once. Flat runs (equal consecutive samples, common
with quantised sensors) carry the previous slope sign, so a plateau gives one extremum at its first
sample.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Sec. 3.4.1 and Fig. 3.9 (after Lei Fang et al., NavMote).
RMS
eq. 3.4; MA filter eq. 3.6.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.pdr.filters import moving_average
from ilocalg.pdr.registry import register_step_detector
from ilocalg.pdr.signals import along_gravity_mps2, gravity_lowpass_mps2

__all__ = ["STEP_COLUMNS", "slope_sign_extrema", "detect_steps_sign_change", "static_rms_mps2"]

#: Columns of the step table every detector returns (one row per detected step).
STEP_COLUMNS = ("i_peak", "t_s", "a_max_mps2", "a_min_mps2", "i_valley", "t_valley_s")


def slope_sign_extrema(g) -> tuple[np.ndarray, np.ndarray]:
    """Indices of local maxima and minima by slope sign change (Fig. 3.9 part A).

    Parameters
    ----------
    g : array_like, shape (n,)
        Smoothed signal.

    Returns
    -------
    i_max, i_min : ndarray of int
        ``t-1`` for every ``t`` where ``sign(g(t) - g(t-1))`` changes from + to - (maxima) or from -
        to + (minima). Zero slopes carry the previous non-zero sign.
    """
    g = np.asarray(g, dtype=float)
    d = np.sign(np.diff(g))
    # carry the previous non-zero sign over flat runs
    nz = np.flatnonzero(d)
    if nz.size == 0:
        return np.array([], dtype=np.int64), np.array([], dtype=np.int64)
    idx = np.maximum.accumulate(np.where(d != 0, np.arange(d.size), -1))
    filled = np.where(idx >= 0, d[np.maximum(idx, 0)], 0.0)
    # plateau start: the extremum sits at the first sample of the flat run
    change = np.flatnonzero((filled[1:] != filled[:-1]) & (filled[:-1] != 0))  # change between d[j] and d[j+1]
    prev_sign = filled[change]
    # first sample of the plateau = index after the last non-zero slope before the change
    last_nz = idx[change]
    i_ext = last_nz + 1
    i_max = i_ext[prev_sign > 0].astype(np.int64)
    i_min = i_ext[prev_sign < 0].astype(np.int64)
    return i_max, i_min


def static_rms_mps2(static_acc_mps2, n_left: int = 2, n_right: int = 2, smooth: bool = False) -> float:
    """RMS (eq. 3.4) of a static accelerometer log, after the same pre-filter as the walking signal.

    The half-width of the +-RMS band of Fig. 3.9 in the thesis's reading (module docstring).

    References
    ----------
    PSO thesis, eq. 3.4 and sec. 5.1.3 (static calibration).
    """
    a = np.asarray(static_acc_mps2, dtype=float)
    if a.ndim != 1 or a.size < 3 or not np.all(np.isfinite(a)):
        raise ValueError(f"static_acc_mps2 must be a finite 1-D log of >= 3 samples, got shape {a.shape}")
    g = moving_average(a, n_left, n_right) if smooth else a
    return float(np.sqrt(np.mean((g - g.mean()) ** 2)))


@register_step_detector("sign_change")
def detect_steps_sign_change(acc_mps2, t_s, n_left: int = 2, n_right: int = 2, smooth: bool = False,
                             rms_mps2: float | None = None, gravity_half_width: int = 50) -> pd.DataFrame:
    """Detect steps on vertical acceleration by slope sign change and the +-RMS band.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n,) or (n, 3)
        Vertical (z) acceleration, m/s^2, with or without gravity (the band is centred on the mean);
        or a 3-axis log, whose specific force along gravity is used
        (:func:`~ilocalg.pdr.signals.along_gravity_mps2` with gravity the moving mean over
        ``2 gravity_half_width + 1`` samples, :func:`~ilocalg.pdr.signals.gravity_lowpass_mps2`).
    t_s : array_like, shape (n,)
        Sample times, s, strictly increasing.
    n_left, n_right : int
        Moving-average window (eq. 3.6); ignored when ``smooth`` is False.
    smooth : bool
        Apply the moving average first (default False: see the module docstring).
    rms_mps2 : float, optional
        Half-width of the rejection band, m/s^2: the static-noise RMS (:func:`static_rms_mps2`, the
        thesis's reading). None: the RMS of the (filtered) walking signal about its mean (eq. 3.4
        applied to the walk, the alternative reading).
    gravity_half_width : int
        Gravity low-pass half-width, samples, for a 3-axis ``acc_mps2`` (50: 1 s at 100 Hz).

    Returns
    -------
    DataFrame
        One row per step with columns :data:`STEP_COLUMNS`: ``i_peak`` (sample index of the maximum),
        ``t_s`` (its time), ``a_max_mps2`` and ``a_min_mps2`` (smoothed acceleration at the maximum
        and at the following minimum, m/s^2, gravity included if it was in the input), ``i_valley``,
        ``t_valley_s``. Empty (with these columns) when no step is found.

    References
    ----------
    PSO thesis, Fig. 3.9, eq. 3.4, eq. 3.6.
    """
    a = np.asarray(acc_mps2, dtype=float)
    t = np.asarray(t_s, dtype=float)
    if a.ndim == 2 and a.shape[1] == 3:
        a = along_gravity_mps2(a, gravity_lowpass_mps2(a, gravity_half_width))
    if a.ndim != 1:
        raise ValueError(f"acc_mps2 must have shape (n,) or (n, 3), got {a.shape}")
    if t.shape != a.shape:
        raise ValueError(f"t_s must have the shape of acc_mps2 {a.shape}, got {t.shape}")
    if a.size < 3:
        raise ValueError(f"acc_mps2 needs at least 3 samples, got {a.size}")
    for name, v in (("acc_mps2", a), ("t_s", t)):
        if not np.all(np.isfinite(v)):
            bad = int(np.flatnonzero(~np.isfinite(v))[0])
            raise ValueError(f"{name} must be finite, sample {bad} is {v[bad]}")
    if np.any(np.diff(t) <= 0):
        bad = int(np.flatnonzero(np.diff(t) <= 0)[0]) + 1
        raise ValueError(f"t_s must be strictly increasing, sample {bad} is not")
    g = moving_average(a, n_left, n_right) if smooth else a
    mean = float(g.mean())
    if rms_mps2 is None:
        band = float(np.sqrt(np.mean((g - mean) ** 2)))
    else:
        band = float(rms_mps2)
        if not np.isfinite(band) or band < 0:
            raise ValueError(f"rms_mps2 must be a finite non-negative number, got {rms_mps2!r}")
    i_max, i_min = slope_sign_extrema(g)
    # B.2: eliminate extrema inside [-RMS, +RMS] about the mean
    i_max = i_max[g[i_max] - mean > band]
    i_min = i_min[g[i_min] - mean < -band]
    # merge into an alternating max/min sequence (keep the more extreme of same-type neighbours)
    idx = np.concatenate([i_max, i_min])
    kind = np.concatenate([np.ones(i_max.size, dtype=np.int8), -np.ones(i_min.size, dtype=np.int8)])
    order = np.argsort(idx, kind="stable")
    idx, kind = idx[order], kind[order]
    seq_i: list[int] = []
    seq_k: list[int] = []
    for i, k in zip(idx.tolist(), kind.tolist(), strict=True):
        if seq_k and seq_k[-1] == k:
            j = seq_i[-1]
            if (k > 0 and g[i] > g[j]) or (k < 0 and g[i] < g[j]):
                seq_i[-1] = i
            continue
        seq_i.append(i)
        seq_k.append(k)
    peaks, valleys = [], []
    for n in range(len(seq_i) - 1):
        if seq_k[n] > 0 and seq_k[n + 1] < 0:
            peaks.append(seq_i[n])
            valleys.append(seq_i[n + 1])
    ip = np.asarray(peaks, dtype=np.int64)
    iv = np.asarray(valleys, dtype=np.int64)
    return pd.DataFrame({
        "i_peak": ip,
        "t_s": t[ip],
        "a_max_mps2": g[ip],
        "a_min_mps2": g[iv],
        "i_valley": iv,
        "t_valley_s": t[iv],
    })
