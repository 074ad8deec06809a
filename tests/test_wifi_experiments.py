"""The Wi-Fi experiments and the ``evaluate wifi`` command."""

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import wifi_iloc, wifi_ujiindoorloc
from ilocalg.papers import comparison_table


def test_wifi_iloc_fast_is_deterministic_and_sane():
    a = wifi_iloc.run(seed=0, fast=True, k_values=(1, 3, 5), timing_repeats=1)
    b = wifi_iloc.run(seed=0, fast=True, k_values=(1, 3, 5), timing_repeats=1)
    for name in ("k_study", "methods", "errors", "paper_vs_reproduced", "sim_summary"):
        pd.testing.assert_frame_equal(a[name], b[name])
    m = a["methods"].set_index("method")
    assert (m["n"] == 28 * 5).all()
    assert (m["median_m"] < 5.0).all()  # 2 m grid, a usable radio map
    ks = a["k_study"].set_index("k_aps")["mean_m"]
    assert ks[5] < ks[1]  # Fig 3: more APs help
    comp = comparison_table(a["paper_vs_reproduced"].to_dict("records"))
    assert {"paper_value", "reproduced_value", "agreement"} <= set(comp.columns)
    assert "RADAR median" in wifi_iloc.findings(a)
    r = a["readings"]
    assert list(r.columns) == ["choice", "paper_line", "text_says", "code_does", "source"]
    assert {"RADAR database", "test route", "floor plan"} <= set(r["choice"])
    # the text's database (every stored scan) and the mean map are both reported
    assert {"Simplified-RADAR", "Simplified-RADAR (mean map)"} <= set(m.index)


