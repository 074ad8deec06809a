"""match_steps (one-to-one step matching), the per-recording diagnosis and its plot."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

from ilocalg.pdr.robust import match_steps
from ilocalg.pdr.step_evaluate import Prepared, diagnosis_window, step_diagnosis


def test_match_steps_counts_missed_and_extra():
    true = np.arange(10) * 0.5
    det = np.r_[true[:4] + 0.05, true[5:] - 0.05, 4.9]          # step 4 missed, one extra at 4.9 s
    tm, dm = match_steps(true, det, 0.2)
    assert (~tm).sum() == 1 and not tm[4]
    assert (~dm).sum() == 1 and not dm[-1]
    # one detection never serves two true steps 0.1 s apart
    tm, dm = match_steps([1.0, 1.1], [1.05], 0.2)
    assert tm.sum() == 1 and dm.all()


def test_match_steps_bad_input():
    with pytest.raises(ValueError, match="tol_s must be > 0"):
        match_steps([1.0], [1.0], 0.0)
    with pytest.raises(ValueError, match="sorted"):
        match_steps([2.0, 1.0], [1.0], 0.2)


def _walk(rate_hz=100.0, f_step_hz=1.8, dur_s=40.0):
    t = np.arange(0, dur_s, 1 / rate_hz)
    acc = np.column_stack([0.3 * np.sin(2 * np.pi * 0.9 * t), np.zeros_like(t),
                           9.81 + 2.0 * np.sin(2 * np.pi * f_step_hz * t)])
    steps = (0.25 + np.arange(int(dur_s * f_step_hz))) / f_step_hz      # the sine's maxima
    return Prepared("synthetic_InHand", {"position": "InHand", "phone": "x"}, steps.size, steps, t, acc, t, acc)


def test_diagnosis_of_a_clean_periodic_walk():
    p = _walk()
    d = step_diagnosis([p]).iloc[0]
    assert d["missed"] <= 1 and d["extra"] <= 1                      # an edge step at most
    assert d["accuracy"] >= 0.98
    assert np.isnan(d["hardware_steps"])                            # no counter: NaN, not 0
    w = diagnosis_window(p, 10.0, 5.0)
    assert w["t_s"].min() >= 10.0 and w["t_s"].max() <= 15.0
    assert w["true_matched"].all() and w["det_matched"].all()


def test_step_detections_plot():
    import matplotlib.pyplot as plt

    import ilocviz.pdr

    w = diagnosis_window(_walk(), 10.0, 5.0)
    ax = ilocviz.pdr.step_detections(w["t_s"], w["signal_mps2"], w["true_t_s"], w["det_t_s"],
                                     np.r_[False, w["true_matched"][1:]], w["det_matched"])
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "missed (1)" in labels and not any(s.startswith("extra") for s in labels)
    plt.close(ax.figure)


def test_diagnosis_reports_both_truths_and_the_counter_column():
    from types import SimpleNamespace

    p = _walk()
    n = p.true_steps
    # loaded under "keep": the published count holds 3 bounces; under "merge" they are already out of true_steps
    keep = SimpleNamespace(true_steps=n, n_heel_bounces=3, n_heel_bounces_merged=0, hardware_steps=None,
                           n_unpaired_landings=2)
    merge = SimpleNamespace(true_steps=n - 3, n_heel_bounces=3, n_heel_bounces_merged=3, hardware_steps=n + 2,
                            n_unpaired_landings=2)
    d = step_diagnosis([p], [keep]).iloc[0]
    assert d["true_steps_published"] == n and d["true_steps_bounces_merged"] == n - 3 and d["n_heel_bounces"] == 3
    assert d["accuracy_bounces_merged"] == pytest.approx(1 - abs(d["counted"] - (n - 3)) / (n - 3))
    assert d["accuracy_unpaired_added"] == pytest.approx(1 - abs(d["counted"] - (n - 1)) / (n - 1))
    p2 = Prepared(p.name, p.meta, n - 3, p.step_t_s, p.t_s, p.acc_mps2, p.t50_s, p.acc50_mps2)
    d2 = step_diagnosis([p2], [merge]).iloc[0]
    assert d2["true_steps_published"] == n and d2["true_steps_bounces_merged"] == n - 3
    assert d2["hardware_steps"] == n + 2
    assert np.isnan(step_diagnosis([p]).iloc[0]["true_steps_bounces_merged"])     # no recordings: NaN


def test_development_split_and_its_summary():
    import pandas as pd

    from ilocalg.pdr.step_evaluate import is_development, split_summary

    assert is_development("Pixel_Jamie_Hard_InHand_3") and not is_development("Pixel_Jamie_Hard_InHand_4")
    with pytest.raises(ValueError, match="repeat number"):
        is_development("Pixel_Jamie_Hard_InHand")
    rng = np.random.default_rng(1)
    names = [f"P_U_Hard_Pos{k // 2}_{k % 2 + 1}" for k in range(20)]
    acc = 1 - rng.uniform(0, 0.04, 20)
    diag = pd.DataFrame({"recording": names, "accuracy": acc, "accuracy_bounces_merged": np.minimum(acc + 0.01, 1),
                         "accuracy_unpaired_added": acc})
    s = split_summary(diag, seed=3)
    assert list(s["recordings"]) == ["development", "held out", "all"] * 3
    dev = s.iloc[0]
    assert dev["n"] == 10 and dev["mean_accuracy"] == pytest.approx(acc[::2].mean())
    assert dev["ci_low"] <= dev["mean_accuracy"] <= dev["ci_high"] and dev["min_accuracy"] == acc[::2].min()
    assert s.iloc[1]["n_below_98%"] == int((acc[1::2] < 0.98).sum())
    assert s.equals(split_summary(diag, seed=3))                       # same seed, same interval
