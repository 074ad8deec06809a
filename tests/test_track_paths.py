"""The walked-path graph (ilocalg.track.paths) and the least squares constrained to it (lsq_paths)."""

import numpy as np
import pytest

from ilocalg.track.estimators import ESTIMATORS, TrackProblem, lsq_paths_track, lsq_track
from ilocalg.track.paths import WalkedPaths

# an L-shaped corridor: 40 m east, then 30 m north
CORNER = np.array([[0.0, 0.0], [40.0, 0.0], [40.0, 30.0]])


def _l_graph(offsets=(-0.5, 0.0, 0.5)):
    """Walks along the L, each shifted sideways by an offset (m), waypoints every few metres."""
    polys = {}
    for i, o in enumerate(offsets):
        leg1 = np.column_stack([np.arange(0.0, 40.0, 5.0), np.full(8, o)])
        leg2 = np.column_stack([np.full(7, 40.0 - o), np.arange(0.0, 35.0, 5.0)])
        polys[f"w{i}"] = np.vstack([leg1, leg2])
    return WalkedPaths.from_polylines(polys)


def _dist_to_segments(p, a, b):
    ab = b - a
    t = np.clip(((p - a) * ab).sum(axis=1) / np.maximum((ab ** 2).sum(axis=1), 1e-12), 0, 1)
    return np.hypot(*(a + t[:, None] * ab - p).T)


def test_projection_lands_on_a_segment_and_is_the_nearest_point():
    g = _l_graph()
    pts = np.random.default_rng(0).uniform([-10, -10], [55, 45], (500, 2))
    proj, dist, seg = g.project(pts)
    # on its segment (distance to that segment ~0) and at the distance it reports
    on = np.array([_dist_to_segments(proj[i:i + 1], g.a_m[seg[i]:seg[i] + 1], g.b_m[seg[i]:seg[i] + 1])[0]
                   for i in range(len(pts))])
    assert on.max() < 1e-9
    np.testing.assert_allclose(dist, np.hypot(*(proj - pts).T), atol=1e-12)
    # no point of the graph is nearer: a dense sampling of every segment never beats it
    dense, _ = g.samples(0.05)
    dense = np.vstack([dense, g.b_m])
    nearest = np.sqrt(((pts[:, None, :] - dense[None]) ** 2).sum(-1)).min(axis=1)
    assert np.all(dist <= nearest + 1e-9)
    assert np.all(nearest - dist < 0.05)
    # a whole trajectory in one call, blocks of any size give the same answer
    import ilocalg.track.paths as mod

    old, mod._BLOCK = mod._BLOCK, 64
    try:
        np.testing.assert_array_equal(g.project(pts)[0], proj)
    finally:
        mod._BLOCK = old


def test_without_and_spread_of_parallel_walks():
    g = WalkedPaths.from_polylines({"a": [[0, 0], [10, 0], [20, 0]], "b": [[0, 1], [20, 1]], "c": [[5, 5]]})
    assert g.walks == ["a", "b"] and g.a_m.shape == (3, 2)          # a one-point walk has no segment
    assert set(g.without("a").walk) == {"b"}
    # each walk lies exactly 1 m from the other one: per-axis variance 1 / 2
    assert g.spread_var_m2() == pytest.approx(0.5, abs=1e-12)
    with pytest.raises(ValueError, match="at least two walks"):
        g.without("a").spread_var_m2()
    with pytest.raises(ValueError, match="no segment"):
        g.without("a", "b").project([[0, 0]])
    with pytest.raises(ValueError, match="WalkedPaths"):
        WalkedPaths(np.zeros((2, 2)), np.zeros((3, 2)), np.array(["a", "b"], dtype=object))


def _l_walk(seed, fix_sd=4.0, step_sd=0.25, heading_bias=0.06):
    """A walk along the L's centre line (0.7 m steps), noisy fixes every 4 steps, PDR with noise and a bias."""
    rng = np.random.default_rng(seed)
    s = np.arange(0.0, 70.0, 0.7)
    truth = np.where(s[:, None] <= 40, np.column_stack([s, np.zeros_like(s)]),
                     np.column_stack([np.full_like(s, 40.0), s - 40.0]))
    d = np.diff(truth, axis=0)
    c, sn = np.cos(heading_bias), np.sin(heading_bias)
    disp = d @ np.array([[c, sn], [-sn, c]]) + rng.normal(0, step_sd, d.shape)
    ts = np.arange(truth.shape[0]) * 0.5
    fi = np.arange(0, truth.shape[0], 4)
    fixes = truth[fi] + rng.normal(0, fix_sd, (fi.size, 2))
    return TrackProblem(ts, disp, step_sd ** 2, ts[fi], fixes, fix_sd ** 2, paths=_l_graph()), truth


