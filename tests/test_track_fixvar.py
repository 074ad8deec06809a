"""Per-fix Wi-Fi variance (ilocalg.track.fixes.FixVarModel) and the map at start-up (walkable posterior)."""

import dataclasses

import numpy as np
import pytest

from ilocalg.fusion.particle_filter import OccupancyGrid
from ilocalg.track import RealWalkConfig
from ilocalg.track.estimators import (
    TrackProblem,
    kf_gain_map_track,
    kf_gain_track,
    lsq_causal_map_track,
    lsq_track,
    map_first_fix,
    walkable_posterior,
)
from ilocalg.track.fixes import log_variance_fit
from ilocalg.track.motion import GainStats
from ilocalg.track.online_kf import gain_kf


def test_log_variance_fit_recovers_a_known_heteroscedastic_variance():
    """Errors whose per-axis variance is exp(0.5 + 0.8 f): the slope, and the mean variance per group (the
    smearing factor removes the log's bias; the 2-D squared error is far from log-normal)."""
    rng = np.random.default_rng(0)
    n = 20000
    f = rng.uniform(0, 3, n)
    var = np.exp(0.5 + 0.8 * f)
    e = rng.normal(0, 1, (n, 2)) * np.sqrt(var)[:, None]
    m = log_variance_fit((e ** 2).sum(1), f[:, None])
    assert m.beta[1] == pytest.approx(0.8, abs=0.03)
    pred = m.predict(f[:, None])
    for lo, hi in ((0, 1), (1, 2), (2, 3)):
        g = (f >= lo) & (f < hi)
        assert pred[g].mean() == pytest.approx(var[g].mean(), rel=0.05)
    with pytest.raises(ValueError, match="need at least"):
        log_variance_fit(np.ones(5), np.ones((5, 1)))


def test_per_fix_variance_weights_the_least_squares_by_each_fix():
    """A still walker, two fixes: the least-squares position is the inverse-variance weighted mean, and a
    per-fix variance equal for all fixes gives the scalar variance's track."""
    ts = np.arange(5.0)
    p = TrackProblem(ts, np.zeros((4, 2)), 1e-6, np.array([1.0, 3.0]), np.array([[0.0, 0.0], [10.0, 0.0]]),
                     np.array([1.0, 4.0]))
    np.testing.assert_allclose(lsq_track(p, n_iter=1)[2], [2.0, 0.0], atol=1e-3)     # (0/1 + 10/4) / (1 + 1/4)
    same = dataclasses.replace(p, fix_var_m2=np.array([2.0, 2.0]))
    np.testing.assert_allclose(lsq_track(same), lsq_track(dataclasses.replace(p, fix_var_m2=2.0)), atol=1e-12)
    with pytest.raises(ValueError, match="fix_var_m2"):
        dataclasses.replace(p, fix_var_m2=np.array([1.0, 2.0, 3.0]))
    with pytest.raises(ValueError, match="fix_var_m2"):
        dataclasses.replace(p, fix_var_m2=np.array([1.0, 0.0]))


def test_gain_kf_with_per_fix_variance():
    """Equal per-fix variances are the scalar filter; a fix with a huge variance is as if absent."""
    rng = np.random.default_rng(1)
    n = 40
    ts = np.arange(n + 1) * 0.5
    d = np.tile([0.7, 0.0], (n, 1)) + rng.normal(0, 0.1, (n, 2))
    ft = ts[1::5]
    z = np.column_stack([0.7 * np.arange(1, n + 1, 5), np.zeros(ft.size)]) + rng.normal(0, 3, (ft.size, 2))
    a = gain_kf(ts, d, ft, z, 9.0, 0.01, 0.02, 1e-4)
    b = gain_kf(ts, d, ft, z, np.full(ft.size, 9.0), 0.01, 0.02, 1e-4)
    np.testing.assert_allclose(a.x, b.x, atol=1e-12)
    v = np.full(ft.size, 9.0)
    v[3] = 1e12
    keep = np.arange(ft.size) != 3
    c = gain_kf(ts, d, ft, z, v, 0.01, 0.02, 1e-4, huber_c=None)
    e = gain_kf(ts, d, ft[keep], z[keep], v[keep], 0.01, 0.02, 1e-4, huber_c=None)
    np.testing.assert_allclose(c.xy_m, e.xy_m, atol=1e-4)


