"""ilocalg.fusion.tracks: tracks scored at test points."""

import numpy as np

from ilocalg.fusion.tracks import crossover_point, score_at_times, score_points


def test_score_points_wifi_is_the_fix():
    true = np.array([[0.0, 0.0], [1.0, 0.0]])
    fix = np.array([[3.0, 4.0], [1.0, 0.0]])
    tracks = {"A": np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]])}
    tp = score_points(tracks, np.array([0, 2]), true, fix)
    e = tp.set_index(["method", "point"])["error_m"]
    assert e[("Wi-Fi only", 1)] == 5.0 and e[("Wi-Fi only", 2)] == 0.0
    assert e[("A", 1)] == 0.0 and e[("A", 2)] == 1.0


def test_score_at_times_is_causal():
    # states at 0, 1, 2 s; fixes available at 1.5 s and 2.5 s
    tracks = {"A": np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])}
    fix_t = np.array([1.5, 2.5])
    fix = np.array([[10.0, 0.0], [20.0, 0.0]])
    tp = score_at_times(tracks, np.array([0.0, 1.0, 2.0]), np.array([0.5, 1.5, 2.4]),
                        np.zeros((3, 2)), fix_t, fix, np.array([5.0, 0.0]))
    e = tp.set_index(["method", "point"])["error_m"]
    # Wi-Fi only holds the latest fix available (the start fix before any), never a later one
    assert [e[("Wi-Fi only", k)] for k in (1, 2, 3)] == [5.0, 10.0, 10.0]
    assert [e[("A", k)] for k in (1, 2, 3)] == [0.0, 1.0, 2.0]


def test_crossover_point():
    assert crossover_point([0, 1, 2, 5, 6], [3, 3, 3, 3, 3]) == 3
    assert crossover_point([4, 4], [3, 3]) == 0
