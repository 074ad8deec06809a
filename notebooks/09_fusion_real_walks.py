# %% [markdown]
# # 09 PDR + Wi-Fi fusion on real walks (Indoor Location Competition 2.0, site 1 floor F1, or site 2 floor F4)
#
# The fusion of notebooks 07-08 (the i-Loc step Kalman filter, eq. 20-26; the fingerprint + PDR
# scheme of Luo et al. 2017) on real phone logs: surveyor walks with accelerometer, gyroscope,
# magnetometer and Wi-Fi scans, and waypoints for ground truth. By default the densely surveyed
# site 1 floor F1 of a mall (about 240 m x 176 m, the data set's own report; 100 walks: a Wi-Fi database as
# dense as the competition's own);
# `DATASET = "ilc2020_site2_F4"` gives the sparse 19-walk floor. Every walk is scored
# **leave-one-walk-out**: the Wi-Fi fingerprint database (each scan positioned by interpolating its
# walk's waypoints in time), the step-length factor, the compass-to-map heading offset, the Wi-Fi
# fix variance and the Wi-Fi configuration (by leave-one-walk-out inside them), and the PDR step
# variance are learned from the other walks; the scored walk's waypoints give only its errors.
#
# Variants, errors at every waypoint: PDR only (from the first fix), Wi-Fi only, KF, KF + RTS, the PDR
# track fitted onto all the walk's fixes, a particle filter constrained by the floor map
# (`geojson_map.json`) and its smoother, a whole-walk map matching, and the least-squares trajectory
# (one sparse system of Wi-Fi fixes and PDR steps per walk, weighted by their measured variances; its
# causal variant `lsq_online`; `*_map`: pulled onto the walkable map), and an online Kalman filter whose
# state carries the walk's own step scale and heading offset (`kf_gain`; `kf_gain_lag5s`: the same smoothed over
# a fixed lag, the lag of Liao et al. 2016, not causal): the track pipeline of
# `ilocalg.track` (the same functions a user calls on one walk, or `python -m ilocalg evaluate track`).
# Every variant weights the Wi-Fi fixes by a fix model measured on the other walks: each fix's own variance, the
# part of the fix error that persists from fix to fix, and (online map variants) the map at start-up; the
# ablation below shows what each piece buys.
# The `*_grid` rows are of another kind: located only at the times the walk is asked about (here its waypoints'
# times, as in the 2021 Indoor Location & Navigation competition, where the times to locate are given), on the
# points the surveyors of the other walks stood on (their waypoints: the survey's marked points); see the section
# on them below.
# Goals (beyond the papers): best offline mean error <= 0.5 x Wi-Fi only, best online <= 0.7 x, reported
# with the EvAAL 75th percentile.

# %% tags=["parameters"]
# Seed of the particle filter; FAST scores every fifth walk with fewer particles; OUT_DIR (set by the
# runner) receives tables and figures; DATA_DIR is the folder of the real data sets (None: default);
# DATASET the floor ("folder/floor" for one floor of a two-floor archive); LOWO_EVERY: the pooled
# leave-one-walk-out over both site 1 floors scores every LOWO_EVERY-th walk of each (1: every walk);
# the fix-model ablation scores every ABLATION_EVERY-th development walk (even walks) of site 1 F1.
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None
DATASET = "ilc2020_site1/site1_F1"
LOWO_EVERY = 1
ABLATION_EVERY = 10

# %%
from pathlib import Path

import matplotlib.pyplot as plt
import pandas as pd

import ilocviz
import ilocviz.fusion
import ilocviz.track
from ilocalg.experiments import fusion_real_walks
from ilocalg.io.paths import data_dir
from ilocalg.workflow.reporting import Report