def _corridor():
    """A 40 x 20 m raster whose only walkable part is the corridor 0 <= y < 2 m."""
    mask = np.zeros((40, 80), dtype=bool)
    mask[:4, :] = True
    return OccupancyGrid(mask, 0.0, 0.0, 0.5)


def test_walkable_posterior_is_the_gaussian_on_open_ground_and_moves_into_a_corridor():
    open_grid = OccupancyGrid(np.ones((400, 400), dtype=bool), -50.0, -50.0, 0.25)
    C = np.array([[4.0, 1.0], [1.0, 2.0]])
    mu, S = walkable_posterior([1.0, 2.0], C, open_grid, n_sd=5.0)
    np.testing.assert_allclose(mu, [1.0, 2.0], atol=0.02)
    np.testing.assert_allclose(S, C, atol=0.05)                     # cell-sampled Gaussian: its own moments
    mu, S = walkable_posterior([20.0, 5.0], np.eye(2) * 9.0, _corridor())
    assert 0.0 <= mu[1] < 2.0 and mu[0] == pytest.approx(20.0, abs=0.1)
    assert S[1, 1] < 2.0 ** 2 / 12 + 0.1 and S[0, 0] == pytest.approx(9.0, rel=0.1)
    # nothing walkable within 3 sd: the nearest walkable cell
    mu, S = walkable_posterior([20.0, 18.0], np.eye(2), _corridor())
    np.testing.assert_allclose(mu, [20.25, 1.75])


def _corridor_walk(seed=0, n=80):
    rng = np.random.default_rng(seed)
    ts = np.arange(n + 1) * 0.5
    truth = np.column_stack([2.0 + 0.4 * np.arange(n + 1), np.full(n + 1, 1.0)])
    d = np.diff(truth, axis=0) + rng.normal(0, 0.05, (n, 2))
    fi = np.arange(2, n + 1, 4)
    z = truth[fi] + rng.normal(0, 3.0, (fi.size, 2))
    gs = GainStats(gain_var=0.01, gain_walk_var=1e-5, step_var_m2=0.0025, n_walks=10)
    return TrackProblem(ts, d, 0.0025, ts[fi], z, np.full(fi.size, 9.0), _corridor(), gain=gs), truth


def test_map_start_is_causal_and_starts_in_the_corridor():
    p, truth = _corridor_walk()
    q = map_first_fix(p)
    assert 0.0 <= q.fix_xy_m[0, 1] < 2.0 and q.fix_var_m2[0] < p.fix_var_m2[0]
    np.testing.assert_array_equal(q.fix_xy_m[1:], p.fix_xy_m[1:])
    for fn in (kf_gain_map_track, lsq_causal_map_track):
        full = fn(p, map_start=True)
        for c in (10, 40):
            keep = p.fix_t_s <= p.state_t_s[c]
            cut = dataclasses.replace(p, state_t_s=p.state_t_s[:c + 1], disp_m=p.disp_m[:c], fix_t_s=p.fix_t_s[keep],
                                      fix_xy_m=p.fix_xy_m[keep], fix_var_m2=p.fix_var_m2[keep])
            np.testing.assert_allclose(fn(cut, map_start=True), full[:c + 1], atol=1e-9)
    # before the second fix the start-up track rests on the first fix: from its walkable posterior it is
    # nearer the truth across the corridor than the plain filter's (then snapped) start
    k = np.searchsorted(p.state_t_s, p.fix_t_s[1])
    plain = kf_gain_track(p)[:k]
    started = kf_gain_map_track(p, map_start=True)[:k]
    assert np.abs(started[:, 1] - truth[:k, 1]).mean() <= np.abs(plain[:, 1] - truth[:k, 1]).mean()


def test_config_rejects_an_unknown_fix_variance_model():
    with pytest.raises(ValueError, match="fix_var"):
        RealWalkConfig(fix_var="robust")
