"""Plots of the fusion experiments (PDR + Wi-Fi Kalman filter, smoothers, particle filter).

Every function takes ``ax`` (``None`` makes one) and returns the Axes.
"""

from __future__ import annotations

import numpy as np

from ilocviz.core import error_cdf, new_axes

__all__ = ["tracks", "error_cdfs", "per_point_errors", "walk_means"]


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
