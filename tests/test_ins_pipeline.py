import numpy as np
import pytest

from ilocalg import ins
from ilocalg.sim import ins_walk


@pytest.fixture(scope="module")
def walk():
    return ins_walk.simulate("iphone", "iphone_5s", seed=1)


def _rms_h(pos, walk):
    ind = walk.t_s >= walk.t_indoor_s
    d = pos[ind, :2] - walk.pos_true_n_m[ind, :2]
    return float(np.sqrt(np.mean(np.sum(d**2, axis=1))))


def test_constraints_and_control_points_order_like_the_paper(walk):
    r_wvc = ins.run_walk(walk, "wvc", use_gcp=False)
    r_gcp = ins.run_walk(walk, "wvc", use_gcp=True)
    sm = ins.eskf_rts_smooth(r_gcp, with_cov=False)
    e_wvc, e_gcp, e_sm = _rms_h(r_wvc.pos_n_m, walk), _rms_h(r_gcp.pos_n_m, walk), _rms_h(sm.pos_n_m, walk)
    assert e_gcp < e_wvc and e_sm < e_gcp
    assert e_sm < 3.0
    # the filter's covariance stays symmetric positive definite over a real-looking walk
    P = r_gcp.P_plus[:: 50]
    assert np.allclose(P, np.swapaxes(P, 1, 2)) and np.linalg.eigvalsh(P).min() > 0


def test_walk_updates_kinds(walk):
    ups = {u.name: u for u in ins.walk_updates(walk, "nhc", use_gcp=True)}
    assert set(ups) == {"GNSS", "ZUPT", "NHC", "GCP"}
    assert ups["GCP"].t_s.size == walk.gcp_t_s.size
    # ZUPTs fall where the walker (nearly) stands still
    k = np.searchsorted(walk.t_s, ups["ZUPT"].t_s)
    speed = np.linalg.norm(walk.vel_true_n_mps[k], axis=1)
    assert k.size > 20 and np.percentile(speed, 80) < 0.1 and speed.max() < 0.3
    with pytest.raises(ValueError, match="constraint"):
        ins.walk_updates(walk, "foo")


def test_body_imu_from_a_phone_log():
    import pandas as pd

    from ilocalg.io.schema import ACC_COLS, GYR_COLS

    t = np.arange(5) * 0.02
    # a phone lying flat, top pointing forward, accelerating forward and turning left
    log = pd.DataFrame({**dict(zip(ACC_COLS, ([0.0] * 5, [0.5] * 5, [9.81] * 5), strict=True)),
                        **dict(zip(GYR_COLS, ([0.0] * 5, [0.0] * 5, [0.3] * 5), strict=True))}, index=t)
    ts, gyr_b, acc_b = ins.body_imu_from_log(log)
    assert np.array_equal(ts, t)
    assert np.allclose(acc_b, [0.5, 0.0, 9.81]) and np.allclose(gyr_b, [0.0, 0.0, 0.3])
    with pytest.raises(ValueError, match="gyr_x_radps"):
        ins.body_imu_from_log(log.drop(columns=GYR_COLS[0]))


def test_walk_batches_split_evenly_in_order():
    from ilocalg.ins.pipeline import walk_batches

    assert walk_batches(list(range(8)), 6) == [[0, 1, 2, 3], [4, 5, 6, 7]]
    assert [len(b) for b in walk_batches(list(range(24)), 6)] == [6, 6, 6, 6]
    assert [len(b) for b in walk_batches(list(range(13)), 6)] == [4, 4, 5]
    assert walk_batches([1, 2], 6) == [[1, 2]] and walk_batches([], 6) == []
    with pytest.raises(ValueError, match="max_size"):
        walk_batches([1], 0)
