"""Hartmann et al.'s Table 2 (as Yeh & Huang's survey reports it) beside the reproduced values: the comparison
rows of experiment ``ins_hartmann`` and the tracker noise implied by the paper's mean deviation.

The published overall row lives in :mod:`ilocalg.ins.paper_values` (``HARTMANN_TABLE2_OVERALL``, a labelled
reference only).

References
----------
Hartmann, B., Link, N., Trommer, G. F. (2010). Indoor 3D position estimation using low-cost inertial
sensors and marker-based video-tracking. IEEE/ION PLANS, 319-326 (survey sec. 5, Table 2).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins.paper_values import HARTMANN_2010, HARTMANN_TABLE2_OVERALL
from ilocalg.papers import paper_ref

__all__ = ["table2_rows", "implied_tracker_noise"]

#: Table 2's columns that describe the tracker's input data (set from Table 2 in the simulator).
_INPUT_KEYS = ("vt_rate_hz", "outage_max_s", "outages_over_1s")


def table2_rows(overall: pd.Series, n_sequences: int, duration_s: float) -> list[dict]:
    """Table 2's overall row beside the reproduced ``overall`` (mean over sequences; maximum of the maximal
    deviations)."""
    comp = []
    for key, pv in HARTMANN_TABLE2_OVERALL.items():
        unit = "Hz" if key.endswith("hz") else "s" if key.endswith("_s") else "" if key.startswith("outages") else "m"
        note = (f"input, not a reproduction: the simulated tracker's outages were set from Table 2 "
                f"({n_sequences} sequences of {duration_s:g} s)" if key in _INPUT_KEYS
                else f"EKF prediction vs VT, {n_sequences} simulated sequences of {duration_s:g} s"
                + ("; echoes the assumed tracker noise: see tracker_noise (sensitivity curve)"
                   if key.startswith("mean_dev") else "; see outage_sensitivity"))
        comp.append(paper_ref(HARTMANN_2010, "Table 2", f"overall {key}", pv, float(overall[key]), unit=unit,
                              note=note, row_class="set by input" if key in _INPUT_KEYS else "result"))
    return comp


def implied_tracker_noise(tn: pd.DataFrame, vt_sd_default) -> pd.DataFrame:
    """Per axis, the tracker noise at which the mean-deviation curve ``tn`` (``noise_scale``, ``mean_dev_<a>_m``,
    sorted by scale) meets Table 2's overall mean deviation, by linear interpolation (NaN outside the swept
    range or when the curve does not rise): a reading of the paper's number, not an input."""
    implied = []
    for j, a in enumerate("xyz"):
        dev = tn[f"mean_dev_{a}_m"].to_numpy(float)
        pv = HARTMANN_TABLE2_OVERALL[f"mean_dev_{a}_m"]
        ok = np.all(np.diff(dev) > 0) and dev[0] <= pv <= dev[-1]
        sc = float(np.interp(pv, dev, tn["noise_scale"].to_numpy(float))) if ok else np.nan
        implied.append({"axis": a, "paper_mean_dev_m": pv, "implied_noise_scale": sc,
                        "implied_vt_sd_mm": 1e3 * sc * vt_sd_default[1 + j],
                        "swept_scales": f"{tn['noise_scale'].min():g}-{tn['noise_scale'].max():g}"})
    return pd.DataFrame(implied)
