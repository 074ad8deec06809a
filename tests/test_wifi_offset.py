"""OffsetFingerprint: WKNN with a per-query device offset search."""

import numpy as np
import pytest

from ilocalg.wifi import KnnFingerprint, OffsetFingerprint, build_index, offset_search, to_features


def _radio_map(rng, n_side=12, n_aps=15, spacing_m=2.0):
    """Log-distance path loss on a grid: positions (n, 2), RSSI (n, n_aps) dBm, NaN below -95 dBm."""
    g = np.arange(n_side) * spacing_m
    xy = np.array([(x, y) for x in g for y in g])
    ap = rng.uniform(0, g[-1], (n_aps, 2))
    d = np.maximum(np.hypot(xy[:, None, 0] - ap[None, :, 0], xy[:, None, 1] - ap[None, :, 1]), 1.0)
    rssi = -35.0 - 30.0 * np.log10(d)
    return xy, ap, rssi


def _noisy(rssi, rng, sd_db=2.0, offset_db=0.0):
    x = np.round(rssi + offset_db + rng.normal(0, sd_db, rssi.shape))
    x[x < -95] = np.nan
    return np.clip(x, -104, 0)


def test_plain_search_equals_the_knn_estimator():
    rng = np.random.default_rng(0)
    xy, _, rssi = _radio_map(rng)
    x = _noisy(rssi, rng)
    q = _noisy(rssi[::7], rng)
    for rep, metric in (("powed", "sorensen"), ("positive", "minkowski")):
        a = OffsetFingerprint(n_neighbors=4, shifts_db=(0.0,), representation=rep, metric=metric).fit(x, xy)
        b = KnnFingerprint(n_neighbors=4, p=2, weights="distance", representation=rep, metric=metric).fit(x, xy)
        np.testing.assert_allclose(a.predict(q), b.predict(q), rtol=0, atol=1e-9)


def test_search_recovers_a_phone_offset_and_cuts_the_error():
    rng = np.random.default_rng(1)
    xy, _, rssi = _radio_map(rng)
    x = _noisy(rssi, rng, sd_db=1.0)
    true_xy = xy[::3] + 1.0                                   # between grid points
    _, ap, _ = _radio_map(np.random.default_rng(1))
    d = np.maximum(np.hypot(true_xy[:, None, 0] - ap[None, :, 0], true_xy[:, None, 1] - ap[None, :, 1]), 1.0)
    q = _noisy(-35.0 - 30.0 * np.log10(d), rng, sd_db=1.0, offset_db=-6.0)   # a phone reading 6 dB low
    shifts = tuple(float(s) for s in range(-8, 9, 2))
    idx = build_index(to_features(x, -104.0, "powed"))
    _, _, s = offset_search(q, idx, 4, shifts)
    assert np.median(s) == pytest.approx(6.0, abs=2.0)        # the search undoes most of the offset
    plain = OffsetFingerprint(n_neighbors=4, shifts_db=(0.0,)).fit(x, xy).predict(q)
    found = OffsetFingerprint(n_neighbors=4, shifts_db=shifts).fit(x, xy).predict(q)
    e_plain = np.hypot(*(plain - true_xy).T).mean()
    e_found = np.hypot(*(found - true_xy).T).mean()
    assert e_found < 0.8 * e_plain


def test_target_with_labels_and_no_shared_ap():
    rng = np.random.default_rng(2)
    xy, _, rssi = _radio_map(rng)
    x = _noisy(rssi, rng)
    floor = (xy[:, 0] > 10).astype(float)
    y = np.column_stack([xy, floor, np.zeros(len(xy))])
    est = OffsetFingerprint(n_neighbors=3).fit(x, y)
    q = x[:5].copy()
    q[0] = np.nan                                              # hears nothing
    p = est.predict(q)
    assert p.shape == (5, 4) and np.isnan(p[0]).all()
    np.testing.assert_array_equal(p[1:, 2], floor[1:5])
    with pytest.raises(ValueError, match="shifts_db"):
        OffsetFingerprint(shifts_db=()).fit(x, y)
    with pytest.raises(ValueError, match="whole numbers"):
        OffsetFingerprint().fit(x, y + [0, 0, 0.5, 0])


