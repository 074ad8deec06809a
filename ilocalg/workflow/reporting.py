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
    "Report",
    "write_table",
    "build_readme",
    "build_index",
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


#: Scoreboard classes: where a paper's value lies against the reproduced one.
VERDICTS = ("inside", "beside", "far off", "n/a")
_VERDICT_OF = {"inside CI": "inside", "agrees": "inside", "beside CI": "beside", "close": "beside",
               "far off": "far off", "differs": "far off"}


def verdict(agreement_text: str) -> str:
    """Scoreboard class of an ``agreement`` text: ``inside`` (the paper's value inside the 95 % CI, or
    within 10 % of a single run), ``beside`` (beside the CI, or within 35 %), ``far off`` or ``n/a``."""
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
    for lab in ("(none, static band, per_step fitness)", "(earlier reading: MA 2, signal band, walk total)")
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


def _conclusion(out_dir: Path, stem: str, notebook_dir: Path | None) -> str:
    """The notebook's ``## Conclusion`` markdown (executed copy first, else the paired source), or ``""``."""
    import nbformat

    for path in (out_dir / f"{stem}.ipynb", (notebook_dir / f"{stem}.ipynb") if notebook_dir else None):
        if path is None or not path.exists():
            continue
        try:
            cells = nbformat.read(path, as_version=4).cells
        except (OSError, ValueError):
            continue
        for c in cells:
            if c.cell_type == "markdown" and c.source.lstrip().lower().startswith("## conclusion"):
                return c.source.lstrip().split("\n", 1)[1].strip() if "\n" in c.source.strip() else ""
    return ""


def _figures(out_dir: Path, stem: str, limit: int = 4) -> list[str]:
    """Up to ``limit`` PNG figures of a notebook, in the order the notebook saves them (paths relative to out_dir)."""
    pngs = sorted((out_dir / "figures").glob(f"{stem}_*.png"))
    src = ""
    nb = out_dir / f"{stem}.ipynb"
    if nb.exists():
        src = nb.read_text()
    def pos(p: Path) -> tuple[int, str]:
        suffix = p.stem[len(stem) + 1:]
        i = src.find(suffix) if suffix else -1
        return (i if i >= 0 else len(src) + 1, p.name)
    return [f"figures/{p.name}" for p in sorted(pngs, key=pos)[:limit]]


def _sections(allrows: pd.DataFrame) -> list[tuple[str, str, str, pd.DataFrame]]:
    """(key, title, blurb, rows) per landing-page section: the five papers, then regression checks, others."""
    out = []
    for key, name in PAPERS.items():
        rows = allrows[allrows["group"] == key]
        if len(rows):
            out.append((key, name, PAPER_CITATIONS[key], rows))
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


def _intro(seed, fast: bool, n_seeds: int, sweep: bool) -> list[str]:
    lines = [
        "Written by `python -m ilocalg reproduce`; every row comes from a comparison table a notebook",
        "wrote under `tables/`. `paper_value` is the published reference; `reproduced_value` is computed",
        "by ilocalg from data in the notebook's run (the seed below).",
        "",
    ]
    if sweep:
        lines += [
            f"`n`, `mean` and `ci95` come from re-running each experiment over N = {n_seeds} simulation seeds",
            "(`reports/sweeps/summary.csv`); `agreement` then says whether the paper's value lies inside the",
            "95 % confidence interval of the mean, beside it (within one interval width, or within 10 % of",
            "the mean) or far off. Experiments on real recordings do not depend on the seed and are not",
            "re-run: their rows, like any row without a sweep, keep n = 1, no interval and the single-run",
            f"classification (within {AGREE_REL:.0%} = agrees, within {CLOSE_REL:.0%} = close).",
            "",
        ]
    else:
        lines += [f"Agreement: within {AGREE_REL:.0%} = agrees, within {CLOSE_REL:.0%} = close, else differs.", ""]
    lines += [f"Seed: {seed}. Mode: {'fast (reduced data)' if fast else 'full'}. Seeds for intervals: N = {n_seeds}.",
              ""]
    return lines


def build_readme(out_dir: str | Path, seed: int | None = None, fast: bool = False,
                 sweep_summary: pd.DataFrame | None = None, n_seeds: int = 1) -> Path:
    """Write ``<out_dir>/README.md`` from every comparison table under ``<out_dir>/tables``.

    One section per paper (its one short name, :data:`ilocalg.papers.PAPERS`): a scoreboard per notebook
    (rows inside / beside / far off), the notebook's conclusion (where and why the numbers differ), its
    key figures as thumbnails linked to the executed notebook, and the full table collapsed; then the
    regression checks (the toolkit against an earlier measurement of its own) and other references.

    With ``sweep_summary`` (the output of :func:`ilocalg.workflow.sweep.aggregate` over ``n_seeds`` seeds),
    every row gains ``n``, ``mean`` and the 95 % confidence interval of its reproduced value, and
    ``agreement`` says where the paper's value lies: inside the interval, beside it, or far off.
    Rows the sweep did not cover keep ``n`` = 1 and the single-run classification.
    """
    out_dir = Path(out_dir)
    sweep = sweep_summary is not None and n_seeds > 1
    lines = ["# Reproduced results", "", *_intro(seed, fast, n_seeds, sweep)]
    allrows = comparison_rows(out_dir, sweep_summary, n_seeds)
    if allrows.empty:
        lines.append("No comparison tables were written.\n")
    else:
        lines += ["The same results as a web page, with figures: [index.html](index.html).", ""]
        cols = _row_columns(allrows)
        for _key, title, blurb, rows in _sections(allrows):
            lines += [f"## {title}", "", blurb, ""]
            board = _scoreboard(rows)
            board["notebook"] = [f"[{s}]({s}.html)" for s in board["notebook"]]
            lines.append(_markdown(board, index=False))
            for stem in sorted(rows["notebook"].unique()):
                figs = _figures(out_dir, stem)
                if figs:
                    lines.append(" ".join(f'<a href="{stem}.html"><img src="{f}" width="220" alt="{Path(f).stem}">'
                                          f"</a>" for f in figs))
                    lines.append("")
            counted = rows[~rows["row_class"].isin([rc for rc, _ in _APART])]
            lines += ["<details><summary>Full table " f"({len(counted)} rows)</summary>", "",
                      _markdown(counted[cols], index=False), "</details>", ""]
            for heading, part in _apart(rows, allrows, cols):
                lines += [f"<details><summary>{heading} ({len(part)} rows)</summary>", "",
                          _markdown(part, index=False), "</details>", ""]
    path = out_dir / "README.md"
    path.write_text("\n".join(lines))
    return path


