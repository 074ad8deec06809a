import numpy as np
import pytest
from filterpy.kalman import KalmanFilter
from scipy import stats

from ilocalg import ins
from ilocalg.ins.eskf import ATT, POS, VEL

ACC_N, GYR_N = 0.02, 0.002  # noise densities of the consistency scenario
CFG = ins.EskfConfig(acc_vrw_mps_rsqrt_s=ACC_N, gyr_arw_rad_rsqrt_s=GYR_N, acc_bias_rw_mps2_rsqrt_s=1e-6,
                     gyr_bias_rw_radps_rsqrt_s=1e-7, acc_sf_rw_rsqrt_s=1e-7, gyr_sf_rw_rsqrt_s=1e-7)
P0_SD = dict(pos_sd_m=0.5, vel_sd_mps=0.05, att_sd_rad=(0.01, 0.01, 0.03), acc_bias_sd_mps2=0.05,
             gyr_bias_sd_radps=0.002, acc_sf_sd=0.01, gyr_sf_sd=0.01)


def circle_run(seed, n=1200, dt=0.05, fix_every=20, fix_sd=0.3):
    """Truth from the discrete mechanisation of a level circle; sensors with errors drawn from P0."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    v, w = 1.2, 0.25
    f_true = np.tile([0.0, v * w, 9.80665], (n, 1))
    g_true = np.tile([0.0, 0.0, w], (n, 1))
    pos_t, vel_t, mat_t = ins.mechanise(t, g_true, f_true, np.zeros(3), np.array([v, 0, 0]), np.eye(3))
    P0 = ins.initial_covariance(**P0_SD)
    x0 = rng.normal(0.0, 1.0, 21) * np.sqrt(np.diag(P0))
    ba, bg, sa, sg = x0[9:12], x0[12:15], x0[15:18], x0[18:21]
    acc = (1 + sa) * f_true + ba + rng.normal(0, ACC_N / np.sqrt(dt), (n, 3))
    gyr = (1 + sg) * g_true + bg + rng.normal(0, GYR_N / np.sqrt(dt), (n, 3))
    idx = np.arange(fix_every, n, fix_every)
    fixes = ins.PositionFix(t[idx], pos_t[idx] + rng.normal(0, fix_sd, (idx.size, 3)), np.full((idx.size, 3), fix_sd))
    # initial estimate = truth - error (error = true - estimated)
    p0 = pos_t[0] - x0[POS]
    v0 = vel_t[0] - x0[VEL]
    C0 = ins.rotvec_to_dcm(-x0[ATT]) @ mat_t[0]
    res = ins.run_eskf(t, gyr, acc, p0, v0, C0, P0, [fixes], CFG)
    return res, pos_t, vel_t, mat_t, idx


def nav_error(pos, vel, mat, pos_t, vel_t, mat_t):
    att = np.array([ins.dcm_to_rotvec(mt @ m.T) for m, mt in zip(mat, mat_t, strict=True)])
    return np.hstack([pos_t - pos, vel_t - vel, att])


def test_nees_consistent_over_seeded_runs():
    runs = [circle_run(s) for s in range(8)]
    nees = []
    for res, pos_t, vel_t, mat_t, idx in runs:
        e = nav_error(res.pos_n_m, res.vel_n_mps, res.mat_nb, pos_t, vel_t, mat_t)
        k = idx[5:]
        for kk in k:
            nees.append(e[kk] @ np.linalg.solve(res.P_plus[kk][:9, :9], e[kk]))
    nees = np.asarray(nees)
    dof = 9 * nees.size
    lo, hi = stats.chi2.ppf([0.001, 0.999], dof) / nees.size
    # time-correlated samples: allow the 99.8 % band widened by 50 %
    assert lo * 0.5 < nees.mean() < hi * 1.5, (nees.mean(), lo, hi)
    assert 6.0 < nees.mean() < 13.0


def test_nis_matches_measurement_dimension():
    res, *_ = circle_run(3)
    nis = res.nis[np.isfinite(res.nis)][5:]
    assert 2.0 < nis.mean() < 4.5


def test_covariance_symmetric_positive_definite():
    res, *_ = circle_run(1)
    for P in (res.P_plus, res.P_minus):
        assert np.allclose(P, np.swapaxes(P, 1, 2), atol=1e-12)
        assert np.linalg.eigvalsh(P).min() > 0
    # updates never increase the variance
    upd = res.n_meas > 0
    assert np.all(np.diagonal(res.P_plus[upd], axis1=1, axis2=2)
                  <= np.diagonal(res.P_minus[upd], axis1=1, axis2=2) + 1e-12)


def test_joseph_update_matches_filterpy():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(21, 21))
    P = A @ A.T + np.eye(21)
    H = rng.normal(size=(4, 21))
    R = np.array([0.1, 0.2, 0.3, 0.4])
    z = rng.normal(size=4)
    dx, P1, nis = ins.joseph_update(P.copy(), z, H, R)
    kf = KalmanFilter(dim_x=21, dim_z=4)
    kf.x = np.zeros((21, 1))
    kf.P = P.copy()
    kf.H = H
    kf.R = np.diag(R)
    kf.update(z.reshape(4, 1))
    assert np.allclose(dx, kf.x.ravel(), atol=1e-10)
    assert np.allclose(P1, kf.P, atol=1e-9)
    assert nis == pytest.approx(float(z @ np.linalg.solve(H @ P @ H.T + np.diag(R), z)))


def test_body_velocity_jacobian_matches_finite_difference():
    C = ins.euler_to_dcm(0.1, -0.2, 0.7)
    v = np.array([1.0, 0.4, -0.1])
    e0, H = ins.body_velocity_rows(C, v, np.zeros(3))
    dx = np.zeros(21)
    dx[VEL] = [0.001, -0.002, 0.0005]
    dx[ATT] = [0.001, 0.0005, -0.002]
    C1 = ins.rotvec_to_dcm(dx[ATT]) @ C
    vb1 = C1.T @ (v + dx[VEL])
    assert np.allclose(vb1 - C.T @ v, H @ dx, atol=1e-5)


def test_transition_matrix_matches_error_propagation():
    """Phi predicts how a small error in the inputs of one mechanisation step propagates."""
    C = ins.euler_to_dcm(0.05, 0.1, 0.4)
    f = np.array([0.3, -0.2, 9.9])
    w = np.array([0.1, -0.05, 0.3])
    dt = 0.05
    Phi = ins.transition_matrix(C, f, w, dt)
    dx = np.zeros(21)
    dx[ATT] = [0.002, -0.001, 0.003]
    dx[9:12] = [0.01, -0.02, 0.01]
    dx[12:15] = [0.001, 0.002, -0.001]
    # true = estimate + error; the true sensors are the corrected ones minus the bias errors
    Ct = ins.rotvec_to_dcm(dx[ATT]) @ C
    pe, ve, Ce = (a[1] for a in ins.strapdown(np.zeros(3), np.zeros(3), C, w[None], f[None], [dt]))
    pt, vt, Cm = (a[1] for a in ins.strapdown(np.zeros(3), np.zeros(3), Ct, (w - dx[12:15])[None],
                                              (f - dx[9:12])[None], [dt]))
    pred = Phi @ dx
    assert np.allclose(vt - ve, pred[VEL], atol=6e-5)
    assert np.allclose(ins.dcm_to_rotvec(Cm @ Ce.T), pred[ATT], atol=2e-5)


def test_measurement_and_run_validation():
    with pytest.raises(ValueError, match="sd must be > 0"):
        ins.PositionFix(np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3)))
    with pytest.raises(ValueError, match="GNSS: t_s"):
        ins.PositionFix(np.zeros(2), np.zeros((1, 3)), np.ones((1, 3)), name="GNSS")
    t = np.arange(10) * 0.1
    with pytest.raises(ValueError, match="Measurement protocol"):
        ins.run_eskf(t, np.zeros((10, 3)), np.tile([0, 0, 9.8], (10, 1)), np.zeros(3), np.zeros(3), np.eye(3),
                     ins.initial_covariance(), [("pos_n", t[:1])])
    u = ins.PositionFix(np.array([5.0]), np.zeros((1, 3)), np.ones((1, 3)))
    with pytest.raises(ValueError, match="within the IMU log"):
        ins.run_eskf(t, np.zeros((10, 3)), np.tile([0, 0, 9.8], (10, 1)), np.zeros(3), np.zeros(3), np.eye(3),
                     ins.initial_covariance(), [u])
    with pytest.raises(ValueError, match="P0"):
        ins.run_eskf(t, np.zeros((10, 3)), np.tile([0, 0, 9.8], (10, 1)), np.zeros(3), np.zeros(3), np.eye(3),
                     np.eye(15))
    with pytest.raises(ValueError, match="EskfConfig"):
        ins.EskfConfig(acc_vrw_mps_rsqrt_s=-1.0)


def test_run_eskf_without_updates_is_the_mechanisation():
    """With no measurement and zero sensor-error estimates the filter's solution is :func:`mechanise`."""
    rng = np.random.default_rng(4)
    t = np.cumsum(rng.uniform(0.04, 0.07, 400))
    gyr = np.tile([0.01, -0.02, 0.25], (t.size, 1)) + rng.normal(0, 0.01, (t.size, 3))
    acc = np.tile([0.1, 0.3, 9.81], (t.size, 1)) + rng.normal(0, 0.05, (t.size, 3))
    C0 = ins.euler_to_dcm(0.02, -0.01, 0.8)
    res = ins.run_eskf(t, gyr, acc, np.ones(3), np.array([1.0, 0.2, 0.0]), C0, ins.initial_covariance(), [], CFG)
    pos, vel, mat = ins.mechanise(t, gyr, acc, np.ones(3), np.array([1.0, 0.2, 0.0]), C0)
    assert np.array_equal(res.pos_n_m, pos) and np.array_equal(res.vel_n_mps, vel)
    assert np.array_equal(res.mat_nb, mat)
    assert not res.dx.any() and res.n_meas.sum() == 0 and np.isnan(res.nis).all()
    # the covariance is the chain of eskf_predict over the stored transition matrices
    P = res.P_plus[0]
    for k in range(1, 6):
        P = ins.eskf_predict(P, res.Phi[k], ins.process_noise_diag(CFG, t[k] - t[k - 1]))
        assert np.array_equal(P, res.P_minus[k])


