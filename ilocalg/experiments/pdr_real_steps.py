"""Every step detector on the real Oxford step counter recordings, scored by leave-one-recording-out CV.

Each recording's accelerometer log is resampled to a common rate (100 Hz; 50 Hz for SAM, whose
X1 feature depends on the rate) so one parameter set serves every phone. Each detector has a small
parameter grid; for every recording, the grid point with the best mean accuracy on the other 47
recordings is chosen and the held-out recording is scored with it (ties: the first grid point).
Step-count accuracy is ``1 - |counted - true| / true`` per recording. The preparation, the grids, the
tuning and the step diagnosis live in :mod:`ilocalg.pdr.step_evaluate`.

Detectors
---------
``robust``            the toolkit's best detector (:mod:`ilocalg.pdr.robust`)
``find_peaks``        a plain baseline: low-pass + :func:`scipy.signal.find_peaks` with a tuned prominence
``peak_window``       the fingerprint+PDR paper's detector (Luo et al. 2017, sec. 3.4.2), tuned threshold
``sign_change``       the PSO thesis's slope-sign-change detector with the +-RMS band (Chao 2008, Fig 3.9),
                      on the vertical acceleration, tuned moving-average width
``sam``               i-Loc SAM (eq. 8-15), ranges learned from the training recordings' true steps
                      (quantiles tuned among 5/95 % (the thesis), 1/99 % and 0/100 %)

References
----------
Oxford step counter data set (reference: its README says the project's own windowed peak detector
scored 93.7 % mean / 96.8 % median accuracy on these 48 recordings; reference values).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.oxford import MIN_STRIDE_S, OxfordRecording, load_oxford_archive
from ilocalg.io.paths import dataset_path
from ilocalg.papers import PAPERS, paper_ref, reading, readings_table
from ilocalg.pdr.robust import ROBUST_DEFAULTS
from ilocalg.pdr.step_evaluate import (
    DETECTORS,
    LOW_RATE_HZ,
    ONSET_GRID,
    RATE_HZ,
    SAM_RATE_HZ,
    Prepared,
    accuracy,
    diagnosis_window,
    error_causes,
    loro_cv,
    prepare,
    rate_robustness,
    score_detector,
    split_summary,
    step_diagnosis,
    truth_artefacts,
    walk_gate_sweep,
)

__all__ = ["run", "load", "missing_table", "headline", "truth_headline", "gate_headline", "cause_headline",
           "causes_by_split", "rate_summary", "rate_headline", "worst", "readings", "GOAL_MEAN", "GOAL_MIN",
           "MATCH_TOL_S",
           # re-exported from ilocalg.pdr.step_evaluate for the notebook
           "Prepared", "prepare", "DETECTORS", "accuracy", "loro_cv", "step_diagnosis", "diagnosis_window",
           "truth_artefacts", "LOW_RATE_HZ"]

OXFORD_REPORT = "Oxford step counter report"
# Settings from the paper
# -----------------------
# OXFORD_MEAN_PAPER, OXFORD_MEDIAN_PAPER: the Oxford data set's README, its own windowed peak
# detector on the 48 recordings (reference values). GOAL_MEAN and GOAL_MIN are this toolkit's
# goals for its best detector, not paper values.
#: The data set's own report for its windowed peak detector on the 48 recordings (reference values).
OXFORD_MEAN_PAPER = 0.937
OXFORD_MEDIAN_PAPER = 0.968
#: The toolkit's goal for its best detector: mean accuracy and worst recording.
GOAL_MEAN = 0.993
GOAL_MIN = 0.98
#: Largest |t_true - t_detected| of a matched step in the diagnosis tables, s (a setting: below half of the
#: shortest step interval the detectors allow, ``2 min_step_s``; :func:`ilocalg.pdr.step_evaluate.step_diagnosis`).
MATCH_TOL_S = 0.25
ARCHIVE = "optimisation_data.tar.xz"


def load(data_dir=None, names=None) -> list[OxfordRecording]:
    """The Oxford optimisation recordings from ``data_dir`` (a folder holding the archive, or the archive)."""
    p = Path(data_dir) if data_dir is not None else dataset_path("oxford_step_counter")
    archive = p / ARCHIVE if p.is_dir() else p
    return load_oxford_archive(archive, names)


def run(seed: int = 0, fast: bool = False, data_dir=None, recordings: list[OxfordRecording] | None = None,
        detectors=tuple(DETECTORS)) -> dict[str, pd.DataFrame]:
    """Score every detector on the Oxford recordings with leave-one-recording-out tuning.

    Parameters
    ----------
    seed : int
        Unused (no randomness); kept for the experiment signature.
    fast : bool
        Every third recording and the small grids.
    data_dir : path, optional
        ``oxford_step_counter`` folder (default :func:`ilocalg.io.paths.dataset_path`).
    recordings : list of OxfordRecording, optional
        Already loaded recordings (then ``data_dir`` is ignored).

    Returns
    -------
    dict of DataFrame
        ``per_recording`` (counts and accuracies of every detector), ``summary`` (per detector:
        mean, median, min accuracy, recordings below 98 %), ``per_position``, ``per_phone``,
        ``choices`` (grid point chosen per fold), ``grid`` (in-sample accuracy of every grid point),
        ``robust_diagnosis`` (per recording at the robust defaults: missed, extra, heel bounces, both truths),
        ``robust_diagnosis_by_position``, ``robust_by_truth_and_split`` (development / held-out halves,
        :func:`ilocalg.pdr.step_evaluate.is_development`, against the published truth and with heel bounces
        merged, mean with a bootstrap interval), ``walk_gate_sweep`` (the robust detector's walk detection
        threshold on the development half only, with its leave-one-recording-out choices and the detector's own
        errors per cause), ``onset_sweep`` (the same for the gait-onset ratio ``min_onset_ratio``), ``robust_errors``
        (every missed and extra step of the robust detector against the bounce-merged truth, with its cause,
        :func:`ilocalg.pdr.step_evaluate.error_causes`), ``robust_error_causes`` (their counts per recording),
        ``robust_error_causes_by_split`` (:func:`causes_by_split`), ``rate_robustness`` (the robust detector on each
        recording as logged and decimated to about 100 Hz, :func:`ilocalg.pdr.step_evaluate.rate_robustness`),
        ``rate_robustness_summary`` (:func:`rate_summary`), ``comparison``, ``readings`` (:func:`readings`).
    """
    recs = recordings if recordings is not None else load(data_dir)
    if fast:
        recs = recs[::3]
    if len(recs) < 3:
        raise ValueError(f"need at least 3 recordings for leave-one-out tuning, got {len(recs)}")
    prep = [prepare(r) for r in recs]
    truth = np.array([p.true_steps for p in prep])
    per = pd.DataFrame({"recording": [p.name for p in prep],
                        "phone": [p.meta.get("phone", "") for p in prep],
                        "position": [p.meta.get("position", "") for p in prep],
                        "user": [p.meta.get("user", "") for p in prep],
                        "true_steps": truth})
    choices, grid_rows = [], []
    for det in detectors:
        grid = DETECTORS[det][1 if fast else 0]
        counted, acc_held, score, choice = score_detector(prep, det, grid)
        per[f"{det}_steps"] = counted
        per[f"{det}_accuracy"] = acc_held
        for g, par in enumerate(grid):
            grid_rows.append({"detector": det, "params": _fmt(par), "mean_accuracy": float(score[g].mean()),
                              "min_accuracy": float(score[g].min()), "times_chosen": int((choice == g).sum())})
        choices.append(pd.DataFrame({"detector": det, "recording": per["recording"],
                                     "params": [_fmt(grid[c]) for c in choice]}))
    summ = []
    for det in detectors:
        a = per[f"{det}_accuracy"]
        summ.append({"detector": det, "mean_accuracy": float(a.mean()), "median_accuracy": float(a.median()),
                     "min_accuracy": float(a.min()), "n_below_98pct": int((a < GOAL_MIN).sum()),
                     "n_recordings": len(a)})
    summary = pd.DataFrame(summ).sort_values("mean_accuracy", ascending=False, kind="stable").reset_index(drop=True)
    cols = [f"{d}_accuracy" for d in detectors]
    by_pos = per.groupby("position")[cols].mean().reset_index()
    by_phone = per.groupby("phone")[cols].mean().reset_index()
    best = summary.iloc[0]
    comp = [
        paper_ref(OXFORD_REPORT, "README", f"mean step-count accuracy (best here: {best['detector']}, LORO)",
                  OXFORD_MEAN_PAPER * 100, best["mean_accuracy"] * 100, unit="%",
                  note="reference: the data set's own windowed peak detector"),
        paper_ref(OXFORD_REPORT, "README", f"median step-count accuracy (best here: {best['detector']}, LORO)",
                  OXFORD_MEDIAN_PAPER * 100, best["median_accuracy"] * 100, unit="%",
                  note="reference: the data set's own windowed peak detector"),
    ]
    diag = step_diagnosis(prep, recs, tol_s=MATCH_TOL_S)
    by_pos_diag = diag.groupby("position")[["accuracy", "accuracy_bounces_merged", "missed", "missed_close_to_true",
                                            "extra", "n_heel_bounces"]]
    by_pos_diag = by_pos_diag.agg(["mean", "min", "max"])
    by_pos_diag.columns = [f"{a}_{b}" for a, b in by_pos_diag.columns]
    errors, causes = error_causes(prep, recs, tol_s=MATCH_TOL_S)
    rates = rate_robustness(recs)
    return {"per_recording": per, "summary": summary, "per_position": by_pos, "per_phone": by_phone,
            "robust_errors": errors, "robust_error_causes": causes,
            "robust_error_causes_by_split": causes_by_split(causes),
            "robust_diagnosis": diag, "robust_diagnosis_by_position": by_pos_diag.reset_index(),
            "robust_by_truth_and_split": split_summary(diag, goal_min=GOAL_MIN, seed=seed),
            "walk_gate_sweep": walk_gate_sweep(prep, recs, tol_s=MATCH_TOL_S),
            "onset_sweep": walk_gate_sweep(prep, recs, ONSET_GRID, "min_onset_ratio", tol_s=MATCH_TOL_S),
            "choices": pd.concat(choices, ignore_index=True), "grid": pd.DataFrame(grid_rows),
            "rate_robustness": rates, "rate_robustness_summary": rate_summary(rates, seed),
            "comparison": pd.DataFrame(comp), "readings": readings(fast)}


_SOURCE = "Oxford step counter data set, SOURCE.txt "


def readings(fast: bool = False) -> pd.DataFrame:
    """One row per choice of :func:`run`: where the data set's description or a paper speaks of it (line numbers of
    ``oxford_step_counter/SOURCE.txt`` and of the papers' text copies), what it says, what the code does, and the
    source of every value neither gives. ``fast``: the run's small grids."""
    grids = {d: DETECTORS[d][1 if fast else 0] for d in DETECTORS}

    def axes(det: str) -> str:
        values = {k: list(dict.fromkeys(str(g[k]) for g in grids[det])) for k in grids[det][0]}   # grid order
        return "; ".join(f"{k} in [{', '.join(v)}]" for k, v in values.items())

    rb = ROBUST_DEFAULTS
    return readings_table([
        reading("ground truth", _SOURCE + "L10-14",
                "a step is a 0 -> 1 transition of either heel-pressure foot state; their count is the 'steps' column",
                "the published count (truth 'published'); beside it the count with heel-sensor bounces merged (a foot "
                f"landing again less than MIN_STRIDE_S = {MIN_STRIDE_S:g} s after its last landing) and, as a "
                "sensitivity check only, with the unpaired landings added",
                "MIN_STRIDE_S measured on the 48 recordings (ilocalg.io.oxford: a gap in the same foot's landing "
                "intervals at 0.50-0.55 s)"),
        reading("accuracy measure", _SOURCE + "L17-18", "accuracy = 1 - |counted - true| / true, per recording",
                "the same, per recording; mean, median, worst and recordings below the goal's floor", "data set"),
        reading("reference values", _SOURCE + "L17-18",
                f"the project's windowed peak detector: {OXFORD_MEAN_PAPER:.1%} mean, {OXFORD_MEDIAN_PAPER:.1%} median",
                "shown beside the best detector's leave-one-recording-out mean and median (comparison table); "
                "reference values, never a target", "data set"),
        reading("sampling", _SOURCE + "L8-9", "each phone at its fastest rate (~221-405 Hz, the Nexus 5 varies)",
                f"linear resampling of the 3-axis log to {RATE_HZ:g} Hz ({SAM_RATE_HZ:g} Hz for SAM, whose X1 "
                "feature scales with the rate)", "one parameter set for every phone; no value from the data set"),
        reading("sampling-rate check", _SOURCE + "L8-9", "each phone at its fastest rate (~221-405 Hz, the Nexus 5 "
                "varies)",
                "the robust detector (defaults) on each log as recorded and decimated by the whole factor nearest its "
                f"rate over {LOW_RATE_HZ:g} Hz, every factor-th sample and after scipy.signal.decimate's anti-alias "
                "low-pass; published truth; nothing chosen from it (tables rate_robustness, rate_robustness_summary)",
                f"{LOW_RATE_HZ:g} Hz: the lowest rate in the set (the Samsung_Jamie logs, measured) and the detectors' "
                "common rate"),
        reading("parameter choice", "", "silent (the data set is for optimising a detector's parameters)",
                "leave-one-recording-out: each recording scored with the grid point best on the other recordings"
                + (" (fast: every third recording)" if fast else ""),
                "the data set's own purpose (README_DataSet.md L7)"),
        reading("robust detector: signal", "", "not a paper's method",
                f"|a| (orientation-free), zero-phase 2nd-order Butterworth low-pass; grid: {axes('robust')}; "
                f"defaults cutoff_hz={rb['cutoff_hz']:g}, prominence_mps2={rb['prominence_mps2']:g}, "
                f"min_step_s={rb['min_step_s']:g}, max_step_s={rb['max_step_s']:g}, "
                f"min_bout_steps={rb['min_bout_steps']}",
                "grid chosen per held-out recording; the defaults are the values that search picks on the set; "
                "min_step_s: 240 steps/min, above walking cadences (Tudor-Locke et al. 2011)"),
        reading("robust detector: walk detection", "", "not a paper's method",
                f"a bout's first and last peaks dropped while the normalised auto-correlation of the stride around "
                f"them is below min_stride_nac = {rb['min_stride_nac']}; then its first peaks while less prominent "
                f"than min_onset_ratio = {rb['min_onset_ratio']} times the peak one stride later (gait onset); "
                "peaks inside a bout never dropped",
                "Rai et al. 2012 (normalised auto-correlation); Crenna & Frigo 1991 (the weight shift before the "
                "first step); both values chosen by leave-one-recording-out on the development half (odd repeats) "
                "only, tables walk_gate_sweep and onset_sweep"),
        reading("find_peaks baseline", "", "not a paper's method",
                f"low-pass |a| and scipy.signal.find_peaks, no bout gate; grid: {axes('find_peaks')}",
                "grid chosen per held-out recording"),
        reading("peak_window (Luo et al. 2017)", f"{PAPERS['luo']}, L175-189",
                "sliding-window peaks; a peak is rejected if it differs from the previous one by more than a "
                "threshold or its interval is outside 0.2-2 s; no threshold value",
                f"ilocalg.pdr.peak_window, valley-rise reading of the rule; grid: {axes('peak_window')}",
                "threshold not given: chosen per held-out recording from the grid"),
        reading("sign_change (Chao 2008)", f"{PAPERS['pso']}, L519-520 (Fig 3.9)",
                "slope sign changes of the filtered vertical acceleration; extrema inside the +-RMS band dropped",
                f"ilocalg.pdr.sign_change on the specific force along gravity; moving-average half-width "
                f"{axes('sign_change')}", "width not given for these phones: chosen per held-out recording"),
        reading("sam (Chiu 2013)", f"{PAPERS['iloc']}, L399 (eq. 8-15)",
                "seven feature ranges, each the 5 % and 95 % points of the training steps' CDFs",
                f"ranges learned on the other recordings' heel-sensor steps; quantile pairs {axes('sam')}",
                "the thesis's 5-95 % is one grid point; the others are sensitivity choices"),
        reading("development / held-out halves", "", "silent",
                "odd repeat numbers (_1, _3) develop, even repeats are kept apart (every condition of the set in "
                "both)", "a rule fixed by the recordings' names (ilocalg.pdr.step_evaluate.is_development)"),
        reading("step matching", "", "silent",
                f"a detection matches a true step within {MATCH_TOL_S:g} s, one-to-one in time order; unmatched "
                "ones within 0.5 s are paired as 'timing' (found, not the detector's count error)",
                "setting: below half the shortest step interval the detectors allow"),
    ])