report = Report(OUT_DIR, "09_fusion_real_walks")
ilocviz.table_display()  # whole numbers without decimals, text cells in full
folder = Path(DATA_DIR or data_dir()) / DATASET.split("/")[0]
HAVE_DATA = folder.exists()
if not HAVE_DATA:
    print(f"ILC 2.0 {DATASET} not found (expected {folder}). The real-data part of this notebook is skipped.")

# %%
if HAVE_DATA:
    report.record_input(folder)
    floor = fusion_real_walks.load_floor(DATA_DIR, DATASET)  # read once: run() and the sweep below share it
    tables = fusion_real_walks.run(seed=SEED, fast=FAST, data_dir=DATA_DIR, dataset=DATASET)
    for name in ("summary", "per_walk", "waypoints", "diagnostics", "measures", "readings"):
        report.table(tables[name], name)
    display(tables["summary"].round(2))  # noqa: F821

# %% [markdown]
# ## Ablation: what each Wi-Fi piece buys
#
# Leave-one-walk-out fix error of every database scan (each walk located against the others) for each
# Wi-Fi configuration (each an input setting); the first row of each policy is the plain reference (weighted
# KNN, K = 5, readings
# older than 2 s dropped: a few dozen lines of numpy). `relisted_wifi`: the loader's rule for the readings
# that re-list the previous scan's reading of the same access point (same RSSI, last seen within 1 ms;
# `ilocalg.io.scans.relisted_readings`), kept or merged into their first listing.

# %%
if HAVE_DATA:
    # the floor model run() scored with holds the database with the readings kept: not built again
    abl = fusion_real_walks.wifi_ablation(floor, db=fusion_real_walks.floor_model(DATA_DIR, DATASET, fast=FAST).db)
    report.table(abl, "wifi_ablation")
    display(abl.round(2))  # noqa: F821

# %% [markdown]
# ## Ablation: what each estimator buys (the summary above, as ratios to Wi-Fi only)
#
# The least-squares system solves, for the states $p_0 \dots p_n$ of a walk,
# $\min \sum_i \lVert p_{i+1} - p_i - d_i \rVert^2 / \sigma_d^2 + \sum_j \rho\big(\lVert (1-a_j) p_{k_j} + a_j p_{k_j+1}
# - z_j \rVert / \sigma_z\big)$ with Huber's $\rho$ (c = 1.345): $d_i$ the PDR step, $z_j$ the Wi-Fi fixes,
# $\sigma_z^2$ and $\sigma_d^2$ measured on the other walks.

# %%
if HAVE_DATA:
    display(tables["summary"][["method", "online", "latency", "mean_error_m", "median_error_m", "p75_error_m",  # noqa: F821
                               "ratio_to_wifi"]].sort_values("mean_error_m").round(2))
    display(tables["diagnostics"].round(2))  # noqa: F821

# %% [markdown]
# ## Per walk: mean waypoint error and what was learned from the other walks

# %%
if HAVE_DATA:
    display(tables["per_walk"].round(2))  # noqa: F821

# %%
shown = ["wifi", "pdr", "kf", "kf_rts", "pf_smooth", "map_align", "lsq", "lsq_online", "kf_gain",
         "map_align_grid", "kf_gain_map_grid"]  # the last two: at the waypoint times, on the marked points
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
        ilocviz.fusion.walk_means(tables["per_walk"], ["wifi", "kf_rts", "pf_smooth", "lsq"], ax=ax)
        ilocviz.savefig(fig, "09_fusion_real_walks_per_walk", OUT_DIR)

# %% [markdown]
# ## The best and the worst walk on the floor plan (`floor_image.png`)

