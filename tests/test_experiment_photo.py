"""Tests of ilocalg.experiments.photo_positioning (fast mode, one shared run)."""

import numpy as np
import pytest

from ilocalg.experiments import photo_positioning as pp


@pytest.fixture(scope="module")
def tables():
    return pp.run(seed=0, fast=True)


def test_tables_present_and_finite(tables):
    for name in ("per_shot", "distance_trend", "per_k", "per_combo", "near_collinear", "modern", "propagation",
                 "comparison", "va_convergence", "combo_geometry"):
        assert name in tables and len(tables[name]) > 0
    assert np.isfinite(tables["errors"]["error_cm"]).all()
    assert len(tables["per_combo"]) == 120
    assert tables["per_k"]["n_combos"].tolist() == [21, 35, 35, 21, 7, 1]


def test_va_error_grows_with_distance_to_p4(tables):
    # the thesis's explanation of Fig 29
    tr = tables["distance_trend"].set_index("method")
    for m in ("VAGIG", "VABIG"):
        assert tr.loc[m, "spearman_rho"] > 0.8
        assert tr.loc[m, "slope_cm_per_m"] > 0


def test_st_beats_va_and_more_pois_help_st(tables):
    cmp = tables["comparison"].set_index("quantity")["reproduced_value"]
    assert cmp["ST overall mean error"] < cmp["VAGIG overall mean error"] < cmp["VABIG overall mean error"] * 1.05
    per_k = tables["per_k"].set_index("k")
    assert per_k.loc[7, "ST"] < per_k.loc[2, "ST"]


def test_true_orientation_beats_sensor_orientation(tables):
    m = tables["modern"].set_index("k")
    assert m.loc["all k>=4", "ST_true_orientation"] < m.loc["all k>=4", "ST"]


def test_same_seed_same_tables():
    a = pp.run(seed=1, n_photos=1, ks=(2, 7))
    b = pp.run(seed=1, n_photos=1, ks=(2, 7))
    for name in ("per_shot", "per_k", "comparison", "errors"):
        assert a[name].equals(b[name])


def test_noise_free_inputs_give_exact_positions():
    t = pp.run(seed=0, n_photos=1, drag_sd_px=0.0, tilt_sd_deg=0.0, yaw_sd_deg=0.0, va_max_iter=5000, ks=(2, 6, 7))
    e = t["errors"]
    assert e.loc[e["method"].isin(["ST", "ST_true_orientation", "PnP_SQPnP", "homography"]), "error_cm"].max() < 1e-3
    # VA with >= 3 PoIs from the good guess: exact unless a combination is ambiguous
    va = e[(e["method"] == "VAGIG") & (e["k"] >= 4)]
    assert np.median(va["error_cm"]) < 0.1


def test_bad_ks_raise():
    with pytest.raises(ValueError, match="ks"):
        pp.run(seed=0, n_photos=1, ks=(1, 2))


def test_sensitivity_heading_error_moves_st_not_va():
    s = pp.sensitivity(seed=0, fast=True, grid=(("yaw_sd_deg", (1.0, 10.0)),))
    e = s.set_index(["value", "k", "method"])["error_cm"]
    assert e[(10.0, 7, "ST")] > 2 * e[(1.0, 7, "ST")]
    assert e[(10.0, 7, "VAGIG")] == pytest.approx(e[(1.0, 7, "VAGIG")])  # VA ignores the sensors


def test_marker_ranging_exact_without_noise_and_grows_with_distance():
    t = pp.marker_ranging(seed=0, fast=True, corner_sd_px=(0.0,), distances_m=(1.0, 4.0))
    err_cols = [c for c in t.columns if c.endswith("_cm")]
    assert t[err_cols].abs().to_numpy().max() < 1e-3
    t = pp.marker_ranging(seed=0, fast=True, corner_sd_px=(1.0,), distances_m=(1.0, 4.0)).set_index("distance_m")
    assert t.loc[4.0, "homography_range_rms_error_cm"] > 5 * t.loc[1.0, "homography_range_rms_error_cm"]
    # IPPE is the better-conditioned estimator of the range on the same corners
    assert t.loc[4.0, "ippe_range_rms_error_cm"] < t.loc[4.0, "homography_range_rms_error_cm"]
    with pytest.raises(ValueError, match="unknown marker"):
        pp.marker_ranging(side=0.2)
