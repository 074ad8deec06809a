"""Hartmann et al.'s EKF on one tracked sequence: initialisation, Table 2's deviations, bias settling.

A sequence holds the IMU log (``t_s``, ``gyr_b_radps``, ``acc_b_mps2``), the video tracker's fixes
(``t_vt_s``, ``z_vt`` = yaw rad, x, y, z m; ``params["vt_sd"]`` its noise) and, for scoring, the truth
(``pos_v_m`` and the constant biases ``bias_true`` = gyro rad/s, accelerometer m/s^2), as
:class:`ilocalg.sim.hartmann.HartmannSequence` gives them.

The deviation at each tracker epoch is taken - an interpretation; the survey does not say how - as that of
the EKF's prediction just before it uses that fix (what the IMU alone carried from the previous fix: after
an outage, the coasting error); the deviation after the correction and the prediction's error against the
truth are given beside it.

References
----------
Hartmann, B., Link, N., Trommer, G. F. (2010). Indoor 3D position estimation using low-cost inertial
sensors and marker-based video-tracking. IEEE/ION PLANS, 319-326 (as reported in Yeh & Huang's survey,
sec. 5, Table 2, Figs 11-12).
"""

from __future__ import annotations

import numpy as np

from ilocalg.ins.hartmann import run_hartmann_many
from ilocalg.ins.mechanisation import coarse_level

__all__ = ["run_sequence", "run_sequences", "settling_time_s", "table2_row"]


def run_sequence(seq, level_s: float = 1.0, vt_sd=None):
    """Level during the initial rest, take yaw and position from the first tracker fix and run the EKF
    (``vt_sd``: the tracker noise the filter assumes; default the sequence's)."""
    return run_sequences([seq], level_s, [vt_sd])[0]


def run_sequences(seqs, level_s: float = 1.0, vt_sd=None, max_batch: int = 32):
    """:func:`run_sequence` on each sequence of ``seqs`` (``vt_sd``: None, or one entry per sequence, None for the
    sequence's own noise). Sequences on one IMU clock, or on the first epochs of a longer one (the simulator's
    clocks of any duration at one rate), run in lockstep, at most ``max_batch`` at a time, longest first
    (:func:`ilocalg.ins.hartmann.run_hartmann_many`); each result is the one :func:`run_sequence` gives."""
    seqs = list(seqs)
    vt_sd = [None] * len(seqs) if vt_sd is None else list(vt_sd)
    if len(vt_sd) != len(seqs):
        raise ValueError(f"vt_sd holds {len(vt_sd)} entries for {len(seqs)} sequences")
    clocks = [np.asarray(seq.t_s, dtype=float) for seq in seqs]
    groups: list[list[int]] = []  # each group's first sequence has its longest clock
    for i in sorted(range(len(seqs)), key=lambda i: -clocks[i].size):
        t = clocks[i]
        g = next((g for g in groups if np.array_equal(clocks[g[0]][:t.size], t)), None)
        if g is None:
            groups.append([i])
        else:
            g.append(i)
    out = [None] * len(seqs)
    for idx in groups:
        for lo in range(0, len(idx), max_batch):
            part = idx[lo:lo + max_batch]
            starts = [_start(seqs[i], level_s) for i in part]
            res = run_hartmann_many([seqs[i].t_s for i in part], [seqs[i].gyr_b_radps for i in part],
                                    [seqs[i].acc_b_mps2 for i in part], [seqs[i].t_vt_s for i in part],
                                    [seqs[i].z_vt for i in part], [x0 for x0, _ in starts], [P0 for _, P0 in starts],
                                    vt_sd=[seqs[i].params["vt_sd"] if vt_sd[i] is None else vt_sd[i] for i in part])
            for i, r in zip(part, res, strict=True):
                out[i] = r
    return out


def _start(seq, level_s: float):
    """``x0, P0``: roll and pitch levelled over the first ``level_s``, yaw and position from the first fix."""
    first = seq.t_s < seq.t_s[0] + level_s
    roll, pitch = coarse_level(seq.acc_b_mps2[first])
    x0 = np.zeros(15)
    x0[0:3] = roll, pitch, seq.z_vt[0, 0]
    x0[3:6] = seq.z_vt[0, 1:4]
    P0 = np.diag(np.square(np.concatenate([np.deg2rad([3.0, 3.0, 2.0]), np.full(3, 0.01), np.full(3, 0.05),
                                           np.full(3, np.deg2rad(0.5)), np.full(3, 0.2)])))
    return x0, P0


def settling_time_s(t, est, true, tol) -> float:
    """First time after which every component of ``est`` stays within ``tol`` of ``true`` (NaN if never)."""
    bad = np.any(np.abs(est - true) > tol, axis=1)
    if not bad.any():
        return float(t[0])
    last_bad = np.flatnonzero(bad)[-1]
    return float(t[last_bad + 1]) if last_bad + 1 < t.size else np.nan


def table2_row(label, seq, res) -> dict:
    """Table 2's columns for one sequence (mean and maximal deviation of the prediction to the tracker per axis,
    tracker rate, longest outage, outages over 1 s) with prediction-minus-truth, after-correction deviation and
    EKF-minus-truth beside them."""
    dev_prior = np.abs(res.prior_at_vt[:, 3:6] - seq.z_vt[:, 1:4])[1:]
    err_prior = np.abs(res.prior_at_vt[:, 3:6] - seq.pos_v_m[res.vt_idx])[1:]
    dev_post = np.abs(res.x[res.vt_idx, 3:6] - seq.z_vt[:, 1:4])[1:]
    err_truth = np.abs(res.x[:, 3:6] - seq.pos_v_m)
    gaps = np.diff(seq.t_vt_s)
    return {"sequence": label,
            **{f"mean_dev_{a}_m": dev_prior[:, j].mean() for j, a in enumerate("xyz")},
            **{f"max_dev_{a}_m": dev_prior[:, j].max() for j, a in enumerate("xyz")},
            "vt_rate_hz": seq.t_vt_s.size / (seq.t_s[-1] - seq.t_s[0]),
            "outage_max_s": gaps.max(), "outages_over_1s": float((gaps > 1.0).sum()),
            **{f"mean_pred_err_truth_{a}_m": err_prior[:, j].mean() for j, a in enumerate("xyz")},
            **{f"max_pred_err_truth_{a}_m": err_prior[:, j].max() for j, a in enumerate("xyz")},
            **{f"mean_dev_post_{a}_m": dev_post[:, j].mean() for j, a in enumerate("xyz")},
            **{f"mean_err_truth_{a}_m": err_truth[:, j].mean() for j, a in enumerate("xyz")},
            "psd_repairs": res.n_psd_repairs}
