# %% [markdown]
# # 07 The i-Loc Kalman filter: PTS + Wi-Fi (thesis ch. 5, Figs 22-23, Tables 4-5)
#
# Reproduces the i-Loc thesis' Kalman filter (eq. 20-26): one predict per detected step (step length
# and WDM heading as control input, `Q` from **Table 4**), one update per Wi-Fi fix (`R` per test point,
# the thesis' **Table 5** procedure), Joseph-form covariance. Compared at the 28 test points:
# the pedestrian trajectory system alone (PTS), Wi-Fi alone and the KF, beside the thesis' means
# (**Fig 23**: PTS 5.15 m -> KF 2.82 m), with the trajectories of one walk (**Fig 22**).
# Beyond the thesis: RTS and fixed-lag smoothing, a heading-error term in `Q`, innovation gating.
#
# Data: the simulated i-Loc floor (`ilocalg.sim.iloc_floor`, radio map and new scans at the test-route
# points) and simulated walkers (`ilocalg.sim.gait`) walking that route with a handheld phone.

# %% tags=["parameters"]
# Seed of every simulation; FAST shrinks the data; OUT_DIR (set by the runner) receives tables and
# figures; DATA_DIR is the folder of the real data sets (unused here).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
import matplotlib.pyplot as plt

import ilocviz
import ilocviz.fusion
from ilocalg.experiments import fusion_iloc_kf
from ilocalg.sim import iloc_floor
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "07_fusion_iloc_kf")

# %% [markdown]
# ## The method: i-Loc (Chiu 2013) eq. (20)-(26), the Kalman filter
#
# State $\mathbf{s}_k = (x_k, y_k)$; one prediction per detected step with its length $D_k$ and heading
# $\theta_k$ as the control input (`ilocalg.fusion.kf_predict_step`, control `ilocalg.fusion.step_control`,
# noise `ilocalg.fusion.step_process_noise`):
#
# $$\mathbf{s}_k = \mathbf{F}_k \mathbf{s}_{k-1} + \mathbf{B}_k \mathbf{u}_k + \mathbf{w}_k \;(20)$$
#
# $$\begin{bmatrix} x_k \\ y_k \end{bmatrix} = \begin{bmatrix} x_{k-1} \\ y_{k-1} \end{bmatrix} + \begin{bmatrix} \cos
# \theta_k \\ \sin \theta_k \end{bmatrix} D_k + \begin{bmatrix} \omega_{x,k} \\ \omega_{y,k} \end{bmatrix} \;(22)$$
#
# $$\mathbf{Q}_k = \delta_{SL,k}^2 \begin{bmatrix} \cos^2 \theta_k & \sin \theta_k \cos \theta_k \\ \sin \theta_k \cos
# \theta_k & \sin^2 \theta_k \end{bmatrix}$$
#
# and one update per Wi-Fi fix, which measures the position directly (`ilocalg.fusion.kf_update`):
#
# $$\mathbf{z}_k = \mathbf{H}_k \mathbf{s}_k + \mathbf{v}_k \;(21), \quad \mathbf{H}_k = \mathbf{I}\;(23), \quad
# \mathbf{R}_k = \delta_{RF,k}^2 \mathbf{I}_{2 \times 2}$$
#
# $$\hat{\mathbf{s}}_k^+ = \hat{\mathbf{s}}_k^- + \mathbf{K}_k (\mathbf{z}_k - \mathbf{H}_k \hat{\mathbf{s}}_k^-)
# \;(24)$$
#
# $$\mathbf{K}_k = \mathbf{P}_k^- \mathbf{H}_k^T (\mathbf{H}_k \mathbf{P}_k^- \mathbf{H}_k^T + \mathbf{R}_k)^{-1}
# \;(25)$$
#
# $$\mathbf{P}_k = (\mathbf{I} - \mathbf{K}_k \mathbf{H}_k) \mathbf{P}_k^- (\mathbf{I} - \mathbf{K}_k \mathbf{H}_k)^T
# + \mathbf{K}_k \mathbf{R}_k \mathbf{K}_k^T \qquad (26)$$
#
# $\delta_{SL}$ is Table 4, $\delta_{RF}$ per test point the Table 5 procedure; `fusion_iloc_kf.run` below runs it.