def missing_table(path) -> pd.DataFrame:
    """The one-row table a notebook writes when the data set is absent."""
    return pd.DataFrame([{"dataset": "oxford_step_counter", "path": str(path), "present": False}])


#: The logs :func:`rate_summary` compares (label, column of ``rate_robustness``).
_RATE_LOGS = (("as logged", "accuracy_as_logged"), (f"decimated to ~{LOW_RATE_HZ:g} Hz", "accuracy_decimated"),
              (f"decimated to ~{LOW_RATE_HZ:g} Hz, anti-aliased", "accuracy_decimated_anti_alias"))


def rate_summary(rates: pd.DataFrame, seed: int = 0) -> pd.DataFrame:
    """Per log (as logged, decimated, decimated with an anti-alias filter) and half (development, held out, all):
    mean accuracy with a bootstrap interval, median, worst, recordings below the goal's floor
    (:func:`ilocalg.pdr.step_evaluate.split_summary`; its ``truth`` column named ``log`` here: the published truth
    throughout), and ``n_changed`` (recordings whose count differs from the count as logged)."""
    out = split_summary(rates, columns=_RATE_LOGS, goal_min=GOAL_MIN, seed=seed).rename(columns={"truth": "log"})
    dev = rates["development"].to_numpy(dtype=bool)
    masks = {"development": dev, "held out": ~dev, "all": np.ones(dev.size, dtype=bool)}
    col = {label: c.replace("accuracy_", "counted_") for label, c in _RATE_LOGS}
    out["n_changed"] = [int((rates.loc[masks[r["recordings"]], col[r["log"]]]
                             != rates.loc[masks[r["recordings"]], "counted_as_logged"]).sum())
                        for _, r in out.iterrows()]
    return out


