"""Tests of ilocalg.ins.hartmann_eval (Hartmann et al.'s EKF on a tracked sequence: Table 2's deviations)."""

import numpy as np
import pytest

from ilocalg.ins.hartmann_eval import run_sequence, settling_time_s, table2_row
from ilocalg.sim import hartmann as sim


def test_settling_time_is_the_last_excursion_plus_one_sample():
    t = np.arange(10.0)
    est = np.zeros((10, 2))
    est[[2, 6], 1] = 1.0
    assert settling_time_s(t, est, np.zeros(2), 0.5) == 7.0
    assert settling_time_s(t, np.zeros((10, 2)), np.zeros(2), 0.5) == 0.0
    est[-1, 0] = 1.0
    assert np.isnan(settling_time_s(t, est, np.zeros(2), 0.5))


def test_table2_row_on_a_short_sequence():
    seq = sim.simulate(20.0, seed=3)
    row = table2_row("1", seq, run_sequence(seq))
    assert row["sequence"] == "1" and row["outages_over_1s"] >= 0
    # the prediction before a fix deviates more from it than the corrected estimate does
    assert row["mean_dev_x_m"] > row["mean_dev_post_x_m"]
    assert row["vt_rate_hz"] == pytest.approx(seq.t_vt_s.size / (seq.t_s[-1] - seq.t_s[0]))


def test_sequences_in_lockstep_give_each_sequence_its_own_result():
    from ilocalg.ins.hartmann_eval import run_sequences

    seqs = [sim.simulate(8.0, seed=s) for s in (0, 1)] + [sim.simulate(6.0, seed=2)]  # two clocks
    sd = tuple(2.0 * np.asarray(sim.VT_SD_DEFAULT))
    got = run_sequences(seqs, vt_sd=[None, sd, None], max_batch=1)
    got2 = run_sequences(seqs, vt_sd=[None, sd, None])
    for q, v, a, b in zip(seqs, (None, sd, None), got, got2, strict=True):
        want = run_sequence(q, vt_sd=v)
        for r in (a, b):
            assert np.array_equal(r.x, want.x) and np.array_equal(r.sd, want.sd)
            assert np.array_equal(r.prior_at_vt, want.prior_at_vt)
    with pytest.raises(ValueError, match="vt_sd holds 1 entries for 3 sequences"):
        run_sequences(seqs, vt_sd=[None])