@pytest.mark.realdata
def test_ujiindoorloc_fast_run(shared_data):
    d = shared_data("ujiindoorloc")
    t = wifi_ujiindoorloc.run(seed=0, fast=True, data_dir=d.parent)
    m = t["methods"].set_index("method")
    assert (m["n"] == 256).all()
    assert m.loc["best (union top-5 APs, N=12)", "mean_m"] < m.loc["KNN K=5 (Euclidean)", "mean_m"]
    lad = t["toolkit_ladder"]
    assert len(lad) == 14 and lad["method"].str.startswith("toolkit: ").all()
    assert set(lad["method"]) <= set(m.index)                          # the literal rows stay, toolkit rows added
    assert ((lad["mean_ci95_lo_m"] <= lad["mean_m"]) & (lad["mean_m"] <= lad["mean_ci95_hi_m"])).all()
    assert set(t["toolkit_cv"]["groups"]) == {"USERID", "PHONEID", "spot x PHONEID"}
    off = t["toolkit_cv"].query("groups == 'PHONEID'")
    assert off["shifts_db"].notna().sum() == 2                     # with and without the offset search
    assert off["estimators"].notna().sum() == 1 + 2 + 3            # the ensemble's members (fast: one candidate),
    assert (off["grid"] == "offset range x members").sum() == 2     # then offset range x members (fast: two)
    assert (off["grid"] == "spots x weight exponent").sum() == 3    # then spots (fast: none, K = 1, K = 2)
    sp = off[off["grid"] == "spots x weight exponent"]
    assert f"members={sp['estimators'].iloc[0]}," in lad["params"].iloc[-3]   # the spot row: the spot CV's first rank
    cv_sp = t["toolkit_cv"].query("groups == 'spot x PHONEID'")
    assert set(cv_sp["grid"]) == {"headline candidates", "device calibration"}
    hl = cv_sp[cv_sp["grid"] == "headline candidates"]
    assert len(hl) == 12 and (hl["n_neighbors"] == 5).all()          # 6 candidates, each with and without rank
    assert hl["estimators"].str.endswith(" + rank_sorensen").sum() == 6
    assert hl["rank"].iloc[0] == 1 and hl["cv_mean_error_m"].is_monotonic_increasing
    assert f"members={hl['estimators'].iloc[0]}," in lad["params"].iloc[-2]   # the spot x PHONEID CV's first rank
    dc = cv_sp[cv_sp["grid"] == "device calibration"]        # then calibration on / off for those members
    assert sorted(dc["device_calibration"]) == ["off", "on"] and dc["rank"].iloc[0] == 1
    assert lad["params"].iloc[-1].startswith(f"device_calibration={dc['device_calibration'].iloc[0]},")
    assert lad["params"].iloc[-1].endswith(f"members={dc['estimators'].iloc[0]}")
    assert lad["method"].iloc[-1] == t["measures"]["item"].iloc[0]   # the headline is the CV-chosen last row
    b = t["toolkit_error_budget"].set_index("group")                # the headline's error budget
    assert b.loc["all located scans", "mean_error_m"] == pytest.approx(lad["mean_m"].iloc[-1])
    assert b.loc["floor hit", "share_of_total_error"] + b.loc["floor missed", "share_of_total_error"] == (
        pytest.approx(1.0))
    cli = t["toolkit_cli"].iloc[0]                                   # does --method toolkit run the headline?
    assert cli["ladder_row"] == lad["method"].iloc[-1] and cli["ladder_n_neighbors"] == "5"
    assert not cli["same"]                                  # fast mode's grids cannot choose the full-mode headline
    al = t["toolkit_ap_loss"]                                  # three rows with APs gone (fast: 0 and 20 %)
    assert list(al["label"]) == list(wifi_ujiindoorloc.AP_LOSS_LABELS) * 2
    assert list(al["row"].iloc[:3]) == [lad["method"].iloc[0], "toolkit: + Sorensen distance", lad["method"].iloc[-1]]
    assert (al.query("fraction_aps_gone == 0.2")["increase_m"] > 0).all()   # losing APs costs every row
    assert len(wifi_ujiindoorloc.ap_loss_findings(al, lad)) == 4
    c = t["campaigns"].set_index("quantity")
    assert c.loc["scans", "validation"] == 256 and c.loc["users (USERID; 0 = not recorded)", "validation"] == 1
    assert 0.5 < c.loc["share of scans with a phone not in training", "validation"] < 1  # 9 of 11 phones are new
    assert set(t["measures"]["quantity"]) >= {"toolkit_mean_error", "toolkit_floor_hit_rate"}
    assert wifi_ujiindoorloc.run(data_dir=d.parent / "nowhere") is None


@pytest.mark.realdata
def test_cli_gives_the_independent_k5_figure(shared_data):
    d = shared_data("ujiindoorloc")
    out = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "wifi", "--train",
                          str(d / "trainingData.csv.gz"), "--test", str(d / "validationData.csv.gz"),
                          "--format", "ujiindoorloc", "--method", "knn", "--k", "5", "--metric", "euclidean",
                          "--json"], capture_output=True, text=True, check=True, timeout=120)
    r = json.loads(out.stdout)
    assert list(r) == ["mean_error_m", "median_error_m", "p75_error_m", "p95_error_m", "floor_hit_rate",
                       "building_hit_rate", "n", "n_no_shared_ap"]
    assert r["mean_error_m"] == pytest.approx(8.808, abs=0.01)
    assert r["floor_hit_rate"] == pytest.approx(0.9028, abs=1e-4)
    assert r["building_hit_rate"] == pytest.approx(0.9973, abs=1e-4)
    assert r["n"] == 1111 and r["n_no_shared_ap"] == 0