def rate_headline(tables: dict) -> str:
    """One sentence per decimated log: all recordings' mean and worst accuracy against the logs as recorded."""
    t = tables["rate_robustness_summary"]
    t = t[t["recordings"] == "all"].set_index("log")
    base = t.loc[_RATE_LOGS[0][0]]
    rates = tables["rate_robustness"]
    out = [f"as logged ({rates['rate_hz'].min():.0f}-{rates['rate_hz'].max():.0f} Hz): mean "
           f"{base['mean_accuracy']:.2%}, worst {base['min_accuracy']:.2%}"]
    for label, _ in _RATE_LOGS[1:]:
        r = t.loc[label]
        change = 100 * (r["mean_accuracy"] - base["mean_accuracy"])
        out.append(f"{label}: mean {r['mean_accuracy']:.2%} ({change:+.2f} points), "
                   f"worst {r['min_accuracy']:.2%}, {int(r['n_changed'])} of {int(r['n'])} counts changed")
    return "; ".join(out)


def worst(tables: dict, n: int = 5) -> pd.DataFrame:
    """The ``n`` recordings the best detector counts worst."""
    det = tables["summary"].iloc[0]["detector"]
    cols = ["recording", "true_steps", f"{det}_steps", f"{det}_accuracy"]
    return tables["per_recording"].nsmallest(n, f"{det}_accuracy")[cols].reset_index(drop=True)


