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