def test_lsq_paths_beats_lsq_on_a_simulated_corridor_walk():
    e_lsq, e_paths, off = [], [], []
    for seed in range(6):
        p, truth = _l_walk(seed)
        x0, x1 = lsq_track(p), lsq_paths_track(p)
        e_lsq.append(np.hypot(*(x0 - truth).T).mean())
        e_paths.append(np.hypot(*(x1 - truth).T).mean())
        off.append(p.paths.project(x1)[1].mean())
        # the registered estimator is this function, offline
        np.testing.assert_array_equal(ESTIMATORS["lsq_paths"].fn(p), x1)
    assert not ESTIMATORS["lsq_paths"].causal
    assert np.mean(e_paths) < 0.8 * np.mean(e_lsq), (e_paths, e_lsq)
    assert np.mean(off) < 1.0                  # the states end near the paths (soft constraint)
    p, truth = _l_walk(0)
    snapped = lsq_paths_track(p, snap=True)
    assert p.paths.project(snapped)[1].max() < 1e-9
    with pytest.raises(ValueError, match="walked-path graph"):
        lsq_paths_track(TrackProblem(p.state_t_s, p.disp_m, p.step_var_m2, p.fix_t_s, p.fix_xy_m, p.fix_var_m2))


def test_gain_solve_reduces_to_lsq_and_finds_the_walks_gain():
    from dataclasses import replace

    from ilocalg.track.estimators import _interp_rows, lsq_gain_solve, lsq_solve

    p, truth = _l_walk(3, heading_bias=0.1)
    j, a = _interp_rows(p.state_t_s, p.fix_t_s)
    for corr in (None, (0.5, 0.8, 4.0)):
        q = replace(p, fix_corr=corr)
        ref = lsq_solve(p.state_t_s.size, p.disp_m, p.step_var_m2, j, a, p.fix_xy_m, p.fix_var_m2, fix_corr=corr)
        x, g = lsq_gain_solve(q, gain_var=1e-12)            # the gain held at 1: the plain least squares
        np.testing.assert_allclose(x, ref, atol=1e-3)
        assert abs(g - 1) < 1e-6
    # free gain, the states held on the truth: the gain undoes the PDR's +0.1 rad heading bias (small step
    # noise: noise on the PDR side of the regression would shrink |g|, errors in variables)
    p, truth = _l_walk(3, heading_bias=0.1, step_sd=0.02)
    _, g = lsq_gain_solve(p, gain_var=1.0, anchor_idx=np.arange(truth.shape[0]), anchor_xy_m=truth,
                          anchor_var_m2=1e-4)
    assert abs(np.angle(g) + 0.1) < 0.01 and abs(abs(g) - 1) < 0.01


def test_evaluate_uses_the_graph_of_the_other_walks_only():
    from ilocalg import track
    from ilocalg.sim import walk_recordings as wr

    walks = wr.simulate_recordings(5, seed=11, n_nodes=35)[1]
    r = track.evaluate_track(walks[0], walks[1:], methods=("wifi", "lsq", "lsq_paths"), select=False)
    assert set(r["problem"].paths.walk) == {w.name for w in walks[1:]}
    assert np.isfinite(r["errors"]["lsq_paths"]).all()
    db = track.WifiDatabase.from_recordings(walks[1:])
    cal = track.calibrate(walks[1:], {w.name: track.walk_steps(w) for w in walks[1:]})
    with pytest.raises(ValueError, match="must not include the scored walk"):
        track.evaluate_walk(walks[0], db, cal, 25.0, methods=("lsq_paths",),
                            paths=WalkedPaths.from_recordings(walks, db.frame))
    # without a graph: the database scans' positions (the other walks' only)
    r2 = track.evaluate_walk(walks[0], db, cal, 25.0, methods=("lsq_paths",))
    assert set(r2["problem"].paths.walk) == {w.name for w in walks[1:]}


def test_spread_of_a_graph_without_a_walk_is_the_same_from_the_whole_graph():
    """A walk's graph (the floor's without it) measures its spread from the whole graph's per-walk distances: the
    same number, bit for bit, as the graph built alone (random walks crossing each other, one of a single point)."""
    rng = np.random.default_rng(7)
    polys = {f"w{i}": np.cumsum(rng.normal(0, 6, (int(rng.integers(2, 30)), 2)), axis=0) + rng.uniform(0, 60, 2)
             for i in range(12)}
    polys["lonely"] = np.array([[5.0, 5.0]])
    whole = WalkedPaths.from_polylines(polys)
    for left in (("w0",), ("w3", "w7"), ("nobody",)):
        sub = whole.without(*left)
        alone = WalkedPaths(sub.a_m.copy(), sub.b_m.copy(), sub.walk.copy())
        assert sub._parent is not None and alone._parent is None
        assert sub.spread_var_m2() == alone.spread_var_m2()
        assert sub.spread_var_m2(0.5) == alone.spread_var_m2(0.5)
    with pytest.raises(ValueError, match="at least two walks"):
        whole.without(*[f"w{i}" for i in range(11)]).spread_var_m2()
