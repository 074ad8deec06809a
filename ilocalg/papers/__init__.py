"""The five papers, their published values beside reproduced ones, and the readings of each paper.

A comparison table has one row per paper result and the columns :data:`COMPARISON_COLUMNS`. Paper
values enter only through :func:`paper_ref` / :func:`comparison_table`, labelled as the reference they
are, and are never used to compute anything.

A readings table (:func:`readings_table`, columns :data:`READINGS_COLUMNS`) has one row per modelling
choice an experiment makes: the paper's line, what the text says, what the code does and the source of
any value the paper does not give.

Each paper has one short name, used everywhere (comparison rows, reports, notebooks):
:data:`PAPERS` maps a key to it, :data:`PAPER_CITATIONS` to the full reference.

References
----------
Chiu, P.-J. (2013). Implement an Integrated Indoor Positioning System (i-Loc). M.S. thesis,
National Chiao Tung University.
Liao, C.-K., Chiang, K.-W., Zhou, Z.-M., Li, C.-H. (2016). Using the on-line smoothing and
constraint algorithms to improve the accuracy of pedestrian indoor navigation.
Yeh, C.-H., Huang, W.-L. (advisor Huang, C.-C.) (undated; cites work up to 2011). Positioning by combining
images and inertial sensors. Teaching report, National Kaohsiung University of Applied Sciences.
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
"""

from __future__ import annotations

import math

import pandas as pd

__all__ = [
    "PAPERS",
    "PAPER_CITATIONS",
    "paper_key",
    "SELF_COMPARISON",
    "is_self_comparison",
    "READINGS_COLUMNS",
    "reading",
    "readings_table",
    "COMPARISON_COLUMNS",
    "PAPER_REF_COLUMNS",
    "ROW_CLASSES",
    "row_class_of",
    "physical_range",
    "clip_interval",
    "AGREE_REL",
    "CLOSE_REL",
    "paper_ref",
    "agreement",
    "comparison_table",
    "claims_of",
    "all_claims",
]

#: One short name per paper, used everywhere: key -> short name.
PAPERS = {
    "iloc": "i-Loc (Chiu 2013)",
    "liao": "Liao et al. 2016",
    "survey": "Yeh & Huang survey",
    "pso": "PSO (Chao 2008)",
    "luo": "Luo et al. 2017",
}

#: key -> full reference (and the plain-text copy in the shared papers folder).
PAPER_CITATIONS = {
    "iloc": "Po-Jung Chiu, \"Implement an Integrated Indoor Positioning System\" (i-Loc), M.S. thesis, "
            "National Chiao Tung University, 2013",
    "liao": "Liao, Chiang, Zhou, Li, \"Using the on-line smoothing and constraint algorithms to improve the "
            "accuracy of pedestrian indoor navigation\", 2016",
    "survey": "Yeh Chi-Hsien, Huang Wei-Li (advisor Huang Ching-Chun), \"Positioning by combining images and "
              "inertial sensors\", teaching report, National Kaohsiung University of Applied Sciences, undated",
    "pso": "Chao Shih-Hsien, \"Pedestrian navigation based on particle swarm optimization\", M.S. thesis, "
           "Tunghai University, 2008",
    "luo": "Luo Siqi et al., \"Indoor positioning technology based on location fingerprint and pedestrian "
           "track\", Computer Systems & Applications, 2017",
}

# Earlier labels of the same papers (and of works the survey reports), mapped to their key.
_PAPER_ALIASES = {
    "iloc": ("i-loc", "chiu"),
    "liao": ("liao", "smartphone ins"),
    "survey": ("yeh", "survey", "hartmann", "movips"),
    "pso": ("pso", "chao", "趙士賢", "003"),
    "luo": ("luo", "罗思奇", "羅思奇"),
}


def paper_key(label: str) -> str | None:
    """Key of :data:`PAPERS` that a paper label names, or ``None`` for a label naming none of them.

    Accepts the short names themselves and earlier spellings (``"i-Loc thesis"``, ``"PSO thesis (003)"``,
    ``"罗思奇 et al. 2017"``, ``"Hartmann et al. 2010 (survey sec. 5)"``).
    """
    text = str(label).strip().lower()
    for key, name in PAPERS.items():
        if text == name.lower():
            return key
    for key, aliases in _PAPER_ALIASES.items():
        if any(a in text for a in aliases):
            return key
    return None


#: Label of comparison rows that set the toolkit beside an earlier, independent measurement of its own
#: (a regression check, not agreement with a paper).
SELF_COMPARISON = "independent re-measurement"

_SELF_MARKERS = ("re-measurement", "remeasurement", "earlier measurement", "toolkit", "ilocalg")


def is_self_comparison(label: str) -> bool:
    """True for a comparison label naming the toolkit's own earlier measurement (:data:`SELF_COMPARISON`)."""
    text = str(label).lower()
    return any(m in text for m in _SELF_MARKERS)


