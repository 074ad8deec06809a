"""Luo et al. (2017) PDR on a sensor log: peak-window steps, eq. (4) lengths, WDM headings.

The pedestrian-track half of Luo et al.'s positioning (sec. 3.4): steps by the sliding-window peak
detector with its time window (sec. 3.4.2, :func:`ilocalg.pdr.peak_window.detect_steps_peak_window`),
lengths by eq. (4) with a fitted ``k`` (:func:`ilocalg.pdr.step_length.luo_steps`), headings by the
accelerometer + magnetometer (sec. 3.4.3, WDM: :func:`ilocalg.pdr.heading.log_headings_rad`).

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications. Sec. 3.4, eq. (4)-(6).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.pdr.heading import log_headings_rad
from ilocalg.pdr.peak_window import detect_steps_peak_window
from ilocalg.pdr.signals import acc_from_log
from ilocalg.pdr.step_length import fit_luo_k, luo_lengths

__all__ = ["luo_pdr", "luo_training_spread", "eq4_vs_constant_error", "LuoLogs"]


class LuoLogs:
    """What Luo et al.'s PDR reads of a sensor log, computed once per log however many calls ask: its
    accelerometer array, its peak-window steps per detector (eq. (4) lengths are added per ``k`` to a copy) and its
    WDM headings per rest time.

    Pass one to :func:`luo_pdr`, :func:`luo_training_spread`, :func:`eq4_vs_constant_error` (``logs=``) when
    they run on the same logs with several ``k`` or detectors: the results are the ones computed without it.
    Logs are keyed by the objects (held here, so their ids stay unique while it lives): a log must not change
    while it is in use; cached arrays are read-only.
    """

    def __init__(self):
        self._values: dict = {}
        self._held: list = []

    def _get(self, imu, key, compute):
        k = (id(imu), key)
        if k not in self._values:
            self._held.append(imu)
            self._values[k] = compute()
        return self._values[k]

    def acc(self, imu: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
        """:func:`ilocalg.pdr.signals.acc_from_log` of ``imu``."""
        def compute():
            acc, t = acc_from_log(imu)
            acc.flags.writeable = t.flags.writeable = False
            return acc, t
        return self._get(imu, "acc", compute)

    def steps(self, imu: pd.DataFrame, k: float, detector: dict | None = None) -> pd.DataFrame:
        """:func:`ilocalg.pdr.step_length.luo_steps` of ``imu`` (a new frame)."""
        det = tuple(sorted((detector or {}).items()))
        st = self._get(imu, ("steps", det), lambda: detect_steps_peak_window(*self.acc(imu), **(detector or {})))
        return luo_lengths(st, k)

    def headings(self, imu: pd.DataFrame, rest_s: float) -> np.ndarray:
        """The WDM headings of :func:`ilocalg.pdr.heading.log_headings_rad` (read-only)."""
        def compute():
            h = log_headings_rad(imu, rest_s)["WDM"]
            h.flags.writeable = False
            return h
        return self._get(imu, ("wdm", float(rest_s)), compute)

    def fit_k(self, walks, detector: dict | None = None) -> tuple[float, float]:
        """:func:`ilocalg.pdr.step_length.fit_luo_k` on walks with their truth (``imu``, ``steps["length_m"]``)."""
        return fit_luo_k([(None, None, sw.steps["length_m"]) for sw in walks], detector,
                         steps=[self.steps(sw.imu, 1.0, detector) for sw in walks])


def luo_pdr(imu: pd.DataFrame, k: float, detector: dict | None = None, rest_s: float = 0.0,
            logs: LuoLogs | None = None) -> dict:
    """Luo et al.'s PDR on one sensor log, as a step filter's inputs.

    Steps by the peak-window detector with eq. (4) lengths (:func:`ilocalg.pdr.step_length.luo_steps`),
    each with the WDM heading at its peak (:func:`ilocalg.pdr.heading.log_headings_rad`, ``rest_s`` of
    standing at the start).

    Returns
    -------
    dict
        ``state_t_s`` (n + 1: the log's start, then each step), ``step_m``, ``theta_rad`` (n) and
        ``heading_rad`` (the WDM heading at every sample).
    """
    logs = LuoLogs() if logs is None else logs
    t = logs.acc(imu)[1]
    st = logs.steps(imu, k, detector)
    heads = logs.headings(imu, rest_s)
    return {"state_t_s": np.concatenate([[t[0]], st["t_s"].to_numpy()]), "step_m": st["length_m"].to_numpy(),
            "theta_rad": heads[st["i_peak"].to_numpy()], "heading_rad": heads}


def luo_training_spread(walks, k: float, detector: dict | None = None,
                        logs: LuoLogs | None = None) -> tuple[float, float, float]:
    """The WDM heading error rms (rad) and the mean true step duration (s) and length (m) of training walks.

    ``walks``: walks with their truth (:mod:`ilocalg.sim.gait`): ``imu`` indexed by time, ``config.stand_s``,
    ``truth`` (``theta_rad`` indexed by time) and ``steps`` (``duration_s``, ``length_m``); the heading is
    taken at each step :func:`ilocalg.pdr.step_length.luo_steps` detects. Walks without a detected step
    are skipped.
    """
    logs = LuoLogs() if logs is None else logs
    errs_h, durs, lens = [], [], []
    for sw in walks:
        st = logs.steps(sw.imu, k, detector)
        if not len(st):
            continue
        heads = logs.headings(sw.imu, sw.config.stand_s)[st["i_peak"].to_numpy()]
        true_th = np.interp(st["t_s"].to_numpy(), sw.truth.index.to_numpy(), np.unwrap(sw.truth["theta_rad"]))
        errs_h.append(np.angle(np.exp(1j * (heads - true_th))))
        durs.append(sw.steps["duration_s"].to_numpy())
        lens.append(sw.steps["length_m"].to_numpy())
    e = np.concatenate(errs_h)
    return float(np.sqrt(np.mean(e**2))), float(np.mean(np.concatenate(durs))), float(np.mean(np.concatenate(lens)))


def eq4_vs_constant_error(train, test, detector: dict | None = None,
                          logs: LuoLogs | None = None) -> tuple[float, float]:
    """Mean relative step-length error of eq. (4) and of one constant step length on walks of known length.

    ``k`` of eq. (4) is fitted on ``train`` (:func:`ilocalg.pdr.step_length.fit_luo_k`) and the constant is
    the mean true step of ``train``; both are scored per detected step (eq. 4) or per walk (the constant)
    on ``test``.

    Parameters
    ----------
    train : sequence of walks with ``imu`` and ``steps`` (``length_m``), e.g. :func:`ilocalg.sim.gait.training_walks`.
    test : iterable of ``(imposed step length m, walk)``.
    detector : dict, optional, parameters of the peak-window detector.

    Returns
    -------
    (eq4_error, constant_error) : mean |estimate - length| / length (fractions).
    """
    logs = LuoLogs() if logs is None else logs
    k, _ = logs.fit_k(train, detector)
    const_m = float(np.mean([sw.steps["length_m"].mean() for sw in train]))
    e4, ec = [], []
    for length_m, sw in test:
        st = logs.steps(sw.imu, k, detector)
        e4 += list(np.abs(st["length_m"].to_numpy() - length_m) / length_m)
        ec.append(abs(const_m - length_m) / length_m)
    return float(np.mean(e4)), float(np.mean(ec))