# %%
if HAVE_DATA:
    import io

    png = fusion_real_walks.floor_image(DATA_DIR, DATASET)
    img = None if png is None else plt.imread(io.BytesIO(png), format="png")
    size = (floor.floor_map.width_m, floor.floor_map.height_m)
    # the track estimators (the grid variants are located at the waypoint times only: see below)
    summ = tables["summary"][~tables["summary"]["method"].isin(["wifi", *fusion_real_walks.GRID_METHODS])]
    # Wi-Fi only, the best online and the best offline variant of this run, and the papers' smoothed KF
    best = [summ[summ["latency"] == lat].sort_values("mean_error_m")["method"].iloc[0]
            for lat in ("none", "whole walk")]
    shown = tuple(dict.fromkeys(["wifi", *best, "kf_rts"]))
    with ilocviz.style():
        fig, axes = plt.subplots(1, 2, figsize=(14, 6))
        for ax, which in zip(axes, ("best", "worst"), strict=True):
            tr = tables["tracks"][tables["tracks"]["which"] == which]
            truth = tables["truth"][tables["truth"]["which"] == which]
            ilocviz.track.tracks_on_plan(tr, truth[["x_m", "y_m"]].to_numpy(), img, size, methods=shown, ax=ax)
            ax.set_title(f"{which} walk: {truth['walk'].iloc[0]}")
        ilocviz.savefig(fig, "09_fusion_real_walks_tracks", OUT_DIR)

# %%
if HAVE_DATA:
    print(fusion_real_walks.findings(tables))

# %% [markdown]
# ## On the survey's marked points, at the query times (`*_grid`)
#
# The surveyors of a floor stand on a fixed set of marked points, so most waypoints of a walk lie on a waypoint of
# another walk. The `*_grid` variants take a base track (`lsq`, `map_align`; online `lsq_online_map`,
# `kf_gain_map`) at the times the walk is asked about and decode, by a hidden Markov model over the other walks'
# distinct waypoints, where the walker stood: a marked point near the base estimate (emission: the persistent
# Wi-Fi fix error's variance, measured on the database walks) whose displacement from the previous query time
# agrees with the PDR's (transition: the measured step variance times the steps between them), or "no marked
# point", whose prior is the share of the database walks' waypoints that no other database walk shares. The
# offline variants take the Viterbi path, the online ones the most probable state of the forward filter (the base
# estimates and PDR up to that time only). What they assume: the query times are given (scored: the waypoints'
# times, which is also what a competition gives), and the walker stands on the survey's points at those times. A
# walk off the marked points keeps its base estimate where no point lies within 3 sd of it or where "no marked
# point" is more probable; on a sparsely surveyed floor (few shared waypoints) that is every query. Their tracks
# between query times, drawn nowhere here, are the base track moved by the query corrections.

# %%
if HAVE_DATA:
    s = tables["summary"].set_index("method")  # noqa: F821
    g = fusion_real_walks.GRID_METHODS
    display(pd.DataFrame({"base": list(g.values()), "grid variant": list(g),  # noqa: F821
                          "online": [s.loc[m, "online"] for m in g],
                          "base mean [m]": [s.loc[b, "mean_error_m"] for b in g.values()],
                          "grid mean [m]": [s.loc[m, "mean_error_m"] for m in g],
                          "base p75 [m]": [s.loc[b, "p75_error_m"] for b in g.values()],
                          "grid p75 [m]": [s.loc[m, "p75_error_m"] for m in g],
                          "base / Wi-Fi": [s.loc[b, "ratio_to_wifi"] for b in g.values()],
                          "grid / Wi-Fi": [s.loc[m, "ratio_to_wifi"] for m in g]}).round(3))

# %% [markdown]
# ## Leave-one-walk-out over both site 1 floors, per floor and pooled
#
# The same scoring over the walks of site 1 F1 and F2, run as a sweep
# (`fusion_real_walks.leave_one_walk_out`: each floor a task of `ilocalg.workflow.sweep`, cached, with a
# progress bar; here in this process, one task per floor; on a cluster each floor is split into shards: the command
# `python -m ilocalg sweep fusion_real_walks --seeds 1 --param dataset=ilc2020_site1/site1_F1,ilc2020_site1/site1_F2
# --param shard=0,1,2,3 --param n_shards=4 [--scheduler tcp://...]` runs the same tasks on a Dask cluster).
# Every waypoint of every scored walk is pooled; the Wi-Fi-only row is checked against the plain reference
# (an input setting: weighted KNN, K = 5, readings older than 2 s dropped, on the same database: `wifi_plain_knn`).
# Goals: best offline mean <= 0.5 x Wi-Fi only, best online <= 0.7 x.

