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


def _textbook_run(t, gyr, acc, t_vt, z_vt, x0, P0, noise, R):
    """The filter written step by step with the public functions (the loop run_hartmann had before the lockstep
    version): predict at every IMU epoch, a PSD test every 400 predictions without a fix, the fixes in order."""
    vt_idx = np.searchsorted(t, t_vt, side="left")
    xs, sds, prior = np.empty((t.size, 15)), np.empty((t.size, 15)), np.empty((t_vt.size, 15))
    x, P, since, n_rep = x0.copy(), P0.copy(), 0, 0
    u = np.hstack([gyr, acc])
    for k in range(t.size):
        if k > 0:
            dt = float(t[k] - t[k - 1])
            x, P = hm.hartmann_predict(x, P, u[k - 1], dt, hm._noise_cov(*noise, dt))
            since += 1
            if since % 400 == 0:
                P, rep = hm.repair_psd(P)
                n_rep += rep
        if (vt_idx == k).any():
            since = 0
        for j in np.flatnonzero(vt_idx == k):
            prior[j] = x
            x, P, _ = hm.hartmann_correct(x, P, z_vt[j], R)
        xs[k], sds[k] = x, np.sqrt(P.diagonal())
    return xs, sds, vt_idx, prior, n_rep


def _assert_same_bits(res, ref):
    for got, want in zip((res.x, res.sd, res.vt_idx, res.prior_at_vt), ref[:4], strict=True):
        assert got.shape == want.shape
        assert np.array_equal(got, want) and np.array_equal(np.signbit(got), np.signbit(want))
    assert res.n_psd_repairs == ref[4]


def test_lockstep_run_equals_the_step_by_step_filter_on_each_sequence():
    """run_hartmann_many moves the sequences together (stacked matmul and solve, one Python pass per epoch);
    each result must be the step-by-step filter's on that sequence alone, bit for bit: sequences with their own
    tracker noise, one losing the tracker early (PSD tests in the outage), one with two fixes at one epoch."""
    from ilocalg.ins.hartmann_eval import _start
    from ilocalg.sim import hartmann as sh

    seqs = [sh.simulate(6.0, seed=s, vt_sd=tuple(f * np.asarray(sh.VT_SD_DEFAULT))) for s, f in ((0, 1.0), (1, 3.0))]
    s2 = sh.simulate(6.0, seed=2)
    keep = s2.t_vt_s < 1.5
    seqs.append(sh.HartmannSequence(**{**s2.__dict__, "t_vt_s": s2.t_vt_s[keep], "z_vt": s2.z_vt[keep]}))
    s3 = sh.simulate(6.0, seed=3)
    dup = np.insert(np.arange(s3.t_vt_s.size), 5, 4)  # fix 4 twice (the second one a little off)
    z3 = s3.z_vt[dup].copy()
    z3[5, 1] += 0.01
    seqs.append(sh.HartmannSequence(**{**s3.__dict__, "t_vt_s": s3.t_vt_s[dup], "z_vt": z3}))
    starts = [_start(q, 1.0) for q in seqs]
    vt_sd = [q.params["vt_sd"] for q in seqs]
    args = (seqs[0].t_s, [q.gyr_b_radps for q in seqs], [q.acc_b_mps2 for q in seqs], [q.t_vt_s for q in seqs],
            [q.z_vt for q in seqs], [x0 for x0, _ in starts], [P0 for _, P0 in starts])
    many = hm.run_hartmann_many(*args, vt_sd=vt_sd)
    noise = (hm.GYR_SD_DEFAULT_RADPS, hm.ACC_SD_DEFAULT_MPS2, 1e-4, 1e-3)
    for i, q in enumerate(seqs):
        ref = _textbook_run(q.t_s, q.gyr_b_radps, q.acc_b_mps2, q.t_vt_s, q.z_vt, *starts[i], noise,
                            np.diag(np.square(vt_sd[i])))
        _assert_same_bits(many[i], ref)
        _assert_same_bits(hm.run_hartmann(args[0], *(a[i] for a in args[1:]), vt_sd=vt_sd[i]), ref)
    assert many[3].prior_at_vt.shape == (seqs[3].t_vt_s.size, 15)


def test_lockstep_run_repairs_each_sequence_as_the_step_by_step_filter_does():
    """Without process noise a P0 with a tiny negative eigenvalue (within check_covariance's tolerance) stays
    indefinite, so the PSD test after 400 predictions repairs it - in that sequence only."""
    from ilocalg.sim import hartmann as sh

    q = sh.simulate(5.0, seed=4)
    P_ok = np.diag(np.full(15, 1e-4))
    P_bad = P_ok.copy()
    P_bad[3, 4] = P_bad[4, 3] = 1e-4 * (1 + 1e-10)  # eigenvalue -1e-14 in (p_x - p_y)
    x0 = np.zeros(15)
    x0[3:6] = q.z_vt[0, 1:4]
    t_vt = q.t_vt_s[:1]
    z = q.z_vt[:1]
    many = hm.run_hartmann_many(q.t_s, [q.gyr_b_radps] * 2, [q.acc_b_mps2] * 2, [t_vt] * 2, [z] * 2, [x0] * 2,
                                [P_ok, P_bad], 0.0, 0.0, 0.0, 0.0)
    for res, P0 in zip(many, (P_ok, P_bad), strict=True):
        ref = _textbook_run(q.t_s, q.gyr_b_radps, q.acc_b_mps2, t_vt, z, x0, P0, (0.0, 0.0, 0.0, 0.0),
                            np.diag(np.square(hm.VT_SD_DEFAULT)))
        _assert_same_bits(res, ref)
    assert many[0].n_psd_repairs == 0 and many[1].n_psd_repairs >= 1


