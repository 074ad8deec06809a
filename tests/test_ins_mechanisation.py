import numpy as np
import pytest

from ilocalg import ins
from ilocalg.ins.mechanisation import coarse_level


def _static(n=2000, dt=0.01, euler=(0.1, -0.2, 1.0)):
    t = np.arange(n) * dt
    C0 = ins.euler_to_dcm(*euler)
    f = C0.T @ (-ins.GRAVITY_N_MPS2)
    return t, C0, np.tile(f, (n, 1)), np.zeros((n, 3))


def test_stationary_imu_stays_put():
    t, C0, acc, gyr = _static()
    p, v, C = ins.mechanise(t, gyr, acc, np.zeros(3), np.zeros(3), C0)
    assert np.abs(p).max() < 1e-9 and np.abs(v).max() < 1e-10
    assert np.allclose(C, C0, atol=1e-12)


def test_constant_velocity_integrates_exactly():
    t, C0, acc, gyr = _static(n=500, dt=0.037)
    v0 = np.array([1.0, -2.0, 0.3])
    p, v, _ = ins.mechanise(t, gyr, acc, np.array([5.0, 6.0, 7.0]), v0, C0)
    assert np.allclose(p, np.array([5.0, 6.0, 7.0]) + t[:, None] * v0, atol=1e-9)
    assert np.allclose(v, v0, atol=1e-12)


def test_constant_acceleration_and_irregular_steps_exact():
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.05, 0.07, 300))
    C0 = np.eye(3)
    a_n = np.array([0.2, -0.1, 0.05])
    acc = np.tile(C0.T @ (a_n - ins.GRAVITY_N_MPS2), (t.size, 1))
    p, v, _ = ins.mechanise(t, np.zeros((t.size, 3)), acc, np.zeros(3), np.zeros(3), C0)
    tt = t - t[0]
    assert np.allclose(p, 0.5 * tt[:, None] ** 2 * a_n, atol=1e-9)


def test_constant_rate_rotation_matches_closed_form():
    n, dt = 1000, 0.01
    t = np.arange(n) * dt
    w = np.array([0.0, 0.0, 0.5])
    gyr = np.tile(w, (n, 1))
    acc = np.tile([0.0, 0.0, 9.80665], (n, 1))
    _, _, C = ins.mechanise(t, gyr, acc, np.zeros(3), np.zeros(3), np.eye(3))
    yaw = ins.dcm_to_euler(C)[:, 2]
    assert np.allclose(np.unwrap(yaw), 0.5 * t, atol=1e-10)


def test_euler_dcm_roundtrip_and_orthonormal():
    rng = np.random.default_rng(0)
    e = np.column_stack([rng.uniform(-3, 3, 50), rng.uniform(-1.5, 1.5, 50), rng.uniform(-3, 3, 50)])
    C = ins.euler_to_dcm(e[:, 0], e[:, 1], e[:, 2])
    assert np.allclose(C @ np.swapaxes(C, 1, 2), np.eye(3), atol=1e-12)
    assert np.allclose(ins.dcm_to_euler(C), e, atol=1e-9)


def test_rotvec_roundtrip_and_small_angle():
    for v in ([0.1, -0.2, 0.3], [1e-10, 0, 0], [0, 2.0, 0.5]):
        v = np.array(v)
        assert np.allclose(ins.dcm_to_rotvec(ins.rotvec_to_dcm(v)), v, atol=1e-9)
    v = np.array([0.3, -0.1, 0.2])
    assert np.allclose(ins.rotvec_to_dcm(v) @ [1.0, 2.0, 3.0] - [1.0, 2.0, 3.0],
                       np.cross(v, [1.0, 2.0, 3.0]), atol=0.2)


def test_coarse_level_recovers_roll_pitch():
    C = ins.euler_to_dcm(0.2, -0.3, 2.0)
    roll, pitch = coarse_level(C.T @ [0, 0, 9.80665])
    assert roll == pytest.approx(0.2) and pitch == pytest.approx(-0.3)


def test_bad_input_raises():
    t, C0, acc, gyr = _static(n=10)
    with pytest.raises(ValueError, match="gyr_b_radps"):
        ins.mechanise(t, gyr[:5], acc, np.zeros(3), np.zeros(3), C0)
    with pytest.raises(ValueError, match="strictly increasing"):
        ins.mechanise(t[::-1], gyr, acc, np.zeros(3), np.zeros(3), C0)
    acc[3, 1] = np.nan
    with pytest.raises(ValueError, match="acc_b_mps2"):
        ins.mechanise(t, gyr, acc, np.zeros(3), np.zeros(3), C0)


def test_phone_to_body_rotation():
    M = ins.MAT_PHONE_TO_BODY
    assert np.allclose(M @ M.T, np.eye(3)) and np.linalg.det(M) == pytest.approx(1.0)
    # the top of the phone (y_p) points forward (x_b), its right edge (x_p) to the walker's right (-y_b)
    assert np.array_equal(ins.phone_to_body([0.0, 1.0, 0.0]), [1.0, 0.0, 0.0])
    assert np.array_equal(ins.phone_to_body([1.0, 0.0, 0.0]), [0.0, -1.0, 0.0])
    assert np.allclose(M.T, ins.euler_to_dcm(0.0, 0.0, np.pi / 2))  # body -> phone is +90 deg about z
    v = np.random.default_rng(0).normal(size=(5, 3))
    assert np.allclose(ins.phone_to_body(v), v @ M.T)
    with pytest.raises(ValueError, match="vec_p"):
        ins.phone_to_body(np.zeros((2, 2)))


def test_rotation_helpers_agree_with_scipy_rotation():
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(3)
    v = rng.normal(size=(2000, 3)) * 10 ** rng.uniform(-9, 0.4, (2000, 1))  # angles 1e-9 .. ~2.5 rad
    ref = Rotation.from_rotvec(v)
    assert np.allclose(ins.rotvecs_to_dcm(v), ref.as_matrix(), rtol=0, atol=1e-15)
    assert np.array_equal(ins.rotvec_to_dcm(v[7]), ins.rotvecs_to_dcm(v)[7])
    back = ins.dcm_to_rotvec(ref.as_matrix())
    assert np.allclose(back, ref.as_rotvec(), rtol=0, atol=1e-12)  # acos loses digits near pi only
    assert np.allclose(back[:1], ins.dcm_to_rotvec(ref.as_matrix()[0]))
    e = rng.uniform(-1.2, 1.2, (500, 3))
    assert np.allclose(ins.euler_to_dcm(e[:, 0], e[:, 1], e[:, 2]),
                       Rotation.from_euler("ZYX", e[:, ::-1]).as_matrix(), rtol=0, atol=1e-15)
    assert np.allclose(ins.dcm_to_euler(ins.euler_to_dcm(e[:, 0], e[:, 1], e[:, 2])), e, atol=1e-12)
    with pytest.raises(ValueError, match="mat"):
        ins.dcm_to_rotvec(np.eye(4))
