"""Tests of ilocalg.measure (measurement functions on synthetic data with known parameters) and of
the accessor ilocalg.sim.measured."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ilocalg.measure import scans
from ilocalg.measure.stats import bootstrap, bootstrap_many
from ilocalg.sim import measured


def _walk_scans(rng, n_scans=60, n_aps=12, interval_s=2.0, age_s=1.0, relist_p=0.5):
    """Synthetic scans with known interval and fresh-reading age; some readings re-listed (last_seen +1 ms)."""
    rows = []
    last = {}
    for k in range(n_scans):
        t = 100.0 + k * interval_s
        for j in range(n_aps):
            if j in last and rng.random() < relist_p:
                rssi, ls = last[j]
                ls = ls + 0.001 * rng.choice([-1, 1])
            else:
                rssi, ls = float(rng.integers(-90, -40)), t - age_s
            last[j] = (rssi, ls)
            rows.append((t, k, f"ap{j}", rssi, ls))
    return pd.DataFrame(rows, columns=["t_s", "scan_id", "bssid", "rssi_dbm", "last_seen_s"])


def test_scan_interval_and_distinct_age_recover_known_values():
    w = _walk_scans(np.random.default_rng(1))
    assert np.allclose(scans.scan_intervals_s(w), 2.0)
    ages = scans.reading_ages_s(w)
    assert np.allclose(ages, 1.0)  # re-listings removed: every distinct reading is 1 s old at first listing
    listed = scans.reading_ages_s(w, distinct=False)
    assert listed.size > ages.size and np.median(listed) > 1.5  # re-listed rows look older


def test_distinct_keeps_a_new_reading_with_equal_rssi_when_last_seen_moves():
    w = pd.DataFrame({"t_s": [1.0, 3.0, 5.0], "scan_id": [0, 1, 2], "bssid": ["a", "a", "a"],
                      "rssi_dbm": [-60.0, -60.0, -60.0], "last_seen_s": [0.0, 0.001, 4.0]})
    kept = scans.distinct_readings(w)
    assert kept["t_s"].tolist() == [1.0, 5.0]


def test_scans_missing_column_is_named():
    with pytest.raises(ValueError, match="last_seen_s"):
        scans.reading_ages_s(pd.DataFrame({"t_s": [1.0], "bssid": ["a"], "rssi_dbm": [-50.0]}))


def test_bootstrap_is_seeded_and_covers_the_mean():
    x = np.random.default_rng(3).normal(5.0, 1.0, 400)
    a = bootstrap(x, np.mean, rng=7)
    b = bootstrap(x, np.mean, rng=7)
    assert a == b
    assert a.ci_low < 5.0 < a.ci_high and a.ci_high - a.ci_low < 0.4
    with pytest.raises(ValueError, match="n_boot"):
        bootstrap(x, np.mean, n_boot=10)


def test_bootstrap_many_gives_each_output_its_own_bootstrap():
    """Several outputs on one set of draws: each is bit for bit the single-output bootstrap with the same seed, which
    is the percentile bootstrap written out (clusters resampled with replacement, 2.5 / 97.5 % of the replicates)."""
    r = np.random.default_rng(5)
    groups = [r.normal(0, 1, (int(r.integers(3, 9)), 2)) for _ in range(15)]  # clusters of (x, y) rows

    def stats(a):
        return float(np.corrcoef(a[:, 0], a[:, 1])[0, 1]), float(a[:, 0].std()), float(a[:, 1].mean())

    many = bootstrap_many(groups, stats, n_boot=200, rng=9)
    for j, e in enumerate(many):
        assert e == bootstrap(groups, lambda a, j=j: stats(a)[j], n_boot=200, rng=9)
        g = np.random.default_rng(9)
        reps = [stats(np.concatenate([groups[i] for i in g.integers(0, 15, size=15)]))[j] for _ in range(200)]
        a = (1.0 - 0.95) / 2.0
        lo, hi = np.nanquantile(reps, [a, 1.0 - a])
        assert (e.value, e.ci_low, e.ci_high, e.n) == (stats(np.concatenate(groups))[j], lo, hi, 15)
    x = r.normal(2.0, 1.0, 300)  # one value per cluster
    m, s = bootstrap_many(x, lambda v: (np.mean(v), np.std(v)), rng=3)
    assert m == bootstrap(x, np.mean, rng=3) and s == bootstrap(x, np.std, rng=3)


def test_cluster_bootstrap_is_wider_than_iid_for_correlated_clusters():
    r = np.random.default_rng(4)
    groups = [np.full(50, r.normal()) + r.normal(0, 0.1, 50) for _ in range(20)]
    wide = bootstrap(groups, np.mean, rng=1)
    narrow = bootstrap(np.concatenate(groups), np.mean, rng=1)
    assert (wide.ci_high - wide.ci_low) > 3 * (narrow.ci_high - narrow.ci_low)


def test_accessor_reads_the_committed_table():
    r = measured.row("wifi_scan_interval_s")
    assert r["unit"] == "s" and r["ci_low"] <= r["value"] <= r["ci_high"]
    assert measured.param("wifi_scan_interval_s") == r["value"]
    assert "wifi_scan_interval_s" in measured.cite("wifi_scan_interval_s")


def test_accessor_unknown_parameter_is_named():
    with pytest.raises(ValueError, match="no_such_parameter"):
        measured.param("no_such_parameter")


def test_accessor_rejects_a_table_with_duplicates(tmp_path):
    p = tmp_path / "m.csv"
    p.write_text("parameter,value,ci_low,ci_high,unit,dataset,method\na,1,0,2,s,x,y\na,1,0,2,s,x,y\n")
    with pytest.raises(ValueError, match="line 3"):
        measured.table(p)


# --- radio: synthetic fields with known parameters ----------------------------------------------

from ilocalg.measure import gait as mgait  # noqa: E402
from ilocalg.measure import heading, radio  # noqa: E402


def _field(rng, n_aps=30, n_pts=120, n=3.0, p0=-35.0, sigma=5.0):
    xy = rng.uniform(0, 60, (n_pts, 2))
    ap = rng.uniform(5, 55, (n_aps, 2))
    d = np.maximum(np.hypot(xy[:, None, 0] - ap[None, :, 0], xy[:, None, 1] - ap[None, :, 1]), 1.0)
    return xy, p0 - 10 * n * np.log10(d) + rng.normal(0, sigma, d.shape)


def test_path_loss_fit_recovers_exponent_and_sigma():
    xy, m = _field(np.random.default_rng(0))
    pl = radio.path_loss_per_ap(xy, m)
    assert len(pl) == 30
    assert abs(np.median(pl["n"]) - 3.0) < 0.3
    assert abs(np.median(pl["sigma_db"]) - 5.0) < 0.5


def test_path_loss_fit_rejects_bad_shapes_and_skips_sparse_aps():
    with pytest.raises(ValueError, match="xy_m"):
        radio.fit_path_loss(np.zeros((5, 3)), np.zeros(5))
    assert radio.fit_path_loss(np.zeros((3, 2)), np.array([-50.0, -60.0, np.nan])) is None


def test_device_offsets_recovered_on_shared_places():
    r = np.random.default_rng(1)
    n_pl, n_ap, offs = 60, 20, np.array([-4.0, 0.0, 3.0, 1.0])
    mu = r.uniform(-90, -40, (n_pl, n_ap))
    rows, place, dev = [], [], []
    for p in range(n_pl):
        for d in r.choice(4, 2, replace=False):
            for _ in range(5):
                rows.append(mu[p] + offs[d] + r.normal(0, 2, n_ap))
                place.append(p)
                dev.append(d)
    off = radio.device_offsets_db(np.array(rows), np.array(place), np.array(dev))
    np.testing.assert_allclose(off.to_numpy(), offs - offs.mean(), atol=0.4)


def test_within_place_sd_and_detection_curve():
    r = np.random.default_rng(2)
    means = np.linspace(-100, -50, 40)
    x = means[None, :] + r.normal(0, 3.0, (400, 40))
    x[x < -90] = np.nan                                   # hard sensitivity at -90 dBm
    cell = np.repeat(np.arange(40), 10)
    sd = radio.within_place_sd_db(x[:, 25:], cell)       # strong APs: always heard
    assert abs(np.sqrt(np.mean(sd**2)) - 3.0) < 0.3
    m, f, _ = radio.detection_curve(x, cell)
    fit = radio.fit_detection(m, f)
    assert -95 < fit["m50_dbm"] < -85 and fit["p_max"] > 0.9


def test_drift_per_ap_recovers_known_drift_and_removes_device_offset():
    r = np.random.default_rng(3)
    xy = r.uniform(0, 50, (80, 2))
    means = r.uniform(-90, -40, (80, 15))
    drift = r.normal(0, 3.0, 15)
    idx = r.integers(0, 80, 300)
    dev = r.integers(0, 3, 300)
    test = means[idx] + drift[None, :] + np.array([5.0, -2.0, 0.0])[dev][:, None] + r.normal(0, 1, (300, 15))
    d = radio.drift_per_ap_db(means, xy, np.zeros(80), test, xy[idx], np.zeros(300), dev, radius_m=0.01)
    np.testing.assert_allclose(d.to_numpy() - d.mean(), drift - drift.mean(), atol=0.5)


# --- gait and heading -----------------------------------------------------------------------------

def test_step_variability_recovers_known_cv():
    r = np.random.default_rng(4)
    T = 0.5 * (1 + 0.05 * r.normal(size=400))
    A = 3.0 * (1 + 0.2 * r.normal(size=400))
    v = mgait.step_variability(pd.DataFrame({"T_s": T, "A_mps2": A}))
    assert abs(v["cv_T"] - 0.05) < 0.01 and abs(v["cv_A"] - 0.2) < 0.03
    assert abs(v["rcv_T"] - 0.05) < 0.01


def test_step_series_on_a_synthetic_walk_finds_each_step():
    t = np.arange(0, 30, 0.01)
    f = 1.8
    acc = np.column_stack([np.zeros_like(t), np.zeros_like(t), 9.81 + 3.0 * np.cos(2 * np.pi * f * t)])
    steps = np.arange(1.0, 29.0, 1 / f)
    s = mgait.step_series(acc, t, steps)
    assert len(s) == steps.size - 1
    np.testing.assert_allclose(s["T_s"], 1 / f, atol=0.02)
    np.testing.assert_allclose(s["A_mps2"], 6.0, rtol=0.05)


def test_gait_correlations_known_structure():
    r = np.random.default_rng(5)
    SL = r.uniform(0.4, 0.8, 300)
    v = r.uniform(0.8, 1.5, 300)
    A = 2 + 5 * SL + 0.5 * r.normal(size=300)
    c = mgait.gait_correlations(pd.DataFrame({"SL_m": SL, "T_s": SL / v, "speed_mps": v, "A_mps2": A}))
    assert c["corr_A_SL"] > 0.6
    assert abs(c["A_resid_rel"] - 0.5 / A.mean()) < 0.02


def test_rotvec_heading_and_misalignment():
    yaw = np.deg2rad(30.0)  # rotation about up by 30 deg: the y axis (north) turns to theta = 120 deg
    rv = np.array([[0.0, 0.0, np.sin(yaw / 2)]])
    assert np.isclose(np.rad2deg(heading.rotvec_theta_rad(rv)[0]), 120.0)
    r = np.random.default_rng(6)
    d = r.uniform(-np.pi, np.pi, 200)
    h = d + 0.7 + np.deg2rad(r.normal(0, 5, 200))        # constant map rotation 0.7 rad + 5 deg scatter
    mis = heading.misalignment(h, d, np.zeros(200))
    assert abs(np.rad2deg(mis).std() - 5.0) < 1.0 and abs(np.median(mis)) < 0.01


def test_measure_command_reports_missing_data_as_one_line(tmp_path, capsys):
    from ilocalg.workflow.cli import main

    rc = main(["measure", "--data", str(tmp_path), "--out", str(tmp_path / "m.csv"), "--parts", "scans"])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error: ") and "ilc2020_site1" in err
    assert main(["measure", "--data", str(tmp_path), "--parts", "nonsense"]) == 2


def test_forward_diff_jacobian_gives_scipy_default_fits_bit_for_bit():
    # the fits pass a Jacobian callable with the numbers of least_squares' default '2-point' estimate (steps turned
    # or shortened at the bounds): every solution, residual vector and evaluation count equals the default's
    from scipy.optimize import least_squares

    r = np.random.default_rng(11)
    for trial in range(30):
        m = r.uniform(-100, -40, int(r.integers(10, 400)))
        f = np.clip(r.uniform(0.8, 1.0) / (1 + np.exp(-(m + r.uniform(-95, -70)) / r.uniform(1, 6)))
                    + r.normal(0, 0.05, m.size), 0, 1)

        def res(q, m=m, f=f):
            return q[2] / (1.0 + np.exp(-(m - q[0]) / q[1])) - f

        lb, ub = [-120, 0.2, 0.3], [-30, 20, 1.0]
        x0 = [np.median(m) - 5.0, 3.0, 0.95] if trial % 3 else [-120 + 1e-9, 20 - 1e-12, 1.0 - 1e-10]  # at the bounds
        d = radio._ForwardDiff(res, lb, ub)
        a = least_squares(res, x0, bounds=(lb, ub))
        b = least_squares(d.fun, x0, jac=d.jac, bounds=(lb, ub))
        assert np.array_equal(a.x, b.x) and np.array_equal(a.fun, b.fun) and np.array_equal(a.jac, b.jac)
        assert a.nfev == b.nfev and a.status == b.status
        if trial % 3:
            assert radio.fit_detection(m, f) == {"m50_dbm": float(a.x[0]), "scale_db": float(a.x[1]),
                                                 "p_max": float(a.x[2])}
    xy, means = _field(np.random.default_rng(12))
    for j in range(8):
        fit = radio.fit_path_loss(xy, means[:, j])
        ok = np.isfinite(means[:, j])
        x, y = xy[ok], means[ok, j]
        top = np.argsort(y)[-5:]
        w = 10 ** (y[top] / 10.0)
        c0 = (x[top] * w[:, None]).sum(axis=0) / w.sum()
        lo = [x[:, 0].min() - 30, x[:, 1].min() - 30, -80.0, 1.0]
        hi = [x[:, 0].max() + 30, x[:, 1].max() + 30, 0.0, 6.0]
        q0 = np.clip([c0[0], c0[1], y.max() + 5.0, 2.5], np.add(lo, 1e-6), np.subtract(hi, 1e-6))
        sol = least_squares(lambda q, x=x, y=y: q[2] - 10.0 * q[3] * np.log10(
            np.maximum(np.hypot(x[:, 0] - q[0], x[:, 1] - q[1]), 1.0)) - y, q0, bounds=(lo, hi))
        assert (fit["x_m"], fit["y_m"], fit["p0_dbm"], fit["n"]) == tuple(sol.x)
        assert np.array_equal(fit["residual_db"], -sol.fun)


def test_gait_correlation_arrays_equal_the_dataframe_path():
    r = np.random.default_rng(13)
    for n in (3, 5, 17, 120):
        a = r.uniform(0.4, 2.0, (n, 4))
        cols = ["A_mps2", "SL_m", "T_s", "speed_mps"]
        want = mgait.gait_correlations(pd.DataFrame(a, columns=cols))
        got = mgait.gait_correlation_arrays(*np.ascontiguousarray(a.T))
        assert list(got) == list(want)
        assert all(np.array_equal(got[k], want[k], equal_nan=True) for k in want)
