"""Readings declared as data (ilocalg.papers._reading_rows and the readings_* modules of the PSO thesis, Liao
et al., the survey and the i-Loc photo positioning)."""

import numpy as np
import pytest

from ilocalg.papers import READINGS_COLUMNS, readings_liao, readings_pso, readings_survey
from ilocalg.papers import readings_iloc_photo as photo
from ilocalg.papers._reading_rows import Fmt, Pick, render
from ilocalg.sim.pso_walks import SENSORS


def test_render_fills_templates_and_picks_and_prefixes_lines():
    rows = [("a", "L1", "says", Pick("x", {"u": "U"}, other="other {x}"), Fmt("{y:.1f}")),
            ("b", "-", Fmt("{x}!"), "code", "")]
    t = render(rows, "Paper, ", x="u", y=2.0)
    assert list(t.columns) == list(READINGS_COLUMNS)
    assert t.loc[0, "paper_line"] == "Paper, L1" and t.loc[1, "paper_line"] == ""
    assert (t.loc[0, "code_does"], t.loc[0, "source"], t.loc[1, "text_says"]) == ("U", "2.0", "u!")
    assert render(rows, "P ", x="v", y=1.0).loc[0, "code_does"] == "other v"


@pytest.mark.parametrize("choices, match", [({"y": 1.0}, "lack 'x'"), ({"x": "v", "y": 1.0}, "is not one of")])
def test_render_refuses_a_missing_or_unknown_choice(choices, match):
    rows = [("a", "L1", "says", Pick("x", {"u": "U"}), "src")]
    with pytest.raises(ValueError, match=match):
        render(rows, "P ", **choices)


def test_every_readings_module_renders_with_its_defaults():
    tabs = [readings_pso.readings("ma2", "static", "per_step", SENSORS, 1.0, (0.95, 1.05), 0.61),
            readings_liao.constraints_readings("none", "drop", 3.0, 1.0, 0.01, 5.0, 1.4),
            readings_liao.online_readings("baro", (0.0, 0.5)),
            readings_survey.readings((np.deg2rad(1.0), 0.003, 0.003, 0.008)),
            photo.readings("A", False, {"drag_sd_px": 12.0, "tilt_sd_deg": 1.0, "yaw_sd_deg": 5.0, "f_px": 1045.0,
                                        "good_guess_sd_m": 2.25})]
    for t in tabs:
        assert len(t) >= 5 and t["paper_line"].str.len().gt(0).mean() > 0.5
    liao, online, survey, ph = tabs[1].set_index("choice"), tabs[2].set_index("choice"), tabs[3], tabs[4]
    assert "3 x the datasheet" in liao.loc["sensor errors", "code_does"]
    assert "time-tag error sd 10 ms" in liao.loc["phone sampling", "code_does"]
    assert "not the same on both phones" in online.loc["filter", "code_does"]
    assert "(0.0, 0.5)" in online.loc["window grid", "code_does"]
    assert survey.loc[2, "code_does"].startswith("sd 3 / 3 / 8 mm")
    assert ph.set_index("choice").loc["VA search space", "code_does"].endswith("(2-D)")
    # the text's set braces ({1,2} ...) are kept as written, no template is left unfilled
    assert "{1,2}, {6,7}" in ph.loc[0, "text_says"]
