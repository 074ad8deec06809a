# %% [markdown]
# # 15 Sweep studies: the papers' parameter studies, far beyond their few points, with 95 % CIs
#
# Four studies run across simulation seeds and parameter grids (`ilocalg.workflow.sweep`: a Dask `LocalCluster`, or
# reproduce's process pool), each point reported as mean and 95 % confidence interval over the seeds:
#
# 1. Wi-Fi fingerprinting (i-Loc (Chiu 2013), sec. 3, Figs 3 and 5): Simplified-RADAR, Simplified-Horus
#    and KNN error vs the number of strongest APs k, the training-point spacing and the scans per
#    point, on the simulated i-Loc floor.
# 2. Online INS smoothing (Liao et al. 2016, Fig 19, Figs 20-21): error vs window size 2-30 s, in
#    windows that hold a control point and in windows that do not.
# 3. i-Loc step Kalman filter (thesis ch. 5): mean error vs Wi-Fi noise scale and vs fix rate.
# 4. PSO (PSO (Chao 2008), sec. 4-5): convergence to minFitness vs swarm size and inertia schedule.
#
# The computations are `ilocalg.experiments.study_wifi`, `study_ins_window`, `study_kf_noise` and
# `study_pso`; `python -m ilocalg sweep study_pso --seeds 20 --param n_particles=5,10,20` runs any
# of them from the command line.

# %% tags=["parameters"]
# Seed of the first simulation (seeds SEED .. SEED + N - 1 are swept; N = 12, FAST: tiny grids, 3 seeds);
# OUT_DIR (set by the runner) receives tables and figures; DATA_DIR is unused (simulated data only).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
import os
import time

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

import ilocviz
import ilocviz.studies as vs
from ilocalg.experiments import study_ins_window, study_kf_noise, study_pso, study_wifi
from ilocalg.experiments.wifi_iloc import PAPER_ILOC
from ilocalg.workflow.reporting import Report
from ilocalg.workflow.studies import curves, notebook_tasks, run_notebook_tasks, select, study_seeds
from ilocalg.workflow.sweep import aggregate

report = Report(OUT_DIR, "15_sweep_studies")
ilocviz.table_display()  # whole numbers without decimals, text cells in full
seeds = study_seeds(SEED, FAST)
N_SEEDS = len(seeds)
STUDIES = {"wifi": study_wifi, "ins_window": study_ins_window, "kf_noise": study_kf_noise, "pso": study_pso}

# %% [markdown]
# ## One sweep, every study
# Each task is one `run(seed, fast, **params)` of a study. Run on its own, this notebook sends all tasks of the four
# studies to one `LocalCluster` of two single-threaded worker processes, and nothing is cached (a re-run
# recomputes). Under `make reproduce` the same tasks run as jobs of reproduce's own process pool, beside the other
# notebooks (no second pool competing for the cores), and this cell reads their results from reproduce's sweep
# cache (keyed by the code's fingerprint); a task not there yet runs here.

# %%
# the workers' own log lines (a failed task is reported below with its seed and parameters; the
# workers' heartbeat complaints while the cluster shuts down are noise) stay out of the notebook
os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "critical")
tasks = notebook_tasks("15_sweep_studies", SEED, FAST)
t0 = time.perf_counter()
res, ran_on = run_notebook_tasks(tasks, workers=2)
wall_s = time.perf_counter() - t0
for f in res.failures:
    print("FAILED:", f["task"], f["error"])
agg = aggregate(res.results)
cv = {name: curves(agg, m.EXPERIMENT) for name, m in STUDIES.items()}
report.table(agg, "summary")
report.table(pd.DataFrame([{"tasks": res.n_tasks, "failed": len(res.failures), "seeds": N_SEEDS, "ran on": ran_on,
                            "read from the cache": res.n_cached, "wall_s": wall_s}]), "sweep_timing",
             deterministic=False)
print(f"{res.n_tasks} tasks ({res.n_cached} read from reproduce's cache), {len(res.failures)} failed, "
      f"{wall_s:.1f} s in this cell ({ran_on})")

# %% [markdown]
# ## 1 Wi-Fi: error vs k, training-point spacing and scans per point
# Each curve varies one factor around the thesis' survey settings (k = 5, 2 m grid, 300 scans per point;
# fast mode: 60); the other factors stay at that base (radio parameters at the simulator's defaults).

