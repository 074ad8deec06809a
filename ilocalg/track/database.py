"""The fingerprint database of a floor: every scan of the surveyed walks positioned by their ground truth."""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ilocalg.io.recording import (
    LocalFrame,
    as_recording,
    recording_fingerprints,
    truth_at,
)
from ilocalg.io.scans import scan_matrix
from ilocalg.io.schema import RSSI_DBM, SCAN_ID, T_S


@dataclass(frozen=True)
class WifiDatabase:
    """Fingerprints of walks, one row per scan: ``rssi_dbm`` (n, n_aps), ``xy_m`` (n, 2) in ``frame``,
    ``walk`` (n,), ``floor`` (n,; NaN when unknown), the walks' content ids (``content_ids``, walk ->
    :attr:`ilocalg.io.recording.Recording.content_id`)."""

    rssi_dbm: np.ndarray
    xy_m: np.ndarray
    walk: np.ndarray
    ap_ids: tuple
    floor: np.ndarray | None = None
    frame: LocalFrame | None = None
    content_ids: dict = dataclasses.field(default_factory=dict, compare=False)
    age_s: np.ndarray | None = dataclasses.field(default=None, compare=False)
    #: what the queries' searches derive from the matrices, per setting (:func:`ilocalg.track.fixes.query_side`),
    #: kept with this database; never copied by :func:`dataclasses.replace` (a new database starts empty)
    _memo: dict = dataclasses.field(init=False, default=None, compare=False, repr=False)
    #: ``(database, rows)`` when this one is :meth:`without` of another (its rows ``rows`` of it), else None
    _parent: tuple | None = dataclasses.field(init=False, default=None, compare=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "_memo", {})

    @classmethod
    def from_recordings(cls, recordings, max_age_s: float | None = None,
                        frame: LocalFrame | None = None, align_time: bool = False) -> WifiDatabase:
        """Every scan of ``recordings`` positioned by interpolating its walk's ground truth (outside: left
        out), all in one shared frame (``frame``, default the first walk's:
        :func:`ilocalg.io.recording.common_frame`).

        ``align_time``: position each scan where the walk was when its readings were taken (the scan time
        minus :func:`effective_age_s` of its readings, about 1.1 s on the ILC 2.0 walks) rather than at
        the scan's own time stamp; a scan whose reading time falls before the ground truth keeps its
        scan-time position. Walks without reading times (``last_seen_s``) are unchanged. Off by default (see
        :class:`ilocalg.track.RealWalkConfig` ``align_fix_time``: no measurable gain on site1)."""
        recs = [as_recording(r) for r in (recordings.values() if isinstance(recordings, dict) else recordings)]
        if not recs:
            raise ValueError("no fingerprint walks given")
        names = [r.name for r in recs]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"fingerprint walks must have distinct names; {dup[0]!r} appears twice")
        rf = recording_fingerprints(recs, frame=frame, max_age_s=max_age_s)
        fp = rf.fingerprints
        ages = _age_matrix(recs, rf, fp)
        xy = np.array(fp.xy_m, dtype=np.float64)
        if align_time:
            walk = fp.meta["walk"].to_numpy(dtype=object)
            t_read = fp.meta[T_S].to_numpy(dtype=np.float64) - effective_age_s(ages)
            for r in recs:
                m = walk == r.name
                if m.any() and len(r.truth) >= 2:
                    at, _ = truth_at(r.in_frame(rf.frame).truth, t_read[m], outside="nan")
                    ok = np.isfinite(at[:, 0])
                    xy[np.flatnonzero(m)[ok]] = at[ok]
        return cls(fp.rssi_dbm, xy, fp.meta["walk"].to_numpy(dtype=object), tuple(fp.ap_ids),
                   np.asarray(fp.floor, dtype=np.float64), rf.frame, {r.name: r.content_id for r in recs}, ages)

    @classmethod
    def from_traces(cls, traces, max_age_s: float | None = None) -> WifiDatabase:
        """:meth:`from_recordings` (kept for walks of any loader type, e.g. ILC traces)."""
        return cls.from_recordings(traces, max_age_s)

    @property
    def has_floors(self) -> bool:
        return self.floor is not None and bool(np.isfinite(self.floor).all())

    def without(self, *walks) -> WifiDatabase:
        """The database without the rows of ``walks`` (leave-walks-out)."""
        keep = ~np.isin(self.walk, list(walks))
        if not keep.any():
            raise ValueError(f"no fingerprint left after removing {walks}")
        out = WifiDatabase(self.rssi_dbm[keep], self.xy_m[keep], self.walk[keep], self.ap_ids,
                           None if self.floor is None else self.floor[keep], self.frame,
                           {k: v for k, v in self.content_ids.items() if k not in walks},
                           None if self.age_s is None else self.age_s[keep])
        object.__setattr__(out, "_parent", (self, np.flatnonzero(keep)))
        return out

    def save(self, path) -> Path:
        """Write the database to one uncompressed ``.npz`` file; :meth:`load` reads it back bit-identical.

        The RSSI and age matrices are mostly not heard (NaN): only their heard cells are stored (flat
        indices and float64 values), so the file is small and loading is a scatter, with no per-row work.
        """
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fr = self.frame
        meta = {"ap_ids": list(self.ap_ids), "content_ids": self.content_ids, "version": _FORMAT_VERSION,
                "frame": None if fr is None else [fr.name, fr.origin_lat_deg, fr.origin_lon_deg],
                "has_floor": self.floor is not None}
        rssi = np.asarray(self.rssi_dbm, dtype=np.float64)
        arrays = {"shape": np.array(rssi.shape, dtype=np.int64), **_sparse("rssi", rssi),
                  "xy_m": np.asarray(self.xy_m, dtype=np.float64), "walk": np.asarray(self.walk, dtype=str),
                  "floor": np.full(len(self.xy_m), np.nan) if self.floor is None else self.floor,
                  "meta": np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)}
        if self.age_s is not None:
            arrays.update(_sparse("age", np.asarray(self.age_s, dtype=np.float64)))
        with open(path, "wb") as f:
            np.savez(f, **arrays)
        return path

    @classmethod
    def load(cls, path) -> WifiDatabase:
        """Read a database written by :meth:`save`; a file of another format version raises naming it."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                meta = json.loads(bytes(z["meta"]).decode())
                if meta.get("version") != _FORMAT_VERSION:
                    raise _VersionError(meta.get("version"))
                shape = tuple(int(n) for n in z["shape"])
                rssi = _dense("rssi", z, shape)
                age = _dense("age", z, shape) if "age_at" in z.files else None
                xy, walk, floor = z["xy_m"], z["walk"].astype(object), z["floor"]
        except _VersionError as e:
            raise ValueError(f"{path}: database format version {e.args[0]!r}, expected {_FORMAT_VERSION}; "
                             "delete the file to rebuild it") from None
        except (OSError, ValueError, KeyError) as e:
            raise ValueError(f"{path}: not a fingerprint database file ({type(e).__name__}: {e})") from None
        fr = meta["frame"]
        return cls(rssi, xy, walk, tuple(meta["ap_ids"]), floor if meta["has_floor"] else None,
                   None if fr is None else LocalFrame(*fr), dict(meta["content_ids"]), age)


class _VersionError(Exception):
    """A database file of another format version (turned into a ValueError naming the file)."""


def _sparse(name: str, a: np.ndarray) -> dict:
    """The non-NaN cells of ``a``: ``{name}_at`` (flat indices) and ``{name}_val`` (float64, exact)."""
    at = np.flatnonzero(~np.isnan(a))
    return {f"{name}_at": at.astype(np.int32 if a.size < 2**31 else np.int64), f"{name}_val": a.ravel()[at]}


def _dense(name: str, z, shape: tuple) -> np.ndarray:
    """The matrix :func:`_sparse` stored: NaN except at the stored cells."""
    out = np.full(shape, np.nan)
    out.ravel()[z[f"{name}_at"]] = z[f"{name}_val"]
    return out


#: Version of the ``.npz`` layout written by :meth:`WifiDatabase.save` (3: scans positioned at their
#: readings' time, :func:`effective_age_s`; 4: heard cells only, float64, lossless).
_FORMAT_VERSION = 4

#: Readings at most this old (s) date a scan (:func:`effective_age_s`): the plain reference's staleness limit.
READING_AGE_S = 2.0


def effective_age_s(age_s, max_age_s: float = READING_AGE_S) -> np.ndarray:
    """How long before its time stamp a scan's readings were taken: the mean age (scan time minus
    ``last_seen``) of its readings at most ``max_age_s`` old; the freshest reading's age when none is
    that fresh; 0 when no age is known. ``age_s``: (m, n_aps), NaN where not heard. Returns (m,) seconds.

    On the ILC 2.0 walks a scan's fresh readings are about 1.1 s old (site2 F4: median 1.06 s, 10-90 %
    0.93-1.29 s), which at walking speed is more than a metre of the walk.
    """
    a = np.asarray(age_s, dtype=np.float64)
    fresh = np.isfinite(a) & (a <= max_age_s)
    n = fresh.sum(axis=1)
    mean = np.where(fresh, a, 0.0).sum(axis=1) / np.maximum(n, 1)
    known = np.isfinite(a).any(axis=1)
    freshest = np.where(known, np.min(np.where(np.isfinite(a), a, np.inf), axis=1), 0.0)
    return np.where(n > 0, mean, np.maximum(freshest, 0.0))


def _age_matrix(recs, rf, fp) -> np.ndarray:
    """Age (s, scan time minus the reading's ``last_seen``) of every reading of the database rows; NaN where
    not heard (same rows and columns as ``fp.rssi_dbm``)."""
    out = np.full(fp.rssi_dbm.shape, np.nan)
    meta = fp.meta
    by = {r.name: r for r in recs}
    row = 0
    for name, g in meta.groupby("walk", sort=False):
        w = by[name].wifi
        n = len(g)
        if "last_seen_s" in w.columns:
            aged = w.assign(**{RSSI_DBM: (w[T_S] - w["last_seen_s"]).to_numpy(dtype=np.float64)})
            sids, _, A = scan_matrix(aged, fp.ap_ids)
            pos = np.searchsorted(sids, g[SCAN_ID].to_numpy())
            out[row:row + n] = A[pos]
        else:
            out[row:row + n] = np.where(np.isnan(fp.rssi_dbm[row:row + n]), np.nan, 0.0)
        row += n
    return np.where(np.isnan(fp.rssi_dbm), np.nan, out)


