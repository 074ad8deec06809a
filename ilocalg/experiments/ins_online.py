"""Online fixed-window smoothing of the smartphone INS (Liao et al. 2016, sec. 4.2, Tables 8-11, Fig 19).

For each phone and seed: the WVC/ZUPT/GCP filter (:func:`ilocalg.ins.pipeline.run_walk`), then
the online smoother on fixed windows (5, 10, 20 s in the tables; a sweep for Fig 19) and the
whole-run RTS. Scored on the indoor part, averaged over seeds. Also: how often a window holds no
control point, and how the windows without one fare (the paper's explanation of Figs 20-21).
"""

from __future__ import annotations

import pandas as pd

from ilocalg.ins.evaluate import AXES, window_sweep, window_sweep_tables
from ilocalg.ins.paper_values import LIAO_2016, paper_value, side_by_side
from ilocalg.ins.pipeline import run_walk
from ilocalg.papers import paper_ref
from ilocalg.sim import ins_walk
from ilocalg.sim.ins_walk import PHONES

__all__ = ["TABLE_WINDOWS_S", "SWEEP_WINDOWS_S", "run"]

#: Window sizes of Tables 8-11 (s).
TABLE_WINDOWS_S = (5.0, 10.0, 20.0)
#: Window sizes of the Fig 19 sweep (s).
SWEEP_WINDOWS_S = (2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0)


def _label(w):
    return f"Online {int(w)}sec"


def run(seed: int = 0, fast: bool = False, n_seeds: int | None = None,
        sweep_windows_s=SWEEP_WINDOWS_S) -> dict[str, pd.DataFrame]:
    """Tables 8-11 and Fig 19 reproduced on simulated walks.

    Returns
    -------
    dict with ``errors`` (phone, method, stat, N..Heading; mean over seeds), ``position_side_by_side``
    and ``attitude_side_by_side`` (paper layout), ``window_sweep`` (phone, window_s, stat, N, E, H,
    horizontal, latency_mean_s), ``windows_without_gcp`` (per window size: share of windows without a
    control point and the horizontal RMS error inside windows with / without one), ``comparison`` and
    ``trajectory`` (first seed: per-epoch E, N, H of the truth, the filter and the 5/10/20 s windows).
    """
    n_seeds = n_seeds or (1 if fast else 6)
    # Window lengths as floats (an int window from a caller or a sweep is the same window).
    windows = sorted({float(w) for w in sweep_windows_s} | {float(w) for w in TABLE_WINDOWS_S})
    rows, sweep, gcp_rows, traj = [], [], [], []
    for phone, route, profile in PHONES:
        # Disjoint simulation seeds per experiment seed: seed k uses k*n_seeds .. (k+1)*n_seeds - 1, so runs
        # with different seeds are independent (a sweep over seeds gives honest confidence intervals).
        for s in range(seed * n_seeds, (seed + 1) * n_seeds):
            walk = ins_walk.simulate(route, profile, seed=s)
            res = run_walk(walk, "wvc", use_gcp=True)
            ind = walk.t_s >= walk.t_indoor_s
            ws = window_sweep(res, windows, ind, walk.pos_true_n_m[ind], walk.mat_true_nb[ind], walk.gcp_t_s)
            if s == seed * n_seeds:
                traj.append(_trajectory(phone, walk, ws.solutions, ind))
            for key, st in ws.stats.items():
                if not isinstance(key, float) or key in TABLE_WINDOWS_S:
                    method = _label(key) if isinstance(key, float) else key
                    rows += [{"phone": phone, "method": method, "seed": s, "stat": k, **st[k]}
                             for k in ("max", "rms", "std")]
            for df, out in ((ws.sweep, sweep), (ws.gcp, gcp_rows)):
                out.append(df.assign(phone=phone, seed=s))
    per_seed = pd.DataFrame(rows)
    errors = per_seed.groupby(["phone", "method", "stat"], sort=False)[list(AXES)].mean().reset_index()
    errors.insert(3, "n_seeds", n_seeds)
    sw, gw = window_sweep_tables(pd.concat(sweep, ignore_index=True), pd.concat(gcp_rows, ignore_index=True))
    in_paper = errors[errors.method.isin(["Filtering"] + [_label(w) for w in TABLE_WINDOWS_S])]
    comp = []
    for phone, *_ in PHONES:
        table = "Table 8" if phone == "Samsung" else "Table 10"
        for method in ["Filtering"] + [_label(w) for w in TABLE_WINDOWS_S]:
            sel = errors[(errors.phone == phone) & (errors.method == method) & (errors.stat == "rms")].iloc[0]
            for ax in ("N", "E", "H"):
                comp.append(paper_ref(LIAO_2016, table, f"{phone} WVC/ZUPT/GCP {method}: RMS {ax} error",
                                      paper_value(phone, method, "rms", ax), sel[ax], unit="m",
                                      note=f"simulated walk, mean of {n_seeds} seed(s)"))
        r = sw[(sw.phone == phone) & (sw.stat == "rms") & sw.window_s.isin(TABLE_WINDOWS_S)]
        best = float(r.loc[r["horizontal"].idxmin(), "window_s"])
        comp.append(paper_ref(LIAO_2016, "Fig 19", f"{phone}: best of the 5/10/20 s windows (horizontal RMS)",
                              20.0, best, unit="s", note="paper: best window 20 s, 10-20 s recommended"))
    return {
        "errors": errors,
        "errors_per_seed": per_seed,
        "position_side_by_side": side_by_side(in_paper, ("N", "E", "H")),
        "attitude_side_by_side": side_by_side(in_paper, ("Roll", "Pitch", "Heading")),
        "window_sweep": sw,
        "windows_without_gcp": gw,
        "comparison": pd.DataFrame(comp),
        "trajectory": pd.concat(traj, ignore_index=True),
    }


def _trajectory(phone, walk, sols, ind):
    """Per-epoch E, N, H of the truth, the filter and the online windows of Tables 8-11 (first seed)."""
    frames = [pd.DataFrame({"phone": phone, "method": "Truth", "t_s": walk.t_s, "indoor": ind,
                            "E": walk.pos_true_n_m[:, 0], "N": walk.pos_true_n_m[:, 1], "H": walk.pos_true_n_m[:, 2]})]
    for key in ["Filtering", *TABLE_WINDOWS_S]:
        pos = sols[key][0]
        frames.append(pd.DataFrame({"phone": phone, "method": key if key == "Filtering" else _label(key),
                                    "t_s": walk.t_s, "indoor": ind, "E": pos[:, 0], "N": pos[:, 1], "H": pos[:, 2]}))
    return pd.concat(frames, ignore_index=True)
