"""The i-Loc floor world as a scenario: the survey, the walks with their sensor streams and scans, the truth.

A world is built once (:func:`build`, from the floor simulator's parameters plus the caller's
declared overrides) and handed to an experiment as an :class:`IlocScenario`, shaped like a set of
recordings: the survey (fingerprints), a standing calibration session on another day, fixed-length
training walks, and test walks whose phone logged an IMU stream and periodic Wi-Fi scans. The
experiment applies methods to it; it never draws from the simulator itself.

Scans while walking
    The phone scans periodically while its user walks (i-Loc thesis, Chiu 2013, L777: "the phone
    periodically detects the Wi-Fi signals"). A scan's result, and the fix made from it, is available
    only when the scan is stamped (``t_ready_s``): fixes are causal. Two lag models:

    ``lag_model="measured"`` (default)
        Results are stamped every ``scan_interval_s`` (default: the measured median interval of the
        ILC 2.0 site1 walks, ``data/measured_parameters.csv: wifi_scan_interval_s``), the first one
        interval after the log starts. Each AP's reading is older than the stamp by an age drawn from
        a log-normal distribution with the measured median (``wifi_reading_age_median_s``) and
        interquartile range (``wifi_reading_age_iqr_s``) of distinct readings' ages (t_scan -
        last_seen) on the same walks; the AP is read at the walker's position then. ``t_start_s`` is
        the scan's earliest reading.
    ``lag_model="uniform"`` (the earlier model, a labelled alternative)
        A scan starts every ``scan_interval_s`` from the start of the log, each AP is read at a
        uniform time within the scan's ``scan_latency_s``, and the result is ready at its end.

    The first scan gives the walk's initial position (i-Loc L792-795; Luo et al. 2017, L212). Each
    walk is its own session: a new per-AP drift (another day than the survey).

Everything is deterministic from ``seed``: the floor, the walks and each walk's scans come from
independent streams (``np.random.Generator.spawn``), so rescanning a world (:func:`rescan`) or
changing the survey size keeps the same walkers and walks.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU. L777, L792-795.
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications. L212, L222.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ilocalg.io.recording import LocalFrame, Recording
from ilocalg.io.schema import BSSID, FLOOR, RSSI_DBM, SCAN_ID, T_S, X_M, Y_M
from ilocalg.io.schema import FREQ_MHZ as _FREQ
from ilocalg.sim import gait, iloc_floor, measured
from ilocalg.units import as_rng

__all__ = ["ScenarioWalk", "IlocScenario", "build", "rescan", "walk_fixes", "reading_ages_s", "scan_model_text",
           "scan_model_source", "to_recording", "ap_bssids", "resolve_scan_interval_s", "SCAN_LATENCY_S", "LAG_MODELS",
           "FREQ_MHZ"]

#: Scan duration of the "uniform" lag model, s (phones take 1-3 s per scan; an assumption).
SCAN_LATENCY_S = 2.0
LAG_MODELS = ("measured", "uniform")
#: Channel frequency written for every simulated AP, MHz (the floor simulator has no channel model).
FREQ_MHZ = 2437.0
_Z75 = 0.6744897501960817  # standard normal 75 % quantile


def resolve_scan_interval_s(value: float | None = None) -> float:
    """The scan interval (s): ``value`` when given, else the measured median of the ILC 2.0 site1 walks
    (``data/measured_parameters.csv: wifi_scan_interval_s``, read when called, not on import)."""
    iv = measured.param("wifi_scan_interval_s") if value is None else float(value)
    if not iv > 0:
        raise ValueError(f"scan_interval_s must be > 0 s, got {iv}")
    return iv


def reading_ages_s(rng, shape, median_s: float | None = None, iqr_s: float | None = None) -> np.ndarray:
    """Ages (s) of RSSI readings at their scan's stamp: log-normal with the given median and interquartile range.

    Defaults: the measured ``wifi_reading_age_median_s`` and ``wifi_reading_age_iqr_s`` (ILC 2.0 site1). For a
    log-normal, ``IQR = 2 median sinh(z75 sigma)``, so ``sigma = asinh(IQR / (2 median)) / z75``.
    """
    med = measured.param("wifi_reading_age_median_s") if median_s is None else float(median_s)
    iqr = measured.param("wifi_reading_age_iqr_s") if iqr_s is None else float(iqr_s)
    if not (med > 0 and iqr >= 0):
        raise ValueError(f"need median_s > 0 and iqr_s >= 0, got {med}, {iqr}")
    sigma = np.arcsinh(iqr / (2.0 * med)) / _Z75
    return med * np.exp(sigma * as_rng(rng).standard_normal(shape))


@dataclass(frozen=True)
class ScenarioWalk:
    """One test walk as a phone would record it, with its truth.

    Attributes
    ----------
    name : str
    imu : DataFrame, the phone's IMU log indexed by ``t_s`` (accelerometer, gyroscope, magnetometer)
    scans : DataFrame, one row per scan: ``t_start_s``, ``t_ready_s`` (the scan's end: when its result is
        available), ``t_ref_s`` (mean read time of the APs heard), ``x_m``, ``y_m`` (true position at the
        start) and one column per AP id (dBm, NaN = not heard)
    steps : DataFrame, the true steps (:func:`ilocalg.sim.gait.simulate_walk`)
    truth : DataFrame, per-sample truth ``x_m, y_m, theta_rad`` indexed by ``t_s``
    pass_t_s : (n_route,) the times the walker passes each route point
    stand_s : float, time at rest at the start of the log
    walker : Walker (truth: the gait the walk was drawn with)
    read_t_s : (n_scans, n_aps) when each AP of each scan was read (its ``last_seen``), s
    """

    name: str
    imu: pd.DataFrame
    scans: pd.DataFrame
    steps: pd.DataFrame
    truth: pd.DataFrame
    pass_t_s: np.ndarray
    stand_s: float
    walker: gait.Walker = field(repr=False)
    read_t_s: np.ndarray = field(repr=False, default=None)

    @property
    def truth_t_s(self) -> np.ndarray:
        return self.truth.index.to_numpy()

    @property
    def truth_xy_m(self) -> np.ndarray:
        return self.truth[["x_m", "y_m"]].to_numpy()


@dataclass(frozen=True)
class IlocScenario:
    """A built world: everything an experiment reads.

    Attributes
    ----------
    floor : IlocFloor, with the survey (``floor.train``) and the standing calibration session at the route
        points on another day (``floor.test``)
    route_xy_m : (28, 2) the test route in walking order
    train_walks : tuple of (Walker, imposed step length m, SimWalk), fixed-length training walks
    walks : tuple of ScenarioWalk, the test walks
    params : dict, the world's scan parameters and overrides
    """

    floor: iloc_floor.IlocFloor
    route_xy_m: np.ndarray
    train_walks: tuple
    walks: tuple
    params: dict


def scan_model_text(lag_model: str, scan_latency_s: float = SCAN_LATENCY_S) -> str:
    """What the lag model does, in one clause (for readings tables)."""
    if lag_model == "measured":
        return ("each AP's reading is older than the scan's stamp by a log-normal age with the measured median and "
                "IQR (read at the walker's position then)")
    return f"each AP read at a uniform time within the {scan_latency_s:g} s scan, ready at its end"


def scan_model_source(interval_s: float | None = None) -> str:
    """Where the scan interval (None = measured) and reading ages come from (for readings tables)."""
    iv = (measured.cite("wifi_scan_interval_s") if interval_s is None
          else f"scan interval {interval_s:g} s (given)")
    med = measured.param("wifi_reading_age_median_s")
    sigma = np.arcsinh(measured.param("wifi_reading_age_iqr_s") / (2.0 * med)) / _Z75
    p90 = med * np.exp(1.2815515655446004 * sigma)
    return (f"{iv}; {measured.cite('wifi_reading_age_median_s')}; {measured.cite('wifi_reading_age_iqr_s')} "
            f"(the log-normal's p90 {p90:.2f} s vs the measured {measured.param('wifi_reading_age_p90_s'):.2f} s: "
            "real ages have a longer tail)")


def _scans(floor, truth, interval, latency, rng, lag_model="measured") -> pd.DataFrame:
    t = truth.index.to_numpy()
    xy = truth[["x_m", "y_m"]].to_numpy()
    drift = iloc_floor.session_drift_db(floor, rng)  # this walk's session
    if lag_model == "uniform":
        starts = iloc_floor.periodic_scan_starts_s(t[0], t[-1], interval, latency)
        return iloc_floor.walking_scans(floor, t, xy, starts, latency, rng, drift, return_read_times=True)
    if lag_model != "measured":
        raise ValueError(f"lag_model must be one of {LAG_MODELS}, got {lag_model!r}")
    stamps = iloc_floor.periodic_scan_starts_s(t[0], t[-1], interval, 0.0)[1:]  # the first result one interval in
    age = reading_ages_s(rng, (stamps.size, floor.ap_xy_m.shape[0]))
    s, t_read = iloc_floor.walking_scans(floor, t, xy, stamps, 0.0, rng, drift, read_age_s=age,
                                         return_read_times=True)
    s["t_start_s"] = t_read.min(axis=1)  # the scan's earliest reading
    return s, t_read


def build(seed=0, n_walkers: int = 8, n_train: int = 8, n_cal: int = 20, scans_per_point: int | None = None,
          scan_interval_s: float | None = None, scan_latency_s: float = SCAN_LATENCY_S,
          train_on_test_walkers: bool = False, lag_model: str = "measured", **floor_overrides) -> IlocScenario:
    """Build the i-Loc floor world once and return it as a scenario.

    Parameters
    ----------
    seed : int or Generator
    n_walkers, n_train : test walks, and walkers of the fixed-length training walks
    n_cal : standing scans per route point in the calibration session (another day)
    scans_per_point : survey scans per training point (default the floor's 300)
    scan_interval_s, scan_latency_s, lag_model : periodic scans while walking (module docstring;
        interval None = the measured one; ``scan_latency_s`` is used by the ``"uniform"`` model only)
    train_on_test_walkers : train on the first ``n_train`` test walkers (Luo et al.: the tester's own
        walks) instead of new walkers (i-Loc: SAM and SLM are trained on other walkers)
    floor_overrides : radio parameters passed to :func:`ilocalg.sim.iloc_floor.simulate`
    """
    if n_walkers < 1 or n_train < 1 or n_cal < 2:
        raise ValueError(f"need n_walkers >= 1, n_train >= 1, n_cal >= 2; got {n_walkers}, {n_train}, {n_cal}")
    given_interval = scan_interval_s
    scan_interval_s = resolve_scan_interval_s(scan_interval_s)
    floor_rng, walk_rng, scan_root = as_rng(seed).spawn(3)
    spp = iloc_floor.SCANS_PER_POINT if scans_per_point is None else int(scans_per_point)
    floor = iloc_floor.simulate(floor_rng, scans_per_point=spp, scans_per_test_point=n_cal, **floor_overrides)
    if train_on_test_walkers:
        everyone = gait.make_walkers(max(n_train, n_walkers), walk_rng)
        train_w, test_w = everyone[:n_train], everyone[:n_walkers]
    else:
        train_w = gait.make_walkers(n_train, walk_rng)
        test_w = gait.make_walkers(n_walkers, walk_rng)  # new walkers: not those the PDR is trained on
    train = tuple(gait.training_walks(train_w, walk_rng))
    route = iloc_floor.route_xy_m()
    scan_rngs = scan_root.spawn(n_walkers)
    walks = []
    for i, w in enumerate(test_w):
        sw = gait.simulate_walk(route, w, walk_rng)
        scans, t_read = _scans(floor, sw.truth, scan_interval_s, scan_latency_s, scan_rngs[i], lag_model)
        walks.append(ScenarioWalk(name=w.name, imu=sw.imu, scans=scans, read_t_s=t_read,
                                  steps=sw.steps, truth=sw.truth, pass_t_s=gait.pass_times_s(sw, route),
                                  stand_s=sw.config.stand_s, walker=w))
    params = {"seed": seed if not isinstance(seed, np.random.Generator) else "rng", "scans_per_point": spp,
              "scan_interval_s": float(scan_interval_s), "scan_latency_s": float(scan_latency_s),
              "lag_model": lag_model, "scan_interval_given": given_interval is not None,
              "n_cal": n_cal, "train_on_test_walkers": bool(train_on_test_walkers), **floor_overrides}
    return IlocScenario(floor=floor, route_xy_m=route, train_walks=train, walks=tuple(walks), params=params)


def rescan(scn: IlocScenario, seed, scan_interval_s: float | None = None,
           scan_latency_s: float | None = None, lag_model: str | None = None) -> IlocScenario:
    """The same world, walks and sessions' walkers, with new periodic scans (another interval or latency).

    ``seed`` must be the seed :func:`build` was given: the scans come from the same stream, so only what
    changes (interval, latency) differs.
    """
    iv = scn.params["scan_interval_s"] if scan_interval_s is None else float(scan_interval_s)
    lat = scn.params["scan_latency_s"] if scan_latency_s is None else float(scan_latency_s)
    lm = scn.params["lag_model"] if lag_model is None else lag_model
    scan_rngs = as_rng(seed).spawn(3)[2].spawn(len(scn.walks))
    walks = tuple(dataclasses.replace(w, **dict(zip(("scans", "read_t_s"),
                                                    _scans(scn.floor, w.truth, iv, lat, scan_rngs[i], lm),
                                                    strict=True)))
                  for i, w in enumerate(scn.walks))
    return dataclasses.replace(scn, walks=walks, params={**scn.params, "scan_interval_s": iv, "scan_latency_s": lat,
                                                         "lag_model": lm})


def walk_fixes(scn: IlocScenario, walk: ScenarioWalk, estimator) -> pd.DataFrame:
    """The fixes a fitted ``estimator`` makes from a walk's scans, in the order they become available.

    Returns
    -------
    DataFrame
        ``t_start_s``, ``t_ready_s`` (available), ``t_ref_s`` (the time the fix describes), ``x_m``,
        ``y_m`` (true position at the start), ``fix_x_m``, ``fix_y_m`` (NaN when the scan heard no AP),
        ``n_heard``.
    """
    ids = list(scn.floor.train.ap_ids)
    X = walk.scans[ids].to_numpy()
    heard = ~np.isnan(X).all(axis=1)
    fix = np.full((X.shape[0], 2), np.nan)
    if heard.any():
        fix[heard] = estimator.predict(X[heard])
    out = walk.scans[["t_start_s", "t_ready_s", "t_ref_s", "x_m", "y_m"]].copy()
    out["fix_x_m"], out["fix_y_m"] = fix[:, 0], fix[:, 1]
    out["n_heard"] = (~np.isnan(X)).sum(axis=1)
    return out.reset_index(drop=True)


def ap_bssids(scn: IlocScenario) -> tuple:
    """A locally administered MAC address per simulated AP, in ``scn.floor.train.ap_ids`` order."""
    return tuple(f"02:00:00:00:{i // 256:02x}:{i % 256:02x}" for i in range(len(scn.floor.train.ap_ids)))


def to_recording(scn: IlocScenario, walk: ScenarioWalk) -> Recording:
    """One test walk as a :class:`~ilocalg.io.recording.Recording`: what a phone logged, plus its truth.

    The IMU log as simulated; each heard AP of each scan as a Wi-Fi row stamped at the scan's result
    (``t_ready_s``) with ``last_seen_s`` = when it was read; the ground truth = the route points at the
    times they are passed (as a surveyor marks them), floor 0, in the floor's map frame; the true steps'
    mid-times as ``step_t_s``. Save it with :func:`ilocalg.io.ilc_write.write_ilc_trace` and read it back
    with :func:`ilocalg.io.recording.load_recording`, like a real walk.
    """
    ids = list(scn.floor.train.ap_ids)
    X = walk.scans[ids].to_numpy()
    si, aj = np.nonzero(~np.isnan(X))
    bss = ap_bssids(scn)
    read = walk.read_t_s if walk.read_t_s is not None else np.repeat(walk.scans["t_ref_s"].to_numpy()[:, None],
                                                                       len(ids), axis=1)
    wifi = pd.DataFrame({T_S: walk.scans["t_ready_s"].to_numpy()[si], SCAN_ID: si.astype(np.int64),
                         BSSID: pd.array([bss[j] for j in aj], dtype="string"), RSSI_DBM: X[si, aj],
                         _FREQ: np.full(si.size, FREQ_MHZ), "last_seen_s": read[si, aj],
                         "ssid": pd.array([ids[j] for j in aj], dtype="string")})
    truth = pd.DataFrame({T_S: walk.pass_t_s, X_M: scn.route_xy_m[:, 0], Y_M: scn.route_xy_m[:, 1],
                          FLOOR: np.zeros(walk.pass_t_s.size)})
    return Recording(name=walk.name, imu=walk.imu, wifi=wifi, truth=truth, frame=LocalFrame("i-Loc floor (simulated)"),
                     step_t_s=walk.steps["t_mid_s"].to_numpy(),
                     meta={"format": "sim", "device": "simulated phone", "skipped": {}, "walker": walk.walker.name,
                           "scenario": dict(scn.params)},
                     source=f"ilocalg.sim.iloc_scenario ({walk.name})")
