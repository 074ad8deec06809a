"""The track pipeline (ilocalg.track) on the real ILC 2.0 site2/F4 walks, leave-one-walk-out."""

import dataclasses

import numpy as np
import pandas as pd
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
    return load_ilc_floor(p, duplicate_bssid="keep_latest", relisted_wifi="keep")


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
    cfg = track.RealWalkConfig(max_age_s=None)                          # every reading: KnnFingerprint sees them all
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


# ---------------------------------------------------------------------------------------------------
# format-neutral: simulated walks (no real data needed)
# ---------------------------------------------------------------------------------------------------

# every method that runs without the floor map (the particle filter then runs unconstrained)
NO_MAP = tuple(m for m in track.METHODS if m not in track.MAP_METHODS or m.startswith("pf"))


@pytest.fixture(scope="module")
def sim_walks():
    from ilocalg.sim import walk_recordings as wr

    return wr.simulate_recordings(8, seed=11, n_nodes=35)[1]


def _reload(recs, tmp_path, fmt):
    from ilocalg.io import load_recording, write_ilc_trace, write_ipin_logfile

    write = write_ipin_logfile if fmt == "ipin" else write_ilc_trace
    return [load_recording(write(r, tmp_path / f"{r.name}.{fmt}"), format=fmt,
                           **({"duplicate_bssid": "error"} if fmt == "ilc" else {})) for r in recs]


def test_ipin_and_ilc_exports_give_the_same_track(sim_walks, tmp_path):
    """The same walks written as IPIN logfiles and as ILC traces: the same fixes, steps and tracks (in one frame).

    Exact up to the ILC clock: ILC stores Unix milliseconds, so its float times differ from the IPIN
    file's by ~1e-7 s, which can move a step peak that falls midway between two 50 Hz samples to the
    other sample (the step's heading is then read one sample away).
    """
    # every reading counts: IPIN logfiles carry no last-seen time, ILC traces do (an age limit would drop
    # readings from the ILC copy only)
    cfg = track.RealWalkConfig(n_particles=200, max_age_s=None)
    out = {}
    for fmt in ("ipin", "ilc"):
        recs = _reload(sim_walks, tmp_path, fmt)
        out[fmt] = track.evaluate_track(recs[0], recs[1:], cfg=cfg, rng=0, methods=NO_MAP, select=False)
        if fmt == "ipin":
            ipin_frame = recs[1].frame               # the database's frame: the first fingerprint logfile's
    a, b = out["ipin"], out["ilc"]
    sim_frame = sim_walks[0].frame
    assert a["info"]["wifi_config"] == b["info"]["wifi_config"]
    assert a["info"]["n_steps"] == b["info"]["n_steps"] and a["info"]["n_fixes"] == b["info"]["n_fixes"]
    # a step peak moved by one sample (the clock, above) moves the fitted factor and fix sd in the 5th digit
    assert a["info"]["k_weinberg"] == pytest.approx(b["info"]["k_weinberg"], rel=1e-4)
    assert a["info"]["fix_sd_m"] == pytest.approx(b["info"]["fix_sd_m"], rel=1e-4)
    np.testing.assert_allclose(sim_frame.to_xy(*ipin_frame.to_latlon(*a["fixes"].xy_m.T).T), b["fixes"].xy_m,
                               atol=1e-6)
    np.testing.assert_allclose(a["state_t_s"] - a["state_t_s"][0], b["state_t_s"] - b["state_t_s"][0], atol=1e-6)
    for m in NO_MAP:
        if m == "wifi":
            continue
        xy = sim_frame.to_xy(*ipin_frame.to_latlon(*a["tracks"][m].T).T)
        if m.startswith("pf"):
            # resampling turns the clock's 1e-7 s into other particle draws: same accuracy, not the same path
            assert abs(a["errors"][m].mean() - b["errors"][m].mean()) < 0.5, m
            continue
        # a few steps' headings read one sample apart: decimetres, never more (a wrong frame would be metres)
        assert np.hypot(*(xy - b["tracks"][m]).T).max() < 0.3, m
        assert abs(a["errors"][m].mean() - b["errors"][m].mean()) < 0.15, m
    np.testing.assert_allclose(a["errors"]["wifi"], b["errors"]["wifi"], atol=1e-6)
    assert a["floors"] is not None and b["floors"] is None      # only the IPIN format carries floors


def test_fusion_beats_wifi_on_simulated_walks(sim_walks):
    """Seeded property: on every simulated walk the smoothed fusion is closer to the truth than Wi-Fi only."""
    ratios = []
    for i in range(3):
        others = [w for j, w in enumerate(sim_walks) if j != i]
        r = track.evaluate_track(sim_walks[i], others, cfg=track.RealWalkConfig(), methods=track.METHODS[:4],
                                 select=False)
        s = track.summary_table(r).set_index("method")
        ratios.append(s.loc["kf_rts", "mean_m"] / s.loc["wifi", "mean_m"])
        assert set(s.columns) >= {"mean_m", "median_m", "p75_m", "p95_m", "floor_hit_rate", "penalised_mean_m"}
        assert (s["floor_hit_rate"] == 1.0).all()       # one floor
        tt = r["track"]
        assert set(tt["method"]) >= set(track.METHODS[:4]) and (tt.groupby("method").size()["kf"] ==
                                                                 r["state_t_s"].size)
    assert np.mean(ratios) < 0.9, ratios


