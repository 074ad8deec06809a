"""Step detectors scored on recordings with counted steps: leave-one-recording-out tuning and diagnosis.

A recording (:class:`ilocalg.io.oxford.OxfordRecording`: accelerometer log, true step count and
heel-sensor step times) is resampled once to the detectors' common rates (:func:`prepare`:
:data:`RATE_HZ`; :data:`SAM_RATE_HZ` for SAM, whose X1 feature depends on the rate). Each grid
detector counts steps at every point of its parameter grid (:data:`DETECTORS`, :func:`count_steps`);
:func:`loro_cv` then picks, for every recording, the grid point best on the *other* recordings
(ties: the first). SAM learns its ranges from the other recordings' true steps
(:func:`sam_loro_scores`). Step-count accuracy is ``1 - |counted - true| / true`` (:func:`accuracy`).
:func:`step_diagnosis` splits a count into missed and extra steps (one-to-one matching,
:func:`ilocalg.pdr.robust.match_steps`); :func:`truth_artefacts` finds the heel sensor's double triggers.

References
----------
Oxford step counter data set (its README_DataSet.md: recordings, heel-sensor truth);
Chiu, P.-J. (2013), i-Loc M.S. thesis, NCTU, sec. 4.1 (SAM, eq. 8-15);
Luo et al. (2017), sec. 3.4.2 (peak window); Chao (2008), Fig 3.9 (slope sign change).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.io.schema import ACC_COLS
from ilocalg.pdr.registry import DETECTOR_RATE_HZ, detect_steps
from ilocalg.pdr.robust import RobustSignal
from ilocalg.pdr.sam import (
    SAM_TESTED_FEATURES,
    learn_feature_ranges,
    match_waves_to_steps,
    passes_ranges,
    range_bounds,
    sam_waves,
)
from ilocalg.pdr.signals import resample_uniform, sample_rate_hz

__all__ = ["RATE_HZ", "SAM_RATE_HZ", "Prepared", "prepare", "accuracy", "DETECTORS", "detector_params",
           "count_steps", "loro_cv", "sam_loro_scores", "score_detector", "step_diagnosis", "diagnosis_window",
           "truth_artefacts", "is_development", "split_summary", "NAC_GRID", "ONSET_GRID", "OWN_CAUSES",
           "walk_gate_sweep", "error_causes", "LOW_RATE_HZ", "decimate_recording",
           "rate_robustness"]

RATE_HZ = DETECTOR_RATE_HZ["robust"]
SAM_RATE_HZ = DETECTOR_RATE_HZ["sam"]


@dataclass(frozen=True)
class Prepared:
    """One recording resampled for the detectors."""

    name: str
    meta: dict
    true_steps: int
    step_t_s: np.ndarray
    t_s: np.ndarray            # 100 Hz grid
    acc_mps2: np.ndarray       # (n, 3) on the grid
    t50_s: np.ndarray          # 50 Hz grid (SAM)
    acc50_mps2: np.ndarray
    #: The 100 Hz log for the robust and find_peaks detectors, keeping what each detection computes for the next
    #: one with other parameters (:class:`ilocalg.pdr.robust.RobustSignal`; made anew by ``dataclasses.replace``).
    robust: RobustSignal = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "robust", RobustSignal(self.acc_mps2, self.t_s))


def prepare(rec) -> Prepared:
    """Resample one recording (an :class:`ilocalg.io.oxford.OxfordRecording`) to the common rates."""
    t = rec.imu.index.to_numpy()
    acc = rec.imu[list(ACC_COLS)].to_numpy()
    au, tu = resample_uniform(acc, t, RATE_HZ)
    a50, t50 = resample_uniform(acc, t, SAM_RATE_HZ)
    return Prepared(rec.name, dict(rec.meta), rec.true_steps, rec.step_t_s, tu, au, t50, a50)


def accuracy(counted, true) -> np.ndarray:
    """Step-count accuracy ``1 - |counted - true| / true``."""
    c, n = np.asarray(counted, dtype=float), np.asarray(true, dtype=float)
    return 1.0 - np.abs(c - n) / n


def _grid(**axes) -> list[dict]:
    keys = list(axes)
    return [dict(zip(keys, v, strict=True)) for v in itertools.product(*axes.values())]


#: Parameter grids (full, fast) of the tuned detectors.
DETECTORS = {
    "robust": (_grid(cutoff_hz=[2.0, 2.5, 3.0], prominence_mps2=[0.3, 0.5, 0.8, 1.2], max_step_s=[1.0, 1.2],
                     min_bout_steps=[4, 6, 8]),
               _grid(cutoff_hz=[2.0, 2.5], prominence_mps2=[0.3, 0.8], max_step_s=[1.0], min_bout_steps=[4, 8])),
    "find_peaks": (_grid(cutoff_hz=[3.0], prominence_mps2=[0.3, 0.5, 0.8, 1.2, 1.6, 2.0], max_step_s=[np.inf],
                         min_bout_steps=[1]),
                   _grid(cutoff_hz=[3.0], prominence_mps2=[0.5, 1.2], max_step_s=[np.inf], min_bout_steps=[1])),
    "peak_window": (_grid(threshold_mps2=[0.5, 1.0, 1.5, 2.0, 3.0]), _grid(threshold_mps2=[1.0, 2.0])),
    "sign_change": (_grid(n=[2, 5, 10, 15]), _grid(n=[5, 10])),
    "sam": (_grid(q=[(0.05, 0.95), (0.01, 0.99), (0.0, 1.0)]), _grid(q=[(0.05, 0.95), (0.0, 1.0)])),
}


def detector_params(detector: str, params: dict) -> dict:
    """A grid point as the registered detector's keyword arguments (``n`` is the sign-change MA half-width)."""
    if detector == "sign_change":
        return {"n_left": params["n"], "n_right": params["n"], "smooth": True}
    if detector == "peak_window":
        return {**params, "rule": "valley_rise"}
    return dict(params)


