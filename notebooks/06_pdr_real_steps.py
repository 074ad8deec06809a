# %% [markdown]
# # 06 PDR step counting on real walks (Oxford step counter data set)
#
# Every step detector of the toolkit on the 48 real recordings of the Oxford step counter optimisation
# set (3 phones, 3 users, 7 carry positions, heel-sensor ground truth): the toolkit's best detector
# (`ilocalg.pdr.robust`), a plain low-pass + `find_peaks` baseline, the fingerprint+PDR paper's
# sliding-window detector (Luo et al. 2017, sec. 3.4.2), the slope-sign-change detector of PSO (Chao 2008), Fig 3.9,
# and the i-Loc SAM (Chiu 2013, eq. 8-15). Accuracy per recording is `1 - |counted - true| / true`, measured by
# **leave-one-recording-out** cross-validation: each detector's parameters are tuned on 47 recordings and
# the 48th is scored. Reference: the data set's own report gives 93.7 % mean / 96.8 % median for its
# windowed peak detector; the goal set for the toolkit is >= 99.3 % mean with no recording below 98 %.

# %% tags=["parameters"]
# Seed (unused: no randomness); FAST scores every third recording with small grids; OUT_DIR (set by the
# runner) receives tables and figures; DATA_DIR is the folder of the real data sets (None: default).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
import dataclasses
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import ilocviz
import ilocviz.pdr
from ilocalg.experiments import pdr_real_steps
from ilocalg.io.paths import data_dir
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "06_pdr_real_steps")
ilocviz.table_display()  # whole numbers without decimals, text cells in full
folder = Path(DATA_DIR or data_dir()) / "oxford_step_counter"
archive = folder / pdr_real_steps.ARCHIVE
HAVE_DATA = archive.is_file()
if not HAVE_DATA:
    print(f"Oxford step counter data not found at {archive}; see the README's 'Real data' section. "
          "The real-data part of this notebook is skipped.")

# %%
if HAVE_DATA:
    report.record_input(archive)
    recordings = pdr_real_steps.load(folder)
    tables = pdr_real_steps.run(seed=SEED, fast=FAST, recordings=recordings)
    for name in ("per_recording", "summary", "per_position", "per_phone", "choices", "grid"):
        report.table(tables[name], name)
    comparison = report.compare(tables["comparison"].to_dict("records"))
    display(comparison)  # noqa: F821
    display(tables["summary"])  # noqa: F821
else:
    report.table(pdr_real_steps.missing_table(archive), "summary")

# %% [markdown]
# ## Readings
# Every choice of the experiment: where the data set's description (`SOURCE.txt`, `README_DataSet.md`) or a paper
# speaks of it (line numbers of the text copies), what it says, what the code does, and the source of each value
# neither gives.

# %%
if HAVE_DATA:
    report.table(tables["readings"], "readings")
    display(tables["readings"])  # noqa: F821

# %%
if HAVE_DATA:
    display(tables["per_position"])  # noqa: F821
    display(tables["per_phone"])  # noqa: F821

# %%
if HAVE_DATA:
    with ilocviz.style():
        fig, ax = plt.subplots(figsize=(8, 4))
        ilocviz.pdr.accuracy_bars(tables["summary"], ax=ax, goal=pdr_real_steps.GOAL_MEAN)
        ilocviz.savefig(fig, "06_pdr_real_steps_accuracy", OUT_DIR)

# %%
if HAVE_DATA:
    print(pdr_real_steps.headline(tables))
    worst = pdr_real_steps.worst(tables, 5)
    display(worst)  # noqa: F821
    display(pdr_real_steps.truth_artefacts([r for r in recordings if r.name in set(worst["recording"])]))  # noqa: F821

# %% [markdown]
# ## Why steps are missed or doubled, per placement
# The robust detector at its default parameters (`ilocalg.pdr.robust.ROBUST_DEFAULTS`), each detection matched
# one-to-one to a heel-sensor step within a tolerance (a setting: 0.25 s, `ilocalg.pdr.robust.match_steps`):
# *missed* = true steps
# without a detection, *extra* = detections without a true step; a count alone lets one cancel the other.
# `hardware_steps` is the phone's own step counter: the Oxford set records it only in its validation
# layout, so on these optimisation recordings the column is empty (NaN), not zero.

# %%
if HAVE_DATA:
    report.table(tables["robust_diagnosis"], "robust_diagnosis")
    report.table(tables["robust_diagnosis_by_position"], "robust_diagnosis_by_position")
    display(tables["robust_diagnosis_by_position"])  # noqa: F821
    display(tables["robust_diagnosis"].nsmallest(6, "accuracy"))  # noqa: F821

