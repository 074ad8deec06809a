"""The claims step of reproduce: every paper's claims judged on the reproduced values, and how robust each is.

After the notebooks and the seed sweep, :func:`claims_step` evaluates :func:`ilocalg.papers.all_claims` on
the per-seed long results of the experiments the claims name (:mod:`ilocalg.papers.claims`):

- an experiment the manifest sweeps over seeds contributes its runs at ``seed .. seed + n_seeds - 1``
  (the sweep cache holds them after the seed sweep); any other experiment its run at the base seed,
  which the notebook's kernel recorded into the same cache (:func:`ilocalg.workflow.sweep.record_runs`).
  A run missing from the cache is computed now, through the same sweep machinery;
- each claim gets its statistic's mean and Student-t 95 % interval over seeds, clipped to the statistic's
  physical range (``ci_clipped``), and a verdict (:func:`ilocalg.papers.claims.judge`);
- robustness (:func:`robustness`): for the claims with ``assumptions``, the joint space of each
  experiment's assumptions is sampled with a seeded Latin hypercube (log scale where
  :attr:`~ilocalg.papers.claims.Assumption.log`), the experiment is run at every sample (one
  :class:`~ilocalg.workflow.sweep.SweepTask` each: cached, on Dask) and each sample is judged on its
  own. ``robust_share`` is the share of samples on the side the claim asserts (a direction claim) or
  agreeing with the paper (a value claim); ``most_influential`` is the assumption with the largest
  \\|Spearman rho\\| between its value and the statistic over the samples.

Schedule: the samples are :func:`samples_of` per experiment (:data:`N_SAMPLES`, or fewer where
:data:`N_SAMPLES_OF` declares it for a costly experiment), fast-mode runs at the base seed, one
:class:`~ilocalg.workflow.sweep.SweepTask` each. A reproduce that runs notebooks side by side runs them as jobs
of the same process pool as the notebooks and the seed sweep (:func:`robustness_tasks`), so they fill the cores
while the notebooks run and every claim with assumptions gets its share on a fresh clone; the claims step then
reads them from the cache. Samples not in the cache (a reproduce one notebook at a time, a sample that failed)
run in the step itself within :data:`BUDGET_S` seconds of wall time (:func:`run_samples`): cheapest experiment
first (measured run times, ``.ilocalg-cache/timings.json``, else :data:`ilocalg.workflow.manifest.COST_S`), one
sample is timed and the budget left decides how many the experiment gets (all, a smaller hypercube of at least 3,
or none: the claim's note says which).

Writes ``reports/claims.csv`` (:data:`LEDGER_COLUMNS`) and ``reports/tables/claims.md``. A claim whose
reference does not resolve (no such experiment, quantity or item; several rows where one is meant) stops
the step with an error naming the claim: it never turns silently into "cannot be tested".
"""

from __future__ import annotations

import json
import math
import sys
import zlib
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.papers import claims as cl

__all__ = ["LEDGER_COLUMNS", "N_SAMPLES", "N_SAMPLES_OF", "N_SAMPLES_FAST", "n_samples_for", "BUDGET_S", "ClaimError",
           "claim_experiments",
           "gather_results", "evaluate_ledger", "sample_assumptions", "samples_of", "judged_claims",
           "robustness_tasks", "run_samples", "robustness", "write_ledger", "claims_step"]

#: Columns of reports/claims.csv.
LEDGER_COLUMNS = (*cl.CLAIM_COLUMNS, "n_seeds", "statistic", "expect", "most_influential", "ci_clipped", "note")
#: Latin-hypercube samples per experiment for robustness.
N_SAMPLES = 8
#: Fewer samples for an experiment whose fast-mode run is costly (a Latin hypercube of n points still covers each
#: assumption's range in n equal strata; at least 4, so that Spearman's rho between an assumption and the
#: statistic is defined with a spread). Fixed numbers, not a time budget, so two runs give the same ledger.
#: None today: ins_constraints and ins_online had 4 while their samples ran their side studies (34 and 2.8 CPU-s
#: per fast-mode sample); sweep tasks now leave those out (manifest.SWEEP_KWARGS).
N_SAMPLES_OF: dict[str, int] = {}
#: Samples per experiment when the run itself is a fast-mode one (``reproduce --fast``, the test suite: a check
#: that every piece runs, not a result): the fewest that still give Spearman's rho a spread (see above).
N_SAMPLES_FAST = 4
#: Seconds of wall time the robustness samples may take (the rest of the step reads the cache: a few s).
BUDGET_S = 40.0
#: Fast-mode run time over full-mode run time, when no fast-mode time was measured yet.
FAST_FACTOR = 0.35


