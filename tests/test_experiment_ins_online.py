import pandas as pd
import pytest

from ilocalg.experiments import ins_online


def test_online_experiment_accepts_integer_window_lengths():
    a = ins_online.run(seed=0, fast=True, sweep_windows_s=(5, 10))
    b = ins_online.run(seed=0, fast=True, sweep_windows_s=(5.0, 10.0))
    pd.testing.assert_frame_equal(a["window_sweep"], b["window_sweep"])


def test_online_rows_are_averaged_over_grid_offsets_with_their_spread():
    r = ins_online.run(seed=0, fast=True, sweep_windows_s=(10.0,), offset_fracs=(0.0, 0.5))
    per = r["errors_per_seed"]
    assert set(per["offset_frac"]) == {0.0, 0.5}
    e = r["errors"].set_index(["phone", "method", "stat"])
    one = per[(per.phone == "Samsung") & (per.method == "Online 10sec") & (per.stat == "rms")]
    assert e.loc[("Samsung", "Online 10sec", "rms"), "N"] == pytest.approx(one["N"].mean())
    sp = r["online_spread"].set_index(["phone", "method"])
    assert sp.loc[("Samsung", "Filtering"), "horizontal_std"] == pytest.approx(0.0)  # the filter has no grid
    sw = r["window_sweep"]
    row = sw[(sw.phone == "Samsung") & (sw.window_s == 10.0) & (sw.stat == "rms")].iloc[0]
    assert row["horizontal_min"] <= row["horizontal"] <= row["horizontal_max"]
    assert {"heading_err_deg", "roll_err_deg", "pitch_err_deg"} <= set(r["trajectory"].columns)
    assert list(r["readings"].columns) == ["choice", "paper_line", "text_says", "code_does", "source"]


def test_fig19_monotonicity_and_one_row_per_quantity():
    r = ins_online.run(seed=0, fast=True, sweep_windows_s=(5.0, 10.0, 20.0, 30.0), offset_fracs=(0.0,))
    m = r["fig19_monotonicity"].set_index(["phone", "axis"])
    sw = r["window_sweep"]
    for phone in ("Samsung", "iPhone"):
        for ax in ("N", "E", "H", "horizontal"):
            row = m.loc[(phone, ax)]
            assert row["rise_10_to_20_m"] == pytest.approx(row["rms_20s_m"] - row["rms_10s_m"])
            d = sw[(sw.phone == phone) & (sw.stat == "rms") & (sw.window_s > 0) & (sw.window_s < float("inf"))]
            d = d.sort_values("window_s")[ax].to_numpy()
            assert row["n_rises"] == int((d[1:] > d[:-1]).sum()) and row["n_windows"] == 4
            assert row["monotone_falling"] == (row["n_rises"] == 0)
            assert -1.0 <= row["spearman_rms_vs_window"] <= 1.0
    # the paper's own rise: Samsung N is worse at 20 s than at 10 s (Table 8; L473), Samsung E falls
    assert m.loc[("Samsung", "N"), "paper_rise_10_to_20_m"] == pytest.approx(0.6913 - 0.6484)
    assert m.loc[("Samsung", "E"), "paper_rise_10_to_20_m"] < 0
    # Tables 8 / 10's "Filtering" rows repeat Tables 4 / 6: not compared twice
    cmp = r["comparison"]
    assert not cmp["quantity"].str.contains("Filtering:").any()
    assert cmp["quantity"].is_unique


def test_run_many_gives_each_run_alone():
    # three runs: two share their walks (same seed and phones, other windows), one has other phones; five walks
    # per phone with BATCH_WALKS 3 make two batches (2 walks one by one, then 3 in lockstep)
    runs = [{"seed": 0, "fast": True, "sweep_windows_s": (5.0,), "offset_fracs": (0.0,)},
            {"seed": 0, "fast": True, "sweep_windows_s": (2.0, 30.0), "offset_fracs": (0.25,)},
            {"seed": 1, "fast": True, "n_seeds": 4, "sweep_windows_s": (5.0,), "offset_fracs": (0.0,),
             "noise_factor": 2.0, "speed_mean_mps": 1.3}]
    from ilocalg.ins import pipeline

    old = pipeline.BATCH_WALKS
    try:
        pipeline.BATCH_WALKS = 3
        many = ins_online.run_many(runs)
    finally:
        pipeline.BATCH_WALKS = old
    for kw, got in zip(runs, many, strict=True):
        alone = ins_online.run(**kw)
        assert list(got) == list(alone)
        for name in alone:
            pd.testing.assert_frame_equal(got[name], alone[name], check_exact=True)


def test_walks_the_study_left_in_the_run_store_give_the_same_tables(monkeypatch):
    from ilocalg.experiments import study_ins_window
    from ilocalg.sim import ins_walk
    from ilocalg.workflow import runstore

    monkeypatch.delenv(runstore.RUN_STORE_ENV, raising=False)
    kw = {"seed": 0, "fast": True, "sweep_windows_s": (5.0,), "offset_fracs": (0.5,)}
    alone = ins_online.run(**kw)
    with runstore.run_store():
        study_ins_window.run(seed=0, fast=True, windows_s=(2.0,), offset_fracs=(0.0,))  # simulation seed 0
        # every walk of the run is read from the store: nothing is simulated
        monkeypatch.setattr(ins_walk, "simulate", lambda *a, **k: (_ for _ in ()).throw(AssertionError("simulated")))
        shared = ins_online.run(**kw)
    for name in alone:
        pd.testing.assert_frame_equal(shared[name], alone[name], check_exact=True)
