"""Whole-walk map matching of a PDR track."""

import numpy as np
import pytest

from ilocalg.fusion.heading_offset import rotate_xy
from ilocalg.fusion.map_align import _walkable_counts, map_align
from ilocalg.fusion.particle_filter import OccupancyGrid

# two parallel corridors 3 m wide, joined by a cross corridor at x in [40, 43]
RINGS = [np.array([[0, 0], [80, 0], [80, 3], [0, 3]], float), np.array([[0, 20], [80, 20], [80, 23], [0, 23]], float),
         np.array([[40, 0], [43, 0], [43, 23], [40, 23]], float)]


def _grid():
    return OccupancyGrid.from_polygons(RINGS, cell_m=1.0, x_range_m=(0, 80), y_range_m=(0, 23))


@pytest.mark.parametrize("shifts", [
    np.array([[0, 0], [1, -2], [-3, 1], [8, 0]]),
    np.array([[0, 0], [1, -2], [0, 0], [-3, 1], [1, -2], [0, 0]]),      # points sharing a cell: counted each
    np.random.default_rng(1).integers(-2, 3, (300, 2)),                  # more than 255 points (wider counts)
])
def test_walkable_counts_match_direct_counting(shifts):
    rng = np.random.default_rng(0)
    mask = rng.random((7, 9)) < 0.5
    out = _walkable_counts(mask, shifts)
    assert out.dtype == np.int32
    for j in range(7):
        for i in range(9):
            want = sum(bool(mask[j + sy, i + sx]) for sx, sy in shifts if 0 <= j + sy < 7 and 0 <= i + sx < 9)
            assert out[j, i] == want


def test_map_align_snaps_the_track_into_the_corridor():
    g = _grid()
    rel = np.column_stack([np.linspace(0, 30, 44), np.zeros(44)])
    true = rel + [5.0, 21.5]                      # along the upper corridor (y in [20, 23])
    errs_map, errs_naive = [], []
    for seed in range(5):
        rng = np.random.default_rng(seed)
        idx = np.arange(0, 44, 4)
        fixes = true[idx] + rng.normal(0, 12.0, (idx.size, 2))
        r = map_align(rel, idx, fixes, 144.0, g, angles_rad=[-0.1, 0.0, 0.1])
        assert r.off_map == 0
        assert 20.0 <= r.track_m[:, 1].min() and r.track_m[:, 1].max() <= 23.0      # inside the corridor
        naive = rel + (fixes - rel[idx]).mean(0)
        errs_map.append(np.abs(r.track_m[:, 1] - true[:, 1]).mean())
        errs_naive.append(np.abs(naive[:, 1] - true[:, 1]).mean())
    # the map fixes the cross-track error
    assert np.mean(errs_map) < 1.5 and np.mean(errs_map) < 0.5 * np.mean(errs_naive)


def test_map_align_uses_rotation_prior_and_candidates():
    g = _grid()
    rel = rotate_xy(np.column_stack([np.linspace(0, 30, 31), np.zeros(31)]), -0.1)   # compass 0.1 rad off
    true = rotate_xy(rel, 0.1) + [5.0, 1.5]
    idx = np.arange(0, 31, 3)
    r = map_align(rel, idx, true[idx], 4.0, g, angles_rad=np.arange(-0.2, 0.21, 0.05))
    assert r.angle_rad == pytest.approx(0.1, abs=0.051)
    assert r.score_by_angle.shape == (9,)


@pytest.mark.parametrize("kw,match", [
    ({"fix_index": [0, 99]}, "fix_index"),
    ({"fix_var_m2": 0.0}, "fix_var_m2"),
    ({"outlier_prob": 0.0}, "outlier_prob"),
])
def test_bad_input(kw, match):
    args = {"track_xy_m": np.zeros((5, 2)), "fix_index": [0, 1], "fix_xy_m": np.ones((2, 2)),
            "fix_var_m2": 1.0, "grid": _grid()}
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        map_align(**args)


def _wifi_loglik_whole_raster(q, fi, z, var, tx, ty, eps, area):
    """The Wi-Fi term as map_align wrote it before the boxes: every fix's Gaussian on the whole raster."""
    sw = np.zeros((ty.size, tx.size))
    for j in range(fi.size):
        cx, cy = z[j] - q[fi[j]]
        g = np.exp(-0.5 * (((ty - cy) ** 2)[:, None] + ((tx - cx) ** 2)[None, :]) / var[j]) / (2 * np.pi * var[j])
        sw = sw + np.log((1 - eps) * g + eps / area)
    return sw


@pytest.mark.parametrize("seed", range(6))
def test_wifi_term_in_boxes_has_the_bits_of_the_whole_raster(seed):
    """Each fix's Gaussian evaluated only where it can change the sum gives the same bits as on the whole raster
    (variances from 0.5 to 400 m^2, fixes inside and outside the raster, areas and outlier rates as used)."""
    from ilocalg.fusion.map_align import _wifi_loglik

    rng = np.random.default_rng(seed)
    tx, ty = np.arange(120) + 0.5 - 10.0, np.arange(90) + 0.5 + 3.0
    m = 40
    q = rng.normal(0, 20, (60, 2))
    fi = rng.integers(0, 60, m)
    z = rng.uniform(-40, 150, (m, 2))
    var = np.exp(rng.uniform(np.log(0.5), np.log(400.0), m))
    for eps, area in ((0.2, 9000.0), (0.05, 3.0e4), (0.5, 123.0)):
        a = _wifi_loglik(q, fi, z, var, tx, ty, eps, area)
        b = _wifi_loglik_whole_raster(q, fi, z, var, tx, ty, eps, area)
        assert np.array_equal(a, b)
