"""The floor model's Wi-Fi selection (ilocalg.track.floor): the floor-level choice made once at build and saved,
the nested choices of the floor's own walks unchanged and computed once per model, old caches rebuilt; the same
for the leave-one-walk-out fixes the per-fix variance is fitted on."""

import dataclasses
import json

import numpy as np
import pandas as pd
import pytest

from ilocalg.sim import walk_recordings as wr
from ilocalg.track import RealWalkConfig
from ilocalg.track import floor as floor_mod
from ilocalg.track.fixes import (
    calibrate_fix_var,
    loo_fix_features,
    loo_fix_features_nested,
    select_wifi,
    select_wifi_nested,
)


@pytest.fixture(scope="module")
def recs():
    return wr.simulate_recordings(7, seed=6, n_nodes=20)[1]


@pytest.fixture(scope="module")
def model(recs):
    return floor_mod.build_floor_model(recs[1:])


def _no_selection(monkeypatch):
    def boom(*a, **k):
        raise AssertionError("select_wifi_nested called again")
    monkeypatch.setattr(floor_mod, "select_wifi_nested", boom)


def test_floor_level_choice_is_made_at_build_saved_and_used_for_an_outside_walk(recs, model, tmp_path, monkeypatch):
    label, c, var = select_wifi_nested(model.db, ["__none__"], RealWalkConfig())["__none__"]
    assert model.selection["label"] == label and model.selection["fix_var_m2"] == var
    back = type(model).load(model.save(tmp_path / "m"))
    assert back.selection == model.selection                     # JSON floats read back bit for bit
    _no_selection(monkeypatch)                                   # an outside walk is now a look-up
    for m in (model, back):
        for name in (recs[0].name, None):
            wm = m.for_walk(name)
            assert (wm.wifi_config, wm.fix_var_m2, wm.cfg) == (label, var, c)


def test_nested_choices_of_the_floor_walks_are_unchanged_and_made_once(recs, monkeypatch):
    m = floor_mod.build_floor_model(recs[1:])
    walks = m.walks[:3]
    want = select_wifi_nested(m.db, walks, RealWalkConfig())
    got = m.select_wifi(walks)
    assert got == want
    s = walks[1]
    assert got[s][0] == select_wifi(m.db.without(s))[0]          # nested: never the scored walk's rows
    _no_selection(monkeypatch)
    for s in walks:                                              # later calls, one walk each: look-ups
        wm = m.for_walk(s)
        assert (wm.wifi_config, wm.cfg, wm.fix_var_m2) == want[s]


def test_a_selection_made_with_other_wknn_settings_is_not_reused(recs, model, monkeypatch):
    cfg = RealWalkConfig(not_heard_dbm=-110.0)
    calls = []
    real = floor_mod.select_wifi_nested

    def counted(db, names, c, *a, **k):
        calls.append(list(names))
        return real(db, names, c, *a, **k)

    monkeypatch.setattr(floor_mod, "select_wifi_nested", counted)
    got = model.for_walk(None, cfg)
    assert calls == [["__none__"]]
    assert (got.wifi_config, got.fix_var_m2) == real(model.db, ["__none__"], cfg)["__none__"][::2]
    assert floor_mod.selection_key(cfg) != model.selection["key"]
    # the fix-model fields do not enter the selection: the stored one serves them
    calls.clear()
    model.for_walk(None, dataclasses.replace(RealWalkConfig(), fix_var="isotropic", fix_corr=False))
    assert calls == []


