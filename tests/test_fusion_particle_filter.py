"""Map-constrained particle filter, occupancy raster, systematic resampling."""

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from ilocalg.fusion import filter_walk, straight_walk
from ilocalg.fusion.particle_filter import OccupancyGrid, map_particle_filter, systematic_resample
from ilocalg.io.ilc import points_in_polygon

SQUARE = np.array([[0, 0], [40, 0], [40, 30], [0, 30]], dtype=float)
HOLE = np.array([[10, 10], [30, 10], [30, 20], [10, 20]], dtype=float)


def _walkable(x, y):
    return points_in_polygon(x, y, SQUARE) & ~points_in_polygon(x, y, HOLE)


def test_raster_from_polygons_agrees_with_point_in_polygon():
    g = OccupancyGrid.from_polygons([SQUARE], [HOLE], cell_m=0.5)
    X, Y = np.meshgrid(0.25 + 0.5 * np.arange(80), 0.25 + 0.5 * np.arange(60))
    assert g.walkable_mask.shape == X.shape
    assert (g.walkable_mask == _walkable(X, Y)).mean() > 0.98     # cell centres, up to edge cells
    assert g.area_m2 == pytest.approx(40 * 30 - 20 * 10, rel=0.03)
    assert not g.walkable(20, 15) and g.walkable(5, 5) and not g.walkable(-1, 5)
    pts = g.sample(500, rng=0)
    assert g.walkable(pts[:, 0], pts[:, 1]).all()


def test_raster_of_a_floor_map_uses_its_size_and_polygons():
    fm = SimpleNamespace(outline=(SQUARE,), obstacles=(HOLE,), width_m=50.0, height_m=35.0)
    g = OccupancyGrid.from_floor_map(fm, cell_m=0.5)
    assert g.walkable_mask.shape == (70, 100) and (g.x0_m, g.y0_m) == (0.0, 0.0)
    np.testing.assert_array_equal(g.walkable_mask[:60, :80],
                                  OccupancyGrid.from_polygons([SQUARE], [HOLE], cell_m=0.5).walkable_mask)
    # nothing beyond the outline (fillPoly also fills the cells its edge touches)
    assert not g.walkable_mask[61:].any() and not g.walkable_mask[:, 81:].any()


def test_coarsen_keeps_a_cell_walkable_when_any_fine_cell_is():
    rng = np.random.default_rng(4)
    m = rng.random((41, 63)) < 0.05
    g = OccupancyGrid(m, 2.0, -1.0, 0.25)
    c = g.coarsen(1.0)
    assert c.cell_m == 1.0 and (c.x0_m, c.y0_m) == (2.0, -1.0) and c.walkable_mask.shape == (10, 15)
    for j, i in np.ndindex(c.walkable_mask.shape):
        assert c.walkable_mask[j, i] == m[4 * j:4 * j + 4, 4 * i:4 * i + 4].any()
    # a point walkable on the fine raster is walkable on the coarse one
    pts = g.sample(300, rng=1)
    inside = (pts[:, 0] < 2.0 + 15) & (pts[:, 1] < -1.0 + 10)
    assert c.walkable(pts[inside, 0], pts[inside, 1]).all()
    assert g.coarsen(0.25) is g and c.coarsen(1.0) is c
    with pytest.raises(ValueError, match="cell_m"):
        g.coarsen(0.0)


def test_systematic_resample_counts():
    w = np.array([0.5, 0.25, 0.25, 0.0])
    idx = systematic_resample(w, rng=0)
    counts = np.bincount(idx, minlength=4)
    np.testing.assert_array_equal(counts, [2, 1, 1, 0])    # systematic: within 1 of N w
    with pytest.raises(ValueError, match="positive sum"):
        systematic_resample([0.0, 0.0])


def _walk_inputs(seed=0, n=120, sigma_rf=4.0, bias=0.0):
    sw = straight_walk(n, rng=seed, sigma_rf_m=sigma_rf, fix_every=4, heading_bias_rad=bias, turn_every=30)
    R = np.broadcast_to(sigma_rf**2 * np.eye(2), (n + 1, 2, 2)).copy()
    return sw, R


def test_pf_without_map_is_close_to_the_kalman_filter_and_beats_dead_reckoning():
    sw, R = _walk_inputs()
    pf = map_particle_filter(sw.truth_xy_m[0], np.eye(2), sw.theta_rad, sw.step_m, sw.z_m, R, n_particles=2000,
                             rng=1, sigma_offset0_rad=0.02, sigma_heading_rad=0.05, outlier_prob=0.0)
    kf = filter_walk(sw.truth_xy_m[0], np.eye(2), sw.theta_rad, sw.step_m, 0.2, sw.z_m, r_var_m2=16.0,
                     sigma_theta_rad=0.05)
    e_pf = np.hypot(*(pf.x - sw.truth_xy_m).T).mean()
    e_kf = np.hypot(*(kf.x - sw.truth_xy_m).T).mean()
    e_fix = np.nanmean(np.hypot(*(sw.z_m - sw.truth_xy_m).T))
    assert e_pf < 0.7 * e_fix
    assert e_pf < 1.5 * e_kf
    # the ancestral-path smoother is a weak smoother (few distinct paths survive): better than the fixes only
    assert np.hypot(*(pf.x_smooth - sw.truth_xy_m).T).mean() < 0.5 * e_fix
    assert pf.n_reset == 0 and pf.n_blocked == 0


