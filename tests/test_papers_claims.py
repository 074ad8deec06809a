"""The claims engine's verdicts (ilocalg.papers.claims.judge, evaluate)."""

from __future__ import annotations

import pandas as pd
import pytest

from ilocalg.papers import claims_of
from ilocalg.papers.claims import AGREE_REL, CLOSE_REL, Claim, M, constant, evaluate, judge, value


def _claim(kind: str, paper_value: float = 100.0, expect: str = "~") -> Claim:
    stat = constant(lambda: 0.0, "x") if kind == "consistency" else value(M("wifi_iloc", "x"), "m")
    return Claim(f"t-{kind}", "iloc", 1, kind, "a claim", paper_value=paper_value, statistic=stat, expect=expect)


@pytest.mark.parametrize("rel", [0.15, 0.3, 2.0])
def test_a_consistency_claim_beyond_agree_rel_is_not_reproduced_never_partly(rel):
    c = _claim("consistency")
    m = 100.0 * (1 + rel)
    assert judge(c, m, m, m) == "not reproduced"
    assert judge(c, 100.0 * (1 - rel), 100.0 * (1 - rel), 100.0 * (1 - rel)) == "not reproduced"


def test_a_consistency_claim_within_agree_rel_is_reproduced():
    c = _claim("consistency")
    m = 100.0 * (1 + 0.9 * AGREE_REL)
    assert judge(c, m, m, m) == "reproduced"


def test_a_value_claim_keeps_partly_between_agree_rel_and_close_rel():
    c = _claim("value")
    mid = 100.0 * (1 + (AGREE_REL + CLOSE_REL) / 2)
    assert judge(c, mid, mid - 1, mid + 1) == "partly"
    far = 100.0 * (1 + 1.1 * CLOSE_REL)
    assert judge(c, far, far - 1, far + 1) == "not reproduced"
    assert judge(c, mid, 90.0, mid + 1) == "reproduced"  # the paper's value inside the interval


def test_the_iloc_floor_area_contradiction_reads_not_reproduced():
    # L295: 75.46 m x 50.26 m = 3792.6 m^2 against the printed 3292.62 m^2 (15 % apart)
    area = {c.id: c for c in claims_of("iloc")}["iloc-floor-area"]
    row = evaluate(area, pd.DataFrame())
    assert row["reproduced"] == pytest.approx(3792.6196)
    assert AGREE_REL < abs(row["reproduced"] / area.paper_value - 1) < CLOSE_REL
    assert row["verdict"] == "not reproduced"


def _long_results() -> pd.DataFrame:
    """Long results of two experiments over three seeds, with a swept-parameter row and a duplicated quantity."""
    rows = []
    for seed in range(3):
        for exp in ("a", "b"):
            rows += [{"experiment": exp, "params": "{}", "seed": seed, "table": "comparison", "item": "x",
                      "quantity": "err", "value": 1.0 + seed + (exp == "b")},
                     {"experiment": exp, "params": "{}", "seed": seed, "table": "measures", "item": "x",
                      "quantity": "err", "value": 10.0 * seed},
                     {"experiment": exp, "params": '{"k": 2}', "seed": seed, "table": "comparison", "item": "y",
                      "quantity": "rate", "value": -1.0}]
    return pd.DataFrame(rows)


@pytest.mark.parametrize("ref", [M("a", "err", table="comparison"), M("b", "err", item="x", table="measures"),
                                 M("a", "err"), M("b", "rate"), M("c", "err")])
def test_lookup_on_a_result_index_gives_the_dataframe_lookups_values_and_errors(ref):
    from ilocalg.papers.claims import ResultIndex, lookup

    res = _long_results()
    try:
        want = lookup(res, ref)
    except KeyError as exc:
        with pytest.raises(KeyError) as got:
            lookup(ResultIndex(res), ref)
        assert got.value.args == exc.args  # the same message (no row; two rows per seed; only swept rows)
        return
    got = lookup(ResultIndex(res), ref)
    pd.testing.assert_series_equal(got, want, check_exact=True)
    assert got.index.dtype == want.index.dtype


def test_a_result_index_with_one_experiment_replaced_reads_the_new_rows_for_it_only():
    from ilocalg.papers.claims import ResultIndex, lookup

    res = _long_results()
    base = ResultIndex(res[res["seed"] == 0])
    new_a = res[(res["experiment"] == "a") & (res["seed"] == 0)].assign(value=lambda d: d["value"] + 100.0)
    idx = base.replace("a", new_a)
    assert lookup(idx, M("a", "err", table="comparison")).iloc[0] == 101.0
    assert lookup(idx, M("b", "err", table="comparison")).iloc[0] == 2.0
    assert lookup(base, M("a", "err", table="comparison")).iloc[0] == 1.0  # the original is unchanged
