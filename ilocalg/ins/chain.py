"""Liao et al.'s processing chain on one walk, and how a walk's solutions are scored and laid out.

A walk is what :func:`ilocalg.ins.pipeline.run_walk` reads (IMU log, initial state, GNSS and control-point
fixes) plus, for scoring, the truth: ``t_s``, ``pos_true_n_m``, ``mat_true_nb``, ``t_indoor_s`` (start of
the scored indoor part), ``t_true_s`` and ``gcp_t_s`` / ``gcp_id`` (control-point fixes), as
:class:`ilocalg.sim.ins_walk.InsWalk` gives them. A solution is ``(pos_n_m, mat_nb)`` per epoch.

The chain (:data:`METHODS`): Filtering + NHC/ZUPT, Filtering + WVC/ZUPT, + indoor control points (GCP),
and the RTS smoothing of the last (Liao et al. 2016, sec. 4.1, Tables 4-7).

References
----------
Liao, J.-K., Chiang, K.-W., Zhou, Z.-M., Li, C.-H. (2016). Using the on-line smoothing and constraint
algorithms to improve the accuracy of pedestrian indoor navigation. Tables 4-11.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.ins.eskf import run_eskf_batch
from ilocalg.ins.evaluate import error_stats, nav_errors
from ilocalg.ins.mechanisation import dcm_to_euler
from ilocalg.ins.pipeline import run_walk, run_walks, walk_filter_args
from ilocalg.ins.smoother import eskf_rts_smooth, rts_gains, rts_gains_shared

__all__ = ["METHODS", "run_methods", "run_methods_many", "smooth_gcp", "indoor_errors", "stats_rows", "gcp_fix_delay_s",
           "trajectory_frame"]

#: The four methods of Tables 4-7, in the order of the chain.
METHODS = ("Filtering + NHC/ZUPT", "Filtering + WVC/ZUPT", "Filtering + WVC/ZUPT + GCP",
           "Smoothing + WVC/ZUPT + GCP")


def run_methods(walk, stairs: str = "none", stair_action: str = "drop", nhc=None, prefix=(), gains_of=None):
    """The four methods on one walk: ``({method: (pos, mat)}, gcp_filter_result)``.

    ``nhc``: the ``(pos, mat)`` of Filtering + NHC/ZUPT on this walk when already run (it does not depend on the
    stair handling, which only the WVC uses). ``prefix``: earlier filter results on the same IMU log (e.g. the
    default stair handling's), whose shared beginning the filters reuse (:func:`~ilocalg.ins.eskf.run_eskf`); the
    filter with control points reuses the one without them up to the first control point. ``gains_of``: ``(ref,
    rts_gains(ref))`` of such an earlier filter with control points, whose smoother gains the smoothing reuses
    where the covariances are the same (:func:`~ilocalg.ins.smoother.rts_gains_shared`). The same numbers.
    """
    out = {}
    prefix = list(prefix)
    if nhc is None:
        r = run_walk(walk, "nhc", use_gcp=False, prefix=prefix)
        nhc = (r.pos_n_m, r.mat_nb)
    out[METHODS[0]] = nhc
    r = run_walk(walk, "wvc", use_gcp=False, stairs=stairs, stair_action=stair_action, prefix=prefix)
    out[METHODS[1]] = (r.pos_n_m, r.mat_nb)
    r = run_walk(walk, "wvc", use_gcp=True, stairs=stairs, stair_action=stair_action, prefix=[r, *prefix])
    out[METHODS[2]] = (r.pos_n_m, r.mat_nb)
    s = eskf_rts_smooth(r, with_cov=False, gains=rts_gains_shared(r, *gains_of) if gains_of else None)
    out[METHODS[3]] = (s.pos_n_m, s.mat_nb)
    return out, r



def run_methods_many(walks, stairs: str = "none", stair_action: str = "drop", smooth: bool = True):
    """:func:`run_methods` on several walks, each filter advanced together with the same filter of the other
    walks (:func:`~ilocalg.ins.pipeline.run_walks`; the filter with control points still reuses the one without
    them up to the first control point): the same numbers. Returns one ``({method: (pos, mat)},
    gcp_filter_result)`` per walk. ``smooth=False`` leaves the smoothing (the last method) to the caller
    (:func:`smooth_gcp`, e.g. one walk at a time, to keep only that walk's smoother gains)."""
    walks = list(walks)
    nhc = run_walks(walks, "nhc", use_gcp=False, keep_covariance=False)
    wvc = run_walks(walks, "wvc", use_gcp=False, stairs=stairs, stair_action=stair_action)
    gcp = run_eskf_batch([{**walk_filter_args(w, "wvc", True, stairs=stairs, stair_action=stair_action),
                           "prefix": (r,)} for w, r in zip(walks, wvc, strict=True)])
    out = []
    for a, b, r in zip(nhc, wvc, gcp, strict=True):
        sol = {METHODS[0]: (a.pos_n_m, a.mat_nb), METHODS[1]: (b.pos_n_m, b.mat_nb), METHODS[2]: (r.pos_n_m, r.mat_nb)}
        if smooth:
            smooth_gcp(sol, r)
        out.append((sol, r))
    return out


def smooth_gcp(sol: dict, r) -> np.ndarray:
    """Add the last method (the RTS smoothing of the filter with control points ``r``) to ``sol`` (``{method:
    (pos, mat)}`` of the first three); returns the smoother gains (:func:`~ilocalg.ins.smoother.rts_gains`, e.g.
    for ``run_methods(gains_of=(r, gains))``)."""
    G = rts_gains(r)
    s = eskf_rts_smooth(r, with_cov=False, gains=G)
    sol[METHODS[3]] = (s.pos_n_m, s.mat_nb)
    return G

def indoor_errors(walk, pos_n_m, mat_nb, ind=None) -> pd.DataFrame:
    """Per-epoch errors (:func:`ilocalg.ins.evaluate.nav_errors`) of a solution on the walk's indoor part
    (``ind``: a boolean mask of the epochs to score; default ``t_s >= t_indoor_s``)."""
    ind = walk.t_s >= walk.t_indoor_s if ind is None else ind
    return nav_errors(pos_n_m[ind], mat_nb[ind], walk.pos_true_n_m[ind], walk.mat_true_nb[ind])


def stats_rows(phone: str, method: str, seed: int, err: pd.DataFrame) -> list[dict]:
    """Max, RMS and STD rows (one per statistic, a column per axis) of per-epoch errors."""
    st = error_stats(err)
    return [{"phone": phone, "method": method, "seed": seed, "stat": k, **st[k]} for k in ("max", "rms", "std")]


def gcp_fix_delay_s(walk, gcp_xyz_m, lookback: int = 60) -> float:
    """Mean time from the closest approach to a control point (``gcp_xyz_m[id]``) to its fix (s), on the true
    clock, searching ``lookback`` epochs before each fix (NaN without fixes)."""
    k = np.searchsorted(walk.t_s, walk.gcp_t_s)
    d = []
    for kk, j in zip(k, walk.gcp_id, strict=True):
        g = gcp_xyz_m[j]
        lo = max(0, kk - lookback)
        dist = np.linalg.norm(walk.pos_true_n_m[lo:kk + 1] - g, axis=1)
        d.append(walk.t_true_s[kk] - walk.t_true_s[lo + int(np.argmin(dist))])
    return float(np.mean(d)) if d else np.nan


def trajectory_frame(phone: str, walk, solutions: dict, indoor, attitude: str = "heading") -> pd.DataFrame:
    """Per-epoch E, N, H of the truth and of every solution (``{method: (pos, mat)}``), one row per epoch and
    method, with the heading (``attitude="heading"``, deg) or the roll, pitch and heading errors against the
    truth (``attitude="errors"``, deg; zero for the truth)."""
    if attitude not in ("heading", "errors"):
        raise ValueError(f"attitude must be 'heading' or 'errors', got {attitude!r}")

    def frame(method, pos, mat):
        d = {"phone": phone, "method": method, "t_s": walk.t_s, "indoor": indoor, "E": pos[:, 0], "N": pos[:, 1],
             "H": pos[:, 2]}
        if attitude == "heading":
            d["heading_deg"] = np.rad2deg(dcm_to_euler(mat))[:, 2]
        elif method == "Truth":
            zero = np.zeros(walk.t_s.size)
            d.update(roll_err_deg=zero, pitch_err_deg=zero, heading_err_deg=zero)
        else:
            err = nav_errors(pos, mat, walk.pos_true_n_m, walk.mat_true_nb)
            d.update(roll_err_deg=err["Roll"].to_numpy(), pitch_err_deg=err["Pitch"].to_numpy(),
                     heading_err_deg=err["Heading"].to_numpy())
        return pd.DataFrame(d)

    frames = [frame("Truth", walk.pos_true_n_m, walk.mat_true_nb)]
    frames += [frame(method, pos, mat) for method, (pos, mat) in solutions.items()]
    return pd.concat(frames, ignore_index=True)
