"""error_budget: a result's mean error by group of test scans, checked against hand-built sets."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.io.schema import FingerprintSet
from ilocalg.wifi.evaluate import error_budget


def _set(xy, floor, phones):
    xy = np.asarray(xy, dtype=float)
    n = len(xy)
    return FingerprintSet(rssi_dbm=np.full((n, 1), -60.0), ap_ids=("a",), x_m=xy[:, 0], y_m=xy[:, 1],
                          floor=np.asarray(floor), building=np.zeros(n, dtype=int),
                          meta=pd.DataFrame({"PHONEID": phones}))


def test_groups_shares_and_bounds():
    train = _set([[0, 0], [10, 0], [0, 0]], [0, 0, 1], [1, 2, 1])
    # test scans: near (0.5 m) a floor-0 reference, 3 m from one, 20 m away on floor 0, and one on floor 1
    test = _set([[0.5, 0], [13, 0], [30, 0], [0, 1]], [0, 0, 0, 1], [1, 9, 9, 1])
    res = {"error_m": np.array([1.0, 2.0, 20.0, 3.0]), "floor": np.array([0, 0, 1, 1])}
    b = error_budget(train, test, res).set_index("group")
    assert b.loc["all located scans", "mean_error_m"] == pytest.approx(6.5)
    assert b.loc["floor missed", "n"] == 1 and b.loc["floor missed", "share_of_total_error"] == pytest.approx(20 / 26)
    assert b.loc["phone seen in training", "mean_error_m"] == pytest.approx(2.0)
    assert b.loc["phone not seen in training", "mean_error_m"] == pytest.approx(11.0)
    # floor-weighted: only floor 0 holds both groups (seen 1.0, unseen 11.0, weighted by its 2 unseen scans)
    assert b.loc["phone seen, floor-weighted (floors with both)", "mean_error_m"] == pytest.approx(1.0)
    assert b.loc["phone not seen, floor-weighted (floors with both)", "mean_error_m"] == pytest.approx(11.0)
    assert b.loc["nearest training reference < 2 m", "n"] == 2      # 0.5 m, and 1 m on floor 1
    assert b.loc["nearest training reference 2-5 m", "n"] == 1
    assert b.loc["nearest training reference >= 5 m", "mean_error_m"] == pytest.approx(20.0)
    assert b.loc["error > 15 m", "share_of_scans"] == pytest.approx(0.25)
    # bounds from positions alone: nearest reference 0.5, 3, 20, 1 m
    assert b.loc["bound: nearest training reference", "mean_error_m"] == pytest.approx(24.5 / 4)


def test_unlocated_scans_are_left_out():
    train = _set([[0, 0], [10, 0]], [0, 0], [1, 1])
    test = _set([[0, 0], [10, 0]], [0, 0], [1, 1])
    b = error_budget(train, test, {"error_m": np.array([np.nan, 4.0]), "floor": np.array([0, 0])}).set_index("group")
    assert b.loc["all located scans", "n"] == 1 and b.loc["all located scans", "mean_error_m"] == 4.0


def test_nearest_same_floor_stays_on_the_floor_and_pads():
    from ilocalg.wifi.evaluate import nearest_same_floor

    ref = np.array([[0, 0, 0, 0], [5, 0, 0, 0], [1, 0, 1, 0]], dtype=float)
    q = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 2, 0]], dtype=float)
    d, i = nearest_same_floor(ref, q, 2)
    np.testing.assert_allclose(d, [[1, 4], [1, np.inf], [np.inf, np.inf]])
    np.testing.assert_array_equal(i, [[0, 1], [2, -1], [-1, -1]])   # floor 1 has one reference, floor 2 none
