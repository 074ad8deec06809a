"""Per-fix Wi-Fi variance (ilocalg.track.fixes.FixVarModel) and the map at start-up (walkable posterior)."""

import dataclasses

import numpy as np
import pytest

from ilocalg.fusion.particle_filter import OccupancyGrid
from ilocalg.track import RealWalkConfig
from ilocalg.track.estimators import (
    TrackProblem,
    kf_gain_map_track,
    kf_gain_track,
    lsq_causal_map_track,
    lsq_track,
    map_first_fix,
    walkable_posterior,
)
from ilocalg.track.fixes import fix_error_correlation, log_variance_fit
from ilocalg.track.motion import GainStats
from ilocalg.track.online_kf import gain_kf, gain_kf_lag


def test_log_variance_fit_recovers_a_known_heteroscedastic_variance():
    """Errors whose per-axis variance is exp(0.5 + 0.8 f): the slope, and the mean variance per group (the
    smearing factor removes the log's bias; the 2-D squared error is far from log-normal)."""
    rng = np.random.default_rng(0)
    n = 20000
    f = rng.uniform(0, 3, n)
    var = np.exp(0.5 + 0.8 * f)
    e = rng.normal(0, 1, (n, 2)) * np.sqrt(var)[:, None]
    m = log_variance_fit((e ** 2).sum(1), f[:, None])
    assert m.beta[1] == pytest.approx(0.8, abs=0.03)
    pred = m.predict(f[:, None])
    for lo, hi in ((0, 1), (1, 2), (2, 3)):
        g = (f >= lo) & (f < hi)
        assert pred[g].mean() == pytest.approx(var[g].mean(), rel=0.05)
    with pytest.raises(ValueError, match="need at least"):
        log_variance_fit(np.ones(5), np.ones((5, 1)))


def test_per_fix_variance_weights_the_least_squares_by_each_fix():
    """A still walker, two fixes: the least-squares position is the inverse-variance weighted mean, and a
    per-fix variance equal for all fixes gives the scalar variance's track."""
    ts = np.arange(5.0)
    p = TrackProblem(ts, np.zeros((4, 2)), 1e-6, np.array([1.0, 3.0]), np.array([[0.0, 0.0], [10.0, 0.0]]),
                     np.array([1.0, 4.0]))
    np.testing.assert_allclose(lsq_track(p, n_iter=1)[2], [2.0, 0.0], atol=1e-3)     # (0/1 + 10/4) / (1 + 1/4)
    same = dataclasses.replace(p, fix_var_m2=np.array([2.0, 2.0]))
    np.testing.assert_allclose(lsq_track(same), lsq_track(dataclasses.replace(p, fix_var_m2=2.0)), atol=1e-12)
    with pytest.raises(ValueError, match="fix_var_m2"):
        dataclasses.replace(p, fix_var_m2=np.array([1.0, 2.0, 3.0]))
    with pytest.raises(ValueError, match="fix_var_m2"):
        dataclasses.replace(p, fix_var_m2=np.array([1.0, 0.0]))


def test_gain_kf_with_per_fix_variance():
    """Equal per-fix variances are the scalar filter; a fix with a huge variance is as if absent."""
    rng = np.random.default_rng(1)
    n = 40
    ts = np.arange(n + 1) * 0.5
    d = np.tile([0.7, 0.0], (n, 1)) + rng.normal(0, 0.1, (n, 2))
    ft = ts[1::5]
    z = np.column_stack([0.7 * np.arange(1, n + 1, 5), np.zeros(ft.size)]) + rng.normal(0, 3, (ft.size, 2))
    a = gain_kf(ts, d, ft, z, 9.0, 0.01, 0.02, 1e-4)
    b = gain_kf(ts, d, ft, z, np.full(ft.size, 9.0), 0.01, 0.02, 1e-4)
    np.testing.assert_allclose(a.x, b.x, atol=1e-12)
    v = np.full(ft.size, 9.0)
    v[3] = 1e12
    keep = np.arange(ft.size) != 3
    c = gain_kf(ts, d, ft, z, v, 0.01, 0.02, 1e-4, huber_c=None)
    e = gain_kf(ts, d, ft[keep], z[keep], v[keep], 0.01, 0.02, 1e-4, huber_c=None)
    np.testing.assert_allclose(c.xy_m, e.xy_m, atol=1e-4)


