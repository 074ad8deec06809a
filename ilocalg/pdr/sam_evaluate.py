"""SAM evaluated on recordings with counted steps: leave one recording out.

For each recording, SAM's ranges are the ``q_range`` quantiles of the features of the true steps of the
other recordings (each true step matched to the nearest wave within ``tol_s``, as the thesis learns its
ranges from known steps, L399); SAM then counts the held-out recording. Logs are resampled to
``rate_hz`` first (X1, eq. 15, scales with the rate).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 4.1, Table 1, Fig 12.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd

from ilocalg.pdr.sam import SAM_TESTED_FEATURES, in_ranges, learn_feature_ranges, match_waves_to_steps, sam_waves
from ilocalg.pdr.signals import acc_from_log, resample_uniform

__all__ = ["sam_leave_one_out"]


def sam_leave_one_out(recs: Sequence, q_range=(0.05, 0.95), rate_hz: float = 50.0, tol_s: float = 0.25,
                      describe: Callable[[str], dict] | None = None) -> pd.DataFrame:
    """SAM on each recording with ranges learned from the others' true steps.

    Parameters
    ----------
    recs : sequence of recordings with ``name``, ``imu`` (sensor log indexed by time, s), ``step_t_s``
        (the true steps' times) and ``true_steps`` (their count), e.g. :func:`ilocalg.io.oxford.load_oxford_archive`.
    q_range : (float, float), the quantiles of the learned ranges (the thesis's 5/95 %).
    rate_hz : float, the rate the logs are resampled to.
    tol_s : float, how far a wave may lie from the true step it is matched to.
    describe : callable, optional: ``name -> dict`` of columns describing a recording (phone, user, ...).

    Returns
    -------
    DataFrame
        One row per recording: ``recording``, the ``describe`` columns, ``true_steps``, ``counted``,
        ``error`` (|counted - true| / true), ``cadence_hz`` (true steps / duration), ``waves_matched``
        (share of true steps with a wave within ``tol_s``), ``steps_passing`` (share of matched true steps
        passing all seven tests), ``worst_test`` and ``worst_test_fail`` (the test its matched steps fail
        most, and how often), ``why`` (a sentence).
    """
    waves, matched, cadence = [], [], []
    for r in recs:
        acc, t = acc_from_log(r.imu)
        a50, t50 = resample_uniform(acc, t, rate_hz)
        w = sam_waves(a50, t50)
        waves.append(w)
        matched.append(match_waves_to_steps(w, r.step_t_s, tol_s))
        cadence.append(r.true_steps / (t[-1] - t[0]))
    rows = []
    for i, r in enumerate(recs):
        others = [j for j in range(len(recs)) if j != i]
        rg = learn_feature_ranges(pd.concat([matched[j] for j in others], ignore_index=True), *q_range)
        counted = int(in_ranges(waves[i], rg, SAM_TESTED_FEATURES).sum())
        m = matched[i]
        fail = {f: float(((m[f] < rg.loc[f, "min"]) | (m[f] > rg.loc[f, "max"])).mean()) if len(m) else np.nan
                for f in SAM_TESTED_FEATURES}
        worst = max(fail, key=lambda f: fail[f])
        med = float(m[worst].median()) if len(m) else np.nan
        side = "below" if med < rg.loc[worst, "min"] else "above" if med > rg.loc[worst, "max"] else "inside"
        c_oth = np.array([cadence[j] for j in others])
        err = abs(counted - r.true_steps) / r.true_steps
        over = (f"counts {counted - r.true_steps} more steps than taken (extra waves pass every test); "
                if counted > r.true_steps else "")
        why = over + (f"{fail[worst]:.0%} of its true steps fail {worst} (median {med:.2f}, {side} the learned "
               f"{rg.loc[worst, 'min']:.2f}-{rg.loc[worst, 'max']:.2f}); cadence {cadence[i]:.2f} steps/s vs "
               f"{c_oth.min():.2f}-{c_oth.max():.2f} in the others; {len(m) / r.true_steps:.0%} of true steps "
               f"have a wave within {tol_s:g} s")
        rows.append({"recording": r.name, **(describe(r.name) if describe else {}), "true_steps": int(r.true_steps),
                     "counted": counted, "error": err, "cadence_hz": cadence[i],
                     "waves_matched": len(m) / r.true_steps,
                     "steps_passing": float(in_ranges(m, rg, SAM_TESTED_FEATURES).mean()) if len(m) else np.nan,
                     "worst_test": worst, "worst_test_fail": fail[worst], "why": why})
    return pd.DataFrame(rows)
