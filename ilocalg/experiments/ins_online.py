"""Online fixed-window smoothing of the smartphone INS (Liao et al. 2016, sec. 4.2, Tables 8-11, Fig 19).

For each phone and seed: the WVC/ZUPT/GCP filter of :mod:`ilocalg.experiments.ins_constraints`, then
the online smoother on fixed windows (5, 10, 20 s in the tables; a sweep for Fig 19) and the
whole-run RTS. Scored on the indoor part, averaged over seeds. Also: how often a window holds no
control point, and how the windows without one fare (the paper's explanation of Figs 20-21).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.experiments.ins_constraints import AXES, PAPER, PHONES
from ilocalg.experiments.ins_paper_values import paper_value
from ilocalg.ins import error_stats, eskf_rts_smooth, nav_errors, online_window_smooth, rts_gains, window_ends
from ilocalg.ins.pipeline import run_walk
from ilocalg.papers import paper_ref
from ilocalg.sim import ins_walk

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
            G = rts_gains(res)
            ind = walk.t_s >= walk.t_indoor_s
            truth = (walk.pos_true_n_m[ind], walk.mat_true_nb[ind])
            sols = {"Filtering": (res.pos_n_m, res.mat_nb, np.zeros(res.t_s.size)), }
            for w in windows:
                sm = online_window_smooth(res, w, gains=G)
                sols[w] = (sm.pos_n_m, sm.mat_nb, sm.latency_s)
            full = eskf_rts_smooth(res, with_cov=False, gains=G)
            sols["RTS (whole run)"] = (full.pos_n_m, full.mat_nb, full.latency_s)
            if s == seed * n_seeds:
                traj.append(_trajectory(phone, walk, sols, ind))
            gcp_epoch = np.zeros(res.t_s.size, bool)
            gcp_epoch[np.searchsorted(res.t_s, walk.gcp_t_s)] = True
            for key, (pos, mat, lat) in sols.items():
                err = nav_errors(pos[ind], mat[ind], *truth)
                st = error_stats(err)
                if not isinstance(key, float) or key in TABLE_WINDOWS_S:
                    method = _label(key) if isinstance(key, float) else key
                    rows += [{"phone": phone, "method": method, "seed": s, "stat": k, **st[k]}
                             for k in ("max", "rms", "std")]
                wsec = key if isinstance(key, float) else (0.0 if key == "Filtering" else np.inf)
                for k in ("max", "rms", "std"):
                    sweep.append({"phone": phone, "seed": s, "window_s": wsec, "stat": k,
                                  **{a: st[k][a] for a in ("N", "E", "H")},
                                  "horizontal": float(np.hypot(st[k]["N"], st[k]["E"])) if k == "rms" else np.nan,
                                  "latency_mean_s": float(np.mean(lat[ind]))})
                if isinstance(key, float):
                    ends = window_ends(res.t_s, key)
                    win = np.concatenate([[0], np.cumsum(ends[:-1])])
                    has = np.zeros(win.max() + 1, bool)
                    has[win[gcp_epoch]] = True
                    hz = np.hypot(err["N"], err["E"]).to_numpy()
                    wi = win[ind]
                    in_gcp = has[wi]
                    indoor_windows = np.unique(wi)
                    gcp_rows.append({
                        "phone": phone, "seed": s, "window_s": key,
                        "windows_indoor": indoor_windows.size,
                        "share_without_gcp": float(np.mean(~has[indoor_windows])),
                        "rms_h_with_gcp_m": float(np.sqrt(np.mean(hz[in_gcp] ** 2))) if in_gcp.any() else np.nan,
                        "rms_h_without_gcp_m": (float(np.sqrt(np.mean(hz[~in_gcp] ** 2))) if (~in_gcp).any()
                                                else np.nan)})
    per_seed = pd.DataFrame(rows)
    errors = per_seed.groupby(["phone", "method", "stat"], sort=False)[list(AXES)].mean().reset_index()
    errors.insert(3, "n_seeds", n_seeds)
    sw = (pd.DataFrame(sweep).groupby(["phone", "window_s", "stat"], sort=False)
          [["N", "E", "H", "horizontal", "latency_mean_s"]].mean().reset_index())
    sw = sw.sort_values(["phone", "stat", "window_s"], kind="stable").reset_index(drop=True)
    gw = (pd.DataFrame(gcp_rows).groupby(["phone", "window_s"], sort=False)
          [["windows_indoor", "share_without_gcp", "rms_h_with_gcp_m", "rms_h_without_gcp_m"]].mean().reset_index())
    in_paper = errors[errors.method.isin(["Filtering"] + [_label(w) for w in TABLE_WINDOWS_S])]
    comp = []
    for phone, *_ in PHONES:
        table = "Table 8" if phone == "Samsung" else "Table 10"
        for method in ["Filtering"] + [_label(w) for w in TABLE_WINDOWS_S]:
            sel = errors[(errors.phone == phone) & (errors.method == method) & (errors.stat == "rms")].iloc[0]
            for ax in ("N", "E", "H"):
                comp.append(paper_ref(PAPER, table, f"{phone} WVC/ZUPT/GCP {method}: RMS {ax} error",
                                      paper_value(phone, method, "rms", ax), sel[ax], unit="m",
                                      note=f"simulated walk, mean of {n_seeds} seed(s)"))
        r = sw[(sw.phone == phone) & (sw.stat == "rms") & sw.window_s.isin(TABLE_WINDOWS_S)]
        best = float(r.loc[r["horizontal"].idxmin(), "window_s"])
        comp.append(paper_ref(PAPER, "Fig 19", f"{phone}: best of the 5/10/20 s windows (horizontal RMS)",
                              20.0, best, unit="s", note="paper: best window 20 s, 10-20 s recommended"))
    from ilocalg.experiments.ins_constraints import side_by_side

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