# %%
wifi = report.table(cv["wifi"], "wifi_curves")
base_w = study_wifi.BASE_FAST if FAST else study_wifi.BASE
axes_spec = [("k_aps", "Strongest APs used, k [APs]", False),
             ("spacing_m", "Training-point spacing [m]", False),
             ("scans_per_point", "Training scans per point [scans]", True)]
with ilocviz.style():
    fig, axs = plt.subplots(1, 3, figsize=(14, 4.2), sharey=True)
    for ax, (x, xl, logx) in zip(axs, axes_spec, strict=True):
        fixed = {k: v for k, v in base_w.items() if k != x}
        d = select(wifi, "mean error", **fixed)
        vs.ci_curves(d, x, by="method", ax=ax, xlabel=xl, ylabel="Mean positioning error [m]", logx=logx)
    fig.suptitle("Simulated i-Loc floor: Wi-Fi fingerprinting error (28 test points)")
    ilocviz.savefig(fig, "15_sweep_studies_wifi", OUT_DIR)

# %% [markdown]
# ### Wi-Fi: error vs each radio parameter of the test session
# Day-to-day drift per AP, body shadowing (AP behind the tester), device offset (test phone minus survey
# phone), path-loss exponent and heavy-wall loss, each varied around the simulator's published defaults
# (`data/iloc_floor/README.md`) with the others held there.

# %%
radio_spec = [("drift_sd_db", "Day-to-day drift sd [dB]"), ("body_loss_db", "Body loss, AP behind [dB]"),
              ("device_offset_db", "Device offset [dB]"), ("path_loss_exponent", "Path-loss exponent [-]"),
              ("heavy_wall_db", "Heavy-wall loss [dB]")]
with ilocviz.style():
    fig, axs = plt.subplots(1, len(radio_spec), figsize=(20, 4.2), sharey=True)
    for ax, (x, xl) in zip(axs, radio_spec, strict=True):
        fixed = {k: v for k, v in base_w.items() if k != x}
        d = select(wifi, "mean error", **fixed)
        vs.ci_curves(d, x, by="method", ax=ax, xlabel=xl, ylabel="Mean positioning error [m]")
    fig.suptitle("Simulated i-Loc floor: Wi-Fi error vs the test session's radio parameters")
    ilocviz.savefig(fig, "15_sweep_studies_wifi_radio", OUT_DIR)

# %% [markdown]
# ## 2 Online INS smoothing: error vs window size, with and without a control point in the window

# %%
ins = report.table(cv["ins_window"], "ins_window_curves")
labels = {"horizontal RMS error": "all indoor epochs",
          "horizontal RMS error, windows with a control point": "windows with a control point",
          "horizontal RMS error, windows without a control point": "windows without a control point"}
with ilocviz.style():
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.2), sharey=True)
    for ax, phone in zip(axs, sorted(ins["phone"].unique()), strict=True):
        for q, lab in labels.items():
            d = select(ins, q, phone=phone)
            d = d[np.isfinite(d["window_s"]) & (d["window_s"] > 0)]
            vs.ci_curve(d, "window_s", ax=ax, label=lab)
        h = select(ins, "horizontal RMS error", phone=phone)
        vs.ci_reference(h[h["window_s"] == 0].iloc[0], ax=ax, label="filter, no smoothing")
        vs.ci_reference(h[np.isinf(h["window_s"])].iloc[0], ax=ax, label="whole-run RTS", linestyle=":")
        ax.set_xlabel("Smoothing window [s]")
        ax.set_ylabel("Horizontal RMS error [m]")
        ax.set_title(f"{phone} (WVC/ZUPT/GCP filter)")
        ax.legend(fontsize=8)
    ilocviz.savefig(fig, "15_sweep_studies_ins_window", OUT_DIR)

# %% [markdown]
# ## 3 Step Kalman filter: mean error vs Wi-Fi noise and fix rate
# The Wi-Fi fix sd is the noise scale times the square root of the median variance of the
# thesis' Table 5; the walker takes about two steps per second, so a fix every 2 steps is ~1 Hz.

