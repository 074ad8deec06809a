"""Everything a floor's surveyed walks teach, built once, saved, reloaded (one cache file set per floor).

A :class:`FloorModel` holds the fingerprint database (:class:`~ilocalg.track.database.WifiDatabase`,
reading ages kept so the Wi-Fi configuration can choose a staleness limit per query), the per-walk
calibration rows (:func:`ilocalg.track.motion.calibrate`) and the per-waypoint-interval PDR
displacement sums (:func:`ilocalg.track.motion.step_intervals`). :meth:`FloorModel.for_walk` gives,
for a scored walk, what the *other* walks teach: the database without it, the step-length factor and
floor heading offset, the step displacement variance, the Wi-Fi configuration and fix variance
(nested leave-one-walk-out, :func:`ilocalg.track.fixes.select_wifi_nested`): exactly what a rebuild
without the walk would give, in well under a second.

:func:`cached_floor_model` keys the saved model by the input files (path, size, modification time), the
loader policies and the configuration, so a second evaluation against the same floor reads one
``.npz`` and two small tables instead of parsing the walk files again.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from ilocalg.io.recording import as_recording, common_frame
from ilocalg.track._config import DEFAULT_CONFIG, RealWalkConfig
from ilocalg.track.database import WifiDatabase
from ilocalg.track.fixes import select_wifi_nested
from ilocalg.track.motion import (
    Calibration,
    GainStats,
    calibrate,
    calibration_from_rows,
    gain_stats,
    step_intervals,
    step_var_from_intervals,
    walk_steps,
)

__all__ = ["FloorModel", "WalkModel", "build_floor_model", "cached_floor_model", "floor_cache_key"]


@dataclass(frozen=True)
class WalkModel:
    """What the other walks of a floor teach for one scored walk (see :meth:`FloorModel.for_walk`)."""

    db: WifiDatabase
    calibration: Calibration
    fix_var_m2: float
    step_var_m2: float
    cfg: RealWalkConfig
    wifi_config: str
    gain: GainStats | None = None


@dataclass(frozen=True)
class FloorModel:
    """A floor's database, per-walk calibration rows and step intervals (module docstring)."""

    db: WifiDatabase
    per_walk: pd.DataFrame
    intervals: pd.DataFrame

    @property
    def walks(self) -> list[str]:
        return list(self.per_walk["walk"])

    def for_walk(self, name: str | None = None, cfg: RealWalkConfig = DEFAULT_CONFIG, select: bool = True,
                 content_id: str | None = None) -> WalkModel:
        """The model of the walks other than ``name`` (None: all walks, for a walk from outside the floor).

        ``content_id``: the scored walk's :attr:`~ilocalg.io.recording.Recording.content_id`; a database
        walk with the same content under another name raises naming it.
        """
        if content_id is not None:
            same = [k for k, v in self.db.content_ids.items() if v == content_id and k != name]
            if same:
                raise ValueError(f"the fingerprint walks must not include the scored walk: {same[0]!r} has the same "
                                 "sensor content (a copy under another name)")
        out = [] if name is None or name not in set(self.per_walk["walk"]) else [name]
        db = self.db.without(*out) if out else self.db
        pw = self.per_walk[~self.per_walk["walk"].isin(out)]
        cal = calibration_from_rows(pw)
        iv = self.intervals[~self.intervals["walk"].isin(out)]
        sv = step_var_from_intervals(iv, cal)
        try:
            gs = gain_stats(iv, cal)
        except ValueError:                         # too few walks with waypoint intervals: no kf_gain
            gs = None
        if select:
            key = name if out else "__none__"
            label, c, var = select_wifi_nested(self.db, [key], cfg)[key]
        else:
            from ilocalg.track.fixes import calibrate_fix_var

            label, c, (var, _) = "given", cfg, calibrate_fix_var(db, cfg)
        return WalkModel(db, cal, var, sv, c, label, gs)

    def save(self, folder) -> Path:
        """Write ``database.npz``, ``per_walk.csv`` and ``intervals.csv`` into ``folder``."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        self.db.save(folder / "database.npz")
        self.per_walk.to_csv(folder / "per_walk.csv", index=False, float_format="%.17g")
        self.intervals.to_csv(folder / "intervals.csv", index=False, float_format="%.17g")
        return folder

    @classmethod
    def load(cls, folder) -> FloorModel:
        folder = Path(folder)
        for f in ("database.npz", "per_walk.csv", "intervals.csv"):
            if not (folder / f).is_file():
                raise ValueError(f"{folder}: no floor model here ({f} missing)")
        pw = pd.read_csv(folder / "per_walk.csv", dtype={"walk": str})
        iv = pd.read_csv(folder / "intervals.csv", dtype={"walk": str})
        return cls(WifiDatabase.load(folder / "database.npz"), pw, iv)


def build_floor_model(walks, cfg: RealWalkConfig = DEFAULT_CONFIG, steps: dict | None = None,
                      progress=None) -> FloorModel:
    """Build the :class:`FloorModel` of walks with ground truth (dict name -> walk, or a sequence).

    ``progress``: optional callable ``progress(n_done, n_total)`` after each walk's steps.
    """
    items = list(walks.values() if isinstance(walks, dict) else walks)
    recs = [as_recording(w) for w in items]
    if not recs:
        raise ValueError("build_floor_model: no walks given")
    frame = common_frame(recs)
    recs = [r.in_frame(frame) for r in recs]
    st = dict(steps or {})
    for i, r in enumerate(recs):
        if r.name not in st:
            st[r.name] = walk_steps(r, cfg)
        if progress is not None:
            progress(i + 1, len(recs))
    db = WifiDatabase.from_recordings(recs, None, frame=frame, align_time=cfg.align_fix_time)
    pw = calibrate(recs, st, cfg).per_walk
    iv = pd.concat([step_intervals(r, st[r.name]) for r in recs], ignore_index=True)
    return FloorModel(db, pw, iv)


def floor_cache_key(files, **settings) -> str:
    """SHA-1 of the input files (resolved path, size, modification time) and the settings."""
    h = hashlib.sha1()
    for f in sorted(str(Path(p).resolve()) for p in files):
        s = Path(f).stat()
        h.update(f"{f}|{s.st_size}|{s.st_mtime_ns}\n".encode())
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    return h.hexdigest()[:16]


#: :class:`RealWalkConfig` fields the floor model does not depend on (how a scored walk's fixes are weighted and
#: started): left out of the cache key, so changing them reuses a floor's saved model.
NOT_IN_FLOOR_MODEL = ("fix_var", "fix_corr", "map_start")


def _model_cfg(cfg: RealWalkConfig) -> dict:
    """The configuration fields a floor model depends on (its cache key's ``cfg``)."""
    return {k: v for k, v in dataclasses.asdict(cfg).items() if k not in NOT_IN_FLOOR_MODEL}


def cached_floor_model(files, load_walks, cache_dir, cfg: RealWalkConfig = DEFAULT_CONFIG, progress=None,
                       **settings) -> tuple[FloorModel, bool]:
    """The floor model of the walks in ``files`` from ``cache_dir`` or, the first time, built and saved.

    ``load_walks()`` returns the walks (called only when building); ``settings`` (e.g. the loader
    policies) join the files and ``cfg`` in the cache key. Returns ``(model, from_cache)``.
    """
    key = floor_cache_key(files, cfg=_model_cfg(cfg), **settings)
    folder = Path(cache_dir) / key
    if folder.is_dir():
        try:
            return FloorModel.load(folder), True
        except ValueError:
            pass                                    # a stale or partial cache entry: rebuild it
    model = build_floor_model(load_walks(), cfg, progress=progress)
    model.save(folder)
    return model, False