class _HeightFix:
    """A new measurement type written outside the package: the height alone (obeys ins.Measurement)."""

    name = "height"

    def __init__(self, t_s, h_m, sd_m):
        self.t_s, self.h_m, self.sd_m = np.asarray(t_s, dtype=float), np.asarray(h_m, dtype=float), sd_m

    def rows(self, j, pos_n_m, vel_n_mps, mat_nb):
        H = np.zeros((1, 21))
        H[0, 2] = 1.0
        return np.array([self.h_m[j] - pos_n_m[2]]), H, np.array([self.sd_m**2])


def test_any_object_obeying_the_protocol_is_applied():
    res0, pos_t, *_ = circle_run(2, n=400)
    t = res0.t_s
    idx = np.arange(10, t.size, 10)
    assert isinstance(_HeightFix(t[idx], pos_t[idx, 2], 0.05), ins.Measurement)
    # a height-only fix equals a PositionFix whose horizontal components are unused (NaN sd)
    fix = ins.PositionFix(t[idx], np.column_stack([np.zeros((idx.size, 2)), pos_t[idx, 2]]),
                          np.tile([np.nan, np.nan, 0.05], (idx.size, 1)))
    args = (t, np.tile([0.0, 0.0, 0.3], (t.size, 1)), np.tile([0.0, 0.36, 9.80665], (t.size, 1)), np.zeros(3),
            np.array([1.2, 0, 0]), np.eye(3), ins.initial_covariance(**P0_SD))
    a = ins.run_eskf(*args, [_HeightFix(t[idx], pos_t[idx, 2], 0.05)], CFG)
    b = ins.run_eskf(*args, [fix], CFG)
    assert np.array_equal(a.pos_n_m, b.pos_n_m) and np.array_equal(a.P_plus, b.P_plus)
    assert (a.n_meas[idx] == 1).all() and np.sqrt(a.P_plus[-1, 2, 2]) < 0.05