class ClaimError(ValueError):
    """A claim that cannot be evaluated as declared (its message names the claim)."""


def claim_experiments(claim: cl.Claim) -> list[str]:
    """Experiments a claim's statistic reads, in order of first mention."""
    out: list[str] = []
    for r in (claim.statistic.refs if claim.statistic is not None else ()):
        if r.experiment not in out:
            out.append(r.experiment)
    return out


def gather_results(experiments: Iterable[str], seed: int, n_seeds: int, swept: Iterable[str], fast: bool,
                   workers: int, cache_dir: Path, progress: bool = False):
    """Per-seed long results of ``experiments`` (seeds ``seed ..`` for the ``swept``, the base seed for the
    others), read from the sweep cache or computed now. Returns the :class:`~ilocalg.workflow.sweep.SweepResult`."""
    from ilocalg.workflow import sweep as sw

    swept = set(swept)
    tasks = [t for e in experiments
             for t in sw.make_tasks(e, range(seed, seed + (n_seeds if e in swept else 1)), fast=fast)]
    return sw.sweep(tasks, workers=workers, cache_dir=cache_dir, progress=progress)


def evaluate_ledger(claims: Sequence[cl.Claim], results: pd.DataFrame, level: float = 0.95) -> pd.DataFrame:
    """The ledger (:data:`LEDGER_COLUMNS`) of ``claims`` on long results.

    Raises
    ------
    ClaimError
        One or more claims whose references do not resolve; the message names every such claim.
    """
    rows, bad = [], []
    index = cl.ResultIndex(results)  # every claim's lookups read one experiment's rows
    for c in claims:
        try:
            rows.append(cl.evaluate(c, index, level))
        except KeyError as exc:
            bad.append(f"claim {c.id} ({c.paper}, line {c.line}): {exc.args[0] if exc.args else exc}")
    if bad:
        raise ClaimError("claims whose reproduced values cannot be found:\n  " + "\n  ".join(bad))
    led = pd.DataFrame(rows)
    if led.empty:
        led = pd.DataFrame(columns=list(LEDGER_COLUMNS))
    led["most_influential"] = ""
    return led[list(LEDGER_COLUMNS)]


def _stable_seed(seed: int, name: str) -> list[int]:
    return [int(seed), zlib.crc32(name.encode())]


def sample_assumptions(assumptions: Sequence[cl.Assumption], n: int, seed: int) -> pd.DataFrame:
    """``n`` Latin-hypercube samples of the joint space of ``assumptions`` (one column per ``param``; log
    scale where ``log``, rounded where ``integer``), seeded by ``seed`` and the experiment's name.

    Raises
    ------
    ValueError
        No assumptions, ``n < 2``, an empty or reversed range, or a log range not above zero.
    """
    from scipy.stats import qmc

    if not assumptions:
        raise ValueError("sample_assumptions needs at least one assumption")
    if n < 2:
        raise ValueError(f"need at least 2 samples, got {n}")
    for a in assumptions:
        if not a.low < a.high:
            raise ValueError(f"assumption {a.experiment}.{a.param}: range [{a.low}, {a.high}] is empty")
        if a.log and a.low <= 0:
            raise ValueError(f"assumption {a.experiment}.{a.param}: log scale needs low > 0, got {a.low}")
    u = qmc.LatinHypercube(d=len(assumptions), seed=np.random.default_rng(
        _stable_seed(seed, assumptions[0].experiment))).random(n)
    cols = {}
    for j, a in enumerate(assumptions):
        if a.log:
            x = np.exp(np.log(a.low) + u[:, j] * (np.log(a.high) - np.log(a.low)))
        else:
            x = a.low + u[:, j] * (a.high - a.low)
        cols[a.param] = np.round(x).astype(int) if a.integer else x
    return pd.DataFrame(cols)


