"""One walk, whatever file it came from: the :class:`Recording` type, its local frame and its loaders.

Every walk loader of :mod:`ilocalg.io` converts to a :class:`Recording` in one call
(:func:`from_ilc_trace`, :func:`from_ipin_log`, :func:`from_oxford`), and :func:`load_recording`
picks the loader from the file's content. The track pipeline (:mod:`ilocalg.track`) is written
against this type only.

Local frames
------------
Ground truth is in metres in a planar frame, :class:`LocalFrame`:

Geographic frames
    Sources that give latitude/longitude (IPIN ``POSI`` records, simulated walks placed on the
    globe) use an azimuthal equidistant projection on the WGS-84 ellipsoid centred at an origin
    (``+proj=aeqd``, computed by PROJ through pyproj): x east, y north, metres. An IPIN logfile's
    frame is centred at its own first ground-truth point, so two logfiles are in two frames;
    :func:`common_frame` and :meth:`Recording.in_frame` put walks into one shared frame through
    their latitude/longitude (kept in the ground truth as ``lat_deg``, ``lon_deg``). Inside a
    building (< 1 km from the origin) the projection's scale error is below 1e-8.
Map frames
    Sources positioned on a floor map (ILC 2.0 waypoints) have no geographic origin; walks can be
    pooled only when their frames have the same ``name`` (e.g. the same site and floor).

Ground truth
------------
``truth``: DataFrame with ``t_s, x_m, y_m, floor`` (``floor`` float: the floor number, NaN when
the source gives none) and, for geographic frames, ``lat_deg, lon_deg``. Positions between the
points are interpolated linearly in time (:func:`truth_at`); the floor is the one of the latest
point at or before the time.

References
----------
Snyder J. P., Map Projections - A Working Manual, USGS Professional Paper 1395 (1987), the
azimuthal equidistant projection; PROJ contributors, PROJ coordinate transformation software
(pyproj interface).
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.scans import scan_matrix
from ilocalg.io.schema import (
    ACC_COLS,
    BSSID,
    FLOOR,
    GYR_COLS,
    MAG_COLS,
    RSSI_DBM,
    SCAN_ID,
    T_S,
    WIFI_COLS,
    X_M,
    Y_M,
    FingerprintSet,
    check_imu,
    check_time_index,
)

__all__ = [
    "PRESSURE_HPA",
    "LAT_DEG",
    "LON_DEG",
    "LocalFrame",
    "Recording",
    "RecordingFingerprints",
    "from_ilc_trace",
    "from_ipin_log",
    "from_oxford",
    "as_recording",
    "load_recording",
    "sniff_format",
    "truth_at",
    "common_frame",
    "require_recording_walk",
    "recording_fingerprints",
    "FORMATS",
]

PRESSURE_HPA = "pressure_hpa"
LAT_DEG = "lat_deg"
LON_DEG = "lon_deg"
TRUTH_COLS = (T_S, X_M, Y_M, FLOOR)
#: Formats :func:`load_recording` reads (``"auto"`` picks one from the content).
FORMATS = ("auto", "ilc", "ipin", "oxford")


@functools.lru_cache(maxsize=64)
def _transformer(lat0: float, lon0: float):
    from pyproj import Transformer

    crs = f"+proj=aeqd +lat_0={lat0!r} +lon_0={lon0!r} +datum=WGS84 +units=m +no_defs"
    return Transformer.from_crs("EPSG:4326", crs, always_xy=True)


@dataclass(frozen=True)
class LocalFrame:
    """A planar frame for positions in metres (see the module docstring).

    Attributes
    ----------
    name : str
        What the frame is (``"aeqd 48.1234567 11.1234567"`` for geographic frames, a floor map's
        name otherwise). Two map frames are the same frame only when their names are equal.
    origin_lat_deg, origin_lon_deg : float or None
        The projection's origin (WGS-84) for a geographic frame; None for a map frame.
    """

    name: str
    origin_lat_deg: float | None = None
    origin_lon_deg: float | None = None

    @classmethod
    def at(cls, lat_deg: float, lon_deg: float) -> LocalFrame:
        """The geographic frame centred at ``(lat_deg, lon_deg)`` (x east, y north, metres)."""
        lat, lon = float(lat_deg), float(lon_deg)
        if not (np.isfinite(lat) and np.isfinite(lon) and abs(lat) <= 90 and abs(lon) <= 180):
            raise ValueError(f"frame origin must be a finite latitude in [-90, 90] and longitude in [-180, 180], "
                             f"got {lat_deg!r}, {lon_deg!r}")
        return cls(f"aeqd {lat:.7f} {lon:.7f}", lat, lon)

    @property
    def geographic(self) -> bool:
        return self.origin_lat_deg is not None

    def _need_geo(self):
        if not self.geographic:
            raise ValueError(f"frame {self.name!r} is a map frame without a geographic origin")

    def to_xy(self, lat_deg, lon_deg) -> np.ndarray:
        """Latitude/longitude (deg, WGS-84) -> (n, 2) metres in this frame."""
        self._need_geo()
        x, y = _transformer(self.origin_lat_deg, self.origin_lon_deg).transform(
            np.asarray(lon_deg, dtype=np.float64), np.asarray(lat_deg, dtype=np.float64))
        return np.column_stack([np.atleast_1d(x), np.atleast_1d(y)])

    def to_latlon(self, x_m, y_m) -> np.ndarray:
        """(x_m, y_m) in this frame -> (n, 2) latitude, longitude (deg, WGS-84)."""
        self._need_geo()
        lon, lat = _transformer(self.origin_lat_deg, self.origin_lon_deg).transform(
            np.asarray(x_m, dtype=np.float64), np.asarray(y_m, dtype=np.float64), direction="INVERSE")
        return np.column_stack([np.atleast_1d(lat), np.atleast_1d(lon)])


def _empty_wifi() -> pd.DataFrame:
    return pd.DataFrame({T_S: np.array([], dtype=np.float64), SCAN_ID: np.array([], dtype=np.int64),
                         BSSID: pd.array([], dtype="string"), RSSI_DBM: np.array([], dtype=np.float64)})


def _empty_truth() -> pd.DataFrame:
    return pd.DataFrame({c: np.array([], dtype=np.float64) for c in TRUTH_COLS})


@dataclass(frozen=True)
class Recording:
    """One walk: what the phone logged and, for learning and scoring only, where it was.

    Attributes
    ----------
    name : str
        The walk's id (file stem, trace id).
    imu : DataFrame
        IMU log indexed by ``t_s`` (one common index; any subset of the accelerometer, gyroscope and
        magnetometer columns of :mod:`ilocalg.io.schema`, phone frame).
    wifi : DataFrame
        Long Wi-Fi scan table (``t_s, scan_id, bssid, rssi_dbm`` and optionally ``freq_mhz``,
        ``ssid``, ``last_seen_s``), same clock as ``imu``.
    truth : DataFrame
        Ground-truth points ``t_s, x_m, y_m, floor`` (+ ``lat_deg, lon_deg`` in a geographic frame),
        strictly increasing in time; may be empty.
    frame : LocalFrame
        The frame of ``truth``'s ``x_m, y_m``.
    pressure : DataFrame or None
        Barometer log indexed by ``t_s`` with ``pressure_hpa`` (hPa), same clock.
    step_t_s : ndarray or None
        Times of the true steps (s), when the source has step truth (Oxford).
    meta : dict
        ``format``, ``device``, ``skipped`` (record type -> lines skipped by the loader, plus
        counts of records changed by a policy), and source-specific entries.
    source : str or None
        The file it came from.
    """

    name: str
    imu: pd.DataFrame
    wifi: pd.DataFrame = field(default_factory=_empty_wifi)
    truth: pd.DataFrame = field(default_factory=_empty_truth)
    frame: LocalFrame = LocalFrame("unpositioned")
    pressure: pd.DataFrame | None = None
    step_t_s: np.ndarray | None = None
    meta: dict = field(default_factory=dict, compare=False)
    source: str | None = None

    def __post_init__(self):
        src = self.source or self.name or "recording"
        if len(self.imu):
            check_imu(self.imu, src)
        missing = [c for c in WIFI_COLS if c not in self.wifi.columns]
        if missing:
            raise ValueError(f"{src}: Wi-Fi scans lack the column(s) {missing}")
        missing = [c for c in TRUTH_COLS if c not in self.truth.columns]
        if missing:
            raise ValueError(f"{src}: ground truth lacks the column(s) {missing}; expected {TRUTH_COLS}")
        if len(self.truth):
            check_time_index(self.truth[T_S].to_numpy(), src, name="ground truth t_s")
            for c in (X_M, Y_M):
                if not np.isfinite(self.truth[c].to_numpy(dtype=np.float64)).all():
                    raise ValueError(f"{src}: ground truth column {c!r} is not finite")
        if self.frame.geographic and len(self.truth) and not {LAT_DEG, LON_DEG} <= set(self.truth.columns):
            raise ValueError(f"{src}: a geographic frame needs lat_deg, lon_deg in the ground truth")
        if self.pressure is not None:
            if self.pressure.index.name != T_S or PRESSURE_HPA not in self.pressure.columns:
                raise ValueError(f"{src}: pressure must be indexed by {T_S!r} with a {PRESSURE_HPA!r} column")
            if len(self.pressure):
                check_time_index(self.pressure.index.to_numpy(), src, name="pressure t_s")

    @property
    def waypoints(self) -> pd.DataFrame:
        """The ground truth (the name the ILC walks use)."""
        return self.truth

    @property
    def has_floors(self) -> bool:
        """True when every ground-truth point has a floor number."""
        return bool(len(self.truth)) and bool(np.isfinite(self.truth[FLOOR].to_numpy(dtype=np.float64)).all())

    @property
    def t_span_s(self) -> tuple[float, float]:
        """First and last IMU time (s): the walk's time span."""
        if not len(self.imu):
            raise ValueError(f"{self.source or self.name}: recording has no IMU samples")
        t = self.imu.index.to_numpy()
        return float(t[0]), float(t[-1])

    @functools.cached_property
    def content_id(self) -> str:
        """SHA-1 of the recorded sensor content (IMU times and values, Wi-Fi times, BSSIDs, RSSI).

        Names and paths are not part of it: the same walk saved under another name has the same id.
        Times are taken relative to the first IMU sample, so re-based clocks still match.
        """
        h = hashlib.sha1()
        t = self.imu.index.to_numpy(dtype=np.float64)
        t0 = t[0] if t.size else 0.0
        h.update(np.round(t - t0, 6).tobytes())
        h.update(np.round(self.imu.to_numpy(dtype=np.float64), 6).tobytes())
        h.update(np.round(self.wifi[T_S].to_numpy(dtype=np.float64) - t0, 6).tobytes())
        h.update(np.round(self.wifi[RSSI_DBM].to_numpy(dtype=np.float64), 3).tobytes())
        # tolist: the same strings, without iterating an Arrow-backed column element by element (5x faster)
        h.update("\n".join(self.wifi[BSSID].astype(str).str.lower().tolist()).encode())
        return h.hexdigest()

    def in_frame(self, frame: LocalFrame) -> Recording:
        """The same walk with its ground truth in ``frame`` (through latitude/longitude).

        Raises when the frames differ and either is a map frame (no way between them).
        """
        if frame == self.frame:
            return self
        if not (frame.geographic and self.frame.geographic):
            raise ValueError(f"{self.source or self.name}: cannot move ground truth from frame {self.frame.name!r} "
                             f"to {frame.name!r}: only geographic frames (latitude/longitude origin) convert")
        tr = self.truth.copy()
        if len(tr):
            xy = frame.to_xy(tr[LAT_DEG].to_numpy(), tr[LON_DEG].to_numpy())
            tr[X_M], tr[Y_M] = xy[:, 0], xy[:, 1]
        return dataclasses.replace(self, truth=tr, frame=frame)


