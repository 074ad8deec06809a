import numpy as np
import pandas as pd
import pytest

from ilocalg import ins


def test_nav_errors_and_stats():
    n = 100
    truth = np.zeros((n, 3))
    est = truth + np.array([1.0, -2.0, 0.5])  # E, N, U offsets
    C = ins.euler_to_dcm(np.zeros(n), np.zeros(n), np.full(n, np.pi - 0.01))
    Ct = ins.euler_to_dcm(np.zeros(n), np.zeros(n), np.full(n, -np.pi + 0.01))
    err = ins.nav_errors(est, C, truth, Ct)
    assert list(err.columns) == ["N", "E", "H", "Roll", "Pitch", "Heading"]
    assert np.allclose(err["N"], -2.0) and np.allclose(err["E"], 1.0)
    assert np.allclose(err["Heading"], np.rad2deg(-0.02))  # wrapped, not 359 deg
    st = ins.error_stats(err)
    assert st["rms"]["N"] == pytest.approx(2.0) and st["std"]["N"] == pytest.approx(0.0)
    assert st["max"]["E"] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="pos_n_m"):
        ins.nav_errors(est[:5], C[:5], truth, Ct)


def test_heading_lag_zero_and_turning():
    t_ref = np.arange(0, 10, 0.005)
    yaw = 0.5 * t_ref  # turning at 0.5 rad/s
    mref = ins.euler_to_dcm(0 * t_ref, 0 * t_ref, yaw)
    t = np.arange(1, 9, 0.06)
    m = ins.euler_to_dcm(0 * t, 0 * t, 0.5 * t)
    assert np.abs(ins.heading_error_with_lag_deg(t, m, t_ref, mref, 0.0)).max() < 1e-6
    e = ins.heading_error_with_lag_deg(t, m, t_ref, mref, 0.1)
    assert np.allclose(e, np.rad2deg(0.05), atol=1e-6)
    with pytest.raises(ValueError, match="outside"):
        ins.heading_error_with_lag_deg(t, m, t_ref, mref, 5.0)


def test_window_sweep_limits_and_control_point_windows():
    from ilocalg.ins.evaluate import window_sweep, window_sweep_tables
    from tests.test_ins_eskf import circle_run

    res, pos_t, _, mat_t, idx = circle_run(6, n=600)
    scored = np.ones(res.t_s.size, bool)
    span = res.t_s[-1] - res.t_s[0]
    ws = window_sweep(res, [2.0, 10 * span], scored, pos_t, mat_t, res.t_s[idx[:10]])
    assert list(ws.solutions) == ["Filtering", 2.0, 10 * span, "RTS (whole run)"]
    sw = ws.sweep.set_index(["window_s", "stat"])
    # one window over the whole run is the whole-run RTS; the filter has no latency
    assert sw.loc[(10 * span, "rms"), "horizontal"] == pytest.approx(sw.loc[(np.inf, "rms"), "horizontal"])
    assert sw.loc[(0.0, "rms"), "latency_mean_s"] == 0.0
    assert sw.loc[(np.inf, "rms"), "horizontal"] < sw.loc[(0.0, "rms"), "horizontal"]
    g = ws.gcp.set_index("window_s")
    # fixes only in the first part of the run: 2 s windows after it hold no control point
    assert 0.0 < g.loc[2.0, "share_without_gcp"] < 1.0 and g.loc[10 * span, "share_without_gcp"] == 0.0
    tab, gw = window_sweep_tables(ws.sweep.assign(phone="a"), ws.gcp.assign(phone="a"))
    assert list(tab["window_s"][tab["stat"] == "rms"]) == [0.0, 2.0, 10 * span, np.inf]
    assert len(gw) == 2
    # a whole-run RTS computed once (a sweep over grid offsets) gives the same tables
    from ilocalg.ins.smoother import eskf_rts_smooth

    again = window_sweep(res, [2.0, 10 * span], scored, pos_t, mat_t, res.t_s[idx[:10]],
                         whole_run=eskf_rts_smooth(res, with_cov=False))
    pd.testing.assert_frame_equal(again.sweep, ws.sweep, check_exact=True)
    pd.testing.assert_frame_equal(again.gcp, ws.gcp, check_exact=True)


def test_window_sweeps_over_offsets_equal_one_offset_at_a_time():
    from ilocalg.ins.evaluate import window_sweep, window_sweeps
    from tests.test_ins_eskf import circle_run

    res, pos_t, _, mat_t, idx = circle_run(7, n=600)
    scored = np.arange(res.t_s.size) >= 100
    offs = (0.0, 0.25, 0.5)
    many = window_sweeps(res, [1.0, 2.0, 5.0], scored, pos_t[scored], mat_t[scored], res.t_s[idx[:10]],
                         offset_fracs=offs)
    assert len(many) == len(offs)
    for off, ws in zip(offs, many, strict=True):
        one = window_sweep(res, [1.0, 2.0, 5.0], scored, pos_t[scored], mat_t[scored], res.t_s[idx[:10]],
                           offset_frac=off)
        pd.testing.assert_frame_equal(ws.sweep, one.sweep, check_exact=True)
        pd.testing.assert_frame_equal(ws.gcp, one.gcp, check_exact=True)
        assert list(ws.solutions) == list(one.solutions)
    # the grid offset moves the windows: the 2 s rows differ between offsets
    assert not many[0].gcp.equals(many[1].gcp) or not many[0].sweep.equals(many[1].sweep)
