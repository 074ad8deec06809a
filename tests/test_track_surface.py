"""ilocalg.track.surface: the scans' likelihood surface and the walk's placement on it (a diagnostic of issue 26);
and, on the same site1 floor model, ilocalg.track.walk_align's site1 walk."""

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from ilocalg.track.surface import (
    ScanSurfaces,
    place_walk,
    placement_evidence,
    placement_scores,
    scan_surfaces,
    surface_fixes,
    translation_grid,
)
from tests.track_sim import SITE1_WALK, site1_floor


def _db_and_walk(seed, offset=(6.0, -4.0)):
    """A 40 x 20 m floor surveyed every metre, 8 access points (log-distance, 3 dB noise), and an L-shaped walk
    of 30 scans; returns the database, the walk's queries, its true positions and the shape moved by -offset."""
    from ilocalg.track.database import WifiDatabase

    rng = np.random.default_rng(seed)
    aps = rng.uniform([0, 0], [40, 20], (8, 2))

    def rssi(xy):
        d = np.hypot(*(xy[:, None, :] - aps[None]).transpose(2, 0, 1))
        return -40 - 25 * np.log10(np.maximum(d, 1.0)) + rng.normal(0, 3.0, d.shape)

    gx, gy = np.meshgrid(np.arange(0, 41.0), np.arange(0, 21.0))
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    db = WifiDatabase(rssi(xy), xy, np.array(["db"] * len(xy)), tuple(f"ap{i}" for i in range(8)))
    true = np.vstack([np.column_stack([np.linspace(8, 28, 20), np.full(20, 6.0)]),
                      np.column_stack([np.full(10, 28.0), np.linspace(7, 16, 10)])])
    return db, rssi(true), true, true - np.asarray(offset)


def test_placement_recovers_a_known_shift_of_a_simulated_walk():
    db, X, true, shape = _db_and_walk(3)
    surf = scan_surfaces(db, X, k=20, h_dbm=5.0, sigma_m=1.0)
    pl = place_walk(surf, shape, half_m=10.0, step_m=1.0)
    assert np.hypot(*(pl.t_m - [6.0, -4.0])) <= 1.0, pl.t_m
    s0, s1 = placement_evidence(surf, shape, [6.0, -4.0])
    assert s1 > s0
    # the posterior mean at a high temperature is pulled toward the lattice's centre, at a low one it is the MAP's
    hot = place_walk(surf, shape, half_m=10.0, step_m=1.0, temperature=1e6).t_m
    cold = place_walk(surf, shape, half_m=10.0, step_m=1.0, temperature=1e-3).t_m
    assert np.hypot(*hot) < 0.5 and np.allclose(cold, pl.t_m, atol=1e-6)


def test_log_likelihood_is_the_floored_gaussian_mixture():
    rng = np.random.default_rng(0)
    xy = rng.normal(0, 5, (2, 4, 2))
    w = rng.dirichlet(np.ones(4), 2)
    surf = ScanSurfaces(xy, np.log(w), sigma_m=1.5, eps=1e-4)
    pts = rng.normal(0, 6, (2, 7, 2))
    got = surf.log_likelihood(pts)
    for i in range(2):
        ref = sum(w[i, j] * multivariate_normal(xy[i, j], 1.5 ** 2 * np.eye(2)).pdf(pts[i]) for j in range(4))
        np.testing.assert_allclose(got[i], np.log(ref + 1e-4), rtol=1e-10)
    far = surf.log_likelihood(np.full((2, 1, 2), 1e4))
    np.testing.assert_allclose(far, np.log(1e-4))
    np.testing.assert_allclose(placement_scores(surf, pts[:, 0], np.zeros((1, 2))), got[:, 0].sum())


def test_surface_fixes_range_from_the_weighted_mean_to_the_row_nearest_the_track():
    rng = np.random.default_rng(1)
    xy = rng.uniform(0, 30, (3, 6, 2))
    lw = np.log(rng.dirichlet(np.ones(6), 3))
    surf = ScanSurfaces(xy, lw, sigma_m=1.0)
    wide = surface_fixes(surf, np.zeros((3, 2)), tau_m=1e6)
    np.testing.assert_allclose(wide, (np.exp(lw)[..., None] * xy).sum(1), rtol=1e-6)
    track = xy[:, 2] + 0.01
    np.testing.assert_allclose(surface_fixes(surf, track, tau_m=0.05), xy[:, 2], atol=1e-6)


