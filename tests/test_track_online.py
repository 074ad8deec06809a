"""The gain-augmented Kalman filter (ilocalg.track.online_kf) and its estimators: maths, causality, a site1 walk."""

import dataclasses

import numpy as np
import pandas as pd
import pytest

from ilocalg.track.estimators import TrackProblem, kf_gain_lag_track, kf_gain_track
from ilocalg.track.motion import Calibration, GainStats, gain_stats
from ilocalg.track.online_kf import gain_kf, gain_kf_lag
from tests.track_sim import SITE1_WALK, gained_walk, site1_floor


def _walk(seed=0, n=200, fix_sd=4.0, step_sd=0.15, scale=1.12, bias_rad=0.12, fix_every=4):
    """A winding walk whose PDR steps are off by a step scale and a heading bias (the walk's own gain)."""
    rng = np.random.default_rng(seed)
    truth, g, pdr = gained_walk(rng, n, scale, bias_rad)
    disp = np.column_stack([pdr.real, pdr.imag]) + rng.normal(0, step_sd, (n, 2))
    ts = np.arange(n + 1) * 0.5
    fi = np.arange(1, n + 1, fix_every)
    fixes = truth[fi] + rng.normal(0, fix_sd, (fi.size, 2))
    gs = GainStats(gain_var=0.02, gain_walk_var=1e-5, step_var_m2=step_sd ** 2, n_walks=10)
    return TrackProblem(ts, disp, step_sd ** 2, ts[fi], fixes, fix_sd ** 2, gain=gs), truth, g


def test_gain_kf_learns_the_walks_gain_and_beats_the_filter_without_it():
    e_gain, e_plain, g_err = [], [], []
    for seed in range(6):
        p, truth, g = _walk(seed)
        r = gain_kf(p.state_t_s, p.disp_m, p.fix_t_s, p.fix_xy_m, p.fix_var_m2, p.gain.step_var_m2,
                    p.gain.gain_var, p.gain.gain_walk_var)
        plain = gain_kf(p.state_t_s, p.disp_m, p.fix_t_s, p.fix_xy_m, p.fix_var_m2, p.gain.step_var_m2, 0.0, 0.0)
        e_gain.append(np.hypot(*(r.xy_m - truth).T).mean())
        e_plain.append(np.hypot(*(plain.xy_m - truth).T).mean())
        g_err.append(abs(complex(*r.x[-1, 2:]) - g))
    assert np.mean(e_gain) < 0.85 * np.mean(e_plain)
    assert np.mean(g_err) < 0.25 * abs(1.12 * np.exp(0.12j) - 1.0)      # most of the gain learned by the end


def test_gain_kf_without_huber_is_the_batch_least_squares_at_its_last_state():
    """Linear Gaussian model: the filtered last state equals the last state of the batch weighted least
    squares over the same prior, steps, gain walk and fixes (a dense solve)."""
    p, _, _ = _walk(3, n=30, fix_every=3)
    gv, qv, sv, fv = 0.02, 1e-4, p.step_var_m2, p.fix_var_m2
    r = gain_kf(p.state_t_s, p.disp_m, p.fix_t_s, p.fix_xy_m, fv, sv, gv, qv, huber_c=None)
    n = p.state_t_s.size
    # unknowns: p_0..p_n (2 each), g_0..g_n (2 each); rows with their weights
    nx = 4 * n
    rows, b, w = [], [], []

    def P(i):
        return slice(2 * i, 2 * i + 2)

    def G(i):
        return slice(2 * n + 2 * i, 2 * n + 2 * i + 2)

    def J(v):
        return np.array([[v[0], -v[1]], [v[1], v[0]]])

    def add(blocks, rhs, weight):
        A = np.zeros((2, nx))
        for sl, M in blocks:
            A[:, sl] += M
        rows.append(A), b.append(rhs), w.extend([weight, weight])

    cum = np.vstack([[0, 0], np.cumsum(p.disp_m, 0)])
    add([(G(0), np.eye(2))], np.array([1.0, 0.0]), 1 / gv)
    for k in range(n - 1):
        add([(P(k + 1), np.eye(2)), (P(k), -np.eye(2)), (G(k), -J(p.disp_m[k]))], np.zeros(2), 1 / sv)
        add([(G(k + 1), np.eye(2)), (G(k), -np.eye(2))], np.zeros(2), 1 / qv)
    k_of = np.searchsorted(p.state_t_s, p.fix_t_s)
    for i, (k, z) in enumerate(zip(k_of, p.fix_xy_m, strict=True)):
        # the first fix starts the filter at the fix's state moved back to state 0 along the steps
        kk = 0 if i == 0 else k
        c_at = np.array([np.interp(p.fix_t_s[i], p.state_t_s, cum[:, j]) for j in range(2)])
        add([(P(kk), np.eye(2)), (G(kk), J(c_at - cum[kk]))], z, 1 / fv)
    A, B, W = np.vstack(rows), np.concatenate(b), np.sqrt(np.array(w))
    x = np.linalg.lstsq(A * W[:, None], B * W, rcond=None)[0]
    np.testing.assert_allclose(r.x[-1, :2], x[P(n - 1)], atol=1e-6)
    np.testing.assert_allclose(r.x[-1, 2:], x[G(n - 1)], atol=1e-6)


