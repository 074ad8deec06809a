"""Claims as data: what a paper claims, the statistic that tests it, and an honest verdict.

A claim is one statement of substance a paper makes in its text or tables (not one table cell): a value
("RADAR's median error is 4.5 m"), an ordering ("Horus beats RADAR"), an improvement or ratio ("the
Kalman filter lowers the Wi-Fi error from 5.15 m to 2.82 m"), a trend ("the error falls with the window
size up to 20 s") or a consistency check of the paper's own numbers (a table against its text).

Each paper declares its claims once, as data, in ``ilocalg/papers/<key>.py`` (``CLAIMS``, a tuple of
:class:`Claim`). A claim names the reproduced scalars it needs with :func:`M` (an experiment's
comparison row, ``sweep_*`` row or ``measures`` row, identified by its quantity and item) and combines
them with a :class:`Stat` (:func:`value`, :func:`ratio`, :func:`diff`, :func:`spearman`, or any
function). The claims step evaluates the statistic per seed, gives it a Student-t 95 % interval and
judges it (:func:`judge`):

- an ordering, improvement, ratio or trend claim on the *direction* it asserts (``expect="<1"``: the
  statistic is below 1): ``reproduced`` when the whole interval is on the asserted side, ``partly``
  when the interval straddles the threshold, ``not reproduced`` when it lies wholly on the other side;
- a value claim (``expect="~"``) on agreement: ``reproduced`` when the paper's value lies inside the
  interval or within :data:`AGREE_REL` of the mean, ``partly`` within :data:`CLOSE_REL`, else
  ``not reproduced``;
- a consistency claim (the paper checked against its own printed numbers) is arithmetic, not a
  measurement: ``reproduced`` within :data:`AGREE_REL`, else ``not reproduced`` (a 15 % mismatch of
  the paper's own numbers is a contradiction, never ``partly``);
- a claim without a statistic is ``cannot be tested``, with the reason in ``untestable``.

Paper values enter only as labelled references and never feed a computation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.papers import PAPER_REF_COLUMNS, clip_interval

__all__ = [
    "KINDS",
    "VERDICTS",
    "AGREE_REL",
    "CLOSE_REL",
    "Ref",
    "M",
    "Stat",
    "value",
    "ratio",
    "diff",
    "spearman",
    "constant",
    "Assumption",
    "Claim",
    "lookup",
    "ResultIndex",
    "statistic_by_seed",
    "interval",
    "judge",
    "evaluate",
    "evaluate_claims",
    "CLAIM_COLUMNS",
    "claims_from_tables",
    "RESULT_COLUMNS",
    "tables_to_long",
    "claims_markdown",
    "rows_markdown",
]

#: Kinds of claim.
KINDS = ("value", "ordering", "improvement", "ratio", "trend", "consistency")
#: Verdicts, best first.
VERDICTS = ("reproduced", "partly", "not reproduced", "cannot be tested")
#: A value claim agrees within this relative difference ("reproduced") or within CLOSE_REL ("partly").
AGREE_REL = 0.10
CLOSE_REL = 0.35


@dataclass(frozen=True)
class Ref:
    """One reproduced scalar: a row of an experiment's result tables in the sweep's long format.

    Matches rows with this ``experiment`` and ``quantity``, and, when given, ``item`` and ``table``
    (``ilocalg.workflow.sweep.RESULT_COLUMNS``). Exactly one row per seed must match.
    """

    experiment: str
    quantity: str
    item: str | None = None
    table: str | None = None

    def __str__(self) -> str:
        where = "/".join(x for x in (self.table, self.item) if x)
        return f"{self.experiment}:{where + ':' if where else ''}{self.quantity}"


def M(experiment: str, quantity: str, item: str | None = None, table: str | None = None) -> Ref:
    """Shorthand for :class:`Ref` (a measured, reproduced scalar)."""
    return Ref(experiment, quantity, item, table)


@dataclass(frozen=True)
class Stat:
    """A statistic of reproduced scalars: ``fn(*values_of(refs)) -> float``."""

    refs: tuple[Ref, ...]
    fn: Callable[..., float]
    label: str
    unit: str = ""

    def __call__(self, *values: float) -> float:
        return float(self.fn(*values))


def value(a: Ref, unit: str = "") -> Stat:
    """The reproduced scalar itself."""
    return Stat((a,), lambda x: x, f"{a.quantity}", unit)


def ratio(a: Ref, b: Ref) -> Stat:
    """``a / b`` (e.g. fused error over Wi-Fi error: an improvement claim expects ``"<1"``)."""
    return Stat((a, b), lambda x, y: x / y if y != 0 else math.nan, f"{a.quantity} / {b.quantity}", "ratio")


def diff(a: Ref, b: Ref, unit: str = "") -> Stat:
    """``a - b`` (an ordering claim "a below b" expects ``"<0"``)."""
    return Stat((a, b), lambda x, y: x - y, f"{a.quantity} - {b.quantity}", unit)


def spearman(refs: Sequence[Ref], xs: Sequence[float]) -> Stat:
    """Spearman rank correlation of the values at ``refs`` with their abscissae ``xs`` (a trend claim:
    ``"<0"`` falls, ``">0"`` rises)."""
    refs = tuple(refs)
    xs = tuple(float(x) for x in xs)
    if len(refs) != len(xs) or len(refs) < 3:
        raise ValueError(f"spearman needs as many abscissae as refs and at least 3, got {len(refs)}, {len(xs)}")

    def rho(*v):
        from scipy.stats import spearmanr  # scipy.stats costs ~1 CPU-s to import: only when a claim is judged

        r = spearmanr(xs, v).statistic
        return float(r) if np.isfinite(r) else math.nan

    return Stat(refs, rho, f"Spearman rho over {len(refs)} points", "")


def constant(fn: Callable[[], float], label: str, unit: str = "") -> Stat:
    """A statistic computed from the paper's own printed numbers only (consistency claims)."""
    return Stat((), fn, label, unit)


