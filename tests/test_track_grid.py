"""The survey's marked points (ilocalg.track.grid) and the *_grid variants located on them at the query times."""

import numpy as np
import pytest

from ilocalg.track._config import CAUSAL_METHODS, GRID_METHODS, METHODS
from ilocalg.track.grid import bend_track, grid_hmm, off_grid_share, survey_points
from ilocalg.track.paths import WalkedPaths
from tests.track_sim import SITE1_WALK, site1_floor


def _marked_walk(seed, bias_sd=3.0, noise_sd=1.0, step_sd=0.35):
    """Marked points on a 4 m lattice; a walk whose query positions are lattice points (a random route, 10 steps of
    0.7 m between queries), its base estimates off by a persistent bias plus noise, its PDR noisy per step."""
    rng = np.random.default_rng(seed)
    lat = np.array([[x, y] for x in np.arange(0.0, 80.0, 4.0) for y in np.arange(0.0, 40.0, 6.0)])
    lat = lat + rng.normal(0, 0.6, lat.shape)             # the marked points are not a perfect lattice
    k = rng.integers(len(lat))
    route = [k]
    for _ in range(11):
        d = np.hypot(*(lat - lat[route[-1]]).T)
        near = np.flatnonzero((d > 2.0) & (d < 9.0))
        route.append(int(rng.choice(near)))
    truth = lat[route]
    n = np.arange(len(route)) * 10.0
    pdr = np.vstack([[0.0, 0.0], np.cumsum(np.diff(truth, axis=0) + rng.normal(0, step_sd * np.sqrt(10), (11, 2)),
                                           axis=0)])
    est = truth + rng.normal(0, bias_sd, 2) + rng.normal(0, noise_sd, truth.shape)
    return lat, truth, est, pdr, n


def _scores(bias_sd, noise_sd, seeds=range(12)):
    """Mean error per walk of the base estimates and of the offline / online grid variants."""
    base, grid_off, grid_on = [], [], []
    for seed in seeds:
        lat, truth, est, pdr, n = _marked_walk(seed, bias_sd, noise_sd)
        var = bias_sd ** 2 + noise_sd ** 2
        for causal, acc in ((False, grid_off), (True, grid_on)):
            xy, on = grid_hmm(est, pdr, n, lat, var, 0.35 ** 2, 0.1, causal=causal)
            assert xy.shape == truth.shape and on.dtype == bool
            # a query on a point is exactly that point; one off the points keeps the base estimate
            if on.any():
                assert np.sqrt(((xy[on][:, None] - lat[None]) ** 2).sum(-1)).min(axis=1).max() < 1e-12
            np.testing.assert_array_equal(xy[~on], est[~on])
            acc.append(np.hypot(*(xy - truth).T).mean())
        base.append(np.hypot(*(est - truth).T).mean())
    return map(np.array, (base, grid_off, grid_on))


def test_grid_variant_is_never_worse_than_its_base_on_a_walk_standing_on_marked_points():
    # the base's error well inside half the points' spacing (4 x 6 m): never worse, walk by walk
    base, grid_off, grid_on = _scores(1.0, 0.5)
    assert np.all(grid_off <= base + 1e-9), (grid_off, base)
    assert np.all(grid_on <= base + 1e-9), (grid_on, base)
    assert grid_off.mean() < 0.2 * base.mean() and grid_on.mean() < 0.3 * base.mean()
    # a persistent error as large as the spacing (3 m sd): the decoded route may be a shifted one, worse on some
    # walks (as on 8-14 of the 50 site1 F1 development walks), better on average
    base, grid_off, grid_on = _scores(3.0, 1.0)
    assert grid_off.mean() < 0.5 * base.mean() and grid_on.mean() < 0.8 * base.mean()
    assert np.any(grid_off > base)


def test_online_grid_estimate_at_a_time_does_not_change_when_later_data_change():
    lat, truth, est, pdr, n = _marked_walk(3)
    xy, _ = grid_hmm(est, pdr, n, lat, 10.0, 0.12, 0.1, causal=True)
    for k in range(1, len(est) - 1):
        est2, pdr2 = est.copy(), pdr.copy()
        est2[k + 1:] += 7.0
        pdr2[k + 1:] -= 5.0
        xy2, _ = grid_hmm(est2, pdr2, n, lat, 10.0, 0.12, 0.1, causal=True)
        np.testing.assert_array_equal(xy2[:k + 1], xy[:k + 1])
        # the Viterbi path (offline) may change: it uses the whole walk
    # the drawn online track holds the latest earlier correction: states before a query do not see it
    ts = np.arange(0.0, 60.0, 0.5)
    states = np.column_stack([ts, np.zeros_like(ts)])
    tq = np.array([10.0, 20.0, 30.0])
    qxy = np.array([[10.0, 1.0], [20.0, 2.0], [30.0, 3.0]])
    b = bend_track(ts, states, tq, qxy, causal=True)
    np.testing.assert_array_equal(b[ts < 10.0], states[ts < 10.0])
    assert np.allclose(b[(ts >= 20.0) & (ts < 30.0), 1], 2.0)
    off = bend_track(ts, states, tq, qxy, causal=False)
    np.testing.assert_allclose(np.interp(tq, ts, off[:, 1]), qxy[:, 1])


