"""How the notebooks show tables: numbers as a reader writes them, text cells in full.

pandas shows every float with six decimals (an access-point count as ``8.000000``, a mean error as
``1.234568``) and cuts text cells after 50 characters (the ``note`` column). :func:`table_display`, called
once at the top of a notebook, sets pandas' display options for that kernel: whole numbers without
decimals, other values with four significant digits (one decimal from 10 000 up), text never cut. Only
what is shown changes; the tables written to ``reports/tables`` keep every digit.
"""

from __future__ import annotations

import math

__all__ = ["readable_number", "table_display"]


def readable_number(value: float) -> str:
    """``value`` as shown in a notebook table: ``8``, ``1.235``, ``0.01234``, ``12345.7``, ``NaN``."""
    v = float(value)
    if math.isnan(v):
        return "NaN"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if v.is_integer() and abs(v) < 1e15:
        return f"{v:.0f}"
    if abs(v) >= 1e4:
        return f"{v:.1f}"
    return f"{v:.4g}"


def table_display() -> None:
    """Set pandas' display options of this kernel for the notebooks' tables (see the module doc)."""
    import pandas as pd

    pd.set_option("display.float_format", readable_number)
    pd.set_option("display.max_colwidth", None)
    pd.set_option("display.max_columns", 40)
