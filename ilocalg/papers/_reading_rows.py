"""Readings declared as data: rows of text that a run's choices fill in, rendered to a readings table.

A paper's readings module (e.g. :mod:`ilocalg.papers.readings_pso`) declares one :data:`Row` per modelling
choice of an experiment: ``(choice, paper_line, text_says, code_does, source)``. A field is plain text, a
:class:`Fmt` (a ``str.format`` template filled from the run's choices) or a :class:`Pick` (one text per
value of a choice). :func:`render` turns the rows into :func:`ilocalg.papers.readings_table` for the
choices of one run, so an experiment names its choices and never writes prose.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import pandas as pd

from ilocalg.papers import reading, readings_table

__all__ = ["Fmt", "Pick", "Row", "render", "fill"]


@dataclass(frozen=True)
class Fmt:
    """A text filled from the run's choices: ``Fmt("fixed {band} m/s^2")``."""

    template: str


@dataclass(frozen=True)
class Pick:
    """One text per value of the choice ``key``; ``other`` (a template) for a value not listed."""

    key: str
    options: Mapping[object, object]
    other: str | None = None


#: One readings row: (choice, paper line, what the text says, what the code does, source). A paper line of
#: "" or "-" means the paper is silent there.
Row = tuple


def _fill(field, choices: Mapping[str, object]) -> str:
    if isinstance(field, str):
        return field
    if isinstance(field, Fmt):
        return field.template.format(**choices)
    if isinstance(field, Pick):
        if field.key not in choices:
            raise ValueError(f"readings: the run's choices lack {field.key!r} (have {sorted(choices)})")
        v = choices[field.key]
        if v in field.options:
            return _fill(field.options[v], choices)
        if field.other is None:
            raise ValueError(f"readings: {field.key}={v!r} is not one of {sorted(map(str, field.options))}")
        return field.other.format(**choices)
    if isinstance(field, tuple):  # pieces joined
        return "".join(_fill(f, choices) for f in field)
    raise ValueError(f"readings: a field must be text, Fmt, Pick or a tuple of them, got {field!r}")


def render(rows: Sequence[Row], cite: str, **choices) -> pd.DataFrame:
    """The readings table of ``rows`` for one run's ``choices``; paper lines get the prefix ``cite``."""
    out = []
    try:
        for choice, line, text, code, source in rows:
            ln = _fill(line, choices)
            out.append(reading(_fill(choice, choices), "" if ln in ("", "-") else cite + ln, _fill(text, choices),
                               _fill(code, choices), _fill(source, choices)))
    except (KeyError, IndexError) as exc:
        raise ValueError(f"readings template needs the value {exc} (given: {sorted(choices)})") from None
    return readings_table(out)


def fill(rows: Sequence[Row], **values) -> pd.DataFrame:
    """:func:`render` of rows whose every field is a template (:class:`Fmt`) and whose paper lines are cited in
    full (the i-Loc and Luo et al. readings)."""
    return render([tuple(Fmt(f) for f in row) for row in rows], "", **values)
