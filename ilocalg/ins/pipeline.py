"""From a phone walk to filtered / smoothed solutions: the paper's processing chain.

``walk_updates`` builds the measurement sets (GNSS outdoors, ZUPT at detected standstills, NHC or
WVC while walking, control points); ``run_walk`` levels the phone, initialises and runs the
21-state filter. Any object with the attributes of :class:`ilocalg.sim.ins_walk.InsWalk` (times,
sensors, GNSS, control points, ``init``) can be processed.

References
----------
Liao, Chiang, Zhou, Li (2016), sec. 3 and 4.1 (Filtering + NHC/ZUPT, + WVC/ZUPT, + GCP; smoothing).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from ilocalg.ins.constraints import (
    detect_stairs_baro,
    detect_stationary,
    nhc_updates,
    step_epochs,
    step_frequency_hz,
    wvc_updates,
    zupt_updates,
)
from ilocalg.ins.eskf import (
    EskfConfig,
    EskfResult,
    Measurement,
    PositionFix,
    initial_covariance,
    run_eskf,
    run_eskf_batch,
)
from ilocalg.ins.mechanisation import coarse_level, euler_to_dcm, phone_to_body
from ilocalg.io.schema import ACC_COLS, GYR_COLS

__all__ = ["PhoneFilterSettings", "body_imu_from_log", "stair_mask", "walk_updates", "walk_filter_args", "run_walk",
           "run_walks", "BATCH_WALKS", "walk_batches", "SmoothingInputs", "smoothing_inputs",
           "SMOOTHING_STORE"]


def body_imu_from_log(imu) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The INS inputs ``(t_s, gyr_b_radps, acc_b_mps2)`` of an IMU log (package data type, phone frame).

    The accelerometer and gyroscope columns are rotated into the body frame with
    :data:`ilocalg.ins.mechanisation.MAT_PHONE_TO_BODY` (phone held flat, top along the walk).
    """
    missing = [c for c in ACC_COLS + GYR_COLS if c not in imu.columns]
    if missing:
        raise ValueError(f"IMU log: columns {missing} missing (expected {list(ACC_COLS + GYR_COLS)})")
    t = imu.index.to_numpy(dtype=float)
    return t, phone_to_body(imu[list(GYR_COLS)].to_numpy(dtype=float)), phone_to_body(
        imu[list(ACC_COLS)].to_numpy(dtype=float))


@dataclass(frozen=True)
class PhoneFilterSettings:
    """Filter tuning for a hand-held phone (generic phone grade, not the simulator's drawn values).

    Noise densities are inflated above the datasheet class to absorb hand vibration and the low,
    irregular sampling rate. Constraint weights: NHC tight (vehicle-like), WVC relaxed lateral /
    vertical plus the forward speed (sec. 3.2).
    """

    eskf: EskfConfig = EskfConfig(acc_vrw_mps_rsqrt_s=0.05, gyr_arw_rad_rsqrt_s=0.002,
                                  acc_bias_rw_mps2_rsqrt_s=5e-4, gyr_bias_rw_radps_rsqrt_s=5e-5,
                                  acc_sf_rw_rsqrt_s=1e-4, gyr_sf_rw_rsqrt_s=1e-4)
    att_sd_rad: tuple = (np.deg2rad(2.0), np.deg2rad(2.0), np.deg2rad(5.0))
    vel_sd_mps: float = 0.1
    acc_bias_sd_mps2: float = 0.3
    gyr_bias_sd_radps: float = float(np.deg2rad(0.5))
    acc_sf_sd: float = 0.02
    gyr_sf_sd: float = 0.02
    nhc_sd_mps: float = 0.05
    wvc_forward_sd_mps: float = 0.15
    wvc_lateral_sd_mps: float = 0.3
    zupt_sd_mps: float = 0.05
    level_s: float = 1.0
    stair_forward_sd_mps: float = 0.5


def stair_mask(walk, stairs: str = "baro") -> np.ndarray | None:
    """Epochs (N,) the WVC treats as stairs: ``"baro"`` detected from the phone's barometer
    (:func:`~ilocalg.ins.constraints.detect_stairs_baro`; None for a phone without one), ``"truth"`` the
    simulator's flag (an upper bound, not a detector), ``"none"`` no stair handling (None)."""
    if stairs not in ("baro", "truth", "none"):
        raise ValueError(f"stairs must be 'baro', 'truth' or 'none', got {stairs!r}")
    if stairs == "none":
        return None
    if stairs == "truth":
        return np.asarray(walk.stairs_true, dtype=bool)
    if np.size(getattr(walk, "baro_t_s", ())) < 3:
        return None
    return detect_stairs_baro(walk.t_s, walk.baro_t_s, walk.baro_height_m)


