"""The README's "Use it on your own data" snippet runs as it is and gives sensible errors."""

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _snippet() -> str:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Use it on your own data", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 1, "the section holds one Python snippet"
    return blocks[0]


def test_own_data_snippet_runs_end_to_end(tmp_path):
    (tmp_path / "snippet.py").write_text(_snippet())
    env_path = str(ROOT)
    out = subprocess.run([sys.executable, "snippet.py"], cwd=tmp_path, capture_output=True, text=True, timeout=300,
                         env={"PYTHONPATH": env_path, "PATH": "/usr/bin:/bin"})
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "my_survey.csv").exists()
    means = {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\w+)\s+mean ([\d.]+) m", out.stdout, re.M)}
    assert set(means) == {"KnnFingerprint", "SimplifiedRadar"}
    # 60 points over 30 m x 30 m (about 3.9 m apart), 3 dB shadowing: errors of a few metres, not tens
    assert all(0.5 < v < 6.0 for v in means.values()), means


def test_repository_has_licence_citation_and_changelog():
    import yaml

    assert "MIT License" in (ROOT / "LICENSE").read_text()
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["license"] == "MIT"
    from ilocalg.papers import PAPERS

    notes = " ".join(r["notes"] for r in cff["references"])
    assert all(name in notes for name in PAPERS.values())
    assert "## [Unreleased]" in (ROOT / "CHANGELOG.md").read_text()