def truth_at(truth: pd.DataFrame, t_s, outside: str = "nan") -> tuple[np.ndarray, np.ndarray]:
    """Ground-truth position and floor at times ``t_s``.

    Parameters
    ----------
    truth : DataFrame
        ``t_s, x_m, y_m, floor`` (at least 2 points, strictly increasing times).
    t_s : array_like, shape (n,)
    outside : {"nan", "error"}
        Times outside the truth's span give NaN (or raise); nothing is extrapolated.

    Returns
    -------
    xy_m : ndarray (n, 2)
        Linear interpolation in time between the surrounding points.
    floor : ndarray (n,)
        The floor of the latest point at or before each time (NaN outside or unknown).
    """
    from ilocalg.io.ilc import interpolate_waypoints  # one interpolation of a walk's ground truth

    xy = interpolate_waypoints(truth, t_s, outside=outside, span_name="ground-truth")
    tw = truth[T_S].to_numpy(dtype=np.float64)
    t = np.asarray(t_s, dtype=np.float64)
    out = np.isnan(xy[:, 0])
    fl = truth[FLOOR].to_numpy(dtype=np.float64)[np.clip(np.searchsorted(tw, t, side="right") - 1, 0, tw.size - 1)]
    fl = np.where(out, np.nan, fl)
    return xy, fl


