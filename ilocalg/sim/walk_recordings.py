"""Simulated phone walks with Wi-Fi, barometer and ground truth, as :class:`~ilocalg.io.recording.Recording`.

Walks through a building whose floors all have the i-Loc floor's corridors (:mod:`ilocalg.sim.iloc_floor`):
each walk is a handheld phone's IMU log (:func:`ilocalg.sim.gait.simulate_walk`), Wi-Fi scans
along the true path, a barometer log, and ground-truth points (time, position, floor) as a
surveyor would click them. Every walk can be written as an IPIN logfile
(:func:`ilocalg.io.ipin_write.write_ipin_logfile`) or an ILC trace
(:func:`ilocalg.io.ilc_write.write_ilc_trace`); the tests and benchmarks of the track pipeline use
them. Deterministic from the seed.

Model (each value and its source)
---------------------------------
Building
    ``n_floors`` identical floors, storey height 3.5 m (:data:`ilocalg.sim.iloc_floor.STOREY_M`);
    walkable = the corridor graph of the 63 i-Loc training points (2 m apart: the ring corridor and
    the corridor to the stairs, :func:`ilocalg.sim.iloc_floor.training_points`).
Routes
    A random walk on that graph (no immediate U-turn except at dead ends) of ``n_nodes`` nodes,
    walked by a simulated pedestrian (:mod:`ilocalg.sim.gait`, its documented gait and sensor
    model; magnetic disturbances drawn once per building).
Floor change
    Optional: from ``floor_change_at`` (fraction of the walk) the walker climbs to ``floor_to``
    over ``climb_s = 10`` s (a ramp: the simulated gait is level walking, so only the barometer and
    the radio see the climb).
Access points and propagation
    ``n_aps_per_floor = 16`` APs per floor (the i-Loc floor's count), in the offices at least 2.5 m
    from a corridor's centre line; the i-Loc floor simulator's propagation model itself,
    :func:`ilocalg.sim.iloc_floor.mean_rssi_dbm` (COST 231 multi-wall model with its light/heavy
    wall and floor losses, Damosso 1999; shadowing 5 dB with a 5 m exponential correlation,
    Gudmundson 1991, as a random-Fourier-feature field of ``n_features = 256`` features per AP,
    Rahimi & Recht 2007), with the APs' floors taken relative to the walker's.
Scans
    Every ``scan_interval_s = 3`` s (+- 0.5 s uniform jitter; the ILC 2.0 site2/F4 walks scan every
    2-4 s), each AP read at the true position: mean + per-walk drift (``drift_sd_db``, 3 dB) +
    fading (``fade_sd_db``, 3 dB), rounded to whole dBm, reported at or above ``detect_dbm``
    (-95 dBm) and missed with probability ``miss_p`` (0.1): the i-Loc floor's values
    (:data:`ilocalg.sim.iloc_floor.PARAM_SOURCES`). Frequency per AP: a 2.4 GHz channel (1, 6, 11)
    or a 5 GHz one (36-48).
Barometer
    ``pressure_hz = 5`` Hz; ICAO standard atmosphere from ``p0_hpa = 1013.25`` at floor 0
    (``p = p0 (1 - 2.25577e-5 h)^5.25588``, about 0.42 hPa per 3.5 m storey), white noise
    ``pressure_noise_hpa = 0.03`` (smartphone barometers resolve 0.01 hPa with a few 0.01 hPa of
    noise, e.g. Bosch BMP280 datasheet: 0.12 Pa RMS at the highest resolution, phones filter
    less) and a linear weather drift of ``N(0, 0.3)`` hPa/hour.
Ground truth
    A point at every ``truth_every_nodes = 4``-th route node and at every turn, when the walker
    passes it, with its floor; latitude/longitude through a geographic frame centred at ``origin``
    (default 24.7869 N, 120.9975 E: an arbitrary placement, the NCTU campus of the i-Loc thesis).

References
----------
Chiu P.-J., i-Loc thesis, NCTU 2013, sec. 3.1 (floor geometry). Damosso E. (ed.), COST Action 231
final report (1999), sec. 4.7 (multi-wall model). Gudmundson M., Electronics
Letters 27(23), 1991 (shadowing correlation). Rahimi A., Recht B., "Random features for large-scale
kernel machines", NIPS 2007. ICAO, Manual of the ICAO Standard Atmosphere, Doc 7488 (1993).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.io.recording import LAT_DEG, LON_DEG, PRESSURE_HPA, LocalFrame, Recording
from ilocalg.io.schema import BSSID, FLOOR, FREQ_MHZ, RSSI_DBM, SCAN_ID, T_S, X_M, Y_M
from ilocalg.sim import gait, iloc_floor
from ilocalg.units import as_rng

__all__ = ["PARAMS", "SimBuilding", "simulate_building", "random_route", "simulate_recording", "simulate_recordings"]

#: Model parameters (module docstring gives each source).
PARAMS = {
    "n_aps_per_floor": 16,
    "n_features": 256,
    "scan_interval_s": 3.0,
    "scan_jitter_s": 0.5,
    "pressure_hz": 5.0,
    "p0_hpa": 1013.25,
    "pressure_noise_hpa": 0.03,
    "pressure_drift_hpa_per_h": 0.3,
    "climb_s": 10.0,
    "truth_every_nodes": 4,
}
ORIGIN = (24.7869, 120.9975)
_FREQS = np.array([2412.0, 2437.0, 2462.0, 5180.0, 5200.0, 5220.0, 5240.0])


@dataclass(frozen=True)
class SimBuilding:
    """A simulated building: its corridor graph, APs and the fields the walks share."""

    nodes_xy_m: np.ndarray
    adjacency: np.ndarray
    n_floors: int
    ap_xy_m: np.ndarray
    ap_floor: np.ndarray
    ap_freq_mhz: np.ndarray
    bssids: tuple
    rff_w: np.ndarray          # (n_aps, n_features, 2) random frequencies, 1/m
    rff_b: np.ndarray          # (n_aps, n_features) random phases
    disturbances: dict
    frame: LocalFrame
    params: dict

    @property
    def shadow_field(self) -> dict:
        """The shadowing field in the form :func:`ilocalg.sim.iloc_floor.mean_rssi_dbm` takes."""
        return {"omega": self.rff_w, "phase": self.rff_b, "sd_db": float(self.params["shadow_sd_db"])}

    def corridor_rings(self) -> list[np.ndarray]:
        """The walkable corridors as rectangles (metres, this building's frame): the outline rings of a
        floor map (e.g. for :meth:`ilocalg.fusion.particle_filter.OccupancyGrid.from_polygons`)."""
        hw = iloc_floor.CORRIDOR_HALF_WIDTH_M
        n = self.nodes_xy_m
        rings = []
        for i, j in zip(*np.nonzero(np.triu(self.adjacency)), strict=True):
            (x0, y0), (x1, y1) = np.minimum(n[i], n[j]) - hw, np.maximum(n[i], n[j]) + hw
            rings.append(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))
        return rings

    def mean_rssi_dbm(self, xy_m: np.ndarray, floor: np.ndarray) -> np.ndarray:
        """Noise-free RSSI (n, n_aps), dBm, at positions ``xy_m`` on floors ``floor`` (the walker's floor,
        rounded): :func:`ilocalg.sim.iloc_floor.mean_rssi_dbm` with each AP's floor relative to it."""
        xy = np.atleast_2d(np.asarray(xy_m, dtype=np.float64))
        fl = np.round(np.broadcast_to(np.asarray(floor, dtype=np.float64), (xy.shape[0],))).astype(np.int64)
        out = np.empty((xy.shape[0], self.ap_xy_m.shape[0]))
        for f in np.unique(fl):
            m = fl == f
            out[m] = iloc_floor.mean_rssi_dbm(xy[m], self.ap_xy_m, self.ap_floor - f, self.params,
                                              self.shadow_field)
        return out


def simulate_building(seed=0, n_floors: int = 1, origin: tuple = ORIGIN, **overrides) -> SimBuilding:
    """Draw a building: APs on every floor, shadowing fields, magnetic disturbances (module docstring)."""
    p = {**iloc_floor.PARAMS, **PARAMS}
    unknown = set(overrides) - set(p)
    if unknown:
        raise ValueError(f"unknown simulator parameters {sorted(unknown)}; known: {sorted(p)}")
    p.update(overrides)
    if n_floors < 1:
        raise ValueError(f"n_floors must be >= 1, got {n_floors}")
    r = as_rng(seed)
    nodes = iloc_floor.training_points()
    d = np.hypot(*(nodes[:, None, :] - nodes[None, :, :]).transpose(2, 0, 1))
    adj = (d > 0) & (d < 1.5 * iloc_floor.SPACING_M)
    n_ap = int(p["n_aps_per_floor"]) * n_floors
    W, H = iloc_floor.FLOOR_W_M, iloc_floor.FLOOR_H_M
    ap = np.empty((0, 2))
    while len(ap) < n_ap:              # in the offices: at least 2.5 m from a corridor's centre line
        c = r.uniform([2.0, 2.0], [W - 2.0, H - 2.0], size=(4 * n_ap, 2))
        near = np.hypot(*(c[:, None, :] - nodes[None, :, :]).transpose(2, 0, 1)).min(axis=1)
        ap = np.vstack([ap, c[near >= 2.5]])
    ap = ap[:n_ap]
    ap_floor = np.repeat(np.arange(n_floors), int(p["n_aps_per_floor"]))
    freq = _FREQS[r.integers(0, _FREQS.size, n_ap)]
    nf = int(p["n_features"])
    # exponential kernel exp(-r / l) in 2-D: spectral density = bivariate Cauchy (Student t, 1 dof)
    z = r.normal(size=(n_ap, nf, 2))
    chi = r.chisquare(1.0, size=(n_ap, nf, 1))
    w = z / (p["shadow_corr_m"] * np.sqrt(chi))
    b = r.uniform(0.0, 2 * np.pi, size=(n_ap, nf))
    dist = gait.magnetic_disturbances((-5.0, W + 5.0, -5.0, H + 5.0), gait.GaitConfig(), r)
    bssids = tuple(f"02:00:00:00:{i // 256:02x}:{i % 256:02x}" for i in range(n_ap))
    return SimBuilding(nodes, adj, n_floors, ap, ap_floor, freq, bssids, w, b, dist, LocalFrame.at(*origin), p)


def random_route(building: SimBuilding, n_nodes: int, rng=None) -> np.ndarray:
    """Node indices of a random walk on the corridor graph (no U-turn except at a dead end)."""
    r = as_rng(rng)
    if n_nodes < 2:
        raise ValueError(f"n_nodes must be >= 2, got {n_nodes}")
    adj = building.adjacency
    route = [int(r.integers(adj.shape[0]))]
    prev = -1
    while len(route) < n_nodes:
        nb = np.flatnonzero(adj[route[-1]])
        choices = nb[nb != prev] if nb.size > 1 else nb
        nxt = int(r.choice(choices))
        prev = route[-1]
        route.append(nxt)
    return np.asarray(route)


def _pass_times(sw: gait.SimWalk, route_xy: np.ndarray) -> np.ndarray:
    """Time the walker passes each route vertex (arc length along the true path)."""
    tr = sw.truth
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(tr[[X_M, Y_M]].to_numpy(), axis=0).T))])
    s_v = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(route_xy, axis=0).T))])
    s_v = np.minimum(s_v, s[-1])
    t = tr.index.to_numpy()
    # s is non-decreasing (flat while standing): take the first time each arc length is reached
    i = np.clip(np.searchsorted(s, s_v, side="left"), 0, s.size - 1)
    return t[i]


