"""Checks shared by the claim-ledger tests of the papers (tests/test_claims_<paper>.py).

Every check takes the paper's key (:data:`ilocalg.papers.PAPERS`). The paper text copies are read from
``$ILOC_PAPERS_DIR`` or ``papers`` beside the data folder (:func:`ilocalg.io.paths.data_dir`); when missing
they skip on a developer machine and FAIL under CI=true, as the real-data tests do. Fast runs of the
experiments (seed 0) are cached per process, so test files that need the same experiment share one run.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import math
import os
import re
from pathlib import Path

import pandas as pd
import pytest

from ilocalg.io.paths import REPO_ROOT, data_dir
from ilocalg.papers import claims_of
from ilocalg.papers.claims import KINDS, VERDICTS, judge, statistic_by_seed

#: Text copy of each paper in the shared papers folder.
PAPER_FILES = {
    "iloc": "000_42091e6b84aac0f5.txt",
    "liao": "001_2222ac3cfae0589e.txt",
    "survey": "002_bd9d55b2d42bda80.txt",
    "pso": "003_75bedf25a7e92732.txt",
    "luo": "004_b095b672cff2e388.txt",
}

#: Keyword arguments of the fast runs (the same quantities as the default run, less of what no claim reads), on
#: top of the sweep's own (manifest.SWEEP_KWARGS: the claims read only the long results, as the sweep does).
FAST_KWARGS = {
    "ins_constraints": {"reference_grade": False},
}

_NUMBER = re.compile(r"\d+(?:\.\d+)?")


def papers_dir() -> Path | None:
    """The shared papers folder (``$ILOC_PAPERS_DIR``, else beside the data folder or a parent), or None."""
    cands = [Path(os.environ["ILOC_PAPERS_DIR"]).expanduser()] if os.environ.get("ILOC_PAPERS_DIR") else []
    cands += [data_dir().parent / "papers"] + [p / "shared" / "papers" for p in REPO_ROOT.parents]
    return next((p.resolve() for p in cands if p.is_dir()), None)


def paper_lines(key: str) -> list[str]:
    """Lines of a paper's text copy (``lines[n - 1]`` is line n); skip, or fail under CI=true, when missing."""
    d = papers_dir()
    if d is None or not (d / PAPER_FILES[key]).is_file():
        msg = f"paper text {PAPER_FILES[key]} not found (set ILOC_PAPERS_DIR or ILOC_DATA_DIR)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return (d / PAPER_FILES[key]).read_text(encoding="utf-8").splitlines()


@functools.cache
def fast_tables(experiment: str) -> dict:
    """One fast run (seed 0) of an experiment, shared by every claims test of the session."""
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    mod = importlib.import_module(f"ilocalg.experiments.{experiment}")
    return mod.run(seed=0, fast=True, **{**SWEEP_KWARGS.get(experiment, {}), **FAST_KWARGS.get(experiment, {})})


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


def notebook_anchors(stem: str) -> set[str]:
    """Anchors of the Markdown headings of notebooks/<stem>.py (jupytext percent format), as nbconvert and
    JupyterLab give them: the heading's text with spaces -> '-'."""
    nb = REPO_ROOT / "notebooks" / f"{stem}.py"
    if not nb.is_file():
        return set()
    return {ln.lstrip("# ").strip().replace(" ", "-") for ln in nb.read_text(encoding="utf-8").splitlines()
            if re.match(r"^# #+ ", ln)}


# ---- the checks --------------------------------------------------------------------------------------------

def check_ids_and_kinds(key: str, minimum: int, require_assumptions: bool = False) -> tuple:
    """Unique ids of this paper, known kinds, a reason for every untestable claim, the paper's value for an
    agreement claim, printed numbers only for a consistency check, at least 60 % testable; with
    ``require_assumptions``, every claim on reproduced values names the values the text does not fix."""
    claims = claims_of(key)
    assert len(claims) >= minimum, f"{key}: {len(claims)} claims, want at least {minimum}"
    ids = [c.id for c in claims]
    assert len(set(ids)) == len(ids), f"duplicate claim ids: {sorted({i for i in ids if ids.count(i) > 1})}"
    for c in claims:
        assert c.paper == key and c.id.startswith(f"{key}-"), c.id
        assert c.kind in KINDS, c.id
        if c.statistic is None:
            assert len(c.untestable) > 20, f"{c.id}: say why it cannot be tested"
            continue
        if c.expect == "~":
            assert c.paper_value is not None and math.isfinite(c.paper_value), f"{c.id}: '~' needs the paper value"
        if not c.statistic.refs:
            assert c.kind == "consistency", f"{c.id}: a statistic of printed numbers only is a consistency check"
        elif require_assumptions:
            assert c.assumptions, f"{c.id}: name the values the text does not fix (assumptions)"
    testable = sum(c.statistic is not None for c in claims)
    assert testable >= 0.6 * len(claims), f"{key}: only {testable} of {len(claims)} claims testable"
    return claims


