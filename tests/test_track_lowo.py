"""Leave-one-walk-out pooling, the Wi-Fi ablation and a floor's files (ilocalg.track.lowo)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.papers.claims import tables_to_long
from ilocalg.track import lowo


def _sweep_rows(errors: dict) -> pd.DataFrame:
    """sweep_waypoints rows from {(floor, walk): {method: [error per waypoint]}}."""
    rows = [{"quantity": m, "value": v, "item": f"{fl}/{w}#{k}", "unit": "m"}
            for (fl, w), per in errors.items() for m, e in per.items() for k, v in enumerate(e)]
    return tables_to_long({"sweep_waypoints": pd.DataFrame(rows)})


def test_sweep_summary_pools_floors_and_waypoints():
    errs = {("site/F1", "a"): {"wifi": [4.0, 6.0], "lsq": [1.0, 2.0], "kf": [3.0, 3.0]},
            ("site/F1", "b"): {"wifi": [2.0], "lsq": [1.0], "kf": [5.0]},
            ("site/F2", "c"): {"wifi": [10.0, 10.0, 10.0], "lsq": [4.0, 4.0, 4.0], "kf": [9.0, 9.0, 9.0]}}
    r = lowo.sweep_summary(_sweep_rows(errs))
    s = r["summary"].set_index(["floor", "method"])
    assert list(s.index.get_level_values(0).unique()) == ["site/F1", "site/F2", "pooled"]
    assert s.loc[("site/F1", "wifi"), "n_waypoints"] == 3 and s.loc[("site/F1", "wifi"), "n_walks"] == 2
    assert s.loc[("site/F1", "lsq"), "mean_m"] == pytest.approx(4.0 / 3.0)
    assert s.loc[("site/F1", "lsq"), "ratio_to_wifi"] == pytest.approx((4.0 / 3.0) / 4.0)
    pooled = np.r_[1.0, 2.0, 1.0, 4.0, 4.0, 4.0]                      # every waypoint, not the floor means
    assert s.loc[("pooled", "lsq"), "mean_m"] == pytest.approx(pooled.mean())
    assert s.loc[("pooled", "lsq"), "p75_m"] == pytest.approx(np.quantile(pooled, 0.75))
    assert s.loc[("pooled", "wifi"), "ratio_to_wifi"] == 1.0 and np.isnan(s.loc[("pooled", "wifi"), "goal"])
    # offline estimators must halve the Wi-Fi error, causal ones reach 0.7 of it
    assert s.loc[("pooled", "lsq"), "goal"] == 0.5 and s.loc[("pooled", "lsq"), "meets_goal"]
    assert s.loc[("pooled", "kf"), "goal"] == 0.7 and not s.loc[("pooled", "kf"), "meets_goal"]
    assert len(r["waypoints"]) == 6 and {"floor", "walk", "waypoint", "wifi", "lsq", "kf"} <= set(r["waypoints"])
    text = lowo.lowo_findings(r["summary"])
    assert "best offline: lsq" in text and "best online: kf" in text and "missed" in text


def test_sweep_summary_needs_waypoint_rows():
    with pytest.raises(ValueError, match="sweep_waypoints"):
        lowo.sweep_summary(tables_to_long({"measures": pd.DataFrame([{"quantity": "x", "value": 1.0}])}))


def test_floor_files_and_image_of_a_folder(tmp_path):
    d = tmp_path / "myfloor"
    (d / "path_data_files").mkdir(parents=True)
    for n in ("b.txt", "a.txt"):
        (d / "path_data_files" / n).write_text("")
    assert [p.name for p in lowo.floor_files(tmp_path, "myfloor")] == ["a.txt", "b.txt"]
    assert lowo.floor_image(tmp_path, "myfloor") is None
    (d / "floor_image.png").write_bytes(b"\x89PNG")
    assert lowo.floor_image(tmp_path, "myfloor") == b"\x89PNG"


def test_floor_image_of_an_archive_is_its_floors(tmp_path):
    """In a two-floor archive each floor gets its own image (read up to it); without a floor name, no image (two)."""
    import io
    import tarfile

    root = tmp_path / "site"
    root.mkdir()
    with tarfile.open(root / "site_F1_F2.tar.xz", "w:xz") as tar:
        for name, data in (("F1/floor_image.png", b"one"), ("F1/path_data_files/a.txt", b""),
                           ("F2/floor_image.png", b"two"), ("F2/path_data_files/b.txt", b"")):
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    assert lowo.floor_image(tmp_path, "site/F1") == b"one"
    assert lowo.floor_image(tmp_path, "site/F2") == b"two"
    assert lowo.floor_image(tmp_path, "site/F3") is None
    assert lowo.floor_image(tmp_path, "site") is None


@pytest.mark.realdata
def test_wifi_ablation_plain_reference_first(shared_data):
    from ilocalg.io.ilc import load_ilc_floor
    from ilocalg.track import WIFI_CANDIDATES

    d = shared_data("ilc2020_site2_F4")
    fl = load_ilc_floor(d, duplicate_bssid="keep_latest", relisted_wifi="keep")
    a = lowo.wifi_ablation(fl)
    assert list(a["relisted_wifi"].unique()) == ["keep", "merge"]
    assert list(a["wifi_config"][:len(WIFI_CANDIDATES)]) == list(WIFI_CANDIDATES)
    assert (a.query("relisted_wifi == 'keep'")["merged_readings"] == 0).all()
    assert (a.query("relisted_wifi == 'merge'")["merged_readings"] > 0).all()
    assert a["n"].iloc[0] > 0 and (a["n"] == a["n"].iloc[0]).all()           # every configuration scores every scan
    assert np.isfinite(a[["mean_m", "median_m", "p75_m"]].to_numpy()).all() and (a["mean_m"] > 0).all()


def test_sweep_summary_judges_a_declared_latency_as_online_and_never_as_offline():
    # the lag variant beats the offline lsq here: it must not become the "best offline", and its goal is 0.7
    errs = {("site/F1", "a"): {"wifi": [10.0, 10.0], "lsq": [6.0, 6.0], "kf": [8.0, 8.0],
                               "kf_gain_map_lag5s": [5.0, 5.0]}}
    s = lowo.sweep_summary(_sweep_rows(errs))["summary"].set_index(["floor", "method"])
    lag = s.loc[("pooled", "kf_gain_map_lag5s")]
    assert lag["goal"] == 0.7 and lag["meets_goal"] and not lag["online"] and lag["latency"] == "every state 5 s"
    assert s.loc[("pooled", "lsq"), "latency"] == "whole walk" and s.loc[("pooled", "kf"), "latency"] == "none"
    text = lowo.lowo_findings(s.reset_index())
    assert "best offline: lsq" in text and "best online: kf," in text
    assert "best online with a declared latency (not causal): kf_gain_map_lag5s" in text
