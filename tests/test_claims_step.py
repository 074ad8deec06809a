"""The claims step: a ledger from per-seed results, loud failures for bad references, Latin-hypercube robustness.

Claims here are small fakes on the toy experiment (tests/sweep_toy.py: the mean and standard deviation of
``n`` normal draws with standard deviation ``scale``), never the papers' own claims.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from ilocalg.papers.claims import Assumption, Claim, M, ratio, value
from ilocalg.workflow import claims_step as cs
from tests import sweep_toy

TOY = "tests.sweep_toy"
MANIFEST = {"99_toy": {TOY: True}}
STD = M(TOY, "std of normals")
MEAN = M(TOY, "mean of normals")
SCALE = Assumption(TOY, "scale", 0.3, 3.0, "toy range", log=True)


def _claims():
    return [
        Claim("toy-1", "iloc", 10, "value", "The draws' sd is 1.", paper_value=1.0, statistic=value(STD),
              assumptions=(SCALE,), decided_in="99_toy.html#sd"),
        Claim("toy-2", "iloc", 11, "trend", "The sd exceeds 0.8.", statistic=value(STD), expect=">0.8",
              assumptions=(SCALE,)),
        Claim("toy-3", "luo", (3, 4), "ratio", "mean / sd is small.", statistic=ratio(MEAN, STD), expect="<0.5"),
        Claim("toy-4", "luo", 5, "value", "Needs the paper's data.", untestable="the paper's walks are not public"),
    ]


def test_ledger_has_its_columns_verdicts_and_intervals_over_seeds(tmp_path):
    code = cs.claims_step(tmp_path, ["99_toy"], seed=0, n_seeds=4, workers=0, cache_dir=tmp_path / "cache",
                          manifest=MANIFEST, claims=_claims(), budget_s=math.inf)
    assert code == 0
    led = pd.read_csv(tmp_path / "claims.csv", keep_default_na=False, na_values=[""])
    assert list(led.columns) == list(cs.LEDGER_COLUMNS)
    led = led.set_index("claim_id")
    sds = [float(np.random.default_rng(s).normal(0, 1, 50).std()) for s in range(4)]
    assert led.loc["toy-1", "n_seeds"] == 4
    assert led.loc["toy-1", "reproduced"] == pytest.approx(np.mean(sds))
    assert led.loc["toy-1", "ci_low"] < np.mean(sds) < led.loc["toy-1", "ci_high"]
    assert led.loc["toy-1", "verdict"] == "reproduced" and led.loc["toy-2", "verdict"] == "reproduced"
    assert led.loc["toy-4", "verdict"] == "cannot be tested" and "not public" in led.loc["toy-4", "note"]
    assert led.loc["toy-3", "line"] == "3;4"
    assert "## i-Loc (Chiu 2013)" in (tmp_path / "tables" / "claims.md").read_text()


def test_robust_share_is_the_share_of_samples_judged_on_their_own(tmp_path):
    claims = _claims()[:2]
    rob = cs.robustness(claims, pd.DataFrame({"seed": []}), seed=0, fast=False, workers=0,
                        cache_dir=tmp_path, n_samples=8, budget_s=math.inf).set_index("claim_id")
    scales = cs.sample_assumptions([SCALE], 8, 0)["scale"]
    # samples are fast-mode runs (the toy then draws n // 2 values)
    sds = np.array([sweep_toy.run(seed=0, fast=True, scale=float(s))["sweep_std"]["value"].iloc[0] for s in scales])
    assert rob.loc["toy-1", "robust_share"] == pytest.approx(np.mean(np.abs(sds - 1.0) <= 0.10))
    assert rob.loc["toy-2", "robust_share"] == pytest.approx(np.mean(sds > 0.8))
    assert rob.loc["toy-2", "most_influential"].startswith("scale (rho 1.00")
    assert rob.loc["toy-1", "n_samples"] == 8


def test_latin_hypercube_samples_are_stratified_seeded_and_on_a_log_scale():
    a = [SCALE, Assumption(TOY, "n", 10, 90, "toy", integer=True)]
    s = cs.sample_assumptions(a, 8, seed=3)
    assert s.equals(cs.sample_assumptions(a, 8, seed=3)) and not s.equals(cs.sample_assumptions(a, 8, seed=4))
    strata = np.floor(np.log(s["scale"] / 0.3) / np.log(10.0) * 8).astype(int)
    assert sorted(strata) == list(range(8))  # one sample per stratum of log(scale)
    assert s["n"].dtype.kind == "i" and s["n"].between(10, 90).all()
    with pytest.raises(ValueError, match="log scale needs low > 0"):
        cs.sample_assumptions([Assumption(TOY, "x", 0.0, 1.0, "t", log=True)], 8, 0)


def test_a_reference_that_does_not_resolve_fails_naming_the_claim(tmp_path, capsys):
    bad = Claim("toy-bad", "pso", 7, "value", "A misspelt quantity.", paper_value=1.0,
                statistic=value(M(TOY, "sd of normals")))
    code = cs.claims_step(tmp_path, ["99_toy"], workers=0, cache_dir=tmp_path / "c", manifest=MANIFEST,
                          claims=[*_claims(), bad], budget_s=0)
    assert code == 1
    err = capsys.readouterr().err
    assert "claim toy-bad (pso, line 7)" in err and "sd of normals" in err
    assert not (tmp_path / "claims.csv").exists()


def test_an_experiment_no_notebook_runs_is_an_error_and_other_notebooks_claims_wait(tmp_path, capsys):
    orphan = Claim("o-1", "liao", 1, "value", "x", paper_value=1.0, statistic=value(M("no_such_exp", "q")))
    assert cs.claims_step(tmp_path, ["99_toy"], workers=0, cache_dir=tmp_path / "c", manifest=MANIFEST,
                          claims=[orphan]) == 1
    assert "claim o-1: experiment 'no_such_exp'" in capsys.readouterr().err
    other = {**MANIFEST, "98_other": {"fusion_iloc_kf": True}}
    waits = Claim("w-1", "iloc", 1, "value", "x", paper_value=1.0, statistic=value(M("fusion_iloc_kf", "q")))
    assert cs.claims_step(tmp_path, ["99_toy"], workers=0, cache_dir=tmp_path / "c", manifest=other,
                          claims=[_claims()[3], waits]) == 0
    assert "1 wait for notebooks not run now" in capsys.readouterr().out
    assert pd.read_csv(tmp_path / "claims.csv")["claim_id"].tolist() == ["toy-4"]


def test_samples_fit_the_wall_time_budget(tmp_path):
    def clock():  # every reading of the clock advances it by 5 s: one sample "takes" 5 s
        clock.t += 5.0
        return clock.t

    joint = {TOY: [SCALE]}
    clock.t = 0.0
    used, res, notes = cs.run_samples(joint, 0, workers=1, cache_dir=tmp_path, budget_s=30, clock=clock)
    assert len(used[TOY]) == 3 and "3 samples, not 8" in notes[TOY]  # 10 s left after the timed sample
    assert res["params"].nunique() == 3
    clock.t = 0.0
    used, res, notes = cs.run_samples(joint, 0, workers=1, cache_dir=tmp_path, budget_s=21, clock=clock)
    assert TOY not in used and "not sampled" in notes[TOY]
    used, res, notes = cs.run_samples(joint, 0, workers=0, cache_dir=tmp_path, budget_s=math.inf)
    assert len(used[TOY]) == 8 and not notes and res["params"].nunique() == 8


def test_reproduce_runs_the_claims_step_and_the_page_shows_the_claims(tmp_path, monkeypatch):
    import nbformat

    import ilocalg.papers
    from ilocalg.workflow.runner import reproduce

    nbdir = tmp_path / "nbs"
    nbdir.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("SEED = 0", metadata={"tags": ["parameters"]})]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, nbdir / "99_toy.ipynb")
    monkeypatch.setattr(ilocalg.papers, "all_claims", lambda: tuple(_claims()))
    code = reproduce(tmp_path / "out", notebook_dir=nbdir, html=False, progress=False, jobs=1, n_seeds=2,
                     workers=0, cache_dir=tmp_path / "cache", manifest=MANIFEST)
    assert code == 0
    led = pd.read_csv(tmp_path / "out" / "claims.csv")
    assert led["claim_id"].tolist() == ["toy-1", "toy-2", "toy-3", "toy-4"] and (led["n_seeds"].iloc[:3] == 2).all()
    html = (tmp_path / "out" / "index.html").read_text()
    assert "The draws&#x27; sd is 1." in html and "Holds:" in html


def test_robustness_tasks_are_the_samples_the_step_reads_so_a_prerun_fills_every_share(tmp_path, monkeypatch):
    from ilocalg.workflow import sweep as sw

    tasks = cs.robustness_tasks(["99_toy"], seed=0, manifest=MANIFEST, claims=_claims())
    assert len(tasks) == cs.N_SAMPLES and all(t.fast and t.seed == 0 and t.experiment == TOY for t in tasks)
    sw.sweep(tasks, workers=0, cache_dir=tmp_path, progress=False)  # as the runner's pool does, beside notebooks
    calls = []
    orig = sw.run_task
    monkeypatch.setattr(sw, "run_task", lambda t: calls.append(t) or orig(t))
    # every sample is cached: even a budget of a fraction of a second gives every claim its share, at no run
    rob = cs.robustness(_claims()[:2], pd.DataFrame({"seed": []}), seed=0, fast=False, workers=0,
                        cache_dir=tmp_path, budget_s=0.5).set_index("claim_id")
    assert calls == [] and rob["n_samples"].tolist() == [cs.N_SAMPLES] * 2
    assert rob["robust_share"].notna().all()


def test_a_costly_experiment_gets_its_declared_smaller_hypercube(monkeypatch):
    monkeypatch.setitem(cs.N_SAMPLES_OF, TOY, 4)
    tasks = cs.robustness_tasks(["99_toy"], seed=0, manifest=MANIFEST, claims=_claims())
    scales = sorted(dict(t.params)["scale"] for t in tasks)
    assert len(scales) == 4  # one per quarter of the log range: still space-filling
    edges = np.exp(np.linspace(np.log(0.3), np.log(3.0), 5))
    assert all(lo <= s < hi for s, lo, hi in zip(scales, edges[:-1], edges[1:], strict=True))


def test_a_fast_run_judges_robustness_on_the_smallest_hypercube_a_full_run_on_the_whole(tmp_path):
    assert cs.n_samples_for(True) == cs.N_SAMPLES_FAST == 4 < cs.n_samples_for(False) == cs.N_SAMPLES
    for fast in (True, False):
        out = tmp_path / str(fast)
        code = cs.claims_step(out, ["99_toy"], seed=0, n_seeds=1, fast=fast, workers=0, cache_dir=out / "cache",
                              manifest=MANIFEST, claims=_claims()[:2], budget_s=math.inf)
        assert code == 0
        led = pd.read_csv(out / "claims.csv", keep_default_na=False, na_values=[""]).set_index("claim_id")
        assert f"{cs.n_samples_for(fast)} Latin-hypercube samples" in led.loc["toy-1", "note"]