def headline(tables: dict) -> str:
    """One sentence with the best detector's measured accuracy against the goal."""
    b = tables["summary"].iloc[0]
    met = b["mean_accuracy"] >= GOAL_MEAN and b["min_accuracy"] >= GOAL_MIN
    return (f"best detector {b['detector']}: mean {b['mean_accuracy']:.2%}, median {b['median_accuracy']:.2%}, "
            f"worst {b['min_accuracy']:.2%}, {b['n_below_98pct']} of {b['n_recordings']} recordings below 98 % "
            f"(goal mean >= {GOAL_MEAN:.1%} and none below {GOAL_MIN:.0%}: {'met' if met else 'NOT met'})")


def truth_headline(tables: dict) -> str:
    """One sentence per truth: the robust detector (defaults) on the held-out half against the goal."""
    t = tables["robust_by_truth_and_split"]
    out = []
    for _, r in t[t["recordings"] == "held out"].iterrows():
        met = r["mean_accuracy"] >= GOAL_MEAN and r["min_accuracy"] >= GOAL_MIN
        out.append(f"held-out recordings, truth {r['truth']}: mean {r['mean_accuracy']:.2%} "
                   f"(95 % CI {r['ci_low']:.2%}-{r['ci_high']:.2%}), worst {r['min_accuracy']:.2%} "
                   f"(goal: {'met' if met else 'NOT met'})")
    return "; ".join(out)


