"""Published reference values beside reproduced ones: the comparison rows every experiment returns.

A comparison table has one row per paper result and the columns :data:`COMPARISON_COLUMNS`. Paper
values enter only through :func:`paper_ref` / :func:`comparison_table`, labelled as the reference they
are, and are never used to compute anything.
"""

from __future__ import annotations

import math

import pandas as pd

__all__ = [
    "COMPARISON_COLUMNS",
    "PAPER_REF_COLUMNS",
    "AGREE_REL",
    "CLOSE_REL",
    "paper_ref",
    "agreement",
    "comparison_table",
]

#: Columns of a comparison table (one row per paper result).
COMPARISON_COLUMNS = (
    "paper",
    "item",
    "quantity",
    "unit",
    "paper_value",
    "reproduced_value",
    "agreement",
)

#: Columns that make a table a comparison table: rows built with :func:`paper_ref` (``agreement`` is
#: added by :func:`comparison_table` and recomputed when missing).
PAPER_REF_COLUMNS = ("paper", "item", "quantity", "paper_value", "reproduced_value")

#: Relative differences below these bounds count as "agrees" and "close".
AGREE_REL = 0.10
CLOSE_REL = 0.35


def paper_ref(paper: str, item: str, quantity: str, paper_value: float, reproduced_value: float,
              unit: str = "", note: str = "") -> dict:
    """One comparison row: the paper's published value (a reference) beside the reproduced one.

    Parameters
    ----------
    paper : str
        Short paper label, e.g. ``"i-Loc thesis"``.
    item : str
        The figure or table, e.g. ``"Fig 3"``.
    quantity : str
        What is compared, e.g. ``"RADAR median error (k=5)"``.
    paper_value : float
        The published value (reference only; never used to compute anything).
    reproduced_value : float
        The value this toolkit computed from data.
    unit, note : str
    """
    return {
        "paper": paper,
        "item": item,
        "quantity": quantity,
        "unit": unit,
        "paper_value": float(paper_value),
        "reproduced_value": float(reproduced_value),
        "note": note,
    }


def agreement(paper_value: float, reproduced_value: float) -> str:
    """Classify a reproduced value against the paper's.

    ``agrees`` when the relative difference is within 10 %, ``close`` within 35 %, otherwise
    ``differs``; the relative difference in percent follows in brackets.
    """
    p = float(paper_value)
    r = float(reproduced_value)
    if not (math.isfinite(p) and math.isfinite(r)):
        return "n/a"
    if p == 0.0:
        return "agrees" if r == 0.0 else "differs (paper 0)"
    rel = (r - p) / abs(p)
    label = "agrees" if abs(rel) <= AGREE_REL else "close" if abs(rel) <= CLOSE_REL else "differs"
    return f"{label} ({rel * 100:+.0f} %)"


def comparison_table(rows: list[dict]) -> pd.DataFrame:
    """DataFrame of :func:`paper_ref` rows with the ``agreement`` column computed."""
    if not rows:
        raise ValueError("comparison_table needs at least one row")
    df = pd.DataFrame(rows)
    missing = [c for c in ("paper", "item", "quantity", "paper_value", "reproduced_value") if c not in df]
    if missing:
        raise ValueError(f"comparison rows lack {missing}; build them with paper_ref()")
    if "unit" not in df:
        df["unit"] = ""
    if "note" not in df:
        df["note"] = ""
    df["agreement"] = [agreement(p, r) for p, r in zip(df["paper_value"], df["reproduced_value"], strict=True)]
    extra = [c for c in df.columns if c not in COMPARISON_COLUMNS and c != "note"]
    return df[list(COMPARISON_COLUMNS) + extra + ["note"]]
