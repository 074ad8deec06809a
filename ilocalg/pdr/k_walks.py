"""Chao (2008)'s walk pipeline around the learned Weinberg k: steps, headings, great-circle dead reckoning.

A walk is a phone log ``imu`` (DataFrame with ``t_s``, the vertical acceleration ``acc_z_mps2`` and the
compass ``yaw_deg``, deg from north, clockwise) and a GPS track ``gps`` (``t_s``, ``lat_deg``,
``lon_deg``). Steps come from the slope sign-change detector with the +-RMS band (Fig. 3.9,
:mod:`ilocalg.pdr.sign_change`) after an optional moving average (``prefilter``); the track is the
great-circle dead reckoning (eq. 3.1-3.3) from the first GPS fix with Weinberg step lengths (eq. 2.5)
and the compass heading after MA(2,2). :func:`ilc_k_study` learns k on real walks (ILC 2020 traces,
surveyed waypoints as the reference distance) and applies it to held-out ones.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University. Eq. 2.5, 3.1-3.4, 4.4, Fig. 3.9.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.gnss import dead_reckon_latlon, haversine_m, latlon_to_local_m
from ilocalg.pdr.filters import moving_average
from ilocalg.pdr.k_factor import learn_k, step_factors
from ilocalg.pdr.registry import detect_steps
from ilocalg.pdr.sign_change import static_rms_mps2
from ilocalg.pdr.signals import along_gravity_mps2, gravity_lowpass_mps2
from ilocalg.pdr.step_length import weinberg_length_m

__all__ = ["PREFILTERS", "check_prefilter", "static_band_mps2", "detect_walk_steps", "step_headings_deg",
           "dr_track", "closure_m", "vertical_acc_mps2", "amp_cv", "ilc_k_study"]

#: Pre-filters of the walking acceleration: none, MA half-width 1, MA half-width 2 (nL = nR = 2).
PREFILTERS = ("none", "ma1", "ma2")
_MA_HALF = {"none": 0, "ma1": 1, "ma2": 2}


def check_prefilter(prefilter: str) -> int:
    """The moving average's half-width of ``prefilter`` (ValueError naming the allowed values otherwise)."""
    if prefilter not in PREFILTERS:
        raise ValueError(f"prefilter must be one of {PREFILTERS}, got {prefilter!r}")
    return _MA_HALF[prefilter]


def static_band_mps2(static_acc_z_mps2, prefilter: str = "ma2") -> float:
    """Static-noise RMS (eq. 3.4) of a static accelerometer log after the walk's pre-filter: the band's half-width."""
    n = check_prefilter(prefilter)
    return static_rms_mps2(np.asarray(static_acc_z_mps2), n, n, smooth=n > 0)


def detect_walk_steps(imu: pd.DataFrame, prefilter: str = "ma2", band_mps2: float | None = None) -> pd.DataFrame:
    """Sign-change steps (Fig. 3.9) of a walk's vertical acceleration.

    Parameters
    ----------
    prefilter : {"none", "ma1", "ma2"}
        Moving average on the walking acceleration (MA(2,2) by default).
    band_mps2 : float, optional
        Half-width of the +-RMS band (the static-noise RMS, :func:`static_band_mps2`); None uses the
        walking signal's RMS.
    """
    n = check_prefilter(prefilter)
    return detect_steps("sign_change", imu["acc_z_mps2"].to_numpy(), imu["t_s"].to_numpy(), smooth=n > 0,
                        n_left=max(n, 1), n_right=max(n, 1), rms_mps2=band_mps2)


def step_headings_deg(imu: pd.DataFrame, steps: pd.DataFrame) -> np.ndarray:
    """Compass yaw at each step (deg from north, clockwise), after MA(2,2) on the unwrapped yaw."""
    yaw = np.rad2deg(np.unwrap(np.deg2rad(imu["yaw_deg"].to_numpy(float))))
    return moving_average(yaw, 2, 2)[steps["i_peak"].to_numpy()] % 360.0


def dr_track(imu: pd.DataFrame, gps: pd.DataFrame, steps: pd.DataFrame, k: float, origin_deg: tuple[float, float],
             name: str = "walk") -> pd.DataFrame:
    """Great-circle dead reckoning (eq. 3.1-3.3) from the first GPS fix with Weinberg steps of factor ``k``.

    Returns
    -------
    DataFrame
        ``lat_deg``, ``lon_deg``, ``x_m``, ``y_m`` (local east/north about ``origin_deg``); one row for
        the start and one per step.

    Raises
    ------
    ValueError
        ``gps`` holds no fix (the message names the walk by ``name``).
    """
    if len(gps) == 0:
        raise ValueError(f"walk {name}: no GPS fix to start from")
    lat0, lon0 = gps["lat_deg"].iloc[0], gps["lon_deg"].iloc[0]
    L = weinberg_length_m(steps["a_max_mps2"].to_numpy(float), steps["a_min_mps2"].to_numpy(float), k)
    lat, lon = dead_reckon_latlon(lat0, lon0, step_headings_deg(imu, steps), L)
    x, y = latlon_to_local_m(lat, lon, *origin_deg)
    return pd.DataFrame({"lat_deg": lat, "lon_deg": lon, "x_m": x, "y_m": y})


def closure_m(track: pd.DataFrame) -> float:
    """Start-to-end great-circle distance of a track (m)."""
    return float(haversine_m(track["lat_deg"].iloc[0], track["lon_deg"].iloc[0],
                             track["lat_deg"].iloc[-1], track["lon_deg"].iloc[-1]))