def _tiny_log(n=50):
    t = np.arange(n) * 0.01
    return t, np.zeros((n, 3)), np.tile([0.0, 0.0, 9.80665], (n, 1))


@pytest.mark.parametrize("bad, msg", [
    (lambda P: P.__setitem__((4, 4), -1.0), "negative"),
    (lambda P: P.__setitem__((2, 2), np.nan), "finite"),
    (lambda P: P.__setitem__((0, 1), 0.5), "symmetric"),
    (lambda P: P.__setitem__((3, 3), 1e20), "exceeds"),
])
def test_run_eskf_refuses_bad_initial_covariance(bad, msg):
    from ilocalg import ins
    t, g, f = _tiny_log()
    P0 = ins.initial_covariance()
    bad(P0)
    with pytest.raises(ValueError, match=f"P0.*{msg}"):
        ins.run_eskf(t, g, f, np.zeros(3), np.zeros(3), np.eye(3), P0)


def test_run_eskf_refuses_indefinite_covariance_and_tiny_measurement_noise():
    from ilocalg import ins
    t, g, f = _tiny_log()
    P0 = ins.initial_covariance()
    P0[0, 1] = P0[1, 0] = 10.0  # symmetric but indefinite
    with pytest.raises(ValueError, match="P0: not positive semi-definite"):
        ins.run_eskf(t, g, f, np.zeros(3), np.zeros(3), np.eye(3), P0)
    fix = ins.PositionFix(t[[10]], np.zeros((1, 3)), np.full((1, 3), 1e-150), name="GCP")
    with pytest.raises(ValueError, match="GCP: noise variance"):
        ins.run_eskf(t, g, f, np.zeros(3), np.zeros(3), np.eye(3), ins.initial_covariance(), [fix])


