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
