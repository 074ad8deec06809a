"""Tests of the PoI-wall photo simulator."""

import numpy as np
import pytest

from ilocalg.photo import project
from ilocalg.sim import photo_poi


def test_same_seed_same_arrays_and_different_seed_differs():
    a = photo_poi.simulate(3, n_photos=2)
    b = photo_poi.simulate(3, n_photos=2)
    c = photo_poi.simulate(4, n_photos=2)
    for name in ("c_m", "T_true", "T_meas", "img_px", "c0_good_m", "c0_bad_m"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.img_px, c.img_px)


def test_layout_matches_the_thesis_description():
    shots = photo_poi.shots_frame()
    d = shots["dist_to_p4_m"].to_numpy()
    assert np.all(np.diff(d) > 0)  # t1 nearest to p4, t7 farthest
    np.testing.assert_allclose(np.diff(shots["y_m"]), 1.0)  # one metre apart
    z = photo_poi.POIS_M[:, 2]
    on_line = z[[0, 2, 3, 4, 5]]
    assert np.ptp(on_line) < 0.05  # p1, p3, p4, p5, p6 almost on one horizontal line
    assert abs(z[1] - on_line.mean()) > 0.3 and abs(z[6] - on_line.mean()) > 0.3


def test_noise_statistics_match_the_documented_inputs():
    s = photo_poi.simulate(0, n_photos=300)
    drag = (s.img_px - s.img_true_px).ravel()
    assert drag.std() == pytest.approx(photo_poi.DEFAULTS["drag_sd_px"], rel=0.05)
    # sensor error rotation: T_meas = T_true @ R_err
    R = np.swapaxes(s.T_true, 1, 2) @ s.T_meas
    yaw = np.degrees(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
    assert yaw.std() == pytest.approx(photo_poi.DEFAULTS["yaw_sd_deg"], rel=0.1)
    assert np.all(s.c0_good_m[:, 1] >= photo_poi.ROOM_M[2])
    good = np.hypot(*(s.c0_good_m[:, :2] - s.c_m[:, :2]).T).mean()
    bad = np.hypot(*(s.c0_bad_m[:, :2] - s.c_m[:, :2]).T).mean()
    assert good < bad


def test_true_screen_points_are_exact_projections_on_screen():
    s = photo_poi.simulate(1, n_photos=3)
    np.testing.assert_allclose(project(s.pois_m, s.c_m, s.T_true, s.f_px), s.img_true_px)
    assert np.all(np.abs(s.img_true_px[..., 0]) <= 640) and np.all(np.abs(s.img_true_px[..., 1]) <= 360)


def test_bad_parameters_raise():
    with pytest.raises(ValueError, match="unknown simulation parameters"):
        photo_poi.simulate(0, drag_px=3)
    with pytest.raises(ValueError, match="n_photos"):
        photo_poi.simulate(0, n_photos=0)
    with pytest.raises(ValueError, match="outside the screen"):
        photo_poi.simulate(0, n_photos=1, f_px=3000.0)


def test_changing_one_input_leaves_other_draws_unchanged():
    a = photo_poi.simulate(0, n_photos=3)
    b = photo_poi.simulate(0, n_photos=3, good_guess_sd_m=0.5, drag_sd_px=3.0)
    np.testing.assert_array_equal(a.c0_bad_m, b.c0_bad_m)
    np.testing.assert_array_equal(a.T_meas, b.T_meas)
    np.testing.assert_allclose((b.img_px - b.img_true_px) * 4.0, a.img_px - a.img_true_px)


@pytest.mark.parametrize("name", [k for k in photo_poi.LAYOUTS if k != "row"])
def test_every_layout_satisfies_the_text(name):
    chk = photo_poi.check_layout(name)
    assert chk["satisfied"].all(), chk.loc[~chk["satisfied"], ["constraint", "value"]].to_string()


def test_layout_satisfies_line_707_distance_ordering():
    """Chiu (2013), L707: {1,2} and {6,7} are nearer the test positions than {3,4}, {3,5}, {4,5}, {3,4,5}."""
    lay = photo_poi.LAYOUTS[photo_poi.DEFAULT_LAYOUT]
    d = np.linalg.norm(lay.pois_m[None, :, :2] - lay.shots_xy_m[:, None, :], axis=2).mean(axis=0)
    near = [d[[0, 1]].mean(), d[[5, 6]].mean()]
    far = [d[[2, 3]].mean(), d[[2, 4]].mean(), d[[3, 4]].mean(), d[[2, 3, 4]].mean()]
    assert max(near) < min(far)
    # the earlier one-wall row breaks it (kept only as a labelled sensitivity case)
    row = photo_poi.check_layout("row").set_index("paper_line")
    assert not row.loc["L707"]["satisfied"].all()


def test_layouts_are_the_documented_selection_from_the_grid():
    import itertools
    g = photo_poi.LAYOUT_GRID
    keys = ("t1_to_end_wall_m", "half_width_m", "side_y_m", "end_spacing_m")
    ok = [d for d in itertools.product(*(g[k] for k in keys))
          if photo_poi.check_layout(photo_poi.make_layout("x", *d))["satisfied"].all()]
    picks = [ok[i] for i in np.round(np.linspace(0, len(ok) - 1, 6)).astype(int)]
    assert [photo_poi.LAYOUT_DIMENSIONS[k][:4] for k in "BCDEFG"] == picks
    span = {k: (min(g[k]), max(g[k])) for k in keys}
    mid = np.array([(a + b) / 2 for a, b in span.values()])
    width = np.array([b - a for a, b in span.values()])
    nearest = min(ok, key=lambda d: float(np.sum(((np.array(d) - mid) / width) ** 2)))
    assert photo_poi.LAYOUT_DIMENSIONS["A"][:4] == nearest


def test_layout_choice_changes_the_geometry_only():
    a = photo_poi.simulate(0, n_photos=2)
    b = photo_poi.simulate(0, n_photos=2, layout="D")
    assert a.params["layout"] == "A" and b.params["layout"] == "D"
    assert not np.array_equal(a.pois_m, b.pois_m)
    with pytest.raises(ValueError, match="layout"):
        photo_poi.simulate(0, n_photos=1, layout="nope")


def test_one_wall_layouts_satisfy_the_text_and_are_the_documented_picks():
    import itertools
    g = photo_poi.WALL_LAYOUT_GRID
    ok = [d for d in itertools.product(*g.values())
          if photo_poi.check_layout(photo_poi.make_wall_layout("x", *d))["satisfied"].all()]
    assert len(ok) >= 4
    picks = [ok[i] for i in np.round(np.linspace(0, len(ok) - 1, 4)).astype(int)]
    assert [photo_poi.WALL_LAYOUT_DIMENSIONS[k] for k in ("W1", "W2", "W3", "W4")] == picks
    for k in ("W1", "W2", "W3", "W4"):
        lay = photo_poi.LAYOUTS[k]
        assert np.allclose(lay.pois_m[:, 1], 0.0)                  # every PoI on one wall
        assert photo_poi.check_layout(k)["satisfied"].all()
    every = photo_poi.satisfying_layouts()
    assert sum(n.startswith("Wg") for n in every) == len(ok)
    assert all(photo_poi.check_layout(lay)["satisfied"].all() for lay in every.values())