@dataclass(frozen=True)
class Assumption:
    """A value the paper does not fix, swept for robustness: a keyword of the experiment's ``run()``.

    ``low``/``high`` are the measured or published range; ``source`` says where it comes from.
    """

    experiment: str
    param: str
    low: float
    high: float
    source: str
    log: bool = False
    integer: bool = False


@dataclass(frozen=True)
class Claim:
    """One claim of a paper, declared as data (see the module docstring)."""

    id: str
    paper: str
    line: int | tuple[int, ...]
    kind: str
    claim: str
    paper_value: float | None = None
    paper_text: str = ""
    statistic: Stat | None = None
    expect: str = "~"
    assumptions: tuple[Assumption, ...] = ()
    decided_in: str = ""
    untestable: str = ""
    note: str = ""

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"claim {self.id}: kind {self.kind!r} is not one of {KINDS}")
        if self.statistic is None and not self.untestable:
            raise ValueError(f"claim {self.id}: no statistic, so say why it cannot be tested (untestable=...)")
        _parse_expect(self.id, self.expect)
        if not self.claim.strip():
            raise ValueError(f"claim {self.id}: empty claim text")

    @property
    def lines(self) -> tuple[int, ...]:
        return self.line if isinstance(self.line, tuple) else (self.line,)


def _parse_expect(cid: str, expect: str) -> tuple[str, float]:
    e = expect.strip()
    if e == "~":
        return "~", math.nan
    if e[:1] in "<>":
        try:
            return e[0], float(e[1:])
        except ValueError:
            pass
    raise ValueError(f"claim {cid}: expect {expect!r} must be '~', '<x' or '>x'")


