# %% [markdown]
# # 11 Photo positioning from points of interest
#
# Reproduces the photo positioning of the i-Loc thesis (P.-J. Chiu, NCTU 2013, ch. 6): the similar-triangle
# algorithm ST (eq. 29-30, least squares over the PoIs, with the phone's accelerometer + magnetometer
# orientation) against the view-angle algorithm VA (gradient descent from a good and a bad initial guess,
# VAGIG / VABIG), on the thesis's set-up of seven PoIs on a wall and seven shooting points one metre apart
# (Figs 27-28):
#
# - Fig 29: mean error per shooting point, and the thesis's explanation that VA's error grows with the
#   distance to p4;
# - Fig 30: error against the number of PoIs (2..7) and the overall means;
# - Figs 31-32: error per PoI combination and the near-collinear combinations {1,3}, {1,4}, {5,6}, {1,3,4};
# - beyond the thesis: OpenCV's SQPnP and the plane-to-plane homography `H = K [r1 r2 t]` of the survey
#   (002, sec. 4, eq. 3-5) on the same photos, and the propagation of the sensors' orientation errors into ST.
#
# The photos are simulated (`ilocalg.sim.photo_poi`; every input and its source is in `data/photo_poi/README.md`).
# The thesis gives the PoI coordinates only in a figure, so the layout is reconstructed from its text.

# %% tags=["parameters"]
# Seed of the simulation; FAST uses 1 photo per shooting point instead of 10 (and 500 VA iterations);
# OUT_DIR (set by the runner) receives tables and figures; DATA_DIR is unused here (no real photo data set).
SEED = 0
FAST = False
OUT_DIR = None
DATA_DIR = None

# %%
import matplotlib.pyplot as plt

import ilocviz
from ilocalg.experiments import photo_positioning
from ilocalg.photo import thin_lens_image_distance_m
from ilocalg.workflow.reporting import Report
from ilocviz import photo as photoviz

report = Report(OUT_DIR, "11_photo_positioning")
tables = photo_positioning.run(seed=SEED, fast=FAST)
d_shots = tables["layout_shots"]["dist_to_p4_m"].to_numpy()[[0, -1]]
print("thin lens d_i / f - 1 at t1, t7:", thin_lens_image_distance_m(d_shots, 3.7e-3) / 3.7e-3 - 1)

# %% [markdown]
# ## Set-up (Figs 27-28) and the simulation inputs
# The pinhole model uses the focal length as the image distance (eq. 27-28). For a 3.7 mm phone lens, the
# printed relative difference `d_i / f - 1` at the nearest and farthest shooting points shows how small the
# approximation error is.

# %%
with ilocviz.style():
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    photoviz.layout(tables["layout_pois"], tables["layout_shots"], ax=axs[0], view="top")
    photoviz.layout(tables["layout_pois"], tables["layout_shots"], ax=axs[1], view="front")
    ilocviz.savefig(fig, "11_photo_positioning_layout", OUT_DIR)
report.table(tables["inputs"], "inputs")

# %% [markdown]
# ## Paper vs reproduced

# %%
report.compare(tables["comparison"].to_dict("records"))

# %% [markdown]
# ## Fig 29: mean error per shooting point
# The thesis explains VA's growing error by the view angles shrinking with the distance to p4 (so a drag error
# of a few pixels matters more). `distance_trend` gives the Spearman correlation and the slope of each method's
# per-shot mean error against that distance.

# %%
with ilocviz.style():
    ax = photoviz.error_per_shot(tables["per_shot"])
    ilocviz.savefig(ax.figure, "11_photo_positioning_fig29_per_shot", OUT_DIR)
report.table(tables["per_shot"], "fig29_per_shot")
report.table(tables["distance_trend"], "fig29_distance_trend")

# %% [markdown]
# ## Fig 30: error against the number of PoIs (stars: the thesis's values)

