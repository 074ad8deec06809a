"""The registry of step detectors: one name -> one function with the documented contract.

Contract of a registered detector ``fn(acc_mps2, t_s, **params) -> DataFrame``:

* ``acc_mps2``: specific force in the phone frame, m/s^2, shape (n, 3) (every registered detector
  accepts it; some also take a one-dimensional signal, see each function);
* ``t_s``: sample times, s, shape (n,), strictly increasing;
* the result has one row per detected step and at least the columns :data:`STEP_CONTRACT`:
  ``i_peak`` (int index into the input samples), ``t_s`` (s, increasing), ``a_max_mps2`` and
  ``a_min_mps2`` (the step's largest and smallest acceleration, m/s^2, as the step-length models
  use them).

Adding a detector is one decorator in its own module::

    from ilocalg.pdr.registry import register_step_detector

    @register_step_detector("my_detector")
    def detect_steps_mine(acc_mps2, t_s, threshold_mps2=1.0) -> pd.DataFrame: ...

Experiments and the command line call detectors by name through :func:`detect_steps` and
:func:`count_steps`; nothing else dispatches on detector names.
"""

from __future__ import annotations

from collections.abc import Callable

import pandas as pd

from ilocalg.pdr.signals import check_acc, check_times, resample_uniform

__all__ = [
    "STEP_CONTRACT",
    "STEP_DETECTORS",
    "DETECTOR_RATE_HZ",
    "register_step_detector",
    "step_detector",
    "detect_steps",
    "count_steps",
]

#: Columns every registered detector returns.
STEP_CONTRACT = ("i_peak", "t_s", "a_max_mps2", "a_min_mps2")

#: name -> detector function (filled by :func:`register_step_detector`, on ``import ilocalg.pdr``).
STEP_DETECTORS: dict[str, Callable[..., pd.DataFrame]] = {}

#: Rate (Hz) at which :func:`count_steps` runs each detector on a real log (resampled first); SAM's
#: X1 feature depends on the rate, so it runs at 50 Hz, every other detector at 100 Hz.
DETECTOR_RATE_HZ: dict[str, float] = {}
DEFAULT_RATE_HZ = 100.0


def register_step_detector(name: str, rate_hz: float = DEFAULT_RATE_HZ):
    """Decorator: register ``fn`` under ``name`` (run at ``rate_hz`` by :func:`count_steps`)."""
    if not isinstance(name, str) or not name:
        raise ValueError(f"a step detector name must be a non-empty str, got {name!r}")

    def deco(fn):
        if name in STEP_DETECTORS and STEP_DETECTORS[name] is not fn:
            raise ValueError(f"step detector {name!r} is already registered ({STEP_DETECTORS[name].__qualname__})")
        STEP_DETECTORS[name] = fn
        DETECTOR_RATE_HZ[name] = float(rate_hz)
        return fn

    return deco


def step_detector(name: str) -> Callable[..., pd.DataFrame]:
    """The detector registered as ``name``."""
    try:
        return STEP_DETECTORS[name]
    except KeyError:
        raise ValueError(f"unknown step detector {name!r}; known: {sorted(STEP_DETECTORS)}") from None


def detect_steps(name: str, acc_mps2, t_s, **params) -> pd.DataFrame:
    """Run the detector registered as ``name`` on ``(acc_mps2, t_s)`` with ``params``."""
    return step_detector(name)(acc_mps2, t_s, **params)


def count_steps(name: str, acc_mps2, t_s, **params) -> int:
    """Steps counted in a log of any sampling: resample to the detector's rate, detect, count.

    Parameters
    ----------
    name : str
        A key of :data:`STEP_DETECTORS`.
    acc_mps2 : array_like, shape (n, 3)
    t_s : array_like, shape (n,)
        Strictly increasing times, s (any spacing).
    **params
        Passed to the detector.
    """
    fn = step_detector(name)
    a = check_acc(acc_mps2, min_samples=2)
    t = check_times(t_s, n=a.shape[0], regular=False)
    au, tu = resample_uniform(a, t, DETECTOR_RATE_HZ[name])
    return int(len(fn(au, tu, **params)))

