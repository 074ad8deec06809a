import numpy as np
import pytest

from ilocalg import ins
from ilocalg.sim import ins_walk


@pytest.fixture(scope="module")
def walk():
    return ins_walk.simulate("samsung", "samsung_s5", seed=3)


def test_same_seed_same_arrays(walk):
    w2 = ins_walk.simulate("samsung", "samsung_s5", seed=3)
    for name in ("t_s", "gyr_b_radps", "acc_b_mps2", "pos_true_n_m", "gnss_pos_n_m", "gcp_pos_n_m"):
        assert np.array_equal(getattr(walk, name), getattr(w2, name))
    w3 = ins_walk.simulate("samsung", "samsung_s5", seed=4)
    assert not np.array_equal(walk.acc_b_mps2[:100], w3.acc_b_mps2[:100])


def test_phone_rate_irregular_15_to_20_hz(walk):
    rate = 1.0 / np.diff(walk.t_s)
    assert rate.min() >= 14.2 and rate.max() <= 20.01 and 15.5 < rate.mean() < 18.0
    assert np.unique(np.round(np.diff(walk.t_s), 6)).size > 2


def test_route_climbs_to_second_floor_and_returns(walk):
    z = walk.pos_true_n_m[:, 2]
    assert z.max() == pytest.approx(4.0, abs=0.1)
    assert np.linalg.norm(walk.pos_true_n_m[-1] - walk.pos_true_n_m[0]) < 0.5


def test_control_points_met_regularly_indoors(walk):
    assert walk.gcp_t_s.size >= 6 and np.all(walk.gcp_t_s >= walk.t_indoor_s)
    gap = np.diff(walk.gcp_t_s)
    assert 8.0 < gap.mean() < 35.0
    # the fix is within a few sd of the truth at that time
    k = np.searchsorted(walk.t_s, walk.gcp_t_s)
    assert np.abs(walk.gcp_pos_n_m - walk.pos_true_n_m[k]).max() < 5 * walk.gcp_sd_m


def test_gnss_only_outdoors(walk):
    assert walk.gnss_t_s.max() < walk.t_indoor_s and walk.gnss_t_s.size > 60


def test_error_free_sensors_integrate_to_truth():
    prof = ins_walk.PhoneProfile("ideal", (1, 1), 0, 0, 0, 0, 0, 0)
    w = ins_walk.simulate("iphone", prof, seed=0)
    n = 20000
    p, _, C = ins.mechanise(w.t_s[:n], w.gyr_b_radps[:n], w.acc_b_mps2[:n], w.pos_true_n_m[0],
                            w.vel_true_n_mps[0], w.mat_true_nb[0])
    assert np.abs(p - w.pos_true_n_m[:n]).max() < 1e-6
    assert np.allclose(C, w.mat_true_nb[:n], atol=1e-9)


def test_bad_arguments():
    with pytest.raises(ValueError, match="route"):
        ins_walk.simulate("nokia")
    with pytest.raises(ValueError, match="profile"):
        ins_walk.simulate("samsung", "nokia")
