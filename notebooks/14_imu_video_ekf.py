# %% [markdown]
# # 14 IMU + video-tracking EKF (Hartmann et al.)
#
# Reproduces the Hartmann et al. (2010) system described in Yeh & Huang's image/inertial positioning survey
# (葉濟賢, 黃偉立), sec. 5: a 15-state EKF (Euler angles, position, velocity, gyro and accelerometer
# biases; eq. 12) driven by a 400 Hz MEMS IMU (eq. 13-19) and corrected by yaw and position from a
# marker-based video tracker (VT, eq. 20), with the Jacobians of eq. 21-24 and the prediction /
# correction of eq. 25-29. Figure 11 (EKF position vs the VT), Figure 12 (bias estimates settling) and
# Table 2 (mean and maximal deviation to the VT per axis, VT sampling rate, longest outage, outages > 1 s).
#
# Data: simulated hand-held sequences (`ilocalg.sim.hartmann`, see `data/hartmann/README.md`).

# %% tags=["parameters"]
# Seed of the simulations; FAST runs two 60 s sequences instead of six of 120 s; OUT_DIR (set by the
# runner) receives tables and figures; DATA_DIR is unused here.
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
import matplotlib.pyplot as plt

import ilocviz
import ilocviz.ins as vins
from ilocalg.experiments import ins_hartmann
from ilocalg.papers import PAPERS
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "14_imu_video_ekf")
ilocviz.table_display()  # whole numbers without decimals, text cells in full

# %% [markdown]
# ## Readings: what the survey says and what the code does

# %%
tables = ins_hartmann.run(seed=SEED, fast=FAST)
report.table(tables["readings"], "readings")

# %% [markdown]
# ## Table 2: EKF vs video tracker
# The survey does not say how "deviation to VT" is taken. Our interpretation: `mean_dev_*` / `max_dev_*`
# are the absolute deviation of the EKF prediction from each VT fix just before the fix is used. Beside it:
# `mean_pred_err_truth_*` / `max_pred_err_truth_*` the same prediction against the simulated truth,
# `mean_dev_post_*` the deviation after the correction and `mean_err_truth_*` the EKF against the truth at
# every IMU epoch. The simulated tracker has the outages Table 2 describes (input statistics
# `vt_rate_hz`, `outage_max_s`, `outages_over_1s`); `psd_repairs` counts covariance repairs in outages.

# %%
report.table(tables["table2"], "table2")

# %%
report.compare(tables["comparison"].to_dict("records"))
with ilocviz.style():
    ax = ilocviz.paper_vs_reproduced(tables["comparison"][tables["comparison"]["item"] == "Table 2"],
                                     title=f"Reproduced / paper ({PAPERS['survey']}, Table 2)")
    ilocviz.savefig(ax.figure, "14_imu_video_ekf_table2_ratio", OUT_DIR)

# %% [markdown]
# ## The tracker noise is an input: the mean deviation as a sensitivity curve
# The survey gives only "millimetre precision" (L218) and no published value fixes this tracker's noise. The
# assumed sd (3 / 3 / 8 mm, 1 deg) scaled by 0.5-4, with the resulting mean deviations to the tracker and the
# prediction's mean error against the truth; the paper's mean deviation per axis is marked (dashed), and
# `tracker_noise_implied` gives the tracker noise at which each curve meets it (a reading, not an input).

# %%
report.table(tables["tracker_noise"], "tracker_noise")
report.table(tables["tracker_noise_implied"], "tracker_noise_implied")
with ilocviz.style():
    fig, ax = plt.subplots(figsize=(6.5, 4))
    tn = tables["tracker_noise"]
    for a, colour in zip("xyz", ("C0", "C1", "C2"), strict=True):
        ax.plot(tn["noise_scale"], 1e3 * tn[f"mean_dev_{a}_m"], "o-", color=colour, label=f"reproduced, {a}")
        ilocviz.paper_mark(ax, 1e3 * tn[f"paper_mean_dev_{a}_m"].iloc[0],
                           f"paper: mean deviation {a} ({PAPERS['survey']}, Table 2)", axis="y", color=colour)
    ax.set_xlabel("tracker noise / assumed (3 / 3 / 8 mm)")
    ax.set_ylabel("mean deviation to VT (mm)")
    ax.legend(fontsize=7)
    ilocviz.savefig(fig, "14_imu_video_ekf_tracker_noise", OUT_DIR)