def common_frame(recordings) -> LocalFrame:
    """The one frame a set of walks can share: the first walk's frame.

    Geographic walks always convert (through latitude/longitude); map-frame walks must all be in the
    same map frame. Mixing the two raises.
    """
    recs = list(recordings)
    if not recs:
        raise ValueError("common_frame: no recordings given")
    f0 = recs[0].frame
    for r in recs[1:]:
        if r.frame == f0 or (r.frame.geographic and f0.geographic):
            continue
        raise ValueError(f"{r.source or r.name}: its frame {r.frame.name!r} differs from {f0.name!r} of "
                         f"{recs[0].source or recs[0].name} and they do not convert (pool walks of one floor map, "
                         "or walks with latitude/longitude)")
    return f0


def require_recording_walk(rec: Recording, min_imu: int = 50, min_truth: int = 2, min_scans: int = 1) -> Recording:
    """Refuse, with a sentence, a recording too small to be scored or used as a fingerprint walk.

    A walk needs IMU samples (steps and headings), at least two ground-truth points (positions
    between them are interpolated in time) and a Wi-Fi scan. Returns ``rec`` unchanged.
    """
    src = rec.source or rec.name or "<recording>"
    n_scans = int(rec.wifi[SCAN_ID].nunique()) if len(rec.wifi) else 0
    if len(rec.imu) < min_imu:
        raise ValueError(f"{src}: the walk has {len(rec.imu)} IMU samples; at least {min_imu} (1 s at 50 Hz) are "
                         "needed to detect steps and headings")
    if len(rec.truth) < min_truth:
        raise ValueError(f"{src}: the walk has {len(rec.truth)} ground-truth point(s) (IPIN: POSI records); at least "
                         f"{min_truth} are needed to place it in time")
    if n_scans < min_scans:
        raise ValueError(f"{src}: the walk has no Wi-Fi scan; fingerprints and Wi-Fi fixes need at least one")
    return rec


