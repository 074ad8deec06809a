"""Simplified-RADAR: eq. (1) against a direct loop, k reduction, weights, class vs function, bad input."""

import numpy as np
import pytest

from ilocalg.sim import iloc_floor
from ilocalg.wifi import SimplifiedRadar, radar_predict, strongest_ap_mask, union_topk_sq_distances
from ilocalg.wifi.preprocessing import mean_fingerprints


def _direct(q, r, k, nh):
    """eq. (1) squared, written literally for one pair."""
    def topk(s):
        heard = np.flatnonzero(~np.isnan(s))
        order = heard[np.argsort(-s[heard], kind="stable")]
        return set(order[:k].tolist())
    u = topk(q) | topk(r)
    qq, rr = np.nan_to_num(q, nan=nh), np.nan_to_num(r, nan=nh)
    return sum((qq[i] - rr[i]) ** 2 for i in u)


def test_union_distance_matches_definition():
    rng = np.random.default_rng(0)
    X = np.round(rng.uniform(-95, -40, (30, 12)))
    X[rng.random(X.shape) < 0.4] = np.nan
    X[0, :] = np.nan
    X[0, 3] = -50.0  # a scan with a single AP: k decreases to 1
    Q = X[:7] + 0.0
    for k in (1, 3, 5):
        d2 = union_topk_sq_distances(Q, X, k, -100.0)
        ref = np.array([[_direct(q, r, k, -100.0) for r in X] for q in Q])
        np.testing.assert_allclose(d2, ref, rtol=1e-6, atol=1e-3)


def test_strongest_mask_reduces_k():
    X = np.array([[-50.0, np.nan, -70.0, np.nan], [-40.0, -41.0, -42.0, -43.0]])
    m = strongest_ap_mask(X, 3)
    np.testing.assert_array_equal(m, [[True, False, True, False], [True, True, True, False]])


def test_weights_are_inverse_square_and_exact_match_wins():
    X = np.array([[-50.0, -60.0], [-52.0, -60.0], [-56.0, -60.0], [-80.0, -90.0]])
    y = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [30.0, 0.0]])
    q = np.array([[-51.0, -60.0]])
    est = SimplifiedRadar(k_aps=2, n_neighbors=3, not_heard_dbm=-100).fit(X, y)
    w = np.array([1 / 1.0, 1 / 1.0, 1 / 25.0])
    np.testing.assert_allclose(est.predict(q)[0], (w / w.sum()) @ y[:3])
    np.testing.assert_allclose(est.predict(X[2:3])[0], y[2])  # distance 0 -> that reference only


def test_class_and_function_agree():
    rng = np.random.default_rng(1)
    X = np.round(rng.uniform(-95, -40, (50, 10)))
    y = rng.uniform(0, 30, (50, 2))
    Q = X[:9] + rng.normal(0, 2, (9, 10))
    a = SimplifiedRadar(4, 3, -100).fit(X, y).predict(Q)
    b = radar_predict(Q, X, y, 4, 3, -100)
    np.testing.assert_allclose(a, b)


# the survey's own conditions at test time: no drift, no body or device difference
SAME_AS_SURVEY = {"drift_sd_db": 0.0, "body_loss_db": 0.0, "device_offset_db": 0.0}


def test_accuracy_on_simulated_floor():
    sim = iloc_floor.simulate(0, scans_per_point=40, scans_per_test_point=3, **SAME_AS_SURVEY)
    fp, pts, _ = mean_fingerprints(sim.train.rssi_dbm, sim.train.xy_m)
    xy = SimplifiedRadar(5, 3, sim.detect_dbm).fit(fp, pts).predict(sim.test.rssi_dbm)
    e = np.hypot(*(xy - sim.test.xy_m).T)
    assert np.median(e) < 3.0
    # more APs help: k = 1 is clearly worse than k = 5 (Fig 3's trend)
    e1 = np.hypot(*(SimplifiedRadar(1, 3, sim.detect_dbm).fit(fp, pts).predict(sim.test.rssi_dbm) - sim.test.xy_m).T)
    assert e1.mean() > 1.5 * e.mean()


def test_bad_input():
    X = np.array([[-50.0, -60.0], [-52.0, np.nan], [-56.0, -60.0]])
    y = np.arange(6.0).reshape(3, 2)
    est = SimplifiedRadar(2, 2, -100).fit(X, y)
    with pytest.raises(ValueError, match="row 0 hears no access point"):
        est.kneighbors(np.array([[np.nan, np.nan]]))
    assert np.isnan(est.predict(np.array([[np.nan, np.nan]]))).all()      # the documented no-AP result
    with pytest.raises(ValueError, match="features"):
        est.predict(np.array([[-50.0, -60.0, -70.0]]))
    with pytest.raises(ValueError, match="k_aps"):
        SimplifiedRadar(0).fit(X, y)
    with pytest.raises(ValueError, match="n_neighbors"):
        SimplifiedRadar(2, 5).fit(X, y)


