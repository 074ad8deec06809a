"""The track pipeline (ilocalg.track) on the real ILC 2.0 site2/F4 walks, leave-one-walk-out."""

import dataclasses

import numpy as np
import pytest

from ilocalg import track
from ilocalg.fusion.heading_offset import rotate_xy
from ilocalg.io.ilc import ilc_fingerprints, load_ilc_floor
from ilocalg.wifi import KnnFingerprint

DATASET = "ilc2020_site2_F4"
SHORT = ["5dd5205dd48f840006f149d3", "5dd5260750e04e0006f564f1"]


@pytest.fixture(scope="module")
def floor():
    from ilocalg.io.paths import dataset_path

    p = dataset_path(DATASET)
    if not p.is_dir():
        pytest.skip(f"{p} not found")
    return load_ilc_floor(p, duplicate_bssid="keep_latest")


@pytest.mark.realdata
def test_leave_one_walk_out_is_enforced(shared_data, floor):
    shared_data(DATASET)
    name = SHORT[0]
    db = track.WifiDatabase.from_traces(floor.traces)
    with pytest.raises(ValueError, match="must not contain the scored walk"):
        track.wifi_fixes(floor.traces[name], db)
    fx = track.wifi_fixes(floor.traces[name], db.without(name))
    assert fx.xy_m.shape == (fx.t_s.size, 2) and np.all(np.diff(fx.t_s) > 0)
    with pytest.raises(ValueError, match="must not include the scored walk"):
        track.evaluate_track(floor.traces[name], floor.traces)
    assert name not in set(db.without(name).walk)


@pytest.mark.realdata
def test_wknn_fixes_agree_with_the_estimator(shared_data, floor):
    """locate_wknn is KnnFingerprint's prediction, plus a neighbour-spread covariance."""
    shared_data(DATASET)
    db = track.WifiDatabase.from_traces(floor.traces).without(SHORT[0])
    cfg = track.RealWalkConfig()
    fx = track.wifi_fixes(floor.traces[SHORT[0]], db, cfg)
    est = KnnFingerprint(n_neighbors=cfg.k_neighbors, p=cfg.p, weights=cfg.weights, not_heard_dbm=cfg.not_heard_dbm,
                         kernel="dense", metric=cfg.metric).fit(db.rssi_dbm, db.xy_m)
    own = track.WifiDatabase.from_traces([floor.traces[SHORT[0]]])      # the walk's scans as queries
    X = np.column_stack([own.rssi_dbm[:, own.ap_ids.index(a)] if a in own.ap_ids else np.full(len(own.xy_m), np.nan)
                         for a in db.ap_ids])
    xy, C = track.locate_wknn(db, X, cfg)
    np.testing.assert_allclose(xy, est.predict(X), atol=1e-9)
    assert (np.linalg.eigvalsh(C) >= 1.0 - 1e-9).all()          # min_var 1 m^2 on the diagonal
    # wifi_fixes gives the same positions for the same scans (its own pivot of the walk's scans)
    t_own = ilc_fingerprints([floor.traces[SHORT[0]]], outside="drop").fingerprints.meta["t_s"].to_numpy()
    heard = ~np.isnan(X).all(axis=1)
    i = np.searchsorted(fx.t_s, t_own[heard])
    np.testing.assert_array_equal(fx.t_s[i], t_own[heard])
    np.testing.assert_allclose(fx.xy_m[i], xy[heard], atol=1e-9)
    # stale readings left out: never more fixes, every fix still finite
    fresh = track.wifi_fixes(floor.traces[SHORT[0]], db, dataclasses.replace(cfg, max_age_s=2.0))
    assert fresh.t_s.size <= fx.t_s.size and np.isfinite(fresh.xy_m).all()


@pytest.mark.realdata
def test_calibration_recovers_offset_of_rotated_walks(shared_data, floor):
    """The floor offset is learned from waypoints: rotating every walk's waypoints by 30 deg shifts it by 30."""
    shared_data(DATASET)
    names = floor.names[:6]
    steps = {n: track.walk_steps(floor.traces[n]) for n in names}
    base = track.calibrate({n: floor.traces[n] for n in names}, steps)
    rot = {}
    for n in names:
        tr = floor.traces[n]
        wp = tr.waypoints.copy()
        wp[["x_m", "y_m"]] = rotate_xy(wp[["x_m", "y_m"]].to_numpy(), np.deg2rad(30.0))
        rot[n] = dataclasses.replace(tr, waypoints=wp)
    r = track.calibrate(rot, steps)
    assert np.rad2deg(r.offset_rad - base.offset_rad) == pytest.approx(30.0, abs=1e-6)
    assert r.k_weinberg == pytest.approx(base.k_weinberg)
    assert 0.3 < base.k_weinberg < 0.7 and abs(np.rad2deg(base.offset_rad)) < 20


@pytest.mark.realdata
def test_evaluate_track_scores_every_method_and_smoothing_helps(shared_data, floor):
    shared_data(DATASET)
    name = SHORT[0]
    others = {k: v for k, v in floor.traces.items() if k != name}
    cfg = track.RealWalkConfig(n_particles=200, grid_cell_m=1.0)
    r = track.evaluate_track(floor.traces[name], others, floor_map=floor.floor_map, cfg=cfg, rng=0, select=False)
    e = r["errors"]
    assert len(e) == len(floor.traces[name].waypoints)
    assert np.isfinite(e[list(track.METHODS)].to_numpy()).all() and (e[list(track.METHODS)].mean() < 30).all()
    assert r["info"]["wifi_config"] == "given"
    for m, xy in r["tracks"].items():
        assert xy.shape == (r["state_t_s"].size, 2), m
    # the whole-walk placement on all fixes is never worse than starting at the first fix on this walk
    assert e["aligned"].mean() <= e["pdr"].mean() + 1e-9
    r2 = track.evaluate_track(floor.traces[name], others, floor_map=floor.floor_map, cfg=cfg, rng=0, select=False)
    assert r2["errors"].equals(e)
    with pytest.raises(ValueError, match="unknown methods"):
        track.evaluate_walk(floor.traces[name], track.WifiDatabase.from_traces(others), None, 25.0, methods=("x",))