def test_filter_without_history_gives_the_same_solution():
    from ilocalg import ins
    from ilocalg.ins import eskf as E
    rng = np.random.default_rng(0)
    n = 3000
    t = np.arange(n) * 0.01
    g = rng.normal(0, 0.01, (n, 3))
    f = np.tile([0.0, 0.0, 9.80665], (n, 1)) + rng.normal(0, 0.05, (n, 3))
    i1 = np.arange(100, n, 700)
    ups = [ins.PositionFix(t[i1], rng.normal(0, 0.3, (i1.size, 3)), np.full((i1.size, 3), 0.3))]
    a = ins.run_eskf(t, g, f, np.zeros(3), np.zeros(3), np.eye(3), ins.initial_covariance(), ups)
    b = ins.run_eskf(t, g, f, np.zeros(3), np.zeros(3), np.eye(3), ins.initial_covariance(), ups,
                     keep_covariance=False)
    assert b.P_plus is None and np.array_equal(a.pos_n_m, b.pos_n_m) and np.array_equal(a.dx, b.dx)
    # checkpoints at every update and at least every CHECKPOINT_EPOCHS epochs
    assert set(i1.tolist()) <= set(b.cp_idx.tolist()) and np.diff(b.cp_idx).max() <= E.CHECKPOINT_EPOCHS
    for cp, P in zip(b.cp_idx, b.cp_P, strict=True):
        assert np.array_equal(P, a.P_plus[cp])


def test_small_solve_has_the_bits_of_numpy_solve_and_its_error():
    from ilocalg.ins._linalg import solve

    rng = np.random.default_rng(3)
    for m in (1, 3, 6, 9, 21):
        A = rng.normal(size=(m, m))
        S = A @ A.T + 1e-3 * np.eye(m)
        for b in (rng.normal(size=m), rng.normal(size=(m, 21)), rng.normal(size=(m, 1))):
            assert np.array_equal(solve(S, b), np.linalg.solve(S, b))
    with pytest.raises(np.linalg.LinAlgError), pytest.warns(RuntimeWarning):
        solve(np.array([[1.0, 2.0], [2.0, 4.0]]), np.ones(2))
    assert solve(np.eye(2, dtype=np.float32), np.ones(2)).dtype == np.float64  # other dtypes: numpy's own path


def test_eskf_predict_into_buffers_gives_the_same_bits():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(21, 21))
    P, Phi, q = A @ A.T, np.eye(21) + 0.01 * rng.normal(size=(21, 21)), rng.uniform(0, 1e-3, 21)
    out, work = np.empty((21, 21)), np.empty((21, 21))
    got = ins.eskf_predict(P, Phi, q, out=out, work=work)
    assert got is out
    assert np.array_equal(got, ins.eskf_predict(P, Phi, q))
    assert np.array_equal(got, Phi @ P @ Phi.T + np.diag(q))


def _fields_equal(a, b):
    keys = ("pos_n_m", "vel_n_mps", "mat_nb", "sensor", "dx", "nis", "n_meas", "P_plus", "P_minus", "Phi", "cp_idx",
            "cp_P")
    return all((getattr(a, k) is None and getattr(b, k) is None)
               or np.array_equal(getattr(a, k), getattr(b, k), equal_nan=True) for k in keys)


