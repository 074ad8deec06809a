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
    assert prov["tables_sha256"] == {}


def test_provenance_hashes_every_table_so_two_runs_compare_by_their_provenance(tmp_path):
    Report(tmp_path, "98_t").table(pd.DataFrame({"a": [1.5, 2.0]}), "t")
    Report(tmp_path, "98_t").table(pd.DataFrame({"b": ["x"]}), "u")
    def hashes_of_a_run():
        path = reporting.write_provenance(tmp_path, tmp_path, 0, True, [], ["98_t"])
        return json.loads(path.read_text())["tables_sha256"]

    hashes = hashes_of_a_run()
    assert set(hashes) == {"98_t__t.csv", "98_t__u.csv"}
    assert hashes["98_t__t.csv"] == reporting.sha256_file(tmp_path / "tables" / "98_t__t.csv")
    Report(tmp_path, "98_t").table(pd.DataFrame({"a": [1.5, 2.1]}), "t")  # one digit differs: another hash
    again = hashes_of_a_run()
    assert again["98_t__t.csv"] != hashes["98_t__t.csv"] and again["98_t__u.csv"] == hashes["98_t__u.csv"]


def test_readme_takes_paper_ref_tables_without_agreement(tmp_path):
    rep = Report(tmp_path, "98_raw")
    rep.table(pd.DataFrame([paper_ref("Raw paper", "Tab 2", "rms", 4.0, 8.0, unit="m")]), "raw_rows")
    readme = reporting.build_readme(tmp_path).read_text()
    assert "| Raw paper | Tab 2 | rms | m | 4 | 8 | differs (+100 %) |" in readme


def test_readme_shows_unitless_rows_with_an_empty_unit(tmp_path):
    Report(tmp_path, "97_u").compare([paper_ref("P", "T", "correlation", 0.5, 0.5)])
    readme = reporting.build_readme(tmp_path).read_text()
    assert "| P | T | correlation |  | 0.5 | 0.5 |" in readme and "nan" not in readme


# --- the landing page --------------------------------------------------------------------------------

