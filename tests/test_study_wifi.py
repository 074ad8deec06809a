"""Study of the Wi-Fi methods vs k, training-point spacing and scans per point (ilocalg.experiments.study_wifi)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import study_wifi
from ilocalg.sim import iloc_floor

SEEDS = (0, 1, 2)


def _mean_error(seed, method, **params):
    df = study_wifi.run(seed=seed, fast=True, scans_per_test_point=3, **params)["sweep_wifi"]
    sel = df[(df["quantity"] == "mean error") & (df["item"] == f"method={method}")]
    assert len(sel) == 1
    return float(sel["value"].iloc[0])


def _clear_caches():
    for f in (study_wifi._floors, study_wifi._training, study_wifi._horus_fit, study_wifi._radar_fit,
              study_wifi._knn_summary):
        f.cache_clear()


def test_ap_count_points_sharing_a_survey_give_the_tables_of_fresh_runs():
    kw = dict(seed=4, fast=True, scans_per_point=8, scans_per_test_point=3)
    fresh = {}
    for k in (3, 6):
        _clear_caches()
        fresh[k] = study_wifi.run(k_aps=k, **kw)["sweep_wifi"]
    _clear_caches()
    study_wifi.run(k_aps=6, **kw)  # fills the survey's caches with k = 6
    pd.testing.assert_frame_equal(study_wifi.run(k_aps=3, **kw)["sweep_wifi"], fresh[3], check_exact=True)
    assert study_wifi._horus_fit.cache_info().hits == 1 and study_wifi._knn_summary.cache_info().hits == 1
    assert not fresh[3].equals(fresh[6])  # k changes RADAR's and Horus's rows: the shared fit is not the answer
    h = fresh[3]
    knn = h["item"] == "method=KNN (Manhattan, K=5)"
    pd.testing.assert_frame_equal(h[knn], fresh[6][knn], check_exact=True)  # KNN does not read k


def test_device_offset_points_sharing_a_survey_give_the_tables_of_fresh_runs():
    kw = dict(seed=4, fast=True, scans_per_point=8, scans_per_test_point=3)
    fresh = {}
    for off in (-10.0, 0.0, 3.0):  # 3 dB: not a grid value (its own survey draw, the same arrays)
        _clear_caches()
        fresh[off] = study_wifi.run(device_offset_db=off, **kw)["sweep_wifi"]
        _clear_caches()
        sim = iloc_floor.simulate(4, scans_per_point=8, scans_per_test_point=3, device_offset_db=off)
        assert study_wifi._floor(4, 8, 3, (("device_offset_db", off),)).test.rssi_dbm.tobytes() == \
            sim.test.rssi_dbm.tobytes()
    _clear_caches()
    for off in (0.0, -10.0, 3.0):
        pd.testing.assert_frame_equal(study_wifi.run(device_offset_db=off, **kw)["sweep_wifi"], fresh[off],
                                      check_exact=True)
    assert study_wifi._floors.cache_info().misses == 2  # the grid's offsets drawn with one survey, 3 dB apart
    assert study_wifi._horus_fit.cache_info().hits == 2 and study_wifi._radar_fit.cache_info().hits == 2
    assert not fresh[0.0].equals(fresh[-10.0])  # the offset reaches the test scans


def test_same_seed_same_table_and_sweep_shape():
    a = study_wifi.run(seed=3, fast=True, scans_per_point=10, spacing_m=4.0)["sweep_wifi"]
    b = study_wifi.run(seed=3, fast=True, scans_per_point=10, spacing_m=4.0)["sweep_wifi"]
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert {"quantity", "value", "unit", "item"} <= set(a.columns)
    assert np.isfinite(a["value"]).all()
    assert set(a.loc[a["quantity"] == "mean error", "item"]) == {
        "method=Simplified-RADAR", "method=Simplified-Horus", "method=KNN (Manhattan, K=5)"}


def test_thin_points_keeps_the_grid_at_2m_and_spaces_coarser_grids():
    pts = iloc_floor.training_points()
    assert np.array_equal(study_wifi.thin_points(pts, 2.0), np.arange(len(pts)))
    for s in (4.0, 6.0, 10.0):
        k = study_wifi.thin_points(pts, s)
        d = np.hypot(*(pts[k][:, None] - pts[k][None]).transpose(2, 0, 1))
        assert d[~np.eye(len(k), dtype=bool)].min() >= s - 1e-3
        assert len(k) < len(pts)
    # every other point of a straight corridor at 4 m (the ring's south side: 18 points 2 m apart)
    assert len(study_wifi.thin_points(pts[:18], 4.0)) == 9
    with pytest.raises(ValueError, match="spacing_m"):
        study_wifi.thin_points(pts, 0.0)
    with pytest.raises(ValueError, match="k_aps"):
        study_wifi.run(seed=0, fast=True, k_aps=0)


def test_errors_move_the_right_way_on_average_over_seeds():
    def avg(method, **p):
        return np.mean([_mean_error(s, method, **p) for s in SEEDS])

    for m in ("Simplified-RADAR", "Simplified-Horus", "KNN (Manhattan, K=5)"):
        # a coarser survey grid is worse
        assert avg(m, spacing_m=8.0, scans_per_point=30) > avg(m, spacing_m=2.0, scans_per_point=30)
    # more scans per point is not worse (Horus needs them for its histograms)
    assert avg("Simplified-Horus", scans_per_point=60) <= avg("Simplified-Horus", scans_per_point=3)
    assert avg("Simplified-RADAR", scans_per_point=60) <= avg("Simplified-RADAR", scans_per_point=3) + 0.05
    # one AP is far worse than five
    assert avg("Simplified-RADAR", k_aps=1, scans_per_point=30) > avg("Simplified-RADAR", k_aps=5, scans_per_point=30)


def test_tasks_share_the_base_point():
    t = study_wifi.tasks(range(2), fast=True)
    keys = [x.key for x in t]
    assert len(keys) == len(set(keys))
    g = study_wifi.GRIDS[True]
    n_points = sum(len(v) for v in g.values()) - (len(g) - 1)  # the base point is shared by the 3 curves
    assert len(t) == 2 * n_points


def test_radio_parameters_reach_the_floor():
    """A swept radio parameter changes the test scans only through the simulator; unknown names fail."""
    a = study_wifi.run(seed=0, fast=True, scans_per_point=10, scans_per_test_point=2)["sweep_wifi"]
    b = study_wifi.run(seed=0, fast=True, scans_per_point=10, scans_per_test_point=2,
                       device_offset_db=-10.0)["sweep_wifi"]
    assert not a["value"].equals(b["value"])
    assert set(study_wifi.RADIO) <= set(study_wifi.BASE) and set(study_wifi.RADIO) <= set(study_wifi.GRIDS[True])
    with pytest.raises(ValueError, match="unknown radio parameters"):
        study_wifi.run(seed=0, fast=True, wall_db=3.0)
