"""Luo et al. 2017's claims (ilocalg/papers/luo.py): declarations, citations, refs, and the measures the
component claims read."""

from __future__ import annotations

from ilocalg.papers import claims_of
from ilocalg.papers import luo as paper
from tests import claims_checks as chk

CLAIMS = claims_of("luo")


def test_declarations():
    assert CLAIMS == paper.CLAIMS
    chk.check_ids_and_kinds("luo", 6, require_assumptions=True)
    chk.check_paper_value_on_asserted_side("luo")
    # what the text says about each component, not only the headline ratio
    for part in ("knn", "kf", "sliding-window", "time-window", "eq4", "pdr", "combined-improves"):
        assert any(part in c.id for c in CLAIMS), part


def test_cited_lines_carry_the_quoted_numbers():
    chk.check_lines_and_numbers("luo", quoted=True)


def test_decided_in_sections_exist():
    chk.check_decided_in("luo", required=True)


def test_assumptions_are_run_keywords():
    chk.check_assumptions("luo")


def test_component_measures_are_sane():
    m = chk.fast_tables("fusion_knn_pdr")["measures"]
    det = m[m["quantity"] == "detected / true steps"].set_index("item")["value"]
    assert ((det > 0) & (det < 3)).all()
    # the 0.2-2 s time window is the detector's default, so the two rows that use it agree
    assert det["time window 0.2-2 s"] == det["sliding window 0.4 s"]
    err = m[m["quantity"].str.startswith("fixed-length walks")].set_index("item")["value"]
    assert set(err.index) == {"eq. (4)", "one constant step length"} and (err >= 0).all()
    # the constant is a mean of 40-80 cm steps, so it is at most 100 % off any of those lengths
    assert err["one constant step length"] <= 100
    rho = m.loc[m["quantity"].str.contains("Spearman"), "value"]
    assert ((rho >= -1) & (rho <= 1)).all()
    jumps = m[m["quantity"].str.startswith("mean |error change|")]
    assert (jumps["value"] >= 0).all() and len(jumps) == 3


def test_published_values_are_the_papers_and_the_experiments_show_them():
    from ilocalg.experiments import fusion_knn_pdr, wifi_iloc

    assert fusion_knn_pdr.PAPER_LUO is paper.PUBLISHED
    assert wifi_iloc.PAPER_ILOC["knn_mean_m"] == paper.PUBLISHED["wifi_mean_m"]
    text = "\n".join(chk.paper_lines("luo"))
    for key in ("wifi_mean_m", "wifi_min_m", "wifi_max_m", "combined_mean_m"):
        assert f"{paper.PUBLISHED[key]}" in text, key
    assert f"前 {paper.PUBLISHED['pdr_better_points']} 个点" in text
