"""ilocalg.measure.calibrate: the inverse calibration of the simulators against the measured table."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ilocalg.measure import calibrate as cal
from ilocalg.sim import gait, iloc_floor
from ilocalg.sim import measured as sm


def test_newton_inverts_a_known_monotone_map_and_carries_the_interval():
    # stats(x) = (x0^2 + 0.3 x1, 2 x1 + 0.1 x0): solve for known targets, interval ends map through the inverse
    def stat_fn(p):
        return {"a": p["u"] ** 2 + 0.3 * p["v"], "b": 2.0 * p["v"] + 0.1 * p["u"]}

    cals = (cal.Calibrand("toy", "u", "a", "1", (0.1, 10.0), ""), cal.Calibrand("toy", "v", "b", "1", (0.0, 10.0), ""))
    x, y, _ = cal.solve(cals, stat_fn, np.array([4.3, 4.2]), np.array([0.01, 0.01]), np.array([1.0, 1.0]))
    np.testing.assert_allclose(y, [4.3, 4.2], atol=0.01)
    v_true = 2.1 - 0.05 * 1.92335  # the root: 2 v + 0.1 u = 4.2, u^2 + 0.3 v = 4.3 -> u = 1.92335
    np.testing.assert_allclose(x, [1.92335, v_true], atol=0.01)
    real = pd.DataFrame({"parameter": ["a", "b"], "value": [4.3, 4.2], "ci_low": [4.0, 4.0], "ci_high": [4.6, 4.4]})
    rows = cal._group(cals, stat_fn, real, {"u": 1.0, "v": 1.0}, {})
    u = rows[0]
    assert u["ci_low"] < u["value"] < u["ci_high"]
    assert u["at_value"] == pytest.approx(4.3, abs=0.3 / 4)  # within a quarter of the real half-width
    assert u["at_copied"] == pytest.approx(1.3)
    # u's interval: about the roots of u^2 + 0.3 v = 4.0 and 4.6 with 2 v + 0.1 u = 4.2
    for end, t in ((u["ci_low"], 4.0), (u["ci_high"], 4.6)):
        v = (4.2 - 0.1 * end) / 2.0
        assert end**2 + 0.3 * v == pytest.approx(t, abs=0.1)  # linearised at the solution


def test_missing_target_is_named():
    with pytest.raises(ValueError, match="shadow_sd_db"):
        cal._targets(cal.RADIO, pd.DataFrame({"parameter": ["x"], "value": [1.0], "ci_low": [0.0], "ci_high": [2.0]}))


def test_committed_table_has_every_calibrand_with_its_target():
    t = sm.calibrated_table()
    real = sm.table()
    for c in cal.RADIO + cal.GAIT:
        r = sm.calibrated_row(c.name)
        assert r["statistic"] == c.statistic
        assert r["target"] == pytest.approx(real.loc[c.statistic, "value"], rel=1e-5)
        assert c.bounds[0] <= r["ci_low"] <= r["value"] <= r["ci_high"] <= c.bounds[1]
        # the calibrated value brings the statistic back inside the real interval (mean of the calibration seeds)
        assert r["target_ci_low"] <= r["at_value"] <= r["target_ci_high"], c.name
    assert set(t.index) >= {"iloc_floor.n_aps_floor", "iloc_floor.n_aps_other"}
    with pytest.raises(ValueError, match="unknown calibrated parameter"):
        sm.calibrated_row("gait.nothing")


def test_worlds_take_the_calibrated_values_and_keep_copied_and_assumed():
    m, c, a = (iloc_floor.world_params(w) for w in ("measured", "copied", "assumed"))
    assert a == iloc_floor.PARAMS
    for k in iloc_floor.CALIBRATED:
        assert m[k] == pytest.approx(sm.calibrated(f"iloc_floor.{k}"))
        assert c[k] == pytest.approx(sm.calibrated_row(f"iloc_floor.{k}")["copied"])
    assert m["fade_sd_edge_db"] - m["fade_sd_db"] == pytest.approx(2.0)
    assert m["path_loss_exponent"] == c["path_loss_exponent"] == sm.param("path_loss_exponent")  # not identifiable
    gm, gc = gait.gait_config("measured"), gait.gait_config("copied")
    for k in gait.CALIBRATED:
        assert getattr(gm, k) == pytest.approx(sm.calibrated(f"gait.{k}"))
        assert getattr(gc, k) == pytest.approx(sm.calibrated_row(f"gait.{k}")["copied"])
    assert gc.strike_jitter_rel == gc.yaw_wander_sd_deg == 0.0
    assert "calibrated_parameters.csv" in iloc_floor.world_sources("measured")["shadow_sd_db"]
    assert "calibrated_parameters.csv" in gait.world_reading("measured")[1]


def test_statistics_are_deterministic_and_move_with_their_parameter():
    a = cal.radio_statistics({}, seeds=(0,))
    assert a == cal.radio_statistics({}, seeds=(0,))
    b = cal.radio_statistics({"shadow_sd_db": 8.0, "detect_dbm": -96.0}, seeds=(0,))
    assert b["shadow_sd_db"] > a["shadow_sd_db"] + 1.0 and b["detect_m50_dbm"] < a["detect_m50_dbm"] - 3.0
    g0 = cal.gait_statistics({}, seeds=(0,), n_walkers=3)
    g1 = cal.gait_statistics({"strike_jitter_rel": 0.05, "yaw_wander_sd_deg": 15.0}, seeds=(0,), n_walkers=3)
    assert g1["gait_step_period_cv"] > g0["gait_step_period_cv"] + 0.02
    assert g1["heading_mis_wdm_rms_deg"] > g0["heading_mis_wdm_rms_deg"] + 3.0


def test_calibration_recomputes_the_committed_table():
    """Recompute data/calibrated_parameters.csv where it is dearest to get wrong, in half the CPU of the whole
    calibration (deterministic): the gait group's solve from the copied values, every column the test reads; for the
    radio group, the statistics at the committed values and AP counts (its solve from the copied values and its
    linearised intervals are not recomputed here: the same solver and interval code as the gait group's) and the AP
    counts the committed radio values give."""
    old = sm.calibrated_table()
    new = cal.calibrate(parts=("gait",)).set_index("parameter")
    assert list(new.index) == [c.name for c in cal.GAIT]
    for k in ("value", "ci_low", "ci_high", "at_value"):
        np.testing.assert_allclose(new[k].to_numpy(float), old.loc[new.index, k].to_numpy(float), rtol=1e-4,
                                   atol=1e-6, err_msg=k)
    radio = {c.parameter: float(old.loc[c.name, "value"]) for c in cal.RADIO}
    counts = tuple(int(old.loc[f"iloc_floor.{k}", "value"]) for k in ("n_aps_floor", "n_aps_other"))
    assert cal.ap_counts({"n_aps_floor": counts[0], "n_aps_other": counts[1], **radio}) == counts
    st = cal.radio_statistics({"n_aps_floor": counts[0], "n_aps_other": counts[1], **radio})
    np.testing.assert_allclose([st[c.statistic] for c in cal.RADIO],
                               old.loc[[c.name for c in cal.RADIO], "at_value"].to_numpy(float), rtol=1e-4, atol=1e-6)
