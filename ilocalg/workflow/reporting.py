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
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.papers import AGREE_REL, CLOSE_REL, PAPER_REF_COLUMNS, comparison_table

__all__ = [
    "Report",
    "write_table",
    "build_readme",
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


def build_readme(out_dir: str | Path, seed: int | None = None, fast: bool = False,
                 sweep_summary: pd.DataFrame | None = None, n_seeds: int = 1) -> Path:
    """Write ``<out_dir>/README.md`` from every comparison table under ``<out_dir>/tables``.

    With ``sweep_summary`` (the output of :func:`ilocalg.workflow.sweep.aggregate` over ``n_seeds`` seeds),
    every row gains ``n``, ``mean`` and the 95 % confidence interval of its reproduced value, and
    ``agreement`` says where the paper's value lies: inside the interval, beside it, or far off.
    Rows the sweep did not cover keep ``n`` = 1 and the single-run classification.
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
    lines = [
        "# Reproduced results",
        "",
        "Written by `python -m ilocalg reproduce`; every row comes from a comparison table a notebook",
        "wrote under `tables/`. `paper_value` is the published reference; `reproduced_value` is computed",
        "by ilocalg from data in the notebook's run (the seed below).",
        "",
    ]
    if sweep_summary is not None and n_seeds > 1:
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
    if frames:
        allrows = pd.concat(frames, ignore_index=True)
        cols = ["paper", "item", "quantity", "unit", "paper_value", "reproduced_value"]
        if sweep_summary is not None and n_seeds > 1 and not sweep_summary.empty:
            keys = ["paper", "item", "quantity", "unit"]
            agg = sweep_summary.copy()
            for k in keys:
                agg[k] = ["" if pd.isna(v) else str(v) for v in agg[k]]
                allrows[k] = ["" if pd.isna(v) else str(v) for v in allrows[k]]
            agg = agg.drop_duplicates(subset=keys)[keys + ["n", "mean", "ci95_low", "ci95_high", "ci_agreement"]]
            allrows = allrows.merge(agg, on=keys, how="left", validate="many_to_one")
            single = allrows["n"].isna()
            allrows.loc[single, "n"] = 1
            allrows.loc[single, "mean"] = allrows.loc[single, "reproduced_value"]
            allrows["agreement"] = allrows["ci_agreement"].where(~single, allrows["agreement"])
            allrows["n"] = allrows["n"].astype(int)
            for c in ("ci95_low", "ci95_high"):
                allrows[c] = ["" if pd.isna(v) else v for v in allrows[c]]
            cols += ["n", "mean", "ci95_low", "ci95_high"]
        cols += ["agreement", "table"]
        lines.append(_markdown(allrows[cols], index=False))
    else:
        lines.append("No comparison tables were written.\n")
    path = out_dir / "README.md"
    path.write_text("\n".join(lines))
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
