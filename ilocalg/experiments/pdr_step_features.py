"""SAM step features and step counting on simulated walkers (i-Loc thesis sec. 4.1, Table 1, Figs 8-12).

Design, as in the thesis: training walkers of different builds each walk 15 steps at fixed step
lengths of 40, 50, 60, 70 and 80 cm; the features of their true steps give the learned ranges
(the [5 %, 95 %] points of each feature's CDF, Table 1). Then 8 other walkers each walk 100 steps
and SAM, with the learned ranges, counts them (Fig 12; the thesis reports a 4.13 % error).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1, Table 1, Figs 8-12.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers import paper_ref
from ilocalg.pdr.sam import (
    SAM_FEATURES,
    SAM_RANGES_PAPER,
    SAM_TESTED_FEATURES,
    in_ranges,
    learn_feature_ranges,
    sam_waves,
)
from ilocalg.pdr.signals import acc_from_log
from ilocalg.sim import gait
from ilocalg.units import as_rng

__all__ = ["run", "headline", "PAPER"]

PAPER = "i-Loc thesis"

# Settings from the paper
# -----------------------
# SAM_COUNT_ERROR_PAPER: Chiu (2013) Fig 12 and sec. 4.1 text, SAM step-count error on 8 walkers
# x 100 steps (a reference value, never used to compute).
SAM_COUNT_ERROR_PAPER = 0.0413


def run(seed: int = 0, fast: bool = False, n_train: int = 8, n_test: int = 8, n_steps: int = 100,
        quantiles=((0.05, 0.95), (0.01, 0.99), (0.0, 1.0))) -> dict[str, pd.DataFrame]:
    """Feature ranges beside Table 1 and SAM step-count errors beside Fig 12.

    Returns
    -------
    dict of DataFrame
        ``features`` (every training step), ``ranges`` (learned vs Table 1), ``counts`` (per test
        walker and range variant), ``summary`` (mean count error per variant), ``comparison``.
    """
    rng = as_rng(seed)
    if fast:
        n_train, n_test = min(n_train, 4), min(n_test, 4)
    train_walkers = gait.make_walkers(n_train, rng)
    test_walkers = [gait.Walker(**{**w.__dict__, "name": f"test{i}"})
                    for i, w in enumerate(gait.make_walkers(n_test, rng))]
    feats = gait.fixed_length_features(gait.training_walks(train_walkers, rng))
    ranges = {q: learn_feature_ranges(feats, *q) for q in quantiles}
    paper_q = quantiles[0]
    rtab = ranges[paper_q].rename(columns={"min": "learned_min", "max": "learned_max"})
    rtab = rtab.join(SAM_RANGES_PAPER.rename(columns={"min": "paper_min", "max": "paper_max"}))
    rtab = rtab.reset_index()

    variants = {f"learned q{lo:g}-{hi:g}": r for (lo, hi), r in ranges.items()}
    variants["thesis Table 1 ranges"] = SAM_RANGES_PAPER
    # beyond the paper: the 5/95 % ranges with a vote (at least 6 of the 7 tests pass)
    vote = f"learned q{paper_q[0]:g}-{paper_q[1]:g}, 6 of 7 tests"
    rows = []
    # the thesis does not say whether its 8 testers were the walkers the ranges were learned from:
    # count both the training walkers' new walks and new walkers' walks
    groups = {"training walkers": train_walkers[:n_test], "new walkers": test_walkers}
    tests = [(name, r, None) for name, r in variants.items()] + [(vote, ranges[paper_q], 6)]
    for group, ws in groups.items():
        for sw in gait.count_walks(ws, rng, n_steps):
            acc, t = acc_from_log(sw.imu)
            waves = sam_waves(acc, t)
            for name, r, k in tests:
                c = int(in_ranges(waves, r, SAM_TESTED_FEATURES, k).sum())
                rows.append({"test_set": group, "walker": sw.walker.name, "ranges": name,
                             "true_steps": len(sw.steps), "counted": c,
                             "error": abs(c - len(sw.steps)) / len(sw.steps)})
    counts = pd.DataFrame(rows)
    summary = counts.groupby(["test_set", "ranges"], sort=False).agg(
        mean_error=("error", "mean"), max_error=("error", "max"), mean_counted=("counted", "mean")).reset_index()
    comp = []
    for f in SAM_FEATURES:
        for k in ("min", "max"):
            comp.append(paper_ref(PAPER, "Table 1", f"{f} {k} (5/95 % point)", SAM_RANGES_PAPER.loc[f, k],
                                  ranges[paper_q].loc[f, k], unit="s" if f.startswith("T") else "m/s^2"))
    lit = summary.set_index(["test_set", "ranges"])["mean_error"]
    key = f"learned q{paper_q[0]:g}-{paper_q[1]:g}"
    for group in groups:
        comp.append(paper_ref(PAPER, "Fig 12", f"SAM step-count error, {n_test} x {n_steps} steps ({group})",
                              SAM_COUNT_ERROR_PAPER * 100, lit.loc[(group, key)] * 100, unit="%",
                              note="ranges = 5/95 % points of simulated training steps"))
    return {"features": feats, "ranges": rtab, "counts": counts, "summary": summary,
            "comparison": pd.DataFrame(comp)}


def headline(tables: dict) -> str:
    """One sentence with the measured SAM count errors (for the notebook's conclusion)."""
    s = tables["summary"].set_index(["test_set", "ranges"])["mean_error"]
    return (f"SAM with the thesis's 5/95 % ranges: mean step-count error "
            f"{s.loc[('training walkers', 'learned q0.05-0.95')]:.1%} on the training walkers' new walks, "
            f"{s.loc[('new walkers', 'learned q0.05-0.95')]:.1%} on new walkers; with 0/100 % ranges "
            f"{s.loc[('training walkers', 'learned q0-1')]:.1%} and {s.loc[('new walkers', 'learned q0-1')]:.1%}.")
