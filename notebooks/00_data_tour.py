# %% [markdown]
# # 00 Data tour
#
# What the toolkit's data sets hold: the embedded default sets that `ilocalg.sim` simulates from a
# seed (documented parameter by parameter in `data/*/README.md`), and, when they are present, the
# real public recordings (UJIIndoorLoc, the Oxford step counter set, Indoor Location Competition
# 2.0). A real set that is absent is reported with where to download it; nothing here needs a
# download.

# %% tags=["parameters"]
# Seed of every simulation; FAST shrinks the data; OUT_DIR (set by the runner) receives tables and
# figures; DATA_DIR is the folder of the real data sets (None: $ILOC_DATA_DIR, else ../shared/data).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
from pathlib import Path

import matplotlib.pyplot as plt

import ilocviz
import ilocviz.wifi
from ilocalg.experiments import data_tour
from ilocalg.io.paths import data_dir
from ilocalg.sim import iloc_floor
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "00_data_tour")
ilocviz.table_display()  # whole numbers without decimals, text cells in full
root = Path(DATA_DIR) if DATA_DIR else data_dir()

# %% [markdown]
# ## Which real sets are here

# %%
tables = data_tour.run(seed=SEED, fast=FAST, data_dir=root)
avail = report.table(tables["availability"], "availability")
for row in avail.itertuples():
    if not row.present:
        print(f"{row.dataset}: not found under {root}. Download: {row.download}")
    else:
        report.record_input(root / row.dataset)
avail

# %% [markdown]
# ## Embedded (simulated) sets
# One instance of each, from the seed: sample rates, durations, distances, Wi-Fi scans.

# %%
report.table(tables["embedded"], "embedded")

# %% [markdown]
# The calibrated radio inputs of the simulated i-Loc floor (the thesis reports 4-18 APs heard per scan).

# %%
report.table(tables["iloc_floor_inputs"], "iloc_floor_inputs")

# %%
floor = iloc_floor.simulate(seed=SEED, scans_per_point=30 if FAST else iloc_floor.SCANS_PER_POINT)
with ilocviz.style():
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    ilocviz.wifi.floor_map(floor.points_xy_m, ax=ax, walls=iloc_floor.walls(),
                           aps=floor.ap_xy_m[floor.ap_floor == 0], test_points=floor.test_points)
    ax.set_title("Simulated i-Loc floor: training points, test route and access points")
    ilocviz.savefig(fig, "00_data_tour_iloc_floor", OUT_DIR)

# %% [markdown]
# ## Real sets (when present)

# %%
for name in ("ujiindoorloc", "oxford_step_counter", "ilc2020_site2_F4"):
    if name in tables:
        print(name)
        display(report.table(tables[name], name))  # noqa: F821

# %% [markdown]
# ## Conclusion
#
# Every number above is computed from the data by `ilocalg.experiments.data_tour`. The simulated
# sets are regenerated from the seed on demand; the real sets are read in place and their sha256
# sums are recorded in `reports/provenance.json`.