# ----------------------------------------------------------------------------------------------
# converters: one call per loader's type
# ----------------------------------------------------------------------------------------------

def from_ilc_trace(trace) -> Recording:
    """An :class:`~ilocalg.io.ilc.IlcTrace` as a Recording (floor-map frame named by site and floor).

    The ILC trace gives the floor only as a name (header ``FloorName``; one floor folder is one
    floor), so ``floor`` is NaN; the name is kept in ``meta["floor_name"]``.
    """
    h = trace.header
    site, fl = h.get("SiteID", ""), h.get("FloorName", h.get("FloorId", ""))
    wp = trace.waypoints
    truth = pd.DataFrame({T_S: wp[T_S].to_numpy(dtype=np.float64), X_M: wp[X_M].to_numpy(dtype=np.float64),
                          Y_M: wp[Y_M].to_numpy(dtype=np.float64), FLOOR: np.full(len(wp), np.nan)})
    meta = {"format": "ilc", "device": " ".join(v for v in (h.get("Brand", ""), h.get("Model", "")) if v),
            "skipped": dict(trace.skipped), "floor_name": fl, "site": site,
            "n_duplicate_bssid_dropped": trace.n_duplicate_bssid_dropped, "header": h}
    return Recording(name=trace.name, imu=trace.imu, wifi=trace.wifi, truth=truth,
                     frame=LocalFrame(f"ILC floor map {site}/{fl}".rstrip("/ ")), meta=meta, source=trace.source)