def test_an_old_or_partial_cache_folder_is_rebuilt_never_read(recs, model, tmp_path, monkeypatch):
    folder = model.save(tmp_path / "m")
    (folder / "selection.json").write_text(json.dumps({"version": 1, "selection": model.selection}))
    want = rf"selection\.json: floor model version 1, expected {floor_mod.FLOOR_MODEL_VERSION}"
    with pytest.raises(ValueError, match=want):
        type(model).load(folder)
    (folder / "selection.json").unlink()                         # a version-1 folder has no selection file
    with pytest.raises(ValueError, match="selection.json missing"):
        type(model).load(folder)
    # cached_floor_model: the version is part of the key, and a broken folder under the key is rebuilt
    f = tmp_path / "walk.txt"
    f.write_text("x")
    key = floor_mod.floor_cache_key([f], cfg=floor_mod._model_cfg(RealWalkConfig()),
                                    floor_model_version=floor_mod.FLOOR_MODEL_VERSION)
    assert key != floor_mod.floor_cache_key([f], cfg=floor_mod._model_cfg(RealWalkConfig()))
    (tmp_path / "cache" / key).mkdir(parents=True)
    (tmp_path / "cache" / key / "selection.json").write_text("{}")
    floor_mod._LAST_MODEL.clear()
    built, cached = floor_mod.cached_floor_model([f], lambda: recs[1:], tmp_path / "cache")
    assert not cached and built.selection == model.selection
    again, cached = floor_mod.cached_floor_model([f], lambda: 1 / 0, tmp_path / "cache")
    assert cached and again is built                             # kept in this process
    floor_mod._LAST_MODEL.clear()
    read, cached = floor_mod.cached_floor_model([f], lambda: 1 / 0, tmp_path / "cache")
    assert cached and read.selection == model.selection
    floor_mod._LAST_MODEL.clear()



def test_nested_selection_is_select_wifi_without_the_walk_for_every_walk(model):
    """Candidates sharing a distance matrix (same reading-age limit) or neighbours (same K) give what each
    candidate alone gives: select_wifi on the database without the walk, for every walk and for none."""
    got = select_wifi_nested(model.db, [*model.walks, "__none__"])
    for s in [*model.walks, "__none__"]:
        label, c, var, table = select_wifi(model.db.without(s) if s != "__none__" else model.db)
        assert got[s][0] == label and got[s][1] == c
        assert got[s][2] == pytest.approx(var, rel=1e-9)
    # K = 10 and the uniform weights really differ from the shared K = 5 neighbours here (the simulated readings
    # are all fresh, so the reading-age limits give one matrix; the real-floor check is in the report)
    assert table["mean_error_m"].nunique() >= 3


def _fractional_rssi(db):
    """The database with fractional readings: the distance products are no longer exact, so each walk's nested
    leave-out gets its own (the simulated readings are whole dBm, as the ILC files')."""
    assert np.array_equal(db.rssi_dbm, np.round(db.rssi_dbm), equal_nan=True)
    return dataclasses.replace(db, rssi_dbm=db.rssi_dbm + 0.37)


def _same(a, b):
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_nested_loo_fixes_are_those_of_the_database_without_the_walk_bit_for_bit(model, monkeypatch):
    from ilocalg.track import fixes

    c5, c10 = (dataclasses.replace(RealWalkConfig(), k_neighbors=k, max_age_s=None) for k in (5, 10))
    own = []                                                      # walks computed alone (their own product)
    real = fixes.loo_fix_features

    def seen(db, cfg, d2=None):
        own.append(d2)
        return real(db, cfg, d2=d2)
    for db, n_own in ((model.db, 0), (_fractional_rssi(model.db), 4)):   # one shared product / one per walk
        ws = list(dict.fromkeys(db.walk))
        cfgs = {ws[0]: c5, ws[1]: c10, ws[2]: c5, "__none__": c10}
        own.clear()
        monkeypatch.setattr(fixes, "loo_fix_features", seen)
        got = loo_fix_features_nested(db, cfgs)
        monkeypatch.setattr(fixes, "loo_fix_features", real)
        assert own == [None] * n_own
        for s, c in cfgs.items():
            want = loo_fix_features(db.without(s) if s != "__none__" else db, c)
            _same(got[s], want)
            assert np.isfinite(want[0]).all(axis=1).sum() > 0.9 * len(want[0])


