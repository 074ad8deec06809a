"""The Wi-Fi likelihood surface of a walk's scans and the walk's placement on it (issue 26; a diagnostic, no method).

A point fix (weighted KNN) keeps one position per scan; the scan's match against the database is a whole surface
over the floor. Here each scan's surface is a mixture over its ``k`` nearest database rows in RSSI space (row
weight ``exp(-(d - d_min) / h_dbm)``, ``d`` the Euclidean RSSI distance of :func:`ilocalg.track.fixes.dense_wknn`),
each row a Gaussian of sd ``sigma_m`` at the row's position, floored at ``eps`` per m^2 (:class:`ScanSurfaces`).
A walk's scans, tied together by the shape of its track, then score every candidate placement of that shape (the
summed log-likelihood, :func:`placement_scores`), and :func:`place_walk` keeps the best one (or the tempered
posterior mean). :func:`surface_fixes` is the per-scan alternative: each fix replaced by the surface's mean near
the current track (one EM step of a mixture observation). :func:`placement_evidence` asks the question behind both:
does the surface prefer the walk's true placement to the one the least squares already found?

What it measured (issue 26; development walks only: site1 F1 even, 50 walks, 379 waypoints, leave-one-walk-out
with the nested Wi-Fi selection, Wi-Fi only 5.73 m; ratio to Wi-Fi only, p75 in m; base ``lsq`` 0.610 / 4.52,
``lsq_map`` 0.567, ``lsq_paths`` 0.582). The shape is the ``lsq`` track at the fix times, translations within
+-20 m every 1 m, ``k`` = 50 (of the 200 nearest rows kept):

- ``lsq`` moved by the best translation (MAP), sd 1 m, h 2 / 5 / 10 dB: 0.609 / 0.604 (p75 4.48) / 0.647;
  sd 2 m or 4 m (any h): 0.651-0.662.
- posterior mean (h 5 dB, sd 2 m), temperature 1 / 10: 0.641 / 0.615.
- rotation (+-6 deg) and scale (0.95-1.05) searched too (MAP, h 5 dB), sd 1 / 2 m: 0.640 / 0.665.
- a per-AP kernel radio map instead (Nadaraya-Watson of the rows' RSSI on a 1 m grid, bandwidth 1 / 2 / 4 m; a
  scan's RSSI distance to the map at each point, MAP or posterior mean): 0.65-0.80.
- each fix replaced by its surface's mean near the track (:func:`surface_fixes`, 3 rounds of ``lsq``), h 2-10 dB,
  tau 3-8 m: 0.613-0.645.
- oracle ceiling (truth, never a method): ``lsq`` moved by the walk's own mean error: 0.286 (p75 2.10).

Why it fails (:func:`placement_evidence`): the summed log-likelihood prefers the walk's *true* placement of the
``lsq`` shape (``lsq`` moved by its mean error) to the ``lsq`` placement itself in only 19 / 20 / 21 of the 50 walks
(sd 1 m, h 2 / 5 / 10 dB) and 14 / 8 (h 5 dB, sd 2 / 4 m); among the 23 walks whose ``lsq`` is more than 3 m off, in
9 / 11 / 11 and 6 / 3 (the radio map, bandwidth 1 / 2 / 4 m: 17 / 9 / 15 of 50, 8 / 5 / 6 of 23). The scans
themselves, matched against this database, point where the fixes point: the persistent fix error is in what the
database's rows near the walk look like, not information a point fix throws away. Online (causal) it is no better:
the surfaces of a walk's first 3 / 5 / 10 scans around the ``lsq_online_map`` states prefer the true placement in
20 / 49, 19 / 48, 14 / 36 walks (``kf_gain_map``: 23, 19, 16), and their best placement moves the start-up
-1.14 / -0.68 / +0.15 m closer to the truth on average (``kf_gain_map``: -1.11 / -0.83 / 0.0). Also measured:
per walk (median), 53 % of its scans' five nearest rows come from one database walk, in 22 of 50 walks one of the
two walks recorded nearest in time; the five neighbours taken from distinct walks (at most one / two rows per walk)
raise the fix error from 5.28 m to 9.03 / 6.60 m (``lsq`` 1.20 / 0.78); the RSSI distance over only the access
points the walk hears at all (its device's): fixes 5.54 m, ``lsq`` 0.604; only the rows within 1 / 2 / 3 s of a
waypoint of their walk (whose positions are not interpolated over a turn): fixes 6.54 / 5.68 / 5.44 m, ``lsq``
0.757 / 0.666 / 0.632 (density matters more than the rows' interpolated positions). The weights' scale h spans
the gap between a scan's nearest and fifth-nearest row (7-33 dB, 10-90 %), the spatial sd the rows' spacing along
a walk (1.3-3.4 m, 10-90 %; swept 1-4 m).

CPU (surface and 41 x 41 placement of one walk, :func:`surface_table`'s ``cpu_s``): median 0.23 s, at most 0.48 s
(50 walks, loaded machine).

References
----------
Dempster A. P., Laird N. M., Rubin D. B., J. R. Stat. Soc. B 39(1) (1977), EM (the mixture observation of
:func:`surface_fixes`); Nadaraya E. A. (1964) / Watson G. S. (1964), the kernel regression of a radio map;
Luo et al. (2017), eq. 1 (the RSSI distance of KNN fingerprinting).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.io.recording import as_recording
from ilocalg.io.scans import scan_matrix
from ilocalg.io.schema import T_S
from ilocalg.track._config import DEFAULT_CONFIG, RealWalkConfig
from ilocalg.track.database import WifiDatabase
from ilocalg.track.fixes import db_matrix, dense_wknn

__all__ = ["ScanSurfaces", "scan_surfaces", "walk_queries", "placement_scores", "place_walk", "Placement",
           "surface_fixes", "placement_evidence", "translation_grid"]


@dataclass(frozen=True)
class ScanSurfaces:
    """Each scan's likelihood over the floor: ``xy_m`` (m, k, 2) its nearest database rows' positions, ``log_w``
    (m, k) their normalised log weights, ``sigma_m`` each row's spatial sd, ``eps`` the floor density (per m^2)."""

    xy_m: np.ndarray
    log_w: np.ndarray
    sigma_m: float
    eps: float = 1e-5

    def __post_init__(self):
        if np.ndim(self.xy_m) != 3 or np.shape(self.xy_m)[2] != 2 or np.shape(self.log_w) != np.shape(self.xy_m)[:2]:
            raise ValueError(f"ScanSurfaces: xy_m must be (m, k, 2) and log_w (m, k), got {np.shape(self.xy_m)} "
                             f"and {np.shape(self.log_w)}")
        if not (self.sigma_m > 0 and self.eps > 0):
            raise ValueError(f"ScanSurfaces: sigma_m and eps must be > 0, got {self.sigma_m}, {self.eps}")

    def log_likelihood(self, pts_m) -> np.ndarray:
        """Log density of every scan at points ``pts_m`` (m, T, 2), one set of T points per scan; returns (m, T)."""
        p = np.asarray(pts_m, dtype=np.float64)
        if p.ndim != 3 or p.shape[0] != self.xy_m.shape[0] or p.shape[2] != 2:
            raise ValueError(f"pts_m must be (m, T, 2) with m = {self.xy_m.shape[0]} scans, got {p.shape}")
        s2 = self.sigma_m ** 2
        d2 = ((p[:, :, None, :] - self.xy_m[:, None, :, :]) ** 2).sum(-1)            # m, T, k
        a = self.log_w[:, None, :] - d2 / (2 * s2) - np.log(2 * np.pi * s2)
        mx = a.max(-1)
        return np.logaddexp(mx + np.log(np.exp(a - mx[..., None]).sum(-1)), np.log(self.eps))


