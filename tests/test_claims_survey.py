"""The image/inertial survey's claims ledger (ilocalg.papers.survey)."""

import numpy as np

from ilocalg.ins.paper_values import HARTMANN_TABLE2_OVERALL
from ilocalg.papers import survey
from tests import claims_checks as cc

KEY = "survey"


def test_ids_kinds_and_count():
    claims = cc.check_ids_and_kinds(KEY, 6)
    ids = {c.id for c in claims}
    assert any("hom" in i for i in ids) and any("hartmann" in i for i in ids) and any("movips" in i for i in ids)


def test_cited_lines_hold_the_quoted_numbers():
    cc.check_lines_and_numbers(KEY)


def test_paper_values_sit_on_the_side_their_claim_asserts():
    cc.check_paper_value_on_asserted_side(KEY)


def test_consistency_claims_redo_the_papers_arithmetic():
    cc.check_consistency_arithmetic(KEY, {
        "survey-eq-3-dims": 1.0,
        "survey-movips-table": 1.0 - 0.28,
        "survey-hartmann-overall-mean": abs(0.0075 - (0.0063 + 0.0075 + 0.0069 + 0.0072 + 0.0096 + 0.0078) / 6),
        "survey-hartmann-overall-outage": 3.19,
        "survey-hartmann-trigger": 1000 / 5.8229,
        "survey-hartmann-vt-rate": 4.42,
        "survey-eq-10-velocity": 1.0,
        "survey-conclusion-image-inertial": 0.0164 / 0.68,
    })


def test_table_2_rows_agree_with_the_overall_row_the_experiment_uses():
    t = survey.HARTMANN_TABLE_2
    for j, a in enumerate("xyz"):
        assert t["mean_dev_m"]["overall"][j] == HARTMANN_TABLE2_OVERALL[f"mean_dev_{a}_m"]
        # the maximal deviation's overall row is the maximum of the six sequences
        assert t["max_dev_m"]["overall"][j] == max(v[j] for k, v in t["max_dev_m"].items() if k != "overall")
    # the number of outages' overall row is their mean (129 / 6)
    assert np.mean([v[2] for k, v in t["vt"].items() if k != "overall"]) == t["vt"]["overall"][2]


def test_assumptions_and_notebook_sections_exist():
    cc.check_assumptions(KEY)
    cc.check_decided_in(KEY)
