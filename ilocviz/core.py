"""Style, figure saving, error-CDF and trajectory plots."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["STYLE", "style", "new_axes", "savefig", "error_cdf", "trajectory"]

#: Publication style: readable sizes, light grid, colour-blind-safe cycle (Okabe-Ito).
STYLE = {
    "figure.figsize": (6.4, 4.2),
    "figure.dpi": 110,
    "savefig.dpi": 200,
    "savefig.bbox": "tight",
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.6,
    "axes.prop_cycle": mpl.cycler(color=["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00",
                                         "#56B4E9", "#F0E442", "#000000"]),
    "svg.hashsalt": "ilocviz",
    "pdf.fonttype": 42,
}


@contextmanager
def style():
    """Context manager applying :data:`STYLE`; on exit restores only the rcParams it set.

    Unlike :func:`matplotlib.rc_context`, which restores every rcParam it saw on entry, this leaves
    ``interactive`` (and the backend) alone: the inline backend turns interactive mode on when
    pyplot first loads inside the block, and restoring it to off would stop every later figure
    from appearing in a notebook.
    """
    saved = {k: mpl.rcParams[k] for k in STYLE}
    mpl.rcParams.update(STYLE)
    try:
        yield
    finally:
        mpl.rcParams.update(saved)


def new_axes(ax=None, **subplots_kw):
    """Return ``ax`` or a fresh Axes from a new figure."""
    if ax is not None:
        return ax
    _, ax = plt.subplots(**subplots_kw)
    return ax


def savefig(fig, name: str, out_dir, formats=("png", "pdf")) -> list[Path]:
    """Save ``fig`` as ``<out_dir>/figures/<name>.<fmt>``; returns the paths (nothing when out_dir is None)."""
    if out_dir is None:
        return []
    d = Path(out_dir) / "figures"
    d.mkdir(parents=True, exist_ok=True)
    paths = []
    for fmt in formats:
        p = d / f"{name}.{fmt}"
        meta = {"CreationDate": None} if fmt == "pdf" else {"Software": None} if fmt == "png" else None
        fig.savefig(p, format=fmt, metadata=meta)
        paths.append(p)
    return paths


def error_cdf(errors: dict, ax=None, unit: str = "m", xlabel: str | None = None):
    """Empirical CDFs of positioning errors.

    Parameters
    ----------
    errors : dict[str, array_like]
        Label -> errors (in ``unit``); NaNs raise.
    """
    ax = new_axes(ax)
    for label, e in errors.items():
        e = np.sort(np.asarray(e, dtype=float).ravel())
        if np.isnan(e).any():
            raise ValueError(f"errors for {label!r} contain NaN")
        ax.step(e, np.arange(1, e.size + 1) / e.size, where="post", label=f"{label} (mean {e.mean():.2f} {unit})")
    ax.set_xlabel(xlabel or f"Positioning error [{unit}]")
    ax.set_ylabel("Cumulative probability [-]")
    ax.set_ylim(0, 1.02)
    ax.set_xlim(left=0)
    ax.legend(loc="lower right")
    return ax


def trajectory(tracks: dict, ax=None, floor_plan=None, markers: dict | None = None):
    """Trajectories on a floor plan.

    Parameters
    ----------
    tracks : dict[str, array_like (n, 2)]
        Label -> positions (x_m, y_m).
    floor_plan : list of (m, 2) arrays, optional
        Polylines (walls, corridor outlines) drawn in grey.
    markers : dict[str, array_like (k, 2)], optional
        Labelled point sets (reference points, access points ...).
    """
    ax = new_axes(ax)
    for poly in floor_plan or []:
        poly = np.asarray(poly, dtype=float)
        ax.plot(poly[:, 0], poly[:, 1], color="0.6", lw=0.8, zorder=0)
    for label, pts in (markers or {}).items():
        pts = np.asarray(pts, dtype=float)
        ax.plot(pts[:, 0], pts[:, 1], ls="none", marker="o", ms=3, label=label, alpha=0.7)
    for label, xy in tracks.items():
        xy = np.asarray(xy, dtype=float)
        ax.plot(xy[:, 0], xy[:, 1], label=label, marker=".", ms=3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best")
    return ax
