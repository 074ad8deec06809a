"""WifiDatabase.save / load: the loaded database is exactly the one saved (every array bit for bit)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ilocalg.io.recording import LocalFrame
from ilocalg.track.database import _FORMAT_VERSION, WifiDatabase


def _assert_identical(a: WifiDatabase, b: WifiDatabase) -> None:
    for f in ("rssi_dbm", "xy_m", "walk", "floor", "age_s"):
        x, y = getattr(a, f), getattr(b, f)
        assert (x is None) == (y is None), f
        if x is None:
            continue
        assert x.dtype == y.dtype and x.shape == y.shape, f
        if x.dtype.kind == "f":   # bit for bit, NaN where NaN (and -0.0 stays -0.0)
            np.testing.assert_array_equal(x.view(np.uint64), y.view(np.uint64), err_msg=f)
        else:
            assert x.tolist() == y.tolist(), f
    assert a.ap_ids == b.ap_ids and a.frame == b.frame and a.content_ids == b.content_ids


def _random_db(rng, with_floor=True, with_age=True) -> WifiDatabase:
    n, m = 40, 7
    rssi = rng.uniform(-100, -30, (n, m))            # not integers: float32 would round them
    rssi[rng.random((n, m)) < 0.6] = np.nan
    rssi[0, 0] = -0.0
    age = np.where(np.isnan(rssi), np.nan, rng.uniform(0, 3, (n, m)))
    return WifiDatabase(rssi, rng.normal(0, 20, (n, 2)), np.array([f"walk{i % 5}" for i in range(n)], dtype=object),
                        tuple(f"ap{j}" for j in range(m)), rng.integers(0, 3, n).astype(float) if with_floor else None,
                        LocalFrame("aeqd 48.1234567 11.1234567", 48.1234567, 11.1234567),
                        {f"walk{i}": f"id{i}" for i in range(5)}, age if with_age else None)


@pytest.mark.parametrize("with_floor,with_age", [(True, True), (False, True), (True, False)])
def test_save_load_is_bit_identical(tmp_path, with_floor, with_age):
    db = _random_db(np.random.default_rng(0), with_floor, with_age)
    x = db.age_s if with_age else db.rssi_dbm
    heard = ~np.isnan(x)
    assert np.any(x[heard] != x[heard].astype(np.float32).astype(np.float64))   # float32 would change them
    back = WifiDatabase.load(db.save(tmp_path / "db.npz"))
    _assert_identical(db, back)


def test_loaded_database_of_simulated_walks_equals_the_built_one(tmp_path):
    from ilocalg.sim import walk_recordings as wr

    _, recs = wr.simulate_recordings(5, seed=4, n_nodes=20)
    db = WifiDatabase.from_recordings(recs)
    back = WifiDatabase.load(db.save(tmp_path / "db.npz"))
    _assert_identical(db, back)
    _assert_identical(db.without(recs[1].name), back.without(recs[1].name))


def test_loaded_database_of_real_walks_equals_the_built_one(tmp_path, shared_data):
    """ILC 2.0 reading ages (scan time minus last-seen, ms-resolution Unix times in seconds) are not float32
    numbers; the file keeps them exactly (format 3 stored float32 and changed them by up to 1e-6 s)."""
    from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor

    root = shared_data("ilc2020_site1")
    names = list_ilc_traces(root, floor_name="site1_F1")[:4]
    fl = load_ilc_floor(root, names=names, duplicate_bssid="keep_latest", relisted_wifi="keep",
                        floor_name="site1_F1")
    db = WifiDatabase.from_recordings(fl.traces)
    assert db.age_s is not None
    back = WifiDatabase.load(db.save(tmp_path / "db.npz"))
    _assert_identical(db, back)


def test_load_refuses_other_files_naming_them(tmp_path):
    db = _random_db(np.random.default_rng(1))
    p = db.save(tmp_path / "db.npz")
    with np.load(p) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(bytes(arrays["meta"]).decode())
    meta["version"] = _FORMAT_VERSION - 1
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    old = tmp_path / "old.npz"
    np.savez(old, **arrays)
    with pytest.raises(ValueError, match=rf"old\.npz: database format version {_FORMAT_VERSION - 1}, expected "
                                         rf"{_FORMAT_VERSION}; delete the file"):
        WifiDatabase.load(old)
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a zip")
    with pytest.raises(ValueError, match=r"junk\.npz: not a fingerprint database file"):
        WifiDatabase.load(junk)


def _reference_wknn(db: WifiDatabase, X, cfg):
    """locate_wknn as written before the shared query side: the dense product of the database's own matrix."""
    from ilocalg.track.fixes import _place, db_matrix, dense_wknn

    D = db_matrix(db, cfg)
    heard = ~np.isnan(D).all(axis=0)
    miss = ~(~np.isnan(X[:, heard])).any(axis=1)
    xy, C = np.full((len(X), 2), np.nan), np.full((len(X), 2, 2), np.nan)
    idx, dist = dense_wknn(D, X[~miss], cfg.k_neighbors, cfg.not_heard_dbm)
    _place(xy, C, db.xy_m, idx, dist, cfg.weights, np.flatnonzero(~miss))
    return xy, C


@pytest.mark.parametrize("whole", [True, False])
@pytest.mark.parametrize("max_age_s", [2.0, None])
def test_queries_against_a_database_left_out_of_another_give_its_own_bits(whole, max_age_s):
    """A walk left out (`without`) takes its query side from the whole database's rows: the same fixes, bit for
    bit, as the database built alone (whole dBm values, where the product runs over heard cells, with ties
    between distances; and fractional values, the dense product)."""
    import dataclasses

    from ilocalg.track import RealWalkConfig
    from ilocalg.track.fixes import locate_wknn, query_side

    rng = np.random.default_rng(3)
    db = _random_db(rng)
    if whole:
        db = dataclasses.replace(db, rssi_dbm=np.round(db.rssi_dbm / 10.0) * 10.0)     # many equal distances
    cfg = RealWalkConfig(max_age_s=max_age_s)
    X = db.rssi_dbm[::3].copy()
    X[1] = np.nan                                                        # hears nothing: no fix
    for left in ("walk1", "walk4"):
        sub = db.without(left)
        alone = WifiDatabase(sub.rssi_dbm.copy(), sub.xy_m, sub.walk, sub.ap_ids, sub.floor, sub.frame,
                             sub.content_ids, sub.age_s)
        assert alone._parent is None and sub._parent is not None
        got, ref = locate_wknn(sub, X, cfg), _reference_wknn(alone, X, cfg)
        for a, b in zip(got, ref, strict=True):
            np.testing.assert_array_equal(a.view(np.uint64), b.view(np.uint64))
        assert (query_side(sub, cfg).A_sparse is not None) == whole
        np.testing.assert_array_equal(query_side(sub, cfg).heard, query_side(alone, cfg).heard)
    # a replaced database starts without the other's memo or parent
    r = dataclasses.replace(sub, xy_m=sub.xy_m + 1.0)
    assert r._memo == {} and r._parent is None
