"""Plots for photo positioning from PoIs (i-Loc thesis Figs 27-32).

Every function takes ``ax`` (or makes one) and returns it; inputs are the tables of
:func:`ilocalg.experiments.photo_positioning.run`.
"""

from __future__ import annotations

import re

import numpy as np

from ilocviz.core import new_axes

__all__ = ["layout", "error_per_shot", "error_vs_k", "error_per_combo", "conditioning_scatter", "propagation"]

_COLORS = {"ST": "#0072B2", "VAGIG": "#D55E00", "VABIG": "#009E73", "ST_true_orientation": "#56B4E9",
           "PnP_SQPnP": "#CC79A7", "homography": "#E69F00",
           "VA_truth": "0.55"}


def layout(pois, shots, ax=None, view: str = "top"):
    """The PoIs and shooting points (Figs 27-28): ``view="top"`` (floor map) or ``"front"`` (the wall).

    Parameters
    ----------
    pois : DataFrame with ``poi``, ``x_m``, ``y_m``, ``z_m``
    shots : DataFrame with ``shot``, ``x_m``, ``y_m``
    """
    ax = new_axes(ax)
    if view == "top":
        ax.axhline(0.0, color="0.5", lw=2, zorder=0)
        ax.plot(pois["x_m"], pois["y_m"], "o", color="#D55E00", label="PoIs (on the wall)")
        ax.plot(shots["x_m"], shots["y_m"], "s", color="#0072B2", label="shooting points")
        for _, r in shots.iterrows():
            ax.annotate(r["shot"], (r["x_m"], r["y_m"]), xytext=(6, -3), textcoords="offset points", fontsize=8)
        ax.set_xlabel("x along the wall [m]")
        ax.set_ylabel("y into the room [m]")
        ax.set_aspect("equal", adjustable="datalim")
    elif view == "front":
        ax.plot(pois["x_m"], pois["z_m"], "o", color="#D55E00", label="PoIs")
        for _, r in pois.iterrows():
            ax.annotate(r["poi"], (r["x_m"], r["z_m"]), xytext=(4, 4), textcoords="offset points", fontsize=8)
        ax.set_xlabel("x along the wall [m]")
        ax.set_ylabel("height z [m]")
    else:
        raise ValueError(f"view must be 'top' or 'front', got {view!r}")
    ax.legend(loc="best")
    return ax


def error_per_shot(per_shot, ax=None, methods=("ST", "VAGIG", "VABIG")):
    """Mean error per shooting point as grouped bars (Fig 29); x tick labels carry the distance to p4."""
    ax = new_axes(ax)
    x = np.arange(len(per_shot))
    w = 0.8 / len(methods)
    for i, m in enumerate(methods):
        ax.bar(x + (i - (len(methods) - 1) / 2) * w, per_shot[m], w, label=m, color=_COLORS.get(m))
    ax.set_xticks(x, [f"t{s}\n{d:.1f} m" for s, d in zip(per_shot["shot"], per_shot["dist_to_p4_m"], strict=True)])
    ax.set_xlabel("Shooting point (distance to p4)")
    ax.set_ylabel("Mean horizontal error [cm]")
    ax.legend(loc="upper left")
    return ax


def error_vs_k(per_k, ax=None, methods=("ST", "VAGIG", "VABIG"), comparison=None):
    """Mean error against the number of PoIs (Fig 30); paper points from a comparison table if given."""
    ax = new_axes(ax)
    for m in methods:
        ax.plot(per_k["k"], per_k[m], marker="o", label=f"{m} (reproduced)", color=_COLORS.get(m))
    if comparison is not None:
        for _, r in comparison.iterrows():
            hit = re.match(r"(\w+) mean error, (\d) PoIs", str(r["quantity"]))
            if hit and hit.group(1) in methods:
                ax.plot(int(hit.group(2)), r["paper_value"], marker="*", ms=11, ls="none",
                        color=_COLORS.get(hit.group(1)), markeredgecolor="k",
                        label=f"{hit.group(1)} (thesis)")
        h, labels = ax.get_legend_handles_labels()
        uniq = dict(zip(labels, h, strict=True))
        ax.legend(uniq.values(), uniq.keys(), loc="upper right")
    else:
        ax.legend(loc="upper right")
    ax.set_yscale("log")
    ax.set_xlabel("Number of PoIs in the combination")
    ax.set_ylabel("Mean horizontal error [cm]")
    return ax


def error_per_combo(per_combo, ax=None, method: str = "ST", highlight=("{1,3}", "{1,4}", "{5,6}", "{1,3,4}"),
                    max_k: int = 3):
    """Mean error per PoI combination of up to ``max_k`` PoIs (Figs 31-32), ``highlight`` in a second colour."""
    ax = new_axes(ax, figsize=(10, 4))
    d = per_combo[per_combo["k"] <= max_k].sort_values(["k", "combo"])
    hi = d["combo"].isin(list(highlight)).to_numpy()
    x = np.arange(len(d))
    ax.bar(x[~hi], d[method].to_numpy()[~hi], color=_COLORS.get(method, "#0072B2"), label=method)
    ax.bar(x[hi], d[method].to_numpy()[hi], color="0.25", hatch="//", edgecolor="w",
           label=f"{method}, thesis's near-collinear combinations")
    ax.legend(loc="upper right")
    ax.set_xticks(x, d["combo"], rotation=90, fontsize=7)
    ax.set_xlim(-1, len(d))
    ax.set_xlabel("PoI combination")
    ax.set_ylabel(f"{method} mean horizontal error [cm]")
    return ax


def conditioning_scatter(per_combo, ax=None, method: str = "ST"):
    """Per combination: median ST condition number against the method's mean error."""
    ax = new_axes(ax)
    for k, g in per_combo.groupby("k"):
        ax.scatter(g["st_cond_median"], g[method], s=14, label=f"{k} PoIs")
    ax.set_xscale("log")
    ax.set_xlabel("Median condition number of the ST system [-]")
    ax.set_ylabel(f"{method} mean horizontal error [cm]")
    ax.legend(loc="best", fontsize=7)
    return ax


def propagation(prop, ax=None):
    """ST (all 7 PoIs): Monte-Carlo RMS error against its first-order prediction per shooting point."""
    ax = new_axes(ax)
    d = prop["dist_to_p4_m"]
    ax.plot(d, prop["mc_rms_3d_cm"], "o-", label="Monte Carlo RMS")
    ax.plot(d, prop["predicted_rms_3d_cm"], "s--", label="predicted (orientation + drag)")
    ax.plot(d, prop["predicted_orientation_only_cm"], ":", label="predicted, orientation only")
    ax.plot(d, prop["predicted_drag_only_cm"], ":", label="predicted, drag only")
    ax.set_xlabel("Distance to p4 [m]")
    ax.set_ylabel("3-D RMS error [cm]")
    ax.legend(loc="upper left")
    return ax