def _ipin_imu(log) -> tuple[pd.DataFrame, int]:
    """The three per-sensor IPIN logs on the accelerometer's times (gyro and magnetometer interpolated
    linearly), over the span all present sensors cover; returns the log and the samples left out."""
    logs = [d for d in (log.acc, log.gyr, log.mag) if len(d)]
    if not len(log.acc):
        return pd.DataFrame({}, index=pd.Index([], dtype=np.float64, name=T_S)), 0
    lo = max(float(d.index[0]) for d in logs)
    hi = min(float(d.index[-1]) for d in logs)
    t = log.acc.index.to_numpy()
    keep = (t >= lo) & (t <= hi)
    tk = t[keep]
    data = {c: log.acc[c].to_numpy()[keep] for c in ACC_COLS}
    for d, cols in ((log.gyr, GYR_COLS), (log.mag, MAG_COLS)):
        if len(d):
            td = d.index.to_numpy()
            same = td.size == t.size and np.array_equal(td, t)
            for c in cols:
                data[c] = d[c].to_numpy()[keep] if same else np.interp(tk, td, d[c].to_numpy())
    return pd.DataFrame(data, index=pd.Index(tk, name=T_S)), int((~keep).sum())


def from_ipin_log(log, pressure: pd.DataFrame | None = None, name: str | None = None) -> Recording:
    """An :class:`~ilocalg.io.ipin.IpinLog` as a Recording.

    IMU: one log on the accelerometer's AppTimestamps, gyroscope and magnetometer interpolated onto
    them (identical times, as in logfiles written by :func:`ilocalg.io.ipin_write.write_ipin_logfile`,
    are copied); accelerometer samples outside the span of the other sensors are left out and
    counted in ``meta["skipped"]["IMU outside common span"]``. Ground truth: the POSI records, in the
    geographic frame centred at the first one (:class:`LocalFrame`); ``floor`` is POSI's floor_ID.
    ``pressure``: the PRES records (:func:`load_recording` reads them).
    """
    imu, n_out = _ipin_imu(log)
    pos = log.positions
    if len(pos):
        frame = LocalFrame.at(pos["lat_deg"].iloc[0], pos["lon_deg"].iloc[0])
        xy = frame.to_xy(pos["lat_deg"].to_numpy(), pos["lon_deg"].to_numpy())
    else:
        frame, xy = LocalFrame("unpositioned"), np.zeros((0, 2))
    truth = pd.DataFrame({T_S: pos[T_S].to_numpy(dtype=np.float64), X_M: xy[:, 0], Y_M: xy[:, 1],
                          FLOOR: pos["floor"].to_numpy(dtype=np.float64), LAT_DEG: pos["lat_deg"].to_numpy(),
                          LON_DEG: pos["lon_deg"].to_numpy(), "building": pos["building"].to_numpy()})
    skipped = dict(log.skipped)
    if pressure is not None:
        skipped.pop("PRES", None)
    if n_out:
        skipped["IMU outside common span"] = n_out
    src = log.source
    nm = name if name is not None else (Path(src).name.split(".")[0] if src else "")
    wifi = log.wifi.drop(columns=[c for c in ("sensor_t_s",) if c in log.wifi.columns])
    return Recording(name=nm, imu=imu, wifi=wifi, truth=truth, frame=frame if len(pos) else LocalFrame("unpositioned"),
                     pressure=pressure, meta={"format": "ipin", "device": "", "skipped": skipped,
                                              "kept": dict(log.kept)}, source=src)


