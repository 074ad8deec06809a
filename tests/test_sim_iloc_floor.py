"""The i-Loc floor simulator: determinism, geometry from the thesis, the radio model's behaviour."""

import numpy as np
import pytest

from ilocalg.sim import iloc_floor


def test_same_seed_same_arrays_and_different_seed_differs():
    a = iloc_floor.simulate(3, scans_per_point=20, scans_per_test_point=2)
    b = iloc_floor.simulate(3, scans_per_point=20, scans_per_test_point=2)
    np.testing.assert_array_equal(a.train.rssi_dbm, b.train.rssi_dbm)
    np.testing.assert_array_equal(a.test.rssi_dbm, b.test.rssi_dbm)
    np.testing.assert_array_equal(a.ap_xy_m, b.ap_xy_m)
    c = iloc_floor.simulate(4, scans_per_point=20, scans_per_test_point=2)
    assert not np.array_equal(np.nan_to_num(a.train.rssi_dbm), np.nan_to_num(c.train.rssi_dbm))


def test_geometry_follows_the_thesis():
    pts = iloc_floor.training_points()
    assert pts.shape == (iloc_floor.N_TRAIN_POINTS, 2) and len(np.unique(pts, axis=0)) == len(pts)
    assert (pts >= 0).all() and (pts[:, 0] <= iloc_floor.FLOOR_W_M).all() and (pts[:, 1] <= iloc_floor.FLOOR_H_M).all()
    # every point has a neighbour 2 m away (L295)
    d = np.hypot(pts[:, None, 0] - pts[None, :, 0], pts[:, None, 1] - pts[None, :, 1])
    np.fill_diagonal(d, np.inf)
    np.testing.assert_allclose(d.min(axis=1), 2.0)


def test_route_is_28_training_points_about_4_m_apart():
    route = iloc_floor.test_route_index()
    pts = iloc_floor.training_points()
    assert route.size == iloc_floor.N_TEST_POINTS == 28 and len(np.unique(route)) == 28
    xy = iloc_floor.route_xy_m()
    np.testing.assert_array_equal(xy, pts[route])
    gaps = np.hypot(*np.diff(xy, axis=0).T)
    np.testing.assert_allclose(gaps, iloc_floor.ROUTE_SPACING_M)  # L515: 4.11 m; 2 m grid -> 4 m
    assert 100.0 <= gaps.sum() <= 115.0  # thesis: 27 x 4.11 = 111 m
    # consecutive route points are joined by corridor (the training point between them lies on the segment)
    mid = 0.5 * (xy[1:] + xy[:-1])
    assert np.hypot(mid[:, None, 0] - pts[None, :, 0], mid[:, None, 1] - pts[None, :, 1]).min(axis=1).max() < 1e-9


def test_wall_attenuation_by_material():
    """One light wall costs 3.4 dB, one heavy wall 6.9 dB (COST 231), at the same distance."""
    p = {**iloc_floor.PARAMS, "shadow_sd_db": 0.0}
    seg, mat = iloc_floor.walls(), iloc_floor.wall_materials()
    assert len(seg) == len(mat) and set(mat) == {"heavy", "light"}
    for kind, loss in (("light", 3.4), ("heavy", 6.9)):
        x0, y0, x1, y1 = seg[np.flatnonzero(mat == kind)[0]]
        c = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1)])
        n = np.array([-(y1 - y0), x1 - x0]) / np.hypot(x1 - x0, y1 - y0)
        rx = np.vstack([c + 0.3 * n, c - 0.3 * n + 0.0])  # 0.6 m apart, on either side of the wall
        ap_same = c + 0.3 * n + 1e-3 * np.array([n[1], -n[0]])
        m = iloc_floor.mean_rssi_dbm(rx, ap_same[None, :], np.array([0]), p)[:, 0]
        free = p["p0_dbm"] - 10 * p["path_loss_exponent"] * np.log10(1.0)
        assert m[0] == pytest.approx(free)  # within 1 m, no wall
        assert m[0] - m[1] == pytest.approx(loss)


def test_drift_changes_between_sessions_not_within_one():
    """No fade, no local change, no body, no misses: scans of one session are identical, sessions differ."""
    quiet = {"fade_sd_db": 0.0, "fade_sd_edge_db": 0.0, "local_sd_db": 0.0, "body_loss_db": 0.0, "miss_p": 0.0}
    sim = iloc_floor.simulate(0, scans_per_point=60, scans_per_test_point=3, scans_per_session=30, **quiet)
    x = sim.train.rssi_dbm
    meta = sim.train.meta
    at0 = (meta["point"] == 0).to_numpy()
    s0, s1 = x[at0 & (meta["session"] == 0).to_numpy()], x[at0 & (meta["session"] == 1).to_numpy()]
    np.testing.assert_array_equal(s0, np.repeat(s0[:1], len(s0), axis=0))
    assert not np.array_equal(np.nan_to_num(s0[0]), np.nan_to_num(s1[0]))
    # the drift is floor-wide: the same shift at every point of a session (up to integer rounding)
    d0 = np.nanmean(x[(meta["session"] == 1).to_numpy() & at0][0] - s0[0])
    at5 = (meta["point"] == 5).to_numpy()
    d5 = np.nanmean(x[at5 & (meta["session"] == 1).to_numpy()][0] - x[at5 & (meta["session"] == 0).to_numpy()][0])
    assert abs(d0 - d5) < 1.0
    # the test session is another session: its drift is not the survey's
    assert sim.test_drift_db.shape == (sim.ap_xy_m.shape[0],)


