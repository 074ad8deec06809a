"""KNN / WKNN: agreement with scikit-learn, tie-breaking, kernels, estimator contract, bad input."""

import numpy as np
import pytest
from sklearn.neighbors import KNeighborsRegressor, NearestNeighbors

from ilocalg.wifi import KnnFingerprint, build_index, knn_search, to_features, vote
from ilocalg.wifi.knn import pairwise_distances_batch


def _radio(rng, n_ref=300, n_q=60, n_aps=25, integer=False):
    xy = rng.uniform(0, 50, (n_ref + n_q, 2))
    aps = rng.uniform(0, 50, (n_aps, 2))
    d = np.hypot(xy[:, None, 0] - aps[None, :, 0], xy[:, None, 1] - aps[None, :, 1])
    rssi = -40 - 30 * np.log10(np.maximum(d, 1)) + rng.normal(0, 3, d.shape)
    if integer:
        rssi = np.round(rssi)
    rssi[rssi < -90] = np.nan
    rssi = np.maximum(rssi, -90)  # values kept are >= the floor
    return rssi[:n_ref], xy[:n_ref], rssi[n_ref:], xy[n_ref:]


@pytest.mark.parametrize("p", [1, 2])
@pytest.mark.parametrize("weights", ["uniform", "distance"])
def test_agrees_with_sklearn(p, weights):
    rng = np.random.default_rng(1)
    X, y, Xq, _ = _radio(rng)
    ours = KnnFingerprint(n_neighbors=5, p=p, weights=weights, not_heard_dbm=-95).fit(X, y).predict(Xq)
    ref = KNeighborsRegressor(n_neighbors=5, p=p, weights=weights, algorithm="brute").fit(
        np.nan_to_num(X, nan=-95), y).predict(np.nan_to_num(Xq, nan=-95))
    np.testing.assert_allclose(ours, ref, rtol=1e-5, atol=1e-4)


@pytest.mark.parametrize("p", [1, 2])
def test_sparse_and_dense_kernels_agree_exactly_on_integer_dbm(p):
    rng = np.random.default_rng(2)
    X, _, Xq, _ = _radio(rng, integer=True)
    idx = build_index(to_features(X, -95))
    fq = to_features(Xq, -95)
    d1, i1 = knn_search(fq, idx, 7, p=p, kernel="sparse")
    d2, i2 = knn_search(fq, idx, 7, p=p, kernel="dense")
    np.testing.assert_array_equal(i1, i2)
    np.testing.assert_array_equal(d1, d2)
    full = pairwise_distances_batch(fq, idx, p=p, kernel="dense")
    nn = NearestNeighbors(n_neighbors=7, p=p, algorithm="brute").fit(np.nan_to_num(X, nan=-95))
    dref, _ = nn.kneighbors(np.nan_to_num(Xq, nan=-95))
    np.testing.assert_allclose(d1, dref, rtol=1e-6)
    np.testing.assert_allclose(np.sort(full, axis=1)[:, :7] ** (0.5 if p == 2 else 1), dref, rtol=1e-5)


def test_ties_broken_by_training_order():
    # five identical references: the first K in training order must be chosen, in order
    X = np.full((8, 3), -60.0)
    X[5:] = -80.0
    y = np.arange(16, dtype=float).reshape(8, 2)
    est = KnnFingerprint(n_neighbors=3, p=1).fit(X, y)
    _, idx = est.kneighbors(np.array([[-60.0, -60.0, -60.0]]))
    np.testing.assert_array_equal(idx[0], [0, 1, 2])
    # boundary tie: one closer reference at the end, then the earliest of the tied ones
    X2 = np.vstack([X, [[-61.0, -60.0, -60.0]]])
    X2[8] = [-60.0, -60.0, -60.0]
    y2 = np.vstack([y, [[99.0, 99.0]]])
    _, idx = KnnFingerprint(n_neighbors=2, p=2).fit(X2, y2).kneighbors(np.array([[-60.0, -60.0, -60.0]]))
    np.testing.assert_array_equal(idx[0], [0, 1])


def test_accuracy_bound_on_seeded_radio_map():
    rng = np.random.default_rng(3)
    X, y, Xq, yq = _radio(rng, n_ref=600, n_q=100)
    e = np.hypot(*(KnnFingerprint(5, p=1, not_heard_dbm=-95).fit(X, y).predict(Xq) - yq).T)
    assert np.median(e) < 5.0  # 50 m square, 25 APs, 3 dB noise
    e_rand = np.hypot(*(y[rng.integers(0, 600, 100)] - yq).T)
    assert np.mean(e) < 0.3 * np.mean(e_rand)


def test_sorensen_matches_scipy_braycurtis():
    from scipy.spatial.distance import cdist

    rng = np.random.default_rng(4)
    X, _, Xq, _ = _radio(rng)
    fx, fq = to_features(X, -95, "powed"), to_features(Xq, -95, "powed")
    d, i = knn_search(fq, build_index(fx), 4, metric="sorensen")
    ref = cdist(fq.astype(float), fx.astype(float), "braycurtis")
    np.testing.assert_allclose(d, np.sort(ref, axis=1)[:, :4], rtol=1e-4, atol=1e-6)