def _demo_reports(tmp_path):
    """A reports folder as reproduce leaves it: comparison tables of two papers, a self-comparison,
    figures and an executed notebook with a conclusion."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import nbformat

    import ilocviz

    rep = Report(tmp_path, "07_demo")
    rep.compare([paper_ref("i-Loc thesis", "Fig 23", "KF mean error", 2.82, 2.9, unit="m"),
                 paper_ref("i-Loc thesis", "Fig 23", "PTS mean error", 5.15, 9.0, unit="m"),
                 paper_ref("罗思奇 et al. 2017", "sec. 4", "fused mean error", 6.74, 5.9, unit="m")])
    Report(tmp_path, "02_demo").compare([paper_ref(papers.SELF_COMPARISON, "UJI", "1-NN mean", 9.75, 9.75, "m")])
    for name in ("07_demo_cdf", "07_demo_tracks"):
        fig, ax = plt.subplots()
        ax.plot([0, 1], [1, 0])
        ilocviz.savefig(fig, name, tmp_path)
        plt.close(fig)
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("## Conclusion\n\nThe **KF** halves the PTS error.")]
    nbformat.write(nb, tmp_path / "07_demo.ipynb")
    return tmp_path


def test_landing_page_has_one_section_per_paper_and_regression_checks_apart(tmp_path):
    out = _demo_reports(tmp_path)
    readme = reporting.build_readme(out, seed=0).read_text()
    html = reporting.build_index(out, seed=0).read_text()
    for text in (readme, html):
        assert text.index("i-Loc (Chiu 2013)") < text.index("Luo et al. 2017") < text.index("Regression checks")
        assert "i-Loc thesis" not in text and "罗思奇" not in text  # one short name per paper
    iloc = html.split('id="iloc"')[1].split("</section>")[0]
    assert "<td>1</td>" not in iloc  # numbers are right-aligned cells
    assert '<td class="num">2</td><td class="num">1</td><td class="num">0</td><td class="num">1</td>' in iloc
    assert 'href="07_demo.html"><img src="figures/07_demo_cdf.png"' in iloc
    assert "<strong>KF</strong> halves" in iloc and "<details" in iloc
    regression = html.split('id="regression"')[1]
    assert "1-NN mean" in regression and "1-NN mean" not in iloc
    rows = reporting.comparison_rows(out)
    assert rows.set_index("quantity")["verdict"].to_dict() == {
        "KF mean error": "agrees", "PTS mean error": "differs", "fused mean error": "close", "1-NN mean": "agrees"}


def _chromium():
    import os
    import shutil

    exe = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
    if exe is None:
        msg = "headless Chromium not found (Debian: apt-get install chromium; `make test` installs it)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return exe


_IMG_CHECK = """<script>
window.addEventListener('load', () => {
  const imgs = [...document.images];
  const d = document.createElement('div');
  d.id = 'imgcheck';
  d.dataset.total = imgs.length;
  d.dataset.broken = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.getAttribute('src')).join(' ');
  document.body.appendChild(d);
});
</script></body>"""


def _images_in_browser(page):
    """(number of <img>, the src of those that did not load) as headless Chromium renders ``page``."""
    import re
    import subprocess

    probe = page.with_name("_imgcheck_" + page.name)
    probe.write_text(page.read_text().replace("</body>", _IMG_CHECK))
    dom = subprocess.run([_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--allow-file-access-from-files",
                          "--virtual-time-budget=10000", "--dump-dom", probe.as_uri()],
                         capture_output=True, text=True, timeout=120).stdout
    probe.unlink()
    m = re.search(r'<div id="imgcheck" data-total="(\d+)" data-broken="([^"]*)"', dom)
    assert m, f"no image report in the rendered page: {dom[-500:]}"
    return int(m.group(1)), m.group(2).split()


def test_landing_page_images_load_in_headless_chromium(tmp_path):
    out = _demo_reports(tmp_path)
    page = reporting.build_index(out, seed=0)
    total, broken = _images_in_browser(page)
    assert total == 2 and broken == []  # notebook 07_demo's two figures, once (in its home section, i-Loc)
    (out / "figures" / "07_demo_tracks.png").write_bytes(b"not a png")  # the check does see a broken image
    assert _images_in_browser(page) == (2, ["figures/07_demo_tracks.png"])


def test_scoreboard_counts_results_only_and_shows_other_classes_apart(tmp_path):
    Report(tmp_path, "10_demo").compare([
        paper_ref("PSO (Chao 2008)", "Table 5-2", "A1 k (PSO)", 0.5, 0.51),
        paper_ref("PSO (Chao 2008)", "Table 5-2", "A1 detected steps", 100, 100, "steps", row_class="set by input"),
        paper_ref("PSO (Chao 2008)", "Table 5-2 (earlier)", "A1 k (PSO)", 0.5, 0.7, row_class="alternative reading",
                  replaces=("Table 5-2", "A1 k (PSO)")),
    ])
    rows = reporting.comparison_rows(tmp_path)
    board = reporting._scoreboard(rows[rows["group"] == "pso"])
    assert board.iloc[0][["rows", "agrees", "differs", "shown apart"]].tolist() == [1, 1, 0, 2]
    html = reporting.build_index(tmp_path).read_text()
    readme = reporting.build_readme(tmp_path).read_text()
    for text in (html, readme):
        assert "Set by input" in text and "Alternative readings" in text
    alt = html.split("Alternative readings")[1]
    # the alternative sits beside the default it replaces, with the default's value
    assert "A1 k (PSO) (Table 5-2)" in alt and '<td class="num">0.51</td>' in alt


def test_duplicate_rows_across_notebooks_are_found_except_known_ones(tmp_path):
    Report(tmp_path, "05_a").compare([paper_ref("PSO (Chao 2008)", "Sec 5.1.3", "static compass RMS, MA", 1, 1)])
    Report(tmp_path, "10_b").compare([paper_ref("PSO (Chao 2008)", "Sec 5.1.3", "static compass RMS, MA", 1, 1),
                                      paper_ref("PSO (Chao 2008)", "Fig 1", "closure", 1, 1, "m"),
                                      paper_ref("PSO (Chao 2008)", "Fig 1", "closure", 1, 1, "%")])
    dup = reporting.duplicate_rows(reporting.comparison_rows(tmp_path), known={})
    assert dup[["quantity", "n"]].values.tolist() == [["closure", 2], ["static compass RMS, MA", 2]]
    assert dup["tables"].iloc[1] == "05_a__paper_vs_reproduced, 10_b__paper_vs_reproduced"
    known = {("PSO (Chao 2008)", "Fig 1", "closure"): "m and %"}
    assert reporting.duplicate_rows(reporting.comparison_rows(tmp_path), known=known)["quantity"].tolist() == [
        "static compass RMS, MA"]


def test_landing_page_opens_with_how_to_read_then_claims_and_links_every_notebook(tmp_path):
    import nbformat

    out = _demo_reports(tmp_path)
    for stem in ("00_tour", "09_walks"):
        nb = nbformat.v4.new_notebook()
        nb.cells = [nbformat.v4.new_markdown_cell(f"# Tour {stem}\n\ntext")]
        nbformat.write(nb, out / f"{stem}.ipynb")
        (out / f"{stem}.html").write_text("<html></html>")
    pd.DataFrame([
        {"paper": "iloc", "claim_id": "iloc-kf", "line": "1520", "kind": "improvement",
         "claim": "The KF lowers the Wi-Fi error.", "paper_value": float("nan"), "reproduced": 1.19,
         "ci_low": 1.1, "ci_high": 1.3, "verdict": "not reproduced", "robust_share": 0.25,
         "decided_in": "07_demo#Kalman-filter", "n_seeds": 5, "statistic": "KF / Wi-Fi", "expect": "<1",
         "most_influential": "scan_latency_s (rho 0.80)", "ci_clipped": False, "note": "worse on this floor"},
        {"paper": "iloc", "claim_id": "iloc-v", "line": "10", "kind": "value", "claim": "RADAR is 4.5 m.",
         "paper_value": 4.5, "reproduced": 4.6, "ci_low": 4.4, "ci_high": 4.8, "verdict": "reproduced",
         "robust_share": float("nan"), "decided_in": "", "n_seeds": 5, "statistic": "x", "expect": "~",
         "most_influential": "", "ci_clipped": False, "note": ""},
    ]).to_csv(out / "claims.csv", index=False)
    html = reporting.build_index(out, seed=0).read_text()
    readme = reporting.build_readme(out, seed=0).read_text()
    for text in (html, readme):
        assert text.index("How to read this page") < text.index("Holds: 1 of 2 testable claims reproduced")
        for stem in ("00_tour", "09_walks", "07_demo", "02_demo"):
            assert f"{stem}.html" in text, stem
        assert "Does not hold: 1." in text
    iloc = html.split('id="iloc"')[1].split("</section>")[0]
    assert '<td class="differs">not reproduced</td>' in iloc and '<td class="agrees">reproduced</td>' in iloc
    assert '<a href="07_demo.html#Kalman-filter">' in iloc and "25%, most: scan_latency_s" in iloc
    assert "1.19 [1.1, 1.3] (n = 5)" in iloc
    assert iloc.index("not reproduced") < iloc.index("Comparison rows")  # claims first, rows below
    # the words of the page are the notebooks' words
    for word in ("inside CI", "far off", "beside CI"):
        assert word not in html


def test_thumbnails_carry_the_figures_title_and_link_to_its_anchor(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import ilocviz

    Report(tmp_path, "05_demo").compare([paper_ref("i-Loc thesis", "Fig 16", "heading error", 13.87, 14.0, "deg")])
    fig, ax = plt.subplots()
    ax.set_title("Per-step heading error")
    ilocviz.savefig(fig, "05_demo_heading", tmp_path)
    plt.close(fig)
    assert reporting.png_title(tmp_path / "figures" / "05_demo_heading.png") == "Per-step heading error"
    import nbformat

    nb = nbformat.v4.new_notebook()
    cell = nbformat.v4.new_code_cell("ilocviz.savefig(fig, '05_demo_heading', OUT_DIR)")
    cell.outputs = [nbformat.v4.new_output("display_data", data={"text/html": '<a id="fig-05_demo_heading"></a>'})]
    nb.cells = [cell]
    nbformat.write(nb, tmp_path / "05_demo.ipynb")
    (fig_,) = reporting._figures(tmp_path, "05_demo")
    assert fig_.title == "Per-step heading error" and fig_.href == "05_demo.html#fig-05_demo_heading"
    html = reporting.build_index(tmp_path).read_text()
    assert "<figcaption>Per-step heading error (05_demo)</figcaption>" in html


def test_notebook_markdown_is_read_like_nbformat_executed_copy_first(tmp_path):
    """The report build reads notebooks' Markdown as JSON: the same sources as nbformat's, list-of-lines sources
    joined, the executed copy before the paired source, an unreadable file skipped."""
    import json

    import nbformat

    out, src = tmp_path / "reports", tmp_path / "notebooks"
    out.mkdir()
    src.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("x = 1"), nbformat.v4.new_markdown_cell("text\n\n## Where and why\n\nno"),
                nbformat.v4.new_markdown_cell("## Conclusion\n\nThe **KF** wins.")]
    nbformat.write(nb, src / "07_demo.ipynb")
    node = json.loads((src / "07_demo.ipynb").read_text())
    node["cells"] = [dict(node["cells"][1], source=["# Demo\n", "\n", "Lines joined."])]
    (out / "07_demo.ipynb").write_text(json.dumps(node))
    sources = list(reporting._markdown_sources(out, "07_demo", src))
    assert sources == [c.source for c in nbformat.read(out / "07_demo.ipynb", as_version=4).cells] + [
        c.source for c in nb.cells if c.cell_type == "markdown"]
    assert sources[0] == "# Demo\n\nLines joined."
    assert reporting._notebook_title(out, "07_demo", src) == "Demo"  # the executed copy's heading
    assert reporting._conclusion(out, "07_demo", src) == "The **KF** wins."  # none there: the source's
    (out / "07_demo.ipynb").write_text("<<<<<<< merge conflict")
    assert reporting._notebook_title(out, "07_demo", src) == "Where and why"  # the source's first heading line
    assert reporting._notebook_title(out, "08_none", src) == "08_none"