def test_body_shadowing_and_device_offset():
    quiet = {"fade_sd_db": 0.0, "fade_sd_edge_db": 0.0, "local_sd_db": 0.0, "drift_sd_db": 0.0, "miss_p": 0.0,
             "detect_dbm": -200.0}
    a = iloc_floor.simulate(1, scans_per_point=1, scans_per_test_point=1, body_loss_db=0.0, **quiet)
    b = iloc_floor.simulate(1, scans_per_point=1, scans_per_test_point=1, body_loss_db=5.0, **quiet)
    d = b.test.rssi_dbm - a.test.rssi_dbm
    assert d.max() <= 0.5 and d.min() >= -5.5 and d.min() < -3.5  # an AP behind loses up to 5 dB
    c = iloc_floor.simulate(1, scans_per_point=1, scans_per_test_point=1, body_loss_db=0.0,
                            device_offset_db=-6.0, **quiet)
    np.testing.assert_array_equal(c.test.rssi_dbm - a.test.rssi_dbm, -6.0)
    np.testing.assert_array_equal(c.train.rssi_dbm, a.train.rssi_dbm)  # survey phone unchanged


def test_device_offsets_at_once_are_the_floors_of_one_simulate_each():
    offsets = (-10.0, 0.0, 7.5)
    kw = dict(scans_per_point=20, scans_per_test_point=3, body_loss_db=2.0)
    rng = np.random.default_rng(8)
    floors = iloc_floor.simulate_device_offsets(offsets, rng, **kw)
    assert len(floors) == 3
    for off, f in zip(offsets, floors, strict=True):
        one_rng = np.random.default_rng(8)
        one = iloc_floor.simulate(one_rng, device_offset_db=off, **kw)
        for a, b in ((f.train.rssi_dbm, one.train.rssi_dbm), (f.test.rssi_dbm, one.test.rssi_dbm),
                     (f.test.xy_m, one.test.xy_m), (f.mean_rssi_dbm, one.mean_rssi_dbm)):
            assert a.tobytes() == b.tobytes()
        assert f.params == one.params and f.params["device_offset_db"] == off
        assert one_rng.bit_generator.state == rng.bit_generator.state  # the caller's generator moves as one call
    assert not np.array_equal(np.nan_to_num(floors[0].test.rssi_dbm), np.nan_to_num(floors[2].test.rssi_dbm))
    with pytest.raises(ValueError, match="device_offsets_db"):
        iloc_floor.simulate_device_offsets((0.0,), 1, device_offset_db=3.0)
    with pytest.raises(ValueError, match="finite"):
        iloc_floor.simulate_device_offsets((np.nan,), 1)


@pytest.mark.parametrize("world", ["measured", "copied", "assumed"])
def test_calibrated_inputs(world):
    sim = iloc_floor.simulate(0, scans_per_point=100, scans_per_test_point=2, world=world)
    s = iloc_floor.summary(sim).set_index("quantity")["value"]
    # thesis L295: 4-18 APs per scan -> the bulk of the scans (5th-95th percentile) lies in that range
    assert 4 <= s["APs heard per scan, 5th percentile"] and s["APs heard per scan, 95th percentile"] <= 18
    assert 2.0 <= s["RSSI sd at a point per AP, median [dB]"] <= 6.0
    x = sim.train.rssi_dbm
    assert np.nanmin(x) >= sim.detect_dbm and np.array_equal(x[~np.isnan(x)], np.round(x[~np.isnan(x)]))
    assert sim.fade_sd_db.max() > sim.fade_sd_db.min()  # windows / corners drift more (Fig 2)


def test_walking_scans_are_tagged_at_the_start_and_ready_after_the_latency():
    sim = iloc_floor.simulate(0, scans_per_point=5, scans_per_test_point=1)
    route = iloc_floor.route_xy_m()
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(route, axis=0).T))])
    t = s / 1.2  # 1.2 m/s
    scans = iloc_floor.walking_scans(sim, t, route, [10.0, 30.0, 50.0], scan_latency_s=2.0, rng=0)
    np.testing.assert_allclose(scans["t_ready_s"] - scans["t_start_s"], 2.0)
    np.testing.assert_allclose(scans["x_m"], np.interp(scans["t_start_s"], t, route[:, 0]))
    assert set(sim.train.ap_ids) <= set(scans.columns)
    again = iloc_floor.walking_scans(sim, t, route, [10.0, 30.0, 50.0], scan_latency_s=2.0, rng=0)
    assert again.equals(scans)
    with pytest.raises(ValueError, match="scan_start_t_s"):
        iloc_floor.walking_scans(sim, t, route, [t[-1] + 1.0])


