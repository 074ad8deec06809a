"""The toolkit's best step detector for real phones: resample, low-pass |a|, prominent peaks, walking bouts.

Beyond the papers. Steps:

1. resample the log to a common rate (``rate_hz``, 100 Hz) so one parameter set serves phones
   sampling at 100-400 Hz;
2. acceleration magnitude (independent of how the phone is carried), zero-phase 2nd-order
   Butterworth low-pass at ``cutoff_hz`` (about the step frequency band);
3. peaks of at least ``prominence_mps2`` prominence, at least ``min_step_s`` apart
   (:func:`scipy.signal.find_peaks`);
4. walk detection at the ends of each walking bout (peaks split into bouts wherever two peaks are
   more than ``max_step_s`` apart): while the first (last) peak of a bout is not inside a periodic
   walk, it is dropped. A peak is inside a walk when the stride of |a| centred on it repeats: the
   normalised auto-correlation between that stride-long window and the window one stride before or
   after it, maximised over stride lengths ``2 min_step_s`` to ``2 max_step_s``, is at least
   ``min_stride_nac`` (:func:`stride_nac`; the normalised auto-correlation of Rai et al. 2012, "Zee",
   there used to tell walking from other motion; walk detection before step counting as Brajdic & Harle
   2013 study it). This removes the handling peaks before and after a walk and a pouch swaying while
   the walker stands, which the bout gate below keeps when they come less than ``max_step_s`` apart;
   peaks inside a bout are never dropped (a weak step between strong ones is still a step);
   gait onset: then, while the first peak of a bout is less prominent than ``min_onset_ratio`` times the
   peak one stride (two peaks) later, the same foot's next landing, it is dropped
   (:func:`trim_bout_onsets`). Starting to walk from standing, the body shifts its weight before the first
   step (the anticipatory postural adjustments of gait initiation, Crenna & Frigo 1991): a small bump of |a|
   about one step period before the first landing, which the stride test above keeps because the walk's
   stride follows it. The first landing is weak too, but less so against the same foot's next one (one
   stride later, so that a phone in one pocket compares like with like). The end of a walk gets no such
   rule: the last landing of a walk is the softest, weaker than a bump after it;
5. walking-bout gate: bouts of fewer than ``min_bout_steps`` peaks (handling the phone, standing)
   are dropped.

The parameters are chosen by leave-one-recording-out cross-validation on labelled walks (the
experiment ``pdr_real_steps``); the defaults are the values that search picks on the Oxford
optimisation set (``min_stride_nac``: on its development half, odd repeats, against the truth with
heel-sensor bounces merged: 0.5 in each of the 24 folds over off, 0, 0.3-0.7; table ``walk_gate_sweep``;
``min_onset_ratio``: the same way, table ``onset_sweep``).

References
----------
Rai, A., Chintalapudi, K. K., Padmanabhan, V. N., Sen, R. (2012), "Zee: zero-effort crowdsourcing for
indoor localization", MobiCom (normalised auto-correlation of |a| over a gait cycle).
Brajdic, A., Harle, R. (2013), "Walk detection and step counting on unconstrained smartphones", UbiComp.
Crenna, P., Frigo, C. (1991), "A motor programme for the initiation of forward-oriented movements in humans",
J. Physiol. 437 (anticipatory postural adjustments before the first step of gait initiation).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import signal as ss

from ilocalg.pdr.registry import register_step_detector
from ilocalg.pdr.signals import check_acc, check_times, magnitude_mps2, resample_uniform

__all__ = ["match_steps", "lowpass_magnitude", "bout_gate", "stride_nac", "trim_bout_ends", "trim_bout_onsets",
           "detect_steps_robust",
           "detect_steps_find_peaks",
           "RobustSignal",
           "RobustStepDetector",
           "ROBUST_DEFAULTS"]

#: Default parameters (selected by leave-one-recording-out search on the Oxford set).
ROBUST_DEFAULTS = {"rate_hz": 100.0, "cutoff_hz": 2.0, "prominence_mps2": 0.3, "min_step_s": 0.25,
                   "max_step_s": 1.0, "min_bout_steps": 8, "min_stride_nac": 0.5, "min_onset_ratio": 0.3}


def lowpass_magnitude(mag_mps2, rate_hz: float, cutoff_hz: float) -> np.ndarray:
    """Zero-phase 2nd-order Butterworth low-pass of a uniformly sampled signal."""
    if not 0 < cutoff_hz < rate_hz / 2:
        raise ValueError(f"cutoff_hz must lie in (0, rate_hz/2 = {rate_hz / 2}), got {cutoff_hz}")
    sos = ss.butter(2, cutoff_hz, fs=rate_hz, output="sos")
    return ss.sosfiltfilt(sos, np.asarray(mag_mps2, dtype=np.float64))


def bout_gate(t_peak_s, max_step_s: float, min_bout_steps: int) -> np.ndarray:
    """Mask of the peaks that belong to a bout of at least ``min_bout_steps`` peaks.

    A bout is a maximal run of peaks whose consecutive intervals are all <= ``max_step_s``.
    """
    t = np.asarray(t_peak_s, dtype=np.float64)
    if t.size == 0:
        return np.zeros(0, dtype=bool)
    bout = np.cumsum(_bout_breaks(t, max_step_s)) - 1
    size = np.bincount(bout)
    return size[bout] >= min_bout_steps


def _bout_breaks(t: np.ndarray, max_step_s: float) -> np.ndarray:
    """True at each peak that starts a bout (the first, and each more than ``max_step_s`` after the one before)."""
    return np.concatenate([[True], np.diff(t) > max_step_s])


def stride_nac(x, i_peak, lag_min: int, lag_max: int, lag_step: int = 1) -> np.ndarray:
    """Normalised auto-correlation of one stride around each peak with the stride before or after it.

    For each lag ``L`` (samples, ``lag_min`` to ``lag_max``) the window of ``L`` samples centred on the
    peak is correlated (Pearson) with the same window moved ``L`` samples later and ``L`` samples
    earlier; the result is the largest correlation over lags and both directions (Rai et al. 2012's
    normalised auto-correlation, taken around a peak). A direction whose window leaves the signal does
    not count; a peak with no window inside the signal, or on a constant signal, gets -1.

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal (here |a|, m/s^2).
    i_peak : array_like of int, shape (k,)
        Sample indices of the peaks.
    lag_min, lag_max : int
        Stride lengths tried, samples (``1 <= lag_min <= lag_max``).
    lag_step : int
        Every ``lag_step``-th stride length from ``lag_min`` is tried (>= 1).

    Returns
    -------
    ndarray, shape (k,), in [-1, 1]
    """
    x = np.asarray(x, dtype=np.float64)
    idx = np.asarray(i_peak, dtype=np.int64)
    if not 1 <= lag_min <= lag_max:
        raise ValueError(f"need 1 <= lag_min <= lag_max, got {lag_min}, {lag_max}")
    if lag_step < 1:
        raise ValueError(f"lag_step must be >= 1, got {lag_step}")
    if idx.size == 0:
        return np.full(0, -1.0)
    return _stride_nac(x, idx, np.arange(int(lag_min), int(lag_max) + 1, int(lag_step)), _flat_floor(x, idx))[0]


def _flat_floor(x: np.ndarray, idx: np.ndarray) -> float:
    """The mean square below which :func:`stride_nac` takes a window as flat: flatter than rounding, on the scale of
    the peaks asked (``idx`` non-empty)."""
    return 1e-18 * float(np.max(x[np.clip(idx, 0, x.size - 1)] ** 2))


def _stride_nac(x: np.ndarray, idx: np.ndarray, lags: np.ndarray, tiny: float):
    """:func:`stride_nac` of the peaks ``idx`` with the flatness floor ``tiny``.

    Each peak's value is computed from its own windows alone (the blocks of :data:`_NAC_CHUNK` peaks only bound
    the temporary arrays). Also returns, per peak, whether a window inside the signal was taken as flat, and the
    smallest mean square of its windows inside the signal (inf: none), with which :class:`RobustSignal` tells
    whether a value computed once holds for another floor.
    """
    n = x.size
    best = np.full(idx.size, -1.0)
    any_flat = np.zeros(idx.size, dtype=bool)
    least = np.full(idx.size, np.inf)
    j = np.arange(lags[-1])
    mask = j[None, :] < lags[:, None]                       # (n_lags, longest): the samples of each lag's window
    for c in range(0, idx.size, _NAC_CHUNK):                # a few peaks at a time: (peaks, lags, samples) arrays
        start = idx[c:c + _NAC_CHUNK, None] - lags[None, :] // 2
        a = _centred_windows(x, start, j, mask, lags)
        aa = (a * a).sum(axis=2)
        for sgn in (1, -1):
            s0 = start + sgn * lags[None, :]
            ok = (start >= 0) & (start + lags <= n) & (s0 >= 0) & (s0 + lags <= n)
            bw = _centred_windows(x, s0, j, mask, lags)
            bb = (bw * bw).sum(axis=2)
            flat = (aa <= tiny * lags) | (bb <= tiny * lags)
            cor = np.where(ok & ~flat, (a * bw).sum(axis=2) / np.where(flat, 1.0, np.sqrt(aa * bb)), -1.0)
            best[c:c + _NAC_CHUNK] = np.maximum(best[c:c + _NAC_CHUNK], cor.max(axis=1))
            any_flat[c:c + _NAC_CHUNK] |= (ok & flat).any(axis=1)
            least[c:c + _NAC_CHUNK] = np.minimum(least[c:c + _NAC_CHUNK],
                                                 np.where(ok, np.minimum(aa, bb) / lags, np.inf).min(axis=1))
    return best, any_flat, least


#: Peaks per block in :func:`stride_nac` (bounds its temporary arrays to a few MB).
_NAC_CHUNK = 8
#: Stride lengths tried by the robust detector's walk detection, every this many seconds (0.02 s: every other
#: sample at 100 Hz; the same counts as every sample on the 24 development recordings, half the work).
_NAC_LAG_S = 0.02


def _centred_windows(x, start, j, mask, lags) -> np.ndarray:
    """Windows ``x[start:start + lag]`` less their means, zero-padded to the longest lag: (peaks, lags, samples)."""
    w = x[np.clip(start[:, :, None] + j[None, None, :], 0, x.size - 1)] * mask[None]
    return (w - (w.sum(axis=2) / lags)[:, :, None]) * mask[None]


def trim_bout_ends(t_peak_s, score_fn, max_step_s: float, min_score: float) -> np.ndarray:
    """Mask of the peaks left once each bout's first and last peaks scoring below ``min_score`` are dropped.

    Bouts as in :func:`bout_gate` (split where two peaks are more than ``max_step_s`` apart). From each
    end of a bout, peaks are dropped while their score is below ``min_score``; the first peak that scores
    at least ``min_score`` stops the trimming at that end, so no peak inside a bout is ever dropped.
    ``score_fn(positions) -> scores`` is called only for the peaks at the current ends (positions into
    ``t_peak_s``), a few per bout.
    """
    t = np.asarray(t_peak_s, dtype=np.float64)
    keep = np.ones(t.size, dtype=bool)
    if t.size == 0:
        return keep
    starts = np.flatnonzero(_bout_breaks(t, max_step_s))
    lo, hi = starts.copy(), np.append(starts[1:], t.size) - 1
    active_lo = np.ones(lo.size, dtype=bool)
    active_hi = np.ones(hi.size, dtype=bool)
    scores: dict[int, float] = {}
    while active_lo.any() or active_hi.any():
        ask = np.unique(np.concatenate([lo[active_lo], hi[active_hi]]))
        ask = ask[[int(i) not in scores for i in ask]]
        if ask.size:
            scores.update(zip(ask.tolist(), np.asarray(score_fn(ask), dtype=float).tolist(), strict=True))
        for k in np.flatnonzero(active_lo):
            if lo[k] <= hi[k] and scores[int(lo[k])] < min_score:
                keep[lo[k]] = False
                lo[k] += 1
            else:
                active_lo[k] = False
        for k in np.flatnonzero(active_hi):
            if hi[k] >= lo[k] and scores[int(hi[k])] < min_score:
                keep[hi[k]] = False
                hi[k] -= 1
            else:
                active_hi[k] = False
        active_lo &= lo <= hi
        active_hi &= hi >= lo
    return keep


def trim_bout_onsets(t_peak_s, prominence, max_step_s: float, min_ratio: float, stride_peaks: int = 2) -> np.ndarray:
    """Mask of the peaks left once each bout's first peaks, weaker than ``min_ratio`` times the peak one stride later,
    are dropped.

    Bouts as in :func:`bout_gate`. From the start of each bout, the first peak is dropped while its
    ``prominence`` is below ``min_ratio`` times that of the peak ``stride_peaks`` later (two: the same foot's next
    landing) and that peak is in the bout; the first peak that passes stops the trimming, so no peak after it
    is dropped.

    Parameters
    ----------
    t_peak_s : array_like, shape (k,)
        Increasing peak times, s.
    prominence : array_like, shape (k,)
        The peaks' prominences (any unit; only their ratios count).
    max_step_s : float
        Longest step: a larger gap starts a new bout, s.
    min_ratio : float
        Smallest prominence of a bout's first peak against the peak one stride later.
    stride_peaks : int
        Peaks per stride (>= 1).
    """
    t = np.asarray(t_peak_s, dtype=np.float64)
    prom = np.asarray(prominence, dtype=np.float64)
    if prom.shape != t.shape:
        raise ValueError(f"prominence must have the shape of t_peak_s {t.shape}, got {prom.shape}")
    if stride_peaks < 1:
        raise ValueError(f"stride_peaks must be >= 1, got {stride_peaks}")
    keep = np.ones(t.size, dtype=bool)
    if t.size == 0:
        return keep
    starts = np.flatnonzero(_bout_breaks(t, max_step_s))
    for i, end in zip(starts, np.append(starts[1:], t.size), strict=True):
        while i + stride_peaks < end and prom[i] < min_ratio * prom[i + stride_peaks]:
            keep[i] = False
            i += 1
    return keep


def match_steps(true_t_s, det_t_s, tol_s: float = 0.2) -> tuple[np.ndarray, np.ndarray]:
    """One-to-one matching of detected to true step times (greedy by time order).

    A true step and a detection match when they are within ``tol_s`` and neither is matched yet;
    each is used once. Use it to tell *missed* steps (true, unmatched) from *extra* ones (detected,
    unmatched), which a count alone mixes up.

    Parameters
    ----------
    true_t_s, det_t_s : array_like, increasing times, s
    tol_s : float
        Largest |t_true - t_det| of a match, s (keep it below half a step period, about 0.25 s).

    Returns
    -------
    true_matched : ndarray of bool (n_true,)
    det_matched : ndarray of bool (n_det,)
    """
    t = np.asarray(true_t_s, dtype=np.float64)
    d = np.asarray(det_t_s, dtype=np.float64)
    if tol_s <= 0:
        raise ValueError(f"tol_s must be > 0, got {tol_s}")
    if (np.diff(t) < 0).any() or (np.diff(d) < 0).any():
        raise ValueError("true_t_s and det_t_s must be sorted in time")
    tm = np.zeros(t.size, dtype=bool)
    dm = np.zeros(d.size, dtype=bool)
    i = j = 0
    while i < t.size and j < d.size:            # one merge pass over the two sorted lists
        if abs(t[i] - d[j]) <= tol_s:
            tm[i] = dm[j] = True
            i += 1
            j += 1
        elif t[i] < d[j]:
            i += 1
        else:
            j += 1
    return tm, dm


class RobustSignal:
    """One accelerometer log for :func:`detect_steps_robust` at many parameter sets.

    Each stage of the detector is computed once per value of what it depends on and kept: the resampled
    magnitude per ``rate_hz``, the low-pass per ``cutoff_hz``, the peaks per ``prominence_mps2`` and
    ``min_step_s``, the walk detection at the bout ends per ``max_step_s`` and ``min_stride_nac``, and each peak's
    stride auto-correlation per stride lengths (shared by every prominence: a peak's value depends on the signal
    and its sample index alone). :meth:`detect` returns what :func:`detect_steps_robust` returns for the same log
    and parameters, number for number; a grid search over the parameters (``ilocalg.pdr.step_evaluate``) keeps one
    per recording. Pass it to :func:`detect_steps_robust` (or ``detect_steps_find_peaks``) in place of the log.

    Parameters
    ----------
    acc_mps2, t_s
        As :func:`detect_steps_robust` (checked at the first :meth:`detect`).
    """

    def __init__(self, acc_mps2, t_s):
        self._raw = (acc_mps2, t_s)
        self._log = None        # (t, |a|) once checked
        self._grid: dict = {}   # rate -> (tu, mu)
        self._lp: dict = {}     # (rate, cutoff) -> y
        self._peaks: dict = {}  # (rate, cutoff, prominence, distance) -> find_peaks' (p, props)
        self._nac: dict = {}    # (rate, lags, step) -> {sample index: (value, smallest window mean square)}
        self._ends: dict = {}   # (rate, cutoff, prominence, distance, max_step, min_stride_nac, lags, step) -> keep

    def _checked(self):
        if self._log is None:
            a = check_acc(self._raw[0], min_samples=3)
            t = check_times(self._raw[1], n=a.shape[0], regular=False)
            self._log = (t, magnitude_mps2(a) if a.ndim == 2 else a)
        return self._log

    def _stage(self, cache: dict, key, make):
        if key not in cache:
            cache[key] = make()
        return cache[key]

    def _resampled(self, rate_hz: float):
        def make():
            t, m = self._log
            dt = np.diff(t)
            if np.abs(dt * rate_hz - 1.0).max() < 1e-6:        # already on the common grid: no resampling
                tu, mu = t, m
            else:
                mu, tu = resample_uniform(m, t, rate_hz)
            if mu.size < 16:
                raise ValueError(f"acc_mps2 is too short: {t[-1] - t[0]:.3g} s of data")
            return tu, mu
        return self._stage(self._grid, rate_hz, make)

    def _stride_scores(self, mu: np.ndarray, key, lags: np.ndarray):
        """``score_fn`` of :func:`trim_bout_ends` over sample indices: :func:`stride_nac`'s values, each peak's
        computed once (reused while no window of it is near the flatness floor of the peaks asked with it)."""
        known = self._nac.setdefault(key, {})

        def score(idx):
            idx = np.asarray(idx, dtype=np.int64)
            out = np.full(idx.size, -1.0)
            if idx.size == 0:
                return out
            tiny = _flat_floor(mu, idx)
            todo = []
            for q, i in enumerate(idx.tolist()):
                hit = known.get(i)
                if hit is not None and tiny < 0.5 * hit[1]:
                    out[q] = hit[0]
                else:
                    todo.append(q)
            if todo:
                best, any_flat, least = _stride_nac(mu, idx[todo], lags, tiny)
                out[todo] = best
                for i, v, fl, le in zip(idx[todo].tolist(), best.tolist(), any_flat.tolist(), least.tolist(),
                                        strict=True):
                    if not fl:
                        known[i] = (v, le)
            return out
        return score

    def detect(self, rate_hz: float = 100.0, cutoff_hz: float = 2.0, prominence_mps2: float = 0.3,
               min_step_s: float = 0.25, max_step_s: float = 1.0, min_bout_steps: int = 8,
               min_stride_nac: float | None = 0.5, min_onset_ratio: float | None = 0.3) -> pd.DataFrame:
        """:func:`detect_steps_robust` of this log (same parameters, same result)."""
        t, _ = self._checked()
        if min_bout_steps < 1:
            raise ValueError(f"min_bout_steps must be >= 1, got {min_bout_steps}")
        if min_stride_nac is not None and not -1.0 <= min_stride_nac <= 1.0:
            raise ValueError(f"min_stride_nac must lie in [-1, 1] (a correlation) or be None, got {min_stride_nac}")
        if min_onset_ratio is not None and not 0.0 <= min_onset_ratio <= 1.0:
            raise ValueError(f"min_onset_ratio must lie in [0, 1] (a prominence ratio) or be None, "
                             f"got {min_onset_ratio}")
        tu, mu = self._resampled(rate_hz)
        y = self._stage(self._lp, (rate_hz, cutoff_hz), lambda: lowpass_magnitude(mu, rate_hz, cutoff_hz))
        distance = max(int(round(min_step_s * rate_hz)), 1)
        p, props = self._stage(self._peaks, (rate_hz, cutoff_hz, prominence_mps2, distance),
                               lambda: ss.find_peaks(y, prominence=prominence_mps2, distance=distance))
        keep = np.ones(p.size, dtype=bool)
        if min_stride_nac is not None and np.isfinite(max_step_s):
            lags = (max(int(round(2 * min_step_s * rate_hz)), 2), int(round(2 * max_step_s * rate_hz)))
            step = max(int(round(_NAC_LAG_S * rate_hz)), 1)

            def ends():
                if lags[0] > lags[1]:       # max_step_s < min_step_s: stride_nac names the error once asked
                    return trim_bout_ends(tu[p], lambda k: stride_nac(mu, p[k], *lags, step), max_step_s,
                                          min_stride_nac)
                score = self._stride_scores(mu, (rate_hz, lags, step), np.arange(lags[0], lags[1] + 1, step))
                return trim_bout_ends(tu[p], lambda k: score(p[k]), max_step_s, min_stride_nac)
            keep = self._stage(self._ends, (rate_hz, cutoff_hz, prominence_mps2, distance, max_step_s,
                                            min_stride_nac, lags, step), ends).copy()
            if min_onset_ratio is not None:
                k = np.flatnonzero(keep)
                keep[k] = trim_bout_onsets(tu[p[k]], props["prominences"][k], max_step_s, min_onset_ratio)
        keep[keep] = bout_gate(tu[p[keep]], max_step_s, min_bout_steps)
        p = p[keep]
        base = np.minimum(y[props["left_bases"][keep]], y[props["right_bases"][keep]])
        ts = tu[p]
        i_in = np.clip(np.searchsorted(t, ts), 0, t.size - 1)
        prev = np.clip(i_in - 1, 0, t.size - 1)
        i_in = np.where(np.abs(t[prev] - ts) <= np.abs(t[i_in] - ts), prev, i_in)
        return pd.DataFrame({"i_peak": i_in.astype(np.int64), "t_s": ts, "a_max_mps2": y[p], "a_min_mps2": base,
                             "prominence_mps2": props["prominences"][keep]})


@register_step_detector("robust")
def detect_steps_robust(acc_mps2, t_s, rate_hz: float = 100.0, cutoff_hz: float = 2.0,
                        prominence_mps2: float = 0.3, min_step_s: float = 0.25, max_step_s: float = 1.0,
                        min_bout_steps: int = 8, min_stride_nac: float | None = 0.5,
                        min_onset_ratio: float | None = 0.3) -> pd.DataFrame:
    """Detect steps in an accelerometer log of any (even irregular) sampling.

    Parameters
    ----------
    acc_mps2 : array_like, shape (n, 3) or (n,), or RobustSignal
        Specific force (m/s^2) or its magnitude; or a :class:`RobustSignal` of the log, which keeps what this call
        computes for the next one with other parameters (then ``t_s`` is not read: the signal holds the times).
    t_s : array_like, shape (n,)
        Strictly increasing times, s (irregular sampling is fine: the log is resampled).
    rate_hz, cutoff_hz, prominence_mps2, min_step_s, max_step_s, min_bout_steps, min_stride_nac, min_onset_ratio
        See the module docstring; ``min_stride_nac=None`` switches the walk detection at bout ends off (the gait
        onset rule with it), ``min_onset_ratio=None`` the gait onset rule alone.

    Returns
    -------
    DataFrame
        ``i_peak`` (index of the input sample nearest the step), ``t_s``, ``a_max_mps2`` (filtered
        magnitude at the peak), ``a_min_mps2`` (the lower of the peak's two bases), ``prominence_mps2``.
    """
    sig = acc_mps2 if isinstance(acc_mps2, RobustSignal) else RobustSignal(acc_mps2, t_s)
    return sig.detect(rate_hz=rate_hz, cutoff_hz=cutoff_hz, prominence_mps2=prominence_mps2, min_step_s=min_step_s,
                      max_step_s=max_step_s, min_bout_steps=min_bout_steps, min_stride_nac=min_stride_nac,
                      min_onset_ratio=min_onset_ratio)


@register_step_detector("find_peaks")
def detect_steps_find_peaks(acc_mps2, t_s, rate_hz: float = 100.0, cutoff_hz: float = 3.0,
                            prominence_mps2: float = 1.2, min_step_s: float = 0.25, max_step_s: float = np.inf,
                            min_bout_steps: int = 1) -> pd.DataFrame:
    """A plain baseline: low-pass |a| and :func:`scipy.signal.find_peaks` with a prominence, no bout gate.

    :func:`detect_steps_robust` with its walk detection and walking-bout gate switched off
    (``min_stride_nac = None``, ``max_step_s = inf``, ``min_bout_steps = 1``) and a 3 Hz cut-off; the
    defaults are those leave-one-recording-out tuning chose on the Oxford optimisation set.
    """
    return detect_steps_robust(acc_mps2, t_s, rate_hz=rate_hz, cutoff_hz=cutoff_hz, prominence_mps2=prominence_mps2,
                               min_step_s=min_step_s, max_step_s=max_step_s, min_bout_steps=min_bout_steps,
                               min_stride_nac=None)


class RobustStepDetector:
    """Thin wrapper around :func:`detect_steps_robust` holding its parameters."""

    def __init__(self, rate_hz: float = 100.0, cutoff_hz: float = 2.0, prominence_mps2: float = 0.3,
                 min_step_s: float = 0.25, max_step_s: float = 1.0, min_bout_steps: int = 8,
                 min_stride_nac: float | None = 0.5, min_onset_ratio: float | None = 0.3):
        self.rate_hz = rate_hz
        self.cutoff_hz = cutoff_hz
        self.prominence_mps2 = prominence_mps2
        self.min_step_s = min_step_s
        self.max_step_s = max_step_s
        self.min_bout_steps = min_bout_steps
        self.min_stride_nac = min_stride_nac
        self.min_onset_ratio = min_onset_ratio

    def get_params(self) -> dict:
        return {k: getattr(self, k) for k in ROBUST_DEFAULTS}

    def detect(self, acc_mps2, t_s) -> pd.DataFrame:
        return detect_steps_robust(acc_mps2, t_s, **self.get_params())
