"""The i-Loc thesis's photo-positioning figures beside the reproduced ones (Chiu 2013, sec. 6.3, Figs 29-32):
the comparison rows of experiment ``photo_positioning`` and the combinations Fig 32 names.

The published values are ``PUBLISHED["photo_positioning"]`` of :mod:`ilocalg.papers.iloc` (labelled references
only, never used to compute a reproduced value).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU. Figs 29-32.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers import PAPERS, paper_ref
from ilocalg.papers.iloc import PUBLISHED

__all__ = ["PAPER", "NEAR_COLLINEAR_PAPER", "fig30_rows"]

#: Fig 30 and the text of sec. 6.3: ST and VABIG errors with 2 and 7 PoIs (``fig30_*``) and the overall mean
#: errors of ST, VAGIG and VABIG (``mean_*``), cm.
PAPER = PUBLISHED["photo_positioning"]
#: The combinations the thesis names as nearly collinear in Fig 32 (1-based PoI numbers).
NEAR_COLLINEAR_PAPER = ((1, 3), (1, 4), (5, 6), (1, 3, 4))


def fig30_rows(per_k: pd.DataFrame, overall: pd.Series, ks, methods) -> list[dict]:
    """Fig 30's ST and VABIG errors with 2 and 7 PoIs beside ``per_k`` (index k, a column per method) for the
    sizes in ``ks``, and, when every size 2..7 ran, the overall means of ``methods`` beside ``overall``."""
    comp = []
    label = PAPERS["iloc"]
    for k, m in ((2, "ST"), (7, "ST"), (2, "VABIG"), (7, "VABIG")):
        if k in ks:
            comp.append(paper_ref(label, "Fig 30", f"{m} mean error, {k} PoIs", PAPER[f"fig30_{m}_k{k}_cm"],
                                  per_k.loc[k, m], "cm"))
    if list(ks) == [2, 3, 4, 5, 6, 7]:
        for m in methods:
            comp.append(paper_ref(label, "Figs 29-30", f"{m} overall mean error", PAPER[f"mean_{m}_cm"],
                                  overall[m], "cm", note="paper-style mean over 120 combinations x 7 shooting points"))
    return comp
