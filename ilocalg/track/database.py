"""The fingerprint database of a floor: every scan of the surveyed walks positioned by their ground truth."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ilocalg.io.recording import (
    LocalFrame,
    as_recording,
    recording_fingerprints,
)


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

    @classmethod
    def from_recordings(cls, recordings, max_age_s: float | None = None,
                        frame: LocalFrame | None = None) -> WifiDatabase:
        """Every scan of ``recordings`` positioned by interpolating its walk's ground truth (outside: left
        out), all in one shared frame (``frame``, default the first walk's:
        :func:`ilocalg.io.recording.common_frame`)."""
        recs = [as_recording(r) for r in (recordings.values() if isinstance(recordings, dict) else recordings)]
        if not recs:
            raise ValueError("no fingerprint walks given")
        names = [r.name for r in recs]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"fingerprint walks must have distinct names; {dup[0]!r} appears twice")
        rf = recording_fingerprints(recs, frame=frame, max_age_s=max_age_s)
        fp = rf.fingerprints
        return cls(fp.rssi_dbm, fp.xy_m, fp.meta["walk"].to_numpy(dtype=object), tuple(fp.ap_ids),
                   np.asarray(fp.floor, dtype=np.float64), rf.frame, {r.name: r.content_id for r in recs})

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
        return WifiDatabase(self.rssi_dbm[keep], self.xy_m[keep], self.walk[keep], self.ap_ids,
                            None if self.floor is None else self.floor[keep], self.frame,
                            {k: v for k, v in self.content_ids.items() if k not in walks})