def _corridor():
    """A 40 x 20 m raster whose only walkable part is the corridor 0 <= y < 2 m."""
    mask = np.zeros((40, 80), dtype=bool)
    mask[:4, :] = True
    return OccupancyGrid(mask, 0.0, 0.0, 0.5)


def test_walkable_posterior_is_the_gaussian_on_open_ground_and_moves_into_a_corridor():
    open_grid = OccupancyGrid(np.ones((400, 400), dtype=bool), -50.0, -50.0, 0.25)
    C = np.array([[4.0, 1.0], [1.0, 2.0]])
    mu, S = walkable_posterior([1.0, 2.0], C, open_grid, n_sd=5.0)
    np.testing.assert_allclose(mu, [1.0, 2.0], atol=0.02)
    np.testing.assert_allclose(S, C, atol=0.05)                     # cell-sampled Gaussian: its own moments
    mu, S = walkable_posterior([20.0, 5.0], np.eye(2) * 9.0, _corridor())
    assert 0.0 <= mu[1] < 2.0 and mu[0] == pytest.approx(20.0, abs=0.1)
    assert S[1, 1] < 2.0 ** 2 / 12 + 0.1 and S[0, 0] == pytest.approx(9.0, rel=0.1)
    # nothing walkable within 3 sd: the nearest walkable cell
    mu, S = walkable_posterior([20.0, 18.0], np.eye(2), _corridor())
    np.testing.assert_allclose(mu, [20.25, 1.75])


def _corridor_walk(seed=0, n=80):
    rng = np.random.default_rng(seed)
    ts = np.arange(n + 1) * 0.5
    truth = np.column_stack([2.0 + 0.4 * np.arange(n + 1), np.full(n + 1, 1.0)])
    d = np.diff(truth, axis=0) + rng.normal(0, 0.05, (n, 2))
    fi = np.arange(2, n + 1, 4)
    z = truth[fi] + rng.normal(0, 3.0, (fi.size, 2))
    gs = GainStats(gain_var=0.01, gain_walk_var=1e-5, step_var_m2=0.0025, n_walks=10)
    return TrackProblem(ts, d, 0.0025, ts[fi], z, np.full(fi.size, 9.0), _corridor(), gain=gs), truth


def test_map_start_is_causal_and_starts_in_the_corridor():
    p, truth = _corridor_walk()
    q = map_first_fix(p)
    assert 0.0 <= q.fix_xy_m[0, 1] < 2.0 and q.fix_var_m2[0] < p.fix_var_m2[0]
    np.testing.assert_array_equal(q.fix_xy_m[1:], p.fix_xy_m[1:])
    for fn in (kf_gain_map_track, lsq_causal_map_track):
        full = fn(p, map_start=True)
        for c in (10, 40):
            keep = p.fix_t_s <= p.state_t_s[c]
            cut = dataclasses.replace(p, state_t_s=p.state_t_s[:c + 1], disp_m=p.disp_m[:c], fix_t_s=p.fix_t_s[keep],
                                      fix_xy_m=p.fix_xy_m[keep], fix_var_m2=p.fix_var_m2[keep])
            np.testing.assert_allclose(fn(cut, map_start=True), full[:c + 1], atol=1e-9)
    # before the second fix the start-up track rests on the first fix: from its walkable posterior it is
    # nearer the truth across the corridor than the plain filter's (then snapped) start
    k = np.searchsorted(p.state_t_s, p.fix_t_s[1])
    plain = kf_gain_track(p)[:k]
    started = kf_gain_map_track(p, map_start=True)[:k]
    assert np.abs(started[:, 1] - truth[:k, 1]).mean() <= np.abs(plain[:, 1] - truth[:k, 1]).mean()


def test_config_rejects_an_unknown_fix_variance_model():
    with pytest.raises(ValueError, match="fix_var"):
        RealWalkConfig(fix_var="robust")