def test_lockstep_run_checks_its_batch():
    t = np.arange(10) * 0.01
    one = (np.zeros((10, 3)), np.zeros((10, 3)), [0.05], np.zeros((1, 4)), np.zeros(15), np.eye(15))
    with pytest.raises(ValueError, match="no sequences"):
        hm.run_hartmann_many(t, [], [], [], [], [], [])
    with pytest.raises(ValueError, match="acc_b_mps2 holds 1 sequences, gyr_b_radps 2"):
        hm.run_hartmann_many(t, [one[0]] * 2, [one[1]], [one[2]] * 2, [one[3]] * 2, [one[4]] * 2, [one[5]] * 2)
    bad = np.eye(15)
    bad[3, 3] = -1.0
    with pytest.raises(ValueError, match=r"sequence 1: P0: variance \[3, 3\] is negative"):
        hm.run_hartmann_many(t, *([a, a] for a in one[:5]), [np.eye(15), bad])
    with pytest.raises(ValueError, match="vt_sd holds 3 rows for 2 sequences"):
        hm.run_hartmann_many(t, *([a, a] for a in one), vt_sd=[hm.VT_SD_DEFAULT] * 3)


def test_model_on_arrays_has_the_bits_of_the_per_sequence_model(monkeypatch):
    """Many sequences take the numpy path of ``_model_many`` (``_model_arrays``): every output, bit for bit, as the
    Python-float path one sequence at a time (states near and far from level, several step lengths)."""
    rng = np.random.default_rng(7)
    n_seq = hm._VECTOR_SEQS + 3
    x = rng.normal(size=(n_seq, hm.HARTMANN_N_STATES)) * np.r_[[0.05, 0.05, 3.0], [10.0] * 3, [1.0] * 3, [0.01] * 6]
    x[0, 0:2] = [1.2, -1.4]  # far from level
    u = rng.normal(size=(n_seq, 6)) * np.r_[[0.5] * 3, [3.0] * 3] + np.r_[0.0, 0.0, 0.0, 0.0, 0.0, 9.81]
    for dt in (0.01, 1 / 3, 0.0123456789):
        arrays = hm._model_many(x, u, dt, {})
        assert x.shape[0] >= hm._VECTOR_SEQS
        monkeypatch.setattr(hm, "_VECTOR_SEQS", 10**9)
        floats = hm._model_many(x, u, dt, {})
        monkeypatch.undo()
        for a, b in zip(arrays, floats, strict=True):
            assert a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))
        x_one = np.stack([hm._model(x[s], u[s], dt)[0] for s in range(n_seq)])  # one sequence at a time
        assert np.array_equal(arrays[0].view(np.int64), x_one.view(np.int64))


def test_lockstep_run_on_prefixes_of_one_clock_equals_each_run_alone():
    """Sequences of different durations at one IMU rate run in one batch (the shorter leave it at their end, the
    longest given last): each result bit for bit the run on that sequence alone; a clock that is not the start
    of the longest is refused."""
    from ilocalg.ins.hartmann_eval import _start
    from ilocalg.sim import hartmann as sh

    seqs = [sh.simulate(d, seed=s) for s, d in ((0, 4.5), (1, 6.0), (2, 4.5), (3, 5.0))]
    starts = [_start(q, 1.0) for q in seqs]
    args = ([q.gyr_b_radps for q in seqs], [q.acc_b_mps2 for q in seqs], [q.t_vt_s for q in seqs],
            [q.z_vt for q in seqs], [x0 for x0, _ in starts], [P0 for _, P0 in starts])
    many = hm.run_hartmann_many([q.t_s for q in seqs], *args)
    for i, q in enumerate(seqs):
        alone = hm.run_hartmann(q.t_s, *(a[i] for a in args))
        assert many[i].x.shape == (q.t_s.size, 15) and np.array_equal(many[i].t_s, q.t_s)
        _assert_same_bits(many[i], (alone.x, alone.sd, alone.vt_idx, alone.prior_at_vt, alone.n_psd_repairs))
    shifted = [q.t_s for q in seqs]
    shifted[2] = shifted[2].copy()
    shifted[2][5] += 1e-6
    with pytest.raises(ValueError, match="sequence 2's t_s is not the start of the longest clock"):
        hm.run_hartmann_many(shifted, *args)
    with pytest.raises(ValueError, match="t_s holds 3 clocks for 4 sequences"):
        hm.run_hartmann_many(shifted[:3], *args)
