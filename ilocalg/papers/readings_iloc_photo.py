"""How the toolkit reads the i-Loc thesis's photo positioning (Chiu 2013, sec. 6.3): the readings of
experiment ``photo_positioning``, as data.

One row per modelling choice (:mod:`ilocalg.papers._reading_rows`): the thesis's line, what it says, what the
code does, and the source of each value the text does not give; the run's layout, VA search space and
simulation inputs fill the rows (:func:`readings`). Line numbers are lines of the thesis's text copy
(``/work/shared/papers/000_42091e6b84aac0f5.txt``).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers._reading_rows import Fmt, Pick, render

__all__ = ["ROWS", "GOOD_GUESS_SD_M", "SENSITIVITY_GRID", "readings"]

ROWS = (
    ("PoI layout", "L658, L688, L696, L707; Figs 27-28",
     "7 PoIs on the walls; 7 test points 1 m apart; distance from p4 grows t1->t7; smallest view angles "
     "p3-t7-p4 and p4-t7-p5; {1,2}, {6,7} nearer than {3,4}, {3,5}, {4,5}, {3,4,5}; p1, p3-p6 on one "
     "horizontal line; coordinates only in Fig 28 (missing)",
     Fmt("layout {layout!r}: a layout satisfying every constraint (layout_check)"),
     "assumption: both families that satisfy the text are swept in layout_sweep (spread reported): rooms "
     "A-G (7 of the 33 satisfying room-grid members) and one-wall layouts W1-W4 (4 of the 9 satisfying "
     "one-wall grid members); layout_sweep(layouts='all') runs all 42"),
    ("PoI layout (earlier reading)", "L707", "as above",
     "'row': seven PoIs 0.4 m apart in a row on one wall, test line straight away from it",
     "sensitivity row only: violates L696 and L707 (one wall as such does not: W1-W4)"),
    ("ST", "L664-680, eq. (29)-(30)", "similar triangles with T_E->AR from accelerometer and magnetometer; "
     "least squares over the PoIs", "linear least squares over the PoIs with the measured orientation",
     "thesis"),
    ("VA cost function", "L694", "VA is a gradient algorithm that depends on its initial value; no equation",
     "sum of squared differences between measured and predicted PoI-pair view angles, gradient descent",
     "the toolkit's own (the thesis gives no VA equation)"),
    ("VA search space", "L672 (output c = [c_x c_y c_z])", "the camera centre",
     Pick("va_free_z", {True: "3-D search"}, other="floor position at the known phone height (2-D)"),
     "assumption; the other search space is a sensitivity row (va_free_z)"),
    ("VAGIG initial guess", "L652, L694", "a good initial view angle; the user first gives a rough position",
     Fmt("true position + N(0, {good_guess_sd_m:g} m) per axis, inside the room"),
     "i-Loc PTS + Wi-Fi fix error 2.82 m mean (thesis sec. 5.2) -> 2.25 m per axis; swept in good_guess_sweep"),
    ("VABIG initial guess", "L694", "a bad initial view angle", "uniform over the room floor",
     "assumption"),
    ("VA started at the truth", "", "silent", "VA from the true centre: VA's floor of error",
     "diagnostic"),
    ("photos per shooting point", "L696", "not given", "10 (fast: 1)", "assumption"),
    ("drag, tilt, heading errors, focal length", "L656-658 (Fig 25)", "the user drags PoI markers; "
     "orientation from accelerometer and magnetometer; no error values",
     Fmt("drag {drag_sd_px:g} px, tilt {tilt_sd_deg:g} deg, heading {yaw_sd_deg:g} deg, f {f_px:g} px"),
     "data/photo_poi/README.md (published measurements); "
     "swept in sensitivity"),
    ("error measure", "L696, L702", "mean positioning error in cm", "horizontal (floor) error, cm",
     "thesis (the floor map is 2-D)"),
)


#: Spreads of the good initial guess swept by the experiment's ``good_guess_sweep`` (m per axis; 2.25 m is the
#: default, from the i-Loc fix error).
GOOD_GUESS_SD_M = (0.5, 1.0, 2.25, 4.0)
#: Inputs the experiment's ``sensitivity`` tries, one changed at a time from the defaults (the values the thesis does
#: not give; sources in :data:`ROWS`).
SENSITIVITY_GRID = (
    ("drag_sd_px", (3.0, 6.0, 12.0, 24.0)),
    ("yaw_sd_deg", (1.0, 2.5, 5.0, 10.0)),
    ("tilt_sd_deg", (0.5, 1.0, 2.0)),
    ("good_guess_sd_m", (0.5, 1.0, 2.25)),
    ("va_free_z", (False, True)),
)


def readings(layout: str, va_free_z: bool, params: dict) -> pd.DataFrame:
    """The readings table of one run: its layout's name, VA search space and simulation inputs ``params``
    (:data:`ilocalg.sim.photo_poi.DEFAULTS` with the run's overrides)."""
    return render(ROWS, "Chiu 2013, ", layout=layout, va_free_z=bool(va_free_z), **params)
