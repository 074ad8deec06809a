"""The least-squares trajectory estimators (ilocalg.track.estimators) and the floor model's pieces."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.fusion.particle_filter import OccupancyGrid
from ilocalg.io.scans import merge_relisted_wifi, relisted_readings
from ilocalg.track.estimators import TrackProblem, lsq_causal_track, lsq_solve, lsq_track, snap_to_map
from tests.track_sim import SITE1_WALK, site1_floor


def _walk(seed=0, n=120, fix_sd=4.0, step_sd=0.2):
    rng = np.random.default_rng(seed)
    th = np.cumsum(rng.normal(0, 0.05, n))
    true_d = 0.7 * np.column_stack([np.cos(th), np.sin(th)])
    truth = np.vstack([[0.0, 0.0], np.cumsum(true_d, 0)])
    ts = np.arange(n + 1) * 0.5
    fi = np.arange(0, n + 1, 4)
    fixes = truth[fi] + rng.normal(0, fix_sd, (fi.size, 2))
    disp = true_d + rng.normal(0, step_sd, true_d.shape)
    return TrackProblem(ts, disp, step_sd ** 2, ts[fi], fixes, fix_sd ** 2), truth


def test_lsq_matches_dense_weighted_least_squares():
    p, _ = _walk()
    x = lsq_track(p, n_iter=1)
    n = p.state_t_s.size
    rows, b, w = [], [], []
    for i, d in enumerate(p.disp_m):
        r = np.zeros(n)
        r[i], r[i + 1] = -1, 1
        rows.append(r), b.append(d), w.append(1 / p.step_var_m2)
    for t, z in zip(p.fix_t_s, p.fix_xy_m, strict=True):
        r = np.zeros(n)
        r[int(np.searchsorted(p.state_t_s, t))] = 1
        rows.append(r), b.append(z), w.append(1 / p.fix_var_m2)
    A, B, W = np.array(rows), np.array(b), np.sqrt(np.array(w))[:, None]
    ref = np.linalg.lstsq(A * W, B * W, rcond=None)[0]
    np.testing.assert_allclose(x, ref, atol=1e-4)      # the solver adds 1e-9 I


@pytest.mark.parametrize("corr", [None, (0.6, 0.8, 5.0)])
def test_lsq_solve_has_the_bits_of_a_spsolve_per_axis(corr, monkeypatch):
    """One SuperLU factorisation per Huber round for both axes gives the bits of a spsolve per axis (the solver
    as written before), Huber rounds, per-fix variances, anchors and correlated fix errors included."""
    import scipy.sparse.linalg as sla

    import ilocalg.track.estimators as est

    p, _ = _walk(seed=3)
    j, a = est._interp_rows(p.state_t_s, p.fix_t_s)
    fv = np.linspace(4.0, 30.0, j.size)
    fv[5] = 0.5                                                   # an outlier's weight to re-weight
    kw = dict(anchor_idx=[10, 40], anchor_xy_m=[[1.0, 2.0], [5.0, -3.0]], fix_corr=corr)
    got = lsq_solve(p.state_t_s.size, p.disp_m, p.step_var_m2, j, a, p.fix_xy_m, fv, **kw)

    class PerAxis:          # splu's stand-in: spsolve for each right-hand side, as the solver did
        def __init__(self, N):
            self.N = N

        def solve(self, rhs):
            return sla.spsolve(self.N, rhs)

    monkeypatch.setattr(est, "splu", PerAxis)
    ref = lsq_solve(p.state_t_s.size, p.disp_m, p.step_var_m2, j, a, p.fix_xy_m, fv, **kw)
    np.testing.assert_array_equal(got.view(np.uint64), ref.view(np.uint64))


def test_lsq_beats_fixes_and_causal_is_causal():
    errs = {"fix": [], "lsq": [], "online": []}
    for seed in range(5):
        p, truth = _walk(seed)
        fi = np.searchsorted(p.state_t_s, p.fix_t_s)
        errs["fix"].append(np.hypot(*(p.fix_xy_m - truth[fi]).T).mean())
        errs["lsq"].append(np.hypot(*(lsq_track(p) - truth).T).mean())
        errs["online"].append(np.hypot(*(lsq_causal_track(p) - truth).T).mean())
    assert np.mean(errs["lsq"]) < 0.5 * np.mean(errs["fix"])
    assert np.mean(errs["online"]) < np.mean(errs["fix"])
    # causal: changing the data after state 60 leaves states 0..59 unchanged
    p, _ = _walk(1)
    a = lsq_causal_track(p)
    late = p.fix_t_s > p.state_t_s[60]
    q = TrackProblem(p.state_t_s, p.disp_m, p.step_var_m2, p.fix_t_s, np.where(late[:, None], p.fix_xy_m + 50,
                     p.fix_xy_m), p.fix_var_m2)
    np.testing.assert_allclose(lsq_causal_track(q)[:60], a[:60])


def test_huber_resists_an_outlier_fix():
    p, truth = _walk(2)
    z = p.fix_xy_m.copy()
    z[10] += 80.0
    q = TrackProblem(p.state_t_s, p.disp_m, p.step_var_m2, p.fix_t_s, z, p.fix_var_m2)
    plain = np.hypot(*(lsq_solve(p.state_t_s.size, p.disp_m, p.step_var_m2,
                                 np.searchsorted(p.state_t_s, p.fix_t_s), np.zeros(z.shape[0]), z,
                                 p.fix_var_m2, n_iter=1) - truth).T).mean()
    robust = np.hypot(*(lsq_track(q) - truth).T).mean()
    assert robust < plain


def test_snap_to_map_moves_only_off_map_points():
    mask = np.zeros((10, 10), dtype=bool)
    mask[4:6, :] = True                       # a corridor y in [2, 3) m
    g = OccupancyGrid(mask, 0.0, 0.0, 0.5)
    xy = np.array([[1.0, 2.2], [1.0, 4.6], [-3.0, 2.4]])
    out, moved = snap_to_map(xy, g)
    assert moved.tolist() == [False, True, True]
    np.testing.assert_allclose(out[0], xy[0])
    assert 2.0 <= out[1, 1] < 3.0 and 2.0 <= out[2, 1] < 3.0


def test_problem_rejects_bad_shapes():
    with pytest.raises(ValueError, match="disp_m"):
        TrackProblem(np.arange(3.0), np.zeros((3, 2)), 1.0, np.zeros(1), np.zeros((1, 2)), 1.0)
    with pytest.raises(ValueError, match="at least one"):
        TrackProblem(np.arange(3.0), np.zeros((2, 2)), 1.0, np.zeros(0), np.zeros((0, 2)), 1.0)


def test_relisted_rule_and_merge():
    w = pd.DataFrame({"t_s": [0.0, 0.0, 2.0, 2.0, 4.0, 4.0], "scan_id": [0, 0, 1, 1, 2, 2],
                      "bssid": ["a", "b", "a", "b", "a", "b"], "rssi_dbm": [-50, -60, -50, -61, -50, -60],
                      "last_seen_s": [-0.5, -0.2, -0.499, 1.9, -0.5, 1.9]})
    rel = relisted_readings(w)
    # a re-listed in scans 1 and 2 (same RSSI, last seen within 1 ms); b changed RSSI, then re-listed
    assert rel.tolist() == [False, False, True, False, True, False]
    m, n = merge_relisted_wifi(w)
    assert n == 2 and len(m) == 4


def test_ilc_loader_policy_refuses_naming_file_and_line(tmp_path):
    from ilocalg.io.ilc import parse_ilc_trace

    lines = []
    for t in range(1000, 3000, 20):
        for typ in ("TYPE_ACCELEROMETER", "TYPE_GYROSCOPE", "TYPE_MAGNETIC_FIELD"):
            lines.append(f"{t}\t{typ}\t0.1\t0.2\t9.8\t3")
    lines.insert(0, "1000\tTYPE_WAYPOINT\t1.0\t2.0")
    lines.append("2990\tTYPE_WAYPOINT\t3.0\t4.0")
    lines.append("1500\tTYPE_WIFI\tx\taa:bb\t-50\t2412\t1400")
    lines.append("2500\tTYPE_WIFI\tx\taa:bb\t-50\t2412\t1401")
    text = "\n".join(sorted(lines, key=lambda s: int(s.split("\t")[0]))) + "\n"
    with pytest.raises(ValueError, match=r"walk\.txt: line \d+: .*relisted_wifi='merge'"):
        parse_ilc_trace(text, "walk.txt", relisted_wifi="refuse")
    tr = parse_ilc_trace(text, "walk.txt", relisted_wifi="merge")
    assert len(tr.wifi) == 1 and tr.skipped["TYPE_WIFI relisted reading"] == 1
    assert len(parse_ilc_trace(text, "walk.txt", relisted_wifi="keep").wifi) == 2


@pytest.mark.realdata
def test_map_methods_not_worse_than_wifi_on_a_site1_walk(shared_data):
    """On the densely surveyed site1 F1 (here 24 walks as the database), map matching and the particle filter
    place the walk where its Wi-Fi fixes are: before the map term was de-correlated, map_align put this walk
    33 m away (Wi-Fi 4.5 m) in a wholly walkable placement, and on site1 the map variants averaged 15-17 m."""
    from ilocalg.fusion.particle_filter import OccupancyGrid
    from ilocalg.track import RealWalkConfig, build_floor_model, evaluate_walk

    scored = SITE1_WALK
    fl = site1_floor(shared_data("ilc2020_site1"))
    cfg = RealWalkConfig(n_particles=300)
    wm = build_floor_model({k: v for k, v in fl.traces.items() if k != scored}, cfg).for_walk(scored, cfg)
    grid = OccupancyGrid.from_floor_map(fl.floor_map, 0.5)
    r = evaluate_walk(fl.traces[scored], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, grid=grid, rng=0,
                      methods=("wifi", "pf", "pf_smooth", "map_align", "lsq_map"), step_var_m2=wm.step_var_m2)
    e = r["errors"].mean()
    for m in ("pf", "pf_smooth", "map_align", "lsq_map"):
        assert e[m] < 1.5 * e["wifi"], (m, e[m], e["wifi"])


def test_floor_model_leaves_the_walk_out_exactly_and_survives_save_load(tmp_path):
    """FloorModel.for_walk(s) gives what a model built without s gives; save/load is lossless."""
    from ilocalg.sim import walk_recordings as wr
    from ilocalg.track import build_floor_model
    from ilocalg.track.fixes import calibrate_fix_var

    _, recs = wr.simulate_recordings(6, seed=5, n_nodes=20)
    full = build_floor_model(recs)
    full.save(tmp_path / "m")
    back = type(full).load(tmp_path / "m")
    np.testing.assert_array_equal(np.nan_to_num(back.db.rssi_dbm, nan=1), np.nan_to_num(full.db.rssi_dbm, nan=1))
    s = recs[2].name
    a = back.for_walk(s, select=False)
    b = build_floor_model([r for r in recs if r.name != s])
    cal_b = b.for_walk(None, select=False)
    assert a.calibration.k_weinberg == pytest.approx(cal_b.calibration.k_weinberg, rel=1e-9)
    assert a.calibration.offset_rad == pytest.approx(cal_b.calibration.offset_rad, abs=1e-9)
    assert a.step_var_m2 == pytest.approx(cal_b.step_var_m2, rel=1e-9)
    assert a.fix_var_m2 == pytest.approx(calibrate_fix_var(b.db)[0], rel=1e-9)
    with pytest.raises(ValueError, match="same sensor content"):
        back.for_walk("renamed", content_id=full.db.content_ids[s])


def test_causal_lsq_uses_a_fix_from_its_scan_time_for_its_readings_time():
    p, truth = _walk(2)
    lag = 1.0                                 # the readings are 1 s (two states) older than the scan
    q = TrackProblem(p.state_t_s, p.disp_m, p.step_var_m2, p.fix_t_s - lag, p.fix_xy_m, p.fix_var_m2,
                     fix_avail_t_s=p.fix_t_s)
    a = lsq_causal_track(q)
    # causal in the availability time: moving the fixes known after state 60 leaves states 0..59 unchanged
    late = q.fix_avail_t_s > p.state_t_s[60]
    r = TrackProblem(p.state_t_s, p.disp_m, p.step_var_m2, q.fix_t_s, np.where(late[:, None], p.fix_xy_m + 50,
                     p.fix_xy_m), p.fix_var_m2, fix_avail_t_s=q.fix_avail_t_s)
    np.testing.assert_allclose(lsq_causal_track(r)[:60], a[:60])
    # a fix tied to its readings' time fits a walk whose fixes describe the past better than one tied to the scan
    fi = np.searchsorted(p.state_t_s, p.fix_t_s)
    d = np.diff(truth, axis=0)                # exact steps: the fixes' timing is the only error
    lagged = TrackProblem(p.state_t_s, d, 0.01 ** 2, p.fix_t_s, truth[np.maximum(fi - 2, 0)], 0.3 ** 2)
    aligned = TrackProblem(p.state_t_s, d, 0.01 ** 2, p.fix_t_s - lag, truth[np.maximum(fi - 2, 0)], 0.3 ** 2,
                           fix_avail_t_s=p.fix_t_s)
    e_lag = np.hypot(*(lsq_track(lagged) - truth).T).mean()
    e_al = np.hypot(*(lsq_track(aligned) - truth).T).mean()
    assert e_al < 0.5 * e_lag
    with pytest.raises(ValueError, match="fix_avail_t_s"):
        TrackProblem(p.state_t_s, p.disp_m, 1.0, p.fix_t_s, p.fix_xy_m, 1.0, fix_avail_t_s=p.fix_t_s[:-1])


def test_effective_age_is_the_mean_fresh_reading_age():
    from ilocalg.track.database import effective_age_s

    a = np.array([[0.5, 1.5, 9.0], [np.nan, 3.0, 4.0], [np.nan, np.nan, np.nan], [0.0, np.nan, 2.0]])
    np.testing.assert_allclose(effective_age_s(a), [1.0, 3.0, 0.0, 1.0])


@pytest.mark.parametrize("rotate", [False, True])
def test_states_used_gives_the_same_states_and_nan_elsewhere(rotate):
    """TrackProblem.states_used: the causal least squares solves only where the used states rest on, and those
    states are the very numbers of the whole solve (bit for bit); the map variants snap them alike."""
    import dataclasses

    from ilocalg.track.estimators import ESTIMATORS, STATES_USED_METHODS

    p, _ = _walk(seed=3, n=160)
    rng = np.random.default_rng(3)
    p = dataclasses.replace(p, fix_avail_t_s=np.sort(p.fix_t_s + rng.uniform(0, 2.5, p.fix_t_s.size)),
                            fix_corr=(0.4, 0.7, 3.0))
    used = np.array([0, 1, 37, 38, 90, 91, 159, 160])
    q = dataclasses.replace(p, states_used=used)
    a, b = lsq_causal_track(p, rotate=rotate), lsq_causal_track(q, rotate=rotate)
    assert a[used].tobytes() == b[used].tobytes()
    assert np.isnan(np.delete(b, used, axis=0)).all()
    if not rotate:
        mask = np.ones((60, 200), dtype=bool)
        mask[:, 90:110] = False                     # a wall band the track crosses: some states snap
        grid = OccupancyGrid(mask, x0_m=-50.0, y0_m=-30.0, cell_m=1.0)
        pg, qg = (dataclasses.replace(r, grid=grid, map_start=True) for r in (p, q))
        for m in STATES_USED_METHODS:
            full, part = ESTIMATORS[m].fn(pg), ESTIMATORS[m].fn(qg)
            assert full[used].tobytes() == part[used].tobytes(), m
    with pytest.raises(ValueError, match="states_used"):
        dataclasses.replace(p, states_used=np.array([0, 161]))
