"""Liao et al. (2016)'s claims ledger (ilocalg.papers.liao)."""

import math

import pytest

from ilocalg.papers import claims_of
from tests import claims_checks as cc

KEY = "liao"


def _rss(*v):
    return math.sqrt(sum(x * x for x in v))


def test_ids_kinds_and_count():
    claims = cc.check_ids_and_kinds(KEY, 12)
    assert {"improvement", "ordering", "trend", "value", "consistency"} <= {c.kind for c in claims}


def test_cited_lines_hold_the_quoted_numbers():
    cc.check_lines_and_numbers(KEY)


def test_paper_values_sit_on_the_side_their_claim_asserts():
    cc.check_paper_value_on_asserted_side(KEY)


def test_paper_values_redo_the_tables_arithmetic():
    by = {c.id: c for c in claims_of(KEY)}
    s = _rss(1.9790, 5.4046, 3.7849) / _rss(14.8002, 5.1419, 3.6398)
    i = _rss(8.9068, 3.7412, 1.1919) / _rss(4.6846, 14.5990, 3.4490)
    assert by["liao-wvc-beats-nhc-rms"].paper_value == pytest.approx(math.sqrt(s * i))
    assert by["liao-wvc-beats-nhc-max"].paper_value == pytest.approx(math.sqrt(12.6542 / 42.4434 * 15.2382 / 82.6971))
    assert by["liao-samsung-n-20s-rises"].paper_value == pytest.approx(0.6913 - 0.6484)
    assert by["liao-rts-50cm"].paper_value == pytest.approx((0.3470 + 0.3967 + 0.5507 + 0.5810) / 4)
    # Fig 19: every curve falls over 5/10/20 s except Samsung-N (rho -0.5), so the mean rho is -11/12
    assert by["liao-window-trend"].paper_value == pytest.approx(-11 / 12)


def test_consistency_claims_redo_the_papers_arithmetic():
    e5, e10, e20 = _rss(1.0969, 1.5530, 0.8141), _rss(0.8574, 1.2766, 0.6265), _rss(0.6907, 0.7679, 0.4985)
    cc.check_consistency_arithmetic(KEY, {
        "liao-max-attitude-table-vs-text": 10.7743,
        "liao-iphone-gains-grow": (e10 - e20) / (e5 - e10),
        "liao-iphone-5s-above-filter": 1.0969 - 0.9885,
        "liao-roll-pitch-random": math.sqrt(1.5690**2 - 0.6652**2) / 0.6652,
        "liao-eq-10-gain": (2 * 1 * 4) / (2 * 1 / 4),
    })


def test_assumptions_and_notebook_sections_exist():
    cc.check_assumptions(KEY)
    cc.check_decided_in(KEY)
