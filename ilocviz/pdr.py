"""Plots for pedestrian dead reckoning: feature CDFs, waves, step-length boxes, headings, accuracies."""

from __future__ import annotations

import numpy as np

from ilocviz.core import new_axes

__all__ = ["step_detections", "feature_cdfs", "wave", "length_boxes", "step_headings", "accuracy_bars",
           "free_walk_distances", "paired_accuracy"]


def feature_cdfs(features, names, ranges=None, ax=None, unit: str = ""):
    """Empirical CDFs of SAM features (thesis Figs 8-11) with the learned [min, max] ranges dashed.

    Parameters
    ----------
    features : DataFrame
        One row per step, a column per feature.
    names : list of str
        Features to draw on this Axes (same unit).
    ranges : DataFrame, optional
        Indexed by feature with ``min`` and ``max``.
    """
    ax = new_axes(ax)
    for n in names:
        x = np.sort(features[n].to_numpy(dtype=float))
        line, = ax.step(x, np.arange(1, x.size + 1) / x.size, where="post", label=n)
        if ranges is not None and n in ranges.index:
            for v in ranges.loc[n, ["min", "max"]]:
                ax.axvline(v, color=line.get_color(), ls="--", lw=0.8)
    ax.set_xlabel(f"Feature value [{unit}]" if unit else "Feature value")
    ax.set_ylabel("Cumulative probability [-]")
    ax.set_ylim(0, 1.02)
    ax.legend(loc="lower right")
    return ax


def wave(t_s, a_perp_mps2, steps=None, ax=None):
    """Vertical acceleration with the detected peaks and valleys (thesis Fig 7)."""
    ax = new_axes(ax)
    t, a = np.asarray(t_s), np.asarray(a_perp_mps2)
    ax.plot(t, a, lw=1.0, label="a_perp")
    if steps is not None and len(steps):
        ax.plot(t[steps["i_peak"]], a[steps["i_peak"]], "v", label="peak P^m")
        if "i_left" in steps:
            ax.plot(t[steps["i_left"]], a[steps["i_left"]], "^", ms=4, label="left valley P^l")
            ax.plot(t[steps["i_right"]], a[steps["i_right"]], "^", ms=4, label="right valley P^r")
    ax.set_xlabel("Time [s]")
    ax.set_ylabel("Vertical acceleration a_perp [m/s^2]")
    ax.legend(loc="upper right")
    return ax


def length_boxes(fixed, column: str = "SLM quadratic", ax=None):
    """Estimated step length boxes per true fixed length (thesis Fig 14), in centimetres."""
    ax = new_axes(ax)
    targets = sorted(fixed["target_m"].unique())
    data = [fixed.loc[fixed["target_m"] == L, column].to_numpy() * 100 for L in targets]
    pos = [L * 100 for L in targets]
    ax.boxplot(data, positions=pos, widths=4.0, whis=(0, 100))
    ax.plot([pos[0] - 5, pos[-1] + 5], [pos[0] - 5, pos[-1] + 5], "k:", lw=0.8, label="estimate = truth")
    ax.set_xlim(pos[0] - 8, pos[-1] + 8)
    ax.set_xlabel("True step length [cm]")
    ax.set_ylabel(f"Estimated step length ({column}) [cm]")
    ax.legend(loc="upper left")
    return ax


def free_walk_distances(free, columns, true_m: float = 20.0, ax=None):
    """Estimated distance of each free walk per model (thesis Fig 15)."""
    ax = new_axes(ax)
    x = np.arange(len(free))
    w = 0.8 / max(len(columns), 1)
    for k, c in enumerate(columns):
        ax.bar(x + k * w - 0.4 + w / 2, free[c].to_numpy(), width=w, label=c)
    ax.axhline(true_m, color="k", ls="--", lw=0.8, label="true distance")
    ax.set_xticks(x, [str(v) for v in free["walker"]], rotation=45, ha="right")
    ax.set_ylabel("Estimated distance [m]")
    ax.legend(loc="lower right", fontsize=8)
    return ax


def step_headings(steps, ax=None):
    """True and estimated heading per step (thesis Fig 16); ``steps`` has ``true_deg``, ``est_deg``."""
    ax = new_axes(ax)
    k = np.arange(len(steps))
    ax.plot(k, np.unwrap(np.deg2rad(steps["true_deg"].to_numpy())) * 180 / np.pi, "-", label="true")
    ax.plot(k, np.unwrap(np.deg2rad(steps["est_deg"].to_numpy())) * 180 / np.pi, "--", label="estimated")
    ax.set_xlabel("Step [-]")
    ax.set_ylabel("Heading from east, counter-clockwise [deg]")
    ax.legend(loc="best")
    return ax