def test_unknown_or_bad_parameter_raises():
    with pytest.raises(ValueError, match="unknown simulator parameters"):
        iloc_floor.simulate(0, path_loss=3)
    with pytest.raises(ValueError, match="drift_sd_db"):
        iloc_floor.simulate(0, drift_sd_db=-1.0)


def test_floor_fixes_shapes_and_variance_floor():
    ff = iloc_floor.floor_fixes(0, n_walkers=2, n_cal=3, method="KNN (Manhattan, K=5)", scans_per_point=20)
    n_pts = ff.route_xy_m.shape[0]
    assert ff.fix_xy_m.shape == (n_pts, 5, 2) and ff.cal_var_m2.shape == (n_pts,)
    assert (ff.cal_var_m2 >= iloc_floor.SPACING_M**2 / 12.0 - 1e-12).all()
    assert np.median(np.hypot(*(ff.fix_xy_m[:, 0] - ff.route_xy_m).T)) < 15.0
    with pytest.raises(ValueError, match="method must be one of"):
        iloc_floor.floor_fixes(0, 1, 2, method="SVM", scans_per_point=5)
    with pytest.raises(ValueError, match="n_cal"):
        iloc_floor.floor_fixes(0, 1, 1, scans_per_point=5)


def test_fit_estimator_and_standing_variance_agree_with_floor_fixes():
    ff = iloc_floor.floor_fixes(0, n_walkers=1, n_cal=3, method="KNN (Manhattan, K=5)", scans_per_point=20)
    est = iloc_floor.fit_estimator(ff.sim, "KNN (Manhattan, K=5)")
    fix = est.predict(ff.sim.test.rssi_dbm).reshape(ff.route_xy_m.shape[0], -1, 2)
    np.testing.assert_array_equal(fix, ff.fix_xy_m)
    var = iloc_floor.standing_fix_variance_m2(ff.sim, est)  # over all 4 standing scans per point
    err2 = ((ff.fix_xy_m - ff.route_xy_m[:, None]) ** 2).sum(-1).mean(axis=1) / 2
    np.testing.assert_allclose(var, np.maximum(err2, iloc_floor.SPACING_M**2 / 12.0))
    with pytest.raises(ValueError, match="method must be one of"):
        iloc_floor.fit_estimator(ff.sim, "SVM")


def test_back_to_back_scans_start_when_the_last_one_ends():
    s = iloc_floor.back_to_back_scan_starts_s(1.0, 10.0, 2.0)
    np.testing.assert_allclose(s, [1.0, 3.0, 5.0, 7.0])      # the last scan ends at 9 s <= 10 s
    np.testing.assert_allclose(iloc_floor.back_to_back_scan_starts_s(0.0, 6.0, 2.0), [0.0, 2.0, 4.0])
    assert iloc_floor.back_to_back_scan_starts_s(0.0, 1.0, 2.0).size == 0
    with pytest.raises(ValueError, match="scan_latency_s"):
        iloc_floor.back_to_back_scan_starts_s(0.0, 6.0, 0.0)


def test_worlds_measured_from_the_table_and_assumed_unchanged():
    from ilocalg.sim.measured import calibrated, param

    c, m, a = (iloc_floor.world_params(w) for w in ("copied", "measured", "assumed"))
    assert a == iloc_floor.PARAMS
    for k, row in iloc_floor.MEASURED_ROWS.items():
        expect = 1.0 - param(row) if k == "miss_p" else param(row)
        assert c[k] == expect  # the copied world: the measured values as they are
        assert m[k] == (calibrated(f"iloc_floor.{k}") if k in iloc_floor.CALIBRATED else expect)
    assert m["light_wall_db"] == m["heavy_wall_db"] == c["light_wall_db"] == 0.0
    assert (c["n_aps_floor"], c["n_aps_other"]) == (13, 10)
    src, srcc = iloc_floor.world_sources("measured"), iloc_floor.world_sources("copied")
    assert all("measured_parameters.csv" in srcc[k] for k in iloc_floor.MEASURED_ROWS)
    assert all(("calibrated_parameters.csv" if k in iloc_floor.CALIBRATED else "measured_parameters.csv") in src[k]
               for k in iloc_floor.MEASURED_ROWS)
    s0 = iloc_floor.simulate(0, scans_per_point=2, scans_per_test_point=1, world="assumed")
    assert s0.params == {**iloc_floor.PARAMS}
    with pytest.raises(ValueError, match="world"):
        iloc_floor.world_params("imagined")