def test_bad_input_raises():
    with pytest.raises(ValueError, match="xy_m must be"):
        ScanSurfaces(np.zeros((2, 3)), np.zeros((2, 3)), 1.0)
    surf = ScanSurfaces(np.zeros((2, 3, 2)), np.zeros((2, 3)), 1.0)
    with pytest.raises(ValueError, match="pts_m must be"):
        surf.log_likelihood(np.zeros((3, 1, 2)))
    with pytest.raises(ValueError, match="temperature"):
        place_walk(surf, np.zeros((2, 2)), temperature=0.0)
    with pytest.raises(ValueError, match="tau_m"):
        surface_fixes(surf, np.zeros((2, 2)), 0.0)
    with pytest.raises(ValueError, match="step_m"):
        translation_grid(5.0, 0.0)
    with pytest.raises(ValueError, match="sigma_m"):
        ScanSurfaces(np.zeros((2, 3, 2)), np.zeros((2, 3)), 0.0)


@pytest.fixture(scope="module")
def site1(shared_data):
    """site1 F1's small floor (tests.track_sim.site1_floor) and its floor model without Wi-Fi selection, built once
    for the surface test and the walk_align test below (the build is most of their cost)."""
    from ilocalg.track import RealWalkConfig, build_floor_model

    fl = site1_floor(shared_data("ilc2020_site1"))
    cfg = RealWalkConfig()
    return fl, cfg, build_floor_model(fl.traces, cfg, select=False)


@pytest.mark.realdata
def test_a_site1_walk_its_scans_are_its_fixes_and_its_placement_is_bounded(site1):
    """On site1 F1 (every 4th walk as the database): the scans :func:`walk_queries` gives are those the fixes were
    made of (the same WKNN fixes again), and the surface placement of the walk's ``lsq`` track stays within the
    lattice (its CPU is reported in ``cpu_s``; speed is measured in benchmarks, not asserted here)."""
    from ilocalg.track.fixes import locate_wknn, wifi_fixes
    from ilocalg.track.surface import surface_table, walk_queries

    scored = SITE1_WALK
    fl, cfg, model = site1
    wm = model.for_walk(scored, cfg, select=False)
    fx = wifi_fixes(fl.traces[scored], wm.db, wm.cfg)
    X = walk_queries(fl.traces[scored], wm.db, fx.t_s, wm.cfg)
    np.testing.assert_array_equal(locate_wknn(wm.db, X, wm.cfg)[0], fx.xy_m)
    with pytest.raises(ValueError, match="fix times"):
        walk_queries(fl.traces[scored], wm.db, fx.t_s[1:] + 0.5, wm.cfg)
    t = surface_table(fl.traces, model, [scored], cfg, select=False, half_m=10.0)
    assert len(t) == len(fl.traces[scored].waypoints) and np.isfinite(t[["lsq_m", "surface_m"]].to_numpy()).all()
    moved = (t["surface_m"] - t["lsq_m"]).abs().max()
    assert moved <= np.hypot(10.0, 10.0) + 1e-9
    assert t["cpu_s"].iloc[0] > 0


@pytest.mark.realdata
def test_walk_align_on_a_site1_walk_its_alignment_table_holds_its_invariants(site1):
    """On site1 F1 (every 4th walk as the database): one row per scan inside the walk's waypoints, the ``fix`` and
    ``lsq`` errors the same in every setting, a wider radius never fewer candidates, and the oracle candidate (chosen
    with the truth) on average no farther from the truth than the cheapest one."""
    from ilocalg.track.walk_align import align_table, scan_summary

    fl, cfg, model = site1
    t = align_table(fl.traces, model, [SITE1_WALK], cfg, settings=((5.0, 0.5, 0.0), (30.0, 0.0, 0.0)), select=False)
    a, b = (g.reset_index(drop=True) for _, g in t.groupby("radius_m"))
    assert len(a) == len(b) > 5
    same = ["fix_dx", "fix_dy", "lsq_dx", "lsq_dy"]
    np.testing.assert_array_equal(a[same], b[same])
    assert b["n_candidates"].iloc[0] == len(set(model.db.walk) - {SITE1_WALK})      # min_frac 0: every other walk
    assert b["n_candidates"].iloc[0] >= a["n_candidates"].iloc[0]
    s = scan_summary(t)
    assert (s["oracle_m"] <= s["best_m"] + 1e-9).all() and np.isfinite(s[["fix_m", "lsq_m"]].to_numpy()).all()
