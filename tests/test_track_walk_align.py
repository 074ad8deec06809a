"""ilocalg.track.walk_align: a walk's scans aligned to the database walks' scan sequences (a diagnostic of issue 26).

Its site1 walk is tested in tests/test_track_surface.py, on the floor model the surface test builds."""

import numpy as np
import pytest

from ilocalg.track.database import WifiDatabase
from ilocalg.track.walk_align import align_to_walks, rssi_distances, subsequence_dtw


def _brute_force(C):
    """The cheapest monotone path with steps (1, 1), (1, 0), (0, 1) from any (0, b) to any (m-1, e): every path
    enumerated (tiny matrices only)."""
    m, n = C.shape
    best = np.inf

    def walk(i, j, acc):
        nonlocal best
        acc = acc + C[i, j]
        if i == m - 1:
            best = min(best, acc)
        for di, dj in ((1, 1), (1, 0), (0, 1)):
            if i + di < m and j + dj < n:
                walk(i + di, j + dj, acc)

    for b in range(n):
        walk(0, b, 0.0)
    return best


@pytest.mark.parametrize("seed", range(6))
def test_subsequence_dtw_is_the_cheapest_path(seed):
    rng = np.random.default_rng(seed)
    C = rng.uniform(0, 10, (rng.integers(1, 5), rng.integers(1, 6)))
    cost, path = subsequence_dtw(C)
    assert cost == pytest.approx(_brute_force(C))
    assert cost == pytest.approx(C[path[:, 0], path[:, 1]].sum())
    steps = np.diff(path, axis=0)
    assert {tuple(s) for s in steps} <= {(1, 1), (1, 0), (0, 1)}
    assert path[0, 0] == 0 and path[-1, 0] == len(C) - 1 and set(path[:, 0]) == set(range(len(C)))


def test_subsequence_dtw_finds_a_query_inside_a_longer_reference():
    rng = np.random.default_rng(1)
    ref = rng.normal(0, 1, (40, 3))
    q = np.repeat(ref[12:22], 2, axis=0)[::3] + rng.normal(0, 0.01, (7, 3))    # resampled stretch 12..21
    C = np.linalg.norm(q[:, None] - ref[None], axis=2)
    _, path = subsequence_dtw(C)
    assert 12 <= path[0, 1] <= 13 and 20 <= path[-1, 1] <= 21
    with pytest.raises(ValueError, match="finite"):
        subsequence_dtw(np.array([[np.nan]]))


def test_align_to_walks_puts_scans_of_a_resurveyed_corridor_at_their_place():
    """Two database walks along a 30 m corridor (one each way), 8 log-distance access points; the walk's scans,
    taken at other points of the corridor, land within the rows' spacing of their truth, and the reversed walk is
    matched in reverse."""
    rng = np.random.default_rng(2)
    aps = np.column_stack([rng.uniform(0, 30, 8), rng.uniform(-5, 5, 8)])

    def rssi(xy):
        d = np.linalg.norm(xy[:, None] - aps[None], axis=2)
        return -40 - 25 * np.log10(np.maximum(d, 1.0)) + rng.normal(0, 1.0, d.shape)

    row_x = np.arange(0, 30.1, 1.5)
    xy_a = np.column_stack([row_x, np.zeros_like(row_x)])
    xy_b = xy_a[::-1]
    db = WifiDatabase(np.vstack([rssi(xy_a), rssi(xy_b)]), np.vstack([xy_a, xy_b]),
                      np.array(["a"] * len(xy_a) + ["b"] * len(xy_b), dtype=object), tuple(f"ap{i}" for i in range(8)))
    true = np.column_stack([np.arange(6.4, 22.0, 2.2), np.zeros(8)])
    res = align_to_walks(db, rssi_distances(db, rssi(true)), true + [1.0, 0.0], radius_m=3.0, min_frac=0.5)
    assert {(w, rev) for _, w, rev, _ in res} == {("a", False), ("a", True), ("b", False), ("b", True)}
    best = {w: (rev, pos) for _, w, rev, pos in reversed(res)}       # cheapest direction per walk
    assert best["a"][0] is False and best["b"][0] is True
    for _, pos in best.values():
        assert np.abs(pos - true).max() <= 1.5
    # a walk far from the track is no candidate; bad parameters raise
    assert align_to_walks(db, rssi_distances(db, rssi(true)), true + [0.0, 20.0]) == []
    with pytest.raises(ValueError, match="min_frac"):
        align_to_walks(db, rssi_distances(db, rssi(true)), true, min_frac=2.0)
    assert [c for c, *_ in res] == sorted(c for c, *_ in res)
