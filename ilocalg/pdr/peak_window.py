"""Step detection of the fingerprint+PDR paper: |a| peaks, a sliding search window, a threshold, 0.2-2 s.

The acceleration magnitude (eq. 3) is smoothed with a centred moving mean (the paper filters before
peak detection, step a; it gives no filter); a sample is a peak candidate when it is the largest
within a sliding search window (``window_s`` wide, centred; sec. 3.4.2 (1) item 1). Each candidate is
then judged by one of two rules:

``rule="literal"`` (default; the paper's rule b, sec. 3.4.2 (1) item 2)
    "compute the candidate's difference in value and in time from the previous peak; if the value
    difference exceeds the threshold, or the time difference is outside the time window (0.2-2 s),
    go back to step a; otherwise store it as a peak". A candidate is a step when
    ``|a - a_prev| <= threshold_mps2`` and ``min_dt_s <= t - t_prev <= max_dt_s``, where ``prev`` is
    the last stored peak. The paper does not say how the sequence starts, nor how it resumes after a
    pause (with the last stored peak more than ``max_dt_s`` back, rule b would reject every later
    candidate); here the first candidate, and the first candidate more than ``max_dt_s`` after the
    last stored peak, become the reference peak without being counted (rule b rejects them), and the
    next accepted step is flagged ``new_bout``. The threshold bounds how much consecutive peaks may
    differ; the paper gives no value (``threshold_mps2`` is an assumption that callers sweep).
``rule="valley_rise"`` (the toolkit's earlier reading)
    A candidate is a step when it rises at least ``threshold_mps2`` above the lowest value since the
    previous candidate and comes at least ``min_dt_s`` after the previous step; a gap longer than
    ``max_dt_s`` starts a new bout and the first step after it is kept.

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

__all__ = ["detect_steps_peak_window", "PeakWindowDetector", "PEAK_RULES"]

#: Candidate rules: the paper's literal rule b (default) and the valley-rise variant.
PEAK_RULES = ("literal", "valley_rise")


@register_step_detector("peak_window")
def detect_steps_peak_window(acc_mps2, t_s, window_s: float = 0.4, threshold_mps2: float = 1.0,
                             min_dt_s: float = 0.2, max_dt_s: float = 2.0, smooth_s: float = 0.1,
                             rule: str = "literal") -> pd.DataFrame:
    """Sliding-window peak search on the smoothed acceleration magnitude.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3) or (n,)
        Specific force (m/s^2), or its magnitude; uniformly sampled.
    t_s : array_like, shape (n,)
    window_s : float
        Width of the sliding search window, s.
    threshold_mps2 : float
        ``rule="literal"``: largest accepted difference from the previous peak, m/s^2;
        ``rule="valley_rise"``: least rise of a peak above the preceding valley, m/s^2.
    min_dt_s, max_dt_s : float
        The paper's time window (0.2 s, 2 s).
    smooth_s : float
        Width of the moving-mean smoothing, s (0 disables it).
    rule : {"literal", "valley_rise"}
        Candidate rule (module docstring).

    Returns
    -------
    DataFrame
        ``i_peak``, ``t_s``, ``a_max_mps2`` (smoothed peak), ``a_min_mps2`` (the lowest value since
        the previous candidate) and ``new_bout`` (True for the first step of a walking bout).

    References
    ----------
    Luo et al. (2017), sec. 3.4.2 (1)-(2).
    """
    if rule not in PEAK_RULES:
        raise ValueError(f"rule must be one of {PEAK_RULES}, got {rule!r}")
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
    keep = np.zeros(cand.size, dtype=bool)
    new_bout = np.zeros(cand.size, dtype=bool)
    if rule == "literal":
        _literal_rule_b(t[cand], y[cand], threshold_mps2, min_dt_s, max_dt_s, keep, new_bout)
        idx = cand[keep]
        return pd.DataFrame({"i_peak": idx.astype(np.int64), "t_s": t[idx], "a_max_mps2": y[idx],
                             "a_min_mps2": cmin[keep], "new_bout": new_bout[keep]})
    rise = y[cand] - cmin
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


def _literal_rule_b(tc, ac, threshold, min_dt, max_dt, keep, new_bout) -> None:
    """The paper's rule b over candidate times ``tc`` and values ``ac``; fills ``keep``, ``new_bout``."""
    ref_t, ref_a = None, 0.0
    fresh = True
    for k in range(tc.size):            # a loop over candidate peaks only (a few per second)
        if ref_t is None or tc[k] - ref_t > max_dt:
            ref_t, ref_a, fresh = tc[k], ac[k], True      # (re)start: the reference peak, not counted
            continue
        if tc[k] - ref_t < min_dt or abs(ac[k] - ref_a) > threshold:
            continue                    # rule b: back to step a, the reference stays
        keep[k] = True
        new_bout[k] = fresh
        fresh = False
        ref_t, ref_a = tc[k], ac[k]


class PeakWindowDetector:
    """Thin wrapper around :func:`detect_steps_peak_window` holding its parameters."""

    def __init__(self, window_s: float = 0.4, threshold_mps2: float = 1.0, min_dt_s: float = 0.2,
                 max_dt_s: float = 2.0, smooth_s: float = 0.1, rule: str = "literal"):
        self.window_s = window_s
        self.threshold_mps2 = threshold_mps2
        self.min_dt_s = min_dt_s
        self.max_dt_s = max_dt_s
        self.smooth_s = smooth_s
        self.rule = rule

    def detect(self, acc_mps2, t_s) -> pd.DataFrame:
        return detect_steps_peak_window(acc_mps2, t_s, self.window_s, self.threshold_mps2, self.min_dt_s,
                                        self.max_dt_s, self.smooth_s, self.rule)
