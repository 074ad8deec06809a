"""Plots of the fusion experiments (PDR + Wi-Fi Kalman filter, smoothers, particle filter).

Every function takes ``ax`` (``None`` makes one) and returns the Axes.
"""

from __future__ import annotations

import numpy as np

from ilocviz.core import error_cdf, new_axes

__all__ = ["tracks", "error_cdfs", "per_point_errors", "walk_means", "error_budget_bars", "weight_sensitivity"]

_NOT_SOURCES = ("none (as simulated)", "all of them")


def tracks(track_example, methods=None, ax=None, floor_plan=None, point_methods=("Wi-Fi only", "Wi-Fi only (KNN)")):
    """Trajectories of one walk (Fig 22 / Fig 7 style) from a long table ``method, x_m, y_m``.

    ``methods`` selects and orders the tracks (default all); methods in ``point_methods`` are
    drawn as points (fixes), the others as lines; ``floor_plan`` is a list of (m, 2) polylines.
    """
    ax = new_axes(ax)
    for poly in floor_plan or []:
        poly = np.asarray(poly, dtype=float)
        ax.plot(poly[:, 0], poly[:, 1], color="0.75", lw=0.6, zorder=0)
    names = list(dict.fromkeys(track_example["method"])) if methods is None else list(methods)
    for m in names:
        d = track_example[track_example["method"] == m]
        if not len(d):
            raise ValueError(f"no track for method {m!r}")
        if m in point_methods:
            ax.plot(d["x_m"], d["y_m"], ls="none", marker="o", ms=4, label=m, alpha=0.8)
        else:
            ax.plot(d["x_m"], d["y_m"], lw=2.0 if m == "truth" else 1.2, color="k" if m == "truth" else None,
                    label=m)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    # equal scales by resizing the box, not the data limits: a caller may then fix both x and y limits
    # (zoom on part of the floor) without matplotlib overriding one of them with a warning
    ax.set_aspect("equal", adjustable="box")
    ax.legend(loc="best", fontsize="small")
    return ax


def error_cdfs(test_points, methods, ax=None, method_col: str = "method", error_col: str = "error_m",
               paper: dict | None = None):
    """Error CDFs (Fig 23) of the selected methods from a long table of per-point errors.

    ``paper`` (label -> value in metres, e.g. from :func:`ilocviz.paper_values`) is drawn as dashed lines.
    """
    errs = {}
    for m in methods:
        e = test_points.loc[test_points[method_col] == m, error_col].to_numpy(dtype=float)
        if not e.size:
            raise ValueError(f"no errors for method {m!r}")
        errs[m] = e[~np.isnan(e)]
    return error_cdf(errs, ax=ax, paper=paper)


def per_point_errors(per_point, methods, ax=None, point_col: str = "point"):
    """Mean error at each point index per method (Fig 6 of the fingerprint+PDR paper)."""
    ax = new_axes(ax)
    styles = ["-", "--", "-.", ":"]
    for i, m in enumerate(methods):
        ax.plot(per_point[point_col], per_point[m], ls=styles[i % len(styles)], marker=".", label=m)
    ax.set_xlabel("Point index [-]")
    ax.set_ylabel("Mean positioning error [m]")
    ax.set_ylim(bottom=0)
    ax.legend(loc="best", fontsize="small")
    return ax


def walk_means(per_walk, methods, ax=None, walk_col: str = "walk"):
    """Grouped bars: mean waypoint error of each walk per method (wide table, one column per method)."""
    ax = new_axes(ax)
    n = len(methods)
    x = np.arange(len(per_walk))
    w = 0.8 / max(n, 1)
    for i, m in enumerate(methods):
        ax.bar(x + (i - (n - 1) / 2) * w, per_walk[m].to_numpy(dtype=float), width=w, label=m)
    ax.set_xticks(x)
    ax.set_xticklabels([str(s)[-6:] for s in per_walk[walk_col]], rotation=60, fontsize="small")
    ax.set_xlabel("Walk (last 6 characters of its id)")
    ax.set_ylabel("Mean waypoint error [m]")
    ax.legend(loc="best", fontsize="small")
    return ax


def error_budget_bars(budget, ax=None, methods=None):
    """Horizontal grouped bars: the share of each method's mean error that each error source carries.

    ``budget`` is the table of :func:`ilocalg.fusion.budget.error_budget` (``method``, ``replaced_by_truth``,
    ``share_of_error``); the baseline and the all-true rows are left out (the latter is written in the
    legend). A negative share means that source's error partly cancels another's.
    """
    ax = new_axes(ax)
    names = list(dict.fromkeys(budget["method"])) if methods is None else list(methods)
    src = [s for s in dict.fromkeys(budget["replaced_by_truth"]) if s not in _NOT_SOURCES]
    if not src:
        raise ValueError("budget has no error-source rows")
    y = np.arange(len(src))
    h = 0.8 / max(len(names), 1)
    for i, m in enumerate(names):
        d = budget[budget["method"] == m].set_index("replaced_by_truth")
        if not len(d):
            raise ValueError(f"no budget rows for method {m!r}")
        base = float(d.loc["none (as simulated)", "mean_error_m"]) if "none (as simulated)" in d.index else np.nan
        left = float(d.loc["all of them", "mean_error_m"]) if "all of them" in d.index else np.nan
        ax.barh(y + (i - (len(names) - 1) / 2) * h, d.loc[src, "share_of_error"].to_numpy(dtype=float), height=h,
                label=f"{m} (mean {base:.2f} m; {left:.2f} m with every source true)")
    ax.axvline(0.0, color="0.3", lw=0.8)
    ax.set_yticks(y)
    ax.set_yticklabels(src)
    ax.invert_yaxis()
    ax.set_xlabel("Share of the mean error removed when the source is replaced by the truth [-]")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), fontsize="small")  # below: never over a bar
    return ax


def weight_sensitivity(adjust_sweep, ax=None):
    """Mean error of a fixed-gain combination against its weight, with Wi-Fi only, PDR only and the default marked.

    ``adjust_sweep``: ``weight``, ``mean_error_m``, optional ``wifi_only_mean_m``, ``pdr_only_mean_m`` and a
    boolean ``default`` column.
    """
    ax = new_axes(ax)
    d = adjust_sweep.sort_values("weight")
    ax.plot(d["weight"], d["mean_error_m"], marker="o", label="combined")
    for col, label, ls in (("wifi_only_mean_m", "Wi-Fi only", "--"), ("pdr_only_mean_m", "PDR only", ":")):
        if col in d.columns:
            ax.axhline(float(d[col].iloc[0]), ls=ls, color="0.4", lw=1.0, label=label)
    if "default" in d.columns and d["default"].any():
        r = d[d["default"]].iloc[0]
        ax.plot([r["weight"]], [r["mean_error_m"]], marker="*", ms=14, color="C3", ls="none",
                label=f"default weight {r['weight']:.2f} (inverse variances, training data)")
    ax.set_xlabel("Adjustment weight (fraction of the gap to a fix closed) [-]")
    ax.set_ylabel("Mean positioning error [m]")
    ax.set_ylim(bottom=0)
    ax.legend(loc="best", fontsize="small")
    return ax
