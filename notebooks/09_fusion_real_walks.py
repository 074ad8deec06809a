# %% [markdown]
# # 09 PDR + Wi-Fi fusion on real walks (Indoor Location Competition 2.0, site 2, floor F4)
#
# The fusion of notebooks 07-08 (the i-Loc step Kalman filter, eq. 20-26; the fingerprint + PDR
# scheme of Luo et al. 2017) on real phone logs: 19 surveyor walks with accelerometer, gyroscope,
# magnetometer and Wi-Fi scans, and waypoints for ground truth. Every walk is scored
# **leave-one-walk-out**: the Wi-Fi fingerprint database (each scan positioned by interpolating its
# walk's waypoints in time), the step-length factor, the compass-to-map heading offset and the Wi-Fi
# fix variance (and the Wi-Fi configuration, by leave-one-walk-out inside them) are learned from the other
# 18 walks; the scored walk's waypoints give only its errors
# (its start position and heading come from its own Wi-Fi fixes and the other walks, never from them).
#
# Variants, errors at every waypoint: PDR only (from the first fix), Wi-Fi only, KF, KF + RTS, the PDR
# track fitted onto all the walk's fixes, a particle filter constrained by the floor map
# (`geojson_map.json`) and its smoother, and a whole-walk map matching: the track pipeline of `ilocalg.track`
# (the same functions a user calls on one walk, or `python -m ilocalg evaluate track`). Goal (beyond the
# papers): fused mean waypoint error at most half the Wi-Fi-only error.

# %% tags=["parameters"]
# Seed of the particle filter; FAST scores every fifth walk with fewer particles; OUT_DIR (set by the
# runner) receives tables and figures; DATA_DIR is the folder of the real data sets (None: default).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
from pathlib import Path

import matplotlib.pyplot as plt

import ilocviz
import ilocviz.fusion
from ilocalg.experiments import fusion_real_walks
from ilocalg.io.paths import data_dir
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "09_fusion_real_walks")
ilocviz.table_display()  # whole numbers without decimals, text cells in full
folder = Path(DATA_DIR or data_dir()) / fusion_real_walks.DATASET
HAVE_DATA = folder.exists()
if not HAVE_DATA:
    print(f"ILC 2.0 site2/F4 not found (expected {folder} with site2_F4.tar.xz). "
          "The real-data part of this notebook is skipped.")

# %%
if HAVE_DATA:
    report.record_input(folder)
    floor = fusion_real_walks.load_floor(folder)
    tables = fusion_real_walks.run(seed=SEED, fast=FAST, floor=floor)
    for name in ("summary", "per_walk", "waypoints", "diagnostics"):
        report.table(tables[name], name)
    display(tables["summary"].round(2))  # noqa: F821

# %% [markdown]
# What limits the fusion: the PDR track's shape alone (fitted onto the walk's own waypoints: an oracle,
# shown only as a diagnostic, never used by a method) beside the Wi-Fi fix errors.

# %%
if HAVE_DATA:
    display(tables["diagnostics"].round(2))  # noqa: F821

# %% [markdown]
# ## Per walk: mean waypoint error and what was learned from the other walks

# %%
if HAVE_DATA:
    display(tables["per_walk"].round(2))  # noqa: F821

# %%
shown = ["wifi", "pdr", "kf", "kf_rts", "pf_smooth", "map_align"]
if HAVE_DATA:
    with ilocviz.style():
        fig, ax = plt.subplots(figsize=(8, 5))
        long = tables["waypoints"].melt(id_vars=["walk", "waypoint", "t_s"], var_name="method", value_name="error_m")
        ilocviz.fusion.error_cdfs(long, shown, ax=ax)
        ilocviz.savefig(fig, "09_fusion_real_walks_cdf", OUT_DIR)

# %%
if HAVE_DATA:
    with ilocviz.style():
        fig, ax = plt.subplots(figsize=(10, 4.5))
        ilocviz.fusion.walk_means(tables["per_walk"], ["wifi", "kf_rts", "pf_smooth", "map_align"], ax=ax)
        ilocviz.savefig(fig, "09_fusion_real_walks_per_walk", OUT_DIR)

# %% [markdown]
# ## The longest walk on the floor map

# %%
if HAVE_DATA:
    ex = fusion_real_walks.example(floor, seed=SEED, select=not FAST)
    plan = list(floor.floor_map.outline) + list(floor.floor_map.obstacles)
    with ilocviz.style():
        fig, ax = plt.subplots(figsize=(9, 8))
        ilocviz.fusion.tracks(ex, ["Wi-Fi fixes", "pdr", "kf_rts", "pf_smooth", "map_align", "waypoints"], ax=ax,
                              floor_plan=plan, point_methods=("Wi-Fi fixes",))
        ilocviz.savefig(fig, "09_fusion_real_walks_tracks", OUT_DIR)

# %%
if HAVE_DATA:
    print(fusion_real_walks.findings(tables))

# %% [markdown]
# ## What the numbers say
#
# - There is no paper value for these walks: the comparison is between the variants, with Wi-Fi only as
#   the reference and the goal of half its error (the findings above say which variants, if any, meet it).
# - Wi-Fi is poor here: 19 short walks cover a large floor (its plan is in notebook 00) sparsely, so a held-out walk
#   often
#   passes where no other walk has scanned and its fixes land tens of metres away on the nearest
#   surveyed path. The fix variance learned from the other walks says so, and the filters weight the
#   fixes accordingly.
# - PDR is good in shape (gyro heading aligned on average to the compass, steps from the robust detector,
#   Weinberg lengths with `k` from the other walks), but started from the first Wi-Fi fix it inherits that
#   fix's error for the whole walk; the causal KF cannot remove it either.
# - Whole-walk smoothing (RTS) and fitting the track onto all of the walk's fixes average the start error
#   down, and the floor map adds the constraint that the whole track must lie in walkable space (the
#   particle filter's smoother and the whole-walk map matching). The gains are modest: the fixes of one walk
#   share their error (they all snap to the same nearest surveyed path), so averaging them removes little.
#   The diagnostics table shows where the limit is: the PDR track's shape alone is accurate to a metre or
#   two, the placement is what the Wi-Fi cannot give. Whether any variant meets the goal of half the
#   Wi-Fi-only error is printed in the findings above; every variant is reported, including those that miss.
# - Causal variants (`pdr`, `wifi`, `kf`, `pf`) only use the past; the others use the whole walk (offline).
