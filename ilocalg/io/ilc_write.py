"""Write any :class:`~ilocalg.io.recording.Recording` as an Indoor Location Competition 2.0 trace file.

The tab-separated records :func:`ilocalg.io.load_ilc_trace` reads (see :mod:`ilocalg.io.ilc`): a
``#`` header (site, floor, ``startTime``), then in time order ``TYPE_ACCELEROMETER``,
``TYPE_GYROSCOPE``, ``TYPE_MAGNETIC_FIELD`` (``x y z accuracy``, one common time), ``TYPE_WIFI``
(``ssid bssid rssi freq last_seen_ms``) and ``TYPE_WAYPOINT`` (``x y`` in the recording's frame),
and ``endTime``. ILC times are Unix milliseconds (integers): ``t_ms = round(1000 (t_s + offset_s))``
with ``offset_s = start_unix_s - t_first`` when the recording's clock is not Unix time; two samples
falling on the same millisecond raise. Values are written with Python's shortest round-trip
representation. The ILC format has no floor number per waypoint and no barometer: floor and
pressure are not written (the header's ``FloorName`` is the recording's first floor, if any).

References
----------
Indoor Location Competition 2.0, trace file format (README of
github.com/location-competition/indoor-location-competition-20).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ilocalg.io.recording import Recording
from ilocalg.io.schema import ACC_COLS, BSSID, FLOOR, FREQ_MHZ, GYR_COLS, MAG_COLS, RSSI_DBM, T_S, X_M, Y_M

__all__ = ["write_ilc_trace"]

#: Unix time (s) a recording whose clock starts near 0 is placed at (2020-01-01T00:00:00Z).
DEFAULT_START_UNIX_S = 1577836800.0


def _ms(t_s, offset_s) -> np.ndarray:
    return np.round((np.asarray(t_s, dtype=np.float64) + offset_s) * 1000.0).astype(np.int64)


def write_ilc_trace(recording: Recording, path, start_unix_s: float | None = None, site: str = "sim") -> Path:
    """Write ``recording`` as an ILC 2.0 trace file.

    Parameters
    ----------
    recording : Recording
    path : str or Path
    start_unix_s : float, optional
        Unix time of the recording's first sample. Default: keep the times when they already are
        Unix seconds (> 1e9), else :data:`DEFAULT_START_UNIX_S`.
    site : str
        Header ``SiteID``.

    Returns
    -------
    Path
    """
    rec = recording
    src = rec.source or rec.name or "recording"
    imu = rec.imu
    if not len(imu):
        raise ValueError(f"{src}: an ILC trace needs IMU samples")
    t_first = float(imu.index[0])
    if start_unix_s is None:
        offset = 0.0 if t_first > 1e9 else DEFAULT_START_UNIX_S - t_first
    else:
        offset = float(start_unix_s) - t_first
    blocks: list[tuple[np.ndarray, list[str]]] = []
    t_imu = _ms(imu.index.to_numpy(), offset)
    if np.any(np.diff(t_imu) <= 0):
        raise ValueError(f"{src}: two IMU samples fall on the same millisecond; ILC times are integer ms")
    for rtype, cols in (("TYPE_ACCELEROMETER", ACC_COLS), ("TYPE_GYROSCOPE", GYR_COLS),
                        ("TYPE_MAGNETIC_FIELD", MAG_COLS)):
        if not all(c in imu.columns for c in cols):
            continue
        v = imu[list(cols)].to_numpy(dtype=np.float64)
        blocks.append((t_imu, [f"{t}\t{rtype}\t{a!r}\t{b!r}\t{c!r}\t3" for t, (a, b, c) in
                               zip(t_imu.tolist(), v.tolist(), strict=True)]))
    w = rec.wifi
    if len(w):
        if FREQ_MHZ not in w.columns:
            raise ValueError(f"{src}: ILC TYPE_WIFI records need the frequency; the Wi-Fi scans lack {FREQ_MHZ!r}")
        tw = _ms(w[T_S].to_numpy(), offset)
        last = _ms(w["last_seen_s"].to_numpy(), offset) if "last_seen_s" in w.columns else tw
        ssid = w["ssid"].astype(str).tolist() if "ssid" in w.columns else [""] * len(w)
        blocks.append((tw, [f"{t}\tTYPE_WIFI\t{s}\t{b}\t{float(r)!r}\t{float(f)!r}\t{ls}" for t, s, b, r, f, ls in
                            zip(tw.tolist(), ssid, w[BSSID].astype(str).tolist(), w[RSSI_DBM].tolist(),
                                w[FREQ_MHZ].tolist(), last.tolist(), strict=True)]))
    tr = rec.truth
    if len(tr):
        tt = _ms(tr[T_S].to_numpy(), offset)
        if np.any(np.diff(tt) <= 0):
            raise ValueError(f"{src}: two ground-truth points fall on the same millisecond")
        blocks.append((tt, [f"{t}\tTYPE_WAYPOINT\t{float(x)!r}\t{float(y)!r}" for t, x, y in
                            zip(tt.tolist(), tr[X_M].tolist(), tr[Y_M].tolist(), strict=True)]))
    t_all = np.concatenate([b[0] for b in blocks])
    lines = [ln for b in blocks for ln in b[1]]
    order = np.argsort(t_all, kind="stable")
    fl = tr[FLOOR].to_numpy(dtype=np.float64) if len(tr) else np.array([np.nan])
    floor_name = f"F{int(fl[0])}" if np.isfinite(fl[0]) else ""
    head = [f"#\tSiteID:{site}\tSiteName:{site}\tFloorId:{floor_name}\tFloorName:{floor_name}",
            f"#\tstartTime:{int(t_all.min())}"]
    tail = [f"#\tendTime:{int(t_all.max())}"]
    path = Path(path)
    path.write_text("\n".join(head + [lines[i] for i in order] + tail) + "\n", encoding="utf-8")
    return path