def test_vote_tie_rules():
    lab = np.array([[2, 1, 1, 2, 3], [0, 0, 1, 1, 1]])
    np.testing.assert_array_equal(vote(lab), [1, 1])
    np.testing.assert_array_equal(vote(lab, tie="nearest"), [2, 1])
    w = np.array([[5, 1, 1, 1, 1], [1, 1, 1, 1, 1]], float)
    np.testing.assert_array_equal(vote(lab, w), [2, 1])


def test_bad_input():
    rng = np.random.default_rng(5)
    X, y, Xq, _ = _radio(rng)
    est = KnnFingerprint(3).fit(X, y)
    with pytest.raises(ValueError, match="AP columns, the fitted database"):
        est.predict(Xq[:, :-1])
    bad = Xq.copy()
    bad[4] = np.nan
    with pytest.raises(ValueError, match="row 4 hears no access point"):
        est.kneighbors(bad)
    pred = est.predict(bad)                     # the documented no-AP result: NaN, the other rows unchanged
    assert np.isnan(pred[4]).all() and np.isfinite(np.delete(pred, 4, axis=0)).all()
    np.testing.assert_array_equal(np.delete(pred, 4, axis=0), est.predict(np.delete(Xq, 4, axis=0)))
    with pytest.raises(ValueError, match="weaker than not_heard_dbm"):
        KnnFingerprint(3, not_heard_dbm=-80).fit(X, y)
    with pytest.raises(ValueError, match="p must be 1"):
        KnnFingerprint(3, p=3).fit(X, y)
    with pytest.raises(ValueError, match="n_neighbors"):
        KnnFingerprint(1000).fit(X, y)
    with pytest.raises(ValueError, match="y must have shape"):
        KnnFingerprint(3).fit(X, y[:-1])
    inf = X.copy()
    inf[2, 3] = np.inf
    with pytest.raises(ValueError, match="infinite at row 2, column 3"):
        KnnFingerprint(3).fit(inf, y)


#: The toolkit raises ValueError for every bad input; scikit-learn expects numpy's TypeError here.
EXPECTED_FAILED = {"check_dtype_object": "object cells raise ValueError (toolkit convention), not TypeError"}


def test_check_estimator():
    from sklearn.utils.estimator_checks import check_estimator

    # random data from check_estimator may contain any float; use a low not-heard value
    check_estimator(KnnFingerprint(n_neighbors=3, not_heard_dbm=-1e4, rssi_range_dbm=None),
                    expected_failed_checks=EXPECTED_FAILED)


@pytest.mark.parametrize("p", [1, 2])
def test_kernels_agree_exactly_on_a_large_database_with_duplicates(p):
    # large enough for the threshold selection (n_refs >= 64 k) and the Euclidean GEMM route; duplicated
    # references make exact ties at and around the k-th neighbour
    rng = np.random.default_rng(5)
    X, _, Xq, _ = _radio(rng, n_ref=1500, n_q=300, integer=True)
    X = np.vstack([X, X[:700]])
    idx = build_index(to_features(X, -95))
    fq = to_features(np.vstack([Xq, X[:50]]), -95)
    d1, i1 = knn_search(fq, idx, 5, p=p, kernel="sparse", batch=64)
    d2, i2 = knn_search(fq, idx, 5, p=p, kernel="dense")
    np.testing.assert_array_equal(i1, i2)
    np.testing.assert_array_equal(d1, d2)
    full = pairwise_distances_batch(fq, idx, p=p, kernel="dense")
    ref = np.lexsort((np.broadcast_to(np.arange(full.shape[1]), full.shape), full), axis=1)[:, :5]
    np.testing.assert_array_equal(i1, ref)


def test_smallest_k_matches_a_stable_sort_with_many_ties():
    from ilocalg.wifi.knn import smallest_k

    rng = np.random.default_rng(6)
    for hi in (3, 50, 5000):
        d = rng.integers(0, hi, (40, 2000)).astype(np.float32)
        for k in (1, 5, 20):
            np.testing.assert_array_equal(smallest_k(d, k), np.argsort(d, axis=1, kind="stable")[:, :k])


