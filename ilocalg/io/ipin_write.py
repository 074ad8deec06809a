"""Write any :class:`~ilocalg.io.recording.Recording` as an IPIN competition smartphone logfile.

The records written (the ``;``-separated Track 3 format that :func:`ilocalg.io.load_ipin_logfile`
reads, see :mod:`ilocalg.io.ipin`), merged in time order (a stable sort: at equal times the order
below):

=====  ========================================================================================
ACCE   AppTimestamp; SensorTimestamp; acc x; y; z (m/s^2); Accuracy (3)
GYRO   AppTimestamp; SensorTimestamp; gyr x; y; z (rad/s); Accuracy (3)
MAGN   AppTimestamp; SensorTimestamp; mag x; y; z (uT); Accuracy (3)
PRES   AppTimestamp; SensorTimestamp; pressure (hPa = mbar); Accuracy (3)
WIFI   AppTimestamp; SensorTimeStamp; SSID; BSSID; frequency (MHz); RSS (dBm)
POSI   Timestamp; Counter; Latitude; Longitude; floor_ID; Building_ID
=====  ========================================================================================

AppTimestamp is ``t_s - t0_s`` (``t0_s`` defaults to the recording's earliest time, so the file
starts near 0 s as the GetSensorData app's files do); the sensor timestamp repeats it (a recording
keeps one clock). Numbers are written with Python's shortest round-trip representation, so reading
the file back gives the same floats. POSI latitude/longitude come from the ground truth's
``lat_deg, lon_deg`` or, for a map frame, from ``origin``: the map frame placed on the globe (x
east, y north) at that latitude/longitude.

References
----------
IPIN competition Track 3 logfile format (the "LogFiles" description distributed with the
competition data, IPIN 2016-2020 Track 3 technical annex).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ilocalg.io.recording import LAT_DEG, LON_DEG, PRESSURE_HPA, LocalFrame, Recording
from ilocalg.io.schema import ACC_COLS, BSSID, FLOOR, FREQ_MHZ, GYR_COLS, MAG_COLS, RSSI_DBM, T_S, X_M, Y_M

__all__ = ["write_ipin_logfile", "ipin_logfile_text"]


def _num(a) -> list[str]:
    return [repr(float(v)) for v in np.asarray(a, dtype=np.float64)]


def _comment(s: str) -> str:
    """Text safe in a ``%`` comment line: no separator, no control character."""
    return "".join(c if c.isprintable() and c != ";" else " " for c in str(s)).strip()


def _clean(s: str) -> str:
    return str(s).replace(";", ",").replace("\n", " ").replace("\r", " ")


def ipin_logfile_text(recording: Recording, t0_s: float | None = None, origin: tuple | None = None,
                      floor_if_unknown: int | None = None, building: int = 0) -> str:
    """The IPIN logfile text of ``recording`` (see :func:`write_ipin_logfile`)."""
    rec = recording
    src = rec.source or rec.name or "recording"
    imu = rec.imu
    times = [imu.index.to_numpy()] if len(imu) else []
    if len(rec.wifi):
        times.append(rec.wifi[T_S].to_numpy())
    if len(rec.truth):
        times.append(rec.truth[T_S].to_numpy())
    if rec.pressure is not None and len(rec.pressure):
        times.append(rec.pressure.index.to_numpy())
    if not times:
        raise ValueError(f"{src}: nothing to write (no IMU, Wi-Fi, pressure or ground truth)")
    t0 = float(min(t.min() for t in times)) if t0_s is None else float(t0_s)

    blocks: list[tuple[np.ndarray, list[str]]] = []
    t_imu = imu.index.to_numpy(dtype=np.float64) - t0
    ts = _num(t_imu)
    for rtype, cols in (("ACCE", ACC_COLS), ("GYRO", GYR_COLS), ("MAGN", MAG_COLS)):
        if not len(imu) or not any(c in imu.columns for c in cols):
            continue
        missing = [c for c in cols if c not in imu.columns]
        if missing:
            raise ValueError(f"{src}: IMU log has only part of the {rtype} axes (lacks {missing})")
        x, y, z = (_num(imu[c]) for c in cols)
        blocks.append((t_imu, [f"{rtype};{a};{a};{b};{c};{d};3" for a, b, c, d in zip(ts, x, y, z, strict=True)]))
    if rec.pressure is not None and len(rec.pressure):
        tp = rec.pressure.index.to_numpy(dtype=np.float64) - t0
        blocks.append((tp, [f"PRES;{a};{a};{b};3" for a, b in zip(_num(tp), _num(rec.pressure[PRESSURE_HPA]),
                                                                   strict=True)]))
    w = rec.wifi
    if len(w):
        if FREQ_MHZ not in w.columns:
            raise ValueError(f"{src}: IPIN WIFI records need the frequency; the Wi-Fi scans lack {FREQ_MHZ!r}")
        tw = w[T_S].to_numpy(dtype=np.float64) - t0
        ssid = w["ssid"].astype(str).tolist() if "ssid" in w.columns else [""] * len(w)
        blocks.append((tw, [f"WIFI;{a};{a};{_clean(s)};{_clean(b)};{f};{r}" for a, s, b, f, r in
                            zip(_num(tw), ssid, w[BSSID].astype(str).tolist(), _num(w[FREQ_MHZ]), _num(w[RSSI_DBM]),
                                strict=True)]))
    tr = rec.truth
    if len(tr):
        if LAT_DEG in tr.columns and LON_DEG in tr.columns:
            ll = tr[[LAT_DEG, LON_DEG]].to_numpy(dtype=np.float64)
        elif origin is not None:
            ll = LocalFrame.at(*origin).to_latlon(tr[X_M].to_numpy(), tr[Y_M].to_numpy())
        else:
            raise ValueError(f"{src}: ground truth in the map frame {rec.frame.name!r} has no latitude/longitude; "
                             "pass origin=(lat_deg, lon_deg) to place the map frame (x east, y north) on the globe")
        fl = tr[FLOOR].to_numpy(dtype=np.float64)
        if np.isnan(fl).any():
            if floor_if_unknown is None:
                raise ValueError(f"{src}: ground truth has no floor number (IPIN POSI needs floor_ID); pass "
                                 "floor_if_unknown=<int>")
            fl = np.where(np.isnan(fl), floor_if_unknown, fl)
        bl = tr["building"].to_numpy() if "building" in tr.columns else np.full(len(tr), building)
        tt = tr[T_S].to_numpy(dtype=np.float64) - t0
        blocks.append((tt, [f"POSI;{a};{i + 1};{la!r};{lo!r};{int(f)};{int(b)}" for i, (a, la, lo, f, b) in
                            enumerate(zip(_num(tt), ll[:, 0].tolist(), ll[:, 1].tolist(), fl, bl, strict=True))]))
    t_all = np.concatenate([b[0] for b in blocks])
    lines = [ln for b in blocks for ln in b[1]]
    order = np.argsort(t_all, kind="stable")
    head = [f"% IPIN logfile written by ilocalg.io.ipin_write from {_comment(rec.name or 'a recording')}",
            f"% source: {_comment(rec.source or '')}, AppTimestamp = t_s - {t0!r}",
            "% ACCE/GYRO/MAGN: AppTimestamp;SensorTimestamp;X;Y;Z;Accuracy  PRES: AppTimestamp;SensorTimestamp;"
            "Pressure(mbar);Accuracy",
            "% WIFI: AppTimestamp;SensorTimeStamp;Name_SSID;MAC_BSSID;Frequency;RSS  "
            "POSI: Timestamp;Counter;Latitude;Longitude;floor_ID;Building_ID"]
    return "\n".join(head + [lines[i] for i in order]) + "\n"


def write_ipin_logfile(recording: Recording, path, t0_s: float | None = None, origin: tuple | None = None,
                       floor_if_unknown: int | None = None, building: int = 0) -> Path:
    """Write ``recording`` as an IPIN competition smartphone logfile.

    Parameters
    ----------
    recording : Recording
        Any walk (a loaded file or a simulated walk; see :func:`ilocalg.io.recording.as_recording`).
    path : str or Path
        The file to write (UTF-8 text).
    t0_s : float, optional
        Time written as AppTimestamp 0 (default: the recording's earliest time).
    origin : (lat_deg, lon_deg), optional
        Places a map-frame recording on the globe for the POSI records (not needed when the ground
        truth has latitude/longitude).
    floor_if_unknown : int, optional
        POSI floor_ID where the ground truth has no floor (by default such a recording raises).
    building : int
        POSI Building_ID when the ground truth has no ``building`` column.

    Returns
    -------
    Path
    """
    path = Path(path)
    path.write_text(ipin_logfile_text(recording, t0_s, origin, floor_if_unknown, building), encoding="utf-8")
    return path
