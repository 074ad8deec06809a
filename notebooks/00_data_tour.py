# %% [markdown]
# # 00 Data tour
#
# What the toolkit's data sets hold: the embedded default sets that `ilocalg.sim` simulates from a
# seed, and, when they are present, the real public recordings (UJIIndoorLoc, the Oxford step
# counter set, Indoor Location Competition 2.0). A real set that is absent is reported with where to
# download it; nothing here needs a download.

# %% tags=["parameters"]
# Seed of every simulation; FAST shrinks the data; OUT_DIR (set by the runner) receives tables and
# figures; DATA_DIR is the folder of the real data sets (None: $ILOC_DATA_DIR, else ../shared/data).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%

from ilocalg.experiments import data_tour
from ilocalg.reporting import Report

report = Report(OUT_DIR, "00_data_tour")

# %%
tables = data_tour.run(seed=SEED, fast=FAST, data_dir=DATA_DIR)
report.table(tables["availability"], "availability")

# %%
for name, df in tables.items():
    if name != "availability":
        report.table(df, name)
        display(df)  # noqa: F821

# %% [markdown]
# ## Conclusion
#
# Every table above is computed from the data by `ilocalg.experiments.data_tour`.
