"""Tests of ilocalg.fusion.step_kf: the i-Loc step filter (pure functions, batched path, filterpy class)."""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from ilocalg import fusion as fu
from ilocalg.fusion import step_kf


def _walk(seed, n=120, **kw):
    return fu.straight_walk(n, rng=seed, **kw)


def _random_spd(rng, scale=4.0):
    A = rng.normal(size=(2, 2))
    return scale * (A @ A.T + 0.3 * np.eye(2))


# ------------------------------------------------------------------------------ model pieces

def test_process_noise_is_eq22_rank_one_along_heading():
    th = np.array([0.0, 0.4, 2.0, -1.2])
    Q = fu.step_process_noise(th, 0.3)
    c, s = np.cos(th), np.sin(th)
    expect = 0.09 * np.stack([np.stack([c * c, s * c], -1), np.stack([s * c, s * s], -1)], -2)
    np.testing.assert_allclose(Q, expect, atol=1e-15)
    assert np.allclose(np.linalg.det(Q), 0.0) and np.allclose(np.trace(Q, axis1=-2, axis2=-1), 0.09)
    # the optional heading term adds (D sigma_theta)^2 across the step only
    Q2 = fu.step_process_noise(th, 0.3, step_m=0.7, sigma_theta_rad=0.1)
    nv = np.stack([-s, c], -1)
    np.testing.assert_allclose(np.einsum("ki,kij,kj->k", nv, Q2 - Q, nv), (0.07) ** 2)
    np.testing.assert_allclose(np.einsum("ki,kij,kj->k", np.stack([c, s], -1), Q2 - Q, np.stack([c, s], -1)), 0,
                               atol=1e-15)


def test_predict_moves_along_heading():
    x, P = fu.kf_predict_step([1.0, 2.0], np.eye(2), np.pi / 2, 0.7, 0.2)
    np.testing.assert_allclose(x, [1.0, 2.7], atol=1e-15)
    np.testing.assert_allclose(P, np.diag([1.0, 1.04]), atol=1e-15)