def test_pf_is_deterministic_and_map_keeps_particles_walkable():
    # a corridor 4 m wide along y = 2; the walk goes along it with a heading bias that would leave it
    corridor = OccupancyGrid.from_polygons([np.array([[-5, 0], [120, 0], [120, 4], [-5, 4]], float)], cell_m=0.25)
    n = 120
    theta = np.full(n, 0.08)                      # biased heading: dead reckoning drifts out of the corridor
    d = np.full(n, 0.7)
    z = np.full((n + 1, 2), np.nan)
    R = np.broadcast_to(25.0 * np.eye(2), (n + 1, 2, 2)).copy()
    a = map_particle_filter([0.0, 2.0], 0.25 * np.eye(2), theta, d, z, R, grid=corridor, n_particles=500, rng=3)
    b = map_particle_filter([0.0, 2.0], 0.25 * np.eye(2), theta, d, z, R, grid=corridor, n_particles=500, rng=3)
    np.testing.assert_array_equal(a.x, b.x)
    free = map_particle_filter([0.0, 2.0], 0.25 * np.eye(2), theta, d, z, R, grid=None, n_particles=500, rng=3)
    assert free.x[-1, 1] > 6.0                    # unconstrained: leaves the corridor
    assert 0.0 <= a.x[-1, 1] <= 4.0 and 0.0 <= a.x_smooth[:, 1].min() and a.x_smooth[:, 1].max() <= 4.0
    assert a.n_blocked > 0


def _glitch_walk(seed):
    """A zig-zag walk whose PDR heading turns 90 degrees away for 30 steps (steps 40-69): the cloud ends
    some 25-30 m from the truth and every fix then scores the particles at about the floor eps / area."""
    n = 160
    sw = straight_walk(n, rng=seed, sigma_rf_m=4.0, fix_every=4, turn_every=40)
    th = sw.theta_rad.copy()
    th[40:70] += np.pi / 2
    return sw, th, np.broadcast_to(16.0 * np.eye(2), (n + 1, 2, 2)).copy()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_augmented_recovery_brings_a_lost_cloud_back_to_the_fixes(seed):
    sw, th, R = _glitch_walk(seed)
    kw = dict(n_particles=1000, rng=seed, sigma_offset0_rad=0.02, sigma_heading_rad=0.05)
    old = map_particle_filter(sw.truth_xy_m[0], np.eye(2), th, sw.step_m, sw.z_m, R, recovery=None, **kw)
    new = map_particle_filter(sw.truth_xy_m[0], np.eye(2), th, sw.step_m, sw.z_m, R, **kw)
    e_old = np.hypot(*(old.x - sw.truth_xy_m).T)
    e_new = np.hypot(*(new.x - sw.truth_xy_m).T)
    has = ~np.isnan(sw.z_m[:, 0])
    floor = kw.get("outlier_prob", 0.1) / 1e4
    # the plain filter: lost for good, the fixes at the floor of the robust likelihood, nothing injected
    assert e_old[120:].mean() > 15.0 and old.n_injected == 0 and (old.p_inject == 0).all()
    lik = old.lik_mean[has] / floor
    assert np.median(lik[:10]) > 10.0 and (lik[-10:] < 1.5).all() and (lik >= 1.0 - 1e-9).all()
    # the recovery: the same start (identical before the glitch's first effect), back on the walk afterwards
    assert e_new[120:].mean() < 6.0 and new.n_injected > 0
    assert (new.p_inject[~has] == 0).all() and (new.p_inject <= 1).all() and np.isnan(new.lik_mean[~has]).all()
    assert new.n_reset == 0 and np.isfinite(new.x).all() and np.isfinite(new.x_smooth).all()
    # amcl's variant restarts both averages after an injection: the next fix never injects
    am = map_particle_filter(sw.truth_xy_m[0], np.eye(2), th, sw.step_m, sw.z_m, R, recovery="amcl", **kw)
    pa = am.p_inject[has]
    assert (pa > 0).any() and not ((pa[:-1] > 0) & (pa[1:] > 0)).any()
    pn = new.p_inject[has]
    assert ((pn[:-1] > 0) & (pn[1:] > 0)).any()                  # Table 8.3 has no restart


def test_recovery_keeps_a_tracked_walk_tracked_and_is_deterministic():
    sw, R = _walk_inputs()
    kw = dict(n_particles=2000, rng=1, sigma_offset0_rad=0.02, sigma_heading_rad=0.05)
    a = map_particle_filter(sw.truth_xy_m[0], np.eye(2), sw.theta_rad, sw.step_m, sw.z_m, R, **kw)
    b = map_particle_filter(sw.truth_xy_m[0], np.eye(2), sw.theta_rad, sw.step_m, sw.z_m, R, **kw)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.x_smooth, b.x_smooth)
    e_fix = np.nanmean(np.hypot(*(sw.z_m - sw.truth_xy_m).T))
    assert np.hypot(*(a.x - sw.truth_xy_m).T).mean() < 0.7 * e_fix