def test_weight_power_is_the_exponent_of_the_inverse_distance_weights():
    from ilocalg.wifi import knn_predict, neighbour_weights, vote

    rng = np.random.default_rng(3)
    xy, _, rssi = _radio_map(rng)
    x = _noisy(rssi, rng)
    y = np.column_stack([xy, (xy[:, 0] > 10).astype(float), np.zeros(len(xy))])
    q = _noisy(rssi[::5], rng, offset_db=-3.0)
    shifts = (-4.0, -2.0, 0.0, 2.0, 4.0)
    base = OffsetFingerprint(n_neighbors=6, shifts_db=shifts)
    np.testing.assert_array_equal(base.fit(x, y).predict(q), base.set_params(weight_power=1.0).fit(x, y).predict(q))
    d, i, _ = offset_search(q, build_index(to_features(x, -104.0, "powed")), 6, shifts)
    w = neighbour_weights(d, "distance", 3.0)
    by_hand = np.column_stack([knn_predict(y[:, :2], i, w), vote(y[:, 2][i], w), vote(y[:, 3][i], w)])
    np.testing.assert_allclose(OffsetFingerprint(n_neighbors=6, shifts_db=shifts, weight_power=3.0).fit(x, y)
                               .predict(q), by_hand, rtol=0, atol=1e-12)
    # several exponents from one search: the same values as one estimator per exponent
    many = OffsetFingerprint(n_neighbors=6, shifts_db=shifts).fit(x, y).predict_weight_powers(q, (1.0, 3.0))
    np.testing.assert_array_equal(many[0], base.predict(q))
    np.testing.assert_allclose(many[1], by_hand, rtol=0, atol=1e-12)
    for bad in (0.0, -1.0, np.inf, "2"):
        with pytest.raises(ValueError, match="weight_power must be a finite number > 0"):
            OffsetFingerprint(weight_power=bad).fit(x, y)


def test_check_estimator():
    from sklearn.utils.estimator_checks import check_estimator

    from tests.test_wifi_knn import EXPECTED_FAILED

    for kw in (dict(representation="positive", metric="minkowski"), dict(representation="powed", metric="sorensen"),
               dict(representation="rank", metric="sorensen")):
        check_estimator(OffsetFingerprint(n_neighbors=3, shifts_db=(-1.0, 0.0, 1.0), not_heard_dbm=-100.0,
                                          rssi_range_dbm=None, **kw), expected_failed_checks=EXPECTED_FAILED)


def test_device_shift_choice_pools_a_phones_scans_so_far_in_time_order():
    from ilocalg.wifi import device_shift_choice

    # criterion per query (rows) and shift (columns); two phones, times out of row order
    c = np.array([[1.0, 3.0, 9.0],   # phone a, t=2: own best 0; pooled with a's t=1 row: 4, 3, 14 -> shift 1
                  [3.0, 0.0, 5.0],   # phone a, t=1: first of a -> its own best, 1
                  [0.0, 9.0, 9.0],   # phone b, t=0: its own best, 0 (b never sees a's rows)
                  [5.0, 1.0, 0.5],   # phone a, t=3: pooled 9, 4, 14.5 -> 1
                  [9.0, 9.0, 1.0]])  # phone b, t=0, later row: pooled 9, 18, 10 -> 0 (ties in time: row order)
    got = device_shift_choice(c, ["a", "a", "b", "a", "b"], [2, 1, 0, 3, 0])
    np.testing.assert_array_equal(got, [1, 1, 0, 1, 0])
    np.testing.assert_array_equal(device_shift_choice(c, np.arange(5), np.zeros(5)), c.argmin(axis=1))
    with pytest.raises(ValueError, match="one entry per query"):
        device_shift_choice(c, ["a"], [0])
    with pytest.raises(ValueError, match="finite"):
        device_shift_choice(c, np.arange(5), [0, 1, np.nan, 2, 3])