def test_check_estimator():
    from sklearn.utils.estimator_checks import check_estimator

    from tests.test_wifi_knn import EXPECTED_FAILED

    check_estimator(SimplifiedRadar(k_aps=3, n_neighbors=3, not_heard_dbm=-100, point_distance=None,
                                    rssi_range_dbm=None),
                    expected_failed_checks=EXPECTED_FAILED)
    # point_distance="min" (the default) needs n_neighbors distinct positions, which check_estimator's
    # random targets do not guarantee; test_every_stored_scan_database_keeps_n_distinct_points covers it


def test_every_stored_scan_database_keeps_n_distinct_points():
    """Thesis L283, L287: the query is compared with every stored scan; the N nearest training points count."""
    rng = np.random.default_rng(0)
    pts = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [30.0, 0.0]])
    X = np.round(rng.normal(-60, 8, (40, 6)))
    y = np.repeat(pts, 10, axis=0)
    est = SimplifiedRadar(3, 3, -100).fit(X, y)
    dist, idx = est.kneighbors(X[:5])
    assert est.points_.shape == (4, 2)
    assert all(len({tuple(p) for p in y[r]}) == 3 for r in idx)  # three distinct points, never one twice
    # idx are reference rows: each the nearest stored scan of its point
    d_rows = np.sqrt(union_topk_sq_distances(X[:5], X, 3, -100))
    np.testing.assert_allclose(np.take_along_axis(d_rows, idx, axis=1), dist, rtol=1e-6)
    # a point's distance is the smallest over its stored scans
    d_all = np.sqrt(union_topk_sq_distances(X[:5], X, 3, -100)).reshape(5, 4, 10).min(axis=2)
    np.testing.assert_allclose(dist, np.sort(d_all, axis=1)[:, :3], rtol=1e-6)
    # with one row per point (a mean map) both readings agree
    fp = X.reshape(4, 10, 6).mean(axis=1).round()
    a = SimplifiedRadar(3, 3, -100).fit(fp, pts).predict(X[:5])
    b = SimplifiedRadar(3, 3, -100, point_distance=None).fit(fp, pts).predict(X[:5])
    np.testing.assert_allclose(a, b)
    with pytest.raises(ValueError, match="point_distance"):
        SimplifiedRadar(point_distance="mean").fit(X, y)


def test_neighbour_rows_are_each_points_first_nearest_scan():
    """With points of unequal scan counts listed out of order and repeated scans (ties), each neighbour's row is
    the first training row, in the order given, among its point's nearest stored scans."""
    rng = np.random.default_rng(4)
    pts = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [30.0, 0.0], [40.0, 0.0]])
    which = rng.permutation(np.repeat(np.arange(5), [3, 9, 1, 6, 4]))
    X = np.round(rng.normal(-60, 6, (which.size, 7)))
    twin = np.flatnonzero(which == 1)[:2]
    X[twin[1]] = X[twin[0]]  # the same scan twice at one point: a tie, broken by the earlier row
    y = pts[which]
    q = np.vstack([X[twin[0]], np.round(rng.normal(-60, 6, (6, 7)))])
    dist, idx = SimplifiedRadar(3, 4, -100).fit(X, y).kneighbors(q)
    d = np.sqrt(union_topk_sq_distances(q, X, 3, -100))
    for i in range(q.shape[0]):
        for j in range(idx.shape[1]):
            rows = np.flatnonzero(which == which[idx[i, j]])
            assert idx[i, j] == rows[np.argmin(d[i, rows])]
            assert dist[i, j] == pytest.approx(d[i, rows].min())