@pytest.mark.parametrize("keep", [True, False])
def test_prefix_reuses_the_shared_beginning_with_the_same_bits(keep):
    rng = np.random.default_rng(5)
    n = 2500
    t = np.cumsum(rng.uniform(0.015, 0.025, n))
    g = rng.normal(0, 0.01, (n, 3))
    f = np.tile([0.0, 0.0, 9.80665], (n, 1)) + rng.normal(0, 0.05, (n, 3))
    i1, i2 = np.arange(10, n, 40), np.arange(1300, n, 300)
    fix = ins.PositionFix(t[i1], rng.normal(0, 0.3, (i1.size, 3)), np.full((i1.size, 3), 0.3))
    vel = ins.NavVelocity(t[i1[::3]], np.zeros((i1[::3].size, 3)), np.full((i1[::3].size, 3), 0.05))
    gcp = ins.PositionFix(t[i2], rng.normal(0, 0.1, (i2.size, 3)), np.full((i2.size, 3), 0.1))
    args = (t, g, f, np.zeros(3), np.zeros(3), np.eye(3), ins.initial_covariance())
    a = ins.run_eskf(*args, [fix, vel], CFG, keep_covariance=keep)
    b = ins.run_eskf(*args, [fix, vel, gcp], CFG, keep_covariance=keep)
    # the run with more fixes, from the run without them (shared up to the update before the first extra fix):
    # equal to its own run from scratch
    assert ins.eskf._resume_point(a, b.inputs) == i1[i1 < i2[0]][-1]
    assert _fields_equal(ins.run_eskf(*args, [fix, vel, gcp], CFG, keep_covariance=keep, prefix=a), b)
    assert ins.same_run(b, ins.run_eskf(*args, [fix, vel, gcp], CFG, keep_covariance=keep, prefix=b))
    assert not ins.same_run(a, b)
    # a fix moved by one ulp after the first extra fix, a changed sensor sample, another history mode: the same
    # bits as a run from scratch
    z2 = gcp.z.copy()
    z2[2, 0] = np.nextafter(z2[2, 0], np.inf)
    gcp2 = ins.PositionFix(gcp.t_s, z2, gcp.sd)
    c = ins.run_eskf(*args, [fix, vel, gcp2], CFG, keep_covariance=keep, prefix=[a, b])
    assert _fields_equal(c, ins.run_eskf(*args, [fix, vel, gcp2], CFG, keep_covariance=keep))
    assert not np.array_equal(c.pos_n_m, b.pos_n_m)
    f2 = f.copy()
    f2[500, 1] += 1e-3
    args2 = (t, g, f2, *args[3:])
    assert _fields_equal(ins.run_eskf(*args2, [fix, vel, gcp], CFG, keep_covariance=keep, prefix=b),
                         ins.run_eskf(*args2, [fix, vel, gcp], CFG, keep_covariance=keep))
    other = ins.run_eskf(*args, [fix, vel, gcp], CFG, keep_covariance=not keep, prefix=b)
    assert np.array_equal(other.pos_n_m, b.pos_n_m) and (other.P_plus is None) == keep


