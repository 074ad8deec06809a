"""The online track's start-up variants (ilocalg.track.estimators): the delayed start and the map-placed fixed lag."""

import dataclasses

import numpy as np
import pytest

from ilocalg.fusion.particle_filter import OccupancyGrid
from ilocalg.track.estimators import (
    ESTIMATORS,
    TrackProblem,
    kf_gain_lag_track,
    kf_gain_map_lag_track,
    kf_gain_map_start_track,
    kf_gain_map_track,
    lsq_causal_map_track,
    lsq_online_map_start_track,
    map_first_fix,
    snap_to_map,
    startup_until_s,
)
from ilocalg.track.motion import GainStats
from ilocalg.track.online_kf import gain_kf, gain_kf_smooth_to


def _walk(seed=0, n=120, fix_sd=4.0, first_fix_sd=None):
    """A walk along a 2 m wide corridor (y in [0, 2)) that turns north into a second one at x = 30 m; PDR off by a
    gain; fixes every 4th state from state 3 on, each known one state (0.5 s) after its readings."""
    rng = np.random.default_rng(seed)
    mask = np.zeros((100, 200), dtype=bool)
    mask[:4, :] = True                                # y in [0, 2)
    mask[:, 60:64] = True                             # x in [30, 32)
    grid = OccupancyGrid(mask, 0.0, 0.0, 0.5)
    ts = np.arange(n + 1) * 0.5
    east = np.minimum(np.arange(n + 1), 70) * 0.4
    north = np.maximum(np.arange(n + 1) - 70, 0) * 0.4
    truth = np.column_stack([2.0 + east, 1.0 + north])
    g = 1.08 * np.exp(0.1j)
    d = np.diff(truth, axis=0)
    pdr = (d[:, 0] + 1j * d[:, 1]) / g
    disp = np.column_stack([pdr.real, pdr.imag]) + rng.normal(0, 0.05, d.shape)
    fi = np.arange(3, n + 1, 4)
    z = truth[fi] + rng.normal(0, fix_sd, (fi.size, 2))
    if first_fix_sd is not None:
        z[0] = truth[fi[0]] + rng.normal(0, first_fix_sd, 2)
    gs = GainStats(gain_var=0.01, gain_walk_var=1e-5, step_var_m2=0.0025, n_walks=10)
    p = TrackProblem(ts, disp, 0.0025, ts[fi], z, np.full(fi.size, fix_sd ** 2), grid, fix_avail_t_s=ts[fi] + 0.5,
                     gain=gs, map_start=True, fix_corr=(0.5, 0.8, fix_sd ** 2 / 2))
    return p, truth


def _cut(p: TrackProblem, c: int) -> TrackProblem:
    keep = p.fix_avail_t_s <= p.state_t_s[c]
    return dataclasses.replace(p, state_t_s=p.state_t_s[:c + 1], disp_m=p.disp_m[:c], fix_t_s=p.fix_t_s[keep],
                               fix_xy_m=p.fix_xy_m[keep], fix_var_m2=p.fix_var_at(keep),
                               fix_avail_t_s=p.fix_avail_t_s[keep])


@pytest.mark.parametrize("start, causal", [(kf_gain_map_start_track, kf_gain_map_track),
                                           (lsq_online_map_start_track, lsq_causal_map_track)])
def test_delayed_start_waits_until_then_only_and_is_the_causal_track_after(start, causal):
    p, _ = _walk(1)
    until = startup_until_s(p)
    assert until == pytest.approx(p.fix_avail_t_s[0] + 5.0)
    j = int(np.searchsorted(p.state_t_s, until, side="right")) - 1
    full = start(p)
    # after the start-up: exactly the causal variant
    np.testing.assert_array_equal(full[j + 1:], causal(p)[j + 1:])
    # the start-up: the data known by `until` only (everything after it removed changes nothing) ...
    np.testing.assert_allclose(start(_cut(p, j))[:j + 1], full[:j + 1], atol=1e-9)
    # ... and more than the causal variant had at each of those states
    assert not np.allclose(full[:j + 1], causal(p)[:j + 1])
    with pytest.raises(ValueError, match="raster"):
        start(dataclasses.replace(p, grid=None))


@pytest.mark.parametrize("start, causal", [(kf_gain_map_start_track, kf_gain_map_track),
                                           (lsq_online_map_start_track, lsq_causal_map_track)])
def test_delayed_start_places_the_start_up_better_when_the_first_fix_is_poor(start, causal):
    """Over 20 walks whose first fix is poor (sd 8 m against 4 m), the start-up states' mean error falls by > 10 %."""
    e_start, e_causal = [], []
    for seed in range(20):
        p, truth = _walk(seed, first_fix_sd=8.0)
        j = int(np.searchsorted(p.state_t_s, startup_until_s(p), side="right"))
        e_start.append(np.hypot(*(start(p)[:j] - truth[:j]).T).mean())
        e_causal.append(np.hypot(*(causal(p)[:j] - truth[:j]).T).mean())
    assert np.mean(e_start) < 0.9 * np.mean(e_causal), (np.mean(e_start), np.mean(e_causal))


def test_map_lag_variant_is_the_lag_smoother_from_the_map_start_moved_onto_the_map():
    p, _ = _walk(2)
    want = snap_to_map(kf_gain_lag_track(map_first_fix(p), lag_s=5.0), p.grid)[0]
    np.testing.assert_array_equal(kf_gain_map_lag_track(p), want)
    on = snap_to_map(want, p.grid)[1]
    assert not on.any()                           # every state on the walkable raster


def test_smooth_to_its_own_state_is_the_filter_and_bad_ends_raise():
    p, _ = _walk(3, n=40)
    r = gain_kf(p.state_t_s, p.disp_m, p.fix_t_s, p.fix_xy_m, p.fix_var_m2, 0.0025, 0.01, 1e-5)
    n = p.state_t_s.size
    np.testing.assert_array_equal(gain_kf_smooth_to(r, np.arange(n)), r.xy_m)
    with pytest.raises(ValueError, match="end"):
        gain_kf_smooth_to(r, np.arange(n) - 1)
    with pytest.raises(ValueError, match="end"):
        gain_kf_smooth_to(r, np.full(n, n))


def test_start_up_variants_are_registered_as_not_causal_map_methods():
    from ilocalg.track._config import CAUSAL_METHODS, LATENCY_METHODS, MAP_METHODS, METHODS

    for m in ("kf_gain_map_lag5s", "kf_gain_map_start5s", "lsq_online_map_start5s"):
        assert m in METHODS and m in MAP_METHODS and m in LATENCY_METHODS and m not in CAUSAL_METHODS
        assert not ESTIMATORS[m].causal and ESTIMATORS[m].needs_map
