"""Attach time-stamped position fixes to the states of a step filter.

The step filter's states are the instants of detected steps (``state_t_s``, ``n + 1`` values: the
start, then one per step). A fix taken at time ``t`` is attached to the latest state at or before
``t`` (causal: the fix is used once the pedestrian has made the steps that precede it). Fixes
before the first state, and several fixes falling on the same state, are handled by explicit
policies and counted; nothing is dropped silently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["AlignedFixes", "fixes_at_states"]


@dataclass(frozen=True)
class AlignedFixes:
    """Fixes on the filter's state grid.

    Attributes
    ----------
    z_m : ndarray (n+1, 2)
        Fix per state, NaN rows where none.
    R_m2 : ndarray (n+1, 2, 2) or None
        Covariance per state (NaN where no fix), if covariances were given.
    state_index : ndarray of int (n_fixes,)
        State each input fix went to (-1: before the first state and left out).
    used : ndarray of bool (n_fixes,)
        Whether each input fix is the one kept on its state.
    n_before_start, n_superseded : int
        Fixes left out for preceding the first state / for a later fix on the same state.
    """

    z_m: np.ndarray
    R_m2: np.ndarray | None
    state_index: np.ndarray
    used: np.ndarray
    n_before_start: int
    n_superseded: int


def fixes_at_states(state_t_s, fix_t_s, fix_xy_m, fix_R_m2=None, before_start: str = "error",
                    same_state: str = "error") -> AlignedFixes:
    """Put each fix on the latest filter state at or before its time.

    Parameters
    ----------
    state_t_s : array_like, shape (n+1,)
        Times of the filter states (start, then each step), strictly increasing, seconds.
    fix_t_s : array_like, shape (m,)
        Fix times, non-decreasing, seconds.
    fix_xy_m : array_like, shape (m, 2)
    fix_R_m2 : array_like, shape (m, 2, 2), optional
    before_start : {"error", "drop"}
        Fixes earlier than ``state_t_s[0]``: raise, or leave out and count.
    same_state : {"error", "last"}
        Several fixes on one state: raise, or keep the latest one and count the others.

    Returns
    -------
    AlignedFixes
    """
    ts = np.asarray(state_t_s, dtype=np.float64)
    tf = np.asarray(fix_t_s, dtype=np.float64)
    xy = np.asarray(fix_xy_m, dtype=np.float64)
    if before_start not in ("error", "drop") or same_state not in ("error", "last"):
        raise ValueError("before_start must be 'error' or 'drop' and same_state 'error' or 'last'")
    if ts.ndim != 1 or ts.size < 1 or not np.isfinite(ts).all() or (np.diff(ts) <= 0).any():
        raise ValueError("state_t_s must be a non-empty, finite, strictly increasing 1-D array")
    if tf.ndim != 1 or not np.isfinite(tf).all() or (np.diff(tf) < 0).any():
        raise ValueError("fix_t_s must be a finite, non-decreasing 1-D array")
    if xy.shape != (tf.size, 2) or not np.isfinite(xy).all():
        raise ValueError(f"fix_xy_m must be finite with shape ({tf.size}, 2), got {xy.shape}")
    R = None
    if fix_R_m2 is not None:
        R = np.asarray(fix_R_m2, dtype=np.float64)
        if R.shape != (tf.size, 2, 2):
            raise ValueError(f"fix_R_m2 must have shape ({tf.size}, 2, 2), got {R.shape}")
    idx = np.searchsorted(ts, tf, side="right") - 1
    before = idx < 0
    if before.any() and before_start == "error":
        i = int(np.flatnonzero(before)[0])
        raise ValueError(f"fix {i} at t={float(tf[i])!r} s precedes the first state ({float(ts[0])!r} s); "
                         "pass before_start='drop' to leave such fixes out (counted)")
    used = ~before
    # several fixes on one state: the last one (in time order) wins
    nxt_same = np.zeros(tf.size, dtype=bool)
    nxt_same[:-1] = (idx[:-1] == idx[1:]) & used[:-1]
    if nxt_same.any() and same_state == "error":
        i = int(np.flatnonzero(nxt_same)[0])
        raise ValueError(f"fixes {i} and {i + 1} both fall on state {int(idx[i])}; pass same_state='last' to keep "
                         "the later one (counted)")
    used &= ~nxt_same
    n1 = ts.size
    z = np.full((n1, 2), np.nan)
    z[idx[used]] = xy[used]
    Rs = None
    if R is not None:
        Rs = np.full((n1, 2, 2), np.nan)
        Rs[idx[used]] = R[used]
    return AlignedFixes(z_m=z, R_m2=Rs, state_index=np.where(before, -1, idx), used=used,
                        n_before_start=int(before.sum()), n_superseded=int(nxt_same.sum()))