# %%
with ilocviz.style():
    ax = photoviz.error_vs_k(tables["per_k"], comparison=tables["comparison"])
    ilocviz.savefig(ax.figure, "11_photo_positioning_fig30_per_k", OUT_DIR)
report.table(tables["per_k"], "fig30_per_k")

# %% [markdown]
# ## Figs 31-32: error per PoI combination, near-collinear combinations
# With the orientation known, ST's linear system is rank deficient only when every ray is parallel (the camera on
# the line of collinear PoIs); otherwise collinearity matters through the conditioning: PoIs that subtend a small
# angle give nearly parallel rays. `combo_geometry` correlates each method's error with the ST condition number.

# %%
with ilocviz.style():
    fig, axs = plt.subplots(2, 1, figsize=(11, 7))
    photoviz.error_per_combo(tables["per_combo"], ax=axs[0], method="ST")
    photoviz.error_per_combo(tables["per_combo"], ax=axs[1], method="VAGIG")
    fig.tight_layout()
    ilocviz.savefig(fig, "11_photo_positioning_fig31_per_combo", OUT_DIR)
    ax = photoviz.conditioning_scatter(tables["per_combo"])
    ilocviz.savefig(ax.figure, "11_photo_positioning_conditioning", OUT_DIR)
report.table(tables["per_combo"], "fig31_per_combo")
report.table(tables["near_collinear"], "fig32_near_collinear")
report.table(tables["combo_geometry"], "combo_geometry")

# %% [markdown]
# ## Beyond the thesis: SQPnP, homography and orientation-error propagation
# SQPnP and the wall homography estimate the orientation from the photo itself (no sensors); ST with the true
# orientation isolates the drag error. The propagation table compares ST's Monte-Carlo RMS error (all seven
# PoIs) with the first-order prediction from the tilt, heading and drag errors.

# %%
report.table(tables["modern"], "modern_methods")
report.table(tables["propagation"], "st_error_propagation")
report.table(tables["va_convergence"], "va_convergence")
with ilocviz.style():
    ax = photoviz.propagation(tables["propagation"])
    ilocviz.savefig(ax.figure, "11_photo_positioning_propagation", OUT_DIR)

# %% [markdown]
# ## Homography ranging to a square marker (survey 002, eq. 3-5)
# A QR code of side 0.18 m on the wall, seen from 1-5 m at up to 30 deg off its normal; the four corners carry a
# detection error of 0.5-2 px. The range `l = ||t||` from `H = K [r1 r2 t]` (scale from the column norms, as in
# Zhang's decomposition) is compared with OpenCV's IPPE on the same corners.

# %%
marker = photo_positioning.marker_ranging(seed=SEED, fast=FAST)
report.table(marker, "marker_ranging")

# %% [markdown]
# ## Sensitivity to the assumed inputs
# One input changed at a time (2 and 7 PoIs); this shows which conclusions hinge on the drag and sensor errors
# chosen from the literature. It was not used to choose them.

# %%
sens = photo_positioning.sensitivity(seed=SEED, fast=FAST)
report.table(sens, "sensitivity")
sens.pivot_table(index=["parameter", "value"], columns=["method", "k"], values="error_cm").round(1)

# %% [markdown]
# ## What the numbers say (computed)

# %%
cmp = tables["comparison"].set_index("quantity")["reproduced_value"]
tr = tables["distance_trend"].set_index("method")
mod = tables["modern"].set_index("k")
nc = tables["near_collinear"].set_index("combo")
print(f"Overall means: ST {cmp['ST overall mean error']:.1f} cm, VAGIG {cmp['VAGIG overall mean error']:.1f} cm, "
      f"VABIG {cmp['VABIG overall mean error']:.1f} cm.")
print(f"Per-shot error vs distance to p4 (Spearman rho): ST {tr.loc['ST', 'spearman_rho']:.2f}, "
      f"VAGIG {tr.loc['VAGIG', 'spearman_rho']:.2f}, VABIG {tr.loc['VABIG', 'spearman_rho']:.2f}.")
