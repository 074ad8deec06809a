"""Wi-Fi fingerprinting plots: AP-count study, error CDFs, radio-map floor plans, hit rates."""

from __future__ import annotations

import numpy as np

from ilocviz.core import error_cdf, new_axes

__all__ = ["k_study", "error_cdfs", "floor_map", "method_bars", "grouped_mean_bars", "ratio_intervals",
           "ap_loss_curves", "rssi_distribution"]


def k_study(df, ax=None, quantities=("median_m", "p80_m", "mean_m")):
    """Error statistics versus the number of strongest APs k (i-Loc thesis Fig 3).

    Parameters
    ----------
    df : DataFrame with ``k_aps`` and the columns in ``quantities`` (metres)
    """
    ax = new_axes(ax)
    for q in quantities:
        ax.plot(df["k_aps"], df[q], marker="o", label=q.replace("_m", ""))
    ax.set_xlabel("Strongest APs compared, k [-]")
    ax.set_ylabel("Positioning error [m]")
    ax.set_xticks(list(df["k_aps"]))
    ax.legend(loc="best")
    return ax


def error_cdfs(errors, ax=None, method_col="method", error_col="error_m", paper=None):
    """Error CDFs per method from a long table (``method``, ``error_m``).

    ``paper`` (label -> value in metres, e.g. from :func:`ilocviz.paper_values`) is drawn as dashed lines.
    """
    d = {m: g[error_col].to_numpy() for m, g in errors.groupby(method_col, sort=False)}
    return error_cdf(d, ax=ax, paper=paper)


def floor_map(points_xy_m, ax=None, value=None, walls=None, aps=None, test_points=None, value_label="value"):
    """Training points on the floor plan, optionally coloured by a per-point value (e.g. drift level).

    Parameters
    ----------
    points_xy_m : array (n, 2)
    value : array (n,), optional colour values
    walls : array (m, 4) wall segments (x0, y0, x1, y1), optional
    aps : array (k, 2) access-point positions, optional
    test_points : array of int, indices of the test route, optional
    """
    ax = new_axes(ax)
    if walls is not None:
        for x0, y0, x1, y1 in np.asarray(walls):
            ax.plot([x0, x1], [y0, y1], color="0.7", lw=0.8, zorder=0)
    pts = np.asarray(points_xy_m)
    if value is None:
        ax.plot(pts[:, 0], pts[:, 1], "o", ms=4, label="training points")
    else:
        sc = ax.scatter(pts[:, 0], pts[:, 1], c=value, s=22, cmap="viridis", label="training points")
        ax.figure.colorbar(sc, ax=ax, label=value_label)
    if test_points is not None:
        tp = pts[np.asarray(test_points)]
        ax.plot(tp[:, 0], tp[:, 1], "-", color="#D55E00", lw=1.2, label="test route")
    if aps is not None:
        a = np.asarray(aps)
        ax.plot(a[:, 0], a[:, 1], "^", color="k", ms=5, label="access points")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="upper right", fontsize=7)
    return ax


def method_bars(df, ax=None, columns=("mean_m", "median_m", "p75_m"), label_col="method", horizontal=False,
                reference=None):
    """Grouped bars of error statistics (metres) per method.

    ``horizontal``: one row per method, first on top (long method names stay readable); ``reference``: an
    optional ``(value_m, label)`` drawn as a dashed line across the bars (e.g. a published figure).
    """
    ax = new_axes(ax)
    n = len(columns)
    x = np.arange(len(df))
    w = 0.8 / n
    for i, c in enumerate(columns):
        off = x + (i - (n - 1) / 2) * w
        if horizontal:
            ax.barh(off, df[c], height=w, label=c.replace("_m", ""))
        else:
            ax.bar(off, df[c], width=w, label=c.replace("_m", ""))
    if horizontal:
        ax.set_yticks(x)
        ax.set_yticklabels(df[label_col])
        ax.invert_yaxis()
        ax.set_xlabel("2-D error [m]")
    else:
        ax.set_xticks(x)
        ax.set_xticklabels(df[label_col], rotation=20, ha="right")
        ax.set_ylabel("2-D error [m]")
    if reference is not None:
        value, label = reference
        (ax.axvline if horizontal else ax.axhline)(float(value), color="k", ls="--", lw=1.0, label=label)
    ax.legend(loc="best")
    return ax