def check_lines_and_numbers(key: str, quoted: bool = False) -> None:
    """Every cited line exists and every number quoted in ``paper_text`` is printed on the cited lines; with
    ``quoted``, every claim quotes the paper and cites no blank line."""
    lines = paper_lines(key)
    for c in claims_of(key):
        assert c.lines, c.id
        assert c.paper_text.strip() or not quoted, f"{c.id}: quote the paper (paper_text)"
        for n in c.lines:
            assert 1 <= n <= len(lines), f"{c.id}: line {n} outside 1..{len(lines)}"
            assert lines[n - 1].strip() or not quoted, f"{c.id}: line {n} is blank"
        cited = "\n".join(lines[n - 1] for n in c.lines)
        missing = [x for x in _NUMBER.findall(c.paper_text) if x not in cited]
        assert not missing, f"{c.id}: {missing} not on lines {c.lines}"


def check_paper_value_on_asserted_side(key: str) -> None:
    """A direction claim's own paper value (when given) lies on the side it asserts (except consistency
    claims, which record where the paper's numbers contradict its text)."""
    for c in claims_of(key):
        if c.kind == "consistency" or c.expect == "~" or c.paper_value is None or c.statistic is None:
            continue
        pv = float(c.paper_value)
        assert judge(c, pv, pv, pv) == "reproduced", f"{c.id}: paper value {pv} against expect {c.expect}"


def check_consistency_arithmetic(key: str, expected: dict[str, float]) -> None:
    """Each consistency claim is arithmetic on printed numbers only, and gives the value worked out by hand."""
    cons = [c for c in claims_of(key) if c.kind == "consistency"]
    assert {c.id for c in cons} == set(expected)
    for c in cons:
        assert c.statistic is not None and c.statistic.refs == (), c.id
        v = statistic_by_seed(c.statistic, pd.DataFrame()).iloc[0]
        assert v == pytest.approx(expected[c.id], rel=1e-3, abs=1e-9), c.id


#: Claims a paper must have judged (not "cannot be tested") on a fast run.
MIN_JUDGED = {"iloc": 0, "liao": 12, "survey": 6, "pso": 10, "luo": 0}


def check_ledger(key: str, ledger: pd.DataFrame) -> None:
    """A paper's rows of a run's ledger (``claims.csv``): every claim once, in order; every ref resolved, so every
    testable claim has a finite statistic inside its interval and a verdict; untestable ones say so."""
    claims = claims_of(key)
    assert list(ledger["claim_id"]) == [c.id for c in claims]
    for c, row in zip(claims, ledger.to_dict("records"), strict=True):
        assert row["verdict"] in VERDICTS, c.id
        if c.statistic is None:
            assert row["verdict"] == "cannot be tested", c.id
        else:
            assert row["n_seeds"] == 1 and math.isfinite(row["reproduced"]), f"{c.id}: {row['reproduced']}"
            assert row["verdict"] != "cannot be tested", c.id
            assert row["ci_low"] <= row["reproduced"] <= row["ci_high"], c.id
    assert (ledger["verdict"] != "cannot be tested").sum() >= MIN_JUDGED[key]


def check_assumptions(key: str) -> None:
    """Each assumption is a ``run()`` keyword of an experiment the claim reads, with a range and a source."""
    for c in claims_of(key):
        exps = {r.experiment for r in c.statistic.refs} if c.statistic is not None else set()
        for a in c.assumptions:
            assert a.experiment in exps, f"{c.id}: assumption on {a.experiment}, which the claim does not read"
            assert a.param in run_kwargs(a.experiment), f"{c.id}: {a.experiment}.run() has no keyword {a.param}"
            assert a.low < a.high and a.source.strip(), f"{c.id}: {a.param} range {a.low}..{a.high}"
            if a.log:
                assert a.low > 0, c.id


def check_decided_in(key: str, required: bool = False) -> None:
    """``decided_in`` names a notebook and one of its Markdown headings (anchor: spaces -> '-'); with
    ``required``, every claim names one."""
    for c in claims_of(key):
        if not c.decided_in:
            assert not required, f"{c.id}: name the notebook section that decides it (decided_in)"
            continue
        stem, _, anchor = c.decided_in.partition("#")
        anchors = notebook_anchors(stem)
        assert anchors, f"{c.id}: no notebook {stem}"
        assert anchor in anchors, f"{c.id}: no section #{anchor} in {stem} (sections: {sorted(anchors)})"
