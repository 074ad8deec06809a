"""Executed notebook -> one self-contained HTML page that reads the same offline as online.

nbconvert's ``lab`` template loads MathJax, require.js and mermaid.js from a CDN, so offline every equation
stays raw LaTeX. Here the equations of the markdown cells are typeset at build time into MathML
(``latex2mathml``), which browsers render natively, and the template drops every remote script: the page
needs nothing but itself (figures are inline data). The page title is the notebook's own (its first
heading), and a few style rules keep wide tables and long equations inside the page.
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["export_html", "html_exporter", "latex_to_mathml", "notebook_title", "REPORT_CSS"]

#: Extra style rules of the report pages: tables and equations wider than the page scroll inside their own
#: box instead of being cut off; long text cells (a ``note`` column) wrap; headings never split mid-word.
REPORT_CSS = """
.jp-RenderedHTMLCommon table { max-width: none; }
.jp-OutputArea-output.jp-RenderedHTMLCommon, .jp-RenderedHTML { overflow-x: auto; }
.jp-RenderedHTMLCommon td, .jp-RenderedHTMLCommon th { white-space: normal; overflow-wrap: normal;
  max-width: 40em; vertical-align: top; }
.jp-RenderedHTMLCommon h1, .jp-RenderedHTMLCommon h2, .jp-RenderedHTMLCommon h3 { overflow-wrap: normal;
  word-break: normal; hyphens: manual; }
math[display="block"] { display: block; overflow-x: auto; overflow-y: hidden; margin: 0.6em 0; }
math { font-size: 1.1em; font-family: "Latin Modern Math", "STIX Two Math", "Cambria Math", "DejaVu Math TeX Gyre",
  math; }
"""

# The lab template without its remote scripts (require.js, MathJax, mermaid), plus the report style.
_TEMPLATE = """{%- extends 'index.html.j2' -%}
{%- block html_head_js -%}{%- endblock html_head_js -%}
{%- block html_head_js_mathjax -%}{%- endblock html_head_js_mathjax -%}
{%- block html_head_js_mermaidjs -%}{%- endblock html_head_js_mermaidjs -%}
{%- block extra_css -%}<style type="text/css">""" + REPORT_CSS + """</style>{%- endblock extra_css -%}
"""
_TEMPLATE_NAME = "ilocalg_report.html.j2"


def latex_to_mathml(tex: str, display: bool = False) -> str:
    """MathML of one LaTeX formula (``display``: a block equation). Raises ValueError naming the formula
    when ``latex2mathml`` cannot parse it."""
    from latex2mathml.converter import convert

    tex = re.sub(r"\\arg(?![A-Za-z])", r"\\operatorname{arg}", tex)  # the one standard operator it lacks
    try:
        out = convert(tex.strip(), display="block" if display else "inline")
    except Exception as exc:  # noqa: BLE001 - the converter raises its own exception types
        raise ValueError(f"cannot typeset the formula {tex!r}: {type(exc).__name__}: {exc}") from None
    # a matrix's brackets stretch to its height (latex2mathml writes them as plain operators)
    out = re.sub(r"<mo>([^<]{1,10})</mo>(?=<mtable)", r'<mo stretchy="true" fence="true" form="prefix">\1</mo>', out)
    out = re.sub(r"(?<=</mtable>)<mo>([^<]{1,10})</mo>", r'<mo stretchy="true" fence="true" form="postfix">\1</mo>',
                 out)
    unknown = re.findall(r">(\\[A-Za-z]+)<", out)  # a command the converter does not know stays raw LaTeX
    if unknown:
        raise ValueError(f"cannot typeset the formula {tex!r}: unknown command(s) {', '.join(unknown)}")
    return out


def notebook_title(nb) -> str:
    """The notebook's title: the text of its first markdown heading (markup removed), else ``"Notebook"``."""
    for cell in nb.cells:
        if cell.cell_type != "markdown":
            continue
        for line in cell.source.splitlines():
            m = re.match(r"\s*#{1,6}\s+(.+?)\s*#*\s*$", line)
            if m:
                text = re.sub(r"\$([^$]*)\$", r"\1", m.group(1))
                return re.sub(r"[*_`]", "", text).strip()
    return "Notebook"


def _renderer_class():
    from nbconvert.filters.markdown_mistune import IPythonRenderer

    class MathMLRenderer(IPythonRenderer):
        """nbconvert's markdown renderer with equations typeset to MathML instead of left for MathJax."""

        def inline_math(self, body: str) -> str:
            return latex_to_mathml(body)

        def block_math(self, body: str) -> str:
            return latex_to_mathml(body, display=True)

        def latex_environment(self, name: str, body: str) -> str:
            return latex_to_mathml(f"\\begin{{{name}}}{body}\\end{{{name}}}", display=True)

    return MathMLRenderer


def html_exporter():
    """An nbconvert ``HTMLExporter`` (lab look) that typesets equations to MathML and loads no remote script."""
    from jinja2 import DictLoader, pass_context
    from nbconvert import HTMLExporter
    from nbconvert.filters.markdown_mistune import MarkdownWithMath

    renderer_cls = _renderer_class()

    class ReportHTMLExporter(HTMLExporter):
        @pass_context
        def markdown2html(self, context, source):
            cell = context.get("cell", {})
            path = context.get("resources", {}).get("metadata", {}).get("path", "")
            renderer = renderer_cls(escape=False, attachments=cell.get("attachments", {}),
                                    embed_images=self.embed_images, path=path,
                                    anchor_link_text=self.anchor_link_text,
                                    exclude_anchor_links=self.exclude_anchor_links, **self.lexer_options)
            return MarkdownWithMath(renderer=renderer).render(source)

    return ReportHTMLExporter(extra_loaders=[DictLoader({_TEMPLATE_NAME: _TEMPLATE})], template_file=_TEMPLATE_NAME)


def export_html(nb, path: str | Path) -> Path:
    """Write the executed notebook ``nb`` (an nbformat node) as a self-contained HTML page at ``path``."""
    path = Path(path)
    body, _ = html_exporter().from_notebook_node(
        nb, resources={"metadata": {"name": notebook_title(nb), "path": str(path.parent)}})
    path.write_text(body)
    return path
