"""RSSI validation, representations and radio-map averaging."""

import numpy as np
import pytest

from ilocalg.wifi import KnnFingerprint, SimplifiedHorus, SimplifiedRadar, check_rssi, fill_not_heard, to_features
from ilocalg.wifi.preprocessing import mean_fingerprints


def test_representations():
    x = np.array([[-104.0, np.nan, -30.0, 0.0]])
    pos = to_features(x, -104, "positive", dtype=np.float64)
    np.testing.assert_array_equal(pos, [[0, 0, 74, 104]])
    ex = to_features(x, -104, "exponential", dtype=np.float64)
    assert ex[0, 0] == 0 and ex[0, 1] == 0 and ex[0, 3] == pytest.approx(np.exp(104 / 24) / np.exp(104 / 24))
    pw = to_features(x, -104, "powed", dtype=np.float64)
    np.testing.assert_allclose(pw, [[0, 0, (74 / 104) ** np.e, 1.0]])
    # positive is distance-equivalent to filling NaN with the floor
    np.testing.assert_array_equal(pos + (-104), fill_not_heard(x, -104))


@pytest.mark.parametrize("representation", ["exponential", "powed"])
def test_representations_equal_the_dense_formula(representation):
    # computed on the heard readings only: the same bytes as the formula over the whole matrix
    rng = np.random.default_rng(0)
    x = np.round(rng.uniform(-104, 0, (200, 60)))
    x[rng.random(x.shape) < 0.8] = np.nan
    pos = np.nan_to_num(x + 104.0, nan=0.0)
    dense = (np.where(pos == 0, 0.0, np.exp(pos / 24.0) / np.exp(104.0 / 24.0)) if representation == "exponential"
             else (pos / 104.0) ** np.e)
    for dtype in (np.float32, np.float64):
        f = to_features(x, -104.0, representation, dtype=dtype)
        assert f.dtype == dtype and f.flags.c_contiguous
        np.testing.assert_array_equal(f, dense.astype(dtype))


@pytest.mark.parametrize("representation", ["positive", "exponential", "powed"])
def test_checked_features_equal_the_dense_formula_in_any_layout(representation):
    # checked_features (the estimators' path after check_rssi) maps only the readings above the floor: the same bytes
    # as the formula over the whole matrix, for non-integer readings, readings exactly at the floor (0) and a
    # column-major matrix (a column selection of the training set), always C-contiguous
    from ilocalg.wifi.preprocessing import checked_features

    rng = np.random.default_rng(1)
    x = rng.uniform(-104, -20, (150, 40))
    x[rng.random(x.shape) < 0.7] = np.nan
    x[rng.random(x.shape) < 0.05] = -104.0
    pos = np.nan_to_num(x + 104.0, nan=0.0)
    dense = {"positive": pos, "exponential": np.where(pos == 0, 0.0, np.exp(pos / 24.0) / np.exp(104.0 / 24.0)),
             "powed": (pos / 104.0) ** np.e}[representation]
    for xx in (x, np.asfortranarray(x)):
        for dtype in (np.float32, np.float64):
            for f in (checked_features(check_rssi(xx), -104.0, representation, dtype=dtype),
                      to_features(xx, -104.0, representation, dtype=dtype)):
                assert f.dtype == dtype and f.flags.c_contiguous
                np.testing.assert_array_equal(f, dense.astype(dtype))
    with pytest.raises(ValueError, match="row 2, column 1 has -105.0 dBm, weaker than not_heard_dbm"):
        checked_features(check_rssi(np.where(np.arange(12).reshape(4, 3) == 7, -105.0, -50.0)), -104.0)


def test_check_rssi_names_the_first_infinite_or_out_of_range_reading():
    # the range is checked by the smallest and largest reading first; a failure still names the first offender
    x = np.full((3, 4), -60.0)
    x[0, 0] = np.nan
    x[2, 1], x[1, 3] = -130.0, 5.0
    with pytest.raises(ValueError, match=r"row 1, column 3: RSSI 5 dBm is outside \[-120, 0\] dBm \(2 such"):
        check_rssi(x, valid_dbm=(-120.0, 0.0))
    x[2, 2] = -np.inf
    with pytest.raises(ValueError, match="infinite at row 2, column 2"):
        check_rssi(x)
    assert check_rssi(np.full((2, 2), np.nan), valid_dbm=(-120.0, 0.0)).shape == (2, 2)  # nothing heard: no range