def scan_surfaces(db: WifiDatabase, X, cfg: RealWalkConfig = DEFAULT_CONFIG, k: int = 50, h_dbm: float = 5.0,
                  sigma_m: float = 1.0, eps: float = 1e-5) -> ScanSurfaces:
    """:class:`ScanSurfaces` of queries ``X`` (m, n_aps in ``db.ap_ids`` order; NaN not heard) against ``db``
    (readings older than ``cfg.max_age_s`` not heard, :func:`~ilocalg.track.fixes.db_matrix`): the ``k`` nearest
    rows by :func:`~ilocalg.track.fixes.dense_wknn`, weights ``exp(-(d - d_min) / h_dbm)`` normalised."""
    if not (k >= 1 and h_dbm > 0):
        raise ValueError(f"scan_surfaces: k must be >= 1 and h_dbm > 0, got {k}, {h_dbm}")
    idx, dist = dense_wknn(db_matrix(db, cfg), X, k, cfg.not_heard_dbm)
    lw = np.where(np.isfinite(dist), -(dist - dist[:, :1]) / h_dbm, -np.inf)
    lw = lw - np.log(np.exp(lw).sum(1, keepdims=True))
    return ScanSurfaces(db.xy_m[idx], lw, sigma_m, eps)


def walk_queries(trace, db: WifiDatabase, fix_t_s, cfg: RealWalkConfig = DEFAULT_CONFIG) -> np.ndarray:
    """The RSSI rows (m, n_aps) of the scans of ``trace`` at the fix times ``fix_t_s`` (those of
    :func:`ilocalg.track.fixes.wifi_fixes` with ``cfg``: readings older than ``cfg.max_age_s`` left out)."""
    w = as_recording(trace).wifi
    fresh = (None if cfg.max_age_s is None or "last_seen_s" not in w.columns
             else ((w[T_S] - w["last_seen_s"]) <= cfg.max_age_s).to_numpy())
    _, t, X = scan_matrix(w, db.ap_ids, keep=fresh)
    ft = np.asarray(fix_t_s, dtype=np.float64)
    keep = np.isin(t, ft) & ~np.isnan(X).all(axis=1)
    if not np.array_equal(t[keep], ft):
        raise ValueError(f"{as_recording(trace).name}: the fix times are not the times of its scans with {cfg}")
    return X[keep]


