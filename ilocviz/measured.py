"""Plots of measured vs simulated world statistics (notebook 16_measured_worlds)."""

from __future__ import annotations

import numpy as np

from ilocviz.core import new_axes

__all__ = ["distribution_hist", "real_vs_sim_intervals", "LABELS"]

#: axis label (with unit) of each distribution quantity
LABELS = {
    "shadow_residual_db": "Residual about the per-AP path-loss fit [dB]",
    "reading_age_s": "Age of an RSSI reading at its scan's timestamp [s]",
    "misalignment_deg": "WDM heading minus walking direction per segment [deg]",
    "step_T_rel": "Step period / walk median [-]",
    "step_A_rel": "Step amplitude / walk median [-]",
}


def distribution_hist(dist, quantity: str, ax=None, bins: int = 40, clip_quantiles=(0.005, 0.995)):
    """Normalised histograms of one quantity, one outline per source (real and each simulated world).

    Parameters
    ----------
    dist : DataFrame
        Long table ``quantity, source, value`` (``run()["distributions"]`` of
        :mod:`ilocalg.experiments.measured_worlds`).
    """
    ax = new_axes(ax)
    d = dist[dist["quantity"] == quantity]
    if d.empty:
        ax.text(0.5, 0.5, f"no samples of {quantity}", ha="center", va="center", transform=ax.transAxes)
        return ax
    lo, hi = np.nanquantile(d["value"], clip_quantiles)
    edges = np.linspace(lo, hi, bins + 1)
    for src, g in d.groupby("source", sort=True):
        v = g["value"].to_numpy(dtype=float)
        v = v[np.isfinite(v)]
        ax.hist(np.clip(v, lo, hi), bins=edges, density=True, histtype="step", lw=1.6,
                ls="-" if src.startswith("real") else "--", label=f"{src} (n={v.size})")
    ax.set_xlabel(LABELS.get(quantity, quantity))
    ax.set_ylabel("Density [1/unit]")
    ax.legend(fontsize="small")
    return ax


def real_vs_sim_intervals(comp, worlds=("sim_measured", "sim_assumed"), ax=None):
    """Each compared statistic as simulated / real ratio with its interval, one marker per world.

    The ratio keeps signs: 1 is equal for a negative statistic too (a detection floor in dBm), and a negative
    ratio means the simulated statistic has the opposite sign (a correlation).
    """
    ax = new_axes(ax)
    y = np.arange(len(comp))
    real = comp["real"].to_numpy(dtype=float)
    scale = np.where(np.abs(real) > 1e-9, real, 1.0)
    ax.axvline(1.0, color="k", lw=0.8)
    for i, w in enumerate(worlds):
        if w not in comp:
            continue
        v = comp[w].to_numpy(dtype=float) / scale
        a = comp[f"{w}_ci_low"].to_numpy(dtype=float) / scale
        b = comp[f"{w}_ci_high"].to_numpy(dtype=float) / scale
        lo, hi = np.minimum(a, b), np.maximum(a, b)  # dividing by a negative statistic swaps the ends
        off = (i - 0.5) * 0.25
        ax.errorbar(v, y + off, xerr=[np.abs(v - lo), np.abs(hi - v)], fmt="o", ms=4, capsize=2, label=w)
    a = comp["real_ci_low"].to_numpy(dtype=float) / scale
    b = comp["real_ci_high"].to_numpy(dtype=float) / scale
    rl, rh = np.minimum(a, b), np.maximum(a, b)
    ax.barh(y, rh - rl, left=rl, height=0.6, color="0.85", zorder=0, label="real 95 % interval")
    ax.set_yticks(y)
    ax.set_yticklabels(comp["parameter"])
    ax.set_xlabel("Simulated / real value [-] (1 = equal; below 0 = opposite sign)")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside: no row hidden
    return ax