class ResultIndex:
    """Long results (see :func:`lookup`) split once into each experiment's default-parameter rows, so that many
    lookups each read one experiment's rows instead of the whole table; :func:`lookup` and
    :func:`statistic_by_seed` take it in place of the DataFrame and give the same values and errors."""

    def __init__(self, results: pd.DataFrame):
        r = results
        if "params" in r.columns:
            r = r[r["params"].isin(["{}", ""])]
        self._empty = r.iloc[:0]
        self._by_experiment = ({str(e): g for e, g in r.groupby("experiment", sort=False)}
                               if "experiment" in r.columns and len(r) else {})
        self._arrays: dict[str, tuple] = {}

    def rows(self, experiment: str) -> pd.DataFrame:
        """The default-parameter rows of ``experiment`` (in the results' order; none: an empty frame)."""
        return self._by_experiment.get(experiment, self._empty)

    def replace(self, experiment: str, rows: pd.DataFrame) -> ResultIndex:
        """A copy whose ``experiment`` rows are ``rows`` (already default-parameter rows of that experiment)."""
        out = ResultIndex.__new__(ResultIndex)
        out._empty = self._empty
        out._by_experiment = {**self._by_experiment, experiment: rows}
        out._arrays = {k: v for k, v in self._arrays.items() if k != experiment}
        return out

    def find(self, ref: Ref) -> pd.Series | None:
        """:func:`lookup` of ``ref`` from column arrays (positions by quantity), or None when it would raise
        (then :func:`lookup` reads the rows as a DataFrame and raises with its message)."""
        if ref.experiment not in self._arrays:
            g = self.rows(ref.experiment)
            if not {"quantity", "item", "table", "value"} <= set(g.columns):
                return None
            by_q: dict = {}
            for i, q in enumerate(g["quantity"].to_numpy(dtype=object)):
                by_q.setdefault(q, []).append(i)
            seeds = g["seed"].to_numpy() if "seed" in g.columns else np.zeros(len(g), dtype=np.int64)
            self._arrays[ref.experiment] = (by_q, g["item"].to_numpy(dtype=object),
                                            g["table"].to_numpy(dtype=object), g["value"].to_numpy(dtype=np.float64),
                                            seeds)
        by_q, item, table, val, seed = self._arrays[ref.experiment]
        pos = [i for i in by_q.get(ref.quantity, ())
               if (ref.item is None or item[i] == ref.item) and (ref.table is None or table[i] == ref.table)]
        if not pos:
            return None
        s = seed[pos]
        if len(set(s.tolist())) < len(pos):
            return None
        return pd.Series(val[pos], index=s, name=str(ref))


def lookup(results: pd.DataFrame | ResultIndex, ref: Ref) -> pd.Series:
    """The values of ``ref`` per seed (index: seed) from long results (columns ``experiment``, ``table``,
    ``item``, ``quantity``, ``value``, optional ``seed`` and ``params``; only default-parameter rows), or from
    their :class:`ResultIndex`.

    Raises
    ------
    KeyError
        No row matches, or more than one row matches for a seed (the message names the ref and the
        candidates, so a claim that names its quantity loosely is found at once).
    """
    if isinstance(results, ResultIndex):
        found = results.find(ref)
        if found is not None:
            return found
        r = results.rows(ref.experiment)
    else:
        r = results
        if "params" in r.columns:
            r = r[r["params"].isin(["{}", ""])]
    m = (r["experiment"] == ref.experiment) & (r["quantity"] == ref.quantity)
    if ref.item is not None:
        m &= r["item"] == ref.item
    if ref.table is not None:
        m &= r["table"] == ref.table
    hit = r[m]
    if hit.empty:
        near = r.loc[r["experiment"] == ref.experiment, "quantity"].drop_duplicates().head(12).tolist()
        raise KeyError(f"{ref}: no such reproduced value (quantities of {ref.experiment}: {near})")
    seeds = hit["seed"] if "seed" in hit.columns else pd.Series(0, index=hit.index)
    if seeds.duplicated().any():
        dup = hit.loc[seeds.duplicated(keep=False), ["table", "item", "quantity"]].drop_duplicates()
        raise KeyError(f"{ref}: {len(dup)} rows match per seed; name item/table: {dup.to_dict('records')[:4]}")
    return pd.Series(hit["value"].to_numpy(dtype=np.float64), index=seeds.to_numpy(), name=str(ref))


def statistic_by_seed(stat: Stat, results: pd.DataFrame | ResultIndex) -> pd.Series:
    """The statistic on each seed that every ref has a value for (index: seed)."""
    if not stat.refs:
        return pd.Series([stat()], index=[0], dtype=np.float64)
    cols = [lookup(results, ref) for ref in stat.refs]
    frame = pd.concat(cols, axis=1, join="inner")
    return pd.Series([stat(*row) for row in frame.to_numpy()], index=frame.index, dtype=np.float64)