# %%
tables = fusion_iloc_kf.run(seed=SEED, fast=FAST)
for name in ("summary", "test_points", "cdf", "r_table", "gating", "by_wifi_method"):
    report.table(tables[name], name)
comparison = report.compare(tables["comparison"].to_dict("records"))
comparison

# %% [markdown]
# ## Mean errors of every variant
# `R per point, calibrated`: the per-point variance of the fix error over a calibration survey (how the
# thesis made Table 5); `R constant`: one variance for every fix; `R = thesis Table 5`: the thesis' own
# numbers (measured on its floor, not this one).

# %%
tables["summary"].round(2)

# %%
tables["by_wifi_method"].round(2)

# %% [markdown]
# ## Fix variances: calibrated on the simulated floor beside the thesis' Table 5

# %%
tables["r_table"].round(3)

# %% [markdown]
# ## Innovation gating (chi-square 99 %, on the KF with heading noise): fixes given and rejected per walker

# %%
tables["gating"]

# %% [markdown]
# ## Trajectories of one walk (Fig 22) and error CDFs (Fig 23)

# %%
walls = [w.reshape(2, 2) for w in iloc_floor.walls()]
shown = ["truth", "PTS", "Wi-Fi only", "KF (R per point, calibrated)", "KF (R per point, calibrated) + RTS"]
with ilocviz.style():
    fig, ax = plt.subplots(figsize=(9, 6))
    ilocviz.fusion.tracks(tables["track_example"], shown, ax=ax, floor_plan=walls)
    ax.set_xlim(10, 45)
    ax.set_ylim(0, 30)
    ilocviz.savefig(fig, "07_fusion_iloc_kf_tracks", OUT_DIR)

# %%
with ilocviz.style():
    fig, ax = plt.subplots(figsize=(8, 5))
    ilocviz.fusion.error_cdfs(tables["test_points"], shown[1:] + ["KF (R per point, calibrated) + heading noise + RTS"],
                              ax=ax)
    ilocviz.savefig(fig, "07_fusion_iloc_kf_cdf", OUT_DIR)

# %%
print(fusion_iloc_kf.findings(tables))

# %% [markdown]
# ## Where and why the numbers differ from the thesis
#
# - The floor is simulated (the thesis' radio map is not published) and its test route is the
#   simulated floor's 28 corridor points 2 m apart, not the thesis' PTS loop of 28 points 4.11 m apart:
#   the walks are shorter, so the PTS drifts less than in the thesis' Fig 23 (see the findings above).
# - Wi-Fi on the simulated floor is easier than on the real one: the test points are also training
#   points, and Simplified-Horus often returns the exact point, so Wi-Fi alone is already more accurate
#   than the PTS here (Wi-Fi is the weaker input in the thesis). The calibrated per-point variances and the
#   thesis' Table 5 differ point by point (table and findings above): the large ones sit at different
#   points of a different floor, so running the KF with the thesis' own variances costs accuracy here.
# - The relative result is what carries over: with the thesis' model (R per test point) the KF is better
#   than both of its inputs, as in the thesis, and the ratio KF / PTS is printed beside the thesis' ratio
#   in the comparison table. That model presumes the filter knows at which test point each fix was taken
#   (as Table 5 does); with one constant R, the honest choice for a deployed system, the gain over an
#   already accurate Wi-Fi shrinks or vanishes (findings above).
# - The paper's `Q` covers the step length only. The WDM heading error (the thesis' 13.87 deg) is what
#   makes the PTS drift, so with the paper's `Q` the filter is over-confident between fixes; adding a
#   heading-error term (beyond the paper) and smoothing the whole walk (RTS) lower the error further.
#   Gating with the paper's over-confident `Q` would reject good fixes, which is why it is shown on the
#   filter with heading noise.
