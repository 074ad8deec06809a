"""Step detection from prominent peaks of the smoothed specific-force norm, for irregular sampling.

The smartphone INS's step detector: the norm of the specific force is smoothed by a centred moving
mean over a time window (the samples of a phone arrive at irregular 14-20 Hz intervals, so the
window is in seconds, not samples); a step is a peak of at least ``min_prominence_mps2`` prominence
and at least ``min_interval_s`` after the previous one (:func:`scipy.signal.find_peaks`; the
distance is converted to samples with the median sampling interval). Its step epochs feed the step
frequency ``F`` of the walking-velocity constraint (Liao et al. 2016, eq. 7).

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 3.2 (steps for the walking-velocity constraint; the paper does
not describe its detector, this one is the toolkit's); Chen, Pei, Chen (2011), ION GNSS (step model).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.signal import find_peaks

from ilocalg.pdr.registry import register_step_detector
from ilocalg.pdr.signals import check_acc, check_times, moving_mean_time

__all__ = ["detect_steps_norm_peaks"]


@register_step_detector("norm_peaks")
def detect_steps_norm_peaks(acc_mps2, t_s, min_interval_s: float = 0.3, min_prominence_mps2: float = 0.8,
                            smooth_s: float = 0.15) -> pd.DataFrame:
    """Steps at prominent peaks of the time-window-smoothed specific-force norm.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3) or (n,)
        Specific force (m/s^2) in any frame, or its norm.
    t_s : array_like, shape (n,)
        Strictly increasing times, s (irregular sampling is fine).
    min_interval_s : float
        Shortest step period accepted, s.
    min_prominence_mps2 : float
        Least peak prominence, m/s^2.
    smooth_s : float
        Width of the moving mean applied to the norm first, s.

    Returns
    -------
    DataFrame
        One row per step: ``i_peak`` (sample index), ``t_s``, ``a_max_mps2`` (smoothed norm at the
        peak), ``a_min_mps2`` (the lower of the peak's two bases) and ``prominence_mps2``.

    References
    ----------
    Liao et al. (2016), sec. 3.2 (the steps of the walking-velocity constraint).
    """
    a = check_acc(acc_mps2, min_samples=3)
    t = check_times(t_s, n=a.shape[0], regular=False)
    if not (min_interval_s > 0 and min_prominence_mps2 >= 0):
        raise ValueError(f"min_interval_s must be > 0 and min_prominence_mps2 >= 0, got {min_interval_s}, "
                         f"{min_prominence_mps2}")
    norm = moving_mean_time(np.linalg.norm(a, axis=1) if a.ndim == 2 else a, t, smooth_s)
    dt = float(np.median(np.diff(t)))
    peaks, props = find_peaks(norm, distance=max(1, int(round(min_interval_s / dt))), prominence=min_prominence_mps2)
    base = np.minimum(norm[props["left_bases"]], norm[props["right_bases"]])
    return pd.DataFrame({"i_peak": peaks.astype(np.int64), "t_s": t[peaks], "a_max_mps2": norm[peaks],
                         "a_min_mps2": base, "prominence_mps2": props["prominences"]})
