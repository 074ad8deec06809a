"""The notebook HTML pages read the same offline: equations typeset at build time, no remote script,
every image in the page; the pages carry the notebook's title."""

from __future__ import annotations

import base64
import os
import re
import shutil
import subprocess

import nbformat
import pytest

from ilocalg.workflow.html_export import export_html, latex_to_mathml, notebook_title
from ilocalg.workflow.runner import NOTEBOOK_DIR, discover_notebooks

# a 2 x 2 PNG (red, green / blue, white), enough for the browser to decode an image
_PNG = "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAEklEQVR4nGP4z8DAAMIM/4EAAB/uBfsL2WiLAAAAAElFTkSuQmCC"


def _chromium():
    exe = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
    if exe is None:
        msg = "headless Chromium not found (Debian: apt-get install chromium; `make test` installs it)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return exe


#: Chromium with every network request refused (names resolve to nothing, any proxy is a closed port).
_OFFLINE = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
            "--proxy-server=127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND"]

# After load: the text of the markdown cells outside code and equations, how many equations there are and
# how many the browser laid out (non-zero width), and which images did not load.
_PROBE = """<script>
window.addEventListener('load', () => {
  const md = [...document.querySelectorAll('.jp-MarkdownOutput')].map(e => {
    const c = e.cloneNode(true);
    c.querySelectorAll('code, pre, math').forEach(x => x.remove());
    return c.textContent;
  }).join(' ');
  const maths = [...document.querySelectorAll('math')];
  const imgs = [...document.images];
  const d = document.createElement('div');
  d.id = 'probe';
  d.dataset.raw = (md.match(/\\$[^$]+\\$/g) || []).join(' | ').replace(/"/g, "'");
  d.dataset.math = maths.length;
  d.dataset.laid = maths.filter(m => m.getBoundingClientRect().width > 0).length;
  d.dataset.errors = document.querySelectorAll('merror').length;
  d.dataset.imgs = imgs.length;
  d.dataset.broken = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).length;
  document.body.appendChild(d);
});
</script></body>"""


def _render(page):
    probe = page.with_name("_probe_" + page.name)
    probe.write_text(page.read_text().replace("</body>", _PROBE))
    dom = subprocess.run([_chromium(), *_OFFLINE, "--virtual-time-budget=10000", "--dump-dom", probe.as_uri()],
                         capture_output=True, text=True, timeout=180).stdout
    m = re.search(r'<div id="probe" data-raw="([^"]*)" data-math="(\d+)" data-laid="(\d+)" data-errors="(\d+)" '
                  r'data-imgs="(\d+)" data-broken="(\d+)"', dom)
    assert m, f"no probe in the rendered page: {dom[-500:]}"
    return {"raw": m.group(1), "math": int(m.group(2)), "laid": int(m.group(3)), "errors": int(m.group(4)),
            "imgs": int(m.group(5)), "broken": int(m.group(6))}


def _with_figure(nb):
    """The stored (output-free) notebook with one figure output, as an executed one has."""
    out = nbformat.v4.new_output("display_data", data={"image/png": _PNG, "text/plain": "<Figure>"})
    code = next(c for c in nb.cells if c.cell_type == "code")
    code.outputs = [out]
    return nb


def test_notebook_01_renders_offline_with_equations_typeset_and_images_loaded(tmp_path):
    nb = _with_figure(nbformat.read(NOTEBOOK_DIR / "01_wifi_radar_horus_knn.ipynb", as_version=4))
    page = export_html(nb, tmp_path / "01_wifi_radar_horus_knn.html")
    text = page.read_text()
    assert not re.search(r"<script[^>]+src=", text), "a script is loaded from elsewhere"
    assert "mathjax" not in text.lower() and "cdnjs" not in text
    assert "<title>01 Wi-Fi fingerprinting: Simplified-RADAR, Simplified-Horus, KNN</title>" in text
    got = _render(page)
    assert got["raw"] == ""  # no $...$ left in the rendered text
    assert got["math"] >= 16 and got["laid"] == got["math"] and got["errors"] == 0
    assert got["imgs"] == 1 and got["broken"] == 0


def test_the_probe_sees_raw_latex_and_a_broken_image(tmp_path):
    """The browser check can fail: a page with MathJax-style raw LaTeX and a broken image is caught."""
    page = tmp_path / "raw.html"
    page.write_text('<html><body><div class="jp-MarkdownOutput">mean $\\mu = 1$ m</div>'
                    f'<img src="data:image/png;base64,{base64.b64encode(b"not a png").decode()}"></body></html>')
    got = _render(page)
    assert got["raw"] == "$\\mu = 1$" and got["math"] == 0 and got["broken"] == 1


@pytest.mark.parametrize("nb", discover_notebooks(), ids=lambda p: p.stem)
def test_every_notebook_exports_with_every_equation_typeset(nb, tmp_path):
    node = nbformat.read(nb, as_version=4)
    text = export_html(node, tmp_path / f"{nb.stem}.html").read_text()
    title = notebook_title(node)
    assert title.startswith(nb.stem[:2] + " ") and f"<title>{title}" in text.replace("&amp;", "&")
    assert "<merror" not in text
    from bs4 import BeautifulSoup

    soup = BeautifulSoup(text, "html.parser")
    for tag in soup.select("code, pre, math, script, style"):
        tag.decompose()
    md = " ".join(d.get_text(" ") for d in soup.select(".jp-MarkdownOutput"))
    assert not re.findall(r"\$[^$\n]{1,200}\$", md)


def test_latex_to_mathml_display_and_bad_formula():
    assert latex_to_mathml(r"\frac{a}{b}", display=True).startswith('<math xmlns="http://www.w3.org/1998/Math/MathML" '
                                                                       'display="block"')
    with pytest.raises(ValueError, match=r"'x\^'.*MissingSuperScript"):
        latex_to_mathml("x^")
    with pytest.raises(ValueError, match=r"unknown command\(s\) \\nosuchcommand"):
        latex_to_mathml(r"\nosuchcommand x")