def _ar_walk(seed, c0=0.6, rho=0.9, sd=4.0, n=200, every=4):
    """A winding walk whose fix errors are a Gauss-Markov bias (share c0, correlation rho) plus white noise."""
    rng = np.random.default_rng(seed)
    th = np.cumsum(rng.normal(0, 0.08, n))
    d = 0.7 * np.column_stack([np.cos(th), np.sin(th)])
    truth = np.vstack([[0.0, 0.0], np.cumsum(d, 0)])
    ts = np.arange(n + 1) * 0.5
    fi = np.arange(1, n + 1, every)
    b = np.zeros((fi.size, 2))
    b[0] = rng.normal(0, sd * np.sqrt(c0), 2)
    for i in range(1, fi.size):
        b[i] = rho * b[i - 1] + rng.normal(0, sd * np.sqrt(c0 * (1 - rho ** 2)), 2)
    z = truth[fi] + b + rng.normal(0, sd * np.sqrt(1 - c0), (fi.size, 2))
    gs = GainStats(gain_var=1e-3, gain_walk_var=1e-6, step_var_m2=0.01, n_walks=10)
    p = TrackProblem(ts, d + rng.normal(0, 0.1, d.shape), 0.01, ts[fi], z, sd ** 2, gain=gs)
    return p, truth, z - truth[fi]


def test_fix_error_correlation_recovers_a_gauss_markov_share_and_correlation():
    errs, walks = [], []
    for s in range(40):
        _, _, e = _ar_walk(s)
        errs.append(e), walks.extend([f"w{s}"] * len(e))
    c0, rho, var_b = fix_error_correlation(np.vstack(errs), np.array(walks))
    assert c0 == pytest.approx(0.6, abs=0.08) and rho == pytest.approx(0.9, abs=0.04)
    assert var_b == pytest.approx(0.6 * 16.0, rel=0.2)
    white = np.random.default_rng(0).normal(0, 3, (400, 2))
    assert fix_error_correlation(white, np.repeat(["a", "b"], 200))[0] < 0.15


def test_correlated_fix_errors_as_states_help_when_fix_errors_persist():
    """Fix errors that persist from fix to fix: the filter that carries them beats the one that takes every fix
    as independent. With no correlated share (c0 = 0) the filter and the least squares are the plain ones; with
    an uncorrelated bias (rho = 0) they are the plain ones with the bias's variance added to every fix's."""
    e = {k: [] for k in ("kf", "kf_corr")}
    for s in range(12):
        p, truth, _ = _ar_walk(s)
        q = dataclasses.replace(p, fix_corr=(0.6, 0.9, 0.6 * 16.0))
        e["kf"].append(np.hypot(*(kf_gain_track(p) - truth).T).mean())
        e["kf_corr"].append(np.hypot(*(kf_gain_track(q) - truth).T).mean())
    assert np.mean(e["kf_corr"]) < 0.95 * np.mean(e["kf"]), e
    p, _, _ = _ar_walk(0, n=60)
    none = dataclasses.replace(p, fix_corr=(0.0, 0.5, 0.0))
    np.testing.assert_allclose(kf_gain_track(none), kf_gain_track(p), atol=1e-9)
    np.testing.assert_allclose(lsq_track(none), lsq_track(p), atol=1e-6)
    white_bias = dataclasses.replace(p, fix_corr=(0.5, 0.0, 3.0))            # 0.5 * 16 + 3 = 11 per fix
    plain = dataclasses.replace(p, fix_var_m2=11.0)
    g = p.gain
    kw = dict(huber_c=None)                                   # Huber scales only the white part: plain updates

    def kf(prob):
        return gain_kf(prob.state_t_s, prob.disp_m, prob.fix_t_s, prob.fix_xy_m, prob.fix_var_m2, g.step_var_m2,
                       g.gain_var, g.gain_walk_var, fix_corr=prob.fix_corr, **kw).xy_m

    np.testing.assert_allclose(kf(white_bias), kf(plain), atol=1e-6)
    np.testing.assert_allclose(lsq_track(white_bias, n_iter=1), lsq_track(plain, n_iter=1), atol=1e-6)