# %%
# The worst recording of each of the two weakest placements: 12 s of the detector's signal with the
# true steps (green), the detections (blue) and the missed (red X) / extra (orange rings) ones.
if HAVE_DATA:
    diag = tables["robust_diagnosis"]
    by_name = {r.name: r for r in recordings}
    weakest = diag.groupby("position")["accuracy"].mean().nsmallest(2).index
    with ilocviz.style():
        fig, axes = plt.subplots(len(weakest), 1, figsize=(10, 3.2 * len(weakest)))
        for ax, pos in zip(np.atleast_1d(axes), weakest, strict=True):
            row = diag[diag["position"] == pos].nsmallest(1, "accuracy").iloc[0]
            prep = pdr_real_steps.prepare(by_name[row["recording"]])
            w = pdr_real_steps.diagnosis_window(prep, t0_s=30.0)
            ilocviz.pdr.step_detections(w["t_s"], w["signal_mps2"], w["true_t_s"], w["det_t_s"],
                                        w["true_matched"], w["det_matched"], ax=ax)
            ax.set_title(f"{row['recording']} ({pos}): {row['missed']} missed, {row['extra']} extra "
                         f"of {row['true_steps']} steps")
        fig.tight_layout()
        ilocviz.savefig(fig, "06_pdr_real_steps_diagnosis", OUT_DIR)

# %% [markdown]
# ## Heel-sensor bounces in the truth, and a development / held-out split
# The truth comes from heel pressure sensors read a few times per step. In some recordings a sensor drops to 0 for one
# to three readings in mid-stance and back, which the published count takes as a second landing of that foot.
# The loader counts these bounces (`n_heel_bounces`: a landing less than `ilocalg.io.oxford.MIN_STRIDE_S` after
# the same foot's last kept landing; its docstring gives the source and the measured gap in the landing
# intervals) and, under `heel_bounces="merge"`, merges them; nothing is changed silently. The table below scores
# the robust detector (defaults) against both truths, on the development half of the recordings (odd repeat
# numbers, `ilocalg.pdr.step_evaluate.is_development`) and the held-out half (even repeats, every condition of
# the set again), mean with a bootstrap interval over recordings (`ci_low`, `ci_high`). The optimisation
# recordings carry no hardware step counter (the set records it only in its validation layout, which is not among
# the shared data), so the `hardware_steps` column of the diagnosis table stays empty.

# %%
if HAVE_DATA:
    report.table(tables["robust_by_truth_and_split"], "robust_by_truth_and_split")
    display(tables["robust_by_truth_and_split"])  # noqa: F821
    print(pdr_real_steps.truth_headline(tables))
    cols = ["recording", "position", "true_steps_published", "n_heel_bounces", "true_steps_bounces_merged",
            "n_unpaired_landings", "counted", "accuracy", "accuracy_bounces_merged", "accuracy_unpaired_added",
            "hardware_steps", "hardware_accuracy"]
    display(tables["robust_diagnosis"][cols].sort_values("accuracy_bounces_merged").head(10))  # noqa: F821

# %% [markdown]
# ## One parameter set for every phone's sampling rate
# The recordings were logged at each phone's fastest rate, and the detector resamples every log to one common rate
# before filtering (`ilocalg.pdr.robust`, step 1; `ilocalg.pdr.step_evaluate.RATE_HZ`). Would a phone that logs at
# that rate itself, as the slowest logs of this set do (the two Samsung_Jamie recordings;
# `ilocalg.pdr.step_evaluate.LOW_RATE_HZ`), count the same walks the same? Each recording logged faster is
# decimated here by the whole factor nearest its rate over that rate (`ilocalg.pdr.step_evaluate.rate_robustness`,
# the table's `factor` column): once by keeping every factor-th sample (aliasing kept, the worst case) and once after
# `scipy.signal.decimate`'s anti-alias low-pass (what a sensor's own filter at a lower output rate does). The
# detector keeps its defaults and the truth is the published one; nothing is chosen from this check. The line under
# the table gives the range of rates as logged.

# %%
if HAVE_DATA:
    report.table(tables["rate_robustness"], "rate_robustness")
    report.table(tables["rate_robustness_summary"], "rate_robustness_summary")
    display(tables["rate_robustness_summary"])  # noqa: F821
    print(pdr_real_steps.rate_headline(tables))
    rates = tables["rate_robustness"]
    with ilocviz.style():
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
        ilocviz.pdr.paired_accuracy(rates["accuracy_as_logged"],
                                    {"every factor-th sample": rates["accuracy_decimated"],
                                     "anti-aliased": rates["accuracy_decimated_anti_alias"]},
                                    ax=ax, goal=pdr_real_steps.GOAL_MIN)
        ax.set_title(f"robust detector, per recording: logged vs ~{pdr_real_steps.LOW_RATE_HZ:g} Hz")
        fig.tight_layout()
        ilocviz.savefig(fig, "06_pdr_real_steps_rate", OUT_DIR)