def test_euclidean_product_over_shared_columns_only_is_exact():
    """The GEMM route drops the AP columns no query or no reference hears (exact zeros in q.r), while |q|^2 keeps
    every column, including readings of APs the database never heard: same neighbours and distances as the
    dense kernel and as a float64 stable sort."""
    from ilocalg.wifi.knn import _shared_columns

    rng = np.random.default_rng(7)
    X, _, Xq, _ = _radio(rng, n_ref=1500, n_q=100, n_aps=40, integer=True)
    X[:, 30:] = np.nan                      # APs 30-39 never heard in training
    Xq[:, :12] = np.nan                     # APs 0-11 never heard by the queries
    Xq[::3, 35] = -60.0                     # a reading of an AP the database never heard
    X = np.vstack([X, X[:300]])             # exact ties
    idx = build_index(to_features(X, -95))
    fq = to_features(Xq, -95)
    cols = _shared_columns(fq, idx)
    assert cols is not None and set(cols.tolist()) <= set(range(12, 30))
    d1, i1 = knn_search(fq, idx, 5, p=2, kernel="sparse")
    d2, i2 = knn_search(fq, idx, 5, p=2, kernel="dense")
    np.testing.assert_array_equal(i1, i2)
    np.testing.assert_array_equal(d1, d2)
    a, b = idx.features.astype(np.float64), fq.astype(np.float64)
    full = ((b[:, None, :] - a[None, :, :]) ** 2).sum(axis=2)
    ref = np.argsort(full, axis=1, kind="stable")[:, :5]
    np.testing.assert_array_equal(i1, ref)
    np.testing.assert_array_equal(d1, np.sqrt(np.take_along_axis(full, ref, axis=1)))


@pytest.mark.parametrize("representation", ["positive", "powed"])
@pytest.mark.parametrize("n_ref,k", [(1700, 5), (40, 5), (1700, 1)])
def test_manhattan_blocks_match_the_unpadded_partial_sums(monkeypatch, representation, n_ref, k):
    """The Manhattan search (query blocks padded to groups of 32 references, the neighbours picked from strided
    group minima; a tiny database falls back to whole rows) gives the bits of the unpadded float32 partial sums
    ranked by (value, training order), the query's own sum added after, for integer and non-integer features,
    with exact ties (duplicated references) and with the queries split over several blocks."""
    from ilocalg.wifi import knn

    rng = np.random.default_rng(8)
    X, _, Xq, _ = _radio(rng, n_ref=n_ref - n_ref // 3, n_q=90, integer=True)
    X = np.vstack([X, X[:n_ref // 3]])
    idx = build_index(to_features(X, -95, representation))
    fq = to_features(np.vstack([Xq, X[:20]]), -95, representation)
    monkeypatch.setattr(knn, "_BLOCK_VALUES", 37 * n_ref)  # blocks of about 37 queries
    d1, i1 = knn_search(fq, idx, k, p=1, kernel="sparse", batch=8)
    part = knn._sparse_partial(fq, idx, 1)
    ref = np.lexsort((np.broadcast_to(np.arange(n_ref), part.shape), part), axis=1)[:, :k]
    np.testing.assert_array_equal(i1, ref)
    own = np.array([row.sum() for row in fq], dtype=np.float32).astype(np.float64)
    want = np.maximum(np.take_along_axis(part, ref, axis=1).astype(np.float64) + own[:, None], 0.0)
    np.testing.assert_array_equal(d1, want)
    if representation == "positive":  # integers: exact, so also the dense kernel's distances
        d2, i2 = knn_search(fq, idx, k, p=1, kernel="dense")
        np.testing.assert_array_equal(i1, i2)
        np.testing.assert_array_equal(d1, d2)


@pytest.mark.parametrize("metric,p,rep,integer", [("sorensen", 1, "powed", False), ("minkowski", 1, "positive", True),
                                                  ("minkowski", 2, "positive", True), ("minkowski", 2, "exponential",
                                                                                       False)])
def test_shared_searches_return_the_same_bits(metric, p, rep, integer):
    from ilocalg.wifi.knn import shared_searches

    rng = np.random.default_rng(11)
    X, _, Xq, _ = _radio(rng, n_ref=400, n_q=70, integer=integer)
    fx, fq = to_features(X, -95, rep), to_features(Xq, -95, rep)
    plain = {k: knn_search(fq, build_index(fx), k, p=p, metric=metric) for k in (3, 5, 12, 20)}
    with shared_searches() as counts:
        shared = {}
        for k in (5, 3, 12, 20, 5, 3):  # a smaller k after a larger one: the stored search's first k
            idx = build_index(fx.copy())  # a new database of the same features: the stored one
            shared[k] = knn_search(fq.copy(), idx, k, p=p, metric=metric)
            for a, b in zip(shared[k], plain[k], strict=True):
                assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b)
        d, i = shared[5]
        d[:] = -1.0  # a caller's result is its own copy: the store is not changed
        again = knn_search(fq, idx, 5, p=p, metric=metric)
        assert np.array_equal(again[0], plain[5][0])
        other = knn_search(fq + np.float32(1.0), idx, 5, p=p, metric=metric)  # other queries: searched
    assert counts == {"hits": 5, "misses": 3}  # k = 5 (holds 12), k = 20, the shifted queries
    assert np.array_equal(other[1], knn_search(fq + np.float32(1.0), build_index(fx), 5, p=p, metric=metric)[1])
