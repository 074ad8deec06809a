import numpy as np
import pytest

from ilocalg.ins import mechanise
from ilocalg.ins.mechanisation import euler_to_dcm
from ilocalg.sim import hartmann as sh


@pytest.fixture(scope="module")
def seq():
    return sh.simulate(40.0, seed=2)


def test_deterministic(seq):
    s2 = sh.simulate(40.0, seed=2)
    assert np.array_equal(seq.acc_b_mps2, s2.acc_b_mps2) and np.array_equal(seq.z_vt, s2.z_vt)
    assert not np.array_equal(sh.simulate(40.0, seed=3).z_vt[:5], seq.z_vt[:5])


def test_imu_rate_noise_and_volume(seq):
    assert np.allclose(np.diff(seq.t_s), 1 / 400)
    still = seq.t_s < 2.5  # initial rest: gyr = bias + white noise of 0.4 deg/s
    sd = np.rad2deg(seq.gyr_b_radps[still].std(axis=0))
    assert np.all((sd > 0.35) & (sd < 0.45))
    span = seq.pos_v_m.max(axis=0) - seq.pos_v_m.min(axis=0)
    assert np.all(span < 1.5) and span[:2].max() > 0.3


def test_tracker_rate_and_outages(seq):
    rate = seq.t_vt_s.size / seq.t_s[-1]
    assert 3.0 < rate < 9.0
    assert np.diff(seq.t_vt_s).max() > 0.5


def test_error_free_imu_integrates_to_truth():
    s = sh.simulate(10.0, seed=1, gyr_sd_dps=0.0, acc_sd_mps2=0.0, gyr_bias_sd_dps=0.0, acc_bias_sd_mps2=0.0)
    C0 = euler_to_dcm(*s.euler_rad[0])
    p, _, _ = mechanise(s.t_s, s.gyr_b_radps, s.acc_b_mps2, s.pos_v_m[0], s.vel_v_mps[0], C0)
    assert np.abs(p - s.pos_v_m).max() < 1e-6


def test_bad_arguments():
    with pytest.raises(ValueError, match="duration_s"):
        sh.simulate(2.0)
    with pytest.raises(ValueError, match="detect_prob"):
        sh.simulate(10.0, detect_prob=0.0)


def test_table2_outages_are_simulated():
    s = sh.simulate(120.0, seed=4)
    out = np.asarray(s.params["outages_s"])
    assert out.shape[1] == 2 and np.all(out[:, 1] - out[:, 0] > 1.0)
    # no tracker fix inside an outage
    for a, b in out:
        assert not np.any((s.t_vt_s > a) & (s.t_vt_s < b))
    gaps = np.diff(s.t_vt_s)
    assert (gaps > 1.0).sum() >= 10 and 1.5 < gaps.max() < 6.0
    # the expected number over many sequences is the Table 2 rate
    n = [len(sh.simulate(20.0, seed=k, outage_rate_per_s=1.0).params["outages_s"]) for k in range(10)]
    assert np.mean(n) == pytest.approx(17.0, rel=0.25)
    none = sh.simulate(40.0, seed=2, outage_rate_per_s=0.0)
    assert none.params["outages_s"] == []