# %% [markdown]
# ## Walk detection at the ends of a bout, swept on the development half
# `min_stride_nac` (`ilocalg.pdr.robust.stride_nac`, `trim_bout_ends`): "off" is the detector without walk
# detection; each value is scored on the development recordings only, against the published and the
# bounce-merged truth, with the number of leave-one-recording-out folds (over the development recordings) that
# choose it. The detector's default is the value those folds choose. The `own_*` columns count the detector's own
# errors against the bounce-merged truth by cause (the cause table below explains them), so a value that raises the
# mean by dropping true steps in recordings the truth over-counts shows as more `own_missed_*`.
#
# Gait onset: starting to walk from standing, the body shifts its weight before the first step (anticipatory
# postural adjustments, Crenna & Frigo 1991), a small bump of |a| about one step period before the first heel
# landing. The stride test keeps it (the walk's stride follows it). The second table sweeps `min_onset_ratio`
# (`ilocalg.pdr.robust.trim_bout_onsets`): a bout's first peak is dropped while it is less prominent than that
# ratio times the peak one stride later (the same foot's next landing, so that a phone in one pocket compares like
# with like), with the stride threshold at its default. The end of a walk gets no such rule: its last landing is
# the softest of the walk, weaker than the bumps after it.

# %%
if HAVE_DATA:
    report.table(tables["walk_gate_sweep"], "walk_gate_sweep")
    report.table(tables["onset_sweep"], "onset_sweep")
    display(tables["walk_gate_sweep"])  # noqa: F821
    print(pdr_real_steps.gate_headline(tables))
    display(tables["onset_sweep"])  # noqa: F821
    print(pdr_real_steps.gate_headline(tables, "onset_sweep", "min_onset_ratio"))

# %% [markdown]
# ## Every missed and extra step given a cause
# Against the truth with the heel bounces merged, each missed true step and extra detection of the robust detector
# (defaults) gets one cause from the step times alone (`ilocalg.pdr.step_errors.classify_step_errors`; no
# placement or recording name enters): `timing` (a missed step and an extra detection closer than half a second,
# paired: the step was found, further from the heel landing than the matching tolerance; the count is right),
# `truth_gap` (a detection inside the walk where two consecutive true steps are 1.5 to 3.5 local step intervals
# apart: one or two landings the heel sensors did not register), `pause` (a longer gap: the walker stood),
# `before_walk` / `after_walk` (handling the phone), `walk_end` (the first or last true step missed) and
# `inside_walk` (a weak step missed, or one step counted twice). Only `truth_gap` and `timing` are not the
# detector's. The loader counts the landings the sensors missed independently, from the foot states alone (a foot
# landing twice with no landing of the other foot between, `n_unpaired_landings`): the left panel below sets the
# two counts side by side per recording. The right panel draws the recording with the most detections in the
# truth's gaps, from its first such detection: the detector keeps counting at the walk's own period where the
# heel sensors skip a landing (dotted lines: the detections classified `truth_gap`). The published truth and the
# bounce-merged truth stay unchanged in the tables above; `accuracy_truth_gaps_added` (the merged truth plus the
# detections in its gaps) is a sensitivity check, not the score.

# %%
if HAVE_DATA:
    for name in ("robust_errors", "robust_error_causes", "robust_error_causes_by_split"):
        report.table(tables[name], name)
    display(tables["robust_error_causes_by_split"])  # noqa: F821
    print(pdr_real_steps.cause_headline(tables))
    causes = tables["robust_error_causes"]
    errors = tables["robust_errors"]
    gap_rec = causes.loc[causes["truth_gap"].idxmax(), "recording"]
    gaps = errors[(errors["recording"] == gap_rec) & (errors["cause"] == "truth_gap")]["t_s"].to_numpy()
    rec = by_name[gap_rec]
    prep = pdr_real_steps.prepare(rec)
    merged = dataclasses.replace(prep, step_t_s=prep.step_t_s[~rec.step_is_heel_bounce])
    w = pdr_real_steps.diagnosis_window(merged, t0_s=float(gaps[0]) - 1.0 if gaps.size else 30.0, span_s=10.0)
    with ilocviz.style():
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(13, 4), gridspec_kw={"width_ratios": [1, 2.4]})
        for dev, marker in ((True, "o"), (False, "s")):
            c = causes[causes["development"] == dev]
            ax0.scatter(c["n_unpaired_landings"], c["truth_gap"], marker=marker, alpha=0.7,
                        label="development" if dev else "held out")
        top = float(max(causes["n_unpaired_landings"].max(), causes["truth_gap"].max())) + 1
        ax0.plot([0, top], [0, top], color="0.6", lw=0.8, ls="--", label="equal")
        ax0.set(xlabel="unpaired landings (foot states)", ylabel="detections in the truth's gaps",
                title="per recording")
        ax0.legend()
        ilocviz.pdr.step_detections(w["t_s"], w["signal_mps2"], w["true_t_s"], w["det_t_s"],
                                    w["true_matched"], w["det_matched"], ax=ax1)
        for t in gaps[(gaps >= w["t_s"][0]) & (gaps <= w["t_s"][-1])]:
            ax1.axvline(t, color="C1", ls=":", lw=1.0)
        ax1.set_title(f"{gap_rec}: truth with heel bounces merged; dotted: detections in the truth's gaps")
        fig.tight_layout()
        ilocviz.savefig(fig, "06_pdr_real_steps_truth_gaps", OUT_DIR)