def interval(values: Iterable[float], level: float = 0.95) -> tuple[float, float, float, int]:
    """Mean, Student-t interval (low, high) and count of the finite values; a single value has a
    zero-width interval (a deterministic result), none gives NaNs."""
    from scipy import stats

    v = np.asarray(list(values), dtype=np.float64)
    v = v[np.isfinite(v)]
    n = int(v.size)
    if n == 0:
        return math.nan, math.nan, math.nan, 0
    mean = float(v.mean())
    if n == 1 or float(v.std(ddof=1)) == 0.0:
        return mean, mean, mean, n
    half = float(stats.t.ppf(0.5 + level / 2, n - 1) * v.std(ddof=1) / math.sqrt(n))
    return mean, mean - half, mean + half, n


def judge(claim: Claim, mean: float, lo: float, hi: float) -> str:
    """The verdict of a claim from its statistic's mean and interval (rules in the module docstring)."""
    if claim.statistic is None:
        return "cannot be tested"
    if not math.isfinite(mean):
        return "cannot be tested"
    op, thr = _parse_expect(claim.id, claim.expect)
    if op == "~":
        p = claim.paper_value
        if p is None or not math.isfinite(p):
            raise ValueError(f"claim {claim.id}: a '~' claim needs the paper's value")
        if lo <= p <= hi:
            return "reproduced"
        rel = abs(mean - p) / abs(p) if p != 0 else (0.0 if mean == 0 else math.inf)
        if rel <= AGREE_REL:
            return "reproduced"
        # the paper's own arithmetic either holds or contradicts it: no "partly" for a consistency claim
        return "partly" if rel <= CLOSE_REL and claim.kind != "consistency" else "not reproduced"
    right = (lambda x: x < thr) if op == "<" else (lambda x: x > thr)
    if right(lo) and right(hi):
        return "reproduced"
    if not right(lo) and not right(hi) and lo != thr and hi != thr:
        return "not reproduced"
    return "partly"


#: Long-format columns of one run's sweepable values (what :func:`lookup` reads, with ``experiment`` and
#: ``seed``; :mod:`ilocalg.workflow.sweep` adds ``params``).
RESULT_COLUMNS = ("table", "paper", "item", "quantity", "unit", "paper_value", "value")


def tables_to_long(tables: Mapping[str, pd.DataFrame]) -> pd.DataFrame:
    """The sweepable values of an experiment's tables, in long format (:data:`RESULT_COLUMNS`)."""
    columns = long_columns(tables)
    if columns is not None:
        return pd.DataFrame(columns)
    return _tables_to_long(tables)


def _long_parts(tables: Mapping[str, pd.DataFrame]) -> list[tuple[str, pd.DataFrame]]:
    return [(name, df) for name, df in tables.items() if isinstance(df, pd.DataFrame) and (
        all(c in df.columns for c in PAPER_REF_COLUMNS)
        or (name.startswith(("sweep_", "measures")) and "value" in df.columns and "quantity" in df.columns))]


def long_columns(tables: Mapping[str, pd.DataFrame]) -> dict | None:
    """The columns of :func:`tables_to_long` (name -> values, :data:`RESULT_COLUMNS` order) without building a
    DataFrame per table, when exactly one non-empty table is sweepable (every study run and most experiments);
    else None (:func:`tables_to_long` then concatenates the tables, whose dtypes may promote each other).
    ``pd.DataFrame(long_columns(t))`` equals ``tables_to_long(t)``, dtypes and index included; a seed sweep builds
    some 1,000 of these, each a few rows, and the per-table frames were most of their cost."""
    parts = _long_parts(tables)
    if len(parts) != 1 or len(parts[0][1]) == 0:
        return None
    name, df = parts[0]
    n = len(df)
    if all(c in df.columns for c in PAPER_REF_COLUMNS):
        src = {"paper": df["paper"], "item": df["item"], "quantity": df["quantity"],
               "unit": df["unit"] if "unit" in df.columns else None, "paper_value": df["paper_value"],
               "value": df["reproduced_value"]}
    else:
        src = {c: df[c] if c in df.columns else None for c in ("paper", "item", "quantity", "unit", "paper_value")}
        src["value"] = df["value"]
    out = {"table": [name] * n}
    for c in ("paper", "item", "quantity", "unit"):
        out[c] = [""] * n if src[c] is None else ["" if pd.isna(v) else str(v) for v in src[c]]
    out["paper_value"] = (np.full(n, np.nan) if src["paper_value"] is None
                          else src["paper_value"].astype(np.float64).to_numpy())
    out["value"] = src["value"].astype(np.float64).to_numpy()
    return {c: out[c] for c in RESULT_COLUMNS}


