"""CascadeFingerprint: the toolkit's building -> floor -> position estimator (scikit-learn contract)."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.model_selection import GridSearchCV, GroupKFold
from sklearn.pipeline import Pipeline

from ilocalg.metrics import horizontal_error_scorer
from ilocalg.wifi import HierarchicalLocator, KnnFingerprint
from ilocalg.wifi.cascade import CascadeFingerprint, split_target


def _two_buildings(seed=0, n_per_floor=40):
    """Two buildings 200 m apart, two floors each; APs per building and per floor (log-distance, seeded)."""
    rng = np.random.default_rng(seed)
    rows, tgt = [], []
    ap_xy = np.random.default_rng(99).uniform(0, 40, (4, 6, 2))   # (building*2+floor, ap, xy), one world
    for b in range(2):
        for f in range(2):
            xy = rng.uniform(0, 40, (n_per_floor, 2))
            r = np.full((n_per_floor, 24), np.nan)
            for g in range(4):
                gb, gf = divmod(g, 2)
                if gb != b:
                    continue
                d = np.linalg.norm(xy[:, None] - ap_xy[g][None], axis=2)
                att = 0.0 if gf == f else 15.0            # the other floor's APs through a slab
                r[:, g * 6:(g + 1) * 6] = np.round(-35 - 25 * np.log10(d + 1) - att + rng.normal(0, 2, d.shape))
            r[r < -100] = np.nan
            rows.append(r)
            tgt.append(np.column_stack([xy + [200.0 * b, 0.0], np.full(n_per_floor, f), np.full(n_per_floor, b)]))
    return np.vstack(rows), np.vstack(tgt)


def test_labels_right_and_positions_inside_the_floor():
    x, y = _two_buildings(0)
    xt, yt = _two_buildings(1, 15)
    p = CascadeFingerprint(n_neighbors=5, representation="powed", metric="sorensen").fit(x, y).predict(xt)
    assert p.shape == (xt.shape[0], 4)
    assert (p[:, 3] == yt[:, 3]).all()                    # buildings 200 m apart with disjoint APs
    assert (p[:, 2] == yt[:, 2]).mean() >= 0.95           # 15 dB slab loss
    e = np.hypot(*(p[:, :2] - yt[:, :2]).T)
    assert np.median(e) < 8.0                             # a 40 m floor, 40 references


def test_agrees_with_hierarchical_locator_of_the_same_knns():
    x, y = _two_buildings(0)
    xt, _ = _two_buildings(1, 10)
    est = CascadeFingerprint(n_neighbors=4, n_neighbors_class=3, representation="positive", p=1).fit(x, y)
    knn = dict(p=1, weights="distance", representation="positive")
    ref = HierarchicalLocator(KnnFingerprint(3, **knn), KnnFingerprint(4, **knn)).fit(
        x, y[:, :2], y[:, 2].astype(int), y[:, 3].astype(int)).predict(xt)
    np.testing.assert_allclose(est.predict(xt), ref[["x_m", "y_m", "floor", "building"]].to_numpy(float))


def test_positions_only_is_flat_wknn():
    x, y = _two_buildings(0)
    xt, _ = _two_buildings(1, 10)
    a = CascadeFingerprint(n_neighbors=5, representation="powed", p=2).fit(x, y[:, :2]).predict(xt)
    b = KnnFingerprint(5, p=2, weights="distance", representation="powed").fit(x, y[:, :2]).predict(xt)
    np.testing.assert_allclose(a, b)


def test_grid_search_in_a_pipeline_with_group_folds():
    x, y = _two_buildings(0)
    groups = np.arange(x.shape[0]) % 4
    pipe = Pipeline([("cascade", CascadeFingerprint())])
    gs = GridSearchCV(pipe, {"cascade__n_neighbors": [1, 5], "cascade__metric": ["minkowski", "sorensen"]},
                      scoring=horizontal_error_scorer(), cv=GroupKFold(4)).fit(x, y, groups=groups)
    assert np.isfinite(gs.cv_results_["mean_test_score"]).all()
    assert gs.best_score_ <= 0


def test_bad_input():
    x, y = _two_buildings(0, 5)
    with pytest.raises(ValueError, match="X has 20 rows but y has 19"):
        CascadeFingerprint(n_neighbors=2).fit(x, y[1:])
    with pytest.raises(ValueError, match="whole numbers"):
        CascadeFingerprint(n_neighbors=2).fit(x, y + [0, 0, 0.5, 0])
    with pytest.raises(ValueError, match="n_neighbors=99"):
        CascadeFingerprint(n_neighbors=99).fit(x, y)
    with pytest.raises(ValueError, match="not finite"):
        split_target(np.array([[0.0, np.nan]]))


def test_check_estimator():
    from sklearn.utils.estimator_checks import check_estimator

    from tests.test_wifi_knn import EXPECTED_FAILED

    # not_heard_dbm=-100 lies below the checks' random data and keeps float32 self-distances at 0
    check_estimator(CascadeFingerprint(n_neighbors=3, n_neighbors_class=3, representation="positive",
                                       not_heard_dbm=-100.0, rssi_range_dbm=None),
                    expected_failed_checks=EXPECTED_FAILED)