def test_bad_input_messages():
    with pytest.raises(ValueError, match="2-D"):
        check_rssi(np.zeros(3))
    with pytest.raises(ValueError, match="0 sample"):
        check_rssi(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="row 1 hears no access point"):
        check_rssi(np.array([[-50.0], [np.nan]]), allow_empty_rows=False)
    with pytest.raises(ValueError, match="representation"):
        to_features(np.zeros((1, 1)) - 50, -100, "log")
    with pytest.raises(ValueError, match="weaker than not_heard_dbm"):
        to_features(np.array([[-101.0]]), -100)


def test_mean_fingerprints():
    X = np.array([[-50, np.nan], [-52, -70], [-60, np.nan], [-62, np.nan]], dtype=float)
    y = np.array([[1, 1], [1, 1], [0, 0], [0, 0]], dtype=float)
    fp, pts, point = mean_fingerprints(X, y, min_heard_fraction=0.5)
    np.testing.assert_array_equal(pts, [[1, 1], [0, 0]])
    np.testing.assert_array_equal(point, [0, 0, 1, 1])
    np.testing.assert_array_equal(fp[:, 0], [-51, -61])
    assert fp[0, 1] == -70 and np.isnan(fp[1, 1])
    fp2, _, _ = mean_fingerprints(X, y, min_heard_fraction=0.6)
    assert np.isnan(fp2[0, 1])  # heard in 1 of 2 scans < 60 %


def test_every_estimator_gives_nan_for_a_scan_sharing_no_ap():
    """A query hearing only APs never heard in training: NaN position (and labels), never the references
    with the weakest fingerprints; a training set hearing no AP is refused at fit."""
    from ilocalg.wifi import HierarchicalLocator, KnnFingerprint, SimplifiedHorus, SimplifiedRadar, locate_flat
    from ilocalg.wifi.preprocessing import shares_no_ap

    rng = np.random.default_rng(3)
    xy = rng.uniform(0, 20, (40, 2))
    X = np.column_stack([-50 - 2 * xy[:, 0], -50 - 2 * xy[:, 1], -90 + xy[:, 0], np.full(40, np.nan)])
    X = np.round(X + rng.normal(0, 1, X.shape))
    X[:, 3] = np.nan                                    # AP 3: never heard in training
    q = np.array([[-60.0, -70.0, -85.0, np.nan], [np.nan, np.nan, np.nan, -45.0], [np.nan] * 4])
    floor = np.repeat([0, 1], 20)
    assert shares_no_ap(q, ~np.isnan(X).all(axis=0)).tolist() == [False, True, True]
    for est in (KnnFingerprint(3, not_heard_dbm=-110), SimplifiedRadar(3, 3, -110), SimplifiedHorus(3)):
        p = est.fit(X, xy).predict(q)
        assert np.isfinite(p[0]).all() and np.isnan(p[1:]).all(), type(est).__name__
        df = locate_flat(est, q, floor, floor)
        assert df.iloc[1:].isna().all().all() and df.iloc[0].notna().all()
        with pytest.raises(ValueError, match="training set hears no access point"):
            type(est)().fit(np.full((5, 4), np.nan), xy[:5])
    h = HierarchicalLocator(KnnFingerprint(3, not_heard_dbm=-110)).fit(X, xy, floor, np.zeros(40, dtype=int))
    df = h.predict(q)
    assert df.iloc[1:].isna().all().all() and df.iloc[0].notna().all()
    assert h.predict(q[:1])["floor"].dtype.kind == "i"      # all located: labels keep their integer type


@pytest.mark.parametrize("make", [lambda: KnnFingerprint(n_neighbors=1), lambda: SimplifiedRadar(n_neighbors=1),
                                  lambda: SimplifiedHorus()])
def test_estimators_refuse_rssi_outside_physics_by_default(make):
    X = np.array([[-50.0, -70.0], [-60.0, np.nan], [-80.0, -40.0]])
    y = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    est = make().fit(X, y)
    with pytest.raises(ValueError, match=r"X row 1, column 0: RSSI 50 dBm is outside \[-110, 0\] dBm"):
        est.predict(np.array([[-50.0, -60.0], [50.0, -60.0]]))
    with pytest.raises(ValueError, match="rssi_range_dbm=None"):
        make().fit(np.vstack([X, [[-50.0, 20.0]]]), np.vstack([y, [[3.0, 0.0]]]))
    # the opt-out accepts any finite value
    est = make().set_params(rssi_range_dbm=None).fit(X + 200.0, y)
    assert np.isfinite(est.predict(X[:1] + 200.0)).all()


