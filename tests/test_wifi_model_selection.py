"""Model selection and scoring of fingerprint estimators (ilocalg.wifi.model_selection)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.io.schema import FingerprintSet
from ilocalg.measure.stats import bootstrap
from ilocalg.wifi import model_selection as ms


def test_selection_mask_is_half():
    assert np.isclose(ms.selection_mask(11).sum(), 5)


def test_offset_shifts_are_one_measured_sd():
    assert ms.offset_shifts_db() == (-4.0, -2.0, 0.0, 2.0, 4.0)   # +-1 sd of the measured offset


def test_uji_metrics_row_counts_unlocated_scans_apart():
    test = FingerprintSet(rssi_dbm=np.full((4, 1), -50.0), ap_ids=("a",), x_m=np.zeros(4),
                          y_m=np.full(4, 4.86e6), floor=np.array([0, 0, 1, 1]), building=np.zeros(4))
    res = {"error_m": np.array([1.0, 3.0, np.nan, 2.0]), "floor": np.array([0, 0, np.nan, 1]),
           "building": np.zeros(4)}
    row = ms.metrics_row(res, test)
    assert row["n"] == 4 and row["n_unlocated"] == 1
    assert row["mean_m"] == pytest.approx(2.0) and row["floor_hit_rate"] == pytest.approx(0.75)


def test_subsampled_group_kfold_keeps_groups_apart():
    groups = np.repeat(np.arange(6), 50)
    folds = list(ms.SubsampledGroupKFold(3, max_test=40, seed=1).split(np.zeros((300, 1)), groups=groups))
    assert len(folds) == 3
    for tr, te in folds:
        assert te.size == 40 and not set(groups[tr]) & set(groups[te])
        assert tr.size == 200                                           # training parts stay whole


def test_ladder_interval_agrees_with_the_clustered_bootstrap():
    # the ladder's vectorised interval draws the same resamples as measure.bootstrap value by value;
    # only the summation order differs
    e = np.random.default_rng(3).gamma(2.0, 3.0, 255)
    lo, hi = ms.bootstrap_mean_ci(e, 7)
    ci = bootstrap(e, np.mean, n_boot=1000, rng=7)
    np.testing.assert_allclose([lo, hi], [ci.ci_low, ci.ci_high], rtol=1e-12)
    assert lo < e.mean() < hi and ms.bootstrap_mean_ci(e, 7) == (lo, hi)
    assert ms.bootstrap_mean_ci(e, 8) != (lo, hi)


def test_toolkit_cv_needs_a_meta_group():
    s = FingerprintSet(rssi_dbm=np.full((4, 1), -50.0), ap_ids=("a",), x_m=np.zeros(4), y_m=np.zeros(4),
                       floor=np.zeros(4), building=np.zeros(4))
    with pytest.raises(ValueError, match="meta column"):
        ms.toolkit_cv(s)


def test_ensemble_cv_equals_grid_search_over_the_pipeline():
    # the ladder's shared-fit CV (each member fitted once per fold) against GridSearchCV over the Pipeline
    from tests.test_wifi_ensemble import _radio

    rng = np.random.default_rng(4)
    x, xy = _radio(rng, n=240)
    floor = (xy[:, 0] > 15).astype(int)
    train = FingerprintSet(rssi_dbm=x, ap_ids=tuple(f"a{i}" for i in range(x.shape[1])), x_m=xy[:, 0],
                           y_m=xy[:, 1], floor=floor, building=np.zeros(len(x), dtype=int),
                           meta=pd.DataFrame({"PHONEID": np.arange(len(x)) % 4}))
    grid = {"est__estimators": [ms.ensemble_members((-2.0, 0.0, 2.0), three=False),
                                ms.ensemble_members((-2.0, 0.0, 2.0), three=True)]}
    best, table = ms.ensemble_cv(train, grid, 4, seed=1, max_test=50)
    ref_best, ref = ms.toolkit_cv(train, seed=1, group="PHONEID", max_test=50, estimator=ms.ensemble_pipeline(4),
                                  grid=grid)
    assert [n for n, _ in best["est__estimators"]] == [n for n, _ in ref_best["est__estimators"]]
    np.testing.assert_array_equal(table["estimators"], ref["estimators"])
    np.testing.assert_allclose(table["cv_mean_error_m"], ref["cv_mean_error_m"], rtol=1e-12)
    np.testing.assert_allclose(table["cv_sd_m"], ref["cv_sd_m"], rtol=1e-9)
    np.testing.assert_array_equal(table["rank"], ref["rank"])


def test_offset_range_two_sd():
    assert ms.offset_shifts_db(2) == (-8.0, -6.0, -4.0, -2.0, 0.0, 2.0, 4.0, 6.0, 8.0)   # +-2 sd, 2 dB steps


@pytest.mark.parametrize("fast", [False, True])
def test_offset_range_grid_names_stand_for_one_configuration(fast):
    # ensemble_cv's cache is keyed by member name: one name, one configuration
    from sklearn.base import clone

    seen = {}
    cands = ms.offset_range_grid(fast)["est__estimators"]
    assert len(cands) == (2 if fast else 6)
    for members in cands:
        for name, est in members:
            p = {k: v for k, v in clone(est).get_params().items()}
            assert seen.setdefault(name, p) == p
    assert {seen["offset_powed_2sd"]["shifts_db"], seen["offset_powed"]["shifts_db"]} == {
        ms.offset_shifts_db(2), ms.offset_shifts_db(1)}


def test_ensemble_cv_cache_gives_the_same_table_and_reuses_fits():
    from tests.test_wifi_ensemble import _radio

    rng = np.random.default_rng(5)
    x, xy = _radio(rng, n=200)
    train = FingerprintSet(rssi_dbm=x, ap_ids=tuple(f"a{i}" for i in range(x.shape[1])), x_m=xy[:, 0],
                           y_m=xy[:, 1], floor=(xy[:, 0] > 15).astype(int), building=np.zeros(len(x), dtype=int),
                           meta=pd.DataFrame({"PHONEID": np.arange(len(x)) % 4}))
    grid = ms.offset_range_grid(fast=True)
    _, ref = ms.ensemble_cv(train, grid, 3, seed=2, max_test=40)
    cache: dict = {}
    ms.ensemble_cv(train, ms.ensemble_grid(fast=True), 3, seed=2, max_test=40, cache=cache)
    n_first = len(cache)
    _, table = ms.ensemble_cv(train, grid, 3, seed=2, max_test=40, cache=cache)
    pd.testing.assert_frame_equal(table, ref)
    # 3 folds x {offset_powed, cascade_powed} first, then only offset_exponential, the two 2-sd members are new
    assert n_first == 3 * 2 and len(cache) == 3 * 5


@pytest.mark.parametrize("fast", [False, True])
def test_spot_grid_crosses_exponents_and_spot_k(fast):
    from sklearn.base import clone

    from ilocalg.wifi.spots import SpotAveragedFingerprint

    base = ms.ensemble_members(ms.offset_shifts_db(2), three=True)          # offset powed, cascade, offset exponential
    cands = ms.spot_grid(base, fast)["est__estimators"]
    n_a, n_k = (1, 2) if fast else (len(ms.SPOT_WEIGHT_POWERS), len(ms.SPOT_NEIGHBORS))
    assert len(cands) == n_a * (1 + n_k)
    assert [n for n, _ in cands[0]] == [n for n, _ in base]                  # exponent 1, no spots: the base itself
    seen = {}
    for members in cands:
        powers = {e.get_params()["weight_power"] for _, e in members if "weight_power" in e.get_params()}
        powers |= {e.estimator.weight_power for _, e in members if isinstance(e, SpotAveragedFingerprint)}
        assert len(powers) == 1                                             # one exponent per candidate
        spots = [e for _, e in members if isinstance(e, SpotAveragedFingerprint)]
        assert len(spots) in (0, 2) and len({e.estimator.n_neighbors for e in spots}) <= 1
        assert "n_neighbors" not in (spots[0].get_params() if spots else {})   # the ensemble's K leaves them alone
        for name, est in members:                                           # one name, one configuration
            p = {k: v for k, v in clone(est).get_params(deep=True).items() if k != "estimator"}
            assert seen.setdefault(name, p) == p


def test_fit_members_shares_one_search_across_weight_exponents(monkeypatch):
    from ilocalg.wifi import CascadeFingerprint, OffsetFingerprint, SpotAveragedFingerprint, spots
    from tests.test_wifi_ensemble import _radio

    rng = np.random.default_rng(6)
    x, xy = _radio(rng, n=200)
    y = np.column_stack([xy, (xy[:, 0] > 15).astype(float), np.zeros(len(xy))])
    q = _radio(rng, n=30)[0]
    off = OffsetFingerprint(shifts_db=(-2.0, 0.0, 2.0))
    members = [("o1", off), ("o4", OffsetFingerprint(shifts_db=(-2.0, 0.0, 2.0), weight_power=4.0)),
               ("cas", CascadeFingerprint(metric="sorensen")),
               ("s2", SpotAveragedFingerprint(OffsetFingerprint(n_neighbors=1, weight_power=2.0))),
               ("s2k2", SpotAveragedFingerprint(OffsetFingerprint(n_neighbors=2))),
               ("s_half", SpotAveragedFingerprint(OffsetFingerprint(n_neighbors=1), min_heard_fraction=0.5))]
    got = ms.fit_members(members, x, y, q, 4)
    calls, averaged = [], []
    real = OffsetFingerprint.predict_weight_powers
    real_spots = spots.spot_fingerprints

    def counting(self, X, powers):
        calls.append(tuple(powers))
        return real(self, X, powers)

    def counting_spots(rssi, yy, frac=0.0):
        averaged.append(frac)
        return real_spots(rssi, yy, frac)

    monkeypatch.setattr(OffsetFingerprint, "predict_weight_powers", counting)
    monkeypatch.setattr(spots, "spot_fingerprints", counting_spots)
    ms.fit_members(members, x, y, q, 4)
    monkeypatch.undo()
    assert sorted(calls) == [(1.0,), (1.0,), (1.0, 4.0), (2.0,)]        # o1 and o4 share one search
    assert sorted(averaged) == [0.0, 0.5]                               # one averaging per heard fraction
    for name, est in members:
        alone = est.set_params(n_neighbors=4) if "n_neighbors" in est.get_params() else est
        np.testing.assert_array_equal(got[name], alone.fit(x, y).predict(q))


def _spot_train(seed=6, n_spots=40, per_spot=6, n_phones=5):
    """A survey shaped like UJIIndoorLoc's: several scans per reference spot, each spot by two phones."""
    from tests.test_wifi_ensemble import _radio

    rng = np.random.default_rng(seed)
    x, xy = _radio(rng, n=n_spots * per_spot)
    xy = np.repeat(xy[::per_spot], per_spot, axis=0)                     # per_spot scans share one position
    spot = np.repeat(np.arange(n_spots), per_spot)
    phone = (spot + np.tile(np.arange(per_spot) % 2, n_spots)) % n_phones
    return FingerprintSet(rssi_dbm=x, ap_ids=tuple(f"a{i}" for i in range(x.shape[1])), x_m=xy[:, 0],
                          y_m=xy[:, 1], floor=(xy[:, 0] > 15).astype(int), building=np.zeros(len(x), dtype=int),
                          meta=pd.DataFrame({"PHONEID": phone})), spot