def _tables_to_long(tables: Mapping[str, pd.DataFrame]) -> pd.DataFrame:
    parts = []
    for name, df in tables.items():
        if not isinstance(df, pd.DataFrame):
            continue
        if all(c in df.columns for c in PAPER_REF_COLUMNS):
            p = df[list(PAPER_REF_COLUMNS)].rename(columns={"reproduced_value": "value"})
            p["unit"] = df["unit"] if "unit" in df.columns else ""
        elif (name.startswith(("sweep_", "measures")) and "value" in df.columns
              and "quantity" in df.columns):
            p = df[["quantity", "value"]].copy()
            for c in ("paper", "item", "unit"):
                p[c] = df[c] if c in df.columns else ""
            p["paper_value"] = df["paper_value"] if "paper_value" in df.columns else np.nan
        else:
            continue
        p = p.copy()
        p.insert(0, "table", name)
        parts.append(p[list(RESULT_COLUMNS)])
    if not parts:
        return pd.DataFrame({c: pd.Series(dtype=float if c in ("paper_value", "value") else object)
                             for c in RESULT_COLUMNS})
    out = pd.concat(parts, ignore_index=True)
    out["paper_value"] = out["paper_value"].astype(np.float64)
    out["value"] = out["value"].astype(np.float64)
    for c in ("table", "paper", "item", "quantity", "unit"):
        out[c] = ["" if pd.isna(v) else str(v) for v in out[c]]
    return out


#: Columns of the claims ledger (reports/claims.csv).
CLAIM_COLUMNS = ("paper", "claim_id", "line", "kind", "claim", "paper_value", "reproduced", "ci_low", "ci_high",
                 "verdict", "robust_share", "decided_in")


def evaluate(claim: Claim, results: pd.DataFrame | ResultIndex, level: float = 0.95) -> dict:
    """One ledger row (:data:`CLAIM_COLUMNS` plus ``n_seeds``, ``statistic``, ``expect``, ``note``) for a claim
    on long results (see :func:`lookup`). ``robust_share`` is left NaN (the robustness step fills it)."""
    row = {"paper": claim.paper, "claim_id": claim.id, "line": ";".join(str(x) for x in claim.lines),
           "kind": claim.kind, "claim": claim.claim,
           "paper_value": math.nan if claim.paper_value is None else float(claim.paper_value),
           "reproduced": math.nan, "ci_low": math.nan, "ci_high": math.nan, "verdict": "cannot be tested",
           "robust_share": math.nan, "decided_in": claim.decided_in, "n_seeds": 0,
           "statistic": "" if claim.statistic is None else claim.statistic.label, "expect": claim.expect,
           "ci_clipped": False,
           "note": claim.untestable or claim.note}
    if claim.statistic is None:
        return row
    per_seed = statistic_by_seed(claim.statistic, results)
    mean, lo, hi, n = interval(per_seed.to_numpy(), level)
    lo, hi, clipped = clip_interval(lo, hi, claim.statistic.unit, claim.statistic.label)
    row.update(reproduced=mean, ci_low=lo, ci_high=hi, n_seeds=n, ci_clipped=clipped,
               verdict=judge(claim, mean, lo, hi))
    return row


