"""The pdr_real_steps experiment's readings table: every choice, its cited lines, and the run's own values."""

from __future__ import annotations

import re

from ilocalg.experiments import pdr_real_steps as E
from ilocalg.papers import READINGS_COLUMNS
from ilocalg.pdr.robust import ROBUST_DEFAULTS
from ilocalg.pdr.step_evaluate import DETECTORS


def test_readings_name_every_detector_and_the_run_s_grids():
    full, fast = E.readings(), E.readings(fast=True)
    assert list(full.columns[:len(READINGS_COLUMNS)]) == list(READINGS_COLUMNS)
    text = " ".join(full["choice"])
    for det in DETECTORS:
        assert det in text, det
    # the rows carry the grids the run uses: the fast run's smaller grids differ from the full run's
    by = full.set_index("choice")["code_does"]
    assert "prominence_mps2 in [0.3, 0.5, 0.8, 1.2]" in by["robust detector: signal"]
    assert "prominence_mps2 in [0.3, 0.8]" in fast.set_index("choice").loc["robust detector: signal", "code_does"]
    assert f"min_stride_nac = {ROBUST_DEFAULTS['min_stride_nac']}" in by["robust detector: walk detection"]
    assert f"within {E.MATCH_TOL_S:g} s" in by["step matching"]
    assert "every third recording" in fast.set_index("choice").loc["parameter choice", "code_does"]


def test_cited_lines_of_the_data_set_say_what_the_readings_quote(shared_data):
    # SOURCE.txt's lines cited by the readings exist and hold the quoted facts (the reference values among them)
    lines = (shared_data("oxford_step_counter") / "SOURCE.txt").read_text(encoding="utf-8").splitlines()
    r = E.readings()
    cited = r[r["paper_line"].str.contains("SOURCE.txt")].set_index("choice")["paper_line"]
    assert len(cited) >= 3

    def span(ref: str) -> str:
        a, b = (int(x) for x in re.search(r"L(\d+)-(\d+)", ref).groups())
        assert 1 <= a <= b <= len(lines), ref
        return " ".join(lines[a - 1:b])

    assert f"{E.OXFORD_MEAN_PAPER * 100:.1f} % mean" in span(cited["reference values"])
    assert f"{E.OXFORD_MEDIAN_PAPER * 100:.1f} % median" in span(cited["reference values"])
    assert "1 - |counted - true| / true" in span(cited["accuracy measure"])
    assert "heel pressure sensors" in span(cited["ground truth"]) and "0->1 transition" in span(cited["ground truth"])
    assert "fastest rate" in span(cited["sampling-rate check"]) and "Samsung" in span(cited["sampling-rate check"])