@pytest.mark.realdata
def test_cli_toolkit_is_the_ladder_headline(shared_data):
    """``--method toolkit`` (a Pipeline, fitted and predicted as a whole) gives what the ladder's code path gives for
    the same members (each fitted apart by fit_members, shared searches, then combined)."""
    from ilocalg.wifi.ensemble import ApSelector, combine_predictions
    from ilocalg.wifi.model_selection import TOOLKIT_HEADLINE, _target, fit_members, headline_members

    d = shared_data("ujiindoorloc")
    out = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "wifi", "--train",
                          str(d / "trainingData.csv.gz"), "--test", str(d / "validationData.csv.gz"),
                          "--method", "toolkit"], capture_output=True, text=True, check=True, timeout=300)
    r = json.loads(out.stdout)
    tr, te = wifi_ujiindoorloc.load(d.parent)
    aps = ApSelector(1).fit(tr.rssi_dbm)
    got = fit_members(headline_members(), aps.transform(tr.rssi_dbm), _target(tr), aps.transform(te.rssi_dbm),
                      TOOLKIT_HEADLINE["n_neighbors"])
    pr = combine_predictions([got[n] for n in TOOLKIT_HEADLINE["members"]])
    e = np.hypot(pr[:, 0] - te.x_m, pr[:, 1] - te.y_m)
    assert r["n"] == np.isfinite(e).sum() == 1111
    assert r["mean_error_m"] == pytest.approx(np.nanmean(e), rel=1e-9)
    assert r["floor_hit_rate"] == pytest.approx(np.mean(pr[:, 2] == te.floor), abs=1e-12)
    assert r["building_hit_rate"] == pytest.approx(np.mean(pr[:, 3] == te.building), abs=1e-12)
    assert r["mean_error_m"] < 7.0          # the toolkit beats every literal method of notebook 02 (best: 7.24 m)


def test_cli_bad_input(tmp_path):
    bad = tmp_path / "x.csv"
    bad.write_text("")
    out = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "wifi", "--train", str(bad), "--test",
                          str(bad), "--method", "knn"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 2 and "empty file" in out.stderr


def test_ap_distribution_is_a_distribution():
    d = wifi_iloc.ap_distribution(0, scans_per_point=50)
    assert np.isclose(d["probability"].sum(), 1.0) and np.isclose(d["cdf"].iloc[-1], 1.0)
    assert (np.diff(d["cdf"]) >= 0).all() and d["rssi_dbm"].min() >= -95


def test_test_scans_hearing_no_ap_are_counted_not_scored():
    from ilocalg.experiments import wifi_iloc

    t = wifi_iloc.run(seed=9, fast=True, k_values=(5,), timing_repeats=1)
    c = t["test_scans"].iloc[0]
    assert c["scored"] + c["not_scored_no_ap_heard"] == c["test_scans"]
    per_method = t["errors"].groupby("method").size()
    assert (per_method == c["scored"]).all()


def test_sweep_runs_time_once_and_give_the_same_results():
    """The seed sweep and the claims' samples time each method in one pass (manifest.SWEEP_KWARGS): every table but
    the measured ``timing`` is that of the notebook's run, and so are the long results but the time per query."""
    from ilocalg.papers.claims import tables_to_long
    from ilocalg.workflow.manifest import SWEEP_KWARGS

    full = wifi_iloc.run(seed=0, fast=True, k_values=(5,))
    lite = wifi_iloc.run(seed=0, fast=True, k_values=(5,), **SWEEP_KWARGS["wifi_iloc"])
    assert list(lite) == list(full)
    for name in full:
        if name != "timing":
            drop = (lambda df: df[df["quantity"] != "time per query"]) if name == "measures" else (lambda df: df)
            pd.testing.assert_frame_equal(drop(lite[name]), drop(full[name]), check_exact=True)
    pd.testing.assert_frame_equal(lite["timing"].drop(columns="ms_per_query"),
                                  full["timing"].drop(columns="ms_per_query"), check_exact=True)
    assert (lite["timing"]["ms_per_query"] > 0).all()
    long_l, long_f = tables_to_long(lite), tables_to_long(full)
    timed = long_f["quantity"].isin(["time per query", "ms_per_query"])
    assert timed.sum() >= 4
    pd.testing.assert_frame_equal(long_l[~timed.to_numpy()], long_f[~timed.to_numpy()], check_exact=True)
