"""Online fixed-window smoothing of the smartphone INS (Liao et al. 2016, sec. 4.2, Tables 8-11, Fig 19).

For each phone and seed: the WVC/ZUPT/GCP filter (:func:`ilocalg.ins.pipeline.run_walk`), then
the online smoother on fixed windows (5, 10, 20 s in the tables; a sweep for Fig 19) and the
whole-run RTS. Scored on the indoor part, averaged over seeds and over where the window grid
falls (offsets of 0, 1/4, 1/2, 3/4 of the window: the paper does not say where its grid starts).
Also: how often a window holds no control point, and how the windows without one fare (the paper's
explanation of Figs 20-21).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins.chain import trajectory_frame
from ilocalg.ins.evaluate import AXES, window_sweep_tables, window_sweeps
from ilocalg.ins.paper_values import side_by_side
from ilocalg.ins.pipeline import SMOOTHING_STORE as STORE
from ilocalg.ins.pipeline import smoothing_inputs
from ilocalg.papers.comparison_liao import fig19_monotonicity, online_rows
from ilocalg.papers.comparison_liao import online_label as _label
from ilocalg.papers.readings_liao import online_readings
from ilocalg.sim import ins_walk
from ilocalg.sim.ins_walk import PHONES
from ilocalg.workflow import runstore

__all__ = ["TABLE_WINDOWS_S", "SWEEP_WINDOWS_S", "OFFSET_FRACS", "readings", "run"]

#: Window sizes of Tables 8-11 (s).
TABLE_WINDOWS_S = (5.0, 10.0, 20.0)
#: Window sizes of the Fig 19 sweep (s).
SWEEP_WINDOWS_S = (2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0)


#: Window-grid offsets, as fractions of the window, averaged over (full and fast mode).
OFFSET_FRACS = (0.0, 0.25, 0.5, 0.75)
OFFSET_FRACS_FAST = (0.0, 0.5)


def readings(stairs: str, offsets) -> pd.DataFrame:
    """One row per modelling choice (declared in :mod:`ilocalg.papers.readings_liao`; see also ins_constraints')."""
    return online_readings(stairs, offsets)


def run(seed: int = 0, fast: bool = False, n_seeds: int | None = None,
        sweep_windows_s=SWEEP_WINDOWS_S, offset_fracs=None, stairs: str = "none",
        noise_factor: float = ins_walk.PHONE_NOISE_FACTOR, bias_instability_factor: float = 1.0,
        time_jitter_sd_s: float = ins_walk.PHONE_TIME_JITTER_SD_S, rssi_sd_db: float = ins_walk.BLE_RSSI_SD_DB,
        speed_mean_mps: float = ins_walk.LEVEL_SPEED_MEAN_MPS) -> dict[str, pd.DataFrame]:
    """Tables 8-11 and Fig 19 reproduced on simulated walks, averaged over seeds and window-grid offsets.

    Returns
    -------
    dict with ``errors`` (phone, method, stat, N..Heading; mean over seeds and grid offsets),
    ``position_side_by_side`` and ``attitude_side_by_side`` (paper layout), ``online_spread`` (per phone and
    online method: mean, sd, min and max over seeds x offsets of the RMS N, E, H and horizontal errors),
    ``window_sweep`` (phone, window_s, stat, N, E, H, horizontal, latency_mean_s; mean over seeds and offsets,
    with ``horizontal_sd``, ``horizontal_min``, ``horizontal_max`` for the Fig 19 band), ``windows_without_gcp``
    (per window size: share of windows without a control point and the horizontal RMS error inside windows with
    / without one), ``comparison``, ``trajectory`` (first seed, grid offset 0: per-epoch E, N, H and roll, pitch,
    heading errors of the truth, the filter and the 5/10/20 s windows), ``fig19_monotonicity`` (per phone and axis:
    RMS at 10 and 20 s, their difference beside the paper's, the number of rises along the window sweep and the
    Spearman correlation of RMS with window size: the test of the text's point that the error does not always
    fall with the window, L471-L473) and ``readings``.

    ``stairs`` (default "none"): the WVC's stair handling, the same on both phones (L202; see ins_constraints).
    The ``comparison`` holds one row per published quantity: the "Filtering" rows of Tables 8 and 10 repeat
    Tables 4 and 6 and are compared in ins_constraints only.

    ``noise_factor``, ``bias_instability_factor``, ``time_jitter_sd_s``, ``rssi_sd_db`` and ``speed_mean_mps``:
    the simulated phones', beacons' and walkers' values the paper does not fix, as in ins_constraints.
    """
    return run_many([{"seed": seed, "fast": fast, "n_seeds": n_seeds, "sweep_windows_s": sweep_windows_s,
                      "offset_fracs": offset_fracs, "stairs": stairs, "noise_factor": noise_factor,
                      "bias_instability_factor": bias_instability_factor, "time_jitter_sd_s": time_jitter_sd_s,
                      "rssi_sd_db": rssi_sd_db, "speed_mean_mps": speed_mean_mps}])[0]


def run_many(runs) -> list[dict[str, pd.DataFrame]]:
    """:func:`run` with the keywords of each mapping of ``runs``, each result the one :func:`run` gives alone.

    Every run's walks of a phone are filtered together, in batches of at most
    :data:`ilocalg.ins.pipeline.BATCH_WALKS` (:func:`ilocalg.ins.pipeline.run_walks`: the same numbers as one by
    one), a walk that two runs share once. The claims' robustness samples (one walk per phone each, fast mode) and
    the seed sweep run this way (:func:`ilocalg.workflow.sweep.sweep`).
    """
    plans = [_plan(**r) for r in runs]
    parts: dict[tuple, tuple] = {}  # (run, phone, simulation seed) -> that walk's rows and frames
    for phone, route, name in PHONES:
        users: dict[tuple, list] = {}  # each walk (simulation and filter settings) -> the runs that score it
        for i, pl in enumerate(plans):
            for s in pl["seeds"]:
                key = (pl["profiles"][name], s, pl["rssi_sd_db"], pl["gait_items"], pl["stairs"])
                users.setdefault(key, []).append(i)
        # the walks' filters advanced together (the same numbers as one by one), a walk of one stair handling per
        # batch; a walk that study_ins_window filtered earlier in the same reproduce run is read, not recomputed
        for st in dict.fromkeys(k[4] for k in users):
            walks = smoothing_inputs(
                [k for k in users if k[4] == st],
                lambda k, route=route: ins_walk.simulate(route, k[0], seed=k[1], rssi_sd_db=k[2],
                                                         gait_kw=dict(k[3]) if k[3] else None),
                stairs=st, lookup=lambda k, route=route: runstore.get(STORE, (route, *k)))
            for key, inp in walks:
                walk, res = inp.walk, inp.result
                ind = walk.t_s >= walk.t_indoor_s
                for i in users[key]:
                    pl = plans[i]
                    # every offset's windows smoothed in one pass
                    sweeps = window_sweeps(res, pl["windows"], ind, walk.pos_true_n_m[ind], walk.mat_true_nb[ind],
                                           walk.gcp_t_s, gains=inp.gains, offset_fracs=pl["offsets"])
                    parts[(i, phone, key[1])] = _walk_parts(phone, key[1], walk, ind, sweeps, pl)
    return [_tables(pl, [parts[(i, phone, s)] for phone, _, _ in PHONES for s in pl["seeds"]])
            for i, pl in enumerate(plans)]


def _plan(seed: int = 0, fast: bool = False, n_seeds: int | None = None, sweep_windows_s=SWEEP_WINDOWS_S,
          offset_fracs=None, stairs: str = "none", noise_factor: float = ins_walk.PHONE_NOISE_FACTOR,
          bias_instability_factor: float = 1.0, time_jitter_sd_s: float = ins_walk.PHONE_TIME_JITTER_SD_S,
          rssi_sd_db: float = ins_walk.BLE_RSSI_SD_DB, speed_mean_mps: float = ins_walk.LEVEL_SPEED_MEAN_MPS) -> dict:
    """What one :func:`run` simulates and scores (its keywords checked)."""
    n_seeds = n_seeds or (1 if fast else 6)
    offsets = tuple(float(f) for f in (offset_fracs if offset_fracs is not None
                                       else (OFFSET_FRACS_FAST if fast else OFFSET_FRACS)))
    if not offsets or any(not (0.0 <= f < 1.0) for f in offsets):
        raise ValueError(f"offset_fracs must be fractions of the window in [0, 1), got {offset_fracs!r}")
    # Window lengths as floats (an int window from a caller or a sweep is the same window).
    windows = sorted({float(w) for w in sweep_windows_s} | {float(w) for w in TABLE_WINDOWS_S})
    gait = (("speed_mean_mps", speed_mean_mps),) if speed_mean_mps != ins_walk.LEVEL_SPEED_MEAN_MPS else ()
    # Disjoint simulation seeds per experiment seed: seed k uses k*n_seeds .. (k+1)*n_seeds - 1, so runs
    # with different seeds are independent (a sweep over seeds gives honest confidence intervals).
    return {"n_seeds": n_seeds, "offsets": offsets, "windows": windows, "stairs": stairs, "gait_items": gait,
            "rssi_sd_db": rssi_sd_db, "seeds": range(seed * n_seeds, (seed + 1) * n_seeds),
            "profiles": {name: ins_walk.phone_profile(name, noise_factor, bias_instability_factor, time_jitter_sd_s)
                         for _, _, name in PHONES}}


def _walk_parts(phone: str, s: int, walk, ind, sweeps, pl: dict) -> tuple[list, list, list, list]:
    """One walk's rows of ``errors_per_seed``, its ``window_sweep`` and ``windows_without_gcp`` frames (one per
    grid offset) and, for the run's first seed, its ``trajectory`` frame."""
    rows, sweep, gcp_rows, traj = [], [], [], []
    offsets = pl["offsets"]
    for off, ws in zip(offsets, sweeps, strict=True):
        if s == pl["seeds"][0] and off == offsets[0]:
            sols = {k if k == "Filtering" else _label(k): ws.solutions[k][:2] for k in ["Filtering", *TABLE_WINDOWS_S]}
            traj.append(trajectory_frame(phone, walk, sols, ind, attitude="errors"))
        for key, st in ws.stats.items():
            if not isinstance(key, float) or key in TABLE_WINDOWS_S:
                method = _label(key) if isinstance(key, float) else key
                rows += [{"phone": phone, "method": method, "seed": s, "offset_frac": off, "stat": k,
                          **st[k]} for k in ("max", "rms", "std")]
        for df, out in ((ws.sweep, sweep), (ws.gcp, gcp_rows)):
            out.append(df.assign(phone=phone, seed=s, offset_frac=off))
    return rows, sweep, gcp_rows, traj


def _tables(pl: dict, parts: list) -> dict[str, pd.DataFrame]:
    """:func:`run`'s tables from its plan (:func:`_plan`) and its walks' parts (:func:`_walk_parts`), phone by
    phone and seed by seed."""
    n_seeds, offsets, stairs = pl["n_seeds"], pl["offsets"], pl["stairs"]
    rows = [r for p in parts for r in p[0]]
    sweep = [d for p in parts for d in p[1]]
    gcp_rows = [d for p in parts for d in p[2]]
    traj = [d for p in parts for d in p[3]]
    per_run = pd.DataFrame(rows)
    errors = per_run.groupby(["phone", "method", "stat"], sort=False)[list(AXES)].mean().reset_index()
    errors.insert(3, "n_seeds", n_seeds)
    errors.insert(4, "n_offsets", len(offsets))
    rms = per_run[per_run.stat == "rms"].assign(horizontal=lambda d: np.hypot(d["N"], d["E"]))
    spread = (rms.groupby(["phone", "method"], sort=False)[["N", "E", "H", "horizontal"]]
              .agg(["mean", "std", "min", "max"]))
    spread.columns = [f"{a}_{b}" for a, b in spread.columns]
    spread = spread.reset_index()
    sw_all = pd.concat(sweep, ignore_index=True)
    sw, gw = window_sweep_tables(sw_all, pd.concat(gcp_rows, ignore_index=True))
    band = (sw_all[sw_all.stat == "rms"].groupby(["phone", "window_s"])["horizontal"]
            .agg(horizontal_sd="std", horizontal_min="min", horizontal_max="max").reset_index().assign(stat="rms"))
    sw = sw.merge(band, on=["phone", "window_s", "stat"], how="left")
    in_paper = errors[errors.method.isin(["Filtering"] + [_label(w) for w in TABLE_WINDOWS_S])]
    mono = fig19_monotonicity(sw)
    comp = online_rows(errors, sw, mono, [ph for ph, *_ in PHONES], TABLE_WINDOWS_S, n_seeds, len(offsets))
    return {
        "errors": errors,
        "errors_per_seed": per_run,
        "online_spread": spread,
        "position_side_by_side": side_by_side(in_paper, ("N", "E", "H")),
        "attitude_side_by_side": side_by_side(in_paper, ("Roll", "Pitch", "Heading")),
        "window_sweep": sw,
        "windows_without_gcp": gw,
        "comparison": pd.DataFrame(comp),
        "trajectory": pd.concat(traj, ignore_index=True),
        "fig19_monotonicity": mono,
        "readings": readings(stairs, offsets),
        "measures": _measures(errors, sw),
    }


def _measures(errors: pd.DataFrame, sweep: pd.DataFrame) -> pd.DataFrame:
    """Named scalars for the claims ledger (ilocalg.papers.liao): max and RMS error per phone, method and axis
    (Filtering, the online windows of Tables 8-11, whole-run RTS), and the horizontal RMS error per window."""
    rows = [{"quantity": f"{r['stat']} {ax} error", "item": f"{r['phone']} {r['method']}", "value": float(r[ax]),
             "unit": "m" if ax in ("N", "E", "H") else "deg"}
            for _, r in errors[errors["stat"].isin(["max", "rms"])].iterrows() for ax in AXES]
    rows += [{"quantity": "rms horizontal error", "item": f"{r['phone']} window={r['window_s']:g}s",
              "value": float(r["horizontal"]), "unit": "m"} for _, r in sweep[sweep["stat"] == "rms"].iterrows()]
    return pd.DataFrame(rows)