def from_oxford(rec) -> Recording:
    """An :class:`~ilocalg.io.oxford.OxfordRecording` as a Recording: accelerometer and step truth,
    no positions (``truth`` empty), ``meta`` with the true and hardware step counts and, under
    ``skipped``, the rows the loader's ``duplicate_timestamps="drop"`` policy left out."""
    n_dup = int(getattr(rec, "n_duplicate_timestamps_dropped", 0))
    meta = {"format": "oxford", "device": rec.meta.get("phone", ""),
            "skipped": {"duplicate timestamps": n_dup} if n_dup else {},
            "true_steps": rec.true_steps, "hardware_steps": rec.hardware_steps, **rec.meta}
    return Recording(name=rec.name, imu=rec.imu, step_t_s=np.asarray(rec.step_t_s, dtype=np.float64), meta=meta,
                     source=rec.meta.get("source"))


def as_recording(walk) -> Recording:
    """A Recording from any walk type of :mod:`ilocalg.io` (a Recording is returned unchanged)."""
    if isinstance(walk, Recording):
        return walk
    from ilocalg.io.ilc import IlcTrace
    from ilocalg.io.ipin import IpinLog
    from ilocalg.io.oxford import OxfordRecording

    if isinstance(walk, IlcTrace):
        return from_ilc_trace(walk)
    if isinstance(walk, IpinLog):
        return from_ipin_log(walk)
    if isinstance(walk, OxfordRecording):
        return from_oxford(walk)
    raise ValueError(f"not a walk recording: {type(walk).__name__} (expected Recording, IlcTrace, IpinLog or "
                     "OxfordRecording)")


# ----------------------------------------------------------------------------------------------
# loading by content
# ----------------------------------------------------------------------------------------------

_IPIN_TYPES = ("ACCE;", "GYRO;", "MAGN;", "PRES;", "WIFI;", "POSI;", "AHRS;", "GNSS;", "LIGH;", "PROX;", "SOUN;",
               "BLE4;", "RFID;", "IMUX;", "IMUL;", "TEMP;", "HUMI;")


def sniff_format(path) -> str:
    """``"ilc"``, ``"ipin"`` or ``"oxford"`` from the content of ``path`` (a folder: Oxford).

    ILC: tab-separated ``<ms>\\tTYPE_...`` records or ``#\\t...`` header lines. IPIN: ``;``-separated
    records of a known type (``ACCE;``, ``WIFI;``, ``POSI;`` ...) or ``%`` comments. Oxford: a folder
    with ``accelerometer.csv``, or a headerless CSV of 7 numeric columns.
    """
    p = Path(path)
    if p.is_dir():
        if (p / "accelerometer.csv").is_file():
            return "oxford"
        raise ValueError(f"{p}: a folder is a walk only as an Oxford recording (accelerometer.csv); "
                         "pass the walk's file")
    if not p.is_file():
        raise ValueError(f"{p}: no such file")
    with open(p, "rb") as fh:
        head = fh.read(65536)
    text = head.decode("utf-8", errors="replace").lstrip("\ufeff")
    lines = [ln.strip("\r") for ln in text.splitlines()[:200] if ln.strip()]
    for ln in lines:
        if ln.startswith(_IPIN_TYPES):
            return "ipin"
        parts = ln.split("\t")
        if (len(parts) >= 2 and parts[1].startswith("TYPE_")) or ln.startswith("#\t") or ln.startswith("#startTime"):
            return "ilc"
    body = [ln for ln in lines if not ln.startswith(("%", "#"))]
    if body and all(len(ln.split(",")) == 7 for ln in body[:20]):
        try:
            [float(v) for v in body[0].split(",")]
            return "oxford"
        except ValueError:
            pass
    if lines and all(ln.startswith("%") for ln in lines):
        return "ipin"
    raise ValueError(f"{p}: cannot tell the format from the content (expected ILC 2.0 tab-separated TYPE_ records, "
                     "IPIN ';'-separated ACCE/WIFI/POSI records or an Oxford 7-column CSV); pass format=")


