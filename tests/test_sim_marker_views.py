"""Tests of ilocalg.sim.marker_views (views of a square marker on a wall)."""

import numpy as np
import pytest

from ilocalg.sim.marker_views import MARKER_DEFAULTS, simulate_marker_views


def test_views_sit_at_the_distance_and_see_the_marker():
    v = simulate_marker_views(np.random.default_rng(0), 3.0, 40, 1045.0)
    assert np.allclose(np.linalg.norm(v.c_m - v.centre_m, axis=1), 3.0)
    assert np.ptp(v.corners_m[:, 0]) == pytest.approx(MARKER_DEFAULTS["side_m"])
    # the marker's centre projects near the image centre (the phone looks at it)
    assert np.abs(v.img_true_px.mean(axis=1)).max() < 5.0


@pytest.mark.parametrize("kw, match", [({"distance_m": 0.0}, "positive"), ({"size_m": 0.2}, "unknown marker")])
def test_bad_inputs_raise(kw, match):
    args = {"distance_m": 2.0, **kw}
    d = args.pop("distance_m")
    with pytest.raises(ValueError, match=match):
        simulate_marker_views(np.random.default_rng(0), d, 5, 1045.0, **args)