def n_samples_for(fast: bool) -> int:
    """Latin-hypercube samples per experiment of a run: :data:`N_SAMPLES_FAST` in fast mode, else
    :data:`N_SAMPLES` (the samples themselves are fast-mode runs either way)."""
    return N_SAMPLES_FAST if fast else N_SAMPLES


def samples_of(experiment: str, n_samples: int = N_SAMPLES) -> int:
    """Latin-hypercube samples of ``experiment``'s assumptions: :data:`N_SAMPLES_OF`, else ``n_samples``."""
    return min(int(N_SAMPLES_OF.get(experiment, n_samples)), int(n_samples))


def _joint_assumptions(claims: Sequence[cl.Claim]) -> dict[str, list[cl.Assumption]]:
    """experiment -> its assumptions over every claim (the first declaration of a parameter wins)."""
    out: dict[str, list[cl.Assumption]] = {}
    for c in claims:
        for a in c.assumptions:
            lst = out.setdefault(a.experiment, [])
            if all(b.param != a.param for b in lst):
                lst.append(a)
    return out


def judged_claims(claims: Sequence[cl.Claim], stems: Sequence[str],
                  manifest: Mapping[str, Mapping[str, bool]]) -> list[cl.Claim]:
    """The claims a run of the notebooks ``stems`` judges: those whose experiments all run in it (or are a
    user's own dotted module)."""
    in_run = {e for s in stems for e in manifest.get(s, {})}
    return [c for c in claims if all(e in in_run or "." in e for e in claim_experiments(c))]


def robustness_tasks(stems: Sequence[str], seed: int = 0, manifest: Mapping[str, Mapping[str, bool]] | None = None,
                     claims: Sequence[cl.Claim] | None = None, n_samples: int = N_SAMPLES) -> list:
    """Every robustness sample the claims step of a run of ``stems`` reads, as sweep tasks (fast mode, base
    seed), cheapest experiment first: the reproduce runner runs them in its process pool beside the notebooks,
    so that the claims step finds them all in the cache (the same samples :func:`run_samples` draws)."""
    from ilocalg.papers import all_claims
    from ilocalg.workflow.manifest import MANIFEST

    manifest = MANIFEST if manifest is None else manifest
    claims = list(all_claims() if claims is None else claims)
    judged = [c for c in judged_claims(claims, stems, manifest) if c.assumptions and c.statistic is not None]
    joint = _joint_assumptions(judged)
    tasks = [t for e in sorted(joint) for t in _tasks(e, sample_assumptions(joint[e], samples_of(e, n_samples),
                                                                             seed), seed)]
    return list({t.key: t for t in tasks}.values())  # integer assumptions may round two samples alike


def _cost(timings: Mapping[str, float], experiment: str, fast: bool) -> float:
    """Estimated seconds of one run of ``experiment``: its measured sweep run (the fast one in fast mode, else
    the full one scaled by :data:`FAST_FACTOR`), else its notebook's time (an upper bound), else 60 s."""
    from ilocalg.workflow.manifest import MANIFEST

    factor = FAST_FACTOR if fast else 1.0
    if fast and timings.get(f"sweep:{experiment} (fast)"):
        return float(timings[f"sweep:{experiment} (fast)"])
    if timings.get(f"sweep:{experiment}"):
        return float(timings[f"sweep:{experiment}"]) * factor
    nb = next((s for s, exps in MANIFEST.items() if experiment in exps), None)
    if nb and fast and timings.get(f"{nb} (fast)"):
        return float(timings[f"{nb} (fast)"])
    if nb and timings.get(nb):
        return float(timings[nb]) * factor
    return 60.0 * factor


def _tasks(e: str, samples: pd.DataFrame, seed: int) -> list:
    from ilocalg.workflow import sweep as sw

    # side studies no claim reads are left out by sweep.run_task (manifest.SWEEP_KWARGS)
    return [sw.SweepTask(e, tuple(sorted({k: v.item() if hasattr(v, "item") else v for k, v in rec.items()}.items())),
                         int(seed), True)
            for rec in samples.to_dict("records")]