def walk_updates(walk, constraint: str = "wvc", use_gcp: bool = True, settings: PhoneFilterSettings | None = None,
                 wvc_params: dict | None = None, stairs: str = "none", stair_action: str = "drop",
                 step_smoothing: str = "none") -> list[Measurement]:
    """Measurement sets for one walk.

    Parameters
    ----------
    walk : InsWalk-like
    constraint : "nhc" (NHC/ZUPT), "wvc" (WVC/ZUPT) or "none" (ZUPT only)
    use_gcp : add the control-point position fixes
    wvc_params : overrides of eq. (7) (``a``, ``b``, ``c``) and ``height_m`` (default: the defaults)
    stairs, stair_action : stair handling of the WVC (:func:`stair_mask`, :func:`~ilocalg.ins.constraints.wvc_updates`)
    step_smoothing : "none" or "chen" (:func:`~ilocalg.ins.constraints.step_frequency_hz`)
    """
    if constraint not in ("nhc", "wvc", "none"):
        raise ValueError(f"constraint must be 'nhc', 'wvc' or 'none', got {constraint!r}")
    s = settings or PhoneFilterSettings()
    t = walk.t_s
    still = detect_stationary(t, walk.acc_b_mps2, walk.gyr_b_radps)
    ups = [PositionFix(walk.gnss_t_s, walk.gnss_pos_n_m, np.tile(walk.gnss_sd_m, (walk.gnss_t_s.size, 1)),
                       name="GNSS"),
           zupt_updates(t, still, sd_mps=s.zupt_sd_mps)]
    if constraint == "nhc":
        ups.append(nhc_updates(t, ~still, s.nhc_sd_mps, s.nhc_sd_mps))
    elif constraint == "wvc":
        steps = step_epochs(t, walk.acc_b_mps2)
        freq = step_frequency_hz(t, steps, smoothing=step_smoothing)
        p = dict(wvc_params or {})
        h = p.pop("height_m", None)
        ups.append(wvc_updates(t, steps, freq, ~still, height_m=h, params=p, forward_sd_mps=s.wvc_forward_sd_mps,
                               lateral_sd_mps=s.wvc_lateral_sd_mps, vertical_sd_mps=s.wvc_lateral_sd_mps,
                               on_stairs=stair_mask(walk, stairs), stair_action=stair_action,
                               stair_forward_sd_mps=s.stair_forward_sd_mps))
    if use_gcp and walk.gcp_t_s.size:
        ups.append(PositionFix(walk.gcp_t_s, walk.gcp_pos_n_m, np.full((walk.gcp_t_s.size, 3), walk.gcp_sd_m),
                               name="GCP"))
    return ups


def walk_filter_args(walk, constraint: str = "wvc", use_gcp: bool = True,
                     settings: PhoneFilterSettings | None = None, wvc_params: dict | None = None, stairs: str = "none",
                     stair_action: str = "drop", step_smoothing: str = "none") -> dict:
    """What :func:`run_walk` hands the filter: the :func:`~ilocalg.ins.eskf.run_eskf` keyword arguments of one walk
    (IMU log, levelled initial state, initial covariance, measurement sets, process noise)."""
    s = settings or PhoneFilterSettings()
    t = walk.t_s
    first = t < t[0] + s.level_s
    roll, pitch = coarse_level(walk.acc_b_mps2[first])
    yaw = float(walk.init["euler_rad"][2])
    P0 = initial_covariance(pos_sd_m=walk.gnss_sd_m, vel_sd_mps=s.vel_sd_mps, att_sd_rad=s.att_sd_rad,
                            acc_bias_sd_mps2=s.acc_bias_sd_mps2, gyr_bias_sd_radps=s.gyr_bias_sd_radps,
                            acc_sf_sd=s.acc_sf_sd, gyr_sf_sd=s.gyr_sf_sd)
    ups = walk_updates(walk, constraint, use_gcp, s, wvc_params, stairs, stair_action, step_smoothing)
    return {"t_s": t, "gyr_b_radps": walk.gyr_b_radps, "acc_b_mps2": walk.acc_b_mps2, "pos0_n_m": walk.init["pos_n_m"],
            "vel0_n_mps": walk.init["vel_n_mps"], "mat0_nb": euler_to_dcm(roll, pitch, yaw), "P0": P0, "updates": ups,
            "config": s.eskf}


def run_walk(walk, constraint: str = "wvc", use_gcp: bool = True, settings: PhoneFilterSettings | None = None,
             wvc_params: dict | None = None, stairs: str = "none", stair_action: str = "drop",
             step_smoothing: str = "none", keep_covariance: bool = True, prefix=()) -> EskfResult:
    """Level the phone over its first ``level_s`` seconds, initialise and run the 21-state filter.

    ``stairs``, ``stair_action``, ``step_smoothing``: see :func:`walk_updates`; ``keep_covariance`` and ``prefix``
    (earlier runs on the same IMU log whose shared beginning is reused, e.g. this walk without control points):
    see :func:`~ilocalg.ins.eskf.run_eskf`.
    """
    return run_eskf(**walk_filter_args(walk, constraint, use_gcp, settings, wvc_params, stairs, stair_action,
                                       step_smoothing), keep_covariance=keep_covariance, prefix=prefix)


