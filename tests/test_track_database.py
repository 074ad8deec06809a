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