def test_spot_phone_kfold_keeps_test_spots_and_phones_out_of_training():
    train, spot = _spot_train()
    phone = train.meta["PHONEID"].to_numpy()
    y = np.column_stack([train.xy_m, train.floor, train.building])
    cv = ms.SpotPhoneKFold(3, max_test=20, seed=3)
    folds = list(cv.split(train.rssi_dbm, y, phone))
    assert len(folds) == 3 and cv.get_n_splits() == 3
    for tr, te in folds:
        assert 0 < te.size <= 20 and tr.size > 0
        assert not set(spot[tr]) & set(spot[te]) and not set(phone[tr]) & set(phone[te])
        assert not set(map(tuple, y[tr])) & set(map(tuple, y[te]))     # no test position is a reference one
    again = list(ms.SpotPhoneKFold(3, max_test=20, seed=3).split(train.rssi_dbm, y, phone))
    assert all((a[0] == b[0]).all() and (a[1] == b[1]).all() for a, b in zip(folds, again, strict=True))
    other = list(ms.SpotPhoneKFold(3, max_test=20, seed=4).split(train.rssi_dbm, y, phone))
    assert any(set(a[1]) != set(b[1]) for a, b in zip(folds, other, strict=True))
    with pytest.raises(ValueError, match="needs y"):
        next(cv.split(train.rssi_dbm, None, phone))
    with pytest.raises(ValueError, match="at least n_splits=3 phones"):
        next(ms.SpotPhoneKFold(3).split(train.rssi_dbm, y, np.zeros(len(y))))


