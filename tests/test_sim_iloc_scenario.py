"""ilocalg.sim.iloc_scenario: a world built once, handed out as recordings-like walks with causal scans."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.sim import iloc_floor, iloc_scenario, measured


@pytest.fixture(scope="module")
def scn():
    return iloc_scenario.build(3, n_walkers=2, n_train=1, n_cal=3, scans_per_point=20, scan_interval_s=4.0,
                               scan_latency_s=2.0, lag_model="uniform")


def test_measured_lag_model_is_periodic_causal_and_has_the_measured_ages():
    s = iloc_scenario.build(3, n_walkers=1, n_train=1, n_cal=3, scans_per_point=20)
    assert s.params["scan_interval_s"] == measured.param("wifi_scan_interval_s")
    sc = s.walks[0].scans
    np.testing.assert_allclose(np.diff(sc["t_ready_s"]), s.params["scan_interval_s"])
    assert ((sc["t_start_s"] <= sc["t_ref_s"]) & (sc["t_ref_s"] <= sc["t_ready_s"])).all()
    ages = iloc_scenario.reading_ages_s(0, 200_000)
    assert np.median(ages) == pytest.approx(measured.param("wifi_reading_age_median_s"), rel=0.01)
    iqr = np.subtract(*np.percentile(ages, [75, 25]))
    assert iqr == pytest.approx(measured.param("wifi_reading_age_iqr_s"), rel=0.02)
    with pytest.raises(ValueError, match="lag_model"):
        iloc_scenario.build(3, n_walkers=1, n_train=1, n_cal=3, scans_per_point=20, lag_model="oracle")


def test_scans_are_periodic_and_causal(scn):
    assert len(scn.walks) == 2 and len(scn.train_walks) > 0
    for w in scn.walks:
        s = w.scans
        np.testing.assert_allclose(np.diff(s["t_start_s"]), 4.0)
        assert s["t_start_s"].iloc[0] == w.imu.index[0]                   # from the start of the log
        np.testing.assert_allclose(s["t_ready_s"] - s["t_start_s"], 2.0)
        assert ((s["t_ref_s"] >= s["t_start_s"]) & (s["t_ref_s"] <= s["t_ready_s"])).all()
        assert s["t_ready_s"].iloc[-1] <= w.truth.index[-1]
        assert set(scn.floor.train.ap_ids) <= set(s.columns)
        assert w.pass_t_s.size == scn.route_xy_m.shape[0]


def test_build_is_deterministic_and_rescan_keeps_the_walks(scn):
    again = iloc_scenario.build(3, n_walkers=2, n_train=1, n_cal=3, scans_per_point=20, scan_interval_s=4.0,
                                scan_latency_s=2.0, lag_model="uniform")
    for a, b in zip(scn.walks, again.walks, strict=True):
        pd.testing.assert_frame_equal(a.scans, b.scans)
        pd.testing.assert_frame_equal(a.imu, b.imu)
    r = iloc_scenario.rescan(scn, 3, scan_interval_s=3.0, scan_latency_s=1.0)
    for a, b in zip(scn.walks, r.walks, strict=True):
        pd.testing.assert_frame_equal(a.imu, b.imu)                      # same walks ...
        np.testing.assert_allclose(np.diff(b.scans["t_start_s"]), 3.0)   # ... new scans
    assert r.params["scan_latency_s"] == 1.0 and scn.params["scan_latency_s"] == 2.0


def test_walk_fixes_and_bad_scan_timing(scn):
    est = iloc_floor.fit_estimator(scn.floor, "KNN (Manhattan, K=5)")
    fx = iloc_scenario.walk_fixes(scn, scn.walks[0], est)
    assert len(fx) == len(scn.walks[0].scans)
    ok = np.isfinite(fx[["fix_x_m", "fix_y_m"]].to_numpy()).all(axis=1)
    assert ok.mean() > 0.9
    with pytest.raises(ValueError, match="longer than the scan interval"):
        iloc_floor.periodic_scan_starts_s(0.0, 10.0, 1.0, 2.0)
    np.testing.assert_allclose(iloc_floor.periodic_scan_starts_s(0.0, 10.0, 3.0, 2.0), [0.0, 3.0, 6.0])


def test_a_scenario_walk_saves_and_loads_like_a_recording(scn, tmp_path):
    from ilocalg.io.ilc_write import write_ilc_trace
    from ilocalg.io.recording import load_recording

    w = scn.walks[0]
    rec = iloc_scenario.to_recording(scn, w)
    heard = int((~np.isnan(w.scans[list(scn.floor.train.ap_ids)].to_numpy())).sum())
    assert len(rec.wifi) == heard and rec.wifi["scan_id"].nunique() == len(w.scans)
    assert (rec.wifi["last_seen_s"] <= rec.wifi["t_s"] + 1e-9).all()     # a reading is never from the future
    back = load_recording(write_ilc_trace(rec, tmp_path / "walk.txt"))
    assert len(back.imu) == len(w.imu) and len(back.wifi) == heard
    np.testing.assert_allclose(back.imu.to_numpy(), w.imu.to_numpy(), atol=1e-9)
    np.testing.assert_allclose(np.sort(back.wifi["rssi_dbm"].to_numpy()), np.sort(rec.wifi["rssi_dbm"].to_numpy()))
    np.testing.assert_allclose(back.truth[["x_m", "y_m"]].to_numpy(), scn.route_xy_m)