def translation_grid(half_m: float = 20.0, step_m: float = 1.0) -> np.ndarray:
    """(T, 2) translations on a square lattice within ``+-half_m`` every ``step_m``."""
    if not (half_m >= 0 and step_m > 0):
        raise ValueError(f"translation_grid: half_m must be >= 0 and step_m > 0, got {half_m}, {step_m}")
    g = np.arange(-half_m, half_m + 1e-9, step_m)
    return np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2)


def placement_scores(surfaces: ScanSurfaces, shape_xy_m, translations_m) -> np.ndarray:
    """Summed log-likelihood (T,) of the scans with the walk at ``shape_xy_m`` (m, 2: the track at the scan times)
    moved by each of ``translations_m`` (T, 2)."""
    s = np.asarray(shape_xy_m, dtype=np.float64)
    tr = np.asarray(translations_m, dtype=np.float64).reshape(-1, 2)
    return surfaces.log_likelihood(s[:, None, :] + tr[None]).sum(axis=0)


@dataclass(frozen=True)
class Placement:
    """The walk's placement: ``t_m`` (2,) the translation kept, ``translations_m`` (T, 2) and ``scores`` (T,)."""

    t_m: np.ndarray
    translations_m: np.ndarray
    scores: np.ndarray


def place_walk(surfaces: ScanSurfaces, shape_xy_m, half_m: float = 20.0, step_m: float = 1.0,
               temperature: float | None = None) -> Placement:
    """The translation of the walk's shape that maximises :func:`placement_scores` (``temperature`` None), or the
    posterior mean under ``exp(scores / temperature)`` (a uniform prior over the lattice)."""
    T = translation_grid(half_m, step_m)
    S = placement_scores(surfaces, shape_xy_m, T)
    if temperature is None:
        t = T[int(np.argmax(S))]
    else:
        if not temperature > 0:
            raise ValueError(f"place_walk: temperature must be > 0, got {temperature}")
        w = np.exp((S - S.max()) / temperature)
        t = (w[:, None] * T).sum(axis=0) / w.sum()
    return Placement(np.asarray(t, dtype=np.float64), T, S)