def run_samples(joint: Mapping[str, Sequence[cl.Assumption]], seed: int, workers: int, cache_dir: Path | None,
                n_samples: int = N_SAMPLES, budget_s: float = BUDGET_S, timings: Mapping[str, float] | None = None,
                progress: bool = False, clock=None) -> tuple[dict[str, pd.DataFrame], pd.DataFrame, dict[str, str]]:
    """Run the Latin-hypercube samples of each experiment (fast mode, base seed) within ``budget_s`` seconds
    of wall time, cheapest experiment first (:func:`_cost`).

    Per experiment, one sample runs first and is timed; the rest of the budget (as if one run at a time:
    ``workers`` only run them side by side) then decides how many samples it gets: all :data:`N_SAMPLES`,
    a smaller Latin hypercube (at least 3), or none. Cached samples cost nothing, so a second reproduce
    samples everything that fits once.
    Returns (samples per experiment, their long results, a note per experiment that got fewer or none).
    """
    import time

    from ilocalg.workflow import sweep as sw

    clock = time.perf_counter if clock is None else clock
    timings = {} if timings is None else timings
    t0 = clock()
    used: dict[str, pd.DataFrame] = {}
    frames, notes = [], {}
    for e in sorted(joint, key=lambda e: (_cost(timings, e, True), e)):
        left = budget_s - (clock() - t0)
        n_e = samples_of(e, n_samples)
        full = sample_assumptions(joint[e], n_e, seed)
        if cache_dir is not None and all(sw._cache_path(cache_dir, t).exists() for t in _tasks(e, full, seed)):
            res = sw.sweep(_tasks(e, full, seed), workers=0, cache_dir=cache_dir, progress=False)  # run beforehand
            frames += [res.results] if not res.results.empty else []
            used[e] = full
            continue
        if left <= 0:
            notes[e] = f"robustness not sampled: the step's {budget_s:.0f} s budget was spent"
            continue
        t1 = clock()
        first = sw.sweep(_tasks(e, full.iloc[:1], seed), workers=0, cache_dir=cache_dir, progress=False)
        one = max(clock() - t1, 1e-3)
        left = budget_s - (clock() - t0)
        # no parallel speed-up is assumed: on a shared machine the workers' runs slow each other down
        fit = n_e if not math.isfinite(left) else 1 + int(max(left, 0.0) // one)
        n = min(n_e, fit)
        if n < 3:
            notes[e] = (f"robustness not sampled: one run of {e} took {one:.0f} s, beyond the step's "
                        f"{budget_s:.0f} s budget")
            continue
        chosen = full if n == n_e else sample_assumptions(joint[e], n, seed)
        if n < n_e:
            notes[e] = f"{n} samples, not {n_e}, within the step's {budget_s:.0f} s budget"
        todo = _tasks(e, chosen, seed) if n < n_e else _tasks(e, full.iloc[1:], seed)
        res = sw.sweep(todo, workers=workers if len(todo) > 1 else 0, cache_dir=cache_dir, progress=progress)
        parts = [res.results] + ([first.results] if n == n_e else [])
        frames += [f for f in parts if not f.empty]
        used[e] = chosen
    results = pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
    return used, results, notes


def robustness(claims: Sequence[cl.Claim], base: pd.DataFrame, seed: int, fast: bool, workers: int,
               cache_dir: Path | None, n_samples: int = N_SAMPLES, budget_s: float = BUDGET_S,
               timings: Mapping[str, float] | None = None, progress: bool = False) -> pd.DataFrame:
    """``robust_share``, ``most_influential``, ``n_samples`` and a ``note`` per claim with assumptions.

    ``base`` are the long results at default parameters (the references a claim's statistic reads in
    other experiments than the sampled one come from there, at the base seed).
    """
    claims = [c for c in claims if c.assumptions and c.statistic is not None]
    cols = ["claim_id", "robust_share", "most_influential", "n_samples", "note"]
    if not claims:
        return pd.DataFrame(columns=cols)
    joint = _joint_assumptions(claims)
    samples, results, notes = run_samples(joint, seed, workers, cache_dir, n_samples, budget_s, timings, progress)
    by_task = {}
    if not results.empty:
        for (e, p), g in results.groupby(["experiment", "params"], sort=False):
            # integer assumptions can round two samples to the same parameters: one task's rows each
            by_task[(e, p)] = g.drop_duplicates(subset=["seed", "table", "item", "quantity"])
    base0 = base[base["seed"] == seed] if "seed" in base.columns else base
    base_index = cl.ResultIndex(base0)  # split once; each sample then replaces its own experiment's rows
    out = []
    for c in claims:
        e = c.assumptions[0].experiment
        if e not in samples:
            out.append({"claim_id": c.id, "robust_share": math.nan, "most_influential": "", "n_samples": 0,
                        "note": notes.get(e, "robustness not sampled")})
            continue
        own = [a.param for a in c.assumptions if a.experiment == e]
        stats, xs = [], []
        for rec in samples[e].to_dict("records"):
            params = json.dumps({k: (v.item() if hasattr(v, "item") else v) for k, v in rec.items()},
                                sort_keys=True, default=str)
            g = by_task.get((e, params))
            if g is None:
                continue
            # the base results of the other experiments with this sample's rows as experiment e's
            frame = base_index.replace(e, g.assign(params="{}"))
            try:
                v = cl.statistic_by_seed(c.statistic, frame)
            except KeyError as exc:
                raise ClaimError(f"claim {c.id}: at assumption sample {params}: {exc.args[0]}") from None
            if len(v) and math.isfinite(float(v.iloc[0])):
                stats.append(float(v.iloc[0]))
                xs.append([rec[p] for p in own])
        n = len(stats)
        if n == 0:
            out.append({"claim_id": c.id, "robust_share": math.nan, "most_influential": "", "n_samples": 0,
                        "note": f"robustness: every sample of {e} failed or gave no value"})
            continue
        share = float(np.mean([cl.judge(c, v, v, v) == "reproduced" for v in stats]))
        infl = _most_influential(own, np.asarray(xs, dtype=np.float64), np.asarray(stats))
        extra = [a.experiment for a in c.assumptions if a.experiment != e]
        note = f"robustness: {n} Latin-hypercube samples of {', '.join(own)} (fast-mode runs)" + (
            f"; {notes[e]}" if e in notes else "")
        if extra:
            note += f"; assumptions of {sorted(set(extra))} not sampled jointly"
        out.append({"claim_id": c.id, "robust_share": share, "most_influential": infl, "n_samples": n,
                    "note": note})
    return pd.DataFrame(out, columns=cols)


def _most_influential(params: Sequence[str], x: np.ndarray, y: np.ndarray) -> str:
    """The parameter with the largest |Spearman rho| against ``y`` (``""`` when none is defined)."""
    from scipy.stats import spearmanr

    best, best_r = "", -1.0
    if len(y) < 3 or np.ptp(y) == 0:
        return ""
    for j, p in enumerate(params):
        if np.ptp(x[:, j]) == 0:
            continue
        r = spearmanr(x[:, j], y).statistic
        if np.isfinite(r) and abs(r) > best_r:
            best, best_r = p, abs(float(r))
    return f"{best} (rho {best_r:.2f})" if best else ""


def _fmt(v) -> str:
    if isinstance(v, (float, np.floating)):
        return "" if not math.isfinite(v) else f"{v:.4g}"
    return str(v).replace("|", "\\|").replace("\n", " ")


def write_ledger(ledger: pd.DataFrame, out_dir: str | Path) -> Path:
    """Write ``<out_dir>/claims.csv`` and ``<out_dir>/tables/claims.md`` (one section per paper)."""
    from ilocalg.papers import PAPERS

    out_dir = Path(out_dir)
    (out_dir / "tables").mkdir(parents=True, exist_ok=True)
    path = out_dir / "claims.csv"
    ledger.to_csv(path, index=False, float_format="%.10g", lineterminator="\n")
    cols = ["claim_id", "claim", "paper_value", "reproduced", "ci_low", "ci_high", "verdict", "robust_share",
            "most_influential", "note"]
    lines = ["# Claims ledger", "", "Written by the claims step of `python -m ilocalg reproduce` (columns: see "
             "`claims.csv`). Verdicts over the seeds of the run; robustness over "
             f"{N_SAMPLES} Latin-hypercube samples of each experiment's assumptions"
             + (f" (fewer for a costly experiment: {', '.join(f'{e} {n}' for e, n in sorted(N_SAMPLES_OF.items()))})"
                if N_SAMPLES_OF else "")
             + "; fast-mode runs at the base seed; a claim's note says when fewer were run.", ""]
    for key, name in PAPERS.items():
        part = ledger[ledger["paper"] == key]
        if part.empty:
            continue
        lines += [f"## {name}", "", "| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
        for rec in part[cols].to_dict("records"):
            lines.append("| " + " | ".join(_fmt(rec[c]) for c in cols) + " |")
        lines.append("")
    (out_dir / "tables" / "claims.md").write_text("\n".join(lines))
    return path


def _load_timings(cache_dir: Path) -> dict:
    from ilocalg.workflow.manifest import COST_S

    try:
        return {**COST_S, **json.loads((Path(cache_dir).parent / "timings.json").read_text())}
    except (OSError, ValueError):
        return dict(COST_S)


def claims_step(out_dir: str | Path, stems: Sequence[str], seed: int = 0, n_seeds: int = 1, fast: bool = False,
                workers: int = 2, cache_dir: str | Path | None = None, progress: bool = False,
                manifest: Mapping[str, Mapping[str, bool]] | None = None, claims: Sequence[cl.Claim] | None = None,
                n_samples: int | None = None, budget_s: float = BUDGET_S) -> int:
    """Evaluate the claims on this run and write the ledger; returns a process exit code (0 on success).

    Only claims whose experiments all belong to the notebooks ``stems`` are judged (a run of a few
    notebooks judges their claims; the rest wait for a full run); claims without references always are.
    A claim naming an experiment that no notebook of the manifest runs is an error, as is one whose
    reference does not resolve (the message names the claim). ``n_samples``: robustness samples per experiment
    (default :func:`n_samples_for` ``fast``).
    """
    from ilocalg.papers import all_claims
    from ilocalg.workflow import sweep as sw
    from ilocalg.workflow.manifest import MANIFEST

    manifest = MANIFEST if manifest is None else manifest
    n_samples = n_samples_for(fast) if n_samples is None else n_samples
    if not manifest:  # notebooks outside the project (no manifest): no experiment is known to have run
        return 0
    claims = list(all_claims() if claims is None else claims)
    cache_dir = Path(cache_dir) if cache_dir is not None else sw.DEFAULT_CACHE
    # a claim must name an experiment of the project (a typo in a claims module is an error); with a manifest
    # of one's own notebooks, the project's claims whose experiments it does not run are simply not judged
    known = {e for exps in MANIFEST.values() for e in exps} | {e for exps in manifest.values() for e in exps}
    swept = {e for s in stems for e, on in manifest.get(s, {}).items() if on}
    orphans = [f"claim {c.id}: experiment {e!r} is run by no notebook of the manifest"
               for c in claims for e in claim_experiments(c) if e not in known and "." not in e]
    if orphans:
        print("FAILED claims step:\n  " + "\n  ".join(orphans), file=sys.stderr, flush=True)
        return 1
    judged = judged_claims(claims, stems, manifest)
    exps = list(dict.fromkeys(e for c in judged for e in claim_experiments(c)))
    try:
        if exps:
            res = gather_results(exps, seed, n_seeds, swept, fast, workers, cache_dir, progress)
            for f in res.failures:
                print(f"FAILED {f['task']}: {f['error']}", file=sys.stderr, flush=True)
            if res.failures:
                return 1
            results = res.results
        else:
            results = pd.DataFrame(columns=["experiment", "params", "seed", *cl.RESULT_COLUMNS])
        ledger = evaluate_ledger(judged, results)
        rob = robustness(judged, results, seed, fast, workers, cache_dir, n_samples, budget_s,
                         _load_timings(cache_dir), progress)
    except ClaimError as exc:
        print(f"FAILED claims step: {exc}", file=sys.stderr, flush=True)
        return 1
    if not rob.empty:
        r = rob.set_index("claim_id")
        ids = ledger["claim_id"]
        ledger["robust_share"] = [r["robust_share"].get(i, math.nan) for i in ids]
        ledger["most_influential"] = [r["most_influential"].get(i, "") for i in ids]
        ledger["note"] = [";  ".join(x for x in (n, r["note"].get(i, "")) if x)
                          for i, n in zip(ids, ledger["note"], strict=True)]
    write_ledger(ledger, out_dir)
    counts = ledger["verdict"].value_counts()
    left = len(claims) - len(judged)
    print(f"claims: {len(ledger)} judged (" + ", ".join(f"{int(counts.get(v, 0))} {v}" for v in cl.VERDICTS)
          + f"){f'; {left} wait for notebooks not run now' if left else ''}", flush=True)
    return 0