def _batch_case(seed, n, with_body=False, with_height=False):
    """One filter run's keyword arguments: its own irregular clock, sensors and measurement sets."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.015, 0.025, n))
    g = rng.normal(0, 0.01, (n, 3))
    f = np.tile([0.0, 0.0, 9.80665], (n, 1)) + rng.normal(0, 0.05, (n, 3))
    i1 = np.sort(rng.choice(np.arange(1, n), n // 12, replace=False))  # stretches of every length
    ups = [ins.PositionFix(t[i1], rng.normal(0, 0.3, (i1.size, 3)), np.full((i1.size, 3), 0.3)),
           ins.NavVelocity(t[i1[::4]], np.zeros((i1[::4].size, 3)), np.full((i1[::4].size, 3), 0.05))]
    if with_body:
        i3 = np.arange(5, n, 7)
        ups.append(ins.BodyVelocity(t[i3], np.zeros((i3.size, 3)), np.tile([np.nan, 0.1, 0.1], (i3.size, 1))))
    if with_height:  # a set of another class: updated through its rows(), not the rows laid out ahead
        i4 = np.arange(30, n, 90)
        ups.append(_HeightFix(t[i4], rng.normal(0, 0.1, i4.size), 0.1))
    return {"t_s": t, "gyr_b_radps": g, "acc_b_mps2": f, "pos0_n_m": np.zeros(3), "vel0_n_mps": rng.normal(0, 0.1, 3),
            "mat0_nb": ins.rotvec_to_dcm(rng.normal(0, 0.05, 3)), "P0": ins.initial_covariance(), "updates": ups,
            "config": CFG}


@pytest.mark.parametrize("batch_epochs", [None, 40])
def test_batch_gives_the_bits_of_each_run_alone(monkeypatch, batch_epochs):
    from ilocalg.ins import eskf as E

    if batch_epochs:  # small groups: the stretches of one step split over several stacked predictions
        monkeypatch.setattr(E, "BATCH_EPOCHS", batch_epochs)
    runs = [_batch_case(0, 700), _batch_case(1, 450, with_body=True), _batch_case(2, 900, with_height=True),
            _batch_case(3, 300, with_body=True, with_height=True), _batch_case(4, 700)]
    runs[4]["updates"] = runs[4]["updates"][:1]  # another schedule on the same kind of log
    alone = [ins.run_eskf(**r) for r in runs]
    got = E.run_eskf_batch(runs)
    assert len(got) == len(runs) and all(_fields_equal(a, b) for a, b in zip(alone, got, strict=True))
    assert all(ins.same_run(a, b) for a, b in zip(alone, got, strict=True))
    # no covariance kept: the same navigation solution, estimates and NIS, no covariance of any kind
    nav = E.run_eskf_batch(runs, keep_covariance=False)
    for a, b in zip(alone, nav, strict=True):
        assert b.P_plus is None and b.cp_P is None
        for k in ("pos_n_m", "vel_n_mps", "mat_nb", "sensor", "dx", "nis", "n_meas"):
            assert np.array_equal(getattr(a, k), getattr(b, k), equal_nan=True), k
    # a run resumed from an earlier result (prefix) inside a batch: the same bits as from scratch
    more = dict(runs[0], updates=[*runs[0]["updates"], ins.PositionFix(runs[0]["t_s"][[400]], np.zeros((1, 3)),
                                                                         np.full((1, 3), 0.1))])
    ref = ins.run_eskf(**more)
    for min_runs in (1, E.BATCH_MIN_RUNS):  # two runs stacked, and two run one by one (too few to stack)
        monkeypatch.setattr(E, "BATCH_MIN_RUNS", min_runs)
        got2 = E.run_eskf_batch([dict(more, prefix=alone[0]), runs[1]])
        assert _fields_equal(got2[0], ref) and _fields_equal(got2[1], alone[1])
        one = E.run_eskf_batch([runs[2]], keep_covariance=False)[0]
        assert one.P_plus is None and one.cp_P is None and np.array_equal(one.pos_n_m, alone[2].pos_n_m)
    assert E.run_eskf_batch([]) == []


def test_batch_checks_every_run():
    from ilocalg.ins import eskf as E

    good = _batch_case(0, 200)
    with pytest.raises(ValueError, match="run 1 has unknown arguments"):
        E.run_eskf_batch([good, dict(good, keep_covariance=False)])
    bad = ins.initial_covariance()
    bad[4, 4] = -1.0
    with pytest.raises(ValueError, match="P0.*negative"):
        E.run_eskf_batch([good, dict(good, P0=bad)])


def test_stacked_joseph_update_and_solve_have_the_bits_of_one_at_a_time():
    from ilocalg.ins._linalg import solve

    rng = np.random.default_rng(7)
    for m in (1, 2, 3, 5, 9):
        B = 6
        A = rng.normal(size=(B, 21, 21))
        P = A @ A.swapaxes(1, 2) + 0.1 * np.eye(21)
        H = rng.normal(size=(B, m, 21))
        e = rng.normal(size=(B, m))
        R = rng.uniform(0.01, 1.0, (B, m))
        dx, Pn, nis = ins.joseph_update_stacked(P, e, H, R)
        for i in range(B):
            d1, P1, n1 = ins.joseph_update(P[i], e[i], H[i], R[i])
            assert np.array_equal(dx[i], d1) and np.array_equal(Pn[i], P1) and nis[i] == n1
        S = H @ H.swapaxes(1, 2) + np.eye(m)
        for b in (e, rng.normal(size=(B, m, 4))):
            got = solve(S, b)
            assert all(np.array_equal(got[i], solve(S[i], b[i])) for i in range(B))
    S = np.stack([np.eye(2), np.array([[1.0, 2.0], [2.0, 4.0]])])
    with pytest.raises(np.linalg.LinAlgError), pytest.warns(RuntimeWarning):
        solve(S, np.ones((2, 2)))
