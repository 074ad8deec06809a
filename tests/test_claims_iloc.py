"""The i-Loc thesis's claims (ilocalg/papers/iloc.py): declarations, citations, refs and the arithmetic of
the consistency checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ilocalg.papers import claims_of
from ilocalg.papers import iloc as paper
from tests import claims_checks as chk

CLAIMS = claims_of("iloc")
BY_ID = {c.id: c for c in CLAIMS}


def test_declarations():
    assert CLAIMS == paper.CLAIMS
    chk.check_ids_and_kinds("iloc", 15, require_assumptions=True)
    chk.check_paper_value_on_asserted_side("iloc")
    # every chapter with results has claims: Wi-Fi, SAM, SLM, WDM/PTS, KF, photo
    for part in ("radar", "horus", "sam", "slm", "wdm", "pts", "kf", "photo"):
        assert any(part in c.id for c in CLAIMS), part


def test_cited_lines_carry_the_quoted_numbers():
    chk.check_lines_and_numbers("iloc", quoted=True)


def test_printed_tables_match_the_text_copy():
    lines = chk.paper_lines("iloc")
    t5 = " ".join(lines[n - 1] for n in (610, 612, 614, 616))
    assert [float(x) for x in t5.split() if x[0].isdigit()] == list(paper.TABLE5_VAR_M2)
    assert [float(x) for x in lines[604].split() if x[0].isdigit()] == list(paper.TABLE4_VAR)
    t2 = dict(ln.split("\t") for ln in lines[440:448])
    assert {k.replace("_", ""): float(v) for k, v in t2.items()} == paper.TABLE2_CORR


def test_decided_in_sections_exist():
    chk.check_decided_in("iloc", required=True)


def test_assumptions_are_run_keywords():
    chk.check_assumptions("iloc")


def _const(cid: str) -> float:
    c = BY_ID[cid]
    assert c.kind == "consistency" and c.statistic is not None and not c.statistic.refs
    return c.statistic()


def test_consistency_arithmetic():
    # L295: the printed sides do not give the printed area
    assert _const("iloc-floor-area") == pytest.approx(3792.6196)
    assert abs(_const("iloc-floor-area") - 3292.62) == pytest.approx(500.0, abs=0.01)
    # L357 vs Table 1: T2's 0.40 s against W_wave / 2 = 0.25 s is the larger overrun (T: 0.62 / 0.5 = 1.24)
    assert _const("iloc-sam-window-vs-table1") == pytest.approx(1.6)
    # L430: 33 of 800 steps
    assert _const("iloc-sam-count-800") == pytest.approx(4.125)
    # Table 2: I, A, A1, A2 above X1
    assert _const("iloc-slm-table2-vs-text") == 5
    # Table 4 read as relative variances: E|N(0, s^2)| = s sqrt(2/pi)
    rng = np.random.default_rng(1)
    mc = np.mean([np.abs(rng.normal(0, math.sqrt(v), 200_000)).mean() for v in paper.TABLE4_VAR]) * 100
    assert _const("iloc-table4-vs-slm-error") == pytest.approx(mc, rel=0.01)
    assert _const("iloc-table4-vs-slm-error") == pytest.approx(18.19, abs=0.01)
    assert _const("iloc-kf-start-is-pts") == 5.15


def test_table5_quantiles_against_sampling():
    rng = np.random.default_rng(2)
    sd = np.sqrt(np.repeat(paper.TABLE5_VAR_M2, 20_000))
    r = np.hypot(rng.normal(0, sd), rng.normal(0, sd))
    for q in (0.5, 0.8):
        assert paper.table5_error_quantile_m(q) == pytest.approx(np.quantile(r, q), rel=0.01)
    assert _const("iloc-table5-vs-wifi-error") == pytest.approx(paper.table5_error_quantile_m(0.5))
    # far below ch. 3's 4.5 m median: the contradiction the claim records
    assert paper.table5_error_quantile_m(0.5) < 0.5 * 4.5


@pytest.mark.parametrize("q", [0.0, 1.0, -0.1, 2.0])
def test_table5_quantile_rejects_bad_q(q):
    with pytest.raises(ValueError, match="q must be"):
        paper.table5_error_quantile_m(q)


def test_table5_quantile_rejects_bad_variances():
    with pytest.raises(ValueError, match="positive"):
        paper.table5_error_quantile_m(0.5, [1.0, 0.0])


def test_one_copy_of_each_printed_value():
    # the experiments show the paper module's published values (papers are data), not copies of their own
    from ilocalg.experiments import (
        fusion_iloc_kf,
        pdr_heading_trajectory,
        pdr_step_features,
        pdr_step_length,
        photo_positioning,
        wifi_iloc,
    )
    from ilocalg.fusion import PAPER_TABLE4_SIGMA_SL_VAR_M2, PAPER_TABLE5_SIGMA_RF_VAR_M2

    pub = paper.PUBLISHED
    assert fusion_iloc_kf.PAPER_KF is pub["fusion_iloc_kf"]
    assert photo_positioning.PAPER is pub["photo_positioning"]
    assert pdr_step_features.PUB is pub["pdr_step_features"]
    assert pdr_step_length.PUB is pub["pdr_step_length"]
    assert pdr_heading_trajectory.PUB is pub["pdr_heading_trajectory"]
    assert {k: wifi_iloc.PAPER_ILOC[k] for k in pub["wifi_iloc"]} == pub["wifi_iloc"]
    assert pub["pdr_step_length"]["corr"] == paper.TABLE2_CORR
    # the KF's Q and R tables (ilocalg.fusion) are the printed Tables 4 and 5 the consistency claims check
    assert tuple(PAPER_TABLE4_SIGMA_SL_VAR_M2) == paper.TABLE4_VAR
    assert tuple(PAPER_TABLE5_SIGMA_RF_VAR_M2) == paper.TABLE5_VAR_M2
