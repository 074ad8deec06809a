"""Checks shared by the per-paper claims tests (tests/test_claims_<key>.py).

The paper copies live in ``../shared/papers`` beside the shared data (``ILOC_PAPERS_DIR`` overrides):
a missing copy skips on a developer machine and FAILS under CI=true, as the real-data tests do.
Each experiment runs once per test session (fast mode, seed 0), whichever claims test asks first.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import math
import os
import re
from pathlib import Path

import pytest

from ilocalg.io.paths import REPO_ROOT, data_dir
from ilocalg.papers import claims as cl

NUMBER = re.compile(r"\d+(?:\.\d+)?")


def papers_dir() -> Path | None:
    """The shared papers folder, or None."""
    cands = [Path(os.environ["ILOC_PAPERS_DIR"])] if os.environ.get("ILOC_PAPERS_DIR") else []
    cands += [data_dir().parent / "papers"] + [p / "shared" / "papers" for p in REPO_ROOT.parents]
    return next((p for p in cands if p.is_dir()), None)


def paper_lines(file: str) -> list[str]:
    """The lines of a paper's text copy (1-based: ``lines[n - 1]`` is line n)."""
    d = papers_dir()
    if d is None or not (d / file).is_file():
        msg = f"paper copy {file} not found (set ILOC_PAPERS_DIR to the shared papers folder)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return (d / file).read_text(encoding="utf-8").splitlines()


def notebook_anchors(stem: str) -> set[str]:
    """Anchors of the Markdown headings of notebooks/<stem>.py (jupytext percent format), as nbconvert and
    JupyterLab give them: the heading's text with spaces -> '-'."""
    path = REPO_ROOT / "notebooks" / f"{stem}.py"
    if not path.is_file():
        return set()
    return {ln.lstrip("# ").strip().replace(" ", "-") for ln in path.read_text(encoding="utf-8").splitlines()
            if re.match(r"^# #+ ", ln)}


def run_kwargs(experiment: str) -> set[str]:
    """Keywords ``run()`` of an experiment accepts (named ones plus those its ``**kwargs`` forward)."""
    mod = importlib.import_module(f"ilocalg.experiments.{experiment}")
    params = inspect.signature(mod.run).parameters
    names = {n for n, p in params.items() if p.kind is not p.VAR_KEYWORD}
    if any(p.kind is p.VAR_KEYWORD for p in params.values()):
        if experiment == "study_wifi":
            names |= set(mod.RADIO)
        elif experiment == "photo_positioning":
            from ilocalg.sim import photo_poi

            names |= set(photo_poi.DEFAULTS)
    return names - {"seed", "fast"}


@functools.cache
def fast_tables(experiment: str) -> dict:
    """One fast run (seed 0) of an experiment, shared by every claims test of the session."""
    return importlib.import_module(f"ilocalg.experiments.{experiment}").run(seed=0, fast=True)


def experiments_of(claims) -> set[str]:
    return {r.experiment for c in claims if c.statistic is not None for r in c.statistic.refs}


# ---- the checks --------------------------------------------------------------------------------------------

def check_declarations(claims, key: str, at_least: int) -> None:
    assert len(claims) >= at_least, f"{key}: {len(claims)} claims, want at least {at_least}"
    ids = [c.id for c in claims]
    assert len(set(ids)) == len(ids), f"duplicate claim ids: {sorted({i for i in ids if ids.count(i) > 1})}"
    for c in claims:
        assert c.paper == key and c.id.startswith(f"{key}-"), c.id
        assert c.kind in cl.KINDS
        if c.expect == "~" and c.statistic is not None:
            assert c.paper_value is not None and math.isfinite(c.paper_value), f"{c.id}: '~' needs paper_value"
        if c.statistic is not None and not c.statistic.refs:
            assert c.kind == "consistency", f"{c.id}: a statistic of printed numbers only is a consistency check"
        if c.statistic is None:
            assert len(c.untestable) > 20, f"{c.id}: say why it cannot be tested"
        elif c.statistic.refs:
            assert c.assumptions, f"{c.id}: name the values the text does not fix (assumptions)"
        if c.kind != "consistency" and c.expect != "~" and c.paper_value is not None and c.statistic is not None:
            # a direction claim's own printed figure lies on the side it asserts
            pv = float(c.paper_value)
            assert cl.judge(c, pv, pv, pv) == "reproduced", f"{c.id}: paper value {pv} against expect {c.expect}"
    testable = sum(c.statistic is not None for c in claims)
    assert testable >= 0.6 * len(claims), f"{key}: only {testable} of {len(claims)} claims testable"


def check_lines(claims, file: str) -> None:
    """Every cited line exists and is not blank, and every number in paper_text is printed on the cited lines."""
    lines = paper_lines(file)
    for c in claims:
        for n in c.lines:
            assert 1 <= n <= len(lines) and lines[n - 1].strip(), f"{c.id}: line {n} is blank or out of range"
        cited = "\n".join(lines[n - 1] for n in c.lines)
        assert c.paper_text.strip(), f"{c.id}: quote the paper (paper_text)"
        for num in NUMBER.findall(c.paper_text):
            assert num in cited, f"{c.id}: {num!r} of its paper_text is not on line(s) {c.lines}"


def check_decided_in(claims) -> None:
    for c in claims:
        stem, _, anchor = c.decided_in.partition("#")
        anchors = notebook_anchors(stem)
        assert anchors, f"{c.id}: no notebook {stem}"
        assert anchor in anchors, f"{c.id}: no section #{anchor} in {stem} (sections: {sorted(anchors)})"


def check_assumptions(claims) -> None:
    for c in claims:
        exps = {r.experiment for r in c.statistic.refs} if c.statistic is not None else set()
        for a in c.assumptions:
            assert a.experiment in exps, f"{c.id}: assumption on {a.experiment}, which the claim does not read"
            assert a.param in run_kwargs(a.experiment), f"{c.id}: {a.experiment}.run() has no keyword {a.param}"
            assert a.low < a.high and a.source.strip(), f"{c.id}: {a.param} range {a.low}..{a.high}"
            if a.log:
                assert a.low > 0


def check_evaluation(claims) -> None:
    """Every ref resolves on a fast run of its experiment and every claim gets one of the verdicts."""
    tables = {e: fast_tables(e) for e in sorted(experiments_of(claims))}
    ledger = cl.claims_from_tables(claims, tables).set_index("claim_id")
    assert list(ledger.index) == [c.id for c in claims]
    for c in claims:
        row = ledger.loc[c.id]
        assert row["verdict"] in cl.VERDICTS
        if c.statistic is None:
            assert row["verdict"] == "cannot be tested"
        else:
            assert row["n_seeds"] == 1 and math.isfinite(row["reproduced"]), f"{c.id}: {row['reproduced']}"
            assert row["verdict"] != "cannot be tested", c.id
            assert row["ci_low"] <= row["reproduced"] <= row["ci_high"]