_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1100px;margin:2em auto;
padding:0 1em;color:#222;line-height:1.45}
h1{margin-bottom:.2em} h2{border-bottom:2px solid #0072B2;padding-bottom:.2em;margin-top:2em}
.cite{color:#555;font-size:.9em} .meta{color:#555}
table{border-collapse:collapse;font-size:.85em;margin:.6em 0} th,td{border:1px solid #ddd;padding:3px 6px}
th{background:#f3f6f9} td.num{text-align:right}
.inside{background:#d9f0e3} .beside{background:#fff2cc} .faroff{background:#f8d7d2}
.thumbs{display:flex;flex-wrap:wrap;gap:10px;margin:.6em 0}
.thumbs figure{margin:0;width:250px} .thumbs img{width:250px;border:1px solid #ccc}
.thumbs figcaption{font-size:.75em;color:#555;word-break:break-all}
.why{background:#f7f7f7;border-left:4px solid #0072B2;padding:.3em 1em;margin:.6em 0;font-size:.92em}
details{margin:.6em 0} summary{cursor:pointer;font-weight:600}
nav a{margin-right:1em}
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
    """Write the landing page ``<out_dir>/index.html``: the sections of :func:`build_readme` as a web page.

    Each paper's section has its scoreboard, the conclusions of its notebooks (where and why the numbers
    differ), its key figures as thumbnails linked to the executed notebooks, and the full table collapsed.
    Everything is relative to ``out_dir``, so the folder can be copied or served as it is.
    """
    from html import escape

    import mistune

    out_dir = Path(out_dir)
    nb_dir = Path(notebook_dir) if notebook_dir else None
    sweep = sweep_summary is not None and n_seeds > 1
    allrows = comparison_rows(out_dir, sweep_summary, n_seeds)
    sections = _sections(allrows) if not allrows.empty else []
    intro = mistune.html("\n".join(_intro(seed, fast, n_seeds, sweep)))
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             "<title>iLoc toolkit: reproduced results</title>", f"<style>{_CSS}</style></head><body>",
             "<h1>iLoc toolkit: reproduced results</h1>",
             f'<div class="meta">{intro}</div>',
             "<nav>" + "".join(f'<a href="#{k}">{escape(t)}</a>' for k, t, _, _ in sections)
             + '<a href="README.md">README.md</a><a href="provenance.json">provenance.json</a></nav>']
    if not sections:
        parts.append("<p>No comparison tables were written.</p>")
    cols = _row_columns(allrows) if not allrows.empty else []
    for key, title, blurb, rows in sections:
        parts += [f'<section id="{key}"><h2>{escape(title)}</h2>', f'<p class="cite">{escape(blurb)}</p>']
        board = _scoreboard(rows)
        board["notebook"] = [f'<a href="{s}.html">{escape(s)}</a>' for s in board["notebook"]]
        parts += ["<h3>Scoreboard</h3>", _html_table(board, html_cols=("notebook",))]
        for stem in sorted(rows["notebook"].unique()):
            why = _conclusion(out_dir, stem, nb_dir)
            if why:
                parts.append(f'<details class="why"><summary>Where and why the numbers differ '
                             f"({escape(stem)})</summary>{mistune.html(why)}</details>")
            figs = _figures(out_dir, stem)
            if figs:
                parts.append('<div class="thumbs">' + "".join(
                    f'<figure><a href="{stem}.html"><img src="{f}" alt="{escape(Path(f).stem)}">'
                    f"</a><figcaption>{escape(Path(f).stem)}</figcaption></figure>" for f in figs) + "</div>")
        counted = rows[~rows["row_class"].isin([rc for rc, _ in _APART])]
        classes = {i: {"inside": "inside", "beside": "beside", "far off": "faroff"}.get(v, "")
                   for i, v in enumerate(counted["verdict"])}
        parts += [f"<details><summary>Full table ({len(counted)} rows)</summary>",
                  _html_table(counted[cols].reset_index(drop=True), classes), "</details>"]
        for heading, part in _apart(rows, allrows, cols):
            parts += [f"<details><summary>{escape(heading)} ({len(part)} rows)</summary>",
                      _html_table(part), "</details>"]
        parts.append("</section>")
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
    """Write ``provenance.json``: git commit, seed, mode, package versions, input sha256s."""
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
    }
    path = Path(out_dir) / "provenance.json"
    path.write_text(json.dumps(prov, indent=2, sort_keys=True) + "\n")
    return path
