"""ilocviz: plotting for the iLoc toolkit (plots only; the maths lives in :mod:`ilocalg`).

Every plotting function takes an ``ax`` (or makes one when given ``None``) and returns it. Nothing
here calls ``plt.show()`` or changes global rcParams on import; apply :data:`STYLE` explicitly with
``with ilocviz.style():``.

A paper's published value is drawn beside the reproduced one with :func:`paper_mark` (a labelled
dashed line or band on any plot), ``error_cdf(..., paper=...)``, or :func:`paper_vs_reproduced` (every
row of a comparison table as a ratio to the paper's value); legends name methods as the papers do
(:func:`legend_name`). Tables show numbers as a reader writes them once a notebook calls
:func:`table_display`.
"""

from ilocviz.core import (
    LEGEND_NAMES,
    STYLE,
    error_cdf,
    figure_title,
    legend_name,
    new_axes,
    paper_mark,
    paper_point,
    paper_values,
    paper_vs_reproduced,
    savefig,
    style,
    trajectory,
)
from ilocviz.tables import readable_number, table_display

__all__ = ["STYLE", "style", "new_axes", "savefig", "figure_title", "error_cdf", "trajectory", "LEGEND_NAMES",
           "legend_name", "paper_mark", "paper_point", "paper_values", "paper_vs_reproduced", "table_display",
           "readable_number"]
