import numpy as np
import pytest

from ilocalg.pdr.dead_reckoning import PDR, dead_reckon


def test_square_closes_and_class_agrees():
    d = np.full(8, 2.5)
    th = np.repeat(np.deg2rad([0, 90, 180, 270]), 2)
    tr = dead_reckon(d, th, 1.0, -2.0)
    assert len(tr) == 9
    np.testing.assert_allclose(tr.iloc[-1], [1.0, -2.0], atol=1e-12)
    np.testing.assert_allclose(tr.iloc[2], [6.0, -2.0], atol=1e-12)
    np.testing.assert_allclose(PDR(1.0, -2.0).track(d, th), tr)


def test_path_length_is_sum_of_steps():
    rng = np.random.default_rng(0)
    d = rng.uniform(0.4, 0.8, 50)
    tr = dead_reckon(d, rng.uniform(-np.pi, np.pi, 50))
    seg = np.hypot(*np.diff(tr.to_numpy(), axis=0).T)
    np.testing.assert_allclose(seg, d)


def test_bad_input():
    with pytest.raises(ValueError, match="same length"):
        dead_reckon([1.0, 2.0], [0.0])
    with pytest.raises(ValueError, match="theta_rad is not finite at step 1"):
        dead_reckon([1.0, 2.0], [0.0, np.nan])
    with pytest.raises(ValueError, match="negative"):
        dead_reckon([-1.0], [0.0])