#: Grid detectors that take the recording's :class:`ilocalg.pdr.robust.RobustSignal` in place of its log (their
#: grid points then share the filtering, the peaks and the walk detection that do not depend on them).
_ON_ROBUST_SIGNAL = ("robust", "find_peaks")


def count_steps(p: Prepared, detector: str, params: dict) -> int:
    """Steps counted in one prepared recording by a grid detector (not SAM, which needs training)."""
    if detector not in DETECTORS or detector == "sam":
        raise ValueError(f"unknown grid detector {detector!r}; known: {sorted(set(DETECTORS) - {'sam'})}")
    acc = p.robust if detector in _ON_ROBUST_SIGNAL else p.acc_mps2
    return len(detect_steps(detector, acc, p.t_s, **detector_params(detector, params)))


def loro_cv(score: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Leave-one-recording-out choice: for each recording the grid row best on the others.

    Parameters
    ----------
    score : ndarray, shape (n_grid, n_recordings)
        Accuracy of every grid point on every recording.

    Returns
    -------
    held_out : ndarray, shape (n_recordings,)
        Accuracy of each recording under the grid point chosen without it.
    choice : ndarray of int, shape (n_recordings,)
    """
    s = np.asarray(score, dtype=float)
    if s.ndim != 2 or s.shape[1] < 2:
        raise ValueError(f"score must have shape (n_grid, n_recordings >= 2), got {s.shape}")
    others = (s.sum(axis=1, keepdims=True) - s) / (s.shape[1] - 1)
    choice = np.argmax(others, axis=0)
    return s[choice, np.arange(s.shape[1])], choice


def sam_loro_scores(prep: list[Prepared], grid: list[dict], tol_s: float = 0.25):
    """SAM leave-one-recording-out: for each fold, ranges learned on the other recordings' true steps.

    Returns ``held`` (grid x recordings: accuracy of each recording under each grid point, ranges learned
    without it), ``counts`` (the same as step counts) and ``choice`` (per recording, the grid point best
    on the others).
    """
    waves = [sam_waves(p.acc50_mps2, p.t50_s) for p in prep]
    train = [match_waves_to_steps(w, p.step_t_s, tol_s) for w, p in zip(waves, prep, strict=True)]
    n = len(prep)
    held = np.zeros((len(grid), n))
    counts = np.zeros((len(grid), n), dtype=int)
    choice = np.zeros(n, dtype=int)
    truth = np.array([p.true_steps for p in prep])
    # every recording's waves as one feature matrix: in_ranges' test on all of them at once, counted per recording
    feats = list(SAM_TESTED_FEATURES)
    x = np.concatenate([np.column_stack([w[f].to_numpy() for f in feats]) for w in waves])
    owner = np.repeat(np.arange(n), [len(w) for w in waves])
    for i in range(n):
        tr = pd.concat([train[j] for j in range(n) if j != i], ignore_index=True)
        fold = np.zeros((len(grid), n))
        for g, par in enumerate(grid):
            lo, hi = range_bounds(learn_feature_ranges(tr, *par["q"]), feats)
            c = np.bincount(owner[passes_ranges(x, lo, hi, len(feats))], minlength=n)
            fold[g] = accuracy(c, truth)
            counts[g, i] = c[i]
            held[g, i] = fold[g, i]
        others = np.delete(fold, i, axis=1).mean(axis=1)
        choice[i] = int(np.argmax(others))
    return held, counts, choice


def score_detector(prep: list[Prepared], detector: str, grid: list[dict]):
    """One detector's leave-one-recording-out result over its ``grid``.

    Returns ``counted`` and ``held_out`` (per recording: steps and accuracy under the grid point chosen
    without it), ``score`` (grid x recordings accuracy; SAM: ranges learned without the recording) and
    ``choice`` (the chosen grid row per recording).
    """
    truth = np.array([p.true_steps for p in prep])
    cols = np.arange(len(prep))
    if detector == "sam":
        score, counts, choice = sam_loro_scores(prep, grid)
        return counts[choice, cols], score[choice, cols], score, choice
    counts = np.array([[count_steps(p, detector, par) for p in prep] for par in grid])
    score = accuracy(counts, truth[None, :])
    held, choice = loro_cv(score)
    return counts[choice, cols], held, score, choice


def step_diagnosis(prep: list[Prepared], recordings=None, params: dict | None = None,
                   tol_s: float = 0.25) -> pd.DataFrame:
    """Per recording: true, counted, *missed* and *extra* steps of the robust detector, and the phone's counter.

    Detections are matched one-to-one to the heel-sensor steps within ``tol_s``
    (:func:`ilocalg.pdr.robust.match_steps`); a count alone hides missed steps balanced by extra ones.
    ``missed_close_to_true`` counts missed true steps closer than 0.75 median step intervals to another
    true step (a heel-sensor double trigger is the likely cause, not the detector);
    ``true_steps_without_close_repeats`` is the true count less the true steps that follow the previous
    one by under 0.75 median intervals, with ``accuracy_without_close_repeats`` against it (a
    sensitivity check, not the score).
    ``hardware_steps`` is the phone's own step counter where the recording has one (the data set's
    validation layout; the optimisation recordings have none: NaN), with its accuracy beside.
    ``n_heel_bounces`` (heel-sensor bounces in the truth, :func:`ilocalg.io.oxford.heel_bounces_mask`),
    ``true_steps_published`` (the count with each bounce a step, the data set's own) and
    ``true_steps_bounces_merged`` (without them), with ``accuracy_bounces_merged`` against the latter;
    ``n_unpaired_landings`` (a foot landing twice with no landing of the other foot between: most likely a
    landing its sensor missed) and ``accuracy_unpaired_added`` against the merged truth plus those (a
    sensitivity check); NaN without ``recordings``. ``accuracy`` is against ``true_steps``, the recordings' as loaded.

    Parameters
    ----------
    prep : list of Prepared
    recordings : list of OxfordRecording, optional
        The same recordings, for their hardware counters.
    params : dict, optional
        Robust detector parameters (default :data:`ilocalg.pdr.robust.ROBUST_DEFAULTS`).
    """
    from ilocalg.pdr.robust import ROBUST_DEFAULTS, detect_steps_robust, match_steps

    par = dict(ROBUST_DEFAULTS if params is None else params)
    rows = []
    for k, p in enumerate(prep):
        d = detect_steps_robust(p.robust, p.t_s, **par)
        tm, dm = match_steps(p.step_t_s, d["t_s"].to_numpy(), tol_s)
        hw = None if recordings is None else recordings[k].hardware_steps
        dt = np.diff(p.step_t_s)
        gap = np.minimum(np.r_[np.inf, dt], np.r_[dt, np.inf])     # to the nearer neighbouring true step
        close = gap < 0.75 * np.median(dt) if dt.size else np.zeros(tm.size, dtype=bool)
        rows.append({"recording": p.name, "position": p.meta.get("position", ""), "phone": p.meta.get("phone", ""),
                     "true_steps": p.true_steps, "counted": len(d), "missed": int((~tm).sum()),
                     "extra": int((~dm).sum()), "missed_close_to_true": int((~tm & close).sum()),
                     "true_steps_without_close_repeats": int(p.true_steps - (dt < 0.75 * np.median(dt)).sum())
                     if dt.size else p.true_steps,
                     "accuracy": float(accuracy(len(d), p.true_steps)),
                     "median_step_interval_s": float(np.median(dt)) if dt.size else float("nan"),
                     "accuracy_without_close_repeats": float("nan"),
                     "hardware_steps": float("nan") if hw is None else float(hw),
                     "hardware_accuracy": float("nan") if hw is None else float(accuracy(hw, p.true_steps)),
                     **_bounce_counts(None if recordings is None else recordings[k], len(d))})
    out = pd.DataFrame(rows)
    out["accuracy_without_close_repeats"] = accuracy(out["counted"], out["true_steps_without_close_repeats"])
    return out


def _bounce_counts(rec, counted: int) -> dict:
    """Both truths of one recording (published, heel bounces merged) and the count's accuracy against the latter."""
    if rec is None:
        nan = float("nan")
        return {"n_heel_bounces": nan, "true_steps_published": nan, "true_steps_bounces_merged": nan,
                "accuracy_bounces_merged": nan, "n_unpaired_landings": nan, "accuracy_unpaired_added": nan}
    published = rec.true_steps + rec.n_heel_bounces_merged
    merged = published - rec.n_heel_bounces
    return {"n_heel_bounces": rec.n_heel_bounces, "true_steps_published": published,
            "true_steps_bounces_merged": merged, "accuracy_bounces_merged": float(accuracy(counted, merged)),
            "n_unpaired_landings": rec.n_unpaired_landings,
            "accuracy_unpaired_added": float(accuracy(counted, merged + rec.n_unpaired_landings))}


def is_development(name: str) -> bool:
    """The development half of the Oxford optimisation recordings: odd repeat numbers (``..._1``, ``..._3``).

    Every phone/user/surface/placement of the set was recorded at least twice (``_1``, ``_2``; four times for
    two in-hand sets), so the odd repeats hold every condition once or twice and the even repeats, kept
    apart, hold the same conditions. A rule fixed by the names, not by any result.
    """
    tail = name.rsplit("_", 1)[-1]
    if not tail.isdigit():
        raise ValueError(f"recording name {name!r} does not end in _<repeat number>")
    return int(tail) % 2 == 1


def split_summary(diag: pd.DataFrame, columns=(("published", "accuracy"),
                                              ("heel bounces merged", "accuracy_bounces_merged"),
                                              ("bounces merged, unpaired landings added", "accuracy_unpaired_added")),
                  goal_min: float = 0.98, seed: int = 0) -> pd.DataFrame:
    """Per truth and recording set (development, held out, all): mean accuracy with a 95 % bootstrap interval
    over recordings (:func:`ilocalg.measure.stats.bootstrap`, seeded), median, worst, recordings below
    ``goal_min``."""
    from ilocalg.measure.stats import bootstrap

    dev = diag["recording"].map(is_development).to_numpy(dtype=bool)
    rows = []
    for truth, col in columns:
        a_all = diag[col].to_numpy(dtype=float)
        for name, mask in (("development", dev), ("held out", ~dev), ("all", np.ones(dev.size, dtype=bool))):
            a = a_all[mask]
            if a.size < 2 or np.isnan(a).any():
                continue
            est = bootstrap(a, np.mean, rng=seed)
            rows.append({"truth": truth, "recordings": name, "n": int(a.size), "mean_accuracy": float(a.mean()),
                         "ci_low": est.ci_low, "ci_high": est.ci_high, "median_accuracy": float(np.median(a)),
                         "min_accuracy": float(a.min()), f"n_below_{goal_min:.0%}": int((a < goal_min).sum())})
    return pd.DataFrame(rows)


#: The rate :func:`rate_robustness` decimates to, Hz: the lowest rate in the Oxford optimisation set (its two
#: Samsung_Jamie recordings, 100.0 Hz) and the detectors' common rate (:data:`RATE_HZ`).
LOW_RATE_HZ = 100.0


def decimate_recording(rec, factor: int, anti_alias: bool = True):
    """``rec`` (an :class:`ilocalg.io.oxford.OxfordRecording`) as a phone sampling ``factor`` times slower would
    have logged it: every ``factor``-th sample, after :func:`scipy.signal.decimate`'s zero-phase order-8 Chebyshev
    type I low-pass at 0.8 of the new Nyquist frequency when ``anti_alias`` (a sensor's own filter at a lower output
    rate), or as they are otherwise (aliasing kept). The truth is unchanged. The filter assumes uniform sampling;
    on a log whose spacing varies it is applied sample by sample all the same."""
    import dataclasses

    from scipy import signal as ss

    if int(factor) != factor or factor < 1:
        raise ValueError(f"factor must be a whole number >= 1, got {factor}")
    factor = int(factor)
    if factor == 1:
        return rec
    imu = rec.imu
    if anti_alias:
        cols = list(ACC_COLS)
        a = ss.decimate(imu[cols].to_numpy(dtype=np.float64), factor, axis=0, zero_phase=True)
        out = pd.DataFrame(a, index=imu.index[::factor][:a.shape[0]], columns=cols)
    else:
        out = imu.iloc[::factor]
    return dataclasses.replace(rec, imu=out)


def rate_robustness(recordings, params: dict | None = None, rate_hz: float = LOW_RATE_HZ) -> pd.DataFrame:
    """The robust detector (``params``: :data:`ilocalg.pdr.robust.ROBUST_DEFAULTS`) on each recording as logged
    and decimated to about ``rate_hz`` (by the whole factor nearest its median rate over ``rate_hz``,
    :func:`decimate_recording`) with and without an anti-alias filter: the step count and the accuracy against
    the published truth of each. A check of the detector's one parameter set for phones sampling at 100-400 Hz
    (:mod:`ilocalg.pdr.robust`, step 1): nothing is chosen from it. One row per recording: ``recording``,
    ``development`` (:func:`is_development`), ``rate_hz`` (median rate as logged), ``factor``, ``rate_decimated_hz``,
    ``true_steps``, ``counted_<as logged|decimated|decimated_anti_alias>`` and ``accuracy_<...>``.
    """
    from ilocalg.pdr.robust import ROBUST_DEFAULTS

    par = {k: v for k, v in (ROBUST_DEFAULTS if params is None else params).items() if k != "rate_hz"}
    rows = []
    for rec in recordings:
        rate = sample_rate_hz(rec.imu.index.to_numpy())
        k = max(int(round(rate / rate_hz)), 1)
        row = {"recording": rec.name, "development": is_development(rec.name), "rate_hz": rate, "factor": k,
               "rate_decimated_hz": rate / k, "true_steps": rec.true_steps}
        for name, r in (("as_logged", rec), ("decimated", decimate_recording(rec, k, anti_alias=False)),
                        ("decimated_anti_alias", decimate_recording(rec, k, anti_alias=True))):
            n = count_steps(prepare(r), "robust", par)
            row[f"counted_{name}"] = n
            row[f"accuracy_{name}"] = float(accuracy(n, rec.true_steps))
        rows.append(row)
    return pd.DataFrame(rows)


#: Walk-detection thresholds swept on the development half (:func:`walk_gate_sweep`; None: gate off).
NAC_GRID = (None, 0.0, 0.3, 0.4, 0.5, 0.6, 0.7)
#: Gait-onset ratios swept on the development half (``walk_gate_sweep(..., param="min_onset_ratio")``; None: off).
ONSET_GRID = (None, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5)
#: The detector's own error causes (:data:`ilocalg.pdr.step_errors.CAUSES` less the truth-limited ones), as
#: ``<kind>_<cause>``, counted per grid point by :func:`walk_gate_sweep`.
OWN_CAUSES = ("missed_walk_end", "missed_inside_walk", "extra_pause", "extra_before_walk", "extra_after_walk",
              "extra_inside_walk")


def walk_gate_sweep(prep: list[Prepared], recordings, grid=NAC_GRID, param: str = "min_stride_nac",
                    tol_s: float = 0.25) -> pd.DataFrame:
    """One parameter of the robust detector's walk detection swept on the development half only.

    Each grid value of ``param`` (``min_stride_nac``, ``min_onset_ratio``; the others at
    :data:`ilocalg.pdr.robust.ROBUST_DEFAULTS`) is scored on the development recordings (:func:`is_development`;
    the others are not read) against the published truth and the truth with heel bounces merged: mean and worst
    accuracy, and how often leave-one-recording-out over the development recordings (:func:`loro_cv`) chooses
    it; and the detector's own errors against the merged truth, summed per cause
    (:func:`ilocalg.pdr.step_errors.classify_step_errors`, :data:`OWN_CAUSES`, with their total ``own_errors``).
    ``recordings`` are the :class:`ilocalg.io.oxford.OxfordRecording` of ``prep``, for the bounce counts.
    """
    from ilocalg.pdr.robust import ROBUST_DEFAULTS, detect_steps_robust
    from ilocalg.pdr.step_errors import classify_step_errors, count_causes

    if param not in ROBUST_DEFAULTS:
        raise ValueError(f"unknown robust detector parameter {param!r}; known: {sorted(ROBUST_DEFAULTS)}")
    dev = [k for k, p in enumerate(prep) if is_development(p.name)]
    if len(dev) < 2:
        raise ValueError(f"need at least 2 development recordings (odd repeats), got {len(dev)}")
    published = np.array([recordings[k].true_steps + recordings[k].n_heel_bounces_merged for k in dev])
    merged = published - np.array([recordings[k].n_heel_bounces for k in dev])
    counts = np.zeros((len(grid), len(dev)), dtype=int)
    own = np.zeros((len(grid), len(OWN_CAUSES)), dtype=int)
    for g, value in enumerate(grid):
        for j, k in enumerate(dev):
            det = detect_steps_robust(prep[k].robust, prep[k].t_s, **{**ROBUST_DEFAULTS, param: value})["t_s"]
            counts[g, j] = det.size
            truth = prep[k].step_t_s[~recordings[k].step_is_heel_bounce]
            n = count_causes(classify_step_errors(truth, det.to_numpy(), tol_s))
            own[g] += [n[c] for c in OWN_CAUSES]
    out = pd.DataFrame({param: ["off" if g is None else g for g in grid]})
    for truth, n in (("published", published), ("bounces_merged", merged)):
        score = accuracy(counts, n[None, :])
        _, choice = loro_cv(score)
        out[f"mean_accuracy_{truth}"] = score.mean(axis=1)
        out[f"min_accuracy_{truth}"] = score.min(axis=1)
        out[f"loro_chosen_{truth}"] = np.bincount(choice, minlength=len(grid))
    out["n_recordings"] = len(dev)
    for c, col in zip(OWN_CAUSES, own.T, strict=True):
        out[f"own_{c}"] = col
    out["own_errors"] = own.sum(axis=1)
    return out


def error_causes(prep: list[Prepared], recordings, params: dict | None = None,
                 tol_s: float = 0.25) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Every missed and extra step of the robust detector against the truth with heel bounces merged, with its cause.

    The detections (``params``, default :data:`ilocalg.pdr.robust.ROBUST_DEFAULTS`) are classified by
    :func:`ilocalg.pdr.step_errors.classify_step_errors` against the heel-sensor step times less the bounces
    (:attr:`ilocalg.io.oxford.OxfordRecording.step_is_heel_bounce`).

    Returns
    -------
    errors : DataFrame
        One row per missed or extra step: ``recording``, ``position``, ``development``
        (:func:`is_development`), ``kind``, ``t_s``, ``cause``, ``gap_intervals``.
    per_recording : DataFrame
        ``recording``, ``position``, ``phone``, ``development``, ``counted``, ``true_steps_bounces_merged``,
        ``accuracy_bounces_merged``, one column per cause (:data:`ilocalg.pdr.step_errors.CAUSES`),
        ``detector_net`` (the detector's own extra less missed steps), ``truth_gap`` (detections in the truth's
        gaps) beside ``n_unpaired_landings`` (the loader's count of landings the heel sensors missed, from the
        foot states alone), and ``accuracy_truth_gaps_added`` (against the merged truth plus ``truth_gap``: the
        count's accuracy were the truth complete where it evidently is not; a sensitivity check, not the score).
    """
    from ilocalg.pdr.robust import ROBUST_DEFAULTS, detect_steps_robust
    from ilocalg.pdr.step_errors import classify_step_errors, count_causes

    par = dict(ROBUST_DEFAULTS if params is None else params)
    events, rows = [], []
    for p, rec in zip(prep, recordings, strict=True):
        if rec.step_is_heel_bounce is None:
            raise ValueError(f"{rec.name}: no heel-bounce marks (not an optimisation recording)")
        truth = p.step_t_s[~rec.step_is_heel_bounce]
        det = detect_steps_robust(p.robust, p.t_s, **par)["t_s"].to_numpy()
        e = classify_step_errors(truth, det, tol_s)
        dev = is_development(p.name)
        pos = p.meta.get("position", "")
        events.append(e.assign(recording=p.name, position=pos, development=dev))
        n = count_causes(e)
        rows.append({"recording": p.name, "position": pos, "phone": p.meta.get("phone", ""), "development": dev,
                     "counted": det.size, "true_steps_bounces_merged": truth.size,
                     "accuracy_bounces_merged": float(accuracy(det.size, truth.size)), **n,
                     "n_unpaired_landings": rec.n_unpaired_landings,
                     "accuracy_truth_gaps_added": float(accuracy(det.size, truth.size + n["truth_gap"]))})
    cols = ["recording", "position", "development", "kind", "t_s", "cause", "gap_intervals"]
    return pd.concat(events, ignore_index=True)[cols], pd.DataFrame(rows)


def diagnosis_window(p: Prepared, t0_s: float, span_s: float = 12.0, params: dict | None = None,
                     tol_s: float = 0.25) -> dict:
    """Signal, true and detected steps of one recording in ``[t0_s, t0_s + span_s]`` (for a figure)."""
    from ilocalg.pdr.robust import ROBUST_DEFAULTS, detect_steps_robust, lowpass_magnitude, match_steps
    from ilocalg.pdr.signals import magnitude_mps2

    par = dict(ROBUST_DEFAULTS if params is None else params)
    d = detect_steps_robust(p.robust, p.t_s, **par)
    det = d["t_s"].to_numpy()
    tm, dm = match_steps(p.step_t_s, det, tol_s)
    y = lowpass_magnitude(magnitude_mps2(p.acc_mps2), par["rate_hz"], par["cutoff_hz"])
    w = (p.t_s >= t0_s) & (p.t_s <= t0_s + span_s)
    wt = (p.step_t_s >= t0_s) & (p.step_t_s <= t0_s + span_s)
    wd = (det >= t0_s) & (det <= t0_s + span_s)
    return {"t_s": p.t_s[w], "signal_mps2": y[w], "true_t_s": p.step_t_s[wt], "det_t_s": det[wd],
            "true_matched": tm[wt], "det_matched": dm[wd]}


def truth_artefacts(recordings, min_interval_s: float = 0.25) -> pd.DataFrame:
    """True steps that follow the previous true step by less than ``min_interval_s`` (sensor double triggers)."""
    rows = []
    for r in recordings:
        d = np.diff(np.asarray(r.step_t_s))
        k = int((d < min_interval_s).sum())
        rows.append({"recording": r.name, "true_steps": r.true_steps, f"intervals_below_{min_interval_s:g}s": k,
                     "share_of_steps": k / r.true_steps if r.true_steps else float("nan")})
    return pd.DataFrame(rows)
