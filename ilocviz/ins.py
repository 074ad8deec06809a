"""Plots of the inertial-navigation experiments (notebooks 12-14)."""

from __future__ import annotations

import re

import numpy as np

from ilocviz.core import new_axes

__all__ = ["walk_trajectories", "errors_vs_time", "heading_errors_vs_time", "window_study", "window_study_band",
           "window_study_paper", "attitude_errors_vs_time", "vt_positions", "bias_estimates"]


def walk_trajectories(traj, phone: str, ax=None, gcp_xy=None, indoor_only: bool = True):
    """Fig 7 / 10: east-north trajectories of every method and the truth for one phone.

    ``traj``: the ``trajectory`` table of :func:`ilocalg.experiments.ins_constraints.run`.
    """
    ax = new_axes(ax)
    d = traj[traj["phone"] == phone]
    if indoor_only:
        d = d[d["indoor"]]
    for method, g in d.groupby("method", sort=False):
        kw = {"color": "k", "lw": 2.2, "zorder": 5} if method == "Truth" else {"lw": 1.1}
        ax.plot(g["E"], g["N"], label=method, **kw)
    if gcp_xy is not None:
        g = np.asarray(gcp_xy, dtype=float)
        ax.plot(g[:, 0], g[:, 1], "^", ms=8, color="tab:blue", mec="k", label="control points", zorder=6)
    ax.set_xlabel("East [m]")
    ax.set_ylabel("North [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=7)
    ax.set_title(f"{phone}: trajectories (indoor part)")
    return ax


def errors_vs_time(traj, phone: str, axis: str = "N", ax=None, gcp_t_s=None):
    """Fig 8 / 11: one position-error component (m) against time for every method."""
    ax = new_axes(ax)
    d = traj[(traj["phone"] == phone) & traj["indoor"]]
    truth = d[d["method"] == "Truth"].set_index("t_s")[axis]
    for method, g in d.groupby("method", sort=False):
        if method == "Truth":
            continue
        ax.plot(g["t_s"], g[axis].to_numpy() - truth.loc[g["t_s"]].to_numpy(), label=method, lw=1)
    for t in gcp_t_s if gcp_t_s is not None else []:
        ax.axvline(t, color="0.5", lw=0.6, ls=":")
    ax.set_xlabel("Time [s]")
    ax.set_ylabel(f"{axis} error [m]")
    ax.legend(loc="best", fontsize=7)
    return ax


def heading_errors_vs_time(traj, phone: str, ax=None):
    """Fig 9 / 12: heading error (deg, wrapped) against time for every method."""
    ax = new_axes(ax)
    d = traj[(traj["phone"] == phone) & traj["indoor"]]
    truth = d[d["method"] == "Truth"].set_index("t_s")["heading_deg"]
    for method, g in d.groupby("method", sort=False):
        if method == "Truth":
            continue
        e = (g["heading_deg"].to_numpy() - truth.loc[g["t_s"]].to_numpy() + 180.0) % 360.0 - 180.0
        ax.plot(g["t_s"], e, label=method, lw=1)
    ax.set_xlabel("Time [s]")
    ax.set_ylabel("Heading error [deg]")
    ax.legend(loc="best", fontsize=7)
    return ax


def window_study(df, ax=None, stat: str = "rms"):
    """Fig 19: position error against the online smoothing window (s), one line per phone and axis.

    ``df`` columns: ``phone``, ``window_s``, ``stat``, ``N``, ``E``, ``H``.
    """
    ax = new_axes(ax)
    d = df[df["stat"] == stat]
    for phone, g in d.groupby("phone", sort=False):
        g = g.sort_values("window_s")
        for axis, ls in (("N", "-"), ("E", "--"), ("H", ":")):
            ax.plot(g["window_s"], g[axis], ls=ls, marker="o", label=f"{phone}-{axis}")
    ax.set_xlabel("Smoothing window [s]")
    ax.set_ylabel(f"{stat.upper()} position error [m]")
    ax.legend(loc="best", fontsize=7, ncol=2)
    return ax


_ONLINE_ROW = re.compile(r"^(?P<phone>\S+) .*Online (?P<window>\d+)\s*sec: RMS (?P<axis>[NEH]) error")


def window_study_paper(ax, comparison, marker: str = "*"):
    """The paper's online-window RMS errors (Fig 19 / Tables 8 and 10) as points on a :func:`window_study` plot.

    Each comparison row whose ``quantity`` reads ``"<phone> ... Online <w>sec: RMS <N|E|H> error"`` is drawn at
    ``(w, paper_value)`` in the colour of the ``"<phone>-<axis>"`` line already on ``ax`` (grey when there is none).

    Raises
    ------
    ValueError
        When no row of ``comparison`` is an online-window row.
    """
    colours = {ln.get_label(): ln.get_color() for ln in ax.get_lines()}
    n = 0
    for r in comparison.itertuples():
        m = _ONLINE_ROW.match(str(r.quantity))
        if m is None:
            continue
        key = f"{m['phone']}-{m['axis']}"
        label = f"paper ({r.paper}): stars, coloured as the line" if n == 0 else None
        ax.plot([float(m["window"])], [float(r.paper_value)], ls="none", marker=marker, ms=10, mec="k", mew=0.6,
                color=colours.get(key, "0.4"), label=label, zorder=4)
        n += 1
    if n == 0:
        raise ValueError("no comparison row reads '<phone> ... Online <w>sec: RMS <N|E|H> error'")
    ax.legend(loc="best", fontsize=7, ncol=2)
    return ax


def window_study_band(df, ax=None):
    """Fig 19 with its spread: horizontal RMS error against the window (s), mean over seeds and window-grid
    offsets, with the min-max band over them, one line per phone.

    ``df``: the ``window_sweep`` table of :func:`ilocalg.experiments.ins_online.run` (columns ``phone``,
    ``window_s``, ``stat``, ``horizontal``, ``horizontal_min``, ``horizontal_max``); finite windows only.
    """
    ax = new_axes(ax)
    d = df[(df["stat"] == "rms") & (df["window_s"] > 0) & np.isfinite(df["window_s"])]
    for phone, g in d.groupby("phone", sort=False):
        g = g.sort_values("window_s")
        line, = ax.plot(g["window_s"], g["horizontal"], marker="o", label=f"{phone} (mean)")
        ax.fill_between(g["window_s"], g["horizontal_min"], g["horizontal_max"], color=line.get_color(),
                        alpha=0.2, lw=0, label=f"{phone} (min-max over seeds x grid offsets)")
    ax.set_xlabel("Smoothing window [s]")
    ax.set_ylabel("Horizontal RMS error [m]")
    ax.legend(loc="best", fontsize=7)
    return ax


def attitude_errors_vs_time(traj, phone: str, ax=None, methods=None):
    """Figs 15 / 18: roll, pitch and heading errors (deg) against time of the filter and the online windows.

    ``traj``: the ``trajectory`` table of :func:`ilocalg.experiments.ins_online.run` (columns ``roll_err_deg``,
    ``pitch_err_deg``, ``heading_err_deg``); ``ax``: three axes (roll, pitch, heading) or None.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(3, 1, sharex=True, figsize=(7, 6))
    d = traj[(traj["phone"] == phone) & traj["indoor"] & (traj["method"] != "Truth")]
    for method, g in d.groupby("method", sort=False):
        if methods is not None and method not in methods:
            continue
        for a, col in zip(ax, ("roll_err_deg", "pitch_err_deg", "heading_err_deg"), strict=True):
            a.plot(g["t_s"], g[col], lw=0.9, label=method)
    for a, name in zip(ax, ("Roll", "Pitch", "Heading"), strict=True):
        a.set_ylabel(f"{name} error [deg]")
    ax[-1].set_xlabel("Time [s]")
    ax[0].legend(loc="best", fontsize=7)
    return ax


def vt_positions(t_s, pos_ekf_m, t_vt_s, pos_vt_m, ax=None, axis: int = 0):
    """Fig 11 (survey): EKF position against the video-tracker measurements for one axis (m)."""
    ax = new_axes(ax)
    name = "xyz"[axis]
    ax.plot(t_s, np.asarray(pos_ekf_m)[:, axis], lw=1, label=f"EKF {name}")
    ax.plot(t_vt_s, np.asarray(pos_vt_m)[:, axis], ".", ms=3, label=f"video tracker {name}")
    ax.set_xlabel("Time [s]")
    ax.set_ylabel(f"{name} position [m]")
    ax.legend(loc="best")
    return ax


def bias_estimates(t_s, bias, true_bias=None, ax=None, unit: str = "", label: str = "b"):
    """Fig 12 (survey): three bias estimates settling over time, with the true values dashed."""
    ax = new_axes(ax)
    bias = np.asarray(bias)
    for i, c in enumerate("xyz"):
        line, = ax.plot(t_s, bias[:, i], lw=1, label=f"{label}_{c}")
        if true_bias is not None:
            ax.axhline(true_bias[i], color=line.get_color(), ls="--", lw=0.8)
    ax.set_xlabel("Time [s]")
    ax.set_ylabel(f"Bias estimate [{unit}]")
    ax.legend(loc="best", fontsize=7)
    return ax