def test_rows_cv_equals_grid_search_of_each_row():
    # a fixed configuration's CV error is GridSearchCV's over the same folds (toolkit_cv with a one-point grid)
    from ilocalg.wifi.offset import OffsetFingerprint

    train, _ = _spot_train()
    est = OffsetFingerprint(3, (-2.0, 0.0, 2.0), "powed", "sorensen")
    for group in ("PHONEID", ms.SPOT_PHONE):
        t = ms.rows_cv(train, [("a", [("off", est)], False), ("b", [("off", est), ("off_w2", est.set_params())],
                                                                     False)], group=group, seed=1, max_test=30)
        _, ref = ms.toolkit_cv(train, seed=1, group=group, max_test=30, estimator=est, grid={"n_neighbors": [3]})
        np.testing.assert_allclose(t["cv_mean_error_m"], ref["cv_mean_error_m"].iloc[0], rtol=1e-12)
        assert list(t["groups"]) == [group, group]
    with pytest.raises(ValueError, match="meta column"):
        ms.rows_cv(train, [("a", [("off", est)], False)], group="USERID")


def test_spot_phone_kfold_scores_only_places_the_survey_covers():
    # with coverage_quantile, every test position lies within that quantile of the survey's own spot spacing of a
    # training-part reference on its floor; without it, some fold scores a place only its held-out phones surveyed
    from scipy.spatial import cKDTree

    train, _ = _spot_train(n_spots=60, n_phones=6)
    phone = train.meta["PHONEID"].to_numpy()
    y = np.column_stack([train.xy_m, train.floor, train.building])
    u = np.unique(y, axis=0)
    spacing = [cKDTree(u[u[:, 2] == f, :2]).query(u[u[:, 2] == f, :2], k=2)[0][:, 1] for f in np.unique(u[:, 2])]
    radius = np.quantile(np.concatenate(spacing), 0.5)

    def nearest(tr, te):
        return np.array([cKDTree(y[tr][y[tr][:, 2] == y[i, 2], :2]).query(y[i, :2])[0] for i in te])

    covered = list(ms.SpotPhoneKFold(3, 500, 1, spot_groups=5, coverage_quantile=0.5).split(None, y, phone))
    every = list(ms.SpotPhoneKFold(3, 500, 1, spot_groups=5, coverage_quantile=None).split(None, y, phone))
    for (tr, te), (tr0, te0) in zip(covered, every, strict=True):
        np.testing.assert_array_equal(tr, tr0)
        assert set(te) <= set(te0) and (nearest(tr, te) <= radius + 1e-9).all()
        np.testing.assert_array_equal(np.sort(te0[nearest(tr0, te0) <= radius + 1e-9]), te)
    assert sum(te.size for _, te in covered) < sum(te.size for _, te in every)