def test_recovery_draws_walkable_particles_near_the_fix():
    from ilocalg.fusion.particle_filter import _fix_sampler

    g = OccupancyGrid.from_polygons([SQUARE], [HOLE], cell_m=0.5)
    draw = _fix_sampler(g)
    rng = np.random.default_rng(0)
    pts = draw(np.array([20.0, 15.0]), 4.0 * np.eye(2), 2000, rng)       # a fix inside the hole
    assert g.walkable(pts[:, 0], pts[:, 1]).all()
    assert np.hypot(*(pts - [20.0, 15.0]).T).max() < 12.0               # on the hole's rim, not anywhere
    far = draw(np.array([200.0, 15.0]), 4.0 * np.eye(2), 500, rng)       # far off the map: the nearest cells
    assert g.walkable(far[:, 0], far[:, 1]).all() and far[:, 0].min() > 38.0
    free = _fix_sampler(None)(np.array([1.0, 2.0]), np.diag([4.0, 1.0]), 20000, rng)
    np.testing.assert_allclose(free.mean(0), [1.0, 2.0], atol=0.05)
    np.testing.assert_allclose(np.cov(free.T), np.diag([4.0, 1.0]), atol=0.1)


@pytest.mark.parametrize("kw,match", [
    ({"z_m": np.zeros((3, 2))}, "z_m must have shape"),
    ({"R_m2": np.zeros((2, 2, 2))}, "R_m2 must have shape"),
    ({"n_particles": 5}, "n_particles"),
    ({"blocked_weight": 1.0}, "blocked_weight"),
    ({"init": "map"}, "init"),
    ({"recovery": "uniform"}, "recovery must be one of"),
    ({"alpha_slow": 0.2, "alpha_fast": 0.1}, "alpha_slow"),
])
def test_pf_bad_input(kw, match):
    n = 4
    args = {"x0_m": [0, 0], "P0_m2": np.eye(2), "theta_rad": np.zeros(n), "step_m": np.ones(n),
            "z_m": np.full((n + 1, 2), np.nan), "R_m2": np.broadcast_to(np.eye(2), (n + 1, 2, 2))}
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        map_particle_filter(**args)


SITE1_WALK = Path(__file__).parent / "data" / "site1_f2_pf_walk.json"


@pytest.mark.realdata
def test_recovery_on_the_site1_f2_walk_that_lost_the_plain_filter(shared_data):
    """Issue 26: ILC 2.0 site1 F2, walk 5dda5a8b...; leave-one-walk-out with the nested Wi-Fi selection the
    plain filter lost the fixes after about 20 steps and ended 62 m mean from the waypoints (Wi-Fi only 11.8 m).
    The filter's inputs are those the track pipeline gave it (tests/data/make_site1_f2_pf_walk.py); the map
    and the waypoints are read from the recording."""
    from ilocalg.io.ilc import load_ilc_floor

    d = json.loads(SITE1_WALK.read_text())
    fl = load_ilc_floor(shared_data("ilc2020_site1"), names=[d["walk"]], floor_name="site1_F2",
                        duplicate_bssid="keep_latest", relisted_wifi="keep")
    wp = fl.traces[d["walk"]].waypoints
    grid = OccupancyGrid.from_floor_map(fl.floor_map, d["grid_cell_m"])
    ts, tw, true = np.asarray(d["state_t_s"]), wp["t_s"].to_numpy(), wp[["x_m", "y_m"]].to_numpy()
    z = np.array([[np.nan, np.nan] if r is None else r for r in d["z_m"]])
    has = ~np.isnan(z[:, 0])
    args = (d["x0_m"], d["P0_m2"], d["theta_rad"], d["step_m"], z, np.asarray(d["R_m2"]))

    def err(x):
        est = np.column_stack([np.interp(tw, ts, x[:, 0]), np.interp(tw, ts, x[:, 1])])
        return np.hypot(*(est - true).T).mean()

    # the inputs are the pipeline's: without recovery, the pipeline's own seed gives its error again
    old = map_particle_filter(*args, grid=grid, rng=np.random.default_rng(d["rng_seed"]), recovery=None, **d["pf_kw"])
    assert err(old.x) == pytest.approx(d["errors_m"]["pf"], rel=1e-6)
    floor = d["pf_kw"]["outlier_prob"] / grid.area_m2
    lik_old = old.lik_mean[has] / floor
    assert np.median(lik_old[:4]) > 10 and (lik_old[-20:] < 1.01).all()       # tracked, then lost for good
    wifi = d["errors_m"]["wifi"]
    for seed in range(3):
        new = map_particle_filter(*args, grid=grid, rng=seed, **d["pf_kw"])
        assert err(new.x) < 1.25 * wifi and err(new.x_smooth) < 1.25 * wifi   # the plain filter: 25-37 m
        assert np.median(new.lik_mean[has][-20:] / floor) > 5 and new.n_reset == 0
