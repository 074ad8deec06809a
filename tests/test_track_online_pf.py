"""The causal particle filter with the gain-augmented model and the walkable map (ilocalg.track.online_pf)."""

import numpy as np
import pytest

from ilocalg.fusion.particle_filter import OccupancyGrid
from ilocalg.track.online_kf import gain_kf
from ilocalg.track.online_pf import gain_pf


def _walk(seed=0, n=120, fix_sd=3.0, fix_every=4, heading=None):
    rng = np.random.default_rng(seed)
    th = np.cumsum(rng.normal(0, 0.08, n)) if heading is None else np.full(n, heading)
    true_d = 0.7 * np.column_stack([np.cos(th), np.sin(th)])
    truth = np.vstack([[0.0, 0.0], np.cumsum(true_d, 0)])
    disp = true_d + rng.normal(0, 0.1, true_d.shape)
    ts = np.arange(n + 1) * 0.5
    fi = np.arange(1, n + 1, fix_every)
    return ts, disp, ts[fi], truth[fi] + rng.normal(0, fix_sd, (fi.size, 2)), fix_sd ** 2, truth


def test_gain_pf_without_a_map_is_the_kalman_filter():
    """Linear Gaussian model, no map: the particles' mean follows the exact filter (no Huber there)."""
    ts, d, ft, fz, fv, _ = _walk(1)
    kw = dict(step_var_m2=0.01, gain_var=0.005, gain_walk_var=1e-6, fix_corr=(0.5, 0.8, 4.0))
    kf = gain_kf(ts, d, ft, fz, fv, huber_c=None, **kw).xy_m
    pf = gain_pf(ts, d, ft, fz, fv, n_particles=20000, rng=0, **kw)
    assert np.hypot(*(pf - kf).T).mean() < 0.3
    assert np.hypot(*(pf - kf).T).max() < 1.5


def test_gain_pf_is_causal():
    """The estimate at state k is unchanged when the fixes after it are moved (same seed)."""
    ts, d, ft, fz, fv, _ = _walk(2)
    kw = dict(step_var_m2=0.01, gain_var=0.005, gain_walk_var=1e-6, fix_corr=(0.5, 0.8, 4.0), n_particles=500, rng=3)
    a = gain_pf(ts, d, ft, fz, fv, **kw)
    k = 60
    fz2 = fz.copy()
    fz2[ft > ts[k]] += 40.0
    d2 = d.copy()
    d2[k:] *= -1.0
    b = gain_pf(ts, d2, ft, fz2, fv, **kw)
    np.testing.assert_array_equal(a[:k + 1], b[:k + 1])
    assert not np.allclose(a[k + 1:], b[k + 1:])


def test_gain_pf_map_keeps_a_corridor_walk_in_the_corridor():
    """A walk along a 4 m wide corridor with fixes biased 6 m into the wall block beside it: with the map the
    estimate stays in the corridor, without it it follows the fixes."""
    ts, d, ft, fz, fv, truth = _walk(4, heading=0.0, fix_sd=1.0)
    fz = fz + [0.0, 6.0]
    mask = np.zeros((60, 200), dtype=bool)
    mask[26:34, :] = True                                  # y in [-2, 2) m with y0 = -15, cell 0.5
    grid = OccupancyGrid(mask, -10.0, -15.0, 0.5)
    kw = dict(step_var_m2=0.01, gain_var=0.005, gain_walk_var=1e-6, fix_corr=(0.8, 0.9, 30.0), n_particles=2000,
              rng=0)
    with_map = gain_pf(ts, d, ft, fz, 1.0, grid=grid, **kw)
    free = gain_pf(ts, d, ft, fz, 1.0, **kw)
    assert np.abs(with_map[10:, 1]).mean() < 2.0
    assert np.abs(free[10:, 1]).mean() > 3.0


def test_gain_pf_rejects_bad_input():
    ts, d, ft, fz, fv, _ = _walk(5)
    with pytest.raises(ValueError, match="disp_m"):
        gain_pf(ts, d[:-1], ft, fz, fv, 0.01, 0.005, 1e-6)
    with pytest.raises(ValueError, match="blocked_weight"):
        gain_pf(ts, d, ft, fz, fv, 0.01, 0.005, 1e-6, blocked_weight=2.0)
    with pytest.raises(ValueError, match="fix_corr"):
        gain_pf(ts, d, ft, fz, fv, 0.01, 0.005, 1e-6, fix_corr=(1.0, 0.5, 1.0))