def gate_headline(tables: dict, table: str = "walk_gate_sweep", param: str = "min_stride_nac") -> str:
    """One sentence: the value of a walk-detection parameter the development folds choose, beside the detector's
    default (``table``/``param``: ``walk_gate_sweep``/``min_stride_nac`` or ``onset_sweep``/``min_onset_ratio``),
    and the detector's own errors on the development half with it off and at the default."""
    g = tables[table]
    out = []
    for truth in ("bounces_merged", "published"):
        best = g.loc[g[f"loro_chosen_{truth}"].idxmax()]
        mean, low = best[f"mean_accuracy_{truth}"], best[f"min_accuracy_{truth}"]
        out.append(f"against the {truth.replace('_', ' ')} truth, {int(best[f'loro_chosen_{truth}'])} of "
                   f"{int(best['n_recordings'])} development folds choose {param} = {best[param]} "
                   f"(development mean {mean:.2%}, worst {low:.2%})")
    default = ROBUST_DEFAULTS[param]
    own = g.set_index(g[param].astype(str))["own_errors"]
    if "off" in own.index and str(default) in own.index:
        out.append(f"the detector's own errors against the bounce-merged truth: {own['off']} with it off, "
                   f"{own[str(default)]} at the default")
    return "; ".join(out) + f"; the detector's default: {default}"