def accuracy_bars(summary, ax=None, goal: float | None = None):
    """Mean and minimum step-count accuracy per detector (percent)."""
    ax = new_axes(ax)
    x = np.arange(len(summary))
    ax.bar(x - 0.2, summary["mean_accuracy"] * 100, width=0.4, label="mean")
    ax.bar(x + 0.2, summary["min_accuracy"] * 100, width=0.4, label="worst recording")
    if goal is not None:
        ax.axhline(goal * 100, color="k", ls="--", lw=0.8, label=f"goal {goal * 100:g} %")
    ax.set_xticks(x, list(summary["detector"]))
    ax.set_ylabel("Step-count accuracy [%]")
    ax.set_ylim(max(0.0, float(summary["min_accuracy"].min()) * 100 - 5), 100.5)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)  # beside the bars, not over them
    return ax


def paired_accuracy(base, others: dict, ax=None, base_label: str = "as logged", goal: float | None = None):
    """Per recording, step-count accuracy (fractions, drawn in percent) of other versions of each log (``others``:
    ``{label: accuracies}``, one marker each) against ``base``, with the line of no change and the goal's floor."""
    ax = new_axes(ax)
    b = np.asarray(base, dtype=float) * 100
    lo = min([b.min()] + [float(np.min(v)) * 100 for v in others.values()]) - 0.5
    for (label, v), marker in zip(others.items(), ("o", "x", "s", "^"), strict=False):
        ax.scatter(b, np.asarray(v, dtype=float) * 100, marker=marker, alpha=0.7, label=label)
    ax.plot([lo, 100.2], [lo, 100.2], color="0.6", lw=0.8, ls="--", label="no change")
    if goal is not None:
        ax.axhline(goal * 100, color="k", lw=0.8, ls=":", label=f"goal floor {goal * 100:g} %")
        ax.axvline(goal * 100, color="k", lw=0.8, ls=":")
    ax.set(xlim=(lo, 100.2), ylim=(lo, 100.2), xlabel=f"accuracy, {base_label} [%]",
           ylabel="accuracy, decimated [%]")
    ax.set_aspect("equal")
    ax.legend(loc="lower right")
    return ax


def step_detections(t_s, signal_mps2, true_t_s, det_t_s, true_matched=None, det_matched=None, ax=None,
                    label: str = "low-passed |a|"):
    """A step signal with true and detected steps; unmatched ones (missed / extra) marked apart.

    Parameters
    ----------
    t_s, signal_mps2 : array_like (n,)
        Time (s) and the detector's signal (m/s^2).
    true_t_s, det_t_s : array_like
        True and detected step times (s).
    true_matched, det_matched : array_like of bool, optional
        :func:`ilocalg.pdr.robust.match_steps` output; unmatched true steps are drawn as "missed",
        unmatched detections as "extra".
    """
    ax = new_axes(ax)
    t, y = np.asarray(t_s, dtype=float), np.asarray(signal_mps2, dtype=float)
    ax.plot(t, y, lw=0.9, color="0.3", label=label)
    tt, td = np.asarray(true_t_s, dtype=float), np.asarray(det_t_s, dtype=float)
    yt, yd = np.interp(tt, t, y), np.interp(td, t, y)
    tmk = np.ones(tt.size, bool) if true_matched is None else np.asarray(true_matched, bool)
    dmk = np.ones(td.size, bool) if det_matched is None else np.asarray(det_matched, bool)
    ax.plot(td[dmk], yd[dmk], "v", color="C0", ms=6, label="detected")
    ax.plot(tt[tmk], yt[tmk] - 0.3, "^", color="C2", ms=5, label="true (heel sensor)")
    if (~tmk).any():
        ax.plot(tt[~tmk], yt[~tmk] - 0.3, "X", color="C3", ms=9, label=f"missed ({int((~tmk).sum())})")
    if (~dmk).any():
        ax.plot(td[~dmk], yd[~dmk], "o", mfc="none", color="C1", ms=10, mew=1.5, label=f"extra ({int((~dmk).sum())})")
    ax.set_xlabel("Time [s]")
    ax.set_ylabel("Acceleration magnitude [m/s^2]")
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.35 * (hi - lo))  # headroom: the legend sits above the signal, not on it
    ax.legend(loc="upper right", fontsize="small", ncol=3)
    return ax