def _mean_fingerprints_reference(X, y, min_heard_fraction):
    """The radio map by np.unique(axis=0) and np.add.at (the earlier implementation)."""
    x = np.asarray(X, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64).reshape(x.shape[0], -1)
    _, first, inv = np.unique(y, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    point = rank[inv.ravel()]
    cnt = np.zeros((order.size, x.shape[1]))
    tot = np.zeros((order.size, x.shape[1]))
    np.add.at(cnt, point, (~np.isnan(x)).astype(np.float64))
    np.add.at(tot, point, np.nan_to_num(x, nan=0.0))
    n_scans = np.bincount(point, minlength=order.size)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        fp = tot / cnt
    fp[(cnt == 0) | (cnt < min_heard_fraction * n_scans)] = np.nan
    return fp, y[first[order]], point


@pytest.mark.parametrize("d", [1, 2, 3])
def test_mean_fingerprints_bits_equal_unique_and_add_at(d):
    rng = np.random.default_rng(d)
    X = rng.normal(-70.0, 10.0, (400, 7))  # not integers: the order of the additions shows in the last bits
    X[rng.random(X.shape) < 0.4] = np.nan
    y = rng.integers(0, 4, (400, d)).astype(np.float64)
    y[3] = np.nan  # a NaN position is a point of its own (np.unique's grouping)
    y[5] = np.nan
    y[9, 0], y[10, 0] = -0.0, 0.0  # -0.0 and 0.0 are one position
    y[10, 1:] = y[9, 1:]
    for frac in (0.0, 0.5, 1.0):
        got, want = mean_fingerprints(X, y, frac), _mean_fingerprints_reference(X, y, frac)
        for a, b in zip(got, want, strict=True):
            assert a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_strongest_ap_mask_is_a_stable_argsorts_first_k():
    """The argmax passes (k <= 8) and the argsort (above, or an infinite reading) give the first k of a stable sort by
    strength: ties by column, fewer when fewer are heard."""
    from ilocalg.wifi.preprocessing import strongest_ap_mask

    rng = np.random.default_rng(3)
    X = np.round(rng.uniform(-100, -30, (300, 12)))  # integer dBm: many ties
    X[rng.random(X.shape) < 0.5] = np.nan
    X[0] = np.nan
    X[1] = -50.0
    X[2, :3] = [0.0, -0.0, 0.0]
    X_inf = X.copy()
    X_inf[3, 4] = -np.inf
    for x in (X, X_inf, X[:, :1]):
        key = np.where(np.isnan(x), -np.inf, x)
        for k in (1, 2, 5, 8, 9, 12, 40):
            want = np.zeros(x.shape, dtype=bool)
            np.put_along_axis(want, np.argsort(-key, axis=1, kind="stable")[:, :k], True, axis=1)
            np.testing.assert_array_equal(strongest_ap_mask(x, k), want & ~np.isnan(x))


def test_rank_representation_agrees_with_scipy_rankdata_per_scan():
    from scipy.stats import rankdata

    from ilocalg.wifi.preprocessing import to_features

    rng = np.random.default_rng(4)
    x = np.where(rng.random((300, 40)) < 0.3, np.round(rng.normal(-75, 12, (300, 40))).clip(-104, -20), np.nan)
    x[5] = np.nan                                   # a scan hearing nothing
    x[6, :3] = -104.0                               # readings at the floor are not heard
    f = to_features(x, -104.0, "rank", dtype=np.float64)
    for i in range(x.shape[0]):
        heard = x[i] > -104.0
        want = np.zeros(x.shape[1])
        if heard.any():
            want[heard] = rankdata(x[i, heard], method="average") / heard.sum()    # ties (whole dB) averaged
        np.testing.assert_allclose(f[i], want, rtol=0, atol=1e-12)
    assert (f[5] == 0).all() and (f[6, :3] == 0).all()
    busy = (x > -104).any(axis=1)
    assert f.max() <= 1.0 and (f[busy].max(axis=1) > 0.5).all()  # the strongest AP of a scan: 1 unless tied


def test_rank_member_is_blind_to_a_phones_offset_and_gain():
    from ilocalg.wifi.candidates import rank_member

    rng = np.random.default_rng(5)
    x = np.where(rng.random((80, 12)) < 0.5, rng.normal(-70, 10, (80, 12)).clip(-100, -30), np.nan)
    y = np.column_stack([rng.uniform(0, 40, 80), rng.uniform(0, 40, 80), rng.integers(0, 3, 80), np.zeros(80)])
    name, est = rank_member(4.0)
    assert name == "rank_sorensen_w4" and rank_member(1.0)[0] == "rank_sorensen"
    est.fit(x, y)
    q = x[:20]
    np.testing.assert_allclose(est.predict(0.9 * q - 5.0), est.predict(q), rtol=0, atol=1e-9)   # -100..-30 stays heard
