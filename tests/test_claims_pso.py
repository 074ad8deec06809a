"""The PSO thesis's claims ledger (ilocalg.papers.pso)."""

import math

import numpy as np
import pytest

from ilocalg.papers import pso
from tests import claims_checks as cc

KEY = "pso"


def _sg_exact(m, nl, nr):
    """Savitzky-Golay weights by least squares (Numerical Recipes sec. 14.8), independent of scipy."""
    i = np.arange(-nl, nr + 1)
    A = np.vander(i, m + 1, increasing=True)
    return np.linalg.pinv(A)[0]


def test_ids_kinds_and_count():
    claims = cc.check_ids_and_kinds(KEY, 10)
    kinds = {c.kind for c in claims}
    assert {"value", "ordering", "improvement", "ratio", "consistency"} <= kinds


def test_cited_lines_hold_the_quoted_numbers():
    cc.check_lines_and_numbers(KEY)


def test_paper_values_sit_on_the_side_their_claim_asserts():
    cc.check_paper_value_on_asserted_side(KEY)


def test_consistency_claims_redo_the_papers_arithmetic():
    t = pso.TABLE_3_2
    sym = max(float(np.max(np.abs(np.asarray(t[k]) - _sg_exact(*k)))) for k in [(2, 2, 2), (2, 5, 5), (4, 4, 4),
                                                                                 (4, 5, 5)])
    cc.check_consistency_arithmetic(KEY, {
        "pso-sg-table-symmetric": sym,
        "pso-sg-table-row-4-0": float(np.max(np.abs(np.asarray(t[(2, 4, 0)]) - _sg_exact(2, 4, 0)))),
        "pso-sg-larger-m-smoother": 0.333525 / 0.207735,
        "pso-closure-scaling": max(abs(3.106687 / 2.807418 - 203.182840 / 180.518522),
                                   abs(6.569617 / 5.791956 - 336.096833 / 298.915925)),
        "pso-fitness-is-per-step": 2.099552 / 0.093934,
        "pso-table-vs-fig-5-12": 158.28 - 158.157835,
        "pso-fig-5-14-denominator": 96.889735 / 0.604588,
        "pso-eq-4-3-inertia": 0.1,
        "pso-eq-3-3-sign": -1.0,
    })
    assert sym < 0.002  # the symmetric rows are right to their 3 decimals
    # the mis-printed row still sums to 1 (a sum check cannot see it)
    assert sum(t[(2, 4, 0)]) == pytest.approx(1.0, abs=1e-3)


def test_published_values_match_the_text():
    t = pso.PAPER_TABLE_5_2
    assert [t[w]["k"] for w in t] == [0.444, 0.489, 0.477, 0.554, 0.494, 0.522]
    # Table 5-2's accuracy is 1 - |GPS - PSO| / GPS to within its rounding (A1 98.77 printed 98.7, C 97.44 -> 97.5)
    for w, r in t.items():
        assert 100 * (1 - abs(r["gps_m"] - r["pso_m"]) / r["gps_m"]) == pytest.approx(r["acc_pct"], abs=0.1), w
    c = next(c for c in pso.CLAIMS if c.id == "pso-step-detection")
    assert c.paper_value == pytest.approx(100 * np.mean([1 / 217, 1 / 116, 5 / 128, 2 / 108, 2 / 118, 1 / 106]))
    assert pso.PAPER_COMPASS_RMS["ma"] < pso.PAPER_COMPASS_RMS["sg"] < pso.PAPER_COMPASS_RMS["raw"]
    assert math.isclose(pso.K_FIXED_PAPER, 0.5)


def test_assumptions_and_notebook_sections_exist():
    cc.check_assumptions(KEY)
    cc.check_decided_in(KEY)


def test_the_experiment_uses_the_values_declared_here():
    from ilocalg.experiments import pso_k_factor

    assert pso_k_factor.PAPER_TABLE_5_2 is pso.PAPER_TABLE_5_2
    assert pso_k_factor.PAPER_PHASE2_A1 is pso.PAPER_PHASE2_A1
    assert pso_k_factor.PAPER_COMPASS_RMS is pso.PAPER_COMPASS_RMS
    assert pso_k_factor.K_FIXED_PAPER == pso.K_FIXED_PAPER
