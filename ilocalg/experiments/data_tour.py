"""The data tour: what the embedded simulated sets and the real public sets contain.

``run(seed, fast, data_dir)`` returns one summary table per set: ``embedded`` (one row per
simulated set: sample rate, duration, distance, scans), ``iloc_floor_inputs`` (the calibrated
radio inputs), and, for each real set present, its own table. A real set that is absent is listed
in the ``availability`` table with where to download it, never an error
(:func:`ilocalg.io.summaries.dataset_availability`, :func:`~ilocalg.io.summaries.real_dataset_summaries`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.summaries import dataset_availability, real_dataset_summaries, sample_rate_hz

__all__ = ["run", "embedded_summary"]


def _row(name, simulator, what, rate_hz=np.nan, duration_s=np.nan, distance_m=np.nan, n_scans=np.nan,
         aps_per_scan_median=np.nan):
    return {"set": name, "simulator": simulator, "what": what, "rate_hz": float(rate_hz),
            "duration_s": float(duration_s), "distance_m": float(distance_m), "n_scans": float(n_scans),
            "aps_per_scan_median": float(aps_per_scan_median)}


def _path_length_m(xy) -> float:
    xy = np.asarray(xy, dtype=np.float64)
    return float(np.hypot(*np.diff(xy, axis=0).T).sum())


def embedded_summary(seed: int = 0, fast: bool = False) -> dict[str, pd.DataFrame]:
    """Simulate one instance of every embedded set and describe it."""
    from ilocalg.sim import gait, hartmann, iloc_floor, ins_walk, photo_poi, pso_walks

    rows = []
    floor = iloc_floor.simulate(seed=seed, scans_per_point=30 if fast else iloc_floor.SCANS_PER_POINT)
    heard = np.sum(~np.isnan(floor.train.rssi_dbm), axis=1)
    rows.append(_row("iloc_floor", "ilocalg.sim.iloc_floor", "Wi-Fi radio map: training scans at 63 points",
                     n_scans=heard.size, aps_per_scan_median=np.median(heard)))
    walker = gait.make_walkers(1, rng=seed)[0]
    walk = gait.simulate_walk(gait.straight_route(20.0 if fast else 100.0), walker, rng=seed)
    t = walk.imu.index.to_numpy()
    rows.append(_row("gait", "ilocalg.sim.gait", f"handheld phone IMU, one walker ({len(walk.steps)} steps)",
                     rate_hz=sample_rate_hz(t), duration_s=t[-1] - t[0],
                     distance_m=float(walk.steps["length_m"].sum())))
    pw = pso_walks.simulate_pso_walks(seed=seed)
    w = next(iter(pw.values()))[0]
    rows.append(_row("pso_walks", "ilocalg.sim.pso_walks",
                     f"8 Hz accelerometer + compass + 1 Hz GPS, walker {w.walker}",
                     rate_hz=sample_rate_hz(w.imu["t_s"].to_numpy()),
                     duration_s=float(w.imu["t_s"].iloc[-1] - w.imu["t_s"].iloc[0]), distance_m=w.route_m))
    iw = ins_walk.simulate(seed=seed)
    rows.append(_row("ins_walk", "ilocalg.sim.ins_walk", "phone IMU (irregular rate), GNSS, control points",
                     rate_hz=sample_rate_hz(iw.t_s), duration_s=iw.t_s[-1] - iw.t_s[0],
                     distance_m=_path_length_m(iw.pos_true_n_m)))
    hs = hartmann.simulate(duration_s=30.0 if fast else 120.0, seed=seed)
    rows.append(_row("hartmann", "ilocalg.sim.hartmann", "400 Hz IMU + marker video tracker with outages",
                     rate_hz=sample_rate_hz(hs.t_s), duration_s=hs.t_s[-1] - hs.t_s[0],
                     distance_m=_path_length_m(hs.pos_v_m)))
    ph = photo_poi.simulate(seed=seed, n_photos=2 if fast else 20)
    rows.append(_row("photo_poi", "ilocalg.sim.photo_poi",
                     f"{len(ph.pois_m)} points of interest, {len(ph.c_m)} simulated photos"))
    return {"embedded": pd.DataFrame(rows), "iloc_floor_inputs": iloc_floor.summary(floor)}


def run(seed: int = 0, fast: bool = False, data_dir: str | Path | None = None) -> dict[str, pd.DataFrame]:
    """Summaries of every available data set (embedded and real)."""
    tables = {"availability": dataset_availability(data_dir)}
    tables.update(embedded_summary(seed, fast))
    tables.update(real_dataset_summaries(data_dir, fast))
    return tables