#: Columns of a readings table (one row per modelling choice).
READINGS_COLUMNS = ("choice", "paper_line", "text_says", "code_does", "source")


def reading(choice: str, paper_line: str, text_says: str, code_does: str, source: str = "") -> dict:
    """One readings row: a modelling choice, where the paper speaks of it and what the code does.

    Parameters
    ----------
    choice : str
        The modelling choice, e.g. ``"step length model"``.
    paper_line : str
        Where the paper speaks, e.g. ``"i-Loc (Chiu 2013), L295"``; ``""`` where it is silent.
    text_says : str
        What the paper's text says (or ``"silent"``).
    code_does : str
        What the code does.
    source : str
        Source of a value the paper does not give (a cited measurement, a sweep), else ``""``.
    """
    return {"choice": choice, "paper_line": paper_line, "text_says": text_says, "code_does": code_does,
            "source": source}


def readings_table(rows: list[dict]) -> pd.DataFrame:
    """DataFrame of readings rows, columns :data:`READINGS_COLUMNS` first (extra columns kept after).

    Parameters
    ----------
    rows : list of dict
        Rows with the keys of :data:`READINGS_COLUMNS` (build them with :func:`reading` or as dicts).

    Raises
    ------
    ValueError
        No rows, a row lacking a column, a non-string value, or an empty ``choice``, ``text_says`` or
        ``code_does`` (the message names the row and column).
    """
    rows = list(rows)
    if not rows:
        raise ValueError("readings_table needs at least one row (one per modelling choice)")
    for i, row in enumerate(rows):
        if not isinstance(row, dict):
            raise ValueError(f"readings row {i}: expected a dict, got {type(row).__name__}")
        missing = [c for c in READINGS_COLUMNS if c not in row]
        if missing:
            raise ValueError(f"readings row {i} ({row.get('choice', '?')!r}): lacks column(s) {missing}")
        for c in READINGS_COLUMNS:
            if not isinstance(row[c], str):
                raise ValueError(f"readings row {i}, column {c}: expected a string, got {row[c]!r}")
        for c in ("choice", "text_says", "code_does"):
            if not row[c].strip():
                raise ValueError(f"readings row {i}, column {c}: empty (say what the paper/code does)")
    df = pd.DataFrame(rows)
    extra = [c for c in df.columns if c not in READINGS_COLUMNS]
    return df[list(READINGS_COLUMNS) + extra].reset_index(drop=True)


#: Columns of a comparison table (one row per paper result).
COMPARISON_COLUMNS = (
    "paper",
    "item",
    "quantity",
    "unit",
    "paper_value",
    "reproduced_value",
    "agreement",
    "row_class",
)

#: Columns that make a table a comparison table: rows built with :func:`paper_ref` (``agreement`` is
#: added by :func:`comparison_table` and recomputed when missing).
PAPER_REF_COLUMNS = ("paper", "item", "quantity", "paper_value", "reproduced_value")

#: Relative differences below these bounds count as "agrees" and "close".
AGREE_REL = 0.10
CLOSE_REL = 0.35


#: Classes of comparison rows. Only ``result`` rows are counted on the scoreboard; the others are shown
#: apart: ``set by input`` (the reproduced value is an input of the simulation, e.g. a noise level scaled
#: to the paper's value, so agreement proves nothing), ``alternative reading`` (another reading of the
#: text, shown beside the default row it replaces, named in ``replaces``), ``regression check`` (the
#: toolkit against an earlier measurement of its own, :data:`SELF_COMPARISON`).
ROW_CLASSES = ("result", "set by input", "alternative reading", "regression check")


