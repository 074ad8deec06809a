"""Command line: ``python -m ilocalg {reproduce,evaluate,notebooks} ...``."""

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
    from ilocalg.commands import evaluators

    p = argparse.ArgumentParser(prog="python -m ilocalg",
                                description="iLoc toolkit: reproduce smartphone indoor positioning papers.")
    p.add_argument("--version", action="version", version=f"ilocalg {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    r = sub.add_parser("reproduce", help="run every notebook and write reports/")
    r.add_argument("--fast", action="store_true", help="shrink the data (FAST=True) for a quick check")
    r.add_argument("--only", metavar="PATTERN", help="notebooks whose name matches (glob or substring, comma list)")
    r.add_argument("--seed", type=int, default=0, help="simulation seed (default 0)")
    r.add_argument("--out", default=None, help="output folder (default: reports/ in the repository)")
    r.add_argument("--no-html", action="store_true", help="skip the HTML export")

    ev = sub.add_parser("evaluate", help="score a method on data and print JSON")
    evsub = ev.add_subparsers(dest="what", required=True, metavar="WHAT")
    for name, mod in evaluators().items():
        sp = evsub.add_parser(name, help=mod.HELP)
        mod.add_arguments(sp)
        sp.add_argument("--json", action="store_true", help="print one JSON object (the default output)")
        sp.set_defaults(_evaluator=mod)

    nb = sub.add_parser("notebooks", help="sync or check the .py <-> .ipynb notebook pairs")
    g = nb.add_mutually_exclusive_group(required=True)
    g.add_argument("--sync", action="store_true", help="write every .ipynb from its .py (outputs stripped)")
    g.add_argument("--check", action="store_true", help="fail if a pair is missing, stale or has outputs")
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.command == "reproduce":
        from ilocalg.runner import REPO_ROOT, reproduce

        out = Path(args.out) if args.out else REPO_ROOT / "reports"
        return reproduce(out, fast=args.fast, only=args.only, seed=args.seed, html=not args.no_html)
    if args.command == "evaluate":
        try:
            result = args._evaluator.run(args)
        except (ValueError, FileNotFoundError) as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        print(json.dumps(_jsonable(result), sort_keys=False))
        return 0
    if args.command == "notebooks":
        from ilocalg import notebook_sync
        from ilocalg.runner import NOTEBOOK_DIR

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
