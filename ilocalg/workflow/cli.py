"""Command line: ``python -m ilocalg {reproduce,evaluate,sweep,measure,notebooks} ...``."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from ilocalg import __version__

__all__ = ["main", "build_parser"]


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, Path):
        return str(obj)
    return obj


def build_parser() -> argparse.ArgumentParser:
    from ilocalg.workflow.commands import evaluators

    p = argparse.ArgumentParser(prog="python -m ilocalg",
                                description="iLoc toolkit: reproduce smartphone indoor positioning papers.")
    p.add_argument("--version", action="version", version=f"ilocalg {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    r = sub.add_parser("reproduce", help="run every notebook and write reports/")
    r.add_argument("--fast", action="store_true", help="shrink the data (FAST=True) for a quick check")
    r.add_argument("--only", metavar="PATTERN", help="notebooks whose name matches (glob or substring, comma list)")
    r.add_argument("--seed", type=int, default=0, help="simulation seed (default 0)")
    r.add_argument("--seeds", type=int, default=1, metavar="N",
                   help="re-run the experiments over N seeds for 95%% confidence intervals (default 1: none)")
    r.add_argument("--jobs", type=int, default=2,
                   help="notebooks (and seed-sweep runs) executed side by side (default 2; 1: one after another)")
    r.add_argument("--workers", type=int, default=2,
                   help="Dask worker processes for sweep runs left after the notebooks (default 2)")
    r.add_argument("--out", default=None, help="output folder (default: reports/ in the repository)")
    r.add_argument("--no-html", action="store_true", help="skip the HTML export")

    ev = sub.add_parser("evaluate", help="score a method on data and print JSON")
    evsub = ev.add_subparsers(dest="what", required=True, metavar="WHAT")
    for name, mod in evaluators().items():
        sp = evsub.add_parser(name, help=mod.HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
        mod.add_arguments(sp)
        sp.add_argument("--json", action="store_true",
                        help="print one JSON object" + (" instead of the table" if hasattr(mod, "format_text")
                                                        else " (the default output)"))
        sp.set_defaults(_evaluator=mod)

    sw = sub.add_parser("sweep", help="run an experiment across seeds and parameter values on Dask")
    sw.add_argument("experiment", help="module name under ilocalg.experiments, e.g. wifi_iloc")
    sw.add_argument("--seeds", type=int, required=True, metavar="N", help="seeds 0..N-1")
    sw.add_argument("--seed-start", type=int, default=0, help="first seed (default 0)")
    sw.add_argument("--param", action="append", default=[], metavar="NAME=V1,V2,...",
                    help="a parameter of run() and its values (repeatable; the grid is their product)")
    sw.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (default: a LocalCluster)")
    sw.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes (0 = serial, no Dask)")
    sw.add_argument("--fast", action="store_true", help="run the experiment in fast mode")
    sw.add_argument("--out", default=None, help="output folder (default: reports/sweeps/EXPERIMENT)")
    sw.add_argument("--no-cache", action="store_true", help="do not read or write the per-task parquet cache")

    from ilocalg.workflow.commands import measure as _measure

    me = sub.add_parser("measure", help=_measure.HELP)
    _measure.add_arguments(me)

    nb = sub.add_parser("notebooks", help="sync or check the .py <-> .ipynb notebook pairs")
    g = nb.add_mutually_exclusive_group(required=True)
    g.add_argument("--sync", action="store_true", help="write every .ipynb from its .py (outputs stripped)")
    g.add_argument("--check", action="store_true", help="fail if a pair is missing, stale or has outputs")
    return p


def _sweep(args) -> int:
    from ilocalg.workflow import sweep as sw
    from ilocalg.workflow.reporting import write_table
    from ilocalg.workflow.runner import REPO_ROOT

    try:
        grid = dict(sw.parse_param(p) for p in args.param)
        if args.seeds < 1:
            raise ValueError(f"--seeds must be >= 1, got {args.seeds}")
        sw._experiment(args.experiment)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    tasks = sw.make_tasks(args.experiment, range(args.seed_start, args.seed_start + args.seeds), grid, args.fast)
    res = sw.sweep(tasks, scheduler=args.scheduler, workers=args.workers,
                   cache_dir=None if args.no_cache else sw.DEFAULT_CACHE)
    out = Path(args.out) if args.out else REPO_ROOT / "reports" / "sweeps" / args.experiment
    out.mkdir(parents=True, exist_ok=True)
    print(f"{res.n_tasks} runs ({res.n_cached} from cache), {len(res.failures)} failed", file=sys.stderr)
    for f in res.failures:
        print(f"FAILED {f['task']}: {f['error']}", file=sys.stderr)
    (out / "failures.json").write_text(json.dumps(_jsonable(res.failures), indent=2) + "\n")
    if not res.results.empty:
        res.results.to_parquet(out / "results.parquet", index=False)
        own = getattr(sw._experiment(args.experiment), "sweep_summary", None)
        # an experiment that pools its tasks itself (e.g. leave-one-walk-out shards) says how; else mean and CI
        summary = own(res.results)["summary"] if own is not None else sw.aggregate(res.results)
        write_table(summary, out / "summary")
        print(summary.to_string(index=False))
    return 1 if res.failures else 0


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.command == "reproduce":
        from ilocalg.workflow.runner import REPO_ROOT, reproduce

        out = Path(args.out) if args.out else REPO_ROOT / "reports"
        try:
            return reproduce(out, fast=args.fast, only=args.only, seed=args.seed, html=not args.no_html,
                             n_seeds=args.seeds, workers=args.workers, jobs=args.jobs)
        except ValueError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
    if args.command == "evaluate":
        # Bad input ends as one line, "error: FILE: line N: what is wrong", exit status 2. The
        # loaders raise ValueError naming file and line (decoding, archive and JSON errors wrapped);
        # an OS error names its file; running out of memory is reported, never a traceback.
        try:
            result = args._evaluator.run(args)
        except ValueError as exc:
            print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
            return 2
        except OSError as exc:  # FileNotFoundError, PermissionError, IsADirectoryError ...
            where = f"{exc.filename}: " if exc.filename else ""
            print(f"error: {where}{exc.strerror or exc}", file=sys.stderr)
            return 2
        except MemoryError:
            print("error: out of memory while evaluating; the input is larger than this machine can hold "
                  "(split it into shorter recordings)", file=sys.stderr)
            return 2
        fmt = getattr(args._evaluator, "format_text", None)
        print(fmt(result) if fmt is not None and not args.json else json.dumps(_jsonable(result), sort_keys=False))
        return 0
    if args.command == "sweep":
        return _sweep(args)
    if args.command == "measure":
        from ilocalg.workflow.commands import measure

        try:
            out = measure.run(args)
        except ValueError as exc:
            print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
            return 2
        print(f"wrote {out}", file=sys.stderr)
        return 0
    if args.command == "notebooks":
        from ilocalg.workflow import notebook_sync
        from ilocalg.workflow.runner import NOTEBOOK_DIR

        if args.sync:
            for p in notebook_sync.sync(NOTEBOOK_DIR):
                print(f"wrote {p.relative_to(NOTEBOOK_DIR.parent)}")
            return 0
        problems = notebook_sync.check(NOTEBOOK_DIR)
        for pr in problems:
            print(pr, file=sys.stderr)
        return 1 if problems else 0
    return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