def simulate_recording(building: SimBuilding, rng=None, n_nodes: int = 40, floor: int = 0,
                       floor_to: int | None = None, floor_change_at: float = 0.5, name: str = "sim",
                       world: str = "measured") -> Recording:
    """One simulated walk through ``building`` as a :class:`Recording` (module docstring); ``world`` is the gait
    world (:func:`ilocalg.sim.gait.gait_config`: ``"measured"``, calibrated to the recordings, ``"copied"`` or
    ``"assumed"``)."""
    r = as_rng(rng)
    p = building.params
    if not 0 <= floor < building.n_floors or (floor_to is not None and not 0 <= floor_to < building.n_floors):
        raise ValueError(f"floors must be in [0, {building.n_floors - 1}], got {floor}, {floor_to}")
    idx = random_route(building, n_nodes, r)
    route = building.nodes_xy_m[idx]
    walker = gait.make_walkers(1, r, world=world)[0]
    sw = gait.simulate_walk(route, walker, r, config=gait.gait_config(world), disturbances=building.disturbances)
    t = sw.imu.index.to_numpy()
    t_end = float(t[-1])
    # height above floor 0 over time (a ramp while climbing)
    t_walk0, t_walk1 = float(sw.steps["t_strike_s"].iloc[0]), float(sw.steps["t_strike_s"].iloc[-1])
    if floor_to is None:
        def height(tq):
            return np.full(np.shape(tq), floor * iloc_floor.STOREY_M)
    else:
        tc = t_walk0 + floor_change_at * (t_walk1 - t_walk0)

        def height(tq):
            frac = np.clip((np.asarray(tq) - tc) / p["climb_s"], 0.0, 1.0)
            return iloc_floor.STOREY_M * (floor + (floor_to - floor) * frac)

    def floor_at(tq):
        return np.round(height(tq) / iloc_floor.STOREY_M)
    # Wi-Fi scans
    n_scan = int((t_end - 1.0) // p["scan_interval_s"])
    ts = 1.0 + p["scan_interval_s"] * np.arange(n_scan) + r.uniform(-p["scan_jitter_s"], p["scan_jitter_s"], n_scan)
    ts = np.round(np.clip(ts, t[0], t_end), 3)
    ts = np.unique(ts)
    xs = np.column_stack([np.interp(ts, t, sw.truth[X_M].to_numpy()), np.interp(ts, t, sw.truth[Y_M].to_numpy())])
    n_ap = building.ap_xy_m.shape[0]
    mean = building.mean_rssi_dbm(xs, height(ts) / iloc_floor.STOREY_M)
    rssi = np.round(mean + r.normal(0.0, p["drift_sd_db"], n_ap)[None, :]
                    + r.normal(0.0, p["fade_sd_db"], mean.shape))
    heard = (rssi >= p["detect_dbm"]) & (r.random(mean.shape) >= p["miss_p"])
    si, aj = np.nonzero(heard)
    wifi = pd.DataFrame({T_S: ts[si], SCAN_ID: si.astype(np.int64),
                         BSSID: pd.array([building.bssids[j] for j in aj], dtype="string"),
                         RSSI_DBM: rssi[si, aj], FREQ_MHZ: building.ap_freq_mhz[aj],
                         "ssid": pd.array([f"sim-{j:03d}" for j in aj], dtype="string")})
    wifi[SCAN_ID] = np.unique(si, return_inverse=True)[1].astype(np.int64)
    # barometer
    tp = np.arange(0.0, t_end, 1.0 / p["pressure_hz"])
    drift = r.normal(0.0, p["pressure_drift_hpa_per_h"]) * tp / 3600.0
    pres = (p["p0_hpa"] * (1.0 - 2.25577e-5 * height(tp)) ** 5.25588 + drift
            + r.normal(0.0, p["pressure_noise_hpa"], tp.size))
    pressure = pd.DataFrame({PRESSURE_HPA: pres}, index=pd.Index(tp, name=T_S))
    # ground truth: every k-th node and every turn, when passed
    tv = _pass_times(sw, route)
    d = np.diff(route, axis=0)
    turn = np.zeros(len(route), dtype=bool)
    cross = d[1:, 0] * d[:-1, 1] - d[1:, 1] * d[:-1, 0]
    turn[1:-1] = (np.abs(cross) > 1e-9) | (np.sum(d[1:] * d[:-1], axis=1) < 0)
    pick = turn | (np.arange(len(route)) % int(p["truth_every_nodes"]) == 0)
    pick[[0, -1]] = True
    tt, keep = np.unique(np.round(tv[pick], 3), return_index=True)
    xy = route[pick][keep]
    ll = building.frame.to_latlon(xy[:, 0], xy[:, 1])
    truth = pd.DataFrame({T_S: tt, X_M: xy[:, 0], Y_M: xy[:, 1], FLOOR: floor_at(tt).astype(np.float64),
                          LAT_DEG: ll[:, 0], LON_DEG: ll[:, 1]})
    meta = {"format": "sim", "device": "simulated phone", "skipped": {}, "walker": walker.name,
            "route_nodes": idx, "floor": floor, "floor_to": floor_to}
    return Recording(name=name, imu=sw.imu, wifi=wifi, truth=truth, frame=building.frame, pressure=pressure,
                     step_t_s=sw.steps["t_mid_s"].to_numpy(), meta=meta, source=f"ilocalg.sim.walk_recordings "
                     f"({name})")


def simulate_recordings(n_walks: int, seed=0, n_floors: int = 1, n_nodes: int = 40, floor_changes: bool = False,
                        building: SimBuilding | None = None, world: str = "measured"
                        ) -> tuple[SimBuilding, list[Recording]]:
    """``n_walks`` walks through one building (drawn from ``seed`` unless given).

    Walk ``i`` is on floor ``i % n_floors``; with ``floor_changes`` every other walk climbs to the
    next floor (or down from the top floor) half-way.
    """
    r = as_rng(seed)
    b = building or simulate_building(r, n_floors=n_floors)
    recs = []
    for i in range(n_walks):
        f = i % b.n_floors
        to = None
        if floor_changes and b.n_floors > 1 and i % 2 == 1:
            to = f + 1 if f + 1 < b.n_floors else f - 1
        recs.append(simulate_recording(b, r, n_nodes=n_nodes, floor=f, floor_to=to, name=f"sim{i:03d}",
                                       world=world))
    return b, recs