# %%
if HAVE_DATA and DATASET.startswith("ilc2020_site1"):
    lowo = fusion_real_walks.leave_one_walk_out(names_every=50 if FAST else LOWO_EVERY, workers=0,
                                                data_dir=DATA_DIR, fast=FAST)
    report.table(lowo["summary"], "lowo_summary")
    display(lowo["summary"].pivot(index="method", columns="floor", values="ratio_to_wifi").round(2))  # noqa: F821
    display(lowo["summary"][lowo["summary"]["floor"] == "pooled"].round(2))  # noqa: F821
    print(fusion_real_walks.lowo_findings(lowo["summary"]))

# %% [markdown]
# ## What the Wi-Fi fix model buys (development walks of site 1 F1)
#
# Each row adds one piece to the fix model every estimator weights the Wi-Fi fixes by, all measured on the
# database walks, never on the scored walk: each fix's own variance (from its neighbours' spread, the access
# points heard and its readings' age), the part of the fix error that persists from fix to fix (a Gauss-Markov
# bias carried by the filter and the least squares), and the map at start-up (the online map variants start from
# the first fix's walkable posterior). Development walks only: the even walks of F1, every ABLATION_EVERY-th.
# `start_mean_m` is the error at each walk's first waypoint (the log start, before the first fix arrives).

# %%
if HAVE_DATA and DATASET == "ilc2020_site1/site1_F1":
    dev = floor.names[::2][::50 if FAST else ABLATION_EVERY]
    abl = fusion_real_walks.fix_ablation(names=dev, data_dir=DATA_DIR, dataset=DATASET, fast=FAST)
    report.table(abl["table"], "fix_ablation")
    display(abl["table"].pivot(index="method", columns="config", values="ratio_to_wifi")  # noqa: F821
            [list(fusion_real_walks.FIX_ABLATION)].round(3))
    print(fusion_real_walks.ablation_findings(abl["table"]))

# %% [markdown]
# ## What the numbers say
#
# - There is no paper value for these walks: the comparison is between the variants, with Wi-Fi only as
#   the reference; the findings above say which goals are met, and every variant is reported.
# - On the densely surveyed site 1 floors the Wi-Fi fixes are a few metres off; on the sparse site 2 F4
#   floor a held-out walk often passes where no other walk has scanned and its fixes land tens of metres
#   away. The fix variance learned from the other walks says so, and every fusion weights the fixes by it.
# - PDR is good in shape (gyro heading aligned on average to the compass, steps from the robust detector,
#   Weinberg lengths with `k` from the other walks) but started from the first Wi-Fi fix it inherits that
#   fix's error; the causal variants (`pdr`, `wifi`, `kf`, `pf`, `lsq_online*`) use only the past, the others
#   the whole walk (offline).
# - The least-squares trajectory equals the Kalman smoother for Gaussian errors (same model); what it adds is
#   robustness (Huber weights) and a place to add constraints. The map-constrained particle filter's smoother
#   uses the floor plan as well and is the strongest offline variant where the corridors are narrow.
# - The `*_grid` rows answer another question than the tracks: where was the walker at given times, knowing that
#   surveyors stand on marked points. They gain where the floor's walks share their waypoints (site 1) and fall back
#   to their base where they do not; they assume the query times are given and the walker stands on a marked point
#   then, which a free walk of a visitor would not.
# - Map matching of the whole walk as one rigid placement failed on site 1 before (see the figures)
# because its map
#   term counted every track point as an independent observation; it now counts as many as there are fixes.