def vertical_acc_mps2(imu: pd.DataFrame, gravity_halfwidth: int = 25) -> np.ndarray:
    """Vertical specific force, m/s^2: projection of a 3-axis accelerometer (``acc_x/y/z_mps2``) on gravity.

    Gravity is the moving average of the accelerometer over ``2 * gravity_halfwidth + 1`` samples
    (about 1 s at the ILC's 50 Hz).
    """
    A = imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy(float)
    return along_gravity_mps2(A, gravity_lowpass_mps2(A, gravity_halfwidth))


def amp_cv(steps: pd.DataFrame) -> float:
    """Coefficient of variation of the per-step ``Amax - Amin`` (NaN below 3 steps)."""
    if len(steps) < 3:
        return float("nan")
    d = (steps["a_max_mps2"] - steps["a_min_mps2"]).to_numpy(float)
    return float(d.std(ddof=1) / d.mean())


def ilc_k_study(data_dir: str | Path, seed: int = 0, fast: bool = False, ma_halfwidth: int = 6,
                min_dist_m: float = 5.0, k_fixed: float = 0.5) -> dict[str, pd.DataFrame]:
    """Learn k on half of the ILC site2/F4 walks and apply it to the other half (fast: 10 walks).

    The ILC traces do not say who walked; they were all recorded with the same phone model, so they
    are treated as one surveyor. Traces sorted by start time alternate between learning (even) and
    test (odd). A walk's reference distance is the sum of straight segments between consecutive
    surveyor waypoints (the 'GPS' distance); its steps are the sign-change steps between the first
    and last waypoint on the vertical acceleration (:func:`vertical_acc_mps2`) after an MA of
    half-width ``ma_halfwidth`` samples (6 at 50 Hz keeps the MA's first null, 3.8 Hz, above the
    step rate; the thesis's MA(2,2) at 8 Hz has it at 1.6 Hz). k is learned by PSO on the pooled
    learning walks (total-distance fitness) and compared with the fixed ``k_fixed`` (the thesis's 0.5).

    Returns
    -------
    dict
        ``walks``: one row per walk (with ``amp_cv``, the CV of the per-step ``Amax - Amin``: the
        measured step-to-step amplitude scatter behind the PSO walk simulator's ``step_amp_cv``);
        ``summary``: learned k (PSO, closed form), mean absolute and relative distance error on the
        test walks with the learned k and with ``k_fixed``.
    """
    from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor

    names = list_ilc_traces(data_dir)
    floor = load_ilc_floor(data_dir, names=names[:10] if fast else None, duplicate_bssid="keep_latest",
                           relisted_wifi="keep")
    traces = sorted(floor.traces.values(), key=lambda tr: float(tr.imu.index[0]))
    rows, step_tabs = [], []
    for tr in traces:
        wp = tr.waypoints
        if len(wp) < 2 or len(tr.imu) == 0:
            continue
        d = float(np.hypot(np.diff(wp["x_m"]), np.diff(wp["y_m"])).sum())
        if d < min_dist_m:
            continue
        t = tr.imu.index.to_numpy(float)
        av = vertical_acc_mps2(tr.imu)
        m = (t >= wp["t_s"].iloc[0]) & (t <= wp["t_s"].iloc[-1])
        st = detect_steps("sign_change", av[m], t[m], n_left=ma_halfwidth, n_right=ma_halfwidth,
                          smooth=True)
        dur = float(wp["t_s"].iloc[-1] - wp["t_s"].iloc[0])
        rows.append({"trace": tr.name, "n_waypoints": len(wp), "duration_s": dur, "waypoint_dist_m": d,
                     "det_steps": len(st), "steps_per_s": len(st) / dur,
                     "sum_q": float(step_factors(st).sum()) if len(st) else 0.0,
                     "amp_cv": amp_cv(st)})
        step_tabs.append(st)
    walks = pd.DataFrame(rows)
    walks["role"] = np.where(np.arange(len(walks)) % 2 == 0, "learn", "test")
    learn = walks["role"] == "learn"
    d_learn = float(walks.loc[learn, "waypoint_dist_m"].sum())
    pooled = pd.concat([s for s, r in zip(step_tabs, learn, strict=True) if r], ignore_index=True)
    summ, _ = learn_k(pooled, d_learn, "total", rng=np.random.default_rng([seed, 52]))
    walks["dist_learned_k_m"] = summ["k_pso"] * walks["sum_q"]
    walks["dist_k05_m"] = k_fixed * walks["sum_q"]
    for c in ("learned_k", "k05"):
        est = walks[f"dist_{c}_m"]
        walks[f"err_{c}_m"] = est - walks["waypoint_dist_m"]
        walks[f"err_{c}_pct"] = 100 * walks[f"err_{c}_m"] / walks["waypoint_dist_m"]
    test = walks[~learn]
    summary = pd.DataFrame([{
        "n_learn_walks": int(learn.sum()), "n_test_walks": int((~learn).sum()),
        "learn_dist_m": d_learn, "k_pso": summ["k_pso"], "k_closed": summ["k_closed"], "pso_iters": summ["iters"],
        "test_mae_learned_k_m": float(test["err_learned_k_m"].abs().mean()),
        "test_mae_k05_m": float(test["err_k05_m"].abs().mean()),
        "test_mape_learned_k_pct": float(test["err_learned_k_pct"].abs().mean()),
        "test_mape_k05_pct": float(test["err_k05_pct"].abs().mean()),
        "test_total_dist_err_learned_k_pct": float(100 * test["err_learned_k_m"].sum() / test["waypoint_dist_m"].sum()),
        "test_total_dist_err_k05_pct": float(100 * test["err_k05_m"].sum() / test["waypoint_dist_m"].sum()),
    }])
    return {"walks": walks, "summary": summary}
