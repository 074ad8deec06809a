"""The PSO thesis's published values beside the reproduced ones (Chao 2008): the comparison rows of experiment
``pso_k_factor`` (:func:`ilocalg.papers.paper_ref`), and Table 5-2 laid out as printed.

Paper values are labelled references only (:mod:`ilocalg.papers.pso`). Detected steps and the PSO distance are
set by input: the simulator walks the paper's true step count along a route as long as the paper's GPS
distance; the static compass RMS is scaled to the paper's raw value.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University. Table 5-2, Figs 5.14-5.15, sec. 5.1.3.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers import PAPERS, paper_ref
from ilocalg.papers.pso import PAPER_COMPASS_RMS, PAPER_PHASE2_A1, PAPER_TABLE_5_2
from ilocalg.pdr.k_factor import PSO_SETTINGS_PAPER

__all__ = ["table_5_2", "fig_5_12_block", "comparison_rows", "compass_rows"]

_PAPER = PAPERS["pso"]


def table_5_2(phase1: pd.DataFrame) -> pd.DataFrame:
    """Table 5-2's columns of the reproduced phase 1 (one row per walker), each beside the paper's."""
    out = phase1[["walker", "leg_cm", "k_pso", "true_steps", "det_steps", "gps_m", "pso_m", "acc_pct"]].copy()
    for col in ("k", "true_steps", "det_steps", "gps_m", "pso_m", "acc_pct"):
        out[f"paper_{col}"] = [PAPER_TABLE_5_2[w][col] for w in out["walker"]]
    return out


def fig_5_12_block(result, walk_row: pd.Series) -> pd.DataFrame:
    """A PSO run laid out as the thesis's result block (Fig 5.12, L833-840): its settings, iterations, fitness,
    best particle and position, and the walk's PSO, start-end and GPS distances (``walk_row``: one phase-1 row)."""
    s, r1 = PSO_SETTINGS_PAPER, walk_row
    return pd.DataFrame([{
        "particles": s["n_particles"], "maxSpeed": s["max_speed"], "minFitness": s["min_fitness"],
        "initWeight": s["w_init"], "finalWeight": s["w_final"], "c1": s["c1"], "c2": s["c2"],
        "Iters": result.n_iters, "Fitness": result.f_best, "Index": result.best_particle,
        "BestPos": float(result.x_best[0]), "PSO_sigma_dist_m": r1["pso_m"], "PSO_start_end_dist_m": r1["start_end_m"],
        "GPS_sigma_dist_m": r1["gps_m"], "PSO_diff_gps_m": abs(r1["gps_m"] - r1["pso_m"]),
        "PSO_diff_gps_rel": abs(r1["gps_m"] - r1["pso_m"]) / r1["gps_m"],
    }])


def comparison_rows(t52: pd.DataFrame, p2: pd.DataFrame, label: str, default_label: str | None = None,
                    note: str = "", route_scale: float = 1.0) -> list[dict]:
    """Table 5-2 and Fig 5.15 rows of one reading (``label``); with ``default_label`` the rows are an alternative
    reading of the rows labelled ``default_label``; ``note`` prefixes every row's note."""
    rows = []

    def ref(item, quantity, p, r, unit="", row_note="", by_input=False):
        full = "; ".join(x for x in (note, row_note) if x)
        if default_label is not None:
            alt_item = item.replace(label, default_label)
            return paper_ref(_PAPER, item, quantity, p, r, unit, full, row_class="alternative reading",
                             replaces=(alt_item, quantity))
        return paper_ref(_PAPER, item, quantity, p, r, unit, full,
                         row_class="set by input" if by_input else "result")

    for r in t52.itertuples():
        p = PAPER_TABLE_5_2[r.walker]
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} k (PSO)", p["k"], r.k_pso))
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} detected steps", p["det_steps"], r.det_steps,
                        row_note=f"true steps {r.true_steps} (walk design, from the paper)", by_input=True))
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} PSO distance", p["pso_m"], r.pso_m, "m",
                        row_note=f"simulated true route = the paper's GPS distance (route_scale {route_scale:g}, "
                                 "swept)", by_input=True))
        rows.append(ref(f"Table 5-2 {label}", f"{r.walker} accuracy vs GPS", p["acc_pct"], r.acc_pct, "%"))
    for place in ("park", "hall"):
        sel = p2[(p2["walker"] == "A1") & (p2["place"] == place)]
        if len(sel):
            r = sel.iloc[0]
            p = PAPER_PHASE2_A1[place]
            rows.append(ref(f"Fig 5.15 {label}", f"A1 {place} closure (PSO k)", p["closure_m"],
                            r["pso_closure_m"], "m"))
            rows.append(ref(f"Fig 5.15 {label}", f"A1 {place} closure (PSO k)", p["closure_pct"],
                            r["pso_closure_pct"], "%"))
    return rows


def compass_rows(compass: pd.DataFrame) -> list[dict]:
    """Sec. 5.1.3's static compass RMS (raw, MA, SG) beside the reproduced means; the raw one is set by input."""
    rows = []
    for key, r in zip(("raw", "ma", "sg"), compass.itertuples(), strict=True):
        note = "input: the simulator's static noise is scaled to this value" if key == "raw" else ""
        rows.append(paper_ref(_PAPER, "Sec 5.1.3", f"static compass RMS, {r.filter}", PAPER_COMPASS_RMS[key],
                              r.rms_deg_mean, "deg", note=note, row_class="set by input" if key == "raw" else "result"))
    return rows
