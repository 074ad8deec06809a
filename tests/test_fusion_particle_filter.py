"""Map-constrained particle filter, occupancy raster, systematic resampling."""

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


@pytest.mark.parametrize("kw,match", [
    ({"z_m": np.zeros((3, 2))}, "z_m must have shape"),
    ({"R_m2": np.zeros((2, 2, 2))}, "R_m2 must have shape"),
    ({"n_particles": 5}, "n_particles"),
    ({"blocked_weight": 1.0}, "blocked_weight"),
    ({"init": "map"}, "init"),
])
def test_pf_bad_input(kw, match):
    n = 4
    args = {"x0_m": [0, 0], "P0_m2": np.eye(2), "theta_rad": np.zeros(n), "step_m": np.ones(n),
            "z_m": np.full((n + 1, 2), np.nan), "R_m2": np.broadcast_to(np.eye(2), (n + 1, 2, 2))}
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        map_particle_filter(**args)