def test_loo_fixes_stored_with_the_floor_model_serve_an_outside_walk(recs, model, tmp_path, monkeypatch):
    from ilocalg import track

    wm = model.for_walk(recs[0].name)
    _same(wm.loo_fixes, loo_fix_features(model.db, wm.cfg))
    assert model.floor_loo_fixes["key"] == floor_mod.wknn_key(wm.cfg)
    back = type(model).load(model.save(tmp_path / "m"))
    _same((back.floor_loo_fixes["err"], back.floor_loo_fixes["features"]), wm.loo_fixes)

    def boom(*a, **k):
        raise AssertionError("loo_fix_features_nested called again")
    monkeypatch.setattr(floor_mod, "loo_fix_features_nested", boom)
    got = back.for_walk(recs[0].name)                              # a look-up, never a refit
    _same(got.loo_fixes, wm.loo_fixes)
    # the walk's scores with the stored fixes are those of evaluate_walk fitting them itself
    kw = dict(methods=("wifi", "lsq", "kf_gain"), step_var_m2=got.step_var_m2, gain=got.gain)
    a = track.evaluate_walk(recs[0], got.db, got.calibration, got.fix_var_m2, got.cfg, loo_fixes=got.loo_fixes, **kw)
    b = track.evaluate_walk(recs[0], got.db, got.calibration, got.fix_var_m2, got.cfg, **kw)
    pd.testing.assert_frame_equal(a["errors"], b["errors"], check_exact=True)
    assert a["info"] == b["info"] or str(a["info"]) == str(b["info"])


def test_loo_fixes_of_the_floor_walks_are_computed_once_for_all_asked(recs, monkeypatch):
    m = floor_mod.build_floor_model(recs[1:])
    walks = m.walks[:3]
    calls = []
    real = floor_mod.loo_fix_features_nested

    def counted(db, walk_cfgs):
        calls.append(sorted(walk_cfgs))
        return real(db, walk_cfgs)
    monkeypatch.setattr(floor_mod, "loo_fix_features_nested", counted)
    got = m.loo_fixes(walks)
    assert calls == [sorted(walks)]
    for s in walks:
        wm = m.for_walk(s)                                         # a look-up
        _same(wm.loo_fixes, got[s])
        _same(got[s], loo_fix_features(m.db.without(s), wm.cfg))
    assert len(calls) == 1
    # a configuration needing no fix model computes none
    assert m.for_walk(walks[0], dataclasses.replace(RealWalkConfig(), fix_var="isotropic",
                                                    fix_corr=False)).loo_fixes is None
    # without the selection: the one isotropic variance from the same fixes, as calibrate_fix_var alone gives
    cfg = RealWalkConfig()
    for s in walks:
        wm = m.for_walk(s, cfg, select=False)
        assert wm.fix_var_m2 == calibrate_fix_var(m.db.without(s), cfg)[0]
        _same(wm.loo_fixes, loo_fix_features(m.db.without(s), cfg))


def test_shared_loo_fixes_give_each_candidates_loo_fix_errors(model):
    """wifi_ablation's candidates from one product per reading-age limit: the errors loo_fix_errors gives each."""
    from ilocalg.track.fixes import WIFI_CANDIDATES, loo_fix_errors, loo_fix_features_shared

    db = model.db
    cands = [dataclasses.replace(RealWalkConfig(), **kw) for kw in WIFI_CANDIDATES.values()]
    got = loo_fix_features_shared(db, [(None, c) for c in cands])
    for c, (err, _) in zip(cands, got, strict=True):
        np.testing.assert_array_equal(np.hypot(*err.T), loo_fix_errors(db, c))


