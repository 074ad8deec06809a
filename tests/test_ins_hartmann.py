import numpy as np
import pytest

from ilocalg.ins import hartmann as hm
from ilocalg.ins.mechanisation import euler_to_dcm


def _xu():
    rng = np.random.default_rng(0)
    x = np.concatenate([[0.2, -0.3, 1.1], rng.normal(size=3), rng.normal(size=3), rng.normal(0, 0.01, 3),
                        rng.normal(0, 0.05, 3)])
    u = np.concatenate([[0.5, -0.2, 0.8], [0.3, 0.2, 9.9]])
    return x, u


def test_jacobians_match_finite_differences():
    x, u = _xu()
    dt = 0.01
    Phi, W = hm.hartmann_jacobians(x, u, dt)
    eps = 1e-6
    num = np.column_stack([(hm.hartmann_f(x + eps * e, u, dt) - hm.hartmann_f(x - eps * e, u, dt)) / (2 * eps)
                           for e in np.eye(15)])
    assert np.allclose(Phi, num, atol=1e-7)
    # sensor noise enters the navigation states exactly as the bias does (eq. 14-15)
    assert np.allclose(W[:9, 0:3], num[:9, 9:12], atol=1e-7)
    assert np.allclose(W[:9, 3:6], num[:9, 12:15], atol=1e-7)


def test_euler_rate_matrix_consistent_with_dcm_kinematics():
    phi, th, psi = 0.3, -0.4, 0.9
    w = np.array([0.2, -0.5, 0.7])
    dt = 1e-6
    d = hm.euler_rate_matrix(phi, th) @ w
    C0 = euler_to_dcm(phi, th, psi)
    C1 = euler_to_dcm(phi + d[0] * dt, th + d[1] * dt, psi + d[2] * dt)
    Cdot = (C1 - C0) / dt
    wx = C0.T @ Cdot  # = [w x]
    assert np.allclose([wx[2, 1], wx[0, 2], wx[1, 0]], w, atol=1e-5)


def test_static_object_stays_put_and_class_agrees_with_functions():
    x = np.zeros(15)
    x[2] = 0.5
    u = np.concatenate([np.zeros(3), [0.0, 0.0, 9.80665]])
    P0 = np.eye(15) * 0.01
    Qw = np.eye(12) * 1e-6
    R = np.eye(4) * 1e-4
    ekf = hm.HartmannEKF(x, P0, Qw, R)
    xf, Pf = x.copy(), P0.copy()
    for _ in range(400):
        ekf.predict(u, 0.0025)
        xf, Pf = hm.hartmann_predict(xf, Pf, u, 0.0025, Qw)
    assert np.allclose(ekf.x, xf) and np.allclose(ekf.P, Pf)
    assert np.abs(xf[3:9]).max() < 1e-12
    z = np.array([0.52, 0.01, 0.0, 0.0])
    ekf.correct(z)
    xc, Pc, innov = hm.hartmann_correct(xf, Pf, z, R)
    assert np.allclose(ekf.x, xc) and np.allclose(ekf.P, Pc)
    assert innov[0] == pytest.approx(0.02)
    assert np.all(np.diag(Pc) <= np.diag(Pf) + 1e-15)


def test_yaw_innovation_wraps():
    x = np.zeros(15)
    x[2] = np.pi - 0.01
    _, _, innov = hm.hartmann_correct(x, np.eye(15), np.array([-np.pi + 0.01, 0, 0, 0]), np.eye(4))
    assert innov[0] == pytest.approx(0.02)


def test_run_validation():
    t = np.arange(10) * 0.01
    with pytest.raises(ValueError, match="z_vt"):
        hm.run_hartmann(t, np.zeros((10, 3)), np.zeros((10, 3)), [0.05], np.zeros((1, 3)), np.zeros(15), np.eye(15))
    with pytest.raises(ValueError, match="within the IMU log"):
        hm.run_hartmann(t, np.zeros((10, 3)), np.zeros((10, 3)), [5.0], np.zeros((1, 4)), np.zeros(15), np.eye(15))


def test_covariance_checked_at_entry():
    t = np.arange(10) * 0.01
    args = (t, np.zeros((10, 3)), np.zeros((10, 3)), [0.05], np.zeros((1, 4)), np.zeros(15))
    P0 = np.eye(15)
    P0[3, 3] = -1.0
    with pytest.raises(ValueError, match=r"P0: variance \[3, 3\] is negative"):
        hm.run_hartmann(*args, P0)
    with pytest.raises(ValueError, match="vt_sd"):
        hm.run_hartmann(*args, np.eye(15), vt_sd=(0.01, 0.0, 0.003, 0.003))
    with pytest.raises(ValueError, match="gyr_sd_radps"):
        hm.run_hartmann(*args, np.eye(15), gyr_sd_radps=np.nan)
    with pytest.raises(ValueError, match="Qw"):
        hm.HartmannEKF(np.zeros(15), np.eye(15), -np.eye(12), np.eye(4))


def test_covariance_stays_positive_definite_over_a_long_outage():
    from ilocalg.experiments.ins_hartmann import run_sequence
    from ilocalg.sim import hartmann as sh

    seq = sh.simulate(200.0, seed=0, outage_rate_per_s=0.0)
    keep = seq.t_vt_s < 10.0  # tracker lost after 10 s: 190 s of prediction
    seq = sh.HartmannSequence(**{**seq.__dict__, "t_vt_s": seq.t_vt_s[keep], "z_vt": seq.z_vt[keep]})
    res = run_sequence(seq)
    assert np.all(np.isfinite(res.sd))
    # the last covariance can be rebuilt from its sds: every sd is finite and positive
    assert np.all(res.sd[-1] > 0)


def test_joseph_update_equals_eq29_form():
    rng = np.random.default_rng(2)
    A = rng.normal(size=(15, 15))
    P = A @ A.T + np.eye(15)
    R = np.diag([1e-4, 1e-5, 1e-5, 4e-5])
    x = rng.normal(size=15)
    z = hm.hartmann_h(x) + 0.01
    _, Pj, _ = hm.hartmann_correct(x, P, z, R)
    H = hm.HARTMANN_H
    K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
    assert np.allclose(Pj, (np.eye(15) - K @ H) @ P, atol=1e-9)
    assert np.linalg.eigvalsh(Pj).min() > 0


def test_repair_psd_only_when_needed():
    P = np.diag([1.0, 2.0])
    assert hm.repair_psd(P)[1] is False
    Q, rep = hm.repair_psd(np.array([[1.0, 1.0 + 1e-9], [1.0 + 1e-9, 1.0]]))
    assert rep and np.linalg.eigvalsh(Q).min() > 0
