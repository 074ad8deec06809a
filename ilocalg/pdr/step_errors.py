"""Why a step count is wrong: every missed and extra step of a detector, given a cause.

A count hides missed steps balanced by extra ones, so the detections are first matched one-to-one to the
true step times (:func:`ilocalg.pdr.robust.match_steps`, within ``tol_s``). Each unmatched true step
(*missed*) and unmatched detection (*extra*) then gets one cause, from the step times alone (no
placement, phone or recording name enters):

``timing``
    a missed true step and an extra detection closer than ``timing_tol_s`` to each other, paired
    one-to-one (a second matching pass): the step was found, a little further from the heel landing
    than ``tol_s``. The count is right; neither the detector nor the truth is wrong in number.
``truth_gap`` (extra)
    a detection inside the walk, in a gap between two consecutive true steps of ``gap_factor`` to
    ``pause_factor`` local step intervals (the median of the true intervals around the gap): one or two
    landings the heel sensors did not register while the detector keeps counting at the walk's own
    period. A limit of the truth, not of the detector (its counterpart in the sensor states is a foot
    that lands twice with no landing of the other foot between,
    :attr:`ilocalg.io.oxford.OxfordRecording.n_unpaired_landings`).
``pause`` (extra)
    a detection in a longer gap between true steps (the walker stood): the detector's.
``before_walk`` / ``after_walk`` (extra)
    a detection before the first or after the last true step (handling the phone): the detector's.
``inside_walk`` (extra)
    a detection in an ordinary step interval (a step counted twice): the detector's.
``walk_end`` (missed)
    the first or last true step of the recording (the first push-off from standing or the last landing,
    weak in |a|): the detector's.
``inside_walk`` (missed)
    any other missed true step (a weak step): the detector's.

References
----------
Brajdic, A., Harle, R. (2013), "Walk detection and step counting on unconstrained smartphones", UbiComp
(errors of step counters split into walk detection and step counting).
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import pandas as pd

from ilocalg.pdr.robust import match_steps

__all__ = ["classify_step_errors", "count_causes", "TRUTH_LIMITED", "CAUSES"]

#: Causes, as ``(kind, cause)`` pairs, in the order tables list them.
CAUSES = (("missed", "timing"), ("missed", "walk_end"), ("missed", "inside_walk"),
          ("extra", "timing"), ("extra", "truth_gap"), ("extra", "pause"), ("extra", "before_walk"),
          ("extra", "after_walk"), ("extra", "inside_walk"))
#: Causes that are not the detector's: the step was found (``timing``) or the truth lacks it (``truth_gap``).
TRUTH_LIMITED = ("timing", "truth_gap")


def classify_step_errors(true_t_s, det_t_s, tol_s: float = 0.25, timing_tol_s: float = 0.5,
                         gap_factor: float = 1.5, pause_factor: float = 3.5, n_local: int = 5) -> pd.DataFrame:
    """Every missed true step and extra detection, with its cause (see the module docstring).

    Parameters
    ----------
    true_t_s, det_t_s : array_like, increasing times, s
        True (heel-sensor) step times and detected step times.
    tol_s : float
        Matching tolerance of :func:`ilocalg.pdr.robust.match_steps`, s.
    timing_tol_s : float
        Second, wider matching pass among the unmatched ones (``timing``), s (> ``tol_s``; about one step
        interval, so that a step found late is not also a step found early for the next one).
    gap_factor, pause_factor : float
        A gap between two consecutive true steps of ``gap_factor`` to ``pause_factor`` local step intervals
        holds one or two landings the truth lacks (``truth_gap``); a longer one is a pause (``pause``).
        1.5: a single missing landing makes the gap two intervals, half an interval is the margin either
        way; 3.5: up to two missing landings in a row.
    n_local : int
        True intervals on each side of a gap whose median is the local step interval.

    Returns
    -------
    DataFrame
        One row per error, in time order: ``kind`` ("missed" or "extra"), ``t_s``, ``cause``,
        ``gap_intervals`` (an extra's gap between true steps in local step intervals; NaN otherwise).
    """
    tt = np.asarray(true_t_s, dtype=np.float64)
    dd = np.asarray(det_t_s, dtype=np.float64)
    if not 0 < tol_s < timing_tol_s:
        raise ValueError(f"need 0 < tol_s < timing_tol_s, got {tol_s}, {timing_tol_s}")
    if not 1.0 < gap_factor < pause_factor:
        raise ValueError(f"need 1 < gap_factor < pause_factor, got {gap_factor}, {pause_factor}")
    if n_local < 1:
        raise ValueError(f"n_local must be >= 1, got {n_local}")
    tm, dm = match_steps(tt, dd, tol_s)
    ti, di = np.flatnonzero(~tm), np.flatnonzero(~dm)
    tm2, dm2 = match_steps(tt[ti], dd[di], timing_tol_s)
    rows = []
    for k, timing in zip(ti, tm2, strict=True):
        cause = "timing" if timing else ("walk_end" if k in (0, tt.size - 1) else "inside_walk")
        rows.append(("missed", tt[k], cause, np.nan))
    dt = np.diff(tt)
    for k, timing in zip(di, dm2, strict=True):
        t, gap = dd[k], np.nan
        if timing:
            cause = "timing"
        elif tt.size == 0 or t < tt[0]:
            cause = "before_walk"
        elif t > tt[-1]:
            cause = "after_walk"
        else:
            j = min(max(int(np.searchsorted(tt, t)), 1), tt.size - 1)      # the gap tt[j-1] .. tt[j]
            local = np.median(dt[max(0, j - 1 - n_local):j + n_local])
            gap = dt[j - 1] / local
            cause = "inside_walk" if gap < gap_factor else ("truth_gap" if gap < pause_factor else "pause")
        rows.append(("extra", t, cause, gap))
    out = pd.DataFrame(rows, columns=["kind", "t_s", "cause", "gap_intervals"])
    return out.sort_values("t_s", kind="stable").reset_index(drop=True)


def count_causes(errors: pd.DataFrame) -> dict:
    """Counts per ``(kind, cause)`` of one :func:`classify_step_errors` table, as ``{"<kind>_<cause>": n}``,
    with ``detector_net`` (the detector's extra less its missed steps) and ``truth_gap`` (extra detections in
    the truth's gaps)."""
    pairs = Counter(zip(errors["kind"].tolist(), errors["cause"].tolist(), strict=True))
    n = {f"{k}_{c}": pairs[(k, c)] for k, c in CAUSES}
    own = {kind: sum(m for (k, c), m in pairs.items() if k == kind and c not in TRUTH_LIMITED)
           for kind in ("extra", "missed")}
    n["detector_net"] = own["extra"] - own["missed"]
    n["truth_gap"] = n["extra_truth_gap"]
    return n
