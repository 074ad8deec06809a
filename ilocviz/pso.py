"""Plots of the PSO step-length experiment (PSO thesis Figs. 3.9, 5.3-5.5, 5.10-5.21)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocviz.core import new_axes

__all__ = ["phase2_grid", "swarm_iterations", "gbest_convergence", "step_detection", "walk_paths",
           "compass_filters", "k_factors"]


def swarm_iterations(swarm: pd.DataFrame, ax=None, max_iter: int | None = None, dim: int = 0):
    """Particles per generation with the generation's best marked (Fig. 5.11).

    Parameters
    ----------
    swarm : DataFrame
        :meth:`ilocalg.optim.PSOResult.swarm_table` output.
    max_iter : int, optional
        Last generation drawn.
    """
    ax = new_axes(ax)
    s = swarm if max_iter is None else swarm[swarm["iteration"] <= max_iter]
    x = f"x{dim}"
    ax.scatter(s["iteration"], s[x], s=14, color="#0072B2", alpha=0.6, label="particles")
    b = s[s["is_gen_best"]]
    ax.scatter(b["iteration"], b[x], s=30, color="#D55E00", zorder=3, label="best of generation")
    ax.set_xlabel("Generation [-]")
    ax.set_ylabel("k [m / (m/s$^2$)$^{1/4}$]")
    ax.legend(loc="best")
    return ax


def gbest_convergence(history: pd.DataFrame, ax=None, min_fitness: float | None = None):
    """gbest fitness per generation (log scale), with the stopping threshold."""
    ax = new_axes(ax)
    ax.semilogy(history["iteration"], history["gbest_fitness"], marker="o", ms=3, label="gbest fitness")
    if min_fitness is not None:
        ax.axhline(min_fitness, color="0.4", ls="--", lw=1, label="minFitness")
    ax.set_xlabel("Generation [-]")
    ax.set_ylabel("Fitness |S_gps - S_ins| [m]")
    ax.legend(loc="best")
    return ax


def step_detection(signal: pd.DataFrame, steps: pd.DataFrame, ax=None, t_range: tuple | None = None):
    """Vertical acceleration raw and MA-filtered with the detected peaks and valleys (Fig. 5.10)."""
    ax = new_axes(ax)
    s = signal if t_range is None else signal[(signal["t_s"] >= t_range[0]) & (signal["t_s"] <= t_range[1])]
    st = steps if t_range is None else steps[(steps["t_s"] >= t_range[0]) & (steps["t_s"] <= t_range[1])]
    ax.plot(s["t_s"], s["acc_z_mps2"], color="0.6", lw=0.8, marker=".", ms=3, label="raw (8 Hz)")
    if "acc_ma_mps2" in s:
        ax.plot(s["t_s"], s["acc_ma_mps2"], lw=1.2, label="MA nL=nR=2")
    ax.plot(st["t_s"], st["a_max_mps2"], ls="none", marker="^", color="#D55E00", label="step max")
    ax.plot(st["t_valley_s"], st["a_min_mps2"], ls="none", marker="v", color="#009E73", label="step min")
    ax.set_xlabel("Time [s]")
    ax.set_ylabel("Vertical acceleration [m/s$^2$]")
    ax.legend(loc="upper right", ncol=2)
    return ax


def walk_paths(paths: dict, ax=None, title: str | None = None):
    """Paths of one walk in local metres (Figs. 5.13-5.21): label -> DataFrame with x_m, y_m."""
    ax = new_axes(ax)
    styles = {"truth": dict(color="0.3", lw=2.5, alpha=0.35), "gps": dict(color="#0072B2", lw=1, marker=".", ms=3),
              "pso": dict(color="#D55E00", lw=1.4), "tar": dict(color="#009E73", lw=1.2, ls="--")}
    for label, df in paths.items():
        kw = styles.get(label.split()[0].lower(), {})
        ax.plot(df["x_m"], df["y_m"], label=label, **kw)
        if label.lower().startswith(("pso", "tar")):
            ax.plot(df["x_m"].iloc[[0, -1]], df["y_m"].iloc[[0, -1]], ls="none", marker="o", ms=4,
                    color=kw.get("color"))
    ax.set_xlabel("East [m]")
    ax.set_ylabel("North [m]")
    ax.set_aspect("equal", adjustable="datalim")
    if title:
        ax.set_title(title)
    ax.legend(loc="best")
    return ax


def compass_filters(log: pd.DataFrame, ax=None):
    """Static compass log raw, MA- and SG-filtered (Figs. 5.3-5.5); columns t_s, raw_deg, ma_deg, sg_deg."""
    ax = new_axes(ax)
    ax.plot(log["t_s"], log["raw_deg"], color="0.6", lw=0.8, label="raw")
    ax.plot(log["t_s"], log["ma_deg"], lw=1.2, label="MA nL=nR=2")
    ax.plot(log["t_s"], log["sg_deg"], lw=1.0, label="SG m=2, nL=nR=2")
    ax.set_xlabel("Time [s]")
    ax.set_ylabel("Compass yaw [deg]")
    ax.legend(loc="best")
    return ax


def k_factors(table: pd.DataFrame, ax=None, columns: dict | None = None):
    """Grouped bars of k per walker (columns: label -> column name)."""
    ax = new_axes(ax)
    cols = columns or {"paper (Table 5-2)": "paper_k", "reproduced (PSO)": "k_pso"}
    x = np.arange(len(table))
    wdt = 0.8 / len(cols)
    for i, (label, c) in enumerate(cols.items()):
        ax.bar(x + (i - (len(cols) - 1) / 2) * wdt, table[c], width=wdt, label=label)
    ax.set_xticks(x, table["walker"])
    ax.set_xlabel("Walker")
    ax.set_ylabel("k [m / (m/s$^2$)$^{1/4}$]")
    ax.legend(loc="best")
    return ax


def phase2_grid(tracks: pd.DataFrame, max_walks: int | None = None, ncols: int = 4):
    """One :func:`walk_paths` panel per walk of a long table (``walk``, ``kind``, ``x_m``, ``y_m``).

    Returns the Figure (it makes its own grid of Axes).
    """
    import matplotlib.pyplot as plt

    walks = list(dict.fromkeys(tracks["walk"]))[:max_walks]
    ncols = min(ncols, len(walks))
    nrows = -(-len(walks) // ncols)
    fig, axs = plt.subplots(nrows, ncols, figsize=(3.8 * ncols, 3.8 * nrows), squeeze=False)
    labels = {"truth": "truth", "gps": "GPS", "pso": "PSO k", "tar": "TAR k=0.5"}
    for ax, w in zip(axs.ravel(), walks, strict=False):
        d = tracks[tracks["walk"] == w]
        walk_paths({lab: d[d["kind"] == kind] for kind, lab in labels.items()}, ax=ax, title=w)
    for ax in axs.ravel()[len(walks):]:
        ax.set_visible(False)
    fig.tight_layout()
    return fig