def test_the_correlated_filter_stays_causal_and_its_lag_smoother_runs():
    p, _, _ = _ar_walk(3, n=120)
    q = dataclasses.replace(p, fix_corr=(0.6, 0.9, 9.6))
    full = kf_gain_track(q)
    for c in (30, 90):
        keep = q.fix_t_s <= q.state_t_s[c]
        cut = dataclasses.replace(q, state_t_s=q.state_t_s[:c + 1], disp_m=q.disp_m[:c], fix_t_s=q.fix_t_s[keep],
                                  fix_xy_m=q.fix_xy_m[keep])
        np.testing.assert_allclose(kf_gain_track(cut), full[:c + 1], atol=1e-9)
    r = gain_kf(q.state_t_s, q.disp_m, q.fix_t_s, q.fix_xy_m, q.fix_var_m2, 0.01, 1e-3, 1e-6, fix_corr=q.fix_corr)
    np.testing.assert_allclose(gain_kf_lag(r, q.state_t_s, 0.0), r.xy_m)
    assert not np.allclose(gain_kf_lag(r, q.state_t_s, 5.0), r.xy_m)


def test_the_fix_model_fields_do_not_change_a_floors_cache_key(tmp_path):
    """A saved floor model does not depend on how a scored walk's fixes are weighted: changing the fix model
    keeps the key (old caches stay valid), changing the database's WKNN does not."""
    from ilocalg.track.floor import _model_cfg, floor_cache_key

    f = tmp_path / "walk.txt"
    f.write_text("x")
    base = RealWalkConfig()

    def key(c):
        return floor_cache_key([f], cfg=_model_cfg(c), dataset="d")

    fix_model = RealWalkConfig(fix_var="isotropic", fix_corr=False, map_start=False)
    assert key(fix_model) == key(base)
    assert key(dataclasses.replace(base, max_age_s=5.0)) != key(base)


def test_a_fix_age_is_one_definition_for_the_database_and_the_scored_walk(shared_data):
    """A site1 F1 walk against 5 others: each fix's age (what FixVarModel predicts on) is the mean age of the
    fresh readings of database access points its scan heard (a pandas reference), t_read_s is its time minus
    that age, and the database rows' ages (what the model is fitted on) follow the same definition."""
    from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor
    from ilocalg.io.recording import as_recording
    from ilocalg.track.database import READING_AGE_S, WifiDatabase
    from ilocalg.track.fixes import db_matrix, fit_fix_var_model, fix_age_s, loo_fix_features, wifi_fixes

    root = shared_data("ilc2020_site1")
    names = list_ilc_traces(root, floor_name="site1_F1")[:12:2]
    fl = load_ilc_floor(root, names=names, duplicate_bssid="keep_latest", relisted_wifi="keep", floor_name="site1_F1")
    scored, others = names[0], {n: fl.traces[n] for n in names[1:]}
    cfg = RealWalkConfig()
    db = WifiDatabase.from_recordings(others, max_age_s=cfg.max_age_s)
    model = fit_fix_var_model(db, cfg)
    fx = wifi_fixes(fl.traces[scored], db, cfg, fix_var_model=model)
    w = fl.traces[scored].wifi
    w = w.assign(age=w["t_s"] - w["last_seen_s"])
    w = w[w["bssid"].isin(db.ap_ids) & (w["age"] <= cfg.max_age_s)]
    assert cfg.max_age_s <= READING_AGE_S                   # every kept reading counts in the mean
    ref = w.groupby("t_s")["age"].mean()
    np.testing.assert_allclose(fx.age_s, ref.reindex(fx.t_s).to_numpy(), atol=1e-9)
    assert 0.5 < np.median(fx.age_s) < 2.0                  # about 1.1 s on the ILC walks
    np.testing.assert_allclose(fx.t_read_s, np.maximum(fx.t_s - fx.age_s, as_recording(fl.traces[scored]).t_span_s[0]))
    assert fx.var_m2.shape == fx.t_s.shape and np.all(fx.var_m2 > 0)
    # the database side: the same function of each row's ages and kept readings
    _, F = loo_fix_features(db, cfg)
    np.testing.assert_array_equal(F[:, 2], fix_age_s(db.age_s, db_matrix(db, cfg)))
    assert abs(np.median(F[:, 2]) - np.median(fx.age_s)) < 0.3