def test_ladder_configs_reproduce_each_row_and_the_diagnostic_ranks_them():
    # every ladder row's recorded configuration, refitted on the training set, gives the row's test error; the
    # diagnostic scores those configurations under both CVs and rank-correlates them with the test errors
    from scipy.stats import spearmanr

    from ilocalg.wifi.ensemble import ApSelector, combine_predictions, wants_devices

    train, _ = _spot_train(seed=7, n_spots=60, per_spot=6, n_phones=6)
    train.meta["USERID"] = train.meta["PHONEID"]
    test, _ = _spot_train(seed=8, n_spots=20, per_spot=3, n_phones=6)
    for s in (train, test):   # scan times: the device-calibration row needs them
        s.meta["TIMESTAMP"] = np.random.default_rng(len(s.meta)).permutation(len(s.meta))
    lad = ms.toolkit_ladder(train, test, seed=0, fast=True)
    rows = lad["toolkit_ladder"].set_index("method")
    assert [n for n, _, _ in lad["configs"]] == list(rows.index) and len(rows) == 14
    assert "device calibration" in set(lad["toolkit_cv"]["grid"])
    y = np.column_stack([train.xy_m, train.floor, train.building])
    meta = {"devices": test.meta["PHONEID"].to_numpy(), "times": test.meta["TIMESTAMP"].to_numpy()}
    for name, members, aps in lad["configs"]:
        x_tr, x_te = train.rssi_dbm, test.rssi_dbm
        if aps:
            sel = ApSelector(1).fit(x_tr)
            x_tr, x_te = sel.transform(x_tr), sel.transform(x_te)
        pr = combine_predictions([e.fit(x_tr, y).predict(x_te, **(meta if wants_devices(e) else {}))
                                  for _, e in members])
        err = np.hypot(pr[:, 0] - test.x_m, pr[:, 1] - test.y_m)
        assert np.nanmean(err) == pytest.approx(rows.loc[name, "mean_m"], rel=1e-6), name
    long, summary = ms.ladder_cv_diagnostic(train, lad, seed=0)
    assert list(summary["groups"]) == ["PHONEID", ms.SPOT_PHONE] and (summary["n_rows"] == 14).all()
    for g, t in long.groupby("groups"):
        rho = summary.set_index("groups").loc[g, "spearman_all"]
        assert rho == pytest.approx(spearmanr(t["cv_mean_error_m"], t["test_mean_m"])[0])
        np.testing.assert_array_equal(t["test_mean_m"], rows["mean_m"])


