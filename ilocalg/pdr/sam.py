"""SAM, the i-Loc stepping aware module: vertical acceleration, wave features, range classifier.

A walk's accelerometer log is projected on the gravity direction at rest ``g0``; every local peak
of the vertical component with no larger value within ``W_peak / 2`` on either side, together with
its left and right valleys (minima within ``W_wave / 2``), forms a *wave* with eight features
(T1, T2, T, A1, A2, A, I, X1). A wave is a step when seven of them (all but A1, as in the thesis)
lie inside ranges learned as the [5 %, 95 %] quantiles of the features of training steps.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1, eq. (8)-(15), Table 1, Figs 7-12.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.pdr.registry import register_step_detector
from ilocalg.pdr.signals import along_gravity_mps2, check_acc, check_times, sample_rate_hz, sliding_max

__all__ = [
    "SAM_FEATURES",
    "SAM_TESTED_FEATURES",
    "SAM_RANGES_PAPER",
    "vertical_horizontal_mps2",
    "seconds_to_samples",
    "sam_waves",
    "learn_feature_ranges",
    "in_ranges",
    "range_bounds",
    "passes_ranges",
    "detect_steps_sam",
    "SAMDetector",
    "match_waves_to_steps",
]

#: The eight wave features of eq. (8)-(15), in the thesis's order.
SAM_FEATURES = ("T1", "T2", "T", "A1", "A2", "A", "I", "X1")
#: The features the thesis tests against their ranges (A1 is listed in Table 1 but not tested).
SAM_TESTED_FEATURES = ("A2", "A", "T1", "T2", "T", "X1", "I")

# Settings from the paper
# -----------------------
# SAM_RANGES_PAPER: Chiu (2013) Table 1, min and max of each SAM feature (s, m/s^2).
#: i-Loc thesis Table 1 (paper values: min, max of each feature; seconds and m/s^2).
SAM_RANGES_PAPER = pd.DataFrame(
    {"min": [0.08, 0.10, 0.36, 2.15, 1.72, 4.24, 0.6, 3.79],
     "max": [0.35, 0.40, 0.62, 8.98, 8.37, 16.77, 1.8, 38.0]},
    index=pd.Index(SAM_FEATURES, name="feature"),
)


def vertical_horizontal_mps2(acc_mps2, g0_mps2=None):
    """Vertical and horizontal parts of the acceleration relative to gravity at rest.

    ``a_perp_i = |g0| - g_i . g0 / |g0|`` (the thesis's vertical component, positive when the
    specific force along gravity drops below 1 g) and ``a_par_i = |g_i - (g_i . u) u|``, the norm
    of the component orthogonal to ``u = g0 / |g0|``.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3)
        Specific force in the phone frame, m/s^2.
    g0_mps2 : array_like, shape (3,) or (n, 3), optional
        Gravity at rest in the phone frame; default the mean of ``acc_mps2`` over the log. A
        per-sample array allows a slowly changing attitude (e.g. a low-pass of the log).

    Returns
    -------
    a_perp_mps2, a_par_mps2 : ndarray, shape (n,)

    References
    ----------
    Chiu (2013), sec. 4.1 (definition of a_perp before eq. (8)).
    """
    a = check_acc(acc_mps2, min_samples=1)
    if a.ndim != 2:
        raise ValueError(f"acc_mps2 must have shape (n, 3), got {a.shape}")
    g0 = a.mean(axis=0) if g0_mps2 is None else np.asarray(g0_mps2, dtype=np.float64)
    if g0.shape not in ((3,), a.shape):
        raise ValueError(f"g0_mps2 must have shape (3,) or {a.shape}, got {g0.shape}")
    n0 = np.linalg.norm(g0, axis=-1)
    if np.any(~np.isfinite(n0)) or np.any(n0 <= 0):
        raise ValueError("g0_mps2 must be a finite non-zero vector")
    u = g0 / n0[..., None] if g0.ndim == 2 else g0 / n0
    proj = along_gravity_mps2(a, g0)
    a_perp = n0 - proj
    horiz = a - proj[:, None] * (u if u.ndim == 2 else u[None, :])
    return a_perp, np.sqrt(np.einsum("ij,ij->i", horiz, horiz))


def seconds_to_samples(duration_s: float, rate_hz: float, mode: str = "round") -> int:
    """A window length in seconds as a number of samples, the same for rates a clock jitter apart.

    ``duration_s * rate_hz`` is first snapped to a multiple of 1e-3 samples (a log's measured rate
    is off its nominal value by parts per million: 49.99999 Hz and 50.000001 Hz are both 50 Hz),
    then rounded half up (``mode="round"``) or down (``mode="floor"``).

    Parameters
    ----------
    duration_s : float
        Window length, s (>= 0).
    rate_hz : float
        Sample rate, Hz (> 0).
    mode : {"round", "floor"}

    Returns
    -------
    int
    """
    if not (np.isfinite(duration_s) and duration_s >= 0):
        raise ValueError(f"duration_s must be a finite number >= 0, got {duration_s}")
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"rate_hz must be a finite number > 0, got {rate_hz}")
    x = np.round(float(duration_s) * float(rate_hz) * 1e3) / 1e3
    if mode == "round":
        return int(np.floor(x + 0.5))
    if mode == "floor":
        return int(np.floor(x))
    raise ValueError(f"mode must be 'round' or 'floor', got {mode!r}")


def _window_sizes(rate_hz: float, w_peak_s: float, w_wave_s: float, valley_s: float):
    half_peak = max(seconds_to_samples(0.5 * w_peak_s, rate_hz), 1)
    half_wave = max(seconds_to_samples(valley_s, rate_hz), 1)
    n_dft = seconds_to_samples(0.5 * w_wave_s, rate_hz, "floor") - 1  # N = floor(W_wave f / 2) - 1
    if n_dft < 1:
        raise ValueError(f"sample rate {rate_hz:.3g} Hz is too low for W_wave = {w_wave_s} s (N = {n_dft} < 1)")
    return half_peak, half_wave, n_dft


def sam_waves(acc_mps2, t_s, g0_mps2=None, w_peak_s: float = 0.25, w_wave_s: float = 0.5,
              valley_s: float | None = None) -> pd.DataFrame:
    """All candidate waves of a log with their eight SAM features.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3)
        Specific force in the phone frame, m/s^2, uniformly sampled.
    t_s : array_like, shape (n,)
        Sample times, s (strictly increasing, regular within 50 %).
    g0_mps2 : array_like, optional
        Gravity at rest (see :func:`vertical_horizontal_mps2`).
    w_peak_s, w_wave_s : float
        W_peak (0.25 s) and W_wave (0.5 s) of the thesis.
    valley_s : float, optional
        How far either side of the peak the valleys are searched, s. Default ``w_wave_s`` (0.5 s).
        Read literally, the thesis (L357) searches ``W_wave / 2 = 0.25 s`` either side, which
        bounds T1 and T2 by 0.25 s and T by 0.5 s, yet Table 1 (L424-425) reports T1 up to 0.35 s,
        T2 up to 0.40 s and T up to 0.62 s: such waves need valleys further out, so the default
        searches ``W_wave`` either side. Pass ``w_wave_s / 2`` for the literal reading. Windows
        are converted to samples with :func:`seconds_to_samples`.

    Returns
    -------
    DataFrame
        One row per wave: ``i_peak``, ``t_s``, ``i_left``, ``i_right``, ``a_max_mps2`` (a^m),
        ``a_min_mps2`` (min of the two valleys) and the features ``T1, T2, T`` (s),
        ``A1, A2, A, I, X1`` (m/s^2).

    References
    ----------
    Chiu (2013), eq. (8)-(15).
    """
    a = check_acc(acc_mps2, min_samples=3)
    t = check_times(t_s, n=a.shape[0])
    rate = sample_rate_hz(t)
    hp, hw, N = _window_sizes(rate, w_peak_s, w_wave_s, w_wave_s if valley_s is None else valley_s)
    if a.shape[0] < 2 * hw + 1:
        raise ValueError(f"acc_mps2 is too short: {a.shape[0]} samples, need at least {2 * hw + 1} "
                         f"(two valley windows at {rate:.3g} Hz)")
    v, h = vertical_horizontal_mps2(a, g0_mps2)
    n = v.size
    # peak: no larger value within W_peak/2 either side; ties resolved to the first sample
    mx = sliding_max(v, hp, hp)
    left_mx = sliding_max(np.concatenate([[-np.inf], v[:-1]]), hp - 1, 0) if hp >= 1 else np.full(n, -np.inf)
    cand = (v >= mx) & (v > left_mx)
    idx = np.flatnonzero(cand)
    idx = idx[(idx >= hw) & (idx < n - hw) & (idx >= N) & (idx < n - N)]
    cols = ["i_peak", "t_s", "i_left", "i_right", "a_max_mps2", "a_min_mps2", *SAM_FEATURES]
    if idx.size == 0:
        return pd.DataFrame({c: pd.Series(dtype=np.int64 if c.startswith("i_") else np.float64) for c in cols})
    offs = np.arange(1, hw + 1)
    lw = v[idx[:, None] - offs[None, ::-1]]          # samples i-hw .. i-1
    rw = v[idx[:, None] + offs[None, :]]             # samples i+1 .. i+hw
    il = idx - hw + np.argmin(lw, axis=1)
    ir = idx + 1 + np.argmin(rw, axis=1)
    am, al, ar = v[idx], v[il], v[ir]
    T1 = t[idx] - t[il]
    T2 = t[ir] - t[idx]
    A1 = am - al
    A2 = am - ar
    k = np.arange(-N, N + 1)
    win = idx[:, None] + k[None, :]
    I = h[win].mean(axis=1)
    basis = np.exp(-2j * np.pi * np.arange(2 * N + 1) / (2 * N + 1))
    X1 = np.abs(v[win] @ basis)
    return pd.DataFrame({
        "i_peak": idx.astype(np.int64), "t_s": t[idx], "i_left": il.astype(np.int64),
        "i_right": ir.astype(np.int64), "a_max_mps2": am, "a_min_mps2": np.minimum(al, ar),
        "T1": T1, "T2": T2, "T": T1 + T2, "A1": A1, "A2": A2, "A": A1 + A2, "I": I, "X1": X1,
    })


def learn_feature_ranges(features: pd.DataFrame, q_low: float = 0.05, q_high: float = 0.95) -> pd.DataFrame:
    """Feature ranges as the [q_low, q_high] quantiles of training steps' features.

    Returns
    -------
    DataFrame indexed by feature (the eight SAM features) with columns ``min`` and ``max``.

    References
    ----------
    Chiu (2013), sec. 4.1 (ranges from the 5 % and 95 % points of the feature CDFs), Table 1.
    """
    missing = [f for f in SAM_FEATURES if f not in features.columns]
    if missing:
        raise ValueError(f"features lack columns {missing}")
    if len(features) < 2:
        raise ValueError(f"need at least 2 training steps to learn ranges, got {len(features)}")
    if not 0 <= q_low < q_high <= 1:
        raise ValueError(f"need 0 <= q_low < q_high <= 1, got {q_low}, {q_high}")
    f = features[list(SAM_FEATURES)].astype(np.float64)
    if not np.isfinite(f.to_numpy()).all():
        raise ValueError("features contain NaN or inf")
    out = pd.DataFrame({"min": f.quantile(q_low), "max": f.quantile(q_high)})
    out.index.name = "feature"
    return out


def in_ranges(waves: pd.DataFrame, ranges: pd.DataFrame, features=SAM_TESTED_FEATURES,
              min_pass: int | None = None) -> np.ndarray:
    """Boolean mask of the waves whose tested features lie inside ``ranges`` (inclusive).

    ``min_pass`` (default: all features, the thesis's rule) is how many of the tests must pass;
    fewer is a beyond-the-paper vote.
    """
    k = len(features) if min_pass is None else int(min_pass)
    if not 1 <= k <= len(features):
        raise ValueError(f"min_pass must lie in [1, {len(features)}], got {min_pass}")
    lo, hi = range_bounds(ranges, features)
    return passes_ranges(np.column_stack([waves[f].to_numpy() for f in features]), lo, hi, k)


def range_bounds(ranges: pd.DataFrame, features=SAM_TESTED_FEATURES) -> tuple[np.ndarray, np.ndarray]:
    """The ``min`` and ``max`` of ``ranges`` (:func:`learn_feature_ranges`) for ``features``, in their order."""
    for f in features:
        if f not in ranges.index:
            raise ValueError(f"ranges lack feature {f!r}")
    r = ranges.loc[list(features)]
    return r["min"].to_numpy(dtype=np.float64), r["max"].to_numpy(dtype=np.float64)


def passes_ranges(x: np.ndarray, lo: np.ndarray, hi: np.ndarray, min_pass: int) -> np.ndarray:
    """Rows of ``x`` (waves x features) with at least ``min_pass`` features inside ``[lo, hi]`` (inclusive); the test
    of :func:`in_ranges` on arrays, for many waves or many ranges at once."""
    return ((x >= lo) & (x <= hi)).sum(axis=1, dtype=np.int64) >= min_pass


@register_step_detector("sam", rate_hz=50.0)
def detect_steps_sam(acc_mps2, t_s, ranges: pd.DataFrame | None = None, g0_mps2=None,
                     w_peak_s: float = 0.25, w_wave_s: float = 0.5, min_pass: int | None = None) -> pd.DataFrame:
    """SAM step detection: the waves of :func:`sam_waves` whose features lie in ``ranges``.

    Parameters
    ----------
    ranges : DataFrame, optional
        Learned ranges (:func:`learn_feature_ranges`); default the thesis's Table 1
        (:data:`SAM_RANGES_PAPER`, which presumes the thesis's phone and sample rate: X1 grows with
        the number of samples in a window, so learn ranges for other rates).
    min_pass : int, optional
        How many of the seven range tests must pass (default all seven, the thesis's rule).

    Returns
    -------
    DataFrame
        The step rows of :func:`sam_waves` (``i_peak``, ``t_s``, ``a_max_mps2``, ``a_min_mps2``,
        features), index reset.

    References
    ----------
    Chiu (2013), sec. 4.1, eq. (8)-(15), Table 1.
    """
    waves = sam_waves(acc_mps2, t_s, g0_mps2, w_peak_s, w_wave_s)
    r = SAM_RANGES_PAPER if ranges is None else ranges
    return waves[in_ranges(waves, r, SAM_TESTED_FEATURES, min_pass)].reset_index(drop=True)


class SAMDetector:
    """Thin wrapper: ``fit`` learns the ranges from training logs' true steps, ``detect`` finds steps.

    Parameters
    ----------
    q_low, q_high : float
        Quantiles of the learned ranges (5 %, 95 % in the thesis).
    w_peak_s, w_wave_s : float
    tol_s : float
        A wave matches a true step when its peak lies within ``tol_s`` of the true step time.
    """

    def __init__(self, q_low: float = 0.05, q_high: float = 0.95, w_peak_s: float = 0.25,
                 w_wave_s: float = 0.5, tol_s: float = 0.2):
        self.q_low = q_low
        self.q_high = q_high
        self.w_peak_s = w_peak_s
        self.w_wave_s = w_wave_s
        self.tol_s = tol_s

    def training_waves(self, acc_mps2, t_s, step_t_s) -> pd.DataFrame:
        """The waves nearest each true step (one per true step, within ``tol_s``)."""
        w = sam_waves(acc_mps2, t_s, None, self.w_peak_s, self.w_wave_s)
        return match_waves_to_steps(w, step_t_s, self.tol_s)

    def fit(self, logs) -> SAMDetector:
        """``logs``: iterable of ``(acc_mps2, t_s, step_t_s)`` training walks with true step times."""
        feats = [self.training_waves(a, t, s) for a, t, s in logs]
        self.train_features_ = pd.concat(feats, ignore_index=True)
        self.ranges_ = learn_feature_ranges(self.train_features_, self.q_low, self.q_high)
        return self

    def detect(self, acc_mps2, t_s) -> pd.DataFrame:
        if not hasattr(self, "ranges_"):
            raise ValueError("SAMDetector is not fitted; call fit() first")
        return detect_steps_sam(acc_mps2, t_s, self.ranges_, None, self.w_peak_s, self.w_wave_s)


def match_waves_to_steps(waves: pd.DataFrame, step_t_s, tol_s: float) -> pd.DataFrame:
    """For each true step time, the wave whose peak is nearest (if within ``tol_s``); one wave per step."""
    st = np.asarray(step_t_s, dtype=np.float64)
    if len(waves) == 0 or st.size == 0:
        return waves.iloc[:0]
    wt = waves["t_s"].to_numpy()
    j = np.clip(np.searchsorted(wt, st), 1, wt.size - 1) if wt.size > 1 else np.zeros(st.size, dtype=int)
    if wt.size > 1:
        j = np.where(np.abs(wt[j - 1] - st) <= np.abs(wt[j] - st), j - 1, j)
    ok = np.abs(wt[j] - st) <= tol_s
    j = np.unique(j[ok])
    return waves.iloc[j].reset_index(drop=True)
