"""Study of the step KF vs Wi-Fi noise and fix rate (ilocalg.experiments.study_kf_noise)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import study_kf_noise
from ilocalg.fusion import PAPER_TABLE5_SIGMA_RF_VAR_M2
from ilocalg.workflow import sweep as sw


def _errors(seed=0, **p):
    df = study_kf_noise.run(seed=seed, fast=True, **p)["sweep_kf_noise"]
    e = df[df["quantity"] == "mean error"]
    return dict(zip(e["item"].str.removeprefix("method="), e["value"], strict=True))


def test_same_seed_same_table():
    a = study_kf_noise.run(seed=5, fast=True, noise_scale=2.0, fix_every=4)["sweep_kf_noise"]
    b = study_kf_noise.run(seed=5, fast=True, noise_scale=2.0, fix_every=4)["sweep_kf_noise"]
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert set(a.loc[a["quantity"] == "mean error", "item"]) == {f"method={m}" for m in study_kf_noise.METHODS}
    assert study_kf_noise.SIGMA_RF_BASE_M == pytest.approx(np.sqrt(np.median(PAPER_TABLE5_SIGMA_RF_VAR_M2)))


def test_filter_beats_fixes_and_smoother_beats_filter():
    for seed in (0, 1):
        e = _errors(seed)
        assert e["step KF"] < 0.6 * e["Wi-Fi fixes"]
        assert e["RTS smoother"] < e["step KF"]


def test_error_grows_with_noise_and_with_fewer_fixes():
    lo, hi = _errors(noise_scale=0.5), _errors(noise_scale=3.0)
    assert hi["step KF"] > lo["step KF"] and hi["Wi-Fi fixes"] > 4 * lo["Wi-Fi fixes"]
    assert hi["dead reckoning"] == lo["dead reckoning"]  # same walks (common random numbers), no fixes used
    dense, sparse = _errors(fix_every=1), _errors(fix_every=20)
    assert dense["step KF"] < sparse["step KF"]
    assert dense["RTS smoother"] < sparse["RTS smoother"]


def test_bad_parameters_are_clear_errors():
    with pytest.raises(ValueError, match="noise_scale"):
        study_kf_noise.run(noise_scale=0.0)
    with pytest.raises(ValueError, match="fix_every"):
        study_kf_noise.run(fix_every=0)


def test_local_cluster_sweep_equals_serial_bit_for_bit():
    tasks = study_kf_noise.tasks(range(2), fast=True)[:4]
    serial = sw.sweep(tasks, workers=0, cache_dir=None, progress=False)
    dask2 = sw.sweep(tasks, workers=2, cache_dir=None, progress=False)
    assert not serial.failures and not dask2.failures

    def srt(df):
        return df.sort_values(["params", "seed", "item", "quantity"]).reset_index(drop=True)

    pd.testing.assert_frame_equal(srt(serial.results), srt(dask2.results), check_exact=True)
