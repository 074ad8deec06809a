"""Building -> floor -> position, and flat locate_flat() with votes."""

import numpy as np
import pytest

from ilocalg.wifi import HierarchicalLocator, KnnFingerprint, SimplifiedHorus, SimplifiedRadar, locate_flat


def _two_buildings(rng, n=240, n_aps=30):
    # building b hears only its own APs (0..14 or 15..29); floors differ by a 15 dB slab
    b = rng.integers(0, 2, n)
    f = rng.integers(0, 3, n)
    xy = rng.uniform(0, 40, (n, 2))
    aps = np.random.default_rng(99).uniform(0, 40, (n_aps, 2))  # one AP layout for every call
    d = np.hypot(xy[:, None, 0] - aps[None, :, 0], xy[:, None, 1] - aps[None, :, 1])
    ap_floor = np.tile(np.arange(3), n_aps // 3)
    rssi = -40 - 25 * np.log10(np.maximum(d, 1)) - 15 * np.abs(f[:, None] - ap_floor[None, :])
    rssi = np.round(rssi + rng.normal(0, 2, rssi.shape))
    own = (np.arange(n_aps)[None, :] < 15) == (b[:, None] == 0)
    rssi[~own | (rssi < -100)] = np.nan
    xy = xy + 100.0 * b[:, None]
    return rssi, xy, f, b


def test_hierarchical_recovers_building_and_floor():
    rng = np.random.default_rng(0)
    X, xy, f, b = _two_buildings(rng)
    Xq, xyq, fq, bq = _two_buildings(np.random.default_rng(1), n=80)
    loc = HierarchicalLocator(KnnFingerprint(5, p=2, not_heard_dbm=-105)).fit(X, xy, f, b)
    out = loc.predict(Xq)
    assert (out["building"].to_numpy() == bq).all()
    assert np.mean(out["floor"].to_numpy() == fq) > 0.9
    e = np.hypot(out["x_m"] - xyq[:, 0], out["y_m"] - xyq[:, 1])
    assert np.median(e) < 8.0
    # the position is always inside the predicted building
    assert ((out["x_m"].to_numpy() >= 100) == (out["building"].to_numpy() == 1)).all()


@pytest.mark.parametrize("est", [KnnFingerprint(5, p=2, not_heard_dbm=-105), SimplifiedRadar(5, 3, -105),
                                 SimplifiedHorus(5)])
def test_locate_flat_votes(est):
    rng = np.random.default_rng(2)
    X, xy, f, b = _two_buildings(rng)
    Xq, xyq, fq, bq = _two_buildings(np.random.default_rng(3), n=60)
    y = np.column_stack([xy, f, b]) if isinstance(est, SimplifiedHorus) else xy
    out = locate_flat(est.fit(X, y), Xq, f, b)
    assert list(out.columns) == ["x_m", "y_m", "floor", "building"]
    assert np.mean(out["building"].to_numpy() == bq) == 1.0
    assert np.mean(out["floor"].to_numpy() == fq) > 0.6


def test_locate_knn_matches_predict():
    rng = np.random.default_rng(4)
    X, xy, f, b = _two_buildings(rng)
    est = KnnFingerprint(4, p=1, weights="distance", not_heard_dbm=-105).fit(X, xy)
    out = locate_flat(est, X[:20], f, b)
    np.testing.assert_allclose(out[["x_m", "y_m"]].to_numpy(), est.predict(X[:20]))


def test_bad_labels():
    rng = np.random.default_rng(5)
    X, xy, f, b = _two_buildings(rng, n=30)
    with pytest.raises(ValueError, match="floor must have shape"):
        HierarchicalLocator().fit(X, xy, f[:-1], b)
    with pytest.raises(ValueError, match="needs floor and building"):
        HierarchicalLocator().fit(X, xy, None, b)
    with pytest.raises(ValueError, match="xy must have shape"):
        HierarchicalLocator().fit(X, xy[:, :1], f, b)