def test_update_joseph_equals_textbook_form_and_filterpy():
    rng = np.random.default_rng(3)
    for _ in range(20):
        x, z = rng.normal(size=2) * 5, rng.normal(size=2) * 5
        P, R = _random_spd(rng), _random_spd(rng, 2.0)
        xu, Pu = fu.kf_update(x, P, z, R)
        K = P @ np.linalg.inv(P + R)
        np.testing.assert_allclose(xu, x + K @ (z - x), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(Pu, (np.eye(2) - K) @ P, rtol=1e-10, atol=1e-12)
        kf = KalmanFilter(dim_x=2, dim_z=2)
        kf.x, kf.P, kf.H = x.reshape(2, 1), P.copy(), np.eye(2)
        kf.update(z.reshape(2, 1), R=R)
        np.testing.assert_allclose(xu, kf.x[:, 0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(Pu, kf.P, rtol=1e-12, atol=1e-12)


def test_update_rejects_nan_fix():
    with pytest.raises(ValueError, match="z must be finite"):
        fu.kf_update([0, 0], np.eye(2), [np.nan, 1.0], np.eye(2))


def test_paper_table4_lookup():
    L = np.array([0.4, 0.6, 0.65, 0.8])
    s = fu.sigma_sl_paper_m(L, reading="m2")
    np.testing.assert_allclose(s**2, [0.054, 0.036, 0.0445, 0.065])
    np.testing.assert_allclose(fu.sigma_sl_paper_m([0.2, 1.1], reading="m2") ** 2, [0.054, 0.065])
    # the default reads Table 4 as relative variances (thesis L478): sigma proportional to the step
    np.testing.assert_allclose(fu.sigma_sl_paper_m(L), s * L)
    # sqrt(0.054) sqrt(2 / pi) = 18.5 % mean absolute relative error (L478: 18.43 %)
    assert fu.sigma_sl_paper_m(0.5) / 0.5 * np.sqrt(2 / np.pi) == pytest.approx(0.1854, abs=1e-3)
    with pytest.raises(ValueError, match="reading"):
        fu.sigma_sl_paper_m(0.5, reading="cm2")
    with pytest.raises(ValueError, match=r"step_m\[1\] = 1.1 m is outside the paper's Table 4"):
        fu.sigma_sl_paper_m([0.5, 1.1], outside="error")
    assert len(fu.PAPER_TABLE5_SIGMA_RF_VAR_M2) == 28
    assert fu.nis_gate(0.99) == pytest.approx(9.21034, rel=1e-5)


# ------------------------------------------------------------------------------ class vs pure vs batch

@pytest.mark.parametrize("seed", [0, 1, 2])
def test_filterpy_class_matches_pure_functions_step_by_step(seed):
    w = _walk(seed, n=60, fix_every=2)
    rng = np.random.default_rng(seed)
    sig = fu.sigma_sl_paper_m(w.step_m)
    r = rng.uniform(0.5, 15.0, size=len(w.z_m))
    cls = fu.StepKalmanFilter(w.z_m[0], 9.0 * np.eye(2))
    x, P = w.z_m[0].copy(), 9.0 * np.eye(2)
    for k in range(1, len(w.z_m)):
        cls.predict_step(w.theta_rad[k - 1], w.step_m[k - 1], sig[k - 1])
        x, P = fu.kf_predict_step(x, P, w.theta_rad[k - 1], w.step_m[k - 1], sig[k - 1])
        np.testing.assert_allclose(cls.x, x, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(cls.P, P, rtol=1e-12, atol=1e-12)
        if not np.isnan(w.z_m[k]).any():
            assert cls.update(w.z_m[k], r[k] * np.eye(2))
            x, P = fu.kf_update(x, P, w.z_m[k], r[k] * np.eye(2))
        else:
            assert not cls.update(w.z_m[k], r[k])
        np.testing.assert_allclose(cls.x, x, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(cls.P, P, rtol=1e-12, atol=1e-12)


def test_batched_path_matches_filterpy_loop_for_many_walks():
    walks = [_walk(s, n=150, fix_every=1 + s % 4, outlier_fraction=0.1) for s in range(12)]
    th = np.stack([w.theta_rad for w in walks])
    st = np.stack([w.step_m for w in walks])
    z = np.stack([w.z_m for w in walks])
    rng = np.random.default_rng(0)
    R = np.stack([[_random_spd(rng, 3.0) for _ in range(151)] for _ in walks])
    x0 = np.stack([w.truth_xy_m[0] for w in walks]) + 1.0
    sig = fu.sigma_sl_paper_m(st)
    gate = fu.nis_gate(0.999)
    batch = fu.filter_walks(x0, 4.0 * np.eye(2), th, st, sig, z, R_m2=R, gate_nis=gate, sigma_theta_rad=0.05)
    assert batch.x.shape == (12, 151, 2) and batch.P.shape == (12, 151, 2, 2)
    for i in range(len(walks)):
        ref = fu.StepKalmanFilter(x0[i], 4.0 * np.eye(2), gate_nis=gate).run(
            th[i], st[i], sig[i], z[i], R_m2=R[i], sigma_theta_rad=0.05)
        for name in ("x_prior", "P_prior", "x", "P"):
            np.testing.assert_allclose(getattr(batch, name)[i], getattr(ref, name), rtol=1e-10, atol=1e-10)
        np.testing.assert_array_equal(batch.accepted[i], ref.accepted)
        np.testing.assert_allclose(batch.nis[i], ref.nis, rtol=1e-10)
    single = fu.filter_walk(x0[3], 4.0 * np.eye(2), th[3], st[3], sig[3], z[3], R_m2=R[3], gate_nis=gate,
                            sigma_theta_rad=0.05)
    np.testing.assert_allclose(single.x, batch.x[3], rtol=1e-13, atol=1e-13)


# ------------------------------------------------------------------------------ invariants

def test_covariance_stays_symmetric_positive_definite_over_long_walks():
    w = _walk(5, n=20000, fix_every=7, sigma_rf_m=4.0, turn_every=50)
    r = fu.filter_walk(w.z_m[0], 16 * np.eye(2), w.theta_rad, w.step_m, fu.sigma_sl_paper_m(w.step_m), w.z_m,
                       r_var_m2=16.0)
    for P in (r.P, r.P_prior):
        asym = np.abs(P - np.swapaxes(P, -1, -2)).max(axis=(-1, -2)) / np.abs(P).max(axis=(-1, -2))
        assert asym.max() < 1e-12
        ev = np.linalg.eigvalsh(0.5 * (P + np.swapaxes(P, -1, -2)))
        assert (ev > 0).all()
    # without fixes the covariance only grows (rank-one Q accumulates along the walked directions)
    r2 = fu.filter_walk([0, 0], np.eye(2), w.theta_rad[:500], w.step_m[:500], 0.2, np.full((501, 2), np.nan),
                        r_var_m2=np.nan)
    tr = np.trace(r2.P, axis1=-2, axis2=-1)
    assert (np.diff(tr) > 0).all()
    np.testing.assert_allclose(tr[-1], 2.0 + 500 * 0.04)


def test_missing_fixes_are_explicit():
    w = _walk(1, n=30, fix_every=1)
    z = w.z_m.copy()
    z[5] = np.nan
    r = fu.filter_walk(z[0], 9 * np.eye(2), w.theta_rad, w.step_m, 0.2, z, r_var_m2=np.where(np.isnan(z[:, 0]),
                                                                                            np.nan, 9.0))
    assert not r.has_fix[5] and r.has_fix[4] and np.isnan(r.nis[5])
    np.testing.assert_array_equal(r.x[5], r.x_prior[5])  # no fix -> no update
    assert not np.array_equal(r.x[4], r.x_prior[4])
    z[7, 1] = np.nan
    with pytest.raises(ValueError, match="z_m row 7 has one NaN coordinate"):
        fu.filter_walk(z[0], 9 * np.eye(2), w.theta_rad, w.step_m, 0.2, z, r_var_m2=9.0)
    with pytest.raises(ValueError, match="one NaN coordinate"):
        fu.StepKalmanFilter([0, 0], np.eye(2)).update([1.0, np.nan], 1.0)


def test_bad_inputs_raise():
    w = _walk(1, n=10)
    args = (w.z_m[0], np.eye(2), w.theta_rad, w.step_m, 0.2)
    with pytest.raises(ValueError, match="z_m .*n\\+1 fixes"):
        fu.filter_walk(*args, w.z_m[:-1], r_var_m2=9.0)
    with pytest.raises(ValueError, match="exactly one of r_var_m2"):
        fu.filter_walk(*args, w.z_m)
    with pytest.raises(ValueError, match="R of the fix at state 3 must be symmetric positive definite"):
        rv = np.full(11, 9.0)
        rv[3] = -1.0
        fu.filter_walk(*args, np.nan_to_num(w.z_m), r_var_m2=rv)
    with pytest.raises(ValueError, match="R of a given fix is not finite"):
        fu.filter_walk(*args, np.nan_to_num(w.z_m), r_var_m2=np.nan)
    with pytest.raises(ValueError, match="P0_m2 must be symmetric positive definite"):
        fu.filter_walk(w.z_m[0], -np.eye(2), w.theta_rad, w.step_m, 0.2, w.z_m, r_var_m2=9.0)
    th = w.theta_rad.copy()
    th[4] = np.nan
    with pytest.raises(ValueError, match=r"theta_rad is not finite at index \(0, 4\)"):
        fu.filter_walk(w.z_m[0], np.eye(2), th, w.step_m, 0.2, w.z_m, r_var_m2=9.0)
    with pytest.raises(ValueError, match="step_m must be >= 0"):
        fu.filter_walk(w.z_m[0], np.eye(2), w.theta_rad, -w.step_m, 0.2, w.z_m, r_var_m2=9.0)


# ------------------------------------------------------------------------------ gating and accuracy

def test_gating_rejects_outliers_and_counts_them():
    gate = fu.nis_gate(0.999)
    n_out = n_rej = n_rej_inlier = 0
    err_gated, err_plain = [], []
    for seed in range(10):
        w = _walk(seed, n=300, fix_every=2, sigma_rf_m=2.0, outlier_fraction=0.15, outlier_m=40.0)
        common = (w.z_m[0] if not w.is_outlier[0] else w.truth_xy_m[0], 4 * np.eye(2), w.theta_rad, w.step_m,
                  0.2, w.z_m)
        g = fu.filter_walk(*common, r_var_m2=4.0, gate_nis=gate)
        p = fu.filter_walk(*common, r_var_m2=4.0)
        assert p.n_rejected == 0 and g.n_rejected == g.rejected.sum()
        n_out += w.is_outlier.sum()
        n_rej += (g.rejected & w.is_outlier).sum()
        n_rej_inlier += (g.rejected & ~w.is_outlier).sum()
        err_gated.append(np.linalg.norm(g.x - w.truth_xy_m, axis=1).mean())
        err_plain.append(np.linalg.norm(p.x - w.truth_xy_m, axis=1).mean())
    assert n_rej >= 0.95 * n_out
    assert n_rej_inlier <= 0.01 * (10 * 151)
    assert np.mean(err_gated) < 0.5 * np.mean(err_plain)
    # the class counts the same rejections
    w = _walk(0, n=300, fix_every=2, sigma_rf_m=2.0, outlier_fraction=0.15)
    cls = fu.StepKalmanFilter(w.truth_xy_m[0], 4 * np.eye(2), gate_nis=gate)
    res = cls.run(w.theta_rad, w.step_m, 0.2, w.z_m, r_var_m2=4.0)
    assert cls.n_rejected == res.n_rejected > 0


def test_kf_beats_dead_reckoning_and_wifi_on_seeded_walks():
    e_kf, e_pdr, e_wifi = [], [], []
    for seed in range(10):
        w = _walk(seed, n=200, fix_every=3, sigma_rf_m=3.0, sigma_heading_rad=0.05, heading_bias_rad=0.1)
        r = fu.filter_walk(w.z_m[0], 9 * np.eye(2), w.theta_rad, w.step_m, 0.2, w.z_m, r_var_m2=9.0,
                           sigma_theta_rad=0.1)
        pdr = w.z_m[0] + np.vstack([[0, 0], np.cumsum(fu.step_control(w.theta_rad) * w.step_m[:, None], 0)])
        has = ~np.isnan(w.z_m[:, 0])
        e_kf.append(np.linalg.norm(r.x - w.truth_xy_m, axis=1)[has].mean())
        e_pdr.append(np.linalg.norm(pdr - w.truth_xy_m, axis=1)[has].mean())
        e_wifi.append(np.linalg.norm(w.z_m - w.truth_xy_m, axis=1)[has].mean())
    assert np.mean(e_kf) < 0.8 * np.mean(e_wifi)
    assert np.mean(e_kf) < 0.5 * np.mean(e_pdr)


def test_module_has_paper_constants_labelled():
    src = open(step_kf.__file__, encoding="utf-8").read()
    block = src[src.index("# Settings from the paper"):].split("\n\n")[0]
    for name in ("PAPER_TABLE4_STEP_M", "PAPER_TABLE4_SIGMA_SL_VAR_M2", "PAPER_TABLE5_SIGMA_RF_VAR_M2"):
        assert name in block                                  # each paper constant is in the labelled block
    assert step_kf.PAPER_TABLE4_SIGMA_SL_VAR_M2[0] == 0.054 and step_kf.PAPER_TABLE5_SIGMA_RF_VAR_M2[0] == 15.072
