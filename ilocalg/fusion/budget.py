"""Error budget of a fused track: rerun a filter with one error source replaced by the truth at a time.

A fused position error is made of several errors at once: the Wi-Fi fix's own error, the scan's lag
(a fix describes where the walker was while the scan read the APs, but enters the filter only after
the scan ends), missed or extra steps, wrong step lengths and wrong headings. :func:`error_budget`
reruns the same filter on the same walk with one of these replaced by the truth, and reports how much
of the fused mean error disappears: the share of the error that source carries. Replacing every source
at once leaves the filter's own error (time discretisation). Shares need not add up to 1: two
sources can interact (a heading error matters more when no fix corrects it), and a share can be
negative when two errors partly cancel (a start fix ahead of the walker offsets missed steps).

Replacements (:func:`with_truth`)
--------------------------------
``"Wi-Fi fix error"``
    Every fix (and the start fix) becomes the true position at the time it describes
    (``fix_ref_t_s``: the mean time at which its RSSI values were read). The lag stays.
``"scan lag"``
    Every fix enters the filter at the time it describes (``fix_ref_t_s``) instead of when its scan
    ends (``fix_t_s``). The fix's own error stays.
``"step detection"``
    The states are the true steps (at each true step's end); each gets the estimated length of the
    nearest detected step and the estimated heading at its mid-time. The per-step length and heading
    errors stay, the missed and extra steps go.
``"step length"``
    Each step gets the true length of the true step it falls in (the nearest one by mid-time).
``"heading"``
    Each step gets the true walking direction at its time.

Data types: times in seconds on the walk's clock, positions in metres in the floor frame.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU. Ch. 5 (the
fused PTS + Wi-Fi track whose errors are budgeted here).
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications. Sec. 3.4.4, 4.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = ["SOURCES", "FusionInputs", "with_truth", "track_at", "walk_errors", "error_budget", "steady_state_weight",
           "input_diagnostics", "inputs_sentence"]

#: The error sources a budget replaces by the truth, one at a time.
SOURCES = ("Wi-Fi fix error", "scan lag", "step detection", "step length", "heading")
_BASE = "none (as simulated)"
_ALL = "all of them"


@dataclass(frozen=True)
class FusionInputs:
    """What a fusion filter reads on one walk, and the truth it is scored against.

    Attributes
    ----------
    t0_s : float
        Time of the start state.
    start_xy_m : (2,) the start position the filter is given (a Wi-Fi fix in i-Loc and Luo);
        ``start_ref_t_s``: the time it describes.
    step_t_s, step_m, theta_rad : (n,) detected steps: time, length (m), heading (rad, from the x axis).
    heading_t_s, heading_rad : (k,) the estimated heading series (used when detection is replaced).
    fix_t_s : (m,) when each fix becomes available (its scan's end), non-decreasing.
    fix_ref_t_s : (m,) the time each fix describes (mean RSSI read time), <= ``fix_t_s``.
    fix_xy_m : (m, 2) the fixes; a NaN row is a scan without a fix.
    true_step_t_s, true_step_mid_t_s, true_step_m : (p,) true steps: end time, mid time, length.
    truth_t_s, truth_xy_m, truth_theta_rad : the true track (increasing times) and walking direction.
    eval_t_s : (q,) the times at which the track is scored.
    eval_xy_m : (q, 2), optional: the true positions at ``eval_t_s`` when they are known exactly (e.g.
        marked test points); default the true track there.
    """

    t0_s: float
    start_xy_m: np.ndarray
    start_ref_t_s: float
    step_t_s: np.ndarray
    step_m: np.ndarray
    theta_rad: np.ndarray
    heading_t_s: np.ndarray
    heading_rad: np.ndarray
    fix_t_s: np.ndarray
    fix_ref_t_s: np.ndarray
    fix_xy_m: np.ndarray
    true_step_t_s: np.ndarray
    true_step_mid_t_s: np.ndarray
    true_step_m: np.ndarray
    truth_t_s: np.ndarray
    truth_xy_m: np.ndarray
    truth_theta_rad: np.ndarray
    eval_t_s: np.ndarray
    eval_xy_m: np.ndarray | None = None

    def __post_init__(self):
        n = np.asarray(self.step_t_s).size
        for name in ("step_m", "theta_rad"):
            if np.asarray(getattr(self, name)).shape != (n,):
                raise ValueError(f"FusionInputs.{name} must have shape ({n},) like step_t_s")
        m = np.asarray(self.fix_t_s).size
        if np.asarray(self.fix_ref_t_s).shape != (m,) or np.asarray(self.fix_xy_m).shape != (m, 2):
            raise ValueError(f"FusionInputs: fix_ref_t_s must be ({m},) and fix_xy_m ({m}, 2) like fix_t_s")
        if np.any(np.asarray(self.fix_ref_t_s) > np.asarray(self.fix_t_s) + 1e-9):
            raise ValueError("FusionInputs: a fix cannot describe a time after it is available (fix_ref_t_s > fix_t_s)")
        tt = np.asarray(self.truth_t_s)
        if tt.ndim != 1 or tt.size < 2 or np.any(np.diff(tt) <= 0):
            raise ValueError("FusionInputs.truth_t_s must be strictly increasing with >= 2 samples")

    def truth_at(self, t_s) -> np.ndarray:
        """True position (n, 2) at times ``t_s`` (linear in time, held at the ends)."""
        t = np.asarray(t_s, dtype=np.float64)
        return np.column_stack([np.interp(t, self.truth_t_s, self.truth_xy_m[:, 0]),
                                np.interp(t, self.truth_t_s, self.truth_xy_m[:, 1])])

    def theta_at(self, t_s) -> np.ndarray:
        """True walking direction (rad) at times ``t_s``."""
        return np.interp(np.asarray(t_s, dtype=np.float64), self.truth_t_s, np.unwrap(self.truth_theta_rad))

    @property
    def state_t_s(self) -> np.ndarray:
        """Times of the filter states: the start, then each step."""
        return np.concatenate([[self.t0_s], self.step_t_s])

    @classmethod
    def from_walk(cls, walk, *, state_t_s, step_m, theta_rad, heading_rad, start_xy_m, start_ref_t_s, fixes,
                  eval_t_s, eval_xy_m=None) -> FusionInputs:
        """A filter's inputs on one recorded walk, with the walk's truth.

        Parameters
        ----------
        walk : a walk shaped like a recording (:mod:`ilocalg.sim.iloc_scenario`): ``imu`` indexed by time,
            ``steps`` (``t_strike_s``, ``duration_s``, ``t_mid_s``, ``length_m``), ``truth_t_s``,
            ``truth_xy_m`` and ``truth["theta_rad"]``.
        state_t_s : (n + 1,) the start state's time, then each detected step's.
        step_m, theta_rad : (n,) the detected steps' lengths and headings.
        heading_rad : the estimated heading at every IMU sample of ``walk.imu``.
        start_xy_m, start_ref_t_s : the start position and the time it describes.
        fixes : DataFrame with ``t_ready_s``, ``t_ref_s``, ``fix_x_m``, ``fix_y_m`` (the fixes the filter reads).
        eval_t_s, eval_xy_m : the scoring times and, when known exactly, the true positions there.
        """
        st = walk.steps
        return cls(t0_s=float(state_t_s[0]), start_xy_m=start_xy_m, start_ref_t_s=float(start_ref_t_s),
                   step_t_s=state_t_s[1:], step_m=step_m, theta_rad=theta_rad,
                   heading_t_s=walk.imu.index.to_numpy(), heading_rad=heading_rad,
                   fix_t_s=fixes["t_ready_s"].to_numpy(), fix_ref_t_s=fixes["t_ref_s"].to_numpy(),
                   fix_xy_m=fixes[["fix_x_m", "fix_y_m"]].to_numpy(),
                   true_step_t_s=(st["t_strike_s"] + st["duration_s"]).to_numpy(),
                   true_step_mid_t_s=st["t_mid_s"].to_numpy(), true_step_m=st["length_m"].to_numpy(),
                   truth_t_s=walk.truth_t_s, truth_xy_m=walk.truth_xy_m,
                   truth_theta_rad=walk.truth["theta_rad"].to_numpy(), eval_t_s=eval_t_s, eval_xy_m=eval_xy_m)


def with_truth(inp: FusionInputs, sources) -> FusionInputs:
    """``inp`` with each error source of ``sources`` (names from :data:`SOURCES`) replaced by the truth."""
    src = set(sources)
    bad = src - set(SOURCES)
    if bad:
        raise ValueError(f"unknown error source(s) {sorted(bad)}; expected some of {SOURCES}")
    rep = {}
    if "Wi-Fi fix error" in src:
        xy = inp.truth_at(inp.fix_ref_t_s)
        rep["fix_xy_m"] = np.where(np.isfinite(inp.fix_xy_m).all(axis=1)[:, None], xy, np.nan)
        rep["start_xy_m"] = inp.truth_at([inp.start_ref_t_s])[0]
    if "scan lag" in src:
        o = np.argsort(inp.fix_ref_t_s, kind="stable")
        rep["fix_t_s"] = np.asarray(inp.fix_ref_t_s)[o]
        rep["fix_ref_t_s"] = np.asarray(inp.fix_ref_t_s)[o]
        rep["fix_xy_m"] = np.asarray(rep.get("fix_xy_m", inp.fix_xy_m))[o]
    st, d, th = np.asarray(inp.step_t_s), np.asarray(inp.step_m), np.asarray(inp.theta_rad)
    if "step detection" in src:
        t_true = np.asarray(inp.true_step_t_s)
        keep = t_true > inp.t0_s
        t_true, t_mid = t_true[keep], np.asarray(inp.true_step_mid_t_s)[keep]
        if st.size:
            near = np.abs(st[None, :] - t_mid[:, None]).argmin(axis=1)
            d = d[near]
        else:
            d = np.zeros(t_true.size)
        th = np.interp(t_mid, inp.heading_t_s, np.unwrap(inp.heading_rad))
        st = t_true
    if "step length" in src:
        mids = np.asarray(inp.true_step_mid_t_s)
        ends = np.asarray(inp.true_step_t_s)
        # the true step a (detected) step falls in: the first true step ending at or after it
        j = np.clip(np.searchsorted(ends, st - 1e-9), 0, ends.size - 1)
        if "step detection" not in src:
            j = np.where(np.abs(mids[j] - st) <= np.abs(mids[np.maximum(j - 1, 0)] - st), j, np.maximum(j - 1, 0))
        d = np.asarray(inp.true_step_m)[j]
    if "heading" in src:
        th = inp.theta_at(st)
    rep.update(step_t_s=st, step_m=d, theta_rad=th)
    return dataclasses.replace(inp, **rep)


def track_at(state_t_s, xy_m, t_s) -> np.ndarray:
    """Each time's estimate: the latest state at or before it (the start state before the first step)."""
    ts = np.asarray(state_t_s, dtype=np.float64)
    k = np.clip(np.searchsorted(ts, np.asarray(t_s, dtype=np.float64), side="right") - 1, 0, ts.size - 1)
    return np.asarray(xy_m)[k]


def walk_errors(inp: FusionInputs, method: Callable[[FusionInputs], np.ndarray]) -> np.ndarray:
    """Position errors (m) at ``inp.eval_t_s`` of ``method(inp)`` (a track over ``inp.state_t_s``)."""
    xy = np.asarray(method(inp), dtype=np.float64)
    if xy.shape != (inp.step_t_s.size + 1, 2):
        raise ValueError(f"a method must return one position per state ({inp.step_t_s.size + 1}, 2), got {xy.shape}")
    est = track_at(inp.state_t_s, xy, inp.eval_t_s)
    true = inp.truth_at(inp.eval_t_s) if inp.eval_xy_m is None else np.asarray(inp.eval_xy_m, dtype=np.float64)
    return np.hypot(*(est - true).T)


def error_budget(walks, methods: dict, sources=SOURCES) -> pd.DataFrame:
    """Mean fused error with each error source replaced by the truth, one at a time.

    Parameters
    ----------
    walks : list of FusionInputs
    methods : dict name -> callable(FusionInputs) -> (n+1, 2) track over the states
    sources : iterable of names from :data:`SOURCES`

    Returns
    -------
    DataFrame
        One row per method and replacement (``"none (as simulated)"``, each source, ``"all of them"``):
        ``method``, ``replaced_by_truth``, ``mean_error_m`` (over every walk's evaluation times),
        ``error_removed_m`` (baseline minus this), ``share_of_error`` (that over the baseline mean).
    """
    walks = list(walks)
    if not walks:
        raise ValueError("error_budget: no walks given")
    sources = tuple(sources)
    rows = []
    for name, fn in methods.items():
        cases = [(_BASE, ())] + [(s, (s,)) for s in sources] + [(_ALL, sources)]
        base = None
        for label, rep in cases:
            e = np.concatenate([walk_errors(with_truth(w, rep), fn) for w in walks])
            mean = float(np.nanmean(e))
            base = mean if base is None else base
            rows.append({"method": name, "replaced_by_truth": label, "mean_error_m": mean,
                         "error_removed_m": base - mean,
                         "share_of_error": (base - mean) / base if base > 0 else np.nan})
    return pd.DataFrame(rows)


def input_diagnostics(walks) -> pd.DataFrame:
    """What the budget's inputs look like against their truth, pooled over walks (a budget's "why").

    Rows (``quantity``, ``value``, ``unit``): the fixes' mean along-track offset from the position they
    describe (``fix_ref_t_s``) and from the position when they enter (``fix_t_s``; positive = ahead of
    the walker), their mean age at entry, the detected / true step count and the PDR distance / true
    distance, and the rms heading error of the detected steps.
    """
    walks = list(walks)
    if not walks:
        raise ValueError("input_diagnostics: no walks given")
    ref, ent, age, nd, nt, dd, dt, he = [], [], [], 0, 0, 0.0, 0.0, []
    for w in walks:
        ok = np.isfinite(w.fix_xy_m).all(axis=1)
        for out, t in ((ref, w.fix_ref_t_s[ok]), (ent, w.fix_t_s[ok])):
            th = w.theta_at(t)
            out.append(((w.fix_xy_m[ok] - w.truth_at(t)) * np.column_stack([np.cos(th), np.sin(th)])).sum(axis=1))
        age.append(w.fix_t_s[ok] - w.fix_ref_t_s[ok])
        nd, nt = nd + w.step_t_s.size, nt + np.sum(np.asarray(w.true_step_t_s) > w.t0_s)
        dd, dt = dd + float(np.sum(w.step_m)), dt + float(np.sum(w.true_step_m))
        he.append(np.angle(np.exp(1j * (np.asarray(w.theta_rad) - w.theta_at(w.step_t_s)))))
    rows = [("fix along-track offset from the position it describes", np.mean(np.concatenate(ref)), "m"),
            ("fix along-track offset from the position when it enters", np.mean(np.concatenate(ent)), "m"),
            ("fix age when it enters", np.mean(np.concatenate(age)), "s"),
            ("detected / true steps", nd / nt if nt else np.nan, "-"),
            ("PDR distance / true distance", dd / dt if dt else np.nan, "-"),
            ("heading error of the detected steps, rms", float(np.sqrt(np.mean(np.concatenate(he) ** 2))), "rad")]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def steady_state_weight(q_var_m2: float, r_var_m2: float) -> float:
    """The steady-state gain of a scalar random walk observed once per interval: an inverse-variance weight.

    Between two fixes the dead-reckoned position gains a variance ``q_var_m2`` (per axis); a fix has
    variance ``r_var_m2``. At steady state the prior variance is ``P = (q + sqrt(q^2 + 4 q r)) / 2`` and
    the fix gets the weight ``w = P / (P + r)``: the inverse-variance weighting of the two estimates.

    References
    ----------
    Kalman, R. E. (1960). A new approach to linear filtering and prediction problems. (The scalar
    steady-state Riccati solution.)
    """
    q, r = float(q_var_m2), float(r_var_m2)
    if not (np.isfinite(q) and np.isfinite(r) and q >= 0 and r > 0):
        raise ValueError(f"need q_var_m2 >= 0 and r_var_m2 > 0, got {q_var_m2!r}, {r_var_m2!r}")
    p = 0.5 * (q + np.sqrt(q * q + 4.0 * q * r))
    return float(p / (p + r))


def inputs_sentence(diagnostics: pd.DataFrame) -> str:
    """One sentence on a budget's inputs against their truth (fix offsets, fix age, PDR distance, detection,
    heading), from the table of :func:`input_diagnostics`."""
    d = diagnostics.set_index("quantity")["value"]
    a = d["fix along-track offset from the position it describes"]
    b = d["fix along-track offset from the position when it enters"]
    return (f"Fixes sit {a:+.2f} m along the walk from where their RSSI was read (+ = ahead) and {b:+.2f} m from "
            f"the walker when they enter, {d['fix age when it enters']:.2f} s later: "
            + ("the lag and that offset partly cancel, so removing the lag alone can raise the error. "
               if abs(b) < abs(a) else "")
            + f"PDR distance / true distance {d['PDR distance / true distance']:.2f}, detected / true steps "
            f"{d['detected / true steps']:.2f}, heading rms {d['heading error of the detected steps, rms']:.2f} rad.")