def evaluate_claims(claims: Iterable[Claim], results: pd.DataFrame, level: float = 0.95) -> pd.DataFrame:
    """The ledger of several claims (one row each, :func:`evaluate`)."""
    rows = [evaluate(c, results, level) for c in claims]
    return pd.DataFrame(rows)


def claims_from_tables(claims: Iterable[Claim], tables_by_experiment: Mapping[str, Mapping[str, pd.DataFrame]]
                       ) -> pd.DataFrame:
    """Evaluate claims on one run's tables (e.g. in a notebook: ``{"fusion_iloc_kf": tables}``), seed 0 only."""
    parts = []
    for exp, tables in tables_by_experiment.items():
        long = tables_to_long(tables)
        long.insert(0, "experiment", exp)
        long["seed"] = 0
        parts.append(long)
    results = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(
        columns=["experiment", "table", "item", "quantity", "value", "seed"])
    wanted = [c for c in claims if c.statistic is None or all(r.experiment in tables_by_experiment
                                                                for r in c.statistic.refs)]
    return evaluate_claims(wanted, results)


def _num(x: float) -> str:
    return f"{x:.3g}" if isinstance(x, (int, float, np.floating)) and math.isfinite(x) else "n/a"


def claims_markdown(ledger: pd.DataFrame, heading: str = "") -> str:
    """Markdown sentences from a claims ledger (:func:`claims_from_tables` on a notebook's own run, or
    :func:`evaluate_claims`): one bullet per claim with its verdict, the paper's figure, the reproduced
    statistic (with its interval over seeds, when there is one) and the note. A notebook displays this as
    its generated conclusion (``IPython.display.Markdown``), so no measured number is typed by hand.
    """
    lines = [heading, ""] if heading else []
    if ledger is None or len(ledger) == 0:
        return "\n".join(lines + ["No claim of this paper is decided by this run."])
    for r in ledger.to_dict("records"):
        stat = r.get("statistic", "")
        rep = _num(r.get("reproduced", math.nan))
        lo, hi = r.get("ci_low", math.nan), r.get("ci_high", math.nan)
        if rep != "n/a" and math.isfinite(lo) and math.isfinite(hi) and hi > lo:
            rep += f" (95 % CI {_num(lo)} to {_num(hi)}, {int(r.get('n_seeds', 0))} seeds)"
        pv = r.get("paper_value", math.nan)
        exp = r.get("expect", "~")
        paper = (f"the paper: {_num(pv)}" if pv is not None and math.isfinite(pv)
                 else f"the claim asserts {stat} {exp[0]} {exp[1:]}" if exp and exp != "~" else "")
        body = f"- **{r['verdict']}**: {r['claim']} (line {r['line']})"
        if r["verdict"] != "cannot be tested":
            body += f". Reproduced {stat} = {rep}" + (f"; {paper}" if paper else "")
        note = r.get("note", "")
        if isinstance(note, str) and note.strip():
            body += f". {note.strip()}"
        lines.append(body.rstrip(".") + ".")
    return "\n".join(lines)


def rows_markdown(rows: pd.DataFrame, where: Callable[[pd.Series], bool] | None = None) -> str:
    """Markdown sentences from comparison rows (``paper_ref`` rows): for each, the reproduced value beside
    the paper's, which is larger, and by how much; ``where`` selects rows. Numbers come from the table."""
    out = []
    for _, r in rows.iterrows():
        if where is not None and not where(r):
            continue
        p, v, unit = float(r["paper_value"]), float(r["reproduced_value"]), str(r.get("unit", "") or "")
        u = f" {unit}" if unit and unit not in ("-", "nan") else ""
        if not (math.isfinite(p) and math.isfinite(v)):
            out.append(f"- {r['item']}, {r['quantity']}: no value to compare.")
            continue
        side = "equal (to 3 digits) to" if _num(v) == _num(p) else "smaller than" if v < p else "larger than"
        rel = f" ({(v - p) / abs(p) * 100:+.0f} %)" if p != 0 else ""
        out.append(f"- {r['item']}, {r['quantity']}: reproduced {_num(v)}{u}, {side} the paper's "
                   f"{_num(p)}{u}{rel}.")
    return "\n".join(out) if out else "No comparison row selected."
