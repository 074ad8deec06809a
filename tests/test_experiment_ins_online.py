import pandas as pd

from ilocalg.experiments import ins_online


def test_online_experiment_accepts_integer_window_lengths():
    a = ins_online.run(seed=0, fast=True, sweep_windows_s=(5, 10))
    b = ins_online.run(seed=0, fast=True, sweep_windows_s=(5.0, 10.0))
    pd.testing.assert_frame_equal(a["window_sweep"], b["window_sweep"])