def test_scored_walk_is_refused_by_content(sim_walks):
    renamed = dataclasses.replace(sim_walks[0], name="another_name", source="elsewhere.txt")
    with pytest.raises(ValueError, match="same sensor content"):
        track.evaluate_track(sim_walks[0], [renamed, *sim_walks[1:4]], methods=NO_MAP)
    db = track.WifiDatabase.from_recordings([renamed, *sim_walks[1:4]])
    with pytest.raises(ValueError, match="same sensor content"):
        track.wifi_fixes(sim_walks[0], db)


def test_scans_outside_the_walk_are_left_out_and_counted(sim_walks):
    r = sim_walks[0]
    db = track.WifiDatabase.from_recordings(sim_walks[1:])
    base = track.wifi_fixes(r, db)
    w = r.wifi
    t_end = r.imu.index[-1]
    late = w[w["scan_id"] == w["scan_id"].max()].assign(t_s=t_end + 30.0, scan_id=w["scan_id"].max() + 1)
    early = w[w["scan_id"] == 0].assign(t_s=r.imu.index[0] - 5.0, scan_id=-1)
    odd = dataclasses.replace(r, wifi=pd.concat([early, w, late], ignore_index=True))
    fx = track.wifi_fixes(odd, db)
    assert fx.n_outside_walk == 2 and base.n_outside_walk == 0
    np.testing.assert_array_equal(fx.xy_m, base.xy_m)
    deaf = w.assign(bssid="00:00:00:00:00:01")[w["scan_id"] == 1].assign(scan_id=w["scan_id"].max() + 5,
                                                                        t_s=w["t_s"].max() + 0.5)
    fx2 = track.wifi_fixes(dataclasses.replace(r, wifi=pd.concat([w, deaf], ignore_index=True)), db)
    assert fx2.n_no_shared_ap == 1 and fx2.t_s.size == base.t_s.size


def test_floors_from_wifi_and_barometer():
    """Walks that change floor: the barometer finds the change; Wi-Fi + barometer gets the floor of every point."""
    from ilocalg.sim import walk_recordings as wr

    # the mechanics on the uncalibrated gait world (with the calibrated hand yaw wander of 19 deg the Wi-Fi-only
    # floors beat Wi-Fi + barometer on these walks: open, see the CHANGELOG)
    _, walks = wr.simulate_recordings(10, seed=5, n_floors=2, n_nodes=35, floor_changes=True, world="copied")
    climbing = [i for i, w in enumerate(walks) if w.meta["floor_to"] is not None]
    hits = {"baro": [], "wifi_only": []}
    for i in climbing[:3]:
        w = walks[i]
        seg = track.barometric_segments(w.pressure)
        assert len(seg) == 2                                   # one level change
        assert abs(seg["height_m"].diff().iloc[1]) == pytest.approx(3.5, abs=0.5)
        others = [x for j, x in enumerate(walks) if j != i]
        r = track.evaluate_track(w, others, methods=("wifi", "kf", "kf_rts"), select=False)
        fl = r["floors"]
        hits["baro"].append(float((fl["kf_rts"] == fl["floor_true"]).mean()))
        r2 = track.evaluate_track(dataclasses.replace(w, pressure=None), others, methods=("wifi", "kf_rts"),
                                  select=False)
        hits["wifi_only"].append(float((r2["floors"]["kf_rts"] == r2["floors"]["floor_true"]).mean()))
        assert r["scans"]["floor_source"] == "wifi+barometer" and r2["scans"]["floor_source"] == "wifi"
    assert min(hits["baro"]) >= 0.9 and np.mean(hits["baro"]) >= np.mean(hits["wifi_only"]), hits
    # penalised error: +15 m per wrong floor, from ilocalg.metrics
    et = track.error_table(r)
    wrong = ~et["floor_hit"]
    np.testing.assert_allclose(et["penalised_error_m"][~wrong], et["error_m"][~wrong])
    np.testing.assert_allclose(et["penalised_error_m"][wrong],
                               et["error_m"][wrong] + 15.0 * (et["floor"] - et["floor_true"]).abs()[wrong])


def test_map_methods_run_on_a_walkable_grid_in_the_walks_frame():
    """A floor map given as a walkable raster in the walks' own frame: particle filter and map matching."""
    from ilocalg.fusion.particle_filter import OccupancyGrid
    from ilocalg.sim import walk_recordings as wr

    # the mechanics on the uncalibrated gait world (the calibrated 19 deg hand yaw wander bends the PDR shape that
    # map_align places: open, see the CHANGELOG)
    b, walks = wr.simulate_recordings(8, seed=13, n_nodes=35, world="copied")
    grid = OccupancyGrid.from_polygons(b.corridor_rings(), cell_m=0.5)
    r = track.evaluate_track(walks[0], walks[1:], floor_map=grid, cfg=track.RealWalkConfig(n_particles=300),
                             select=False)
    e = r["errors"]
    assert np.isfinite(e[list(track.METHODS)].to_numpy()).all()
    # no accuracy claim for the map-only placements on this symmetric corridor graph (map matching or the
    # particle filter can lock onto a parallel corridor); the KF started from the map placement stays sane
    assert e["map_align_kf_rts"].mean() < 2 * e["wifi"].mean()
    # the map-constrained states lie on the corridors (the particle filter's mean may cut a corner)
    # a rigid placement among those the Wi-Fi fixes accept (map_align's wifi_margin): most states on the map, and
    # never far from where the fixes put the walk
    assert grid.walkable(*r["tracks"]["map_align"].T).mean() > 0.6
    assert e["map_align"].mean() < 1.5 * e["wifi"].mean()
