"""Study: online smoothing error vs window size 2-30 s, inside windows with and without a control
point (extends Liao et al. 2016, Fig 19 and the explanation of Figs 20-21).

One ``run(seed)`` is one simulated walk per phone (:mod:`ilocalg.sim.ins_walk`), its WVC/ZUPT/GCP
filter (:func:`ilocalg.ins.pipeline.run_walks`) and the fixed-window online smoother for every window
size (:func:`ilocalg.ins.evaluate.window_sweep`, as in the online-smoothing experiment), re-labelled as
a ``sweep_ins_window`` table, averaged over four offsets of the window grid (0, 1/4, 1/2, 3/4 of the
window). Scored on the indoor part of the walk.

Quantities per ``phone`` and window (``item`` = ``phone=...;window_s=...``):
``horizontal RMS error`` (m, all indoor epochs), ``horizontal RMS error, windows with a control
point`` and ``..., windows without a control point`` (m, epochs of the windows that hold / do not
hold a control-point update), ``share of windows without a control point`` (%), ``height RMS
error`` (m) and ``mean latency`` (s). References at ``window_s=0`` (the filter alone, no smoothing)
and ``window_s=inf`` (whole-run RTS) carry the first and last two quantities.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins.evaluate import window_sweep_tables, window_sweeps
from ilocalg.ins.pipeline import SMOOTHING_STORE as STORE
from ilocalg.ins.pipeline import smoothing_inputs
from ilocalg.sim import ins_walk
from ilocalg.workflow import runstore
from ilocalg.workflow.studies import select, study_row, study_tasks

__all__ = ["run", "run_many", "WINDOWS_S", "GRIDS", "tasks", "findings"]

EXPERIMENT = "study_ins_window"
#: Window sizes of the study (s).
WINDOWS_S = (2.0, 3.0, 4.0, 5.0, 7.0, 10.0, 12.0, 15.0, 20.0, 25.0, 30.0)
WINDOWS_S_FAST = (2.0, 5.0, 10.0, 20.0, 30.0)
GRIDS = {False: {}, True: {}}  # only seeds are swept: every window comes from the same filtered walk


#: Window-grid offsets (fractions of the window) averaged inside each task.
OFFSET_FRACS = (0.0, 0.25, 0.5, 0.75)


def run(seed: int = 0, fast: bool = False, windows_s=None, offset_fracs=OFFSET_FRACS) -> dict[str, pd.DataFrame]:
    """Window-size curves of one walk per phone (module docstring).

    Parameters
    ----------
    seed : int
        Seed of the simulated walks.
    fast : bool
        Five window sizes instead of eleven (default of ``windows_s``).
    windows_s : sequence of float, optional
        Window sizes (s), each > 0.
    offset_fracs : sequence of float
        Offsets of the window grid as fractions of the window, in [0, 1); every quantity is their mean.
    """
    return run_many([{"seed": seed, "fast": fast, "windows_s": windows_s, "offset_fracs": offset_fracs}])[0]


def run_many(runs) -> list[dict[str, pd.DataFrame]]:
    """:func:`run` with the keywords of each mapping of ``runs``, each result the one :func:`run` gives alone: the
    runs' walks of a phone are filtered together, in batches of at most :data:`ilocalg.ins.pipeline.BATCH_WALKS`
    (:func:`ilocalg.ins.pipeline.run_walks`: the same numbers as one by one), a walk that two runs share once.
    The study notebook's seeds run this way (:func:`ilocalg.workflow.runner.study_jobs`)."""
    plans = [_plan(**r) for r in runs]
    parts: dict[tuple, tuple] = {}  # (run, phone) -> that walk's window-sweep frames, one per grid offset
    for phone, route, profile in ins_walk.PHONES:
        users: dict[int, list] = {}  # simulation seed -> the runs that score its walk
        for i, pl in enumerate(plans):
            users.setdefault(pl["seed"], []).append(i)
        # both phones alike (Liao 2016, L202); the walks' filters advanced together, and left in the reproduce run's
        # store for ins_online, whose notebook and seed sweep filter the same walks (seeds 0-11)
        prof = ins_walk.PROFILES.get(profile, profile)
        keys = [(prof, s, ins_walk.BLE_RSSI_SD_DB, (), "none") for s in users]
        for key, inp in smoothing_inputs(keys, lambda k, route=route: ins_walk.simulate(route, k[0], seed=k[1]),
                                         stairs="none", lookup=lambda k, route=route: runstore.get(STORE, (route, *k)),
                                         keep=lambda k, v, route=route: runstore.put(STORE, (route, *k), v)):
            walk, filt = inp.walk, inp.result
            ind = walk.t_s >= walk.t_indoor_s
            for i in users[key[1]]:
                pl = plans[i]
                # averaged over where the window grid falls; every offset's windows smoothed in one pass
                sweeps = window_sweeps(filt, sorted(set(pl["windows"])), ind, walk.pos_true_n_m[ind],
                                       walk.mat_true_nb[ind], walk.gcp_t_s, gains=inp.gains, offset_fracs=pl["offsets"])
                parts[(i, phone)] = ([r.sweep.assign(phone=phone) for r in sweeps],
                                     [r.gcp.assign(phone=phone) for r in sweeps])
    return [_table([d for ph, *_ in ins_walk.PHONES for d in parts[(i, ph)][0]],
                   [d for ph, *_ in ins_walk.PHONES for d in parts[(i, ph)][1]]) for i in range(len(plans))]