@pytest.mark.parametrize("kind", ["cascade", "offset"])
def test_toolkit_cv_one_fit_per_fold_over_k_equals_grid_search(kind):
    # candidates that differ only in K share one fit per fold (_at_n_neighbors): the same table, bit for bit, as
    # GridSearchCV fitting every candidate; floors smaller than the largest K are clamped as a fresh fit clamps them
    from sklearn.model_selection import GridSearchCV

    from ilocalg.metrics import horizontal_error_scorer
    from ilocalg.wifi import CascadeFingerprint, OffsetFingerprint
    from tests.test_wifi_ensemble import _radio

    rng = np.random.default_rng(7)
    x, xy = _radio(rng, n=200)
    floor = (xy[:, 0] > 15).astype(int) + (xy[:, 1] > 27).astype(int) * 2   # floor 2 / 3: a few rows only
    train = FingerprintSet(rssi_dbm=x, ap_ids=tuple(f"a{i}" for i in range(x.shape[1])), x_m=xy[:, 0],
                           y_m=xy[:, 1], floor=floor, building=(xy[:, 1] > 20).astype(int),
                           meta=pd.DataFrame({"USERID": np.arange(len(x)) % 3}))
    if kind == "cascade":
        est, grid = CascadeFingerprint(p=2), {"representation": ["positive", "powed"], "metric": ["sorensen"],
                                              "n_neighbors": [3, 8, 12]}
    else:
        est, grid = OffsetFingerprint(), {"representation": ["powed"], "shifts_db": [(0.0,), (-2.0, 0.0, 2.0)],
                                          "n_neighbors": [3, 8]}
    assert (np.bincount(floor) < 12).any()
    best, table = ms.toolkit_cv(train, seed=2, max_test=40, estimator=est, grid=grid)
    cv = ms.group_cv("USERID", 3, 40, 2)
    gs = GridSearchCV(est, grid, scoring=horizontal_error_scorer(), cv=cv, refit=False)
    gs.fit(train.rssi_dbm, ms._target(train), groups=train.meta["USERID"].to_numpy())
    r = gs.cv_results_
    ref = pd.DataFrame({"groups": "USERID", **{k: [ms._fmt(v) for v in r[f"param_{k}"]] for k in grid},
                        "cv_mean_error_m": -r["mean_test_score"], "cv_sd_m": r["std_test_score"],
                        "rank": r["rank_test_score"]}).sort_values("rank", kind="stable").reset_index(drop=True)
    pd.testing.assert_frame_equal(table, ref, check_exact=True)
    assert best == gs.best_params_
    shared = ms._k_shared_grid_search(est, grid, horizontal_error_scorer(), cv, train.rssi_dbm, ms._target(train),
                                      train.meta["USERID"].to_numpy())
    assert shared is not None   # the shared path ran (not the GridSearchCV fallback)


def test_ensemble_cv_at_several_k_equals_one_call_per_k():
    # one fit per member and fold for every K (offset and cascade members through _at_n_neighbors, spot members
    # once for all K): the same tables and cache entries as one ensemble_cv call per K, bit for bit
    from tests.test_wifi_ensemble import _radio

    rng = np.random.default_rng(5)
    x, xy = _radio(rng, n=160)
    xy = np.round(xy / 3.0) * 3.0   # several scans per spot
    floor = (xy[:, 0] > 15).astype(int)
    train = FingerprintSet(rssi_dbm=x, ap_ids=tuple(f"a{i}" for i in range(x.shape[1])), x_m=xy[:, 0],
                           y_m=xy[:, 1], floor=floor, building=np.zeros(len(x), dtype=int),
                           meta=pd.DataFrame({"PHONEID": np.arange(len(x)) % 4}))
    base = ms.ensemble_members((-2.0, 0.0, 2.0), three=True)
    grid = ms.spot_grid(base, fast=True)
    assert any("spots_" in n for m in grid["est__estimators"] for n, _ in m)
    cache_many, cache_one = {}, {}
    many = ms._ensemble_cv_at(train, grid, (3, 6), seed=1, max_test=40, cache=cache_many)
    for k, (best, table) in zip((3, 6), many, strict=True):
        ref_best, ref = ms.ensemble_cv(train, grid, k, seed=1, max_test=40, cache=cache_one)
        pd.testing.assert_frame_equal(table, ref, check_exact=True)
        assert [n for n, _ in best["est__estimators"]] == [n for n, _ in ref_best["est__estimators"]]
    assert cache_many.keys() == cache_one.keys()
    for key, v in cache_one.items():
        np.testing.assert_array_equal(cache_many[key], v)


