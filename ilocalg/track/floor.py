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
loader policies, the configuration and :data:`FLOOR_MODEL_VERSION`, so a second evaluation against the same
floor reads one ``.npz``, two small tables and one small JSON file instead of parsing the walk files again.

The Wi-Fi configuration a walk from *outside* the floor gets depends on the floor only: it is chosen once,
when the model is built, and saved with it (``selection.json``, :attr:`FloorModel.selection`). The nested
selections of the floor's own walks (each chosen without the walk) are computed on demand, one distance
matrix per reading-age limit for all the walks asked at once (:meth:`FloorModel.select_wifi`), and kept in
memory with the model so that later calls for the same walks only look them up.

The same holds for the database walks' leave-one-walk-out fixes the per-fix variance model and the fix-error
correlation are fitted on (:func:`ilocalg.track.fixes.loo_fix_features`): for a walk from outside the floor
they are computed at build with the floor-level selection and saved (``loo_fixes.npz``); for the floor's own
walks (each without the walk) on demand, one distance matrix for all the walks asked at once
(:meth:`FloorModel.loo_fixes`), and kept in memory.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.recording import as_recording, common_frame
from ilocalg.track._config import DEFAULT_CONFIG, RealWalkConfig
from ilocalg.track.database import WifiDatabase
from ilocalg.track.fixes import WIFI_CANDIDATES, loo_fix_features_nested, select_wifi_nested, wknn_key
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
from ilocalg.track.paths import WalkedPaths

__all__ = ["FLOOR_MODEL_VERSION", "FloorModel", "WalkModel", "build_floor_model", "cached_floor_model",
           "floor_cache_key", "floor_selection", "selection_key"]


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
    #: :func:`ilocalg.track.fixes.loo_fix_features` of ``db`` with ``cfg`` (``(err, features)``), the
    #: per-fix variance's and the fix-error correlation's data (:func:`ilocalg.track.evaluate_walk`'s
    #: ``loo_fixes``); None: not computed (``cfg`` needs neither, or its WKNN is not Euclidean).
    loo_fixes: tuple | None = None
    #: :meth:`~ilocalg.track.paths.WalkedPaths.spread_var_m2` of the graph of ``db``'s scan positions (what
    #: :data:`~ilocalg.track.PATH_METHODS` weight the graph by, :func:`ilocalg.track.evaluate_walk`'s
    #: ``path_var_m2``); None: computed when needed.
    path_var_m2: float | None = None