@pytest.mark.parametrize("not_heard_dbm", [-100.0, -93.76])  # integer features (float32 path) / float64 path
def test_reference_factor_stacked_once_gives_the_same_bits(monkeypatch, not_heard_dbm):
    from ilocalg.wifi import radar

    rng = np.random.default_rng(11)
    n_ref = radar._REF_CHUNK + 700  # two slabs of references
    X = np.round(rng.uniform(-93, -40, (n_ref, 9)))
    X[rng.random(X.shape) < 0.3] = np.nan
    X[np.all(np.isnan(X), axis=1), 0] = -60.0
    y = np.repeat(rng.uniform(0, 40, (n_ref // 5 + 1, 2)), 5, axis=0)[:n_ref]  # 5 scans per point
    Q = X[rng.choice(n_ref, 40, replace=False)] + np.round(rng.normal(0, 3, (40, 9)))
    Q = np.clip(Q, -93, -30)
    cached = SimplifiedRadar(5, 3, not_heard_dbm).fit(X, y)
    monkeypatch.setattr(radar, "_STACK_CACHE_BYTES", 0)
    stacked = SimplifiedRadar(5, 3, not_heard_dbm).fit(X, y)
    assert cached._refs.cached and not stacked._refs.cached
    for q in (Q, Q[:1], Q[17:18]):
        for a, b in zip(cached.kneighbors(q), stacked.kneighbors(q), strict=True):
            assert a.tobytes() == b.tobytes()
        assert cached.predict(q).tobytes() == stacked.predict(q).tobytes()


def test_clamp_after_the_point_minima_gives_the_bits_of_clamping_every_distance(monkeypatch):
    """kneighbors clamps a float64 product's negative roundings only when a point's minimum is below 0: the same
    distances, neighbours and positions as clamping the whole matrix (what _union_sq does by default)."""
    from ilocalg.wifi import radar
    from ilocalg.wifi.preprocessing import to_features

    rng = np.random.default_rng(5)
    X = np.round(rng.uniform(-90, -40, (40, 6))) + rng.choice([0.0, 0.3, 0.37], size=(40, 6))
    X[rng.random(X.shape) < 0.3] = np.nan
    X[np.isnan(X).all(axis=1), 0] = -50.0
    y = np.repeat(np.arange(10.0), 4)[:, None] * [1.0, 0.0]  # 10 points of 4 scans
    nh = -93.76  # features x - nh are not integers: the float64 product
    est = SimplifiedRadar(k_aps=3, n_neighbors=3, not_heard_dbm=nh).fit(X, y)
    raw = radar._union_sq(to_features(X, nh, dtype=np.float64), strongest_ap_mask(X, 3).astype(np.float64),
                          est._refs, clamp=False)
    assert (raw < 0).any()  # an exact match rounds below 0: the clamp path is exercised
    Q = np.vstack([X, X[:7] + 2.0])  # exact matches (rounding below 0) and queries without one
    got = est.kneighbors(Q), est.predict(Q)
    assert (got[0][0] >= 0).all() and (got[0][0][:40, 0] < 1e-5).all()  # each scan finds itself (0 within rounding)
    orig = radar._union_sq
    monkeypatch.setattr(radar, "_union_sq", lambda q, a, ref, clamp=True, **kw: orig(q, a, ref, clamp=True, **kw))
    want = est.kneighbors(Q), est.predict(Q)
    for a, b in zip((*got[0], got[1]), (*want[0], want[1]), strict=True):
        assert a.tobytes() == b.tobytes()


@pytest.mark.parametrize("point_distance", ["min", None])
@pytest.mark.parametrize("not_heard_dbm", [-100.0, -93.76])  # integer features (float32 path) / float64 path
def test_kept_distance_buffer_gives_the_bits_of_fresh_arrays(monkeypatch, point_distance, not_heard_dbm):
    """kneighbors writes each batch's distances into one kept buffer per thread: the same neighbours, distances and
    positions as fresh arrays, batches of several sizes one after another (the buffer reused and regrown), and two
    estimators in turn."""
    from ilocalg.wifi import radar

    rng = np.random.default_rng(3)
    X = np.round(rng.uniform(-93, -40, (300, 8))) + rng.choice([0.0, 0.25], size=(300, 8))
    X[rng.random(X.shape) < 0.3] = np.nan
    X[np.isnan(X).all(axis=1), 0] = -55.0
    y = np.repeat(rng.uniform(0, 30, (60, 2)), 5, axis=0)
    Q = np.clip(X[rng.choice(300, 50, replace=False)] + np.round(rng.normal(0, 3, (50, 8))), -93, -30)
    ests = [SimplifiedRadar(k, 3, not_heard_dbm, point_distance=point_distance).fit(X[:n], y[:n])
            for k, n in ((3, 300), (5, 200))]
    monkeypatch.setattr(radar, "_Q_BATCH", 7)  # 8 batches, the last of 1 query
    got = [(e.kneighbors(q), e.predict(q)) for q in (Q, Q[:3], Q) for e in ests]
    assert radar._scratch.buf.size >= 7 * 300 * 4
    monkeypatch.setattr(radar, "_SCRATCH_BYTES", 0)  # every batch into a fresh array
    want = [(e.kneighbors(q), e.predict(q)) for q in (Q, Q[:3], Q) for e in ests]
    for (g_nb, g_xy), (w_nb, w_xy) in zip(got, want, strict=True):
        for a, b in zip((*g_nb, g_xy), (*w_nb, w_xy), strict=True):
            assert a.tobytes() == b.tobytes()