# %% [markdown]
# ## Conclusion
#
# * The toolkit's best detector (resample to a common rate, zero-phase low-pass of the orientation-free magnitude |a|,
#   prominence peaks, a walking-bout gate that drops isolated peaks from handling the phone) beats the data set's
#   own report and the plain `find_peaks` baseline under leave-one-recording-out tuning. Whether its mean reaches
#   the goal set above, and which recordings stay below its floor, is printed above (computed, not typed here).
# * The swinging-arm and armband shortfall is in the ground truth, not the detector: the worst recordings are
#   the ones with the most heel-sensor bounces (compare `n_heel_bounces` with `accuracy` in the diagnosis
#   table), the missed "true" steps are the bounces (`missed_close_to_true`), and against the truth with the
#   bounces merged those placements score among the best (`accuracy_bounces_merged` per position).
# * What remains against the merged truth is of two kinds, seen in the per-recording diagnosis and the windows
#   drawn above. Steps the heel sensors did not register at all: a foot that lands twice with no landing of the
#   other foot between (`n_unpaired_landings`, counted by the loader, never added to the truth); the third truth
#   of the split table adds them back as a sensitivity check, and the recordings with the most extra detections
#   are the ones with the most such landings. And weak peaks while the phone is handled before and after the walk
#   or sways in a pouch while the walker stands. A gate on each peak's prominence relative to its neighbours'
#   did not separate those on the development half (the handling peaks come in runs, and one leg's peaks are weak
#   beside the other's in a pocket). What does separate them is periodicity: inside a walk, the stride of |a|
#   around a step repeats one stride before or after it, around a handling peak it does not. The robust detector
#   therefore detects the walk at the ends of each bout (walk detection before step counting, as Brajdic & Harle
#   2013 study it): while a bout's first or last peak has a normalised auto-correlation (Rai et al. 2012) below
#   `min_stride_nac`, it is dropped; a peak inside a bout is never dropped. Its threshold was chosen on the
#   development half only, by leave-one-recording-out (the sweep table below: every value, both truths, how often
#   each was chosen); the held-out half was scored once, with the chosen value, in the split table above.
#   A pouch swaying while the walker stands *inside* a walk (less than `max_step_s` between the peaks) stays
#   counted, and a walk that starts with the recording can lose its first steps (no stride before them repeats).
#   The weight shift before the first step passes the stride test; the gait-onset rule drops a bout's first peaks
#   while they are much weaker than the same foot's next landing (the onset table: how many handling detections
#   before the walk it removes and whether any first step is lost). Neither the intervals between the peaks
#   (a run of detections at the walk's own period: the bumps before a walk come at that period too) nor a
#   prominence ratio at the end of a walk (its last landing is weak) separated handling from steps on the
#   development half.
# * What is left below the goal's floor is, recording by recording, printed above from the cause table: the
#   recordings below it against the bounce-merged truth, how many of their extra detections lie in the truth's gaps
#   beside the loader's independent count of unpaired landings, and their accuracy once those gaps are filled. Where
#   the two counts agree and the detector's own net error is a step or two, the shortfall is the truth's, not the
#   detector's; the detector's own errors (steps missed at the ends of a walk or weak ones inside it, handling
#   before and after, a pouch swaying during a stop) are the `detector_net` column.
# * The papers' detectors do worse on these real walks, honestly reported: Luo et al. 2017's sliding window with a
#   tuned threshold is close to the baseline; Chao 2008's slope-sign-change rule with its +-RMS band, built for a
#   waist-mounted sensor, miscounts pocket and arm positions; the i-Loc SAM, whose seven range tests must
#   all pass, rejects many true steps (notebook 03 shows the same on simulated walks).
