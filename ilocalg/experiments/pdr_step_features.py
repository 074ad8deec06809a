"""SAM step features and step counting on simulated walkers (i-Loc thesis sec. 4.1, Table 1, Figs 8-12).

Design, as in the thesis: training walkers of different builds each walk 15 steps at fixed step
lengths of 40, 50, 60, 70 and 80 cm; the features of their true steps give the learned ranges
(the [5 %, 95 %] points of each feature's CDF, Table 1). Then 8 other walkers each walk 100 steps
and SAM, with the learned ranges, counts them (Fig 12; the thesis reports a 4.13 % error).

Beside the simulation, a real-data row: SAM trained and tested on the in-hand optimisation
recordings of the Oxford step counter data set, leave one recording out (ranges = the 5-95 %
points of the other recordings' true steps), with the per-recording errors and, for each, the
range test its true steps fail most and its cadence beside the others' (``oxford``). And the
sample rate, which the thesis does not give and which X1 (eq. 15) scales with, swept
(``rate_sweep``).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1, Table 1, Figs 8-12.
Oxford step counter DataSet (github.com/Oxford-step-counter/DataSet), CC BY 4.0.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.oxford import load_oxford_archive, parse_recording_name
from ilocalg.io.paths import dataset_path
from ilocalg.papers import PAPERS, paper_ref, readings_iloc
from ilocalg.papers.iloc import PUBLISHED
from ilocalg.pdr.sam import (
    SAM_FEATURES,
    SAM_RANGES_PAPER,
    SAM_TESTED_FEATURES,
    in_ranges,
    learn_feature_ranges,
    sam_waves,
)
from ilocalg.pdr.sam_evaluate import sam_leave_one_out
from ilocalg.pdr.signals import acc_from_log
from ilocalg.sim import gait
from ilocalg.units import as_rng

__all__ = ["run", "headline", "oxford_loro", "rate_sweep", "readings", "PAPER"]

OXFORD_ARCHIVE = "optimisation_data.tar.xz"

PAPER = PAPERS["iloc"]

#: The thesis's published values (:data:`ilocalg.papers.iloc.PUBLISHED`): reference only, never used to compute.
PUB = PUBLISHED["pdr_step_features"]


def readings(world: str = "measured") -> pd.DataFrame:
    """The modelling choices of this experiment against the thesis's text (:mod:`ilocalg.papers.readings_iloc`)."""
    code, source = gait.world_reading(world)
    return readings_iloc.readings("pdr_step_features", gait_code=code, gait_source=source)


def _oxford_archive(data_dir=None) -> Path:
    """The in-hand archive: ``data_dir`` is the data root the runner passes (``<root>/oxford_step_counter/``
    holds the archive) or the data set's own folder; None means the default data root."""
    if data_dir is None:
        return dataset_path("oxford_step_counter") / OXFORD_ARCHIVE
    root = Path(data_dir)
    direct = root / OXFORD_ARCHIVE
    return direct if direct.exists() else root / "oxford_step_counter" / OXFORD_ARCHIVE


def oxford_loro(data_dir=None, q_range=(0.05, 0.95), rate_hz: float = 50.0, position: str = "InHand",
                max_recordings: int | None = None, tol_s: float = 0.25) -> pd.DataFrame:
    """SAM on the Oxford step counter recordings held at ``position``, leave one recording out
    (:func:`ilocalg.pdr.sam_evaluate.sam_leave_one_out`; columns ``phone``, ``user``, ``surface`` from the
    recording's name). One row with a ``missing`` column when the data are not on disk."""
    archive = _oxford_archive(data_dir)
    if not archive.exists():
        return pd.DataFrame([{"missing": str(archive)}])
    return sam_leave_one_out(list(_held_recordings(archive, position)[:max_recordings]), q_range, rate_hz, tol_s,
                             parse_recording_name)


#: The recordings :func:`_held_recordings` read last, kept in the process: the seed sweep's and the claims'
#: robustness runs of this experiment share a pool process and would each decompress the whole xz archive (about
#: 3 CPU-s) for the same recordings. Keyed on the archive's path, size and modification time and the position.
_HELD: dict[tuple, tuple] = {}


def _held_recordings(archive: Path, position: str) -> tuple:
    """The archive's recordings held at ``position``, sorted by name (read once per process, :data:`_HELD`)."""
    st = archive.stat()
    key = (str(archive.resolve()), st.st_size, st.st_mtime_ns, position)
    if key not in _HELD:
        def held(name: str) -> bool:
            return parse_recording_name(name).get("position") == position

        _HELD.clear()  # one archive's recordings at a time
        _HELD[key] = tuple(load_oxford_archive(archive, select=held))  # one pass over the archive
    return _HELD[key]