def grouped_mean_bars(df, ax=None, group_col="floor", method_col="method", value_col="mean_m",
                      lo_col="mean_ci95_lo_m", hi_col="mean_ci95_hi_m"):
    """Mean 2-D error (m) per group (e.g. a floor) and method, side by side, each bar labelled with its value and
    with its interval as an error bar (``lo_col`` / ``hi_col``)."""
    ax = new_axes(ax)
    groups = list(dict.fromkeys(df[group_col]))
    methods = list(dict.fromkeys(df[method_col]))
    w = 0.8 / len(methods)
    x = np.arange(len(groups))
    for i, m in enumerate(methods):
        d = df[df[method_col] == m].set_index(group_col).reindex(groups)
        v = d[value_col].to_numpy(dtype=float)
        err = np.vstack([v - d[lo_col].to_numpy(dtype=float), d[hi_col].to_numpy(dtype=float) - v])
        bars = ax.bar(x + (i - (len(methods) - 1) / 2) * w, v, width=w, yerr=err, capsize=3, label=m)
        ax.bar_label(bars, labels=[f"{b:.1f}" for b in v], padding=2, fontsize="small")
    ax.set_xticks(x)
    ax.set_xticklabels(groups)
    ax.set_ylabel("mean 2-D error [m]")
    ax.legend(loc="upper left", fontsize="small")
    return ax


def ratio_intervals(df, ax=None, label_col="floor", value_col="ratio", lo_col="ci95_lo", hi_col="ci95_hi",
                    xlabel="ratio of mean errors [-]"):
    """One point per row (``label_col``) at ``value_col`` with its interval, and a dashed line at 1 (no change)."""
    ax = new_axes(ax)
    y = np.arange(len(df))
    v = df[value_col].to_numpy(dtype=float)
    err = np.vstack([v - df[lo_col].to_numpy(dtype=float), df[hi_col].to_numpy(dtype=float) - v])
    ax.errorbar(v, y, xerr=err, fmt="o", capsize=3, color="k")
    ax.axvline(1.0, color="0.4", ls="--", lw=1.0, label="no change")
    ax.set_yticks(y)
    ax.set_yticklabels(df[label_col])
    ax.invert_yaxis()
    ax.set_xlabel(xlabel)
    ax.legend(loc="best")
    return ax


def ap_loss_curves(df, ax=None, ax_increase=None, x_col="fraction_aps_gone", label_col="label"):
    """CV mean error (``cv_mean_error_m``, on ``ax``) and its paired increase with a 95 % interval
    (``increase_m``, ``increase_ci95_lo_m`` / ``increase_ci95_hi_m``, on ``ax_increase`` when given) against the
    share of APs gone (``x_col``, plotted in %), one curve per ``label_col``."""
    ax = new_axes(ax)
    for lab, d in df.groupby(label_col, sort=False):
        d = d.sort_values(x_col)
        x = 100.0 * d[x_col].to_numpy(dtype=float)
        ax.plot(x, d["cv_mean_error_m"].to_numpy(dtype=float), marker="o", ms=4, label=lab)
        if ax_increase is not None:
            v = d["increase_m"].to_numpy(dtype=float)
            err = np.vstack([v - d["increase_ci95_lo_m"].to_numpy(dtype=float),
                             d["increase_ci95_hi_m"].to_numpy(dtype=float) - v])
            ax_increase.errorbar(x, v, yerr=err, marker="o", ms=4, capsize=3, label=lab)
    ax.set_xlabel("APs gone at query time [% of the survey's APs]")
    ax.set_ylabel("CV mean 2-D error [m]")
    ax.legend(loc="upper left", fontsize="small")
    if ax_increase is not None:
        ax_increase.axhline(0.0, color="0.4", ls="--", lw=1.0)
        ax_increase.set_xlabel("APs gone at query time [% of the survey's APs]")
        ax_increase.set_ylabel("increase of the CV mean error [m]")
    return ax


def rssi_distribution(df, ax=None):
    """Histogram (bars, left axis) and CDF (line, right axis) of one AP's RSSI at one point (thesis Fig 4).

    Parameters
    ----------
    df : DataFrame with ``rssi_dbm`` (bin start), ``probability`` and ``cdf``
    """
    ax = new_axes(ax)
    w = float(np.diff(df["rssi_dbm"]).min()) if len(df) > 1 else 1.0
    ax.bar(df["rssi_dbm"], df["probability"], width=0.9 * w, align="edge", color="#56B4E9", label="probability")
    ax.set_xlabel("RSSI [dBm]")
    ax.set_ylabel("Probability per bin [-]")
    ax2 = ax.twinx()
    ax2.step(df["rssi_dbm"] + w, df["cdf"], where="pre", color="#D55E00", label="CDF")
    ax2.set_ylabel("Cumulative probability [-]")
    ax2.set_ylim(0, 1.02)
    return ax