@dataclass(frozen=True)
class FloorModel:
    """A floor's database, per-walk calibration rows and step intervals (module docstring)."""

    db: WifiDatabase
    per_walk: pd.DataFrame
    intervals: pd.DataFrame
    #: The floor-level Wi-Fi selection (every walk of the floor; what a walk from outside it gets), made at
    #: build: ``{"key": ..., "label": ..., "fix_var_m2": ...}`` (:func:`floor_selection`); None: not made
    #: (fewer than two walks), then chosen when asked.
    selection: dict | None = None
    #: :func:`ilocalg.track.fixes.loo_fix_features` of the whole database with the floor-level selection's
    #: configuration (what a walk from outside the floor is weighted with), made at build with :attr:`selection`:
    #: ``{"key": wknn_key(config), "err": (n, 2), "features": (n, 3)}``; None: not made.
    floor_loo_fixes: dict | None = None
    #: The spread (per-axis variance, m^2) of the walked-path graph of the whole database's scan positions
    #: (:meth:`~ilocalg.track.paths.WalkedPaths.spread_var_m2` of
    #: :meth:`~ilocalg.track.paths.WalkedPaths.from_database`): what a walk from outside the floor weights the
    #: graph with, made at build; None: fewer than two walks.
    paths_var_m2: float | None = None
    #: The floor's walks in the order they were given to :func:`build_floor_model` (a loaded floor's
    #: :attr:`~ilocalg.io.ilc.IlcFloor.names`), every walk, also those without a database row; None: not stored.
    names: tuple | None = None
    #: The walked-path graph of every walk's waypoints in :attr:`db`'s frame
    #: (:meth:`~ilocalg.track.paths.WalkedPaths.from_recordings`), made at build, so that scoring some of the
    #: floor's walks needs only those walks' files (``paths.npz``); None: not stored.
    walk_paths: WalkedPaths | None = None
    _selected: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)
    _loo: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)

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
        loo = None
        if cfg.fix_var == "per_fix" or cfg.fix_corr or not select:
            loo = self.loo_fixes([name], cfg, select=select)[name]
        if select:
            label, c, var = self.select_wifi([name], cfg)[name]
        else:       # the isotropic variance from the same leave-one-walk-out fixes
            from ilocalg.track.fixes import calibrate_fix_var

            label, c, (var, _) = "given", cfg, calibrate_fix_var(db, cfg, None if loo is None else loo[0])
        if not (cfg.fix_var == "per_fix" or cfg.fix_corr):
            loo = None
        return WalkModel(db, cal, var, sv, c, label, gs, loo, None if out else self.paths_var_m2)

    def loo_fixes(self, names, cfg: RealWalkConfig = DEFAULT_CONFIG, select: bool = True) -> dict:
        """The database walks' leave-one-walk-out fixes (:func:`ilocalg.track.fixes.loo_fix_features`: error
        vectors and features) that :meth:`for_walk` gives each walk of ``names``: of the database without the
        walk (the whole database for a name that is not a walk of the floor, or None), with the walk's Wi-Fi
        configuration (:meth:`select_wifi` when ``select``, else ``cfg``). Returns ``{name: (err, features)}``,
        None for a configuration that is not Euclidean.

        For a walk from outside the floor they are :attr:`floor_loo_fixes` when made with the same
        configuration; the others are computed together (:func:`ilocalg.track.fixes.loo_fix_features_nested`,
        one distance matrix per reading-age limit) the first time they are asked, then kept with the model.
        """
        own = set(self.per_walk["walk"])
        sel = self.select_wifi(names, cfg) if select else {n: ("given", cfg, None) for n in names}
        keys = {n: (n if n in own else "__none__", json.dumps(wknn_key(sel[n][1]))) for n in names}
        fl = self.floor_loo_fixes
        if fl is not None:
            self._loo.setdefault(("__none__", json.dumps(fl["key"])), (fl["err"], fl["features"]))
        todo = {}
        for n, k in keys.items():
            if k not in self._loo and k not in todo:
                c = sel[n][1]
                todo[k] = c if c.p == 2 and c.metric == "minkowski" else None
        for k in [k for k, c in todo.items() if c is None]:
            self._loo[k] = None
        walks = [k for k, c in todo.items() if c is not None]
        if walks:
            got = loo_fix_features_nested(self.db, {k[0]: todo[k] for k in walks if k[0] != "__none__"})
            for k in walks:
                if k[0] != "__none__":
                    self._loo[k] = got[k[0]]
            for k in walks:                         # outside the floor: the whole database, one key per config
                if k[0] == "__none__":
                    self._loo[k] = loo_fix_features_nested(self.db, {"__none__": todo[k]})["__none__"]
        return {n: self._loo[k] for n, k in keys.items()}

    def select_wifi(self, names, cfg: RealWalkConfig = DEFAULT_CONFIG) -> dict:
        """The nested Wi-Fi configuration of each walk of ``names`` (:func:`ilocalg.track.fixes.select_wifi_nested`:
        chosen by leave-one-walk-out over the floor's *other* walks; a name that is not a walk of the floor, or
        None, gets the floor-level choice over every walk). Returns ``{name: (label, cfg_with_it, fix_var_m2)}``.

        The floor-level choice is :attr:`selection` when it was made with the same candidates and WKNN settings
        (:func:`selection_key`); the others are computed together (one distance matrix per reading-age limit) the
        first time they are asked, then kept with the model (in memory): the same numbers are never computed twice.
        """
        key = selection_key(cfg)
        memo = self._selected.setdefault(json.dumps(key), {})
        sel = self.selection
        if sel is not None and sel["key"] == key:
            memo.setdefault("__none__", (sel["label"], sel["fix_var_m2"]))
        own = set(self.per_walk["walk"])
        keys = {n: n if n in own else "__none__" for n in names}
        todo = [k for k in dict.fromkeys(keys.values()) if k not in memo]
        if todo:
            for k, (label, _, var) in select_wifi_nested(self.db, todo, cfg).items():
                memo[k] = (label, var)
        return {n: (memo[k][0], dataclasses.replace(cfg, **WIFI_CANDIDATES[memo[k][0]]), memo[k][1])
                for n, k in keys.items()}

    def save(self, folder) -> Path:
        """Write ``database.npz``, ``per_walk.csv``, ``intervals.csv``, ``loo_fixes.npz`` (when
        :attr:`floor_loo_fixes` is made), ``paths.npz`` (when :attr:`walk_paths` is made) and ``selection.json``
        (last: the model is complete when it is there) into ``folder``."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        self.db.save(folder / "database.npz")
        self.per_walk.to_csv(folder / "per_walk.csv", index=False, float_format="%.17g")
        self.intervals.to_csv(folder / "intervals.csv", index=False, float_format="%.17g")
        fl = self.floor_loo_fixes
        if fl is not None:
            with open(folder / "loo_fixes.npz", "wb") as f:
                np.savez(f, err=np.asarray(fl["err"], dtype=np.float64),
                         features=np.asarray(fl["features"], dtype=np.float64))
        wp = self.walk_paths
        if wp is not None:
            with open(folder / "paths.npz", "wb") as f:
                np.savez(f, a_m=np.asarray(wp.a_m, dtype=np.float64), b_m=np.asarray(wp.b_m, dtype=np.float64),
                         walk=np.asarray(wp.walk, dtype=str))
        tmp = folder / "selection.json.tmp"
        tmp.write_text(json.dumps({"version": FLOOR_MODEL_VERSION, "selection": self.selection,
                                   "loo_fixes_key": None if fl is None else fl["key"],
                                   "paths_var_m2": self.paths_var_m2,
                                   "names": None if self.names is None else list(self.names)}))
        os.replace(tmp, folder / "selection.json")      # JSON floats are repr: read back bit-identical
        return folder

    @classmethod
    def load(cls, folder) -> FloorModel:
        """Read a model written by :meth:`save`; an incomplete folder or one of another
        :data:`FLOOR_MODEL_VERSION` raises naming it."""
        folder = Path(folder)
        for f in ("database.npz", "per_walk.csv", "intervals.csv", "selection.json"):
            if not (folder / f).is_file():
                raise ValueError(f"{folder}: no floor model here ({f} missing)")
        try:
            meta = json.loads((folder / "selection.json").read_text())
        except ValueError as e:
            raise ValueError(f"{folder / 'selection.json'}: not a floor model's selection file ({e})") from None
        got = meta.get("version") if isinstance(meta, dict) else None
        if got != FLOOR_MODEL_VERSION:
            raise ValueError(f"{folder / 'selection.json'}: floor model version {got!r}, expected "
                             f"{FLOOR_MODEL_VERSION}; delete the folder to rebuild it")
        pw = pd.read_csv(folder / "per_walk.csv", dtype={"walk": str})
        iv = pd.read_csv(folder / "intervals.csv", dtype={"walk": str})
        fl = None
        if meta.get("loo_fixes_key") is not None:
            try:
                with np.load(folder / "loo_fixes.npz", allow_pickle=False) as z:
                    fl = {"key": meta["loo_fixes_key"], "err": z["err"], "features": z["features"]}
            except (OSError, ValueError, KeyError) as e:
                raise ValueError(f"{folder / 'loo_fixes.npz'}: not a floor model's leave-one-walk-out fixes "
                                 f"({type(e).__name__}: {e})") from None
        pvar = meta.get("paths_var_m2")
        if pvar is not None and not (isinstance(pvar, (int, float)) and math.isfinite(pvar) and pvar > 0):
            raise ValueError(f"{folder / 'selection.json'}: paths_var_m2 must be a positive number or null, got "
                             f"{pvar!r}")
        wp = None
        if (folder / "paths.npz").is_file():
            try:
                with np.load(folder / "paths.npz", allow_pickle=False) as z:
                    wp = WalkedPaths(z["a_m"], z["b_m"], z["walk"].astype(object))
            except (OSError, ValueError, KeyError) as e:
                raise ValueError(f"{folder / 'paths.npz'}: not a floor model's walked-path graph "
                                 f"({type(e).__name__}: {e})") from None
        names = meta.get("names")
        if names is not None and not (isinstance(names, list) and all(isinstance(n, str) for n in names)):
            raise ValueError(f"{folder / 'selection.json'}: names must be a list of walk names or null")
        return cls(WifiDatabase.load(folder / "database.npz"), pw, iv, meta["selection"], fl, pvar,
                   None if names is None else tuple(names), wp)


#: Version of a saved floor model (1: database, calibration rows, step intervals; 2: + the floor-level Wi-Fi
#: selection, ``selection.json``; 3: + the leave-one-walk-out fixes of that selection, ``loo_fixes.npz``; 4: + the
#: spread of the walked-path graph, :attr:`FloorModel.paths_var_m2`; 5: + the walks' names and the walked-path graph
#: of their waypoints, :attr:`FloorModel.names`, :attr:`FloorModel.walk_paths`). Part of :func:`cached_floor_model`'s
#: key, so an older cache is never read.
FLOOR_MODEL_VERSION = 5


def selection_key(cfg: RealWalkConfig = DEFAULT_CONFIG, candidates=None) -> list:
    """What a Wi-Fi selection depends on besides the database: each candidate's label and its effective WKNN
    settings in ``cfg`` (``k_neighbors, p, weights, metric, max_age_s, not_heard_dbm``), as JSON-ready lists."""
    cands = WIFI_CANDIDATES if candidates is None else candidates
    out = []
    for label, kw in cands.items():
        c = dataclasses.replace(cfg, **kw)
        out.append([label, c.k_neighbors, c.p, c.weights, c.metric, c.max_age_s, c.not_heard_dbm])
    return out


def floor_selection(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG) -> dict | None:
    """The floor-level Wi-Fi selection of a :class:`FloorModel`: :func:`~ilocalg.track.fixes.select_wifi_nested`
    over every walk of ``db``, as ``{"key": selection_key(cfg), "label", "fix_var_m2"}``; None for fewer than
    two walks (no walk to leave out)."""
    if len(set(db.walk)) < 2:
        return None
    label, _, var = select_wifi_nested(db, ["__none__"], cfg)["__none__"]
    return {"key": selection_key(cfg), "label": label, "fix_var_m2": var}


def build_floor_model(walks, cfg: RealWalkConfig = DEFAULT_CONFIG, steps: dict | None = None,
                      progress=None, select: bool = True) -> FloorModel:
    """Build the :class:`FloorModel` of walks with ground truth (dict name -> walk, or a sequence).

    ``progress``: optional callable ``progress(n_done, n_total)`` after each walk's steps. ``select``: make the
    floor-level Wi-Fi selection (:func:`floor_selection`) now, as a saved model must; False leaves it to the
    first walk from outside the floor (:meth:`FloorModel.select_wifi`).
    """
    items = list(walks.values() if isinstance(walks, dict) else walks)
    recs = [as_recording(w) for w in items]
    names = tuple(walks) if isinstance(walks, dict) else tuple(r.name for r in recs)
    if not recs:
        raise ValueError("build_floor_model: no walks given")
    frame = common_frame(recs)
    # the graph of every walk's waypoints, as a scorer of the loaded walks makes it (walks given, the database's frame)
    wpaths = WalkedPaths.from_recordings(walks, frame)
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
    sel = floor_selection(db, cfg) if select else None
    pvar = WalkedPaths.from_database(db).spread_var_m2() if len(set(db.walk)) >= 2 else None
    return FloorModel(db, pw, iv, sel, floor_loo_fixes(db, sel, cfg), pvar, names, wpaths)


def floor_loo_fixes(db: WifiDatabase, selection: dict | None, cfg: RealWalkConfig = DEFAULT_CONFIG) -> dict | None:
    """:attr:`FloorModel.floor_loo_fixes`: :func:`ilocalg.track.fixes.loo_fix_features` of the whole ``db`` with
    the floor-level ``selection``'s configuration in ``cfg`` (made whatever ``cfg.fix_var`` and ``cfg.fix_corr``
    say: they are not in the cache key); None without a selection or for a selection that is not Euclidean."""
    if selection is None:
        return None
    c = dataclasses.replace(cfg, **WIFI_CANDIDATES[selection["label"]])
    if not (c.p == 2 and c.metric == "minkowski"):
        return None
    err, feats = loo_fix_features_nested(db, {"__none__": c})["__none__"]
    return {"key": wknn_key(c), "err": err, "features": feats}


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
                       steps: dict | None = None, build: bool = True, **settings) -> tuple[FloorModel | None, bool]:
    """The floor model of the walks in ``files`` from ``cache_dir`` or, the first time, built and saved.

    ``load_walks()`` returns the walks (called only when building); ``settings`` (e.g. the loader
    policies) join the files and ``cfg`` in the cache key. ``steps``: :func:`ilocalg.track.motion.walk_steps` of
    some of the walks with ``cfg`` when already computed (name -> steps; :func:`build_floor_model` computes the
    others). ``build=False``: only look (``(None, False)`` when the model is neither kept nor saved). Returns
    ``(model, from_cache)``.

    The last :data:`KEPT_MODELS` models returned are kept in this process: asked again with the same key (e.g. a
    notebook's run, its leave-one-walk-out and each configuration of an ablation), the same object comes back, with
    the Wi-Fi selections it has made (:meth:`FloorModel.select_wifi`), and ``from_cache`` is True.
    """
    key = floor_cache_key(files, cfg=_model_cfg(cfg), floor_model_version=FLOOR_MODEL_VERSION, **settings)
    folder = Path(cache_dir) / key
    kept = _LAST_MODEL.pop(str(folder.resolve()), None)
    if kept is not None:
        _LAST_MODEL[str(folder.resolve())] = kept               # the most recently used, kept longest
        return kept, True
    model, cached = None, False
    if folder.is_dir():
        try:
            model, cached = FloorModel.load(folder), True
        except ValueError:
            pass                                    # a stale or partial cache entry: rebuild it
    if model is None:
        if not build:
            return None, False
        model = build_floor_model(load_walks(), cfg, steps=steps, progress=progress)
        model.save(folder)
    while len(_LAST_MODEL) >= KEPT_MODELS:          # a site 1 floor is about 60 MB in memory
        _LAST_MODEL.pop(next(iter(_LAST_MODEL)))
    _LAST_MODEL[str(folder.resolve())] = model
    return model, cached


#: How many floor models :func:`cached_floor_model` keeps in this process: two, so that a notebook's floor keeps its
#: selections while a leave-one-walk-out over two floors visits the other one.
KEPT_MODELS = 2
#: The floor models :func:`cached_floor_model` returned last in this process (resolved folder -> model), least
#: recently used first.
_LAST_MODEL: dict = {}