def test_a_walk_far_from_every_marked_point_keeps_its_base_estimate():
    lat, truth, est, pdr, n = _marked_walk(1)
    far = est + 500.0
    xy, on = grid_hmm(far, pdr, n, lat, 9.0, 0.12, 0.1, causal=False)
    np.testing.assert_array_equal(xy, far)
    assert not on.any()
    # no database walk stands where another stood (a sparse survey): every query keeps its base estimate
    xy, on = grid_hmm(est, pdr, n, lat, 9.0, 0.12, 1.0, causal=True)
    np.testing.assert_array_equal(xy, est)
    assert not on.any()
    with pytest.raises(ValueError, match="off_share"):
        grid_hmm(est, pdr, n, lat, 9.0, 0.12, 1.5, causal=False)


def test_survey_points_and_the_share_off_them():
    g = WalkedPaths.from_polylines({"a": [[0, 0], [4, 0], [8, 0]], "b": [[0, 0.05], [4, 0], [8, 3]],
                                    "c": [[0, 0], [8, 0]]})
    pts = survey_points(g)
    assert pts.shape == (5, 2)                     # (0, 0), (4, 0), (8, 0), (0, 0.05), (8, 3): each once
    # walk a: all 3 on others' points; b: (0, 0.05) within 0.1 m of (0, 0), (8, 3) alone; c: both on
    assert off_grid_share(g) == pytest.approx(1 / 8)
    assert off_grid_share(g, tol_m=0.01) == pytest.approx(2 / 8)


def _off_share_per_walk(paths, tol_m):
    """The definition, walk by walk: each walk's distinct points against a tree of the other walks' points."""
    from scipy.spatial import cKDTree

    pts, walk = np.vstack([paths.a_m, paths.b_m]), np.concatenate([paths.walk, paths.walk])
    r, n_off, n = np.round(pts, 3), 0, 0
    for w in dict.fromkeys(walk):
        own = np.unique(r[walk == w], axis=0)
        n_off += int((cKDTree(r[walk != w]).query(own)[0] > tol_m).sum())
        n += own.shape[0]
    return n_off / n


@pytest.mark.parametrize("seed", range(6))
def test_off_grid_share_equals_the_per_walk_definition(seed):
    # points on a 0.05 m lattice (many shared, many exactly 0.1 m apart: the tolerance's edge) and some off it
    rng = np.random.default_rng(seed)
    polys = {}
    for w in range(int(rng.integers(2, 12))):
        p = rng.integers(0, 8, size=(int(rng.integers(2, 9)), 2)) * 0.05
        off = rng.random(len(p)) < 0.3
        p[off] += rng.normal(0.0, 0.07, size=(int(off.sum()), 2))
        polys[f"w{w}"] = (p + 100.0 * seed).tolist()
    g = WalkedPaths.from_polylines(polys)
    for tol in (0.05, 0.1, 0.15, 1.0):
        assert off_grid_share(WalkedPaths.from_polylines(polys), tol) == _off_share_per_walk(g, tol)


def test_grid_methods_are_registered_with_their_bases():
    for m, base in GRID_METHODS.items():
        assert m in METHODS and base in METHODS
        assert (m in CAUSAL_METHODS) == (base in CAUSAL_METHODS)


def test_grid_variants_on_a_site1_walk(shared_data):
    """site1 F1, 24 walks as the database (every 4th walk: a sparse survey, most of whose waypoints no other of them
    shares): the grid variants are located at the scored walk's waypoint times, from the other walks' waypoints
    only; here the measured share off the marked points is high, so the "no marked point" state keeps every query
    at its base estimate (on the full floor, 11 % of the waypoints are off them)."""
    from ilocalg.fusion.particle_filter import OccupancyGrid
    from ilocalg.track import RealWalkConfig, build_floor_model, evaluate_walk

    scored = SITE1_WALK
    fl = site1_floor(shared_data("ilc2020_site1"))
    cfg = RealWalkConfig(n_particles=300)
    model = build_floor_model({k: v for k, v in fl.traces.items() if k != scored}, cfg)
    wm = model.for_walk(scored, cfg)
    grid = OccupancyGrid.from_floor_map(fl.floor_map, 0.5)
    methods = ("wifi", "lsq", "lsq_grid", "kf_gain_map", "kf_gain_map_grid")
    kw = dict(grid=grid, rng=0, methods=methods, step_var_m2=wm.step_var_m2, gain=wm.gain)
    r = evaluate_walk(fl.traces[scored], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, survey=model.walk_paths,
                      **kw)
    assert r["info"]["grid_off_share"] == pytest.approx(off_grid_share(model.walk_paths))
    assert r["info"]["grid_off_share"] > 0.5
    e = r["errors"]
    for m in ("lsq_grid", "kf_gain_map_grid"):
        tq, xy, on = r["grid"][m]
        np.testing.assert_array_equal(tq, e["t_s"].to_numpy())      # the query times: the waypoints' times
        assert not on.any()
        np.testing.assert_allclose(e[m], e[GRID_METHODS[m]], atol=1e-9)
    assert np.isfinite(e[["lsq_grid", "kf_gain_map_grid"]].to_numpy()).all()
    # the scored walk's own waypoints are never marked points; the database's scan positions are not either
    with pytest.raises(ValueError, match="must not include the scored walk"):
        evaluate_walk(fl.traces[scored], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg,
                      survey=WalkedPaths.from_recordings(fl.traces, wm.db.frame), **kw)
    with pytest.raises(ValueError, match="waypoints"):
        evaluate_walk(fl.traces[scored], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, **kw)
