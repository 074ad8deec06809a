"""Step detection of the fingerprint+PDR paper: |a| peaks, a sliding search window, a threshold, 0.2-2 s.

The acceleration magnitude (eq. 3) is smoothed with a centred moving mean; a sample is a peak
candidate when it is the largest within a sliding search window (``window_s`` wide, centred); a
candidate is a step when it rises at least ``threshold_mps2`` above the lowest value since the
previous candidate and comes at least ``min_dt_s`` (0.2 s) after the previous step. A gap longer
than ``max_dt_s`` (2 s) ends a walking bout: the next step starts a new bout (the paper's time
window rejects intervals outside 0.2-2 s; the first step after a pause is kept, since a pause is
not an error).

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Sec. 3.4.1-3.4.2, eq. (3), Fig 5.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.pdr.registry import register_step_detector
from ilocalg.pdr.signals import check_acc, check_times, magnitude_mps2, moving_mean, sample_rate_hz, sliding_max

__all__ = ["detect_steps_peak_window", "PeakWindowDetector"]


@register_step_detector("peak_window")
def detect_steps_peak_window(acc_mps2, t_s, window_s: float = 0.4, threshold_mps2: float = 1.0,
                             min_dt_s: float = 0.2, max_dt_s: float = 2.0, smooth_s: float = 0.1) -> pd.DataFrame:
    """Sliding-window peak search on the smoothed acceleration magnitude.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3) or (n,)
        Specific force (m/s^2), or its magnitude; uniformly sampled.
    t_s : array_like, shape (n,)
    window_s : float
        Width of the sliding search window, s.
    threshold_mps2 : float
        Least rise of a peak above the preceding valley, m/s^2.
    min_dt_s, max_dt_s : float
        The paper's time window (0.2 s, 2 s).
    smooth_s : float
        Width of the moving-mean smoothing, s (0 disables it).

    Returns
    -------
    DataFrame
        ``i_peak``, ``t_s``, ``a_max_mps2`` (smoothed peak), ``a_min_mps2`` (the preceding valley)
        and ``new_bout`` (True for the first step after a gap longer than ``max_dt_s``).

    References
    ----------
    Luo et al. (2017), sec. 3.4.2 (1)-(2).
    """
    a = check_acc(acc_mps2, min_samples=3)
    t = check_times(t_s, n=a.shape[0])
    if not (0 < min_dt_s < max_dt_s):
        raise ValueError(f"need 0 < min_dt_s < max_dt_s, got {min_dt_s}, {max_dt_s}")
    rate = sample_rate_hz(t)
    m = magnitude_mps2(a) if a.ndim == 2 else a
    ns = int(round(0.5 * smooth_s * rate))
    y = moving_mean(m, ns) if ns > 0 else m
    h = max(int(round(0.5 * window_s * rate)), 1)
    mx = sliding_max(y, h, h)
    left = sliding_max(np.concatenate([[-np.inf], y[:-1]]), h - 1, 0)
    cand = np.flatnonzero((y >= mx) & (y > left))
    # lowest value between consecutive candidates (and from the start before the first)
    cmin = np.minimum.reduceat(y, np.concatenate([[0], cand[:-1]])) if cand.size else np.array([])
    rise = y[cand] - cmin
    keep = np.zeros(cand.size, dtype=bool)
    new_bout = np.zeros(cand.size, dtype=bool)
    last_t = -np.inf
    for k in range(cand.size):          # a loop over candidate peaks only (a few per second)
        if rise[k] < threshold_mps2:
            continue
        dt = t[cand[k]] - last_t
        if dt < min_dt_s:
            continue
        keep[k] = True
        new_bout[k] = dt > max_dt_s
        last_t = t[cand[k]]
    idx = cand[keep]
    return pd.DataFrame({"i_peak": idx.astype(np.int64), "t_s": t[idx], "a_max_mps2": y[idx],
                         "a_min_mps2": cmin[keep], "new_bout": new_bout[keep]})


class PeakWindowDetector:
    """Thin wrapper around :func:`detect_steps_peak_window` holding its parameters."""

    def __init__(self, window_s: float = 0.4, threshold_mps2: float = 1.0, min_dt_s: float = 0.2,
                 max_dt_s: float = 2.0, smooth_s: float = 0.1):
        self.window_s = window_s
        self.threshold_mps2 = threshold_mps2
        self.min_dt_s = min_dt_s
        self.max_dt_s = max_dt_s
        self.smooth_s = smooth_s

    def detect(self, acc_mps2, t_s) -> pd.DataFrame:
        return detect_steps_peak_window(acc_mps2, t_s, self.window_s, self.threshold_mps2, self.min_dt_s,
                                        self.max_dt_s, self.smooth_s)
