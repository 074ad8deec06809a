"""i-Loc photo positioning: ST vs VA over shooting points and PoI combinations (thesis Figs 29-32).

``run(seed, fast, **params)`` simulates photos of the PoIs (:mod:`ilocalg.sim.photo_poi`, a layout built
from the thesis's text), locates every photo with every combination of 2..7 PoIs (120 combinations) by ST
(similar triangles with the sensor orientation), VAGIG and VABIG (view angles from a good and a bad initial
guess), VA started at the true centre (``VA_truth``: VA's floor of error, not in the thesis) and, for
combinations of >= 4 PoIs, by OpenCV's SQPnP and by a wall homography (only for combinations whose PoIs
share one wall), and scores the horizontal (floor-map) error in centimetres against the true camera centre.

VA's cost function (the sum of squared view-angle mismatches, :mod:`ilocalg.photo.view_angle`) is the
toolkit's own: the thesis names VA a gradient algorithm (L694) but gives no VA equation. By default VA
searches the floor position at the known phone height (2-D); ``va_free_z=True`` searches in 3-D.

Sweeps: :func:`layout_sweep` (the layouts that satisfy the text, Fig 28 being missing: rooms and one-wall
layouts, both families satisfy every constraint of the text, :mod:`ilocalg.sim.photo_poi`) and
:func:`good_guess_sweep` (the good guess's spread, an assumption); :func:`readings` lists every
modelling choice with the thesis line it follows or the source of the value.

Tables returned
---------------
``layout_pois``, ``layout_shots``
    The simulated set-up (Figs 27-28).
``inputs``
    The simulation inputs used (sources in :mod:`ilocalg.sim.photo_poi`).
``per_shot`` (Fig 29)
    Mean error per shooting point and method, with the distance to ``p4``.
``distance_trend``
    Per method: Spearman correlation and least-squares slope of the per-shot mean error against the
    distance to ``p4`` (the thesis's explanation of Fig 29).
``per_k`` (Fig 30)
    Mean error per number of PoIs and method.
``per_combo`` (Fig 31)
    Mean error per PoI combination and method, with the median ST condition number and the
    smallest PoI-pair view angle.
``combo_geometry``
    Spearman correlation, over combinations, of each method's error with the ST condition number and
    with the smallest view angle.
``near_collinear`` (Fig 32)
    The thesis's near-collinear combinations {1,3}, {1,4}, {5,6}, {1,3,4} beside the mean of all
    combinations of the same size.
``modern``
    ST with sensor and with true orientation, SQPnP and homography per number of PoIs (>= 4).
``propagation``
    ST with all seven PoIs: Monte-Carlo RMS 3-D error per shooting point beside the first-order
    prediction from the orientation and drag errors (:func:`ilocalg.photo.st_error_propagation`).
``va_convergence``
    Share of VA runs that converged and their mean iteration count.
``layout_check``
    The layout against every constraint of the text (:func:`ilocalg.sim.photo_poi.check_layout`).
``readings``
    One row per modelling choice: ``choice``, ``paper_line``, ``text_says``, ``code_does``, ``source``.
``comparison``
    Paper values (Fig 30 text, overall means) beside the reproduced ones (``paper_ref`` rows).
``errors``
    Long table, one row per photo, combination and method (for plots).

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 6.3, Figs 29-32.
Ye, C.-H. and Huang, W.-L. Positioning by combining images and inertial sensors (a survey). Teaching
report, National Kaohsiung University of Applied Sciences. Sec. 4, eq. (3)-(5).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from itertools import combinations

import numpy as np
import pandas as pd

from ilocalg.papers.comparison_iloc_photo import NEAR_COLLINEAR_PAPER, PAPER, fig30_rows
from ilocalg.papers.readings_iloc_photo import GOOD_GUESS_SD_M, SENSITIVITY_GRID
from ilocalg.papers.readings_iloc_photo import readings as _readings
from ilocalg.photo import (
    homography_dlt_batch,
    homography_pose_batch,
    square_marker_pose,
    st_error_propagation,
    st_solve_batch,
    view_angles_rad,
)
from ilocalg.photo.combinations import combo_label, horizontal_error_cm, locate_methods
from ilocalg.sim import photo_poi
from ilocalg.sim.marker_views import MARKER_DEFAULTS, simulate_marker_views
from ilocalg.units import as_rng

__all__ = ["run", "sensitivity", "SENSITIVITY_GRID", "marker_ranging", "MARKER_DEFAULTS", "combo_label",
           "NEAR_COLLINEAR_PAPER", "PAPER", "METHODS", "SHOWN_METHODS", "layout_sweep", "good_guess_sweep",
           "readings", "GOOD_GUESS_SD_M"]

#: Methods of the thesis's comparison (Figs 29-32).
METHODS = ("ST", "VAGIG", "VABIG")
#: Methods shown in the per-shot / per-k tables: the thesis's three and VA started at the truth.
SHOWN_METHODS = METHODS + ("VA_truth",)
#: Tables of :func:`run` that show methods other than the thesis's three (left out with ``side_studies=False``).
_SHOW_OTHER_METHODS = ("per_shot", "per_k", "modern", "va_convergence", "errors")


def run(seed: int = 0, fast: bool = False, n_photos: int | None = None, va_free_z: bool = False,
        va_max_iter: int | None = None, ks=(2, 3, 4, 5, 6, 7), layout: str = photo_poi.DEFAULT_LAYOUT,
        side_studies: bool = True, **sim_params) -> dict[str, pd.DataFrame]:
    """Simulate, locate and score; see the module docstring for the tables.

    Parameters
    ----------
    seed : int
        Simulation seed.
    fast : bool
        One photo per shooting point instead of 10 and at most 500 VA iterations instead of 2000.
    n_photos : int, optional
        Photos per shooting point (overrides ``fast``).
    va_free_z : bool
        ``False`` (default): VA searches the floor position at the known phone height (the guesses'
        height, the nominal eye height); ``True``: all three coordinates (the thesis's output
        ``c = [c_x c_y c_z]``, L672).
    va_max_iter : int, optional
        Iteration cap of the VA gradient descent (default 500 when ``fast``, else 2000).
    ks : sequence of int
        Numbers of PoIs per combination to evaluate (2..7; tables needing a missing size leave it out).
    layout : str
        A key of :data:`ilocalg.sim.photo_poi.LAYOUTS` (default: the default layout built from the text).
    side_studies : bool
        False locates with the thesis's methods only (ST with the measured orientation, VAGIG, VABIG: no VA from
        the truth, ST with the true orientation, SQPnP or homography) and leaves out the tables that show the
        others (``per_shot``, ``per_k``, ``modern``, ``va_convergence``, ``errors``); the tables returned are the
        same either way. The seed sweep and the claims' robustness samples read none of them
        (:data:`ilocalg.workflow.manifest.SWEEP_KWARGS`).
    **sim_params
        Overrides of :data:`ilocalg.sim.photo_poi.DEFAULTS` (e.g. ``drag_sd_px``).
    """
    out = _run(seed, fast, n_photos, va_free_z, va_max_iter, ks, layout, SHOWN_METHODS if side_studies else METHODS,
               side_studies, True, sim_params)
    if not side_studies:  # the tables that show the methods left out
        out = {name: df for name, df in out.items() if name not in _SHOW_OTHER_METHODS}
    return out


#: :func:`locate_methods` results of this process by a digest of their inputs (:func:`_locate`): notebook 11's
#: layout sweep meets run()'s default layout again (the same photos, starts and settings). As many entries as run()
#: has combination sizes; nothing is kept between processes.
_LOCATED: OrderedDict = OrderedDict()
_LOCATED_MAX = 6
#: the methods :func:`locate_methods` adds with ``others=True``
_OTHER_METHODS = ("ST_true_orientation", "PnP_SQPnP", "homography")


def _locate(P, U, f, Tm, Tt, c0, va_max_iter, va_free_z, others):
    """:func:`locate_methods`, reused when the same inputs were located before in this process (an ``others=True``
    result also serves ``others=False``: the same estimates for the methods both locate, in the same order)."""
    h = hashlib.blake2b(digest_size=20)
    for a in (P, U, Tm, Tt, *c0.values()):
        a = np.ascontiguousarray(a, dtype=np.float64)
        h.update(repr(a.shape).encode())
        h.update(a.tobytes())
    h.update(repr((float(f), tuple(c0), int(va_max_iter), bool(va_free_z))).encode())
    key = h.digest()
    hit = _LOCATED.get(key)
    if hit is None or (others and not hit[0]):
        est, st, conv = locate_methods(P, U, f, Tm, Tt, c0, va_max_iter, va_free_z, others=others)
        for a in (*est.values(), *st.values()):
            if isinstance(a, np.ndarray):
                a.flags.writeable = False  # shared by later hits: read only
        hit = (others, est, st, conv)
        _LOCATED[key] = hit
        while len(_LOCATED) > _LOCATED_MAX:
            _LOCATED.popitem(last=False)
    _LOCATED.move_to_end(key)
    _, est, st, conv = hit
    if not others:
        est = {name: c for name, c in est.items() if name not in _OTHER_METHODS}
    return dict(est), dict(st), [dict(c) for c in conv]


def _run(seed, fast, n_photos, va_free_z, va_max_iter, ks, layout, shown_methods, others, measures, sim_params,
         sweep: bool = False):
    """The tables of :func:`run` with VA from the starts of ``shown_methods`` only, ``others=False``: without ST with
    the true orientation, SQPnP and the homography (``modern`` then has ST only), ``measures=False``: without the
    ``measures`` table (and its marker ranging). The sweeps below read only ``per_k``, ``per_shot``, ``errors`` and
    ``layout_check``, which are those of :func:`run` for the methods located; ``sweep=True`` returns those four
    alone (the other tables are not built)."""
    ks = sorted({int(k) for k in ks})
    if not ks or ks[0] < 2 or ks[-1] > 7:
        raise ValueError(f"ks must be numbers of PoIs between 2 and 7, got {ks}")
    n_photos = int(n_photos) if n_photos is not None else (1 if fast else 10)
    va_max_iter = int(va_max_iter) if va_max_iter is not None else (500 if fast else 2000)
    sim = photo_poi.simulate(seed, n_photos=n_photos, layout=layout, **sim_params)
    f = sim.f_px
    N = sim.c_m.shape[0]
    rows = []
    conv_rows = []
    combo_info = []
    for k in ks:
        combos = list(combinations(range(7), k))
        C = len(combos)
        idx = np.array(combos)  # (C, k)
        P = np.broadcast_to(sim.pois_m[idx][None], (N, C, k, 3)).reshape(N * C, k, 3)
        U = sim.img_px[:, idx].reshape(N * C, k, 2)
        Tm = np.repeat(sim.T_meas, C, axis=0)
        Tt = np.repeat(sim.T_true, C, axis=0)
        ctrue = np.repeat(sim.c_m, C, axis=0)
        c0 = {name: np.repeat(c, C, axis=0) for name, c in (("VAGIG", sim.c0_good_m), ("VABIG", sim.c0_bad_m),
                                                           ("VA_truth", sim.c_m)) if name in shown_methods}
        est, st, conv = _locate(P, U, f, Tm, Tt, c0, va_max_iter, va_free_z, others)
        conv_rows += [{"method": c.pop("method"), "k": k, **c} for c in conv]
        if not sweep:  # the combinations' geometry (per_combo)
            cond = st["cond"].reshape(N, C)
            va_true = view_angles_rad(sim.c_m[:, None, :].repeat(C, 1).reshape(N * C, 3), P).reshape(N, C, -1)
            for j, combo in enumerate(combos):
                combo_info.append({"combo": combo_label(combo), "k": k,
                                   "st_cond_median": float(np.median(cond[:, j])),
                                   "min_view_angle_deg": float(np.degrees(va_true[:, j].min(axis=1).mean()))})
        shot = np.repeat(sim.shot_index, C)
        photo = np.repeat(np.arange(N), C)
        labels = np.tile(np.array([combo_label(c) for c in combos], dtype=object), N)
        for name, c in est.items():
            rows.append(pd.DataFrame({"photo": photo, "shot": shot + 1, "k": k, "combo": labels, "method": name,
                                      "error_cm": horizontal_error_cm(c, ctrue)}))
    errors = pd.concat(rows, ignore_index=True)
    bad_rows = ~np.isfinite(errors["error_cm"]) & (errors["method"] != "homography")
    if bad_rows.any():
        bad = errors[bad_rows].iloc[0]
        raise ValueError(f"non-finite error for {bad['method']} combo {bad['combo']} photo {bad['photo']}")
    shots = photo_poi.shots_frame(layout)

    thesis = errors[errors["method"].isin(METHODS)]
    shown_methods = list(shown_methods)
    shown = errors[errors["method"].isin(shown_methods)]
    per_shot = shown.pivot_table(index="shot", columns="method", values="error_cm", aggfunc="mean")[shown_methods]
    per_shot = per_shot.reset_index()
    per_shot.insert(1, "dist_to_p4_m", shots["dist_to_p4_m"].to_numpy()[per_shot["shot"].to_numpy() - 1])
    per_shot.columns.name = None

    trend = []
    for m in METHODS:
        x = per_shot["dist_to_p4_m"].to_numpy()
        y = per_shot[m].to_numpy()
        rho = pd.Series(x).corr(pd.Series(y), method="spearman")
        slope = np.polyfit(x, y, 1)[0]
        trend.append({"method": m, "spearman_rho": float(rho), "slope_cm_per_m": float(slope),
                      "error_t1_cm": float(y[0]), "error_t7_cm": float(y[-1])})
    distance_trend = pd.DataFrame(trend)

    per_k = shown.pivot_table(index="k", columns="method", values="error_cm", aggfunc="mean")[shown_methods]
    per_k.insert(0, "n_combos", errors[errors["method"] == "ST"].groupby("k")["combo"].nunique())
    per_k = per_k.reset_index()
    per_k.columns.name = None
    p = sim.params
    layout_check = photo_poi.check_layout(layout, f_px=f, width_px=int(p["width_px"]), height_px=int(p["height_px"]),
                                          eye_height_m=p["eye_height_m"])
    if sweep:
        return {"per_shot": per_shot, "per_k": per_k, "layout_check": layout_check, "errors": errors}

    info = pd.DataFrame(combo_info)
    per_combo = thesis.pivot_table(index="combo", columns="method", values="error_cm", aggfunc="mean")[list(METHODS)]
    per_combo = info.merge(per_combo.reset_index(), on="combo")
    on_line = {0, 2, 3, 4, 5}
    per_combo["on_horizontal_line"] = [set(int(i) - 1 for i in c.strip("{}").split(",")) <= on_line
                                       for c in per_combo["combo"]]
    per_combo.columns.name = None

    cr = []
    for m in METHODS:
        for col in ("st_cond_median", "min_view_angle_deg"):
            cr.append({"method": m, "versus": col, "spearman_rho_all_combos": float(
                per_combo[col].corr(per_combo[m], method="spearman")),
                "spearman_rho_pairs_only": float(per_combo.loc[per_combo["k"] == 2, col].corr(
                    per_combo.loc[per_combo["k"] == 2, m], method="spearman"))})
    combo_geometry = pd.DataFrame(cr)

    nc = []
    for combo in NEAR_COLLINEAR_PAPER:
        if len(combo) not in ks:
            continue
        lab = "{" + ",".join(map(str, combo)) + "}"
        r = per_combo[per_combo["combo"] == lab].iloc[0]
        same_k = per_combo[per_combo["k"] == len(combo)]
        row = {"combo": lab, "k": len(combo), "st_cond_median": r["st_cond_median"],
               "st_cond_median_all_same_k": float(same_k["st_cond_median"].median()),
               "min_view_angle_deg": r["min_view_angle_deg"]}
        for m in METHODS:
            row[m] = r[m]
            row[f"{m}_mean_same_k"] = float(same_k[m].mean())
            row[f"{m}_rank_among_same_k"] = int((same_k[m] > r[m]).sum() + 1)
        row["n_same_k"] = len(same_k)
        nc.append(row)
    near_collinear = pd.DataFrame(nc)

    modern_methods = ["ST", "ST_true_orientation", "PnP_SQPnP", "homography"]
    mod = errors[(errors["k"] >= 4) & errors["method"].isin(modern_methods)]
    if mod.empty:
        mod = pd.DataFrame({"k": [4], "method": ["ST"], "error_cm": [np.nan]})
    modern = mod.pivot_table(index="k", columns="method", values="error_cm", aggfunc="mean", dropna=False)
    # the homography needs PoIs on one plane; combinations that span walls have no homography estimate
    modern = modern.reindex(columns=modern_methods)
    med = mod.groupby("method")["error_cm"].mean()
    modern.loc["all k>=4"] = [med.get(m, np.nan) for m in modern_methods]
    modern = modern.reset_index()
    modern["k"] = modern["k"].astype(str)
    modern.columns.name = None

    # orientation-error propagation, all seven PoIs
    prop = st_error_propagation(sim.pois_m, sim.img_true_px, f, sim.T_true, np.deg2rad(p["tilt_sd_deg"]),
                                np.deg2rad(p["yaw_sd_deg"]), p["drag_sd_px"])
    st7 = st_solve_batch(sim.pois_m, sim.img_px, f, sim.T_meas)["c_m"]
    err7 = np.linalg.norm(st7 - sim.c_m, axis=1)
    pr = []
    for s in range(7):
        m = sim.shot_index == s
        pr.append({"shot": s + 1, "dist_to_p4_m": float(shots["dist_to_p4_m"][s]),
                   "mc_rms_3d_cm": 100 * float(np.sqrt(np.mean(err7[m] ** 2))),
                   "predicted_rms_3d_cm": 100 * float(np.sqrt(np.mean(prop["rms_m"][m] ** 2))),
                   "predicted_orientation_only_cm": 100 * float(np.sqrt(np.mean(
                       np.trace(prop["cov_orientation_m2"][m], axis1=1, axis2=2)))),
                   "predicted_drag_only_cm": 100 * float(np.sqrt(np.mean(
                       np.trace(prop["cov_drag_m2"][m], axis1=1, axis2=2))))})
    propagation = pd.DataFrame(pr)

    overall = thesis.groupby("method")["error_cm"].mean()
    k_means = per_k.set_index("k")
    comp = fig30_rows(k_means, overall, ks, METHODS)
    comparison = pd.DataFrame(comp)
    inputs = pd.DataFrame({"parameter": [k for k in p if k != "layout"],
                           "value": [float(v) for k, v in p.items() if k != "layout"]})
    # named scalars for the claims ledger (ilocalg/papers/iloc.py): Fig 30 per PoI count, Fig 29's distance
    # trend, Figs 31-32's combinations (near-collinear vs same-size; near the shots vs near p3-p5)
    meas = [{"quantity": "mean error by PoI count", "item": f"{m}, {int(k)} PoIs", "value": float(k_means.loc[k, m]),
             "unit": "cm"} for k in k_means.index for m in METHODS]
    meas += [{"quantity": "error vs distance to p4, Spearman rho", "item": r["method"],
              "value": float(r["spearman_rho"]), "unit": "-"} for _, r in distance_trend.iterrows()]
    if len(near_collinear):
        meas.append({"quantity": "near-collinear combos' error / mean of same-size combos", "item": "ST",
                     "value": float((near_collinear["ST"] / near_collinear["ST_mean_same_k"]).mean()), "unit": "-"})
    cm = per_combo.set_index("combo")["ST"]
    near_c, far_c = ["{1,2}", "{6,7}"], ["{3,4}", "{3,5}", "{4,5}", "{3,4,5}"]
    if all(c in cm.index for c in near_c + far_c):
        meas.append({"quantity": "ST error, combos {1,2},{6,7} / combos {3,4},{3,5},{4,5},{3,4,5}", "item": "ST",
                     "value": float(cm[near_c].mean() / cm[far_c].mean()), "unit": "-"})
    out = {
        "layout_pois": photo_poi.pois_frame(layout),
        "layout_shots": shots,
        "inputs": inputs,
        "per_shot": per_shot,
        "distance_trend": distance_trend,
        "per_k": per_k,
        "per_combo": per_combo,
        "near_collinear": near_collinear,
        "combo_geometry": combo_geometry,
        "modern": modern,
        "propagation": propagation,
        "va_convergence": pd.DataFrame(conv_rows),
        "comparison": comparison,
        "layout_check": layout_check,
        "readings": readings(layout, va_free_z, **{k: v for k, v in p.items() if k in photo_poi.DEFAULTS}),
        "errors": errors,
    }
    if measures:
        out["measures"] = pd.concat([pd.DataFrame(meas), _marker_measures(seed, fast)], ignore_index=True)
    return out


def _marker_measures(seed: int, fast: bool) -> pd.DataFrame:
    """Named scalars for the claims ledger (ilocalg.papers.survey): range error of the homography (survey
    eq. 3-5, Fig 8) and of IPPE to a square marker, without and with 1 px corner noise (:func:`marker_ranging`)."""
    t = marker_ranging(seed=seed, fast=fast, corner_sd_px=(0.0, 1.0))
    return pd.DataFrame([{"quantity": f"{name} range RMS error", "unit": "cm",
                          "item": f"{r.distance_m:g} m, corner sd {r.corner_sd_px:g} px",
                          "value": float(getattr(r, f"{key}_range_rms_error_cm"))}
                         for r in t.itertuples() for key, name in (("homography", "homography"), ("ippe", "IPPE"))])


def readings(layout: str = photo_poi.DEFAULT_LAYOUT, va_free_z: bool = False, **sim_params) -> pd.DataFrame:
    """One row per modelling choice of :func:`run` (declared in :mod:`ilocalg.papers.readings_iloc_photo`);
    ``sim_params`` override :data:`ilocalg.sim.photo_poi.DEFAULTS` as in the run."""
    return _readings(getattr(layout, "name", layout), va_free_z, {**photo_poi.DEFAULTS, **sim_params})


def layout_sweep(seed: int = 0, fast: bool = False, layouts=None, ks=(2, 3, 4, 5, 6, 7)) -> dict[str, pd.DataFrame]:
    """Figs 29-30 summaries for every layout that satisfies the text (and the earlier ``"row"``).

    ``layouts``: names of :data:`ilocalg.sim.photo_poi.LAYOUTS` (default: all of them, rooms A-G, one-wall
    W1-W4 and ``"row"``), or ``"all"`` for every satisfying member of both grids
    (:func:`ilocalg.sim.photo_poi.satisfying_layouts`, 42 layouts). The ``family`` column says "room",
    "one wall" or "row (earlier)"; ``spread_by_family`` gives the spread per family.

    Returns
    -------
    dict
        ``per_layout``: one row per layout and method: overall mean error, mean error with 2 and 7
        PoIs, Spearman rho of the per-shot error against the distance to p4, and whether the layout
        satisfies the text (``all_pois_framed`` False, errors NaN and not satisfying: a layout whose photos, with
        the aim error, put a PoI off the screen, as W4 does with 10 photos per shot); ``spread``: per method,
        min / max / sd over the satisfying layouts.
    """
    if isinstance(layouts, str) and layouts == "all":
        items = list(photo_poi.satisfying_layouts().values()) + [photo_poi.LAYOUTS["row"]]
    else:
        items = [photo_poi.LAYOUTS[n] if isinstance(n, str) and n in photo_poi.LAYOUTS else n
                 for n in (layouts if layouts is not None else list(photo_poi.LAYOUTS))]
    rows = []
    for lay in items:
        name = lay.name if isinstance(lay, photo_poi.Layout) else lay
        fam = ("row (earlier)" if name == "row" else
               "one wall" if isinstance(lay, photo_poi.Layout) and lay.dims.get("family") == "one wall" else "room")
        try:
            t = _run(seed, fast, None, False, None, ks, lay, SHOWN_METHODS, False, False, {}, sweep=True)
        except ValueError as e:  # a shot whose aim error puts a PoI off the screen: the layout cannot be photographed
            if "falls outside the screen" not in str(e):
                raise
            rows += [{"layout": name, "family": fam, "satisfies_text": False, "all_pois_framed": False, "method": m,
                      "overall_mean_cm": np.nan, "k2_cm": np.nan, "k7_cm": np.nan, "spearman_rho_dist_p4": np.nan}
                     for m in SHOWN_METHODS]
            continue
        ok = bool(t["layout_check"]["satisfied"].all())
        pk = t["per_k"].set_index("k")
        tr = t["per_shot"]
        for m in SHOWN_METHODS:
            err = t["errors"]
            rows.append({"layout": name, "family": fam, "satisfies_text": ok, "all_pois_framed": True, "method": m,
                         "overall_mean_cm": float(err.loc[err["method"] == m, "error_cm"].mean()),
                         "k2_cm": float(pk.loc[2, m]) if 2 in pk.index else np.nan,
                         "k7_cm": float(pk.loc[7, m]) if 7 in pk.index else np.nan,
                         "spearman_rho_dist_p4": float(pd.Series(tr["dist_to_p4_m"]).corr(tr[m], method="spearman"))})
    per_layout = pd.DataFrame(rows)
    sat = per_layout[per_layout["satisfies_text"]]
    spread = sat.groupby("method", sort=False).agg(
        n_layouts=("layout", "nunique"), overall_min_cm=("overall_mean_cm", "min"),
        overall_max_cm=("overall_mean_cm", "max"), overall_sd_cm=("overall_mean_cm", "std"),
        k2_min_cm=("k2_cm", "min"), k2_max_cm=("k2_cm", "max"),
        k7_min_cm=("k7_cm", "min"), k7_max_cm=("k7_cm", "max")).reset_index()
    by_fam = sat.groupby(["family", "method"], sort=False).agg(
        n_layouts=("layout", "nunique"), overall_mean_cm=("overall_mean_cm", "mean"),
        overall_min_cm=("overall_mean_cm", "min"), overall_max_cm=("overall_mean_cm", "max")).reset_index()
    return {"per_layout": per_layout, "spread": spread, "spread_by_family": by_fam}


def good_guess_sweep(seed: int = 0, fast: bool = False, sds=GOOD_GUESS_SD_M, ks=(2, 7),
                     layout: str = photo_poi.DEFAULT_LAYOUT) -> pd.DataFrame:
    """VAGIG's error against the good guess's spread (an assumption), beside VA from the truth and VABIG."""
    rows = []
    for sd in sds:
        t = _run(seed, fast, None, False, None, ks, layout, SHOWN_METHODS, False, False,
                 {"good_guess_sd_m": float(sd)}, sweep=True)
        for _, r in t["per_k"].iterrows():
            for m in ("VA_truth", "VAGIG", "VABIG", "ST"):
                rows.append({"good_guess_sd_m": float(sd), "k": int(r["k"]), "method": m, "error_cm": float(r[m])})
    return pd.DataFrame(rows)


def sensitivity(seed: int = 0, fast: bool = False, ks=(2, 7), grid=SENSITIVITY_GRID) -> pd.DataFrame:
    """How the ST / VA errors move when one simulation input changes (all others at their defaults).

    Runs :func:`run` on combinations of ``ks`` PoIs for each value in ``grid`` and returns a long table
    (``parameter``, ``value`` (float; for ``va_free_z`` 1 = 3-D search), ``k``, ``method``, ``error_cm``).
    It shows which conclusions depend on the documented-but-assumed inputs; it is not used to choose them.
    ``fast`` uses one photo per shooting point and only the first and last value of the drag and heading errors.
    """
    rows = []
    n = 1 if fast else 4
    if fast:
        grid = tuple((name, (values[0], values[-1])) for name, values in grid if name in ("drag_sd_px", "yaw_sd_deg"))
    for name, values in grid:
        for v in values:
            free_z, sim = (v, {}) if name == "va_free_z" else (False, {name: v})
            t = _run(seed, fast, n, free_z, None, ks, photo_poi.DEFAULT_LAYOUT, METHODS, False, False, sim,
                     sweep=True)["per_k"]
            for _, r in t.iterrows():
                for m in METHODS:
                    rows.append({"parameter": name, "value": float(v), "k": int(r["k"]), "method": m,
                                 "error_cm": float(r[m])})
    return pd.DataFrame(rows)


def marker_ranging(seed: int = 0, fast: bool = False, distances_m=(1.0, 2.0, 3.0, 4.0, 5.0),
                   corner_sd_px=(0.5, 1.0, 2.0), f_px: float = photo_poi.DEFAULTS["f_px"],
                   **marker) -> pd.DataFrame:
    """Distance to a square planar marker (a QR code) from its four corners by ``H = K [r1 r2 t]``.

    The phone looks at a marker of side ``side_m`` on the wall from ``distance`` metres, at a bearing
    uniform in ``+-bearing_max_deg`` off the wall's normal (:func:`ilocalg.sim.marker_views.simulate_marker_views`,
    ``marker`` overrides its :data:`MARKER_DEFAULTS`); the four detected corners get independent
    ``N(0, corner_sd^2)`` errors per axis. The homography is estimated by the normalised DLT and
    decomposed (:func:`ilocalg.photo.homography_pose`); the range ``l = ||t||`` and the camera centre
    are scored, beside OpenCV's IPPE (:func:`ilocalg.photo.square_marker_pose`) on the same corners.

    Returns
    -------
    DataFrame with one row per (distance, corner error): ``marker_px`` (the marker's width on the
    screen) and, for ``homography`` and ``ippe``, ``*_range_mean_error_cm`` (signed),
    ``*_range_rms_error_cm`` and ``*_position_rms_error_cm`` (3-D camera centre).

    References
    ----------
    Ye and Huang (survey), sec. 4, eq. (3)-(5) and Fig 8 (distance from the 2-D code to the camera).
    """
    rng = as_rng(seed)
    n = 50 if fast else 500
    side_m = {**MARKER_DEFAULTS, **marker}["side_m"]
    rows = []
    for d in distances_m:
        v = simulate_marker_views(rng, d, n, f_px, **marker)
        XY, centre, c, img_true = v.corners_plane_m, v.centre_m, v.c_m, v.img_true_px
        width_px = float(np.mean(np.linalg.norm(img_true[:, 1] - img_true[:, 0], axis=1)))
        for sd in corner_sd_px:
            img = img_true + sd * rng.standard_normal(img_true.shape)
            row = {"distance_m": float(d), "corner_sd_px": float(sd), "marker_px": width_px}
            for name in ("homography", "ippe"):
                rng_err = np.empty(n)
                pos_err = np.empty(n)
                if name == "homography":  # the n views in one batch (each pose that of the view alone)
                    hp = homography_pose_batch(homography_dlt_batch(XY, img), f_px)
                    dist, c_plane = hp.distance_m, hp.c_plane_m
                else:
                    poses = [square_marker_pose(img[b], side_m, f_px) for b in range(n)]
                    dist, c_plane = [p.distance_m for p in poses], [p.c_plane_m for p in poses]
                for b in range(n):
                    rng_err[b] = dist[b] - np.linalg.norm(c[b] - centre)
                    cp = c_plane[b]  # plane frame: e1 = x, e2 = z, e3 = -y
                    pos_err[b] = np.linalg.norm(centre + np.array([cp[0], -cp[2], cp[1]]) - c[b])
                row[f"{name}_range_mean_error_cm"] = 100 * float(rng_err.mean())
                row[f"{name}_range_rms_error_cm"] = 100 * float(np.sqrt(np.mean(rng_err ** 2)))
                row[f"{name}_position_rms_error_cm"] = 100 * float(np.sqrt(np.mean(pos_err ** 2)))
            rows.append(row)
    return pd.DataFrame(rows)
