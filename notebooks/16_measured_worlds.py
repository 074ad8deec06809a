# %% [markdown]
# # 16 Where the simulators' numbers come from
#
# The i-Loc and Luo reproductions run on simulated floors, gaits and scans (issue 24). This notebook
# sets each statistic measured on public recordings (`data/measured_parameters.csv`, written by
# `python -m ilocalg measure` from UJIIndoorLoc, the Oxford step counter InHand walks and the ILC 2.0
# site1 walks) beside the same statistic measured, with the same functions, on the simulated worlds:
# the **measured** world (defaults from that table, used by notebooks 01 and 03-05) and the
# **assumed** world (the published-value world used before). A world is *calibrated* for a
# statistic when the real value lies inside the simulated 95 % interval. No paper result is used.

# %% tags=["parameters"]
# Seed of every simulation; FAST shrinks the data; OUT_DIR (set by the runner) receives tables and
# figures; DATA_DIR is the folder of the real data sets (None: $ILOC_DATA_DIR, else ../shared/data).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
import matplotlib.pyplot as plt

import ilocviz
import ilocviz.measured
from ilocalg.experiments import measured_worlds
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "16_measured_worlds")
tables = measured_worlds.run(seed=SEED, fast=FAST, data_dir=DATA_DIR)

# %% [markdown]
# ## The measured table
# Every value with its seeded bootstrap interval (resampling walks, APs, phones or recordings as the
# `method` column says).

# %%
report.table(tables["table"], "measured_parameters")

# %% [markdown]
# ## Real beside simulated
# `sim_<world>_calibrated` is True when the real value lies in the simulated world's interval.

# %%
report.table(tables["real_vs_sim"], "real_vs_sim")

# %%
report.table(tables["measures"], "measures")

# %%
with ilocviz.style():
    fig, ax = plt.subplots(figsize=(8, 6.5))
    ilocviz.measured.real_vs_sim_intervals(tables["real_vs_sim"], ax=ax)
    ax.set_title("Simulated statistic relative to the real one (1 = equal)")
    fig.tight_layout()
    ilocviz.savefig(fig, "16_measured_worlds_ratios", OUT_DIR)

# %% [markdown]
# ## Distributions: shadowing, scan lag, misalignment, step variability
# Real samples come from UJIIndoorLoc (shadowing), a subsample of the ILC site1 walks (scan lag,
# misalignment) and the Oxford InHand walks (step period and amplitude); they are missing when
# ../shared/data is absent.

# %%
with ilocviz.style():
    fig, axes = plt.subplots(3, 2, figsize=(11, 11))
    for ax, q in zip(axes.ravel(), ["shadow_residual_db", "reading_age_s", "misalignment_deg", "step_T_rel",
                                    "step_A_rel"], strict=False):
        ilocviz.measured.distribution_hist(tables["distributions"], q, ax=ax)
    axes.ravel()[-1].set_visible(False)
    fig.tight_layout()
    ilocviz.savefig(fig, "16_measured_worlds_distributions", OUT_DIR)

# %%
report.table(tables["readings"], "readings")

# %% [markdown]
# ## Conclusion
#
# The table above is computed by `ilocalg.experiments.measured_worlds.run`; its `measures` row counts
# how many statistics each world reproduces. Where the measured world is not calibrated, the
# mapping from a measured statistic to a simulator parameter is not the identity (for example the
# per-AP fit on a censored, sparse simulated survey does not return the exponent put in, and the
# walkers' phone amplitudes are measured through the same low-pass as the real ones): those rows
# say which simulator parameters still need an inverse calibration, not which papers fail.
