"""Style, figure saving, error-CDF and trajectory plots."""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["STYLE", "style", "new_axes", "savefig", "figure_title", "error_cdf", "trajectory", "LEGEND_NAMES",
           "legend_name",
           "paper_mark", "paper_point", "paper_values", "paper_vs_reproduced"]

#: Method ids used in result tables -> the names a reader of the papers knows (legends use these).
LEGEND_NAMES = {
    "pdr": "PDR only",
    "pts": "PTS (PDR, i-Loc)",
    "wifi": "Wi-Fi only",
    "kf": "Kalman filter (PDR + Wi-Fi)",
    "kf_rts": "Kalman filter + RTS smoother",
    "aligned": "PDR aligned to Wi-Fi",
    "aligned_rot": "PDR aligned to Wi-Fi (with rotation)",
    "aligned_kf_rts": "aligned PDR + KF + RTS",
    "pf": "particle filter",
    "pf_smooth": "particle filter + smoother",
    "map_align": "map-matched PDR",
    "map_align_kf_rts": "map-matched PDR + KF + RTS",
    "radar": "Simplified-RADAR",
    "horus": "Simplified-Horus",
    "knn": "KNN",
    "wknn": "weighted KNN",
    "sam": "SAM (i-Loc)",
    "ma": "moving average",
    "sg": "Savitzky-Golay",
    "nhc": "NHC",
    "wvc": "WVC",
    "zupt": "ZUPT",
    "gcp": "control points (GCP)",
    "rts": "RTS smoother",
}


def legend_name(method: str) -> str:
    """The reader-facing name of a method id (:data:`LEGEND_NAMES`); other labels are returned unchanged."""
    return LEGEND_NAMES.get(str(method), str(method))

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


def figure_title(fig, name: str = "") -> str:
    """The figure's own title: its suptitle, else the titles of its axes (joined by " / "), else ``name``
    with underscores as spaces. Used as the caption of the figure's thumbnail on the landing page."""
    sup = getattr(fig, "_suptitle", None)
    text = sup.get_text().strip() if sup is not None else ""
    if not text:
        titles = [ax.get_title().strip() for ax in fig.get_axes()]
        text = " / ".join(dict.fromkeys(t for t in titles if t))
    return " ".join(text.split()) or name.replace("_", " ")


def _anchor_in_notebook(name: str) -> None:
    """In a notebook kernel, an invisible HTML anchor ``fig-<name>`` in the cell's output, just before the
    figure the inline backend draws: the landing page's thumbnails link to it."""
    try:
        from IPython import get_ipython
        from IPython.display import HTML, display
    except ImportError:
        return
    ip = get_ipython()
    if ip is None or not hasattr(ip, "kernel"):
        return
    display(HTML(f'<a id="fig-{name}"></a>'))


def savefig(fig, name: str, out_dir, formats=None) -> list[Path]:
    """Save ``fig`` as ``<out_dir>/figures/<name>.<fmt>``; returns the paths (nothing when out_dir is None).

    ``formats``: default PNG and PDF, or those the environment variable
    :data:`ilocalg.workflow.reporting.FIGURE_FORMATS_ENV` names (the reproduce runner's fast mode: PNG only).
    The PNG carries the figure's title (:func:`figure_title`) in its ``Title`` text chunk; in a notebook
    kernel an anchor ``#fig-<name>`` marks the figure in the executed notebook's HTML.
    """
    if formats is None:
        formats = _default_formats()
    if out_dir is None:
        return []
    d = Path(out_dir) / "figures"
    d.mkdir(parents=True, exist_ok=True)
    paths = []
    for fmt in formats:
        p = d / f"{name}.{fmt}"
        meta = ({"CreationDate": None} if fmt == "pdf" else
                {"Software": None, "Title": figure_title(fig)} if fmt == "png" else None)
        fig.savefig(p, format=fmt, metadata=meta)
        paths.append(p)
    _anchor_in_notebook(name)
    return paths


def _default_formats() -> tuple[str, ...]:
    from ilocalg.workflow.reporting import FIGURE_FORMATS_ENV

    value = os.environ.get(FIGURE_FORMATS_ENV, "").strip()
    if not value:
        return ("png", "pdf")
    formats = tuple(f.strip().lower() for f in value.split(",") if f.strip())
    bad = [f for f in formats if f not in ("png", "pdf", "svg")]
    if bad or not formats:
        raise ValueError(f"{FIGURE_FORMATS_ENV}={value!r}: figure formats are png, pdf or svg, comma-separated")
    return formats