print(f"k>=4 PoIs: ST {mod.loc['all k>=4', 'ST']:.1f} cm, ST with true orientation "
      f"{mod.loc['all k>=4', 'ST_true_orientation']:.1f} cm, SQPnP {mod.loc['all k>=4', 'PnP_SQPnP']:.1f} cm, "
      f"homography {mod.loc['all k>=4', 'homography']:.1f} cm.")
mk = marker.set_index(["distance_m", "corner_sd_px"]).loc[(4.0, 1.0)]
print(f"Marker at 4 m, 1 px corners: range RMS error homography {mk['homography_range_rms_error_cm']:.1f} cm, "
      f"IPPE {mk['ippe_range_rms_error_cm']:.1f} cm.")
print("ST rank of the near-collinear combinations among combinations of the same size (1 = worst): "
      + ", ".join(f"{c} {int(r['ST_rank_among_same_k'])}/{int(r['n_same_k'])}" for c, r in nc.iterrows()))

# %% [markdown]
# ## Conclusion
#
# - **ST agrees with the thesis where the thesis is most specific.** Its error falls as PoIs are added, and its
#   7-PoI and overall errors land near the published values (comparison table). With two PoIs the reproduced ST
#   error is lower than the thesis's. The main error source is the magnetometer heading: with the true
#   orientation, ST's error drops to a fraction, and the heading dominates the first-order error budget at every
#   range. The budget tracks the Monte-Carlo RMS error to within the sampling noise of a few photos per point.
#   The unit test checks it to 10 % with 4000 draws.
# - **Fig 29's explanation is reproduced.** The per-shot errors of VAGIG and VABIG rise steadily with the
#   distance to p4 (Spearman rho near 1). ST's error rises too, but several times more slowly. From far away the
#   PoIs subtend small angles, so the same drag error in pixels moves the estimate further.
# - **VA is much worse here than in the thesis**, both VAGIG and VABIG, and even with all seven PoIs. In our
#   layout the PoIs sit on one plane in a narrow row (0.4 m apart, so that all seven fit the camera's field of
#   view from t1), mostly on one horizontal line. Seen from 2.5-8.5 m, view angles alone hardly fix the camera's
#   bearing around the wall. This is the weak perspective of a distant planar target, and it is also why SQPnP
#   and the homography, which ignore the orientation sensors too, are far worse than ST.
#   - The sensitivity table shows VA depends strongly on the drag error. With a drag error of a few pixels, VA's
#     seven-PoI error comes close to the thesis's value while ST still leads. So the thesis's users may have
#     dragged more precisely than the 1 mm assumed here, or its PoIs were spread wider.
#   - The thesis's Fig 28 coordinates, its drag statistics and how it scored VA are not in the text, so the gap
#     cannot be pinned on one cause.
#   - VABIG with two PoIs is below the thesis's value because our "bad" guess is uniform over the room, not one
#     deliberately wrong point.
# - **Near-collinear combinations (Fig 32) are only partly reproduced.** Among pairs, ST's error follows the
#   condition number of its linear system closely (`combo_geometry`). The pair with the smallest subtended angle,
#   {5,6}, ranks among the worst, as in the thesis, but {1,4}, which subtends a wide angle in our layout, is not
#   singled out (ranks printed above). With a known orientation, collinear PoIs do not by themselves make ST rank
#   deficient; only (near-)parallel rays do. `ilocalg.photo.st_solve` raises `RankDeficientError` for parallel
#   rays and warns (`IllConditionedWarning`) for near-parallel ones.
# - **Marker ranging (survey 002):** with exact corners, `H = K [r1 r2 t]` gives the exact range. With
#   pixel-level corner errors, the scale taken from the column norms of `K^-1 H` underestimates the range more and
#   more as the marker shrinks on the screen, because the noisy perspective terms inflate those norms. IPPE on the
#   same corners keeps the range error small. Both leave the camera's bearing around a small distant marker
#   poorly fixed, which is the same weak-perspective effect that hurts VA.