def _ipin_pressure(path: Path) -> pd.DataFrame:
    """PRES records (``PRES;AppTimestamp;SensorTimestamp;Pressure(mbar);Accuracy``) of an IPIN logfile.

    A fast pass over the lines; a file where some PRES line is malformed is read again line by line,
    which names the line.
    """
    data = path.read_bytes()
    rows = [ln.rstrip(b"\r").split(b";") for ln in data.split(b"\n") if ln.startswith(b"PRES;")]
    if all(len(r) == 5 for r in rows):
        try:
            ta = np.array([r[1] for r in rows], dtype=np.float64).reshape(-1)
            va = np.array([r[3] for r in rows], dtype=np.float64).reshape(-1)
        except ValueError:
            ta = None
        if ta is not None:
            return _pressure_frame(ta, va, path)
    t, v = [], []
    with open(path, encoding="utf-8", errors="replace") as fh:
        for lineno, line in enumerate(fh, start=1):
            if not line.startswith("PRES;"):
                continue
            f = line.rstrip("\r\n").split(";")
            try:
                t.append(float(f[1]))
                v.append(float(f[3]))
            except (IndexError, ValueError):
                raise ValueError(f"{path}: line {lineno}: PRES expects AppTimestamp;SensorTimestamp;Pressure;Accuracy "
                                 f"numbers, got {line.strip()[:60]!r}") from None
    return _pressure_frame(np.asarray(t, dtype=np.float64), np.asarray(v, dtype=np.float64), path)


def _pressure_frame(ta: np.ndarray, va: np.ndarray, path) -> pd.DataFrame:
    if ta.size:
        check_time_index(ta, str(path), name="PRES AppTimestamp")
        bad = np.flatnonzero(~((va > 300) & (va < 1100)))
        if bad.size:
            raise ValueError(f"{path}: PRES record {bad[0] + 1}: pressure {va[bad[0]]!r} mbar is outside (300, 1100)")
    return pd.DataFrame({PRESSURE_HPA: va}, index=pd.Index(ta, name=T_S))


def load_recording(path, format: str = "auto", **options) -> Recording:
    """Load one walk of any supported format as a :class:`Recording`.

    Parameters
    ----------
    path : str or Path
        An ILC 2.0 trace file, an IPIN logfile, an Oxford recording folder or validation CSV.
    format : {"auto", "ilc", "ipin", "oxford"}
        ``"auto"`` picks the loader from the file's content (:func:`sniff_format`).
    **options
        Passed to the format's loader (e.g. ``duplicate_bssid="keep_latest"`` for ILC,
        ``time="sensor"`` for IPIN), whose policies they are.

    Returns
    -------
    Recording
    """
    if format not in FORMATS:
        raise ValueError(f"format must be one of {FORMATS}, got {format!r}")
    p = Path(path)
    fmt = sniff_format(p) if format == "auto" else format
    if fmt == "ilc":
        from ilocalg.io.ilc import load_ilc_trace

        return from_ilc_trace(load_ilc_trace(p, **options))
    if fmt == "ipin":
        from ilocalg.io.ipin import load_ipin_logfile

        log = load_ipin_logfile(p, **options)
        pres = _ipin_pressure(p) if log.skipped.get("PRES") else None
        return from_ipin_log(log, pressure=pres, name=p.name.split(".")[0])
    from ilocalg.io.oxford import load_oxford_step_counter

    rec = from_oxford(load_oxford_step_counter(p, **options))
    return dataclasses.replace(rec, source=str(p))


# ----------------------------------------------------------------------------------------------
# fingerprints from walks
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RecordingFingerprints:
    """Wi-Fi fingerprints made from walks (see :func:`recording_fingerprints`).

    Attributes
    ----------
    fingerprints : FingerprintSet
        One sample per used scan, positions in ``frame``; ``floor`` set; ``meta`` has ``walk,
        scan_id, t_s``.
    frame : LocalFrame
    n_outside, n_stale_dropped : int
        Scans left out for lying outside their walk's ground-truth span; AP readings left out for
        being older than ``max_age_s``.
    """

    fingerprints: FingerprintSet
    frame: LocalFrame
    n_outside: int
    n_stale_dropped: int