def error_cdf(errors: dict, ax=None, unit: str = "m", xlabel: str | None = None, paper: dict | None = None):
    """Empirical CDFs of positioning errors, optionally with the paper's values marked.

    Parameters
    ----------
    errors : dict[str, array_like]
        Label (or method id, see :func:`legend_name`) -> errors (in ``unit``); NaN = not located: left
        out of the mean, counted in the legend, and the curve ends below 1.
    paper : dict[str, float], optional
        Label -> a value the paper publishes on the same axis (e.g. ``{"KF mean, thesis Fig 23": 2.82}``),
        drawn as a dashed vertical line (:func:`paper_mark`).
    """
    ax = new_axes(ax)
    n_colours = max(len(plt.rcParams["axes.prop_cycle"].by_key().get("color", [])), 1)
    for i, (label, e) in enumerate(errors.items()):
        e = np.asarray(e, dtype=float).ravel()
        n_all = e.size
        e = np.sort(e[~np.isnan(e)])  # NaN: not located (counted; the curve then ends below 1)
        if e.size == 0:
            raise ValueError(f"errors for {label!r} are all NaN (nothing located)")
        missing = f", {n_all - e.size} not located" if e.size < n_all else ""
        # past the colour cycle, the colours repeat: the next round of curves is dashed, then dotted
        ax.step(e, np.arange(1, e.size + 1) / n_all, where="post", ls=("-", "--", ":")[(i // n_colours) % 3],
                label=f"{legend_name(label)} (mean {e.mean():.2f} {unit}{missing})")
    for i, (label, value) in enumerate((paper or {}).items()):
        paper_mark(ax, value, label, axis="x", color=f"{0.15 + 0.2 * (i % 3):.2f}")
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
    # equal scales by resizing the box, not the data limits: a caller may then fix both x and y limits
    # (zoom on part of the floor) without matplotlib overriding one of them with a warning
    ax.set_aspect("equal", adjustable="box")
    ax.legend(loc="best")
    return ax


def _show(ax, axis: str, values) -> None:
    """Widen the ``axis`` limits of ``ax`` (when they are fixed or too narrow) so that ``values`` are in view.

    A paper's value outside the plotted range would otherwise be silently invisible.
    """
    get, set_ = (ax.get_xlim, ax.set_xlim) if axis == "x" else (ax.get_ylim, ax.set_ylim)
    lo, hi = get()
    vals = [float(v) for v in values]
    if lo > hi or (min(vals) >= lo and max(vals) <= hi):
        return  # inverted axis (left alone) or already in view
    log = (ax.get_xscale() if axis == "x" else ax.get_yscale()) == "log"
    new_lo, new_hi = min(lo, *vals), max(hi, *vals)
    pad = 0.0 if log else 0.04 * (new_hi - new_lo)
    set_(new_lo - pad if new_lo < lo else lo, new_hi + pad if new_hi > hi else hi)


def paper_mark(ax, value: float, label: str, axis: str = "x", band: tuple[float, float] | None = None,
               color: str = "0.25"):
    """Mark a paper's published value on ``ax``: a dashed line (and an optional shaded band), labelled.

    Parameters
    ----------
    value : float
        The paper's value, in the axis' units (a reference, drawn, never computed with).
    label : str
        What it is and where it is from, e.g. ``"paper: KF mean (i-Loc Fig 23)"``; ``"paper: "`` is
        prefixed when missing.
    axis : {"x", "y"}
        ``"x"``: a vertical line at ``x = value``; ``"y"``: a horizontal one.
    band : (low, high), optional
        A range the paper gives (e.g. Table 1's 5-95 % range), shaded.
    """
    if axis not in ("x", "y"):
        raise ValueError(f"axis must be 'x' or 'y', got {axis!r}")
    label = label if label.lower().startswith("paper") else f"paper: {label}"
    _show(ax, axis, [value, *(band or ())])
    line = ax.axvline if axis == "x" else ax.axhline
    line(float(value), color=color, ls="--", lw=1.2, label=label, zorder=3)
    if band is not None:
        span = ax.axvspan if axis == "x" else ax.axhspan
        span(float(band[0]), float(band[1]), color=color, alpha=0.12, lw=0, zorder=0)
    ax.legend(loc="best", fontsize="small")
    return ax


def paper_point(ax, x: float, y: float, label: str, marker: str = "X", color: str = "k"):
    """Mark one published point on ``ax`` (e.g. a median at ``(4.5 m, 0.5)`` on an error CDF), labelled.

    Parameters
    ----------
    x, y : float
        The paper's point in the axes' units (a reference, drawn, never computed with).
    label : str
        What it is and where it is from; ``"paper: "`` is prefixed when missing.
    """
    label = label if label.lower().startswith("paper") else f"paper: {label}"
    _show(ax, "x", [x])
    _show(ax, "y", [y])
    ax.plot([float(x)], [float(y)], ls="none", marker=marker, ms=9, mfc="none" if marker in "os^D" else color,
            mec=color, mew=1.6, color=color, label=label, zorder=4)
    ax.legend(loc="best", fontsize="small")
    return ax


def paper_values(table, item: str | None = None, contains: str | None = None, unit: str | None = None) -> dict:
    """Published values of a comparison table's rows, as ``{"<quantity> (<paper> <item>)": paper_value}``.

    Parameters
    ----------
    table : DataFrame
        Comparison rows (``paper``, ``item``, ``quantity``, ``paper_value``; :mod:`ilocalg.papers`).
    item, contains, unit : str, optional
        Keep rows whose ``item`` starts with ``item``, whose ``quantity`` contains ``contains``
        (case-insensitive) and whose ``unit`` equals ``unit``.

    Raises
    ------
    ValueError
        When no row is left (the message names the filter).
    """
    import pandas as pd

    df = pd.DataFrame(table)
    keep = np.ones(len(df), dtype=bool)
    if item is not None:
        keep &= df["item"].astype(str).str.startswith(item).to_numpy()
    if contains is not None:
        keep &= df["quantity"].astype(str).str.lower().str.contains(contains.lower(), regex=False).to_numpy()
    if unit is not None and "unit" in df:
        keep &= (df["unit"].astype(str) == unit).to_numpy()
    df = df[keep]
    if df.empty:
        raise ValueError(f"no comparison row with item={item!r}, quantity containing {contains!r}, unit={unit!r}")
    return {f"{r.quantity} ({r.paper} {r.item})": float(r.paper_value) for r in df.itertuples()}


def paper_vs_reproduced(table, ax=None, label_col: str = "quantity", title: str | None = None):
    """Every reproduced value as a ratio to the paper's, on one log axis: the paper's value is 1.

    Parameters
    ----------
    table : DataFrame
        Comparison rows (``paper_value``, ``reproduced_value``; with ``mean``, ``ci95_low`` and
        ``ci95_high`` the mean and its 95 % interval are drawn instead of the single run).
        Rows whose paper value is 0 or not finite are left out (a ratio has no meaning there).
    label_col : str
        Column naming each row (default ``quantity``; ``item`` is prefixed when present).
    title : str, optional
        The figure's title, e.g. the paper's figure or table number.

    The bands show the agreement classes of :mod:`ilocalg.papers`: within 10 % and within 35 %.
    """
    import pandas as pd

    df = pd.DataFrame(table).copy()
    pv = pd.to_numeric(df["paper_value"], errors="coerce")
    has_ci = all(c in df.columns for c in ("mean", "ci95_low", "ci95_high"))
    val = pd.to_numeric(df["mean"] if has_ci else df["reproduced_value"], errors="coerce")
    keep = np.isfinite(pv) & (pv != 0) & np.isfinite(val) & (val / pv > 0)
    df, pv, val = df[keep], pv[keep], val[keep]
    if df.empty:
        raise ValueError("no row with a finite, non-zero paper value and a reproduced value of the same sign")
    ax = new_axes(ax, figsize=(7.0, 0.32 * len(df) + 1.4))
    y = np.arange(len(df))[::-1]
    ratio = (val / pv).to_numpy(dtype=float)
    ax.axvspan(1 / 1.35, 1.35, color="#F0E442", alpha=0.25, lw=0, label="within 35 %")
    ax.axvspan(0.9, 1.1, color="#009E73", alpha=0.25, lw=0, label="within 10 %")
    ax.axvline(1.0, color="k", lw=1.0, label="paper value")
    if has_ci:
        lo = pd.to_numeric(df["ci95_low"], errors="coerce").to_numpy(dtype=float) / pv.to_numpy(dtype=float)
        hi = pd.to_numeric(df["ci95_high"], errors="coerce").to_numpy(dtype=float) / pv.to_numpy(dtype=float)
        ok = np.isfinite(lo) & np.isfinite(hi) & (lo > 0) & (hi > 0)
        ax.hlines(y[ok], np.minimum(lo, hi)[ok], np.maximum(lo, hi)[ok], color="#0072B2", lw=2.0,
                  label="reproduced 95 % CI")
    ax.plot(ratio, y, "o", color="#0072B2", label="reproduced / paper")
    names = df[label_col].astype(str)
    if "item" in df.columns and label_col != "item":
        names = df["item"].astype(str) + ": " + names
    ax.set_yticks(y, names)
    ax.set_xscale("log")
    # plain ratios (0.5, 1, 2) instead of the log scale's 3x10^-1 labels, which overlap within a decade
    lo, hi = ax.get_xlim()
    for mantissas in ((1, 2, 5), (1, 2, 3, 5), (1, 1.5, 2, 3, 5, 7), (1, 1.1, 1.2, 1.3, 1.5, 1.7, 2, 3, 5, 7, 8, 9)):
        ticks = [m * 10.0**e for e in range(-3, 4) for m in mantissas]
        if sum(lo <= t <= hi for t in ticks) >= 3:
            break
    ax.xaxis.set_major_locator(mpl.ticker.FixedLocator(ticks))
    ax.xaxis.set_major_formatter(mpl.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(mpl.ticker.NullFormatter())
    ax.set_xlabel("reproduced / paper value [-]")
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize="small")
    return ax