def test_drop_aps_removes_whole_columns_from_the_queries_only():
    rng = np.random.default_rng(0)
    x = rng.uniform(-90, -30, (50, 200))
    x[rng.random(x.shape) < 0.3] = np.nan
    out, gone = ms.drop_aps(x, 0.25, np.random.default_rng(3))
    assert out is not x and np.isnan(out[:, gone]).all()
    np.testing.assert_array_equal(out[:, ~gone], x[:, ~gone])            # the other APs untouched, NaN kept
    assert 0.15 < gone.mean() < 0.35
    # the same generator state draws nested sets: a larger share loses the smaller one's APs and more
    _, more = ms.drop_aps(x, 0.5, np.random.default_rng(3))
    assert (more | ~gone).all() and more.sum() > gone.sum()
    _, none = ms.drop_aps(x, 0.0, np.random.default_rng(3))
    assert not none.any()
    for bad in (-0.1, 1.0):
        with pytest.raises(ValueError, match="drop_ap_fraction"):
            ms.drop_aps(x, bad, np.random.default_rng(0))


def test_ap_loss_cv_is_paired_against_rows_cv_and_losing_aps_costs():
    # fraction 0 is rows_cv itself; with APs gone from the queries every row's CV error grows, and each increase is
    # the mean of the paired (same fold) differences
    from sklearn.base import clone

    from ilocalg.wifi.knn import KnnFingerprint
    from ilocalg.wifi.offset import OffsetFingerprint

    # (every share's queries predicted by one fit per fold, a device-calibrated member once per share: the values of
    # one rows_cv per share)
    train, _ = _spot_train(n_spots=60, n_phones=6)
    train.meta["TIMESTAMP"] = np.random.default_rng(1).permutation(len(train.meta))
    off = OffsetFingerprint(3, (-2.0, 0.0, 2.0), "powed", "sorensen")
    rows = [("wknn", [("wknn", KnnFingerprint(3, p=2, weights="distance"))], False),
            ("off", [("off", off)], True),
            ("both", [("off", off), ("cal", clone(off).set_params(device_calibration=True))], True)]
    t = ms.ap_loss_cv(train, rows, fractions=(0.5,), seeds=(0, 1), max_test=30)
    assert list(t["fraction_aps_gone"]) == [0.0] * 3 + [0.5] * 3 and (t["n_folds"] == 6).all()
    for fr in (0.0, 0.5):
        one = pd.concat([ms.rows_cv(train, rows, ms.SPOT_PHONE, s, max_test=30, drop_ap_fraction=fr) for s in (0, 1)])
        got = t[t["fraction_aps_gone"] == fr].set_index("row")["cv_mean_error_m"]
        np.testing.assert_allclose(got, one.groupby("row", sort=False)["cv_mean_error_m"].mean(), rtol=1e-12)
    at0 = t[t["fraction_aps_gone"] == 0.0].set_index("row")
    assert (at0["increase_m"] == 0.0).all()
    half = t[t["fraction_aps_gone"] == 0.5].set_index("row")
    assert (half["increase_m"] > 0).all()
    np.testing.assert_allclose(half["cv_mean_error_m"] - at0["cv_mean_error_m"], half["increase_m"], rtol=1e-12)
    assert (half["increase_ci95_lo_m"] <= half["increase_m"]).all()
    assert (half["increase_m"] <= half["increase_ci95_hi_m"]).all()
    assert half.loc["wknn", "ratio_to_first_row"] == 1.0
    with pytest.raises(ValueError, match="drop_ap_fraction"):
        ms.rows_cv(train, rows, drop_ap_fraction=1.0)
