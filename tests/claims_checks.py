"""Checks shared by the claim-ledger tests of the papers (tests/test_claims_<paper>.py).

The paper text copies are read from ``$ILOC_PAPERS_DIR`` or ``papers`` beside the data folder
(:func:`ilocalg.io.paths.data_dir`); when missing they skip on a developer machine and FAIL under CI=true.
Fast runs of the experiments are cached per process, so test files that need the same experiment share
one run.
"""

from __future__ import annotations

import functools
import inspect
import math
import os
import re
from pathlib import Path

import pandas as pd
import pytest

from ilocalg.io.paths import REPO_ROOT, data_dir
from ilocalg.papers import claims_of
from ilocalg.papers.claims import VERDICTS, evaluate, judge, statistic_by_seed

#: Text copy of each paper in the shared papers folder.
PAPER_FILES = {
    "iloc": "000_42091e6b84aac0f5.txt",
    "liao": "001_2222ac3cfae0589e.txt",
    "survey": "002_bd9d55b2d42bda80.txt",
    "pso": "003_75bedf25a7e92732.txt",
    "luo": "004_b095b672cff2e388.txt",
}

#: Keyword arguments of the fast runs (the same quantities as the default run, less of what no claim reads).
FAST_KWARGS = {
    "ins_constraints": {"reference_grade": False},
    "pso_k_factor": {"real": False},
}

_NUMBER = re.compile(r"\d+(?:\.\d+)?")


def papers_dir() -> Path:
    env = os.environ.get("ILOC_PAPERS_DIR")
    return Path(env).expanduser().resolve() if env else data_dir().parent / "papers"


def paper_lines(key: str) -> list[str]:
    """Lines of a paper's text copy (skip, or fail under CI=true, when the file is missing)."""
    p = papers_dir() / PAPER_FILES[key]
    if not p.is_file():
        msg = f"paper text {p} not found (set ILOC_PAPERS_DIR or ILOC_DATA_DIR)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return p.read_text(encoding="utf-8").splitlines()


@functools.cache
def fast_long(experiment: str) -> pd.DataFrame:
    """One fast run (seed 0) of an experiment in the sweep's long format, with ``experiment`` and ``seed``."""
    import importlib

    from ilocalg.workflow.sweep import tables_to_long

    mod = importlib.import_module(f"ilocalg.experiments.{experiment}")
    long = tables_to_long(mod.run(seed=0, fast=True, **FAST_KWARGS.get(experiment, {})))
    long.insert(0, "experiment", experiment)
    long["seed"] = 0
    return long


def experiments_of(claims) -> list[str]:
    return sorted({r.experiment for c in claims if c.statistic is not None for r in c.statistic.refs}
                  | {a.experiment for c in claims for a in c.assumptions})


def check_ids_and_kinds(key: str, minimum: int) -> tuple:
    claims = claims_of(key)
    assert len(claims) >= minimum
    ids = [c.id for c in claims]
    assert len(set(ids)) == len(ids), "claim ids must be unique"
    assert all(i.startswith(f"{key}-") for i in ids)
    assert all(c.paper == key for c in claims)
    for c in claims:
        assert c.statistic is not None or c.untestable, c.id
        if c.expect == "~" and c.statistic is not None:
            assert c.paper_value is not None and math.isfinite(c.paper_value), f"{c.id}: '~' needs the paper value"
    return claims


def check_lines_and_numbers(key: str) -> None:
    """Every cited line exists and every number quoted in ``paper_text`` is printed on the cited lines."""
    lines = paper_lines(key)
    for c in claims_of(key):
        assert c.lines, c.id
        for n in c.lines:
            assert 1 <= n <= len(lines), f"{c.id}: line {n} outside 1..{len(lines)}"
        cited = "\n".join(lines[n - 1] for n in c.lines)
        missing = [x for x in _NUMBER.findall(c.paper_text) if x not in cited]
        assert not missing, f"{c.id}: {missing} not on lines {c.lines}"


def check_paper_value_on_asserted_side(key: str) -> None:
    """A direction claim's own paper value (when given) lies on the side it asserts (except consistency
    claims, which record where the paper's numbers contradict its text)."""
    for c in claims_of(key):
        if c.kind == "consistency" or c.expect == "~" or c.paper_value is None or c.statistic is None:
            continue
        assert judge(c, c.paper_value, c.paper_value, c.paper_value) == "reproduced", c.id


def check_consistency_arithmetic(key: str, expected: dict[str, float]) -> None:
    """Each consistency claim is arithmetic on printed numbers only, and gives the value worked out by hand."""
    cons = [c for c in claims_of(key) if c.kind == "consistency"]
    assert {c.id for c in cons} == set(expected)
    for c in cons:
        assert c.statistic is not None and c.statistic.refs == (), c.id
        v = statistic_by_seed(c.statistic, pd.DataFrame()).iloc[0]
        assert v == pytest.approx(expected[c.id], rel=1e-3, abs=1e-9), c.id


def check_refs_resolve(key: str) -> pd.DataFrame:
    """Every ref of every claim resolves on a fast run (one row per seed) and evaluate() gives a verdict."""
    claims = claims_of(key)
    exps = [e for e in experiments_of(claims)]
    results = pd.concat([fast_long(e) for e in exps], ignore_index=True) if exps else pd.DataFrame()
    rows = []
    for c in claims:
        row = evaluate(c, results)
        assert row["verdict"] in VERDICTS, c.id
        if c.statistic is None:
            assert row["verdict"] == "cannot be tested"
        else:
            assert row["n_seeds"] == 1, c.id
        rows.append(row)
    return pd.DataFrame(rows)


def check_assumptions(key: str) -> None:
    import importlib

    for c in claims_of(key):
        for a in c.assumptions:
            run = importlib.import_module(f"ilocalg.experiments.{a.experiment}").run
            assert a.param in inspect.signature(run).parameters, f"{c.id}: {a.param} is no keyword of run()"
            assert a.low < a.high and a.source.strip(), c.id


def check_decided_in(key: str) -> None:
    """``decided_in`` names a notebook and one of its Markdown headings (anchor: spaces -> '-')."""
    for c in claims_of(key):
        if not c.decided_in:
            continue
        stem, _, anchor = c.decided_in.partition("#")
        nb = REPO_ROOT / "notebooks" / f"{stem}.py"
        assert nb.is_file(), f"{c.id}: no notebook {stem}"
        heads = [ln.lstrip("# ").strip().replace(" ", "-") for ln in nb.read_text(encoding="utf-8").splitlines()
                 if re.match(r"^# #+ ", ln)]
        assert anchor in heads, f"{c.id}: no heading {anchor!r} in {stem}"