def test_device_calibration_finds_a_phones_offset_from_its_scans():
    rng = np.random.default_rng(1)
    xy, ap, rssi = _radio_map(rng)
    x = _noisy(rssi, rng, sd_db=1.0)
    true_xy = xy[::3] + 1.0
    d = np.maximum(np.hypot(true_xy[:, None, 0] - ap[None, :, 0], true_xy[:, None, 1] - ap[None, :, 1]), 1.0)
    q = _noisy(-35.0 - 30.0 * np.log10(d), rng, sd_db=4.0, offset_db=-6.0)   # noisy scans of one phone, 6 dB low
    shifts = tuple(float(s) for s in range(-8, 9, 2))
    idx = build_index(to_features(x, -104.0, "powed"))
    n = len(q)
    _, _, s_query = offset_search(q, idx, 4, shifts)
    _, _, s_dev = offset_search(q, idx, 4, shifts, devices=np.zeros(n), times=np.arange(n))
    assert s_dev[0] == s_query[0]                                  # the first scan: its own search
    assert np.abs(s_dev[n // 2:] - 6.0).mean() < np.abs(s_query[n // 2:] - 6.0).mean()  # pooled: nearer the truth
    assert np.all(s_dev[n // 2:] == s_dev[-1])                     # and settled
    est = OffsetFingerprint(n_neighbors=4, shifts_db=shifts, device_calibration=True).fit(x, xy)
    with pytest.raises(ValueError, match="devices= and times="):
        est.predict(q)
    with pytest.raises(ValueError, match="one entry per row"):
        est.predict(q, devices=np.zeros(3), times=np.arange(3))
    each_own = est.predict(q, devices=np.arange(n), times=np.zeros(n))   # every scan its own phone: per-query search
    np.testing.assert_array_equal(each_own, OffsetFingerprint(n_neighbors=4, shifts_db=shifts).fit(x, xy).predict(q))
    e_dev = np.hypot(*(est.predict(q, devices=np.zeros(n), times=np.arange(n)) - true_xy).T).mean()
    assert e_dev < np.hypot(*(each_own - true_xy).T).mean()


def test_device_calibration_goes_through_spots_and_ensembles():
    from ilocalg.wifi import FingerprintEnsemble, SpotAveragedFingerprint
    from ilocalg.wifi.ensemble import wants_devices
    from ilocalg.wifi.model_selection import with_device_calibration

    rng = np.random.default_rng(3)
    xy, _, rssi = _radio_map(rng)
    x = np.vstack([_noisy(rssi, rng), _noisy(rssi, rng)])
    y = np.vstack([xy, xy])
    q = _noisy(rssi[::5], rng, offset_db=4.0)
    members = [("off", OffsetFingerprint(n_neighbors=3, shifts_db=(-4.0, 0.0, 4.0))),
               ("spots", SpotAveragedFingerprint(OffsetFingerprint(n_neighbors=1, shifts_db=(-4.0, 0.0, 4.0))))]
    dev = with_device_calibration(members)
    assert [n for n, _ in dev] == ["off_dev", "spots_dev"] and all(wants_devices(e) for _, e in dev)
    assert not any(wants_devices(e) for _, e in members)
    meta = {"devices": np.zeros(len(q)), "times": np.arange(len(q))}
    ens = FingerprintEnsemble(dev).fit(x, y)
    got = ens.predict(q, **meta)
    one = [e.predict(q, **meta) for e in ens.estimators_]
    np.testing.assert_allclose(got, np.mean(one, axis=0))
    with pytest.raises(ValueError, match="devices="):
        ens.predict(q)