def recording_fingerprints(recordings, frame: LocalFrame | None = None, max_age_s: float | None = None,
                           outside: str = "drop") -> RecordingFingerprints:
    """Every scan of the walks, positioned by interpolating its walk's ground truth in time.

    Parameters
    ----------
    recordings : iterable of Recording
    frame : LocalFrame, optional
        The shared frame (default :func:`common_frame`); every walk's ground truth is moved into it.
    max_age_s : float or None
        Leave out (and count) AP readings whose ``last_seen_s`` is more than this before the scan.
    outside : {"drop", "error"}
        Scans outside their walk's ground-truth span are left out and counted, or raise.

    Returns
    -------
    RecordingFingerprints
        Samples in walk order then scan order; access points sorted.
    """
    if outside not in ("error", "drop"):
        raise ValueError(f"outside must be 'error' or 'drop', got {outside!r}")
    if max_age_s is not None and not max_age_s >= 0:
        raise ValueError(f"max_age_s must be >= 0 or None, got {max_age_s!r}")
    recs = list(recordings)
    if not recs:
        raise ValueError("recording_fingerprints: no recordings given")
    frame = frame or common_frame(recs)
    rows_used, xy_all, fl_all, meta = [], [], [], {"walk": [], SCAN_ID: [], T_S: []}
    n_out = n_stale = 0
    for r in recs:
        w = r.wifi
        if not len(w):
            continue
        if len(r.truth) < 2:
            raise ValueError(f"{r.source or r.name}: needs at least 2 ground-truth points to position its scans, "
                             f"has {len(r.truth)}")
        r = r.in_frame(frame)
        st = w.groupby(SCAN_ID, sort=True)[T_S].first()
        xy, fl = truth_at(r.truth, st.to_numpy(), outside="nan")
        out = np.isnan(xy[:, 0])
        if outside == "error" and out.any():
            i = int(np.flatnonzero(out)[0])
            raise ValueError(f"{r.source or r.name}: scan {int(st.index[i])} at t_s={float(st.iloc[i])!r} lies outside "
                             "the ground-truth time span (pass outside='drop' to leave such scans out, counted)")
        stale = np.zeros(len(w), dtype=bool)
        if max_age_s is not None:
            if "last_seen_s" not in w.columns:
                raise ValueError(f"{r.source or r.name}: max_age_s needs the Wi-Fi column 'last_seen_s'")
            stale = (w[T_S] - w["last_seen_s"]).to_numpy() > max_age_s
        sid = w[SCAN_ID].to_numpy()
        pos = np.searchsorted(st.index.to_numpy(), sid)
        fresh = ~stale
        n_fresh = np.bincount(pos, weights=fresh, minlength=st.size)
        n_stale_scan = np.bincount(pos, weights=stale, minlength=st.size)
        ok = ~out & (n_fresh > 0)
        n_out += int(out.sum())
        n_stale += int(n_stale_scan[ok].sum())
        used = fresh & ok[pos]
        if not used.any():
            continue
        rows_used.append(w[used])
        xy_all.append(xy[ok])
        fl_all.append(fl[ok])
        meta["walk"] += [r.name] * int(ok.sum())
        meta[SCAN_ID] += st.index.to_numpy()[ok].tolist()
        meta[T_S] += st.to_numpy()[ok].tolist()
    if not rows_used:
        raise ValueError("recording_fingerprints: no usable scan in the given recordings")
    ap_ids = sorted({b for w in rows_used for b in w[BSSID].tolist()})
    rssi = np.concatenate([scan_matrix(w, ap_ids)[2] for w in rows_used])
    xy = np.concatenate(xy_all)
    fps = FingerprintSet(rssi_dbm=rssi, ap_ids=tuple(ap_ids), x_m=xy[:, 0], y_m=xy[:, 1],
                         floor=np.concatenate(fl_all), meta=pd.DataFrame(meta),
                         source=f"walks ({len(recs)} recordings)")
    return RecordingFingerprints(fps, frame, n_out, n_stale)