def run_walks(walks, constraint: str = "wvc", use_gcp: bool = True, settings: PhoneFilterSettings | None = None,
              wvc_params: dict | None = None, stairs: str = "none", stair_action: str = "drop",
              step_smoothing: str = "none", keep_covariance: bool = True) -> list[EskfResult]:
    """:func:`run_walk` on several walks with the same settings, the filters advanced together
    (:func:`~ilocalg.ins.eskf.run_eskf_batch`): the same results, bit for bit. ``keep_covariance=False`` keeps no
    covariance at all (the navigation solution only; such a result cannot be smoothed)."""
    return run_eskf_batch([walk_filter_args(w, constraint, use_gcp, settings, wvc_params, stairs, stair_action,
                                            step_smoothing) for w in walks], keep_covariance=keep_covariance)


#: Walks whose filters :func:`run_walks` advances together at most when a caller splits many (each keeps its
#: covariance history, ~40 MB for a 4000-epoch walk): the six seeds of a phone in a full-mode ins_online run.
BATCH_WALKS = 6


def walk_batches(items: list, max_size: int | None = None) -> list[list]:
    """``items`` in order, split into the fewest batches of at most ``max_size`` (default :data:`BATCH_WALKS`), of
    sizes as equal as possible (8 walks: 4 + 4, not 6 + 2, as fewer than 3 filters run one by one)."""
    max_size = BATCH_WALKS if max_size is None else int(max_size)
    if max_size < 1:
        raise ValueError(f"max_size must be >= 1, got {max_size}")
    items = list(items)
    k = -(-len(items) // max_size)
    bounds = [len(items) * i // k for i in range(k + 1)] if k else [0]
    return [items[a:b] for a, b in zip(bounds[:-1], bounds[1:], strict=True)]


#: Namespace of :class:`SmoothingInputs` in a reproduce run's store (:mod:`ilocalg.workflow.runstore`), keyed by
#: ``(route, PhoneProfile, simulation seed, rssi_sd_db, gait keyword items, stairs)`` of a walk simulated with
#: :func:`ilocalg.sim.ins_walk.simulate`'s other defaults and filtered with the default :class:`PhoneFilterSettings`.
SMOOTHING_STORE = "ins_smoothing_inputs_v1"


@dataclass(frozen=True)
class SmoothingInputs:
    """What the online smoother and its scoring (:func:`ilocalg.ins.evaluate.window_sweeps`) need of a walk filtered
    with WVC/ZUPT + control points: ``walk`` (``t_s``, ``t_indoor_s``, ``pos_true_n_m``, ``mat_true_nb``,
    ``gcp_t_s`` of the walk), ``result`` (the :class:`~ilocalg.ins.eskf.EskfResult` without its covariance
    histories) and ``gains`` (:func:`ilocalg.ins.smoother.rts_gains`, (N, 21, 21))."""

    walk: SimpleNamespace
    result: EskfResult
    gains: np.ndarray


def smoothing_inputs(keys, simulate, stairs: str = "none", lookup=None, keep=None):
    """:class:`SmoothingInputs` of the walks ``simulate(key)`` for each of ``keys``, filtered (``"wvc"``, control
    points, ``stairs``) in batches (:func:`walk_batches`, :func:`run_walks`). Yields ``(key, inputs)``, in ``keys``
    order within each batch.

    ``lookup(key)``: inputs computed earlier (e.g. by another process of the same reproduce run), or None; such a
    key is neither simulated nor filtered. ``keep(key, inputs)``: called with every inputs computed here. Either
    way the numbers are those of the walk filtered here.
    """
    from ilocalg.ins.smoother import rts_gains

    todo = []
    for key in keys:
        found = lookup(key) if lookup is not None else None
        if found is not None:
            yield key, found
        else:
            todo.append(key)
    for chunk in walk_batches(todo):
        walks = [simulate(key) for key in chunk]
        results = run_walks(walks, "wvc", use_gcp=True, stairs=stairs)
        for j, (key, walk) in enumerate(zip(chunk, walks, strict=True)):
            res, results[j] = results[j], None
            n = res.t_s.size
            inputs = SmoothingInputs(
                walk=SimpleNamespace(t_s=walk.t_s, t_indoor_s=walk.t_indoor_s, pos_true_n_m=walk.pos_true_n_m,
                                     mat_true_nb=walk.mat_true_nb, gcp_t_s=walk.gcp_t_s),
                result=replace(res, P_plus=None, P_minus=None, Phi=None, cp_idx=np.array([0, n - 1]), cp_P=None,
                               inputs=None),
                gains=rts_gains(res))
            del res
            if keep is not None:
                keep(key, inputs)
            yield key, inputs