# %%
kf = report.table(cv["kf_noise"], "kf_noise_curves")
kf = kf.assign(fix_sd_m=kf["noise_scale"] * study_kf_noise.SIGMA_RF_BASE_M)
with ilocviz.style():
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.2))
    d = select(kf, "mean error", fix_every=study_kf_noise.BASE["fix_every"])
    vs.ci_curves(d, "fix_sd_m", by="method", ax=axs[0], xlabel="Wi-Fi fix error sd [m]",
                 ylabel="Mean position error [m]", title=f"fix every {study_kf_noise.BASE['fix_every']} steps")
    d = select(kf, "mean error", noise_scale=study_kf_noise.BASE["noise_scale"])
    vs.ci_curves(d, "fix_every", by="method", ax=axs[1], xlabel="Steps between Wi-Fi fixes [steps]",
                 ylabel="Mean position error [m]", logx=True,
                 title=f"fix sd {study_kf_noise.SIGMA_RF_BASE_M:.2f} m")
    ilocviz.savefig(fig, "15_sweep_studies_kf_noise", OUT_DIR)

# %% [markdown]
# ## 4 PSO: convergence vs swarm size and inertia schedule
# Thesis settings otherwise (maxIters 100, maxSpeed 0.1, minFitness 0.1 m, c1 = c2 = 2); the
# fitness is eq. 4.4 in its per-step reading (the one the thesis's Fig 5.12 supports) on the six simulated
# phase-1 walks, steps detected without a moving average and with the static-noise RMS band (notebook 10's
# defaults), several independent swarms per walk. In this 1-D problem the swarm stops as soon as one particle
# is below minFitness, often in the initial swarm (k uniform in [0, 1], a box the thesis does not give), so
# these curves describe the stop rule and the initial box as much as the swarm's dynamics.

# %%
pso = report.table(cv["pso"], "pso_curves")
panels = [("success rate", "Runs reaching minFitness [%]"),
          ("iterations to minFitness", "Iterations to minFitness [iterations]"),
          ("fitness evaluations per success", "Fitness evaluations per success [evaluations]")]
with ilocviz.style():
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.2))
    for ax, (q, yl) in zip(axs, panels, strict=True):
        vs.ci_curves(select(pso, q), "n_particles", by="schedule", ax=ax, xlabel="Particles [-]", ylabel=yl,
                     logx=True)
    axs[2].set_yscale("log")
    ilocviz.savefig(fig, "15_sweep_studies_pso", OUT_DIR)

# %% [markdown]
# ## Findings (computed from the tables above)

# %%
k_curve = select(wifi, "mean error", method="Simplified-RADAR",
                 **{k: v for k, v in base_w.items() if k != "k_aps"})
best_k = int(k_curve.loc[k_curve["mean"].idxmin(), "k_aps"])
at_k5 = k_curve[k_curve["k_aps"] == PAPER_ILOC["radar_best_k"]].iloc[0]
text = "\n\n".join([
    f"**Sweep.** {res.n_tasks} tasks ({N_SEEDS} seeds per point), {len(res.failures)} failed.",
    "**Wi-Fi.** " + study_wifi.findings(wifi, FAST).replace("\n", " ")
    + f" The thesis found k = {PAPER_ILOC['radar_best_k']} best for RADAR (paper value); here the lowest mean "
    f"error is at k = {best_k} of the grid, and at k = {PAPER_ILOC['radar_best_k']} it is {at_k5['mean']:.2f} m "
    f"[95 % CI {at_k5['ci95_low']:.2f}-{at_k5['ci95_high']:.2f}].",
    "**Online smoothing.** " + study_ins_window.findings(ins).replace("\n", " "),
    "**Step KF.** " + study_kf_noise.findings(kf).replace("\n", " "),
    "**PSO.** " + study_pso.findings(pso).replace("\n", " "),
])
display(Markdown(text))

# %% [markdown]
# ## Conclusion
#
# Every number in the findings above is computed from the sweep tables; the tables hold the mean,
# standard deviation and Student-t 95 % interval over the seeds for every parameter point. All data
# are simulated (the papers' radio maps, walks and logs are not published), so the curves describe
# the simulators' worlds: their trends (more APs, denser grids, longer windows and more frequent
# fixes help; windows without a control point are where the online smoother's error lives; swarm
# size and inertia trade success rate against cost) are what transfers, not the absolute metres.
# The papers studied a handful of points on one data set each; where one of their points falls in
# our grids (k = 5, windows of 5/10/20 s, the thesis' PSO settings), the corresponding single-run
# comparison is in notebooks 01, 10 and 13.
