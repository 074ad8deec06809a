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