def test_the_walked_path_spread_stored_with_the_floor_model_serves_an_outside_walk(recs, model, tmp_path, monkeypatch):
    from ilocalg import track
    from ilocalg.track.paths import WalkedPaths

    want = WalkedPaths.from_database(model.db).spread_var_m2()
    assert model.paths_var_m2 == want > 0
    back = type(model).load(model.save(tmp_path / "m"))
    assert back.paths_var_m2 == want                              # JSON floats read back bit-identical
    folder = tmp_path / "bad"
    model.save(folder)
    meta = json.loads((folder / "selection.json").read_text())
    for bad in ("1.0", -1.0, float("nan")):
        (folder / "selection.json").write_text(json.dumps({**meta, "paths_var_m2": bad}))
        with pytest.raises(ValueError, match=r"bad/selection\.json: paths_var_m2 must be a positive number"):
            type(model).load(folder)
    assert back.for_walk(recs[0].name).path_var_m2 == want        # an outside walk: the whole database's graph
    assert back.for_walk(recs[1].name).path_var_m2 is None        # a floor walk's graph leaves it out: measured then
    got = back.for_walk(recs[0].name)
    kw = dict(methods=("wifi", "lsq_paths"), step_var_m2=got.step_var_m2, gain=got.gain, loo_fixes=got.loo_fixes)
    b = track.evaluate_walk(recs[0], got.db, got.calibration, got.fix_var_m2, got.cfg, **kw)

    def boom(self, *a, **k):
        raise AssertionError("spread measured again")
    monkeypatch.setattr(WalkedPaths, "spread_var_m2", boom)
    a = track.evaluate_walk(recs[0], got.db, got.calibration, got.fix_var_m2, got.cfg, path_var_m2=got.path_var_m2,
                            **kw)
    pd.testing.assert_frame_equal(a["errors"], b["errors"], check_exact=True)


def test_the_last_two_floor_models_are_kept(tmp_path, monkeypatch):
    """A notebook's floor stays in memory while a leave-one-walk-out visits a second floor; a third evicts the
    least recently used."""
    class Fake:
        def save(self, folder):
            return folder

    monkeypatch.setattr(floor_mod, "build_floor_model", lambda walks, cfg, steps=None, progress=None: Fake())
    files = []
    for name in "abc":
        f = tmp_path / f"{name}.txt"
        f.write_text(name)
        files.append(f)
    floor_mod._LAST_MODEL.clear()
    a, _ = floor_mod.cached_floor_model([files[0]], list, tmp_path / "cache")
    b, _ = floor_mod.cached_floor_model([files[1]], list, tmp_path / "cache")
    assert floor_mod.cached_floor_model([files[0]], lambda: 1 / 0, tmp_path / "cache") == (a, True)
    floor_mod.cached_floor_model([files[2]], list, tmp_path / "cache")       # evicts b, the oldest now
    assert floor_mod.cached_floor_model([files[0]], lambda: 1 / 0, tmp_path / "cache")[0] is a
    c, cached = floor_mod.cached_floor_model([files[1]], list, tmp_path / "cache")
    assert c is not b and not cached                                         # rebuilt (a fake has no files)
    floor_mod._LAST_MODEL.clear()


def test_the_floor_model_keeps_its_walks_and_their_walked_path_graph(recs, model, tmp_path):
    """A scorer of some of a floor's walks reads only those: the model holds every walk's name (in the order
    given) and the walked-path graph of their waypoints, the same segments as the graph of the walks themselves in
    the database's frame, read back bit-identical; ``build=False`` only looks."""
    from ilocalg.track.paths import WalkedPaths

    assert model.names == tuple(r.name for r in recs[1:])
    want = WalkedPaths.from_recordings(recs[1:], model.db.frame)
    back = type(model).load(model.save(tmp_path / "m"))
    for got in (model.walk_paths, back.walk_paths):
        np.testing.assert_array_equal(got.a_m, want.a_m)
        np.testing.assert_array_equal(got.b_m, want.b_m)
        assert list(got.walk) == list(want.walk) and got.walk.dtype == object
    assert back.names == model.names
    d = {r.name: r for r in recs[1:4]}
    assert floor_mod.build_floor_model(d).names == tuple(d)
    floor_mod._LAST_MODEL.clear()
    files = [tmp_path / "walks.txt"]
    files[0].write_text("x")
    assert floor_mod.cached_floor_model(files, lambda: 1 / 0, tmp_path / "cache", build=False) == (None, False)
    floor_mod._LAST_MODEL.clear()
