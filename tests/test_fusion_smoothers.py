"""Tests of ilocalg.fusion.smoothers: RTS and fixed-lag smoothing of the step filter."""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter, rts_smoother

from ilocalg import fusion as fu


def _filter(w, r_var=9.0, **kw):
    return fu.filter_walk(w.z_m[0], 9.0 * np.eye(2), w.theta_rad, w.step_m, 0.2, w.z_m, r_var_m2=r_var, **kw)


def test_rts_matches_filterpy_rts_smoother():
    """filterpy's rts_smoother has no control input: smooth y_k = x_k - c_k (c_k the summed steps) instead."""
    w = fu.straight_walk(80, rng=4, fix_every=2, turn_every=20)
    sig = fu.sigma_sl_paper_m(w.step_m)
    res = fu.filter_walk(w.z_m[0], 9.0 * np.eye(2), w.theta_rad, w.step_m, sig, w.z_m, r_var_m2=9.0)
    ours = fu.rts_smooth(res)
    n = len(w.step_m)
    c = np.vstack([[0, 0], np.cumsum(fu.step_control(w.theta_rad) * w.step_m[:, None], axis=0)])
    Qs = np.concatenate([np.zeros((1, 2, 2)), fu.step_process_noise(w.theta_rad, sig)])
    kf = KalmanFilter(dim_x=2, dim_z=2)
    kf.x, kf.P, kf.F, kf.H = w.z_m[0].reshape(2, 1).copy(), 9.0 * np.eye(2), np.eye(2), np.eye(2)
    xs, Ps = [], []
    for k in range(n + 1):
        if k > 0:
            kf.predict(Q=Qs[k])
        if not np.isnan(w.z_m[k, 0]):
            kf.update((w.z_m[k] - c[k]).reshape(2, 1), R=9.0 * np.eye(2))
        xs.append(kf.x.copy())
        Ps.append(kf.P.copy())
    # filterpy's rts_smoother uses Qs[k] for the step k -> k+1
    xr, Pr, _, _ = rts_smoother(np.array(xs), np.array(Ps), np.repeat(np.eye(2)[None], n + 1, 0),
                                np.concatenate([Qs[1:], np.zeros((1, 2, 2))]))
    np.testing.assert_allclose(res.x, np.array(xs)[:, :, 0] + c, atol=1e-9)
    np.testing.assert_allclose(ours.x, xr[:, :, 0] + c, atol=1e-9)
    np.testing.assert_allclose(ours.P, Pr, atol=1e-9)


def test_rts_not_worse_than_filter_on_seeded_straight_walks():
    e_f, e_s = [], []
    for seed in range(25):
        w = fu.straight_walk(200, rng=seed, fix_every=3, sigma_rf_m=3.0, sigma_heading_rad=0.0)
        res = _filter(w)
        sm = fu.rts_smooth(res)
        e_f.append(np.linalg.norm(res.x - w.truth_xy_m, axis=1).mean())
        e_s.append(np.linalg.norm(sm.x - w.truth_xy_m, axis=1).mean())
    e_f, e_s = np.array(e_f), np.array(e_s)
    assert e_s.mean() < 0.8 * e_f.mean()
    assert (e_s <= e_f).mean() >= 0.9
    # smoothed covariance never exceeds the filtered one (in the Loewner order)
    ev = np.linalg.eigvalsh(res.P - sm.P)
    assert (ev > -1e-10).all()
    np.testing.assert_array_equal(sm.x[-1], res.x[-1])


def test_rts_batched_equals_per_walk():
    walks = [fu.straight_walk(60, rng=s, fix_every=2) for s in range(5)]
    res = fu.filter_walks(np.stack([w.z_m[0] for w in walks]), 9 * np.eye(2), np.stack([w.theta_rad for w in walks]),
                          np.stack([w.step_m for w in walks]), 0.2, np.stack([w.z_m for w in walks]), r_var_m2=9.0)
    sm = fu.rts_smooth(res)
    for i, w in enumerate(walks):
        np.testing.assert_allclose(sm.x[i], fu.rts_smooth(_filter(w)).x, atol=1e-12)


def test_fixed_lag_limits_and_causality():
    w = fu.straight_walk(100, rng=7, fix_every=2)
    res = _filter(w)
    f0 = fu.fixed_lag_smooth(res, 0)
    np.testing.assert_array_equal(f0.x, res.x)
    rts = fu.rts_smooth(res)
    for lag in (100, 500):
        fl = fu.fixed_lag_smooth(res, lag)
        np.testing.assert_allclose(fl.x, rts.x, atol=1e-12)
        np.testing.assert_allclose(fl.P, rts.P, atol=1e-12)
    # lag L: state j uses fixes up to j + L only (changing later fixes does not change it)
    L, j = 6, 40
    z2 = w.z_m.copy()
    z2[j + L + 1:] += 25.0
    res2 = fu.filter_walk(z2[0], 9.0 * np.eye(2), w.theta_rad, w.step_m, 0.2, z2, r_var_m2=9.0)
    a, b = fu.fixed_lag_smooth(res, L).x, fu.fixed_lag_smooth(res2, L).x
    np.testing.assert_allclose(a[: j + 1], b[: j + 1], atol=1e-12)
    assert not np.allclose(a[j + 1:], b[j + 1:])
    # equals RTS over the truncated walk
    trunc = fu.filter_walk(w.z_m[0], 9.0 * np.eye(2), w.theta_rad[: j + L], w.step_m[: j + L], 0.2,
                           w.z_m[: j + L + 1], r_var_m2=9.0)
    np.testing.assert_allclose(a[j], fu.rts_smooth(trunc).x[j], atol=1e-12)
    with pytest.raises(ValueError, match="lag must be an integer >= 0"):
        fu.fixed_lag_smooth(res, -1)


def test_fixed_lag_error_between_filter_and_rts():
    e = {"kf": [], "lag5": [], "rts": []}
    for seed in range(15):
        w = fu.straight_walk(200, rng=seed, fix_every=3, sigma_rf_m=3.0, sigma_heading_rad=0.0)
        res = _filter(w)
        for name, x in (("kf", res.x), ("lag5", fu.fixed_lag_smooth(res, 5).x), ("rts", fu.rts_smooth(res).x)):
            e[name].append(np.linalg.norm(x - w.truth_xy_m, axis=1).mean())
    m = {k: np.mean(v) for k, v in e.items()}
    assert m["rts"] <= m["lag5"] < m["kf"]


def test_fixed_lag_batched_equals_per_walk():
    walks = [fu.straight_walk(40, rng=s, fix_every=3) for s in range(4)]
    res = fu.filter_walks(np.stack([w.z_m[0] for w in walks]), 9 * np.eye(2), np.stack([w.theta_rad for w in walks]),
                          np.stack([w.step_m for w in walks]), 0.2, np.stack([w.z_m for w in walks]), r_var_m2=9.0)
    fl = fu.fixed_lag_smooth(res, 4)
    for i, w in enumerate(walks):
        one = fu.fixed_lag_smooth(_filter(w), 4)
        np.testing.assert_allclose(fl.x[i], one.x, atol=1e-12)
        np.testing.assert_allclose(fl.P[i], one.P, atol=1e-12)