def paper_ref(paper: str, item: str, quantity: str, paper_value: float, reproduced_value: float,
              unit: str = "", note: str = "", *, row_class: str = "result",
              replaces: tuple[str, str] | str | None = None) -> dict:
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
    row_class : str
        One of :data:`ROW_CLASSES`; ``"result"`` (counted) unless the row compares an input with itself
        (``"set by input"``), is an alternative reading (``"alternative reading"``, with ``replaces``) or
        a regression check.
    replaces : (item, quantity) or quantity, optional
        For an alternative reading: the default row it replaces (a bare quantity means the same item).

    Raises
    ------
    ValueError
        An unknown ``row_class``, or ``replaces`` given for a row that is not an alternative reading.
    """
    if row_class not in ROW_CLASSES:
        raise ValueError(f"paper_ref {quantity!r}: row_class {row_class!r} is not one of {ROW_CLASSES}")
    if replaces is not None and row_class != "alternative reading":
        raise ValueError(f"paper_ref {quantity!r}: replaces= is only for row_class='alternative reading'")
    row = {
        "paper": paper,
        "item": item,
        "quantity": quantity,
        "unit": unit,
        "paper_value": float(paper_value),
        "reproduced_value": float(reproduced_value),
        "note": note,
        "row_class": row_class,
    }
    if replaces is not None:
        r_item, r_quantity = (item, replaces) if isinstance(replaces, str) else replaces
        row["replaces_item"], row["replaces_quantity"] = str(r_item), str(r_quantity)
    return row


def row_class_of(row: dict | pd.Series) -> str:
    """The row class of a comparison row: its ``row_class`` when set, else ``regression check`` for a
    :data:`SELF_COMPARISON` label and ``result`` otherwise (rows written before row classes existed)."""
    rc = row.get("row_class", "")
    if isinstance(rc, str) and rc.strip():
        if rc not in ROW_CLASSES:
            raise ValueError(f"comparison row {row.get('quantity', '?')!r}: row_class {rc!r} is not one of "
                             f"{ROW_CLASSES}")
        return rc
    return "regression check" if is_self_comparison(row.get("paper", "")) else "result"


_NONNEG_UNITS = {"m", "cm", "mm", "km", "s", "ms", "min", "h", "hz", "m^2", "m2", "points", "steps", "count",
                 "counts", "aps", "walks", "scans", "samples", "ratio", "x", "m/s", "px", "pixel", "pixels"}
_SIGNED_WORDS = ("difference", " diff", "bias", "offset", "change", "improvement", "gain", " - ", "drift",
                 "rho", "correlation", "slope", "log", "minus", "signed", "mean error x", "mean error y")


def physical_range(unit: str, quantity: str = "") -> tuple[float, float]:
    """The physically possible range of a quantity, from its unit: ``(-inf, inf)`` when unknown.

    Lengths, durations, rates, counts and ratios are ``>= 0``; a percentage lies in ``[0, 100]``; a
    probability (unit ``"probability"`` or ``"p"``) in ``[0, 1]``. A quantity whose name says it is
    signed (a difference, bias, offset, change, improvement, correlation, slope ...) keeps the whole
    real line, as does any unit not listed (degrees, dB, dBm, m/s^2: signed or wrapped).
    """
    u = str(unit).strip().lower()
    q = f" {str(quantity).lower()} "
    if any(w in q for w in _SIGNED_WORDS):
        return -math.inf, math.inf
    if u in ("%", "percent", "pct"):
        return 0.0, 100.0
    if u in ("probability", "p", "share", "fraction"):
        return 0.0, 1.0
    if u in _NONNEG_UNITS:
        return 0.0, math.inf
    return -math.inf, math.inf


def clip_interval(lo: float, hi: float, unit: str, quantity: str = "") -> tuple[float, float, bool]:
    """``(lo, hi)`` clipped to :func:`physical_range`, and whether clipping changed it (NaNs pass)."""
    a, b = physical_range(unit, quantity)
    clo = min(max(lo, a), b) if math.isfinite(lo) else lo
    chi = max(min(hi, b), a) if math.isfinite(hi) else hi
    clipped = (math.isfinite(lo) and clo != lo) or (math.isfinite(hi) and chi != hi)
    return clo, chi, bool(clipped)


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
    df["row_class"] = [row_class_of(r) for r in df.to_dict("records")]
    for c in ("replaces_item", "replaces_quantity"):
        if c in df:
            df[c] = ["" if not isinstance(v, str) else v for v in df[c]]
    df["agreement"] = [agreement(p, r) for p, r in zip(df["paper_value"], df["reproduced_value"], strict=True)]
    extra = [c for c in df.columns if c not in COMPARISON_COLUMNS and c != "note"]
    return df[list(COMPARISON_COLUMNS) + extra + ["note"]]


def claims_of(key: str) -> tuple:
    """The claims a paper makes (:class:`ilocalg.papers.claims.Claim`), declared in ``ilocalg/papers/<key>.py``.

    Raises
    ------
    ValueError
        ``key`` is not one of :data:`PAPERS`.
    """
    import importlib

    if key not in PAPERS:
        raise ValueError(f"unknown paper {key!r}; one of {sorted(PAPERS)}")
    try:
        mod = importlib.import_module(f"ilocalg.papers.{key}")
    except ModuleNotFoundError as exc:
        if exc.name != f"ilocalg.papers.{key}":
            raise
        return ()
    claims = tuple(getattr(mod, "CLAIMS", ()))
    bad = [c.id for c in claims if c.paper != key]
    if bad:
        raise ValueError(f"ilocalg/papers/{key}.py: claims {bad} name another paper")
    return claims


def all_claims() -> tuple:
    """Every paper's claims, in :data:`PAPERS` order; claim ids are unique."""
    out = tuple(c for key in PAPERS for c in claims_of(key))
    ids = [c.id for c in out]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise ValueError(f"duplicate claim ids: {dup}")
    return out
