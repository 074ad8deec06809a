"""Gait statistics: step-to-step variability, amplitude at equal length and speed, gait correlations.

Two kinds of input, both shaped like the toolkit's recordings:

Steps with true times (Oxford step counter, simulator truth)
    :func:`step_series` cuts the accelerometer magnitude at the true foot contacts and returns per
    step its peak-to-peak period ``T`` (s) and peak-to-trough amplitude ``A`` (m/s^2, of the
    magnitude low-passed at 3 Hz, the band of the toolkit's detectors). :func:`step_variability` gives the within-walk
    coefficients of variation of ``T`` and ``A`` over steady walking (periods within 0.6-1.6 x the
    walk's median; the turn-around and start/stop steps excluded).
Segments between surveyed waypoints (ILC walks)
    :func:`segment_gait` counts detected steps (:func:`ilocalg.pdr.robust.detect_steps_robust`)
    between consecutive waypoints and returns per segment the mean step length ``SL`` (straight
    distance / steps), mean period ``T``, speed and mean amplitude ``A``. Across segments
    :func:`gait_correlations` gives corr(A, SL), corr(T, SL) and the relative spread of ``A`` at
    equal ``SL`` and speed (residual sd of ``A ~ SL + speed`` over the mean ``A``).

References
----------
Hausdorff, J. M. et al. (1995). Walking is more like catching a controlled fall. J. Appl. Physiol.
(stride-time variability of healthy adults, CV about 2-3 %).
Chiu (2013), Table 3 (the thesis's step features; its implied correlations are references only).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import signal as ss

from ilocalg.pdr.robust import detect_steps_robust

__all__ = ["lowpass_norm", "step_series", "step_variability", "segment_gait", "gait_correlations",
           "gait_correlation_arrays", "STEADY_BAND"]

#: step periods within this band of the walk's median period count as steady walking
STEADY_BAND = (0.6, 1.6)


def lowpass_norm(acc_mps2, t_s, rate_hz: float = 100.0, cutoff_hz: float = 3.0):
    """Magnitude of the specific force resampled to ``rate_hz`` and low-passed (4th-order Butterworth,
    zero phase). Returns ``(t_s, a_mps2)``."""
    a = np.asarray(acc_mps2, dtype=np.float64)
    t = np.asarray(t_s, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3 or a.shape[0] != t.size:
        raise ValueError(f"acc_mps2 must be (n, 3) matching t_s (n,), got {a.shape} and {t.shape}")
    m = np.linalg.norm(a, axis=1)
    tu = np.arange(t[0], t[-1], 1.0 / rate_hz)
    mu = np.interp(tu, t, m)
    b, c = ss.butter(4, cutoff_hz / (rate_hz / 2.0))
    return tu, ss.filtfilt(b, c, mu)


def step_series(acc_mps2, t_s, step_t_s, rate_hz: float = 100.0) -> pd.DataFrame:
    """Per true step: ``t_s`` (time of the acceleration peak), ``T_s`` (peak-to-peak period), ``A_mps2``.

    Each true contact owns the window of +-half the walk's median contact interval around it; the
    step's peak is the maximum of the low-passed norm in that window (timed to a fraction of a
    sample by parabolic interpolation) and ``A`` its peak-to-trough range there. Periods are taken between
    the peaks (the phone's view of cadence; the Oxford heel-sensor contact times are quantised at
    about 48 ms, too coarse for step-to-step variability).
    """
    tu, y = lowpass_norm(acc_mps2, t_s, rate_hz)
    st = np.sort(np.asarray(step_t_s, dtype=np.float64))
    st = st[(st >= tu[0]) & (st <= tu[-1])]
    if st.size < 4:
        raise ValueError(f"step_series needs >= 4 steps inside the log, got {st.size}")
    half = 0.5 * np.median(np.diff(st))
    lo = np.searchsorted(tu, st - half)
    hi = np.searchsorted(tu, st + half)
    tp, amp = [], []
    for i, j in zip(lo, hi, strict=True):
        if j - i < 2:
            continue
        seg = y[i:j]
        k = int(np.argmax(seg))
        dk = 0.0
        if 0 < k < seg.size - 1:  # parabolic interpolation of the peak: sub-sample timing
            den = seg[k - 1] - 2 * seg[k] + seg[k + 1]
            dk = 0.5 * (seg[k - 1] - seg[k + 1]) / den if den < 0 else 0.0
        tp.append(tu[i + k] + dk / rate_hz)
        amp.append(float(np.ptp(seg)))
    tp = np.asarray(tp)
    return pd.DataFrame({"t_s": tp[1:], "T_s": np.diff(tp), "A_mps2": np.asarray(amp)[1:]})


def step_variability(steps: pd.DataFrame) -> dict:
    """Within-walk coefficients of variation of period and amplitude over steady steps.

    Returns ``cv_T, cv_A, n_steps``; ``rcv_T, rcv_A`` the robust versions (1.4826 MAD / median,
    insensitive to the few turning and stopping steps left in the band); ``cv_dT`` the CV of
    successive differences / sqrt 2 (insensitive to slow drifts of pace); ``cv_stride`` the robust
    CV of two-step strides (insensitive to left/right alternation).
    """
    T = steps["T_s"].to_numpy()
    A = steps["A_mps2"].to_numpy()
    med = np.median(T)
    ok = (T > STEADY_BAND[0] * med) & (T < STEADY_BAND[1] * med) & np.isfinite(A)
    T, A = T[ok], A[ok]
    if T.size < 5:
        return {"cv_T": np.nan, "cv_A": np.nan, "cv_dT": np.nan, "rcv_T": np.nan, "rcv_A": np.nan,
                "cv_stride": np.nan, "n_steps": int(T.size)}
    stride = T[: T.size // 2 * 2].reshape(-1, 2).sum(axis=1)
    return {"cv_T": float(T.std(ddof=1) / T.mean()), "cv_A": float(A.std(ddof=1) / A.mean()),
            "cv_dT": float(np.diff(T).std(ddof=1) / np.sqrt(2) / T.mean()),
            "rcv_T": _rcv(T), "rcv_A": _rcv(A), "cv_stride": _rcv(stride), "n_steps": int(T.size)}


def _rcv(x) -> float:
    """Robust coefficient of variation: 1.4826 MAD / median."""
    med = np.median(x)
    return float(1.4826 * np.median(np.abs(x - med)) / med)


#: The step detector's settings for the gait statistics: walk detection at bout ends (``min_stride_nac``) is off.
#: It was chosen on the Oxford step-counter recordings; the ILC walks start with their recording, where it
#: drops a walk's first peaks (site1 F1: 98 peaks in 59 of 100 walks, the first step later by > 0.5 s in 18),
#: and the measured parameters and the worlds calibrated on them were measured without it.
GAIT_DETECTOR_PARAMS = {"min_stride_nac": None}


def segment_gait(acc_mps2, t_s, waypoints_t_s, waypoints_xy_m, min_steps: int = 4, min_dist_m: float = 2.0,
                 detector_params: dict | None = None) -> pd.DataFrame:
    """Per waypoint-to-waypoint segment: ``SL_m, T_s, speed_mps, A_mps2, n_steps, dist_m, dt_s``.

    Steps are detected on the whole walk (:func:`ilocalg.pdr.robust.detect_steps_robust`, its defaults but
    without the walk detection at bout ends, :data:`GAIT_DETECTOR_PARAMS`) and counted by their peak time
    inside each segment; ``A`` is the mean peak-to-base amplitude of those steps.
    """
    t = np.asarray(t_s, dtype=np.float64)
    st = detect_steps_robust(acc_mps2, t, **(GAIT_DETECTOR_PARAMS if detector_params is None else detector_params))
    ts, amp = st["t_s"].to_numpy(), (st["a_max_mps2"] - st["a_min_mps2"]).to_numpy()
    wt = np.asarray(waypoints_t_s, dtype=np.float64)
    wxy = np.asarray(waypoints_xy_m, dtype=np.float64)
    rows = []
    for k in range(wt.size - 1):
        sel = (ts >= wt[k]) & (ts < wt[k + 1])
        n = int(sel.sum())
        dist = float(np.hypot(*(wxy[k + 1] - wxy[k])))
        dt = float(wt[k + 1] - wt[k])
        if n < min_steps or dist < min_dist_m:
            continue
        rows.append({"SL_m": dist / n, "T_s": dt / n, "speed_mps": dist / dt, "A_mps2": float(amp[sel].mean()),
                     "n_steps": n, "dist_m": dist, "dt_s": dt})
    return pd.DataFrame(rows, columns=["SL_m", "T_s", "speed_mps", "A_mps2", "n_steps", "dist_m", "dt_s"])


def gait_correlations(seg: pd.DataFrame) -> dict:
    """corr(A, SL), corr(T, SL) (Pearson) and the relative residual sd of ``A ~ 1 + SL + speed``."""
    return gait_correlation_arrays(*(seg[c].to_numpy() for c in ("A_mps2", "SL_m", "T_s", "speed_mps")))


def gait_correlation_arrays(A, SL, T, v) -> dict:
    """:func:`gait_correlations` of the segments' columns ``A_mps2, SL_m, T_s, speed_mps`` given as arrays (n,)
    (the same numbers without a DataFrame: a bootstrap calls it once per replicate)."""
    if len(A) < 5:
        return {"corr_A_SL": np.nan, "corr_T_SL": np.nan, "A_resid_rel": np.nan}
    X = np.column_stack([np.ones_like(SL), SL, v])
    beta, *_ = np.linalg.lstsq(X, A, rcond=None)
    res = A - X @ beta
    return {"corr_A_SL": float(np.corrcoef(A, SL)[0, 1]), "corr_T_SL": float(np.corrcoef(T, SL)[0, 1]),
            "A_resid_rel": float(res.std(ddof=3) / A.mean())}