def _cut(p: TrackProblem, c: int) -> TrackProblem:
    """The problem with everything after state c removed (steps and the fixes not yet known at it)."""
    avail = p.fix_t_s if p.fix_avail_t_s is None else p.fix_avail_t_s
    keep = avail <= p.state_t_s[c]
    return dataclasses.replace(p, state_t_s=p.state_t_s[:c + 1], disp_m=p.disp_m[:c],
                               fix_t_s=p.fix_t_s[keep], fix_xy_m=p.fix_xy_m[keep], fix_var_m2=p.fix_var_at(keep),
                               fix_avail_t_s=None if p.fix_avail_t_s is None else p.fix_avail_t_s[keep])


def test_kf_gain_is_causal_and_the_lag_variant_waits_exactly_its_lag():
    p, _, _ = _walk(1)
    full = kf_gain_track(p)
    for c in (20, 90, 150):
        np.testing.assert_allclose(kf_gain_track(_cut(p, c)), full[:c + 1], atol=1e-9)
    lag = kf_gain_lag_track(p, lag_s=3.0)
    c = 100                                      # the state 3 s (6 states) before the cut needs no later data
    np.testing.assert_allclose(kf_gain_lag_track(_cut(p, c), lag_s=3.0)[:c - 5], lag[:c - 5], atol=1e-9)
    assert not np.allclose(lag[:c - 5], full[:c - 5])       # and it is not the filter


def test_gain_kf_lag_zero_is_the_filter():
    p, _, _ = _walk(2, n=60)
    r = gain_kf(p.state_t_s, p.disp_m, p.fix_t_s, p.fix_xy_m, p.fix_var_m2, 0.02, 0.02, 1e-4)
    np.testing.assert_allclose(gain_kf_lag(r, p.state_t_s, 0.0), r.xy_m)


def test_gain_stats_recovers_a_known_gain_spread():
    rng = np.random.default_rng(0)
    rows = []
    g_sd = 0.1
    for w in range(200):
        g = 1 + g_sd * (rng.standard_normal() + 1j * rng.standard_normal())
        for _ in range(8):
            s = 5 * np.exp(1j * rng.uniform(-np.pi, np.pi))
            t = g * s
            rows.append({"walk": f"w{w}", "s_re": s.real, "s_im": s.imag, "dx_m": t.real, "dy_m": t.imag, "n": 7})
    cal = Calibration(1.0, 0.0, pd.DataFrame())
    gs = gain_stats(pd.DataFrame(rows), cal)
    assert gs.gain_var == pytest.approx(g_sd ** 2, rel=0.2)
    assert gs.step_var_m2 < 1e-12 and gs.gain_walk_var < 1e-12        # exact gains: no residual, no walk
    with pytest.raises(ValueError, match="at least 2 walks"):
        gain_stats(pd.DataFrame(rows[:8]), cal)