def _plan(seed: int = 0, fast: bool = False, windows_s=None, offset_fracs=OFFSET_FRACS) -> dict:
    """One :func:`run`'s keywords, checked."""
    offsets = tuple(float(f) for f in offset_fracs)
    if not offsets or any(not (0.0 <= f < 1.0) for f in offsets):
        raise ValueError(f"offset_fracs must be fractions of the window in [0, 1), got {offset_fracs!r}")
    ws = tuple(float(w) for w in (windows_s if windows_s is not None else (WINDOWS_S_FAST if fast else WINDOWS_S)))
    if not ws or any(not np.isfinite(w) or w <= 0 for w in ws):
        raise ValueError(f"windows_s must be positive finite window sizes in seconds, got {windows_s!r}")
    return {"seed": int(seed), "windows": ws, "offsets": offsets}


def _table(sweep: list, gcp: list) -> dict[str, pd.DataFrame]:
    """The ``sweep_ins_window`` table of one run from its walks' window-sweep frames."""
    sw, gw = window_sweep_tables(pd.concat(sweep, ignore_index=True), pd.concat(gcp, ignore_index=True))
    sw = sw[sw["stat"] == "rms"]
    gw = gw.set_index(["phone", "window_s"])
    rows = []
    for r in sw.itertuples(index=False):
        w = float(r.window_s)
        ctx = {"phone": r.phone, "window_s": f"{w:g}"}
        rows.append(study_row("horizontal RMS error", r.horizontal, "m", **ctx))
        rows.append(study_row("height RMS error", r.H, "m", **ctx))
        rows.append(study_row("mean latency", r.latency_mean_s, "s", **ctx))
        if (r.phone, w) in gw.index:
            g = gw.loc[(r.phone, w)]
            rows.append(study_row("horizontal RMS error, windows with a control point", g["rms_h_with_gcp_m"],
                                  "m", **ctx))
            rows.append(study_row("horizontal RMS error, windows without a control point",
                                  g["rms_h_without_gcp_m"], "m", **ctx))
            rows.append(study_row("share of windows without a control point", 100.0 * g["share_without_gcp"],
                                  "%", **ctx))
    return {"sweep_ins_window": pd.DataFrame(rows)}


def tasks(seeds, fast: bool = False) -> list:
    """One task per seed (every window size is computed inside a task, from the same filtered walk)."""
    return study_tasks(EXPERIMENT, [GRIDS[fast]], seeds, fast=fast)


def findings(cv: pd.DataFrame) -> str:
    """Sentences computed from the study's curves (:func:`ilocalg.workflow.studies.curves`)."""
    out = []
    for phone in sorted(cv["phone"].unique()):
        h = select(cv, "horizontal RMS error", phone=phone)
        win = h[np.isfinite(h["window_s"]) & (h["window_s"] > 0)].sort_values("window_s")
        filt = h[h["window_s"] == 0]["mean"].iloc[0]
        rts = h[np.isinf(h["window_s"])]["mean"].iloc[0]
        wi = select(cv, "horizontal RMS error, windows with a control point", phone=phone).set_index("window_s")
        wo = select(cv, "horizontal RMS error, windows without a control point", phone=phone).set_index("window_s")
        w0, w1 = win["window_s"].iloc[0], win["window_s"].iloc[-1]
        out.append(
            f"{phone}: horizontal RMS {filt:.2f} m filtered, {win['mean'].iloc[0]:.2f} m with {w0:g} s windows, "
            f"{win['mean'].iloc[-1]:.2f} m with {w1:g} s, {rts:.2f} m whole-run RTS (N={int(win['n'].min())} seeds). "
            f"Inside windows without / with a control point: {wo.loc[w0, 'mean']:.2f} / {wi.loc[w0, 'mean']:.2f} m "
            f"at {w0:g} s, {wo.loc[w1, 'mean']:.2f} / {wi.loc[w1, 'mean']:.2f} m at {w1:g} s.")
    return "\n".join(out)