# %% [markdown]
# ## Outage statistics are inputs set from Table 2: swept
# The simulated tracker's outages were set from Table 2's own statistics, so the rate and outage rows of the
# comparison are inputs, not reproductions. No published marker-tracking outage statistics are used; the rate
# and the excess duration of the outages over an assumed 1 s are scaled by 0.5 and 2 to show what the deviations do.

# %%
report.table(tables["outage_sensitivity"], "outage_sensitivity")

# %% [markdown]
# ## Fig 11: EKF position and VT fixes; Fig 12: bias estimates (true values dashed)

# %%
tr, vt = tables["trace"], tables["vt"]
with ilocviz.style():
    fig, axs = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    for i in range(3):
        vins.vt_positions(tr["t_s"], tr[[f"ekf_{c}_m" for c in "xyz"]].to_numpy(), vt["t_s"],
                          vt[[f"{c}_m" for c in "xyz"]].to_numpy(), ax=axs[i], axis=i)
    ilocviz.savefig(fig, "14_imu_video_ekf_fig11", OUT_DIR)
    fig, axs = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    vins.bias_estimates(tr["t_s"], tr[[f"bg_{c}_dps" for c in "xyz"]].to_numpy(),
                        tr[[f"bg_true_{c}_dps" for c in "xyz"]].iloc[0].to_numpy(), ax=axs[0], unit="deg/s",
                        label="b_w")
    vins.bias_estimates(tr["t_s"], tr[[f"ba_{c}_mps2" for c in "xyz"]].to_numpy(),
                        tr[[f"ba_true_{c}_mps2" for c in "xyz"]].iloc[0].to_numpy(), ax=axs[1], unit="m/s^2",
                        label="b_a")
    ilocviz.savefig(fig, "14_imu_video_ekf_fig12", OUT_DIR)

# %%
report.table(tables["settling"], "bias_settling")
ov = tables["table2"].iloc[-1]
print(f"mean deviation to VT (x, y, z): {ov.mean_dev_x_m:.4f}, {ov.mean_dev_y_m:.4f}, {ov.mean_dev_z_m:.4f} m; "
      f"max: {ov.max_dev_x_m:.3f}, {ov.max_dev_y_m:.3f}, {ov.max_dev_z_m:.3f} m; "
      f"VT {ov.vt_rate_hz:.2f} Hz, longest outage {ov.outage_max_s:.2f} s")

# %% [markdown]
# ## Conclusion
#
# The 15-state EKF bridges the tracker's outages with the IMU and stays at the millimetre-to-centimetre
# level against the tracker, with the z (depth) deviation the largest as in the paper, because the tracker
# is least precise along the camera's optical axis. The mean deviation to the tracker mostly echoes the
# assumed tracker noise (tracker-noise table: doubling the noise roughly doubles it), while the prediction's
# error against the truth is smaller: Table 2's mean deviation says more about the tracker than about the
# EKF. The maximal deviations come from coasting through the longest outages, which the simulated tracker
# now has as Table 2 describes them.
#
# Differences: the sequences are simulated (IMU noise from the survey, tracker outages from Table 2's input
# statistics with an assumed sequence length of 120 s, tracker noise and biases assumed); the motion is
# smoother than a real hand and the IMU-marker lever arm, time offsets and camera calibration errors of the
# real set-up are absent. Whether the simulated maximal deviations come out smaller or larger than the paper's
# is generated below from this run's comparison rows (Table 2), never typed.

# %%
from IPython.display import Markdown

from ilocalg.papers.claims import rows_markdown

Markdown(rows_markdown(tables["comparison"], where=lambda r: r["item"] == "Table 2" and "max_dev" in r["quantity"]))