def causes_by_split(causes: pd.DataFrame) -> pd.DataFrame:
    """Per half (development, held out) and placement: the causes of the robust detector's errors, summed.

    ``n_below_goal`` counts the recordings below :data:`GOAL_MIN` against the bounce-merged truth,
    ``n_below_goal_truth_gaps_added`` those still below it once the detections in the truth's gaps are added to
    the truth (the recordings whose shortfall is the detector's own).
    """
    num = [c for c in causes.columns if c.startswith(("missed_", "extra_"))] + ["detector_net", "truth_gap",
                                                                                 "n_unpaired_landings"]
    c = causes.assign(half=np.where(causes["development"], "development", "held out"),
                      n_below_goal=causes["accuracy_bounces_merged"] < GOAL_MIN,
                      n_below_goal_truth_gaps_added=causes["accuracy_truth_gaps_added"] < GOAL_MIN)
    extra = ["n_below_goal", "n_below_goal_truth_gaps_added"]
    return c.groupby(["half", "position"])[num + extra].sum().astype(int).reset_index()


def cause_headline(tables: dict) -> str:
    """Per half: the recordings below the goal against the bounce-merged truth, and what their errors are."""
    c = tables["robust_error_causes"]
    out = []
    for half, mask in (("development", c["development"]), ("held out", ~c["development"])):
        h = c[mask]
        if h.empty:
            continue
        low = h[h["accuracy_bounces_merged"] < GOAL_MIN]
        if low.empty:
            out.append(f"{half}: no recording below {GOAL_MIN:.0%} against the bounce-merged truth")
            continue
        parts = [f"{r.recording} {r.accuracy_bounces_merged:.2%} ({r.truth_gap} extra detections in the truth's "
                 f"gaps, {r.n_unpaired_landings} unpaired landings; detector's own net {r.detector_net:+d}; "
                 f"{r.accuracy_truth_gaps_added:.2%} with the gaps added)" for r in low.itertuples()]
        out.append(f"{half}: {len(low)} below {GOAL_MIN:.0%}: " + ", ".join(parts)
                   + f"; over the half, {int(h['truth_gap'].sum())} detections in the truth's gaps beside "
                     f"{int(h['n_unpaired_landings'].sum())} unpaired landings, worst with the gaps added "
                     f"{h['accuracy_truth_gaps_added'].min():.2%}")
    return "; ".join(out)


def _fmt(par: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in par.items())
