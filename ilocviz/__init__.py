"""ilocviz: plotting for the iLoc toolkit (plots only; the maths lives in :mod:`ilocalg`).

Every plotting function takes an ``ax`` (or makes one when given ``None``) and returns it. Nothing
here calls ``plt.show()`` or changes global rcParams on import; apply :data:`STYLE` explicitly with
``with ilocviz.style():``.
"""

from ilocviz.core import STYLE, error_cdf, new_axes, savefig, style, trajectory

__all__ = ["STYLE", "style", "new_axes", "savefig", "error_cdf", "trajectory"]
