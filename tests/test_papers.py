"""Tests of ilocalg.papers: the paper names, readings tables and comparison rows."""

import pytest

from ilocalg import papers
from ilocalg.papers import PAPERS, paper_key, reading, readings_table


def test_readings_table_columns_in_order_and_extra_kept():
    rows = [reading("step length", "i-Loc (Chiu 2013), L295", "linear in frequency", "eq. (16)"),
            {**reading("window", "", "silent", "0.2-2 s", "Luo et al. 2017, L40"), "value": 2.0}]
    df = readings_table(rows)
    assert list(df.columns) == list(papers.READINGS_COLUMNS) + ["value"]
    assert len(df) == 2
    assert df.loc[1, "source"] == "Luo et al. 2017, L40"


@pytest.mark.parametrize("rows, match", [
    ([], "at least one row"),
    ([{"choice": "x", "paper_line": "", "text_says": "a"}], r"lacks column\(s\) \['code_does', 'source'\]"),
    ([reading("x", "", "a", "")], "row 0, column code_does: empty"),
    ([reading("x", "", "a", "b"), {**reading("y", "", "a", "b"), "source": 3}], "row 1, column source"),
])
def test_readings_table_rejects_bad_rows(rows, match):
    with pytest.raises(ValueError, match=match):
        readings_table(rows)


def test_paper_key_maps_every_earlier_label():
    assert paper_key("i-Loc thesis") == "iloc"
    assert paper_key("PSO thesis (003)") == "pso"
    assert paper_key("罗思奇 et al. 2017") == "luo"
    assert paper_key("Liao et al. 2016 (smartphone INS)") == "liao"
    assert paper_key("Hartmann et al. 2010 (survey sec. 5)") == "survey"
    assert paper_key("independent re-measurement") is None
    for key, name in PAPERS.items():
        assert paper_key(name) == key
    assert set(papers.PAPER_CITATIONS) == set(PAPERS)


# --- row classes -----------------------------------------------------------------------------------

def test_paper_ref_row_class_defaults_to_result_and_is_validated():
    assert papers.paper_ref("P", "T", "q", 1.0, 1.0)["row_class"] == "result"
    alt = papers.paper_ref("P", "T", "q alt", 1.0, 2.0, row_class="alternative reading", replaces="q")
    assert (alt["replaces_item"], alt["replaces_quantity"]) == ("T", "q")
    with pytest.raises(ValueError, match="row_class 'counted' is not one of"):
        papers.paper_ref("P", "T", "q", 1.0, 1.0, row_class="counted")
    with pytest.raises(ValueError, match="replaces= is only for"):
        papers.paper_ref("P", "T", "q", 1.0, 1.0, row_class="set by input", replaces="x")


def test_comparison_table_fills_row_class_of_older_rows():
    old = {k: v for k, v in papers.paper_ref("P", "T", "q", 1.0, 1.0).items() if k != "row_class"}
    self_row = {**old, "paper": papers.SELF_COMPARISON}
    df = papers.comparison_table([old, self_row, papers.paper_ref("P", "T", "s", 3, 3, row_class="set by input")])
    assert df["row_class"].tolist() == ["result", "regression check", "set by input"]


@pytest.mark.parametrize("unit, quantity, rng", [
    ("m", "mean error", (0.0, float("inf"))),
    ("%", "step-count error", (0.0, 100.0)),
    ("ratio", "KF mean / PTS mean", (0.0, float("inf"))),
    ("-", "mean of normals", (float("-inf"), float("inf"))),
    ("probability", "share", (0.0, 1.0)),
    ("m", "mean error difference", (float("-inf"), float("inf"))),
    ("deg", "heading", (float("-inf"), float("inf"))),
])
def test_physical_range_from_unit_and_signed_names(unit, quantity, rng):
    assert papers.physical_range(unit, quantity) == rng


def test_clip_interval_flags_only_a_change():
    assert papers.clip_interval(-2.0, 5.0, "m") == (0.0, 5.0, True)
    assert papers.clip_interval(90.0, 104.0, "%") == (90.0, 100.0, True)
    assert papers.clip_interval(1.0, 5.0, "m") == (1.0, 5.0, False)
    lo, hi, c = papers.clip_interval(float("nan"), float("nan"), "m")
    assert not c and lo != lo


def test_claims_markdown_and_rows_markdown_say_what_the_numbers_say():
    from ilocalg.papers.claims import Claim, M, claims_from_tables, claims_markdown, ratio, rows_markdown

    comp = papers.comparison_table([papers.paper_ref("i-Loc", "Fig 23", "KF", 2.82, 4.9, "m"),
                                    papers.paper_ref("i-Loc", "Fig 23", "Wi-Fi", 5.15, 4.1, "m")])
    claim = Claim("k", "iloc", 1520, "improvement", "The KF lowers the Wi-Fi error.", paper_value=2.82 / 5.15,
                  statistic=ratio(M("exp", "KF"), M("exp", "Wi-Fi")), expect="<1")
    led = claims_from_tables([claim], {"exp": {"comparison": comp}})
    text = claims_markdown(led)
    assert text.startswith("- **not reproduced**: The KF lowers the Wi-Fi error. (line 1520)")
    assert "= 1.2" in text and "the paper: 0.548" in text
    rows = rows_markdown(comp, where=lambda r: r["quantity"] == "KF")
    assert rows == "- Fig 23, KF: reproduced 4.9 m, larger than the paper's 2.82 m (+74 %)."
