import json

import pandas as pd
import pytest

from ilocalg import papers
from ilocalg.papers import paper_ref
from ilocalg.workflow import reporting
from ilocalg.workflow.reporting import Report


def test_agreement_classes():
    assert papers.agreement(10.0, 10.5).startswith("agrees")
    assert papers.agreement(10.0, 12.0).startswith("close")
    assert papers.agreement(10.0, 20.0).startswith("differs")
    assert papers.agreement(10.0, float("nan")) == "n/a"


def test_comparison_table_requires_paper_rows():
    with pytest.raises(ValueError, match="at least one row"):
        papers.comparison_table([])
    with pytest.raises(ValueError, match="paper_ref"):
        papers.comparison_table([{"quantity": "x"}])


def test_report_writes_tables_and_readme_is_built_from_them(tmp_path):
    rep = Report(tmp_path, "99_demo")
    rep.compare([paper_ref("Demo paper", "Fig 1", "mean error", 2.0, 2.1, unit="m")])
    rep.table(pd.DataFrame({"a": [1.0, 2.0]}), "other")
    rep.table(pd.DataFrame({"qps": [123.0]}), "speed", deterministic=False)
    assert (tmp_path / "tables" / "99_demo__paper_vs_reproduced.csv").exists()
    assert (tmp_path / "tables" / "99_demo__other.md").exists()
    assert (tmp_path / "tables" / "timing" / "99_demo__speed.csv").exists()
    readme = reporting.build_readme(tmp_path, seed=3).read_text()
    assert "| Demo paper | Fig 1 | mean error | m | 2 | 2.1 | agrees (+5 %) |" in readme
    assert "Seed: 3" in readme
    # non-comparison tables are not rows of the README
    assert "other" not in readme.split("| table |")[-1].replace("99_demo__paper_vs_reproduced", "")


def test_report_without_out_dir_writes_nothing(tmp_path):
    df = Report(None, "x").compare([paper_ref("P", "T", "q", 1.0, 1.0)])
    assert df["agreement"].iloc[0] == "agrees (+0 %)"


def test_provenance_has_commit_seed_versions_and_hashes(tmp_path):
    f = tmp_path / "input.bin"
    f.write_bytes(b"abc")
    p = reporting.write_provenance(tmp_path, tmp_path, seed=5, fast=True, inputs=[f], notebooks=["00_x"])
    prov = json.loads(p.read_text())
    assert prov["seed"] == 5
    assert prov["packages"]["numpy"]
    assert prov["input_files_sha256"][str(f)] == (
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    )


def test_readme_takes_paper_ref_tables_without_agreement(tmp_path):
    rep = Report(tmp_path, "98_raw")
    rep.table(pd.DataFrame([paper_ref("Raw paper", "Tab 2", "rms", 4.0, 8.0, unit="m")]), "raw_rows")
    readme = reporting.build_readme(tmp_path).read_text()
    assert "| Raw paper | Tab 2 | rms | m | 4 | 8 | differs (+100 %) |" in readme


def test_readme_shows_unitless_rows_with_an_empty_unit(tmp_path):
    Report(tmp_path, "97_u").compare([paper_ref("P", "T", "correlation", 0.5, 0.5)])
    readme = reporting.build_readme(tmp_path).read_text()
    assert "| P | T | correlation |  | 0.5 | 0.5 |" in readme and "nan" not in readme