def rate_sweep(seed: int = 0, rates_hz=(25.0, 50.0, 100.0), n_train: int = 8, n_test: int = 8,
               n_steps: int = 100, q_range=(0.05, 0.95), world: str = "measured") -> pd.DataFrame:
    """The sample rate the thesis does not give: X1's learned range and SAM's count error at each rate.

    Same walkers and seed at every rate (only the sensor rate changes); ranges learned at that rate.
    """
    rows = []
    for rate in rates_hz:
        rng = as_rng(seed)
        cfg = gait.gait_config(world, rate_hz=float(rate))
        tw = gait.make_walkers(n_train, rng, world=world)
        nw = gait.make_walkers(n_test, rng, world=world)
        feats = gait.fixed_length_features(gait.training_walks(tw, rng, config=cfg))
        r = learn_feature_ranges(feats, *q_range)
        errs = []
        for sw in gait.count_walks(nw, rng, n_steps, config=cfg):
            acc, t = acc_from_log(sw.imu)
            c = int(in_ranges(sam_waves(acc, t), r, SAM_TESTED_FEATURES).sum())
            errs.append(abs(c - len(sw.steps)) / len(sw.steps))
        rows.append({"rate_hz": float(rate), "X1_min": r.loc["X1", "min"], "X1_max": r.loc["X1", "max"],
                     "X1_paper_min": SAM_RANGES_PAPER.loc["X1", "min"],
                     "X1_paper_max": SAM_RANGES_PAPER.loc["X1", "max"],
                     "count_error_new_walkers": float(np.mean(errs))})
    return pd.DataFrame(rows)


def run(seed: int = 0, fast: bool = False, n_train: int = 8, n_test: int = 8, n_steps: int = 100,
        quantiles=((0.05, 0.95), (0.01, 0.99), (0.0, 1.0)), data_dir=None,
        world: str = "measured") -> dict[str, pd.DataFrame]:
    """Feature ranges beside Table 1 and SAM step-count errors beside Fig 12.

    ``data_dir`` is the folder of the real data sets (the reproduce runner passes it; the Oxford archive is
    under its ``oxford_step_counter/``) or the Oxford data set's own folder; None: the default data root.

    Returns
    -------
    dict of DataFrame
        ``features`` (every training step), ``ranges`` (learned vs Table 1), ``counts`` (per test
        walker and range variant), ``summary`` (mean count error per variant), ``comparison``,
        ``oxford`` (real recordings, leave one out, per recording; :func:`oxford_loro`), ``oxford_summary``,
        ``rate_sweep`` (:func:`rate_sweep`), ``readings``.
    """
    rng = as_rng(seed)
    gcfg = gait.gait_config(world)
    if fast:
        n_train, n_test = min(n_train, 4), min(n_test, 4)
    train_walkers = gait.make_walkers(n_train, rng, world=world)
    test_walkers = [gait.Walker(**{**w.__dict__, "name": f"test{i}"})
                    for i, w in enumerate(gait.make_walkers(n_test, rng, world=world))]
    feats = gait.fixed_length_features(gait.training_walks(train_walkers, rng, config=gcfg))
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
        for sw in gait.count_walks(ws, rng, n_steps, config=gcfg):
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
                              PUB["sam_count_error"] * 100, lit.loc[(group, key)] * 100, unit="%",
                              note="ranges = 5/95 % points of simulated training steps"))
    ox = oxford_loro(data_dir, quantiles[0], max_recordings=6 if fast else None)
    if "error" in ox.columns:
        ox_sum = pd.DataFrame([{"recordings": len(ox), "median_error": float(ox["error"].median()),
                                "mean_error": float(ox["error"].mean()), "max_error": float(ox["error"].max()),
                                "recordings_over_20pct": int((ox["error"] > 0.2).sum())}])
        comp.append(paper_ref(PAPER, "Fig 12", "SAM step-count error, Oxford in-hand recordings (leave one out), mean",
                              PUB["sam_count_error"] * 100, ox["error"].mean() * 100, unit="%",
                              note="real recordings, not the thesis's testers"))
    else:
        ox_sum = ox
    rs = rate_sweep(seed, (25.0, 50.0) if fast else (25.0, 50.0, 100.0), n_train, n_test, n_steps, quantiles[0],
                    world)
    return {"features": feats, "ranges": rtab, "counts": counts, "summary": summary,
            "comparison": pd.DataFrame(comp), "oxford": ox, "oxford_summary": ox_sum, "rate_sweep": rs,
            "readings": readings(world),
            # named scalars for the claims ledger (ilocalg/papers/iloc.py): the Fig 12 count error under a name
            # that does not change with the number of test walkers
            "measures": pd.DataFrame([{"quantity": "SAM step-count error, 5/95 % ranges", "item": g,
                                       "value": float(lit.loc[(g, key)] * 100), "unit": "%"} for g in groups])}


def headline(tables: dict) -> str:
    """One sentence with the measured SAM count errors (for the notebook's conclusion)."""
    s = tables["summary"].set_index(["test_set", "ranges"])["mean_error"]
    return (f"SAM with the thesis's 5/95 % ranges: mean step-count error "
            f"{s.loc[('training walkers', 'learned q0.05-0.95')]:.1%} on the training walkers' new walks, "
            f"{s.loc[('new walkers', 'learned q0.05-0.95')]:.1%} on new walkers; with 0/100 % ranges "
            f"{s.loc[('training walkers', 'learned q0-1')]:.1%} and {s.loc[('new walkers', 'learned q0-1')]:.1%}.")
