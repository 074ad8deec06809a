"""Report files: result tables on disk, reports/README.md, provenance.

A notebook writes its result tables with a :class:`Report`; comparison tables (one row per
paper result, :data:`ilocalg.papers.COMPARISON_COLUMNS`) are what ``reports/README.md`` is built
from, so nothing in that README is typed in by hand.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import platform
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.papers import (
    AGREE_REL,
    CLOSE_REL,
    COMPARISON_COLUMNS,
    PAPER_CITATIONS,
    PAPER_REF_COLUMNS,
    PAPERS,
    comparison_table,
    is_self_comparison,
    paper_key,
)

__all__ = [
    "FIGURE_FORMATS_ENV",
    "Report",
    "write_table",
    "build_readme",
    "build_index",
    "how_to_read",
    "notebooks",
    "read_ledger",
    "claims_summary",
    "png_title",
    "comparison_rows",
    "duplicate_rows",
    "verdict",
    "write_provenance",
    "sha256_file",
]


def _fmt(x) -> str:
    if isinstance(x, (float, np.floating)):
        if not math.isfinite(x):
            return str(x)
        return f"{x:.4g}"
    return str(x)


def _markdown(df: pd.DataFrame, index: bool) -> str:
    d = df.reset_index() if index else df
    cols = [str(c) for c in d.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for row in d.itertuples(index=False):
        lines.append("| " + " | ".join(_fmt(v).replace("|", "\\|") for v in row) + " |")
    return "\n".join(lines) + "\n"


def write_table(df: pd.DataFrame, path_stem: Path, index: bool = False) -> Path:
    """Write ``df`` as ``<stem>.csv`` (10 significant digits, LF line ends) and ``<stem>.md``."""
    path_stem = Path(path_stem)
    path_stem.parent.mkdir(parents=True, exist_ok=True)
    csv = path_stem.with_suffix(".csv")
    df.to_csv(csv, index=index, float_format="%.10g", lineterminator="\n")
    path_stem.with_suffix(".md").write_text(_markdown(df, index))
    return csv


@dataclass
class Report:
    """Where a notebook writes its tables.

    Parameters
    ----------
    out_dir : path or None
        The reports folder (``reports/``); ``None`` writes nothing (interactive exploration).
    notebook : str
        The notebook's stem, prefixed to every table name.

    Tables go to ``<out_dir>/tables/<notebook>__<name>.csv`` and ``.md``. Tables whose content
    depends on timing (queries per second ...) are written with ``deterministic=False`` to
    ``tables/timing/`` so the byte-for-byte reproducibility check can leave them out.
    """

    out_dir: str | Path | None
    notebook: str

    def __post_init__(self):
        # Under the reproduce runner, the experiments this notebook runs also fill the seed sweep's cache,
        # so the sweep reuses this run instead of repeating it (see ilocalg.workflow.sweep.record_runs).
        from ilocalg.workflow import sweep

        cache = os.environ.get(sweep.RECORD_ENV)
        exps = [e for e in os.environ.get(sweep.RECORD_EXPERIMENTS_ENV, "").split(",") if e]
        if cache and exps and self.out_dir is not None:
            sweep.record_runs(exps, cache)

    def table(self, df: pd.DataFrame, name: str, index: bool = False,
              deterministic: bool = True) -> pd.DataFrame:
        if self.out_dir is not None:
            sub = "tables" if deterministic else "tables/timing"
            write_table(df, Path(self.out_dir) / sub / f"{self.notebook}__{name}", index=index)
        return df

    def record_input(self, path: str | Path) -> None:
        """Note a real input file (or every file of a folder) for provenance.json."""
        if self.out_dir is None:
            return
        p = Path(path)
        files = sorted(f for f in p.rglob("*") if f.is_file()) if p.is_dir() else [p]
        d = Path(self.out_dir) / ".inputs"
        d.mkdir(parents=True, exist_ok=True)
        with open(d / f"{self.notebook}.txt", "a") as fh:
            for f in files:
                fh.write(f"{f.resolve()}\n")

    def compare(self, rows: list[dict], name: str = "paper_vs_reproduced") -> pd.DataFrame:
        """Build a comparison table from :func:`paper_ref` rows, write it and return it."""
        df = comparison_table(rows)
        return self.table(df, name)


#: Environment variable naming the file formats of the figures a notebook saves (comma-separated, e.g. ``png``;
#: read by :func:`ilocviz.savefig`; unset: PNG and PDF). The reproduce runner sets it to ``png`` in fast mode: the
#: PDF is the print copy of a full run's figure, and writing it is about half of a figure's cost.
FIGURE_FORMATS_ENV = "ILOC_FIGURE_FORMATS"

#: The one vocabulary of the project (notebooks, tables, this page) for a comparison row: where the paper's
#: value lies against the reproduced one. ``agrees``: inside the 95 % CI over seeds (a single run: within
#: 10 %); ``close``: beside the CI (within one interval width or 10 % of the mean; a single run: within
#: 35 %); ``differs``: farther; ``n/a``: no number to compare.
VERDICTS = ("agrees", "close", "differs", "n/a")
_VERDICT_OF = {"agrees": "agrees", "inside CI": "agrees", "close": "close", "beside CI": "close",
               "differs": "differs", "far off": "differs"}


def verdict(agreement_text: str) -> str:
    """Scoreboard class of an ``agreement`` text (:data:`VERDICTS`): ``agrees``, ``close``, ``differs`` or
    ``n/a`` (older spellings inside/beside/far off are read as the same classes)."""
    text = str(agreement_text)
    for prefix, v in _VERDICT_OF.items():
        if text.startswith(prefix):
            return v
    return "n/a"


#: Sections of the landing page besides the papers: self-comparisons and other published references.
REGRESSION, OTHER = "regression", "other"


def _group(label: str) -> str:
    key = paper_key(label)
    if key is not None:
        return key
    return REGRESSION if is_self_comparison(label) else OTHER


def comparison_rows(out_dir: str | Path, sweep_summary: pd.DataFrame | None = None,
                    n_seeds: int = 1) -> pd.DataFrame:
    """Every comparison row the notebooks wrote under ``<out_dir>/tables``, one DataFrame.

    Columns: :data:`ilocalg.papers.COMPARISON_COLUMNS` (``paper`` is the paper's one short name,
    :data:`ilocalg.papers.PAPERS`, where the label names one of the five papers), ``note``, with a
    sweep also ``n``, ``mean``, ``ci95_low``, ``ci95_high`` (and ``agreement`` from the interval), then
    ``table``, ``notebook``, ``group`` (a :data:`PAPERS` key, :data:`REGRESSION` or :data:`OTHER`) and
    ``verdict`` (:func:`verdict`).
    """
    out_dir = Path(out_dir)
    frames = []
    for csv in sorted((out_dir / "tables").glob("*.csv")):
        df = pd.read_csv(csv, keep_default_na=False, na_values=[""])
        if all(c in df.columns for c in PAPER_REF_COLUMNS):
            for c in ("unit", "note"):
                if c in df.columns:
                    df[c] = ["" if pd.isna(v) else str(v) for v in df[c]]
            df = comparison_table(df.drop(columns=["agreement"], errors="ignore").to_dict("records"))
            df.insert(0, "table", csv.stem)
            frames.append(df)
    if not frames:
        return pd.DataFrame(columns=[*COMPARISON_COLUMNS, "note", "table", "notebook", "group", "verdict"])
    allrows = pd.concat(frames, ignore_index=True)
    allrows["note"] = ["" if pd.isna(v) else str(v) for v in allrows["note"]]
    if sweep_summary is not None and n_seeds > 1 and not sweep_summary.empty:
        keys = ["paper", "item", "quantity", "unit"]
        agg = sweep_summary.copy()
        for k in keys:
            agg[k] = ["" if pd.isna(v) else str(v) for v in agg[k]]
            allrows[k] = ["" if pd.isna(v) else str(v) for v in allrows[k]]
        if "ci_clipped" not in agg.columns:
            agg["ci_clipped"] = False
        agg = agg.drop_duplicates(subset=keys)[keys + ["n", "mean", "ci95_low", "ci95_high", "ci_clipped",
                                                        "ci_agreement"]]
        allrows = allrows.merge(agg, on=keys, how="left", validate="many_to_one")
        single = allrows["n"].isna()
        allrows.loc[single, "n"] = 1
        allrows.loc[single, "mean"] = allrows.loc[single, "reproduced_value"]
        allrows["agreement"] = allrows["ci_agreement"].where(~single, allrows["agreement"])
        allrows["n"] = allrows["n"].astype(int)
        for c in ("ci95_low", "ci95_high"):
            allrows[c] = ["" if pd.isna(v) else v for v in allrows[c]]
        allrows["ci_clipped"] = ["yes" if v is True or v == 1 else "" for v in allrows["ci_clipped"]]
        allrows = allrows.drop(columns=["ci_agreement"])
    allrows["notebook"] = [t.split("__")[0] for t in allrows["table"]]
    allrows["group"] = [REGRESSION if rc == "regression check" else _group(p)
                        for p, rc in zip(allrows["paper"], allrows["row_class"], strict=True)]
    allrows["paper"] = [PAPERS.get(g, p) for g, p in zip(allrows["group"], allrows["paper"], strict=True)]
    allrows["verdict"] = [verdict(a) for a in allrows["agreement"]]
    return allrows


#: Comparison rows that may share (paper, item, quantity) today: key -> why. Each entry is a debt; the
#: test of the manifest's notebooks fails on any other duplicate.
KNOWN_DUPLICATES = {
    ("PSO (Chao 2008)", f"Fig 5.15 {lab}", f"A1 {place} closure (PSO k)"):
        "the same closure in m and in % (one row per unit)"
    for lab in ("(ma2, static band, per_step fitness)", "(none, static band, per_step fitness)",
                "(earlier reading: MA 2, signal band, walk total)")
    for place in ("park", "hall")
}


def duplicate_rows(allrows: pd.DataFrame, known: Mapping | None = None) -> pd.DataFrame:
    """Comparison rows sharing (paper, item, quantity) with another row, in any notebook, less the ``known``
    keys (default :data:`KNOWN_DUPLICATES`): one row per duplicate with the tables that carry it."""
    known = KNOWN_DUPLICATES if known is None else known
    if allrows.empty:
        return pd.DataFrame(columns=["paper", "item", "quantity", "n", "tables"])
    g = allrows.groupby(["paper", "item", "quantity"], sort=True)["table"]
    out = pd.DataFrame({"n": g.size(), "tables": g.agg(lambda t: ", ".join(sorted(set(t))))}).reset_index()
    out = out[out["n"] > 1]
    keep = [(p, i, q) not in known for p, i, q in zip(out["paper"], out["item"], out["quantity"], strict=True)]
    return out[keep].reset_index(drop=True)


def _row_columns(allrows: pd.DataFrame) -> list[str]:
    cols = ["paper", "item", "quantity", "unit", "paper_value", "reproduced_value"]
    if "n" in allrows.columns:
        cols += ["n", "mean", "ci95_low", "ci95_high", "ci_clipped"]
    return cols + ["agreement", "table"]


#: Headings of a notebook's closing section (its account of where and why the numbers differ).
_CONCLUSION_HEADINGS = ("## conclusion", "## where and why")


def _conclusion(out_dir: Path, stem: str, notebook_dir: Path | None) -> str:
    """The notebook's ``## Conclusion`` (or ``## Where and why ...``) markdown (executed copy first, else the
    paired source), or ``""``."""
    for source in _markdown_sources(out_dir, stem, notebook_dir):
        if source.lstrip().lower().startswith(_CONCLUSION_HEADINGS):
            return source.lstrip().split("\n", 1)[1].strip() if "\n" in source.strip() else ""
    return ""


def _markdown_sources(out_dir: Path, stem: str, notebook_dir: Path | None):
    """The sources of a notebook's Markdown cells, in order: those of the executed copy ``out_dir/<stem>.ipynb``,
    then those of ``notebook_dir/<stem>.ipynb`` (a missing file, or one that cannot be read as a notebook, gives
    none), so a caller's first match prefers the executed copy.

    An nbformat-4 file is read as the JSON it is (a cell's ``source`` is a string or a list of lines), not with
    :func:`nbformat.read`: importing nbformat (jsonschema) and validating every executed notebook, figures
    included, was most of the report build's time. Other versions go through nbformat's conversion.
    """
    for path in (out_dir / f"{stem}.ipynb", (notebook_dir / f"{stem}.ipynb") if notebook_dir else None):
        if path is None or not path.exists():
            continue
        try:
            node = json.loads(Path(path).read_text(encoding="utf-8"))
            if not isinstance(node, dict) or node.get("nbformat") != 4:
                import nbformat

                node = nbformat.read(path, as_version=4)
            sources = ["".join(c["source"]) if isinstance(c["source"], list) else c["source"]
                       for c in node["cells"] if c["cell_type"] == "markdown"]
        except (OSError, ValueError, KeyError, TypeError):
            continue
        yield from sources


def png_title(path: str | Path) -> str:
    """The ``Title`` text chunk of a PNG (what :func:`ilocviz.savefig` stores), or ``""``."""
    import struct
    import zlib

    try:
        data = Path(path).read_bytes()
    except OSError:
        return ""
    i = 8
    while i + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind in (b"tEXt", b"zTXt", b"iTXt"):
            key, _, rest = body.partition(b"\0")
            if key == b"Title":
                if kind == b"tEXt":
                    return rest.decode("latin-1")
                if kind == b"zTXt":
                    return zlib.decompress(rest[1:]).decode("latin-1")
                flag, rest = rest[0], rest[2:]
                _lang, _, rest = rest.partition(b"\0")
                _tkey, _, text = rest.partition(b"\0")
                return (zlib.decompress(text) if flag else text).decode("utf-8")
        if kind == b"IDAT":
            break
        i += 12 + n
    return ""


@dataclass(frozen=True)
class Figure:
    """A notebook figure on the landing page: its PNG, its title and the anchor in the notebook's HTML."""

    src: str
    title: str
    href: str


def _figures(out_dir: Path, stem: str, limit: int = 4) -> list[Figure]:
    """Up to ``limit`` figures of a notebook, in the order the notebook saves them, each captioned with its
    own title and linked to its anchor (``#fig-<name>``) in the executed notebook's HTML."""
    pngs = sorted((out_dir / "figures").glob(f"{stem}_*.png"))
    src = ""
    nb = out_dir / f"{stem}.ipynb"
    if nb.exists():
        src = nb.read_text()

    def pos(p: Path) -> tuple[int, str]:
        suffix = p.stem[len(stem) + 1:]
        i = src.find(suffix) if suffix else -1
        return (i if i >= 0 else len(src) + 1, p.name)

    out = []
    for p in sorted(pngs, key=pos)[:limit]:
        anchor = f"fig-{p.stem}"
        href = f"{stem}.html#{anchor}" if anchor in src else f"{stem}.html"
        out.append(Figure(f"figures/{p.name}", png_title(p) or p.stem[len(stem) + 1:].replace("_", " "), href))
    return out


def _sections(allrows: pd.DataFrame, ledger: pd.DataFrame | None = None
              ) -> list[tuple[str, str, str, pd.DataFrame]]:
    """(key, title, blurb, rows) per landing-page section: the five papers (with comparison rows or claims),
    then regression checks, others."""
    out = []
    empty = allrows.iloc[0:0]
    for key, name in PAPERS.items():
        rows = allrows[allrows["group"] == key] if not allrows.empty else empty
        has_claims = ledger is not None and not ledger.empty and (ledger["paper"] == key).any()
        if len(rows) or has_claims:
            out.append((key, name, PAPER_CITATIONS[key], rows))
    if allrows.empty:
        return out
    rows = allrows[allrows["group"] == REGRESSION]
    if len(rows):
        out.append((REGRESSION, "Regression checks",
                    "The toolkit against an earlier, independent measurement of the same quantity (not agreement "
                    "with a paper): a change here means the code changed what it computes.", rows))
    rows = allrows[allrows["group"] == OTHER]
    if len(rows):
        out.append((OTHER, "Other published references",
                    "Values published by others for the same data sets (data-set papers, competitions).", rows))
    return out


def _scoreboard(rows: pd.DataFrame) -> pd.DataFrame:
    """Per notebook: its result rows and how many are inside / beside / far off / n/a (results only: rows
    set by input, alternative readings and regression checks are counted apart, in ``shown apart``)."""
    recs = []
    for stem, g in rows.groupby("notebook", sort=True):
        res = g[g["row_class"].isin(["result", "regression check"])] if (g["group"] == REGRESSION).all() \
            else g[g["row_class"] == "result"]
        counts = res["verdict"].value_counts()
        recs.append({"notebook": stem, "rows": len(res), **{v: int(counts.get(v, 0)) for v in VERDICTS},
                     "shown apart": len(g) - len(res)})
    return pd.DataFrame(recs)


#: Row classes shown apart from the counted results, with the heading of their table.
_APART = (("set by input", "Set by input (not counted: the reproduced value is an input of the simulation)"),
          ("alternative reading", "Alternative readings (not counted: beside the default row each replaces)"))


def _apart(rows: pd.DataFrame, allrows: pd.DataFrame, cols: list[str]) -> list[tuple[str, pd.DataFrame]]:
    """(heading, rows) of the non-counted classes; alternatives carry the default row they replace and its
    value (``default_value``) beside their own."""
    out = []
    for rc, heading in _APART:
        part = rows[rows["row_class"] == rc]
        if part.empty:
            continue
        show = part[cols].copy()
        if rc == "alternative reading" and "replaces_quantity" in part.columns:
            val = "mean" if "mean" in allrows.columns else "reproduced_value"
            base = allrows[allrows["row_class"] != "alternative reading"]
            idx = {(p, i, q, u): v for p, i, q, u, v in zip(base["paper"], base["item"], base["quantity"],
                                                            base["unit"], base[val], strict=True)}
            show.insert(show.columns.get_loc("quantity") + 1, "replaces",
                        [f"{q} ({i})" if i != it else q for i, q, it in
                         zip(part["replaces_item"], part["replaces_quantity"], part["item"], strict=True)])
            show.insert(show.columns.get_loc("agreement"), "default_value",
                        [idx.get((p, i, q, u), math.nan) for p, i, q, u in
                         zip(part["paper"], part["replaces_item"], part["replaces_quantity"], part["unit"],
                             strict=True)])
        out.append((heading, show.reset_index(drop=True)))
    return out


#: Claim verdicts (:data:`ilocalg.papers.claims.VERDICTS`) -> the colour class of the page.
_CLAIM_CLASS = {"reproduced": "agrees", "partly": "close", "not reproduced": "differs", "cannot be tested": "na"}


def how_to_read(seed, fast: bool, n_seeds: int, sweep: bool) -> list[str]:
    """The "How to read this page" section (Markdown lines): the one vocabulary of the page and the notebooks."""
    from ilocalg.workflow.claims_step import BUDGET_S, N_SAMPLES

    ci = (f"the 95 % confidence interval over N = {n_seeds} simulation seeds" if sweep else
          "a single run (no interval: reproduce with `--seeds N` for one)")
    return [
        "## How to read this page",
        "",
        "Each paper's section opens with its **claims**: one row per statement of substance the paper makes (a "
        "value, an ordering such as \"A beats B\", a ratio, a trend), the paper's figure, the reproduced figure "
        f"with {ci}, and a verdict:",
        "",
        "- **reproduced**: the interval lies wholly on the side the claim asserts (an ordering, ratio or trend), "
        f"or holds the paper's value or comes within {AGREE_REL:.0%} of it (a value);",
        f"- **partly**: the interval straddles the claim's threshold, or the value is within {CLOSE_REL:.0%};",
        "- **not reproduced**: the interval lies wholly on the other side, or the value is farther off. This is a "
        "finding, not a failure: the note says why;",
        "- **cannot be tested**: the paper's data or setting are not available (the note says what is missing).",
        "",
        "**Robustness** is the share of the space of the assumptions the paper does not fix (sampled jointly, Latin "
        f"hypercube: {N_SAMPLES} fast-mode runs per experiment at the base seed, beside the notebooks; a run still "
        f"missing afterwards gets a {BUDGET_S:.0f} s budget, and the note says when fewer were run) in which the "
        "verdict holds, and the assumption "
        "that moves it most (largest |Spearman rho| with the claim's statistic). Each claim links to the notebook "
        "section that decides it.",
        "",
        "Below the claims, collapsed, are the **comparison rows**: one published number beside the reproduced one, "
        "with the words of the notebooks' `agreement` column: the paper's value **agrees** (inside the interval; "
        f"a single run: within {AGREE_REL:.0%}), is **close** (beside it: within one interval width or 10 % of "
        f"the mean; a single run: within {CLOSE_REL:.0%}) or **differs**. Only rows that are results are "
        "counted; rows **set by input** (the reproduced value is an input of the simulation), **alternative "
        "readings** (beside the default they replace) and **regression checks** (the toolkit against its own "
        "earlier measurement) are shown apart. Experiments on real recordings do not depend on the seed: their "
        "rows have n = 1.",
        "",
        f"Seed: {seed}. Mode: {'fast (reduced data)' if fast else 'full'}. Seeds for intervals: N = {n_seeds}.",
        "",
    ]


def _notebook_title(out_dir: Path, stem: str, notebook_dir: Path | None) -> str:
    """The first Markdown heading of a notebook (executed copy, else the source), without its ``#``s."""
    for source in _markdown_sources(out_dir, stem, notebook_dir):
        for line in source.splitlines():
            if line.startswith("#"):
                return line.lstrip("#").strip()
    return stem


def notebooks(out_dir: str | Path, notebook_dir: str | Path | None = None) -> list[tuple[str, str, str]]:
    """(stem, title, link) of every executed notebook in ``out_dir`` (the HTML when exported, else the ipynb)."""
    out_dir = Path(out_dir)
    nb_dir = Path(notebook_dir) if notebook_dir else None
    out = []
    for nb in sorted(out_dir.glob("[0-9][0-9]_*.ipynb")):
        link = f"{nb.stem}.html" if nb.with_suffix(".html").exists() else nb.name
        out.append((nb.stem, _notebook_title(out_dir, nb.stem, nb_dir), link))
    return out


def read_ledger(out_dir: str | Path) -> pd.DataFrame:
    """``<out_dir>/claims.csv`` (written by the claims step), or an empty frame."""
    path = Path(out_dir) / "claims.csv"
    if not path.exists():
        return pd.DataFrame(columns=["paper", "claim_id", "verdict"])
    led = pd.read_csv(path, keep_default_na=False, na_values=[""])
    for c in ("decided_in", "note", "most_influential", "claim", "line", "expect", "statistic"):
        if c in led.columns:
            led[c] = ["" if pd.isna(v) else str(v) for v in led[c]]
    return led


def claims_summary(ledger: pd.DataFrame) -> str:
    """One line per paper from its claims: what holds and what does not."""
    if ledger.empty:
        return "No claims judged in this run."
    v = ledger["verdict"].value_counts()
    n = len(ledger)
    testable = n - int(v.get("cannot be tested", 0))
    held, part, no = (int(v.get(k, 0)) for k in ("reproduced", "partly", "not reproduced"))
    return (f"Holds: {held} of {testable} testable claims reproduced" + (f", {part} partly" if part else "")
            + f". Does not hold: {no}." + (f" Cannot be tested: {n - testable}." if n - testable else ""))


def _decided_href(decided_in: str) -> str:
    d = str(decided_in).strip()
    if not d:
        return ""
    stem, _, anchor = d.partition("#")
    stem = stem.removesuffix(".html").removesuffix(".ipynb").removesuffix(".py")
    return f"{stem}.html" + (f"#{anchor}" if anchor else "")


def _num(x) -> str:
    try:
        x = float(x)
    except (TypeError, ValueError):
        return ""
    return f"{x:.3g}" if math.isfinite(x) else ""


def _claim_cells(r: dict) -> dict[str, str]:
    """Plain-text cells of one claim: paper value, reproduced with CI, robustness."""
    paper = _num(r.get("paper_value"))
    if not paper and r.get("expect", "~") not in ("~", ""):
        paper = f"{r['expect'][0]} {r['expect'][1:]}"  # a direction claim: the side it asserts
    rep = _num(r.get("reproduced"))
    lo, hi = _num(r.get("ci_low")), _num(r.get("ci_high"))
    if rep and lo and hi and (lo != rep or hi != rep):
        rep += f" [{lo}, {hi}]" + ("*" if str(r.get("ci_clipped", "")).lower() in ("true", "1") else "")
    n = r.get("n_seeds")
    if rep and n == n and n not in ("", None):
        rep += f" (n = {int(float(n))})"
    rob = ""
    share = r.get("robust_share")
    if share is not None and share == share and str(share) != "":
        rob = f"{float(share):.0%}" + (f", most: {r['most_influential']}" if r.get("most_influential") else "")
    return {"paper": paper, "reproduced": rep, "robustness": rob}


def _claims_markdown(part: pd.DataFrame) -> list[str]:
    cols = ["verdict", "claim", "paper", "reproduced [95 % CI]", "robustness", "decided in"]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in part.to_dict("records"):
        c = _claim_cells(r)
        href = _decided_href(r.get("decided_in", ""))
        cells = [f"**{r['verdict']}**", f"{r['claim']} ({r['claim_id']}, L{r.get('line', '')})", c["paper"],
                 c["reproduced"], c["robustness"], f"[{href.split('#')[0]}]({href})" if href else ""]
        lines.append("| " + " | ".join(str(x).replace("|", "\\|").replace("\n", " ") for x in cells) + " |")
    return lines + [""]


def _claims_html(part: pd.DataFrame) -> str:
    from html import escape

    head = "".join(f"<th>{h}</th>" for h in ("verdict", "claim", "paper", "reproduced [95 % CI]", "robustness",
                                             "decided in"))
    body = []
    for r in part.to_dict("records"):
        c = _claim_cells(r)
        href = _decided_href(r.get("decided_in", ""))
        note = f'<div class="note">{escape(r["note"])}</div>' if r.get("note") else ""
        link = f'<a href="{escape(href)}">{escape(href.split("#")[0].removesuffix(".html"))}</a>' if href else ""
        body.append(
            f'<tr><td class="{_CLAIM_CLASS.get(r["verdict"], "na")}">{escape(r["verdict"])}</td>'
            f'<td>{escape(r["claim"])} <span class="id">{escape(str(r["claim_id"]))}, L{escape(str(r.get("line", "")))}'
            f"</span>{note}</td>"
            f'<td class="num">{escape(c["paper"])}</td><td class="num">{escape(c["reproduced"])}</td>'
            f'<td>{escape(c["robustness"])}</td><td>{link}</td></tr>')
    return f'<table class="claims"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


def _home_sections(allrows: pd.DataFrame) -> dict[str, str]:
    """notebook -> the section its figures and conclusion appear in (the group with most of its result rows),
    so no figure set is shown twice."""
    home = {}
    for stem, g in allrows.groupby("notebook", sort=True):
        res = g[g["row_class"] == "result"]
        counts = (res if len(res) else g)["group"].value_counts()
        order = [*PAPERS, REGRESSION, OTHER]
        home[stem] = max(counts.index, key=lambda k: (counts[k], -order.index(k) if k in order else -99))
    return home


def build_readme(out_dir: str | Path, seed: int | None = None, fast: bool = False,
                 sweep_summary: pd.DataFrame | None = None, n_seeds: int = 1,
                 notebook_dir: str | Path | None = None) -> Path:
    """Write ``<out_dir>/README.md``: the landing page (:func:`build_index`) as Markdown.

    "How to read" first, the list of every notebook, then one section per paper (its one short name,
    :data:`ilocalg.papers.PAPERS`): the one-line summary and the table of its claims (``claims.csv``), its
    notebooks' key figures (each notebook's once, captioned with the figure's title and linked to it in the
    executed notebook), then the comparison rows collapsed by class with a scoreboard that counts results
    only; then the regression checks and other references.

    With ``sweep_summary`` (:func:`ilocalg.workflow.sweep.aggregate` over ``n_seeds`` seeds) every row gains
    ``n``, ``mean`` and the 95 % interval (clipped to the quantity's range, ``ci_clipped``).
    """
    out_dir = Path(out_dir)
    sweep = sweep_summary is not None and n_seeds > 1
    lines = ["# Reproduced results", "", "The same as a web page, with figures: [index.html](index.html). "
             "Claims ledger: [claims.csv](claims.csv).", "", *how_to_read(seed, fast, n_seeds, sweep)]
    nbs = notebooks(out_dir, notebook_dir)
    allrows = comparison_rows(out_dir, sweep_summary, n_seeds)
    ledger = read_ledger(out_dir)
    glance = [f"- **{PAPERS[k]}**: {claims_summary(ledger[ledger['paper'] == k])}" for k in PAPERS
              if not ledger.empty and (ledger["paper"] == k).any()]
    if glance:
        lines += ["## At a glance: what holds", "", *glance, ""]
    if allrows.empty and ledger.empty:
        lines.append("No comparison tables were written.\n")
    home = _home_sections(allrows) if not allrows.empty else {}
    cols = _row_columns(allrows) if not allrows.empty else []
    for key, title, blurb, rows in _sections(allrows, ledger):
        lines += [f"## {title}", "", blurb, ""]
        part = ledger[ledger["paper"] == key] if key in PAPERS else ledger.iloc[0:0]
        if len(part):
            lines += [f"**{claims_summary(part)}**", "", *_claims_markdown(part)]
        for stem in sorted(s for s, h in home.items() if h == key):
            figs = _figures(out_dir, stem)
            if figs:
                lines.append(" ".join(f'<a href="{f.href}"><img src="{f.src}" width="400" alt="{f.title}" '
                                      f'title="{f.title}"></a>' for f in figs))
                lines.append("")
        if rows.empty:
            continue
        board = _scoreboard(rows)
        board["notebook"] = [f"[{s}]({s}.html)" for s in board["notebook"]]
        counted = rows[~rows["row_class"].isin([rc for rc, _ in _APART])]
        lines += ["<details><summary>Comparison rows: results " f"({len(counted)} rows)</summary>", "",
                  _markdown(board, index=False), _markdown(counted[cols], index=False), "</details>", ""]
        for heading, apart in _apart(rows, allrows, cols):
            lines += [f"<details><summary>{heading} ({len(apart)} rows)</summary>", "",
                      _markdown(apart, index=False), "</details>", ""]
    if nbs:
        lines += ["## Notebooks", ""] + [f"- [{stem}]({link}): {title}" for stem, title, link in nbs] + [""]
    path = out_dir / "README.md"
    path.write_text("\n".join(lines))
    return path


_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1150px;margin:2em auto;
padding:0 1em;color:#222;line-height:1.45}
h1{margin-bottom:.2em} h2{border-bottom:2px solid #0072B2;padding-bottom:.2em;margin-top:2em}
.cite{color:#555;font-size:.9em} .howto{background:#f7f9fb;border:1px solid #dde5ee;padding:.2em 1em;font-size:.93em}
table{border-collapse:collapse;font-size:.85em;margin:.6em 0} th,td{border:1px solid #ddd;padding:3px 6px;
vertical-align:top} th{background:#f3f6f9} td.num{text-align:right;white-space:nowrap}
.agrees{background:#d9f0e3} .close{background:#fff2cc} .differs{background:#f8d7d2} .na{background:#eee}
table.claims td:first-child{font-weight:600;white-space:nowrap} .id{color:#777;font-size:.85em}
.note{color:#555;font-size:.85em;margin-top:.2em} .summary{font-weight:600;font-size:1.02em}
.thumbs{display:flex;flex-wrap:wrap;gap:14px;margin:.8em 0}
.thumbs figure{margin:0;width:520px} .thumbs img{width:520px;border:1px solid #ccc}
.thumbs figcaption{font-size:.85em;color:#333}
.why{background:#f7f7f7;border-left:4px solid #0072B2;padding:.3em 1em;margin:.6em 0;font-size:.92em}
details{margin:.6em 0} summary{cursor:pointer;font-weight:600}
nav a{margin-right:1em} ul.nbs{columns:2;font-size:.92em}
"""


def _html_table(df: pd.DataFrame, classes: dict[int, str] | None = None, html_cols: tuple[str, ...] = ()) -> str:
    """An HTML table of ``df`` (cells escaped, except the columns ``html_cols``, which hold HTML)."""
    from html import escape

    raw = {i for i, c in enumerate(df.columns) if c in html_cols}
    head = "".join(f"<th>{escape(str(c))}</th>" for c in df.columns)
    body = []
    for i, row in enumerate(df.itertuples(index=False)):
        cls = f' class="{classes[i]}"' if classes and classes.get(i) else ""
        cells = []
        for j, v in enumerate(row):
            num = isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
            cells.append(f"<td>{v}</td>" if j in raw else f'<td class="num">{escape(_fmt(v))}</td>' if num
                         else f"<td>{escape(_fmt(v))}</td>")
        body.append(f"<tr{cls}>{''.join(cells)}</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def build_index(out_dir: str | Path, seed: int | None = None, fast: bool = False,
                sweep_summary: pd.DataFrame | None = None, n_seeds: int = 1,
                notebook_dir: str | Path | None = None) -> Path:
    """Write the landing page ``<out_dir>/index.html`` (the sections of :func:`build_readme` as a web page).

    "How to read this page" first; then per paper the one-line summary of what holds and what does not,
    the claims table (verdict coloured, paper vs reproduced with its interval, robustness, a link to the
    notebook section that decides it), the conclusions and key figures of its notebooks, and the comparison
    rows collapsed by class. Everything is relative to ``out_dir``, so the folder can be copied or served.
    """
    from html import escape

    import mistune

    out_dir = Path(out_dir)
    nb_dir = Path(notebook_dir) if notebook_dir else None
    sweep = sweep_summary is not None and n_seeds > 1
    allrows = comparison_rows(out_dir, sweep_summary, n_seeds)
    ledger = read_ledger(out_dir)
    sections = _sections(allrows, ledger)
    home = _home_sections(allrows) if not allrows.empty else {}
    nbs = notebooks(out_dir, nb_dir)
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             "<title>iLoc toolkit: reproduced results</title>", f"<style>{_CSS}</style></head><body>",
             "<h1>iLoc toolkit: reproduced results</h1>",
             "<nav>" + "".join(f'<a href="#{k}">{escape(t)}</a>' for k, t, _, _ in sections)
             + '<a href="#notebooks">Notebooks</a><a href="claims.csv">claims.csv</a>'
               '<a href="README.md">README.md</a><a href="provenance.json">provenance.json</a></nav>',
             f'<div class="howto">{mistune.html(chr(10).join(how_to_read(seed, fast, n_seeds, sweep)))}</div>']
    glance = [(k, t, claims_summary(ledger[ledger["paper"] == k])) for k, t, _, _ in sections
              if k in PAPERS and not ledger.empty and (ledger["paper"] == k).any()]
    if glance:
        parts.append('<section id="glance"><h2>At a glance: what holds</h2><table><tbody>' + "".join(
            f'<tr><td><a href="#{k}">{escape(t)}</a></td><td>{escape(line)}</td></tr>' for k, t, line in glance)
            + "</tbody></table></section>")
    if not sections:
        parts.append("<p>No comparison tables were written.</p>")
    cols = _row_columns(allrows) if not allrows.empty else []
    for key, title, blurb, rows in sections:
        parts += [f'<section id="{key}"><h2>{escape(title)}</h2>', f'<p class="cite">{escape(blurb)}</p>']
        part = ledger[ledger["paper"] == key] if key in PAPERS else ledger.iloc[0:0]
        if len(part):
            parts += [f'<p class="summary">{escape(claims_summary(part))}</p>', _claims_html(part)]
        for stem in sorted(s for s, h in home.items() if h == key):
            why = _conclusion(out_dir, stem, nb_dir)
            if why:
                parts.append(f'<details class="why"><summary>Where and why the numbers differ '
                             f"({escape(stem)})</summary>{mistune.html(why)}</details>")
            figs = _figures(out_dir, stem)
            if figs:
                parts.append('<div class="thumbs">' + "".join(
                    f'<figure><a href="{escape(f.href)}"><img src="{f.src}" alt="{escape(f.title)}">'
                    f"</a><figcaption>{escape(f.title)} ({escape(stem)})</figcaption></figure>" for f in figs)
                    + "</div>")
        if not rows.empty:
            board = _scoreboard(rows)
            board["notebook"] = [f'<a href="{s}.html">{escape(s)}</a>' for s in board["notebook"]]
            counted = rows[~rows["row_class"].isin([rc for rc, _ in _APART])]
            classes = {i: {"agrees": "agrees", "close": "close", "differs": "differs"}.get(v, "")
                       for i, v in enumerate(counted["verdict"])}
            parts += [f"<details><summary>Comparison rows: results ({len(counted)} rows)</summary>",
                      "<h3>Scoreboard (results only)</h3>", _html_table(board, html_cols=("notebook",)),
                      _html_table(counted[cols].reset_index(drop=True), classes), "</details>"]
            for heading, apart in _apart(rows, allrows, cols):
                parts += [f"<details><summary>{escape(heading)} ({len(apart)} rows)</summary>",
                          _html_table(apart), "</details>"]
        parts.append("</section>")
    if nbs:
        parts.append('<section id="notebooks"><h2>Notebooks</h2><ul class="nbs">' + "".join(
            f'<li><a href="{escape(link)}">{escape(stem)}</a>: {escape(title)}</li>' for stem, title, link in nbs)
            + "</ul></section>")
    parts.append("</body></html>")
    path = out_dir / "index.html"
    path.write_text("\n".join(parts) + "\n")
    return path


def sha256_file(path: str | Path) -> str:
    """Hex sha256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _git_commit(repo: Path) -> str | None:
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=repo, capture_output=True, text=True,
                             check=True, timeout=10)
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=repo,
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return out.stdout.strip() + ("-dirty" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return None


PROVENANCE_PACKAGES = ("numpy", "pandas", "scipy", "scikit-learn", "filterpy", "matplotlib", "papermill",
                       "pyarrow", "opencv-python-headless", "dask", "iloc-toolkit")


def write_provenance(out_dir: str | Path, repo: str | Path, seed: int, fast: bool,
                     inputs: list[str | Path], notebooks: list[str], n_seeds: int = 1) -> Path:
    """Write ``provenance.json``: git commit, seed, mode, package versions, input sha256s, and the sha256 of every
    table the run wrote (``tables_sha256``, by file name): two runs wrote byte-identical tables exactly when these
    maps are equal, which compares two full reproduces without keeping both folders."""
    versions = {}
    for p in PROVENANCE_PACKAGES:
        try:
            versions[p] = metadata.version(p)
        except metadata.PackageNotFoundError:
            versions[p] = None
    files = {}
    for f in sorted({str(Path(f)) for f in inputs}):
        fp = Path(f)
        if fp.is_file():
            files[f] = sha256_file(fp)
    prov = {
        "git_commit": _git_commit(Path(repo)),
        "seed": seed,
        "n_seeds_for_intervals": n_seeds,
        "fast": fast,
        "python": platform.python_version(),
        "packages": versions,
        "notebooks": notebooks,
        "input_files_sha256": files,
        "tables_sha256": {t.name: sha256_file(t) for t in sorted((Path(out_dir) / "tables").glob("*.csv"))},
    }
    path = Path(out_dir) / "provenance.json"
    path.write_text(json.dumps(prov, indent=2, sort_keys=True) + "\n")
    return path