def surface_fixes(surfaces: ScanSurfaces, track_at_scans_m, tau_m: float) -> np.ndarray:
    """Each scan's position (m, 2) as the mean of its surface's rows weighted by their weight times a Gaussian of
    sd ``tau_m`` around the track's position at the scan (one EM step of a mixture observation; Dempster et al.
    1977). ``tau_m`` -> inf gives the rows' weighted mean; a small one the row nearest the track."""
    if not tau_m > 0:
        raise ValueError(f"surface_fixes: tau_m must be > 0, got {tau_m}")
    p = np.asarray(track_at_scans_m, dtype=np.float64)
    a = surfaces.log_w - ((surfaces.xy_m - p[:, None, :]) ** 2).sum(-1) / (2 * tau_m ** 2)
    w = np.exp(a - a.max(axis=1, keepdims=True))
    return (w[..., None] * surfaces.xy_m).sum(axis=1) / w.sum(axis=1)[:, None]


def placement_evidence(surfaces: ScanSurfaces, shape_xy_m, true_shift_m) -> tuple[float, float]:
    """``(score at no shift, score at true_shift_m)`` (:func:`placement_scores`): whether the scans prefer the
    walk's true placement (``true_shift_m``: the walk's mean error, from its truth; a diagnostic) to the shape's."""
    s = placement_scores(surfaces, shape_xy_m, np.vstack([np.zeros(2), np.asarray(true_shift_m, dtype=np.float64)]))
    return float(s[0]), float(s[1])


def surface_table(traces: dict, model, names, cfg: RealWalkConfig = DEFAULT_CONFIG, settings=((5.0, 1.0),),
                  k: int = 50, half_m: float = 20.0, step_m: float = 1.0, select: bool = True):
    """The development table behind the module docstring: for each walk of ``names`` (leave-one-walk-out against
    ``model``, a :class:`ilocalg.track.floor.FloorModel` of ``traces``, with its nested Wi-Fi selection when
    ``select``), the ``lsq`` track and, per ``(h_dbm, sigma_m)`` of ``settings``, that track moved by
    :func:`place_walk` (MAP), and :func:`placement_evidence` at the walk's own mean error (truth; diagnostic).

    Returns a DataFrame, one row per waypoint and setting: ``walk, h_dbm, sigma_m, wifi_m, lsq_m, surface_m``
    (errors), ``prefers_truth`` (the scans' score higher at the true placement), ``shift_m`` (|mean error of
    lsq|), ``cpu_s`` (the surface and placement of the walk)."""
    import time

    import pandas as pd

    from ilocalg.io.schema import X_M, Y_M
    from ilocalg.track.evaluation import evaluate_walk
    from ilocalg.track.motion import _track_at

    if select:
        model.select_wifi(list(names), cfg)
    rows = []
    for name in names:
        wm = model.for_walk(name, cfg, select=select)
        r = evaluate_walk(traces[name], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, methods=("wifi", "lsq"),
                          step_var_m2=wm.step_var_m2, gain=wm.gain,
                          loo_fixes=model.loo_fixes([name], cfg, select=select)[name])
        ts, lsq, fx = r["state_t_s"], r["tracks"]["lsq"], r["fixes"]
        wp = as_recording(traces[name]).in_frame(wm.db.frame).truth
        tw, true = wp[T_S].to_numpy(), wp[[X_M, Y_M]].to_numpy()
        shape = _track_at(ts, lsq, fx.t_s)
        shift = (true - _track_at(ts, lsq, tw)).mean(axis=0)
        X = walk_queries(traces[name], wm.db, fx.t_s, wm.cfg)
        for h, sd in settings:
            c0 = time.process_time()
            surf = scan_surfaces(wm.db, X, wm.cfg, k=k, h_dbm=h, sigma_m=sd)
            t = place_walk(surf, shape, half_m, step_m).t_m
            cpu = time.process_time() - c0
            s0, s1 = placement_evidence(surf, shape, shift)
            rows.append(pd.DataFrame({"walk": name, "h_dbm": h, "sigma_m": sd, "wifi_m": r["errors"]["wifi"],
                                      "lsq_m": r["errors"]["lsq"],
                                      "surface_m": np.hypot(*(_track_at(ts, lsq + t, tw) - true).T),
                                      "prefers_truth": s1 > s0, "shift_m": float(np.hypot(*shift)), "cpu_s": cpu}))
    return pd.concat(rows, ignore_index=True)
