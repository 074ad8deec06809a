"""decimate_recording / rate_robustness: the robust detector's check at a lower sampling rate."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest

from ilocalg.io.oxford import OxfordRecording
from ilocalg.io.schema import ACC_COLS
from ilocalg.pdr.step_evaluate import decimate_recording, rate_robustness


def _recording(name="Phone_User_Hard_InHand_1", rate_hz=400.0, dur_s=40.0, f_step_hz=1.8, tone_hz=None):
    """A periodic walk logged at ``rate_hz``; ``tone_hz`` adds a strong vibration there (aliases when decimated)."""
    t = np.arange(0, dur_s, 1 / rate_hz)
    z = 9.81 + 2.0 * np.sin(2 * np.pi * f_step_hz * t)
    if tone_hz is not None:
        z = z + 3.0 * np.sin(2 * np.pi * tone_hz * t)
    acc = np.column_stack([0.3 * np.sin(2 * np.pi * 0.9 * t), np.zeros_like(t), z])
    steps = (0.25 + np.arange(int(dur_s * f_step_hz))) / f_step_hz
    imu = pd.DataFrame(acc, index=pd.Index(t, name="t_s"), columns=list(ACC_COLS))
    return OxfordRecording(name=name, imu=imu, step_t_s=steps, true_steps=steps.size, meta={})


def test_decimation_keeps_the_truth_and_every_kth_time():
    rec = _recording()
    for aa in (False, True):
        d = decimate_recording(rec, 4, anti_alias=aa)
        assert d.true_steps == rec.true_steps and d.step_t_s is rec.step_t_s
        np.testing.assert_array_equal(d.imu.index.to_numpy(), rec.imu.index.to_numpy()[::4][:len(d.imu)])
        assert abs(len(d.imu) - len(rec.imu) / 4) <= 1
        assert list(d.imu.columns) == list(ACC_COLS)
    assert decimate_recording(rec, 1) is rec
    for bad in (0, 2.5, -1):
        with pytest.raises(ValueError, match="whole number"):
            decimate_recording(rec, bad)


def test_anti_alias_filter_removes_what_plain_decimation_folds_down():
    # a 99 Hz vibration logged at 400 Hz: kept every 4th sample (100 Hz) it folds to 1 Hz, in the step band;
    # after the anti-alias low-pass (cut-off 40 Hz) it is gone
    rec = _recording(tone_hz=99.0)
    clean = _recording()
    z = list(ACC_COLS)[2]
    plain = decimate_recording(rec, 4, anti_alias=False).imu[z].to_numpy()
    aa = decimate_recording(rec, 4, anti_alias=True).imu[z].to_numpy()
    ref = clean.imu[z].to_numpy()[::4]
    n = min(plain.size, aa.size, ref.size)
    mid = slice(n // 10, n - n // 10)                      # away from the filter's edges
    assert np.std((plain - ref[:plain.size])[mid]) > 1.5
    assert np.std((aa[:n] - ref[:n])[mid]) < 0.1


def test_rate_robustness_table():
    recs = [_recording("Phone_User_Hard_InHand_1", 400.0), _recording("Phone_User_Hard_InHand_2", 100.0),
            _recording("Phone_User_Hard_InHand_3", 210.0)]
    t = rate_robustness(recs)
    assert list(t["factor"]) == [4, 1, 2]
    assert t["development"].tolist() == [True, False, True]
    np.testing.assert_allclose(t["rate_decimated_hz"], [100.0, 100.0, 105.0], rtol=1e-6)
    row = t.iloc[1]                                        # already at 100 Hz: the three logs are one
    assert row["counted_as_logged"] == row["counted_decimated"] == row["counted_decimated_anti_alias"]
    for c in ("as_logged", "decimated", "decimated_anti_alias"):
        assert (t[f"accuracy_{c}"] >= 0.97).all()          # a clean periodic walk at any of these rates
        np.testing.assert_allclose(t[f"accuracy_{c}"], 1 - np.abs(t[f"counted_{c}"] - t["true_steps"])
                                   / t["true_steps"])


def test_rate_summary_and_headline():
    from ilocalg.experiments.pdr_real_steps import rate_headline, rate_summary

    recs = [_recording(f"Phone_User_Hard_InHand_{k}", rate, tone_hz=tone)
            for k, (rate, tone) in enumerate([(400.0, 99.0), (400.0, None), (200.0, None), (400.0, 99.0)], 1)]
    rates = rate_robustness(recs)
    s = rate_summary(rates)
    assert set(s["log"]) == {"as logged", "decimated to ~100 Hz", "decimated to ~100 Hz, anti-aliased"}
    assert set(s["recordings"]) == {"development", "held out", "all"}
    base = s[s["log"] == "as logged"]
    assert (base["n_changed"] == 0).all()
    allrow = s[(s["log"] == "decimated to ~100 Hz") & (s["recordings"] == "all")].iloc[0]
    assert allrow["n_changed"] == int((rates["counted_decimated"] != rates["counted_as_logged"]).sum())
    line = rate_headline({"rate_robustness": rates, "rate_robustness_summary": s})
    assert line.startswith("as logged (200-400 Hz)") and "of 4 counts changed" in line


def test_paired_accuracy_plot():
    import matplotlib.pyplot as plt

    import ilocviz.pdr

    ax = ilocviz.pdr.paired_accuracy([0.99, 0.97], {"a": [0.98, 0.97], "b": [0.99, 0.96]}, goal=0.98)
    assert "[%]" in ax.get_xlabel() and "[%]" in ax.get_ylabel()
    assert [t.get_text() for t in ax.get_legend().get_texts()][:2] == ["a", "b"]
    assert ax.get_xlim()[0] < 96.0
    plt.close(ax.figure)