def _gain_stats_by_groupby(intervals, calibration, min_intervals=4):
    """gain_stats as it was written before its per-walk loop read numpy arrays: a pandas groupby (reference)."""
    from ilocalg.track.motion import _walk_gain

    iv = intervals[intervals["n"] > 0]
    G = calibration.k_weinberg * np.exp(1j * calibration.offset_rad)
    dev, walk_var, res2, nsum = [], [], 0.0, 0
    for _, w in iv.groupby("walk", sort=False):
        if len(w) < min_intervals:
            continue
        pred = G * (w["s_re"].to_numpy(dtype=float) + 1j * w["s_im"].to_numpy(dtype=float))
        true = w["dx_m"].to_numpy(dtype=float) + 1j * w["dy_m"].to_numpy(dtype=float)
        n = w["n"].to_numpy(dtype=np.int64)
        g, e, v = _walk_gain(pred, true)
        if not (np.isfinite(g) and np.isfinite(v)):
            continue
        dev.append(abs(g - 1.0) ** 2 / 2.0 - v)
        res2 += float((np.abs(e) ** 2).sum())
        nsum += int(n.sum())
        h = len(w) // 2
        g1, _, v1 = _walk_gain(pred[:h], true[:h])
        g2, _, v2 = _walk_gain(pred[h:], true[h:])
        m = 0.5 * (n[:h].sum() + n[h:].sum())
        if np.isfinite(g1) and np.isfinite(g2) and np.isfinite(v1) and np.isfinite(v2) and m > 0:
            walk_var.append((abs(g1 - g2) ** 2 / 2.0 - v1 - v2) / m)
    return GainStats(max(float(np.mean(dev)), 0.0), max(float(np.mean(walk_var)), 0.0) if walk_var else 0.0,
                     res2 / (2.0 * nsum), len(dev))


def test_gain_stats_equals_the_groupby_reference_bit_for_bit():
    # walks interleaved, some too short, intervals without steps, a row without a walk name, a zero interval
    rng = np.random.default_rng(3)
    n = 400
    iv = pd.DataFrame({"walk": rng.choice([f"w{i}" for i in range(30)], n).astype(object),
                       "s_re": rng.normal(0, 3, n), "s_im": rng.normal(0, 3, n), "dx_m": rng.normal(0, 3, n),
                       "dy_m": rng.normal(0, 3, n), "n": rng.integers(0, 9, n)})
    iv.loc[5, "walk"] = None
    iv.loc[7, ["s_re", "s_im"]] = 0.0
    cal = Calibration(0.93, 0.21, pd.DataFrame())
    for k in (2, 4, 12):
        a, b = gain_stats(iv, cal, min_intervals=k), _gain_stats_by_groupby(iv, cal, min_intervals=k)
        assert [np.float64(x).tobytes() for x in dataclasses.astuple(a)] == \
            [np.float64(x).tobytes() for x in dataclasses.astuple(b)]


def test_kf_gain_needs_the_gain_spread():
    p, _, _ = _walk(0, n=20)
    with pytest.raises(ValueError, match="gain"):
        kf_gain_track(dataclasses.replace(p, gain=None))


@pytest.mark.realdata
def test_kf_gain_on_a_site1_walk_is_causal_and_beats_wifi(shared_data):
    """A site1 F1 walk (even index in the sorted walk list: a development walk) against 25 other F1 walks:
    the online kf_gain track stays causal on real data (removing everything after a state leaves it and
    every earlier state unchanged) and its mean error is well below the Wi-Fi-only error."""
    from ilocalg.track import RealWalkConfig, build_floor_model, evaluate_walk

    scored = SITE1_WALK
    fl = site1_floor(shared_data("ilc2020_site1"))
    cfg = RealWalkConfig()
    wm = build_floor_model({k: v for k, v in fl.traces.items() if k != scored}, cfg).for_walk(scored, cfg)
    r = evaluate_walk(fl.traces[scored], wm.db, wm.calibration, wm.fix_var_m2, wm.cfg, rng=0,
                      methods=("wifi", "kf_gain", "lsq_online"), step_var_m2=wm.step_var_m2, gain=wm.gain)
    e = r["errors"].mean()
    assert e["kf_gain"] < 0.8 * e["wifi"], (e["kf_gain"], e["wifi"])
    p = r["problem"]
    full = kf_gain_track(p)
    np.testing.assert_allclose(full, r["tracks"]["kf_gain"])
    n = p.state_t_s.size
    for c in (n // 4, n // 2, n - 2):
        np.testing.assert_allclose(kf_gain_track(_cut(p, c)), full[:c + 1], atol=1e-9)
