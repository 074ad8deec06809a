"""``python -m ilocalg evaluate steps PATH... [--method NAME] --json``: step counting on real recordings.

PATH is an Oxford step counter optimisation recording folder, the optimisation archive (every
recording in it, or ``--member NAME``), or a validation-style single headerless CSV (see
:mod:`ilocalg.io.oxford`). Prints one JSON object::

    {"method": ..., "recordings": [{"path", "name", "true_steps", "detected_steps", "accuracy",
     "hardware_steps", "duplicate_timestamps_dropped", "heel_bounces", "heel_bounces_merged"}, ...],
     "mean_accuracy": ..., "heel_bounces_policy": "keep" | "merge"}

``accuracy`` is ``1 - |detected - true| / true`` (a fraction); ``hardware_steps`` is the phone's own
step counter when the file has it (validation layout), else null. ``--duplicate-timestamps drop``
accepts files that repeat a timestamp on consecutive lines (some published validation CSVs do);
``duplicate_timestamps_dropped`` counts the lines it dropped per recording. ``--heel-bounces merge`` scores
against the optimisation truth with heel-sensor bounces merged into the contact before them
(:func:`ilocalg.io.oxford.load_oxford_step_counter`); the default ``keep`` is the published truth. Per
recording, ``heel_bounces`` counts the bounces found in the truth (under either policy; 0 in the validation
layout, which carries counts, not foot states) and ``heel_bounces_merged`` those merged. Methods use fixed
parameters: those that leave-one-recording-out tuning chose on the Oxford optimisation set (experiment
``pdr_real_steps``); SAM uses the i-Loc thesis's Table 1 ranges.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ilocalg.io.oxford import HEEL_BOUNCE_POLICIES, _is_archive, load_oxford_archive, load_oxford_step_counter

NAME = "steps"
#: Shortest recording the command scores, s (about two strides: every detector needs a few steps).
MIN_DURATION_S = 2.0
HELP = "count steps in Oxford step counter recordings (folder, archive or validation CSV)"

#: Fixed parameters per registered detector (``robust`` is the toolkit's best; its defaults, and
#: those of ``find_peaks``, are the tuned values; SAM uses the thesis's Table 1 ranges).
METHODS = {
    "robust": {},
    "find_peaks": {},
    "peak_window": {"threshold_mps2": 2.0, "rule": "valley_rise"},
    "sign_change": {"n_left": 2, "n_right": 2, "smooth": True},
    "sam": {},
}


def add_arguments(parser) -> None:
    parser.add_argument("paths", nargs="+", metavar="PATH",
                        help="recording folder, optimisation .tar.xz archive, or validation .csv")
    parser.add_argument("--method", default="robust", choices=sorted(METHODS),
                        help="step detector (default: robust, the toolkit's best)")
    parser.add_argument("--member", action="append", default=None, metavar="NAME",
                        help="recording name inside an archive (repeatable; default: all; other paths ignore it)")
    parser.add_argument("--duplicate-timestamps", default="error", choices=("error", "drop"),
                        help="a timestamp repeated on consecutive lines: refuse (default) or drop the later line "
                             "(counted per recording)")
    parser.add_argument("--heel-bounces", default="keep", choices=HEEL_BOUNCE_POLICIES,
                        help="optimisation truth: keep heel-sensor bounces as steps (default: the published count) "
                             "or merge each into the contact before it (counted per recording)")


def count(rec, method: str) -> int:
    """Steps counted in one :class:`~ilocalg.io.oxford.OxfordRecording` by ``method``.

    The log is resampled to the detector's rate (:data:`ilocalg.pdr.registry.DETECTOR_RATE_HZ`) and
    run through the registered detector (:func:`ilocalg.pdr.count_steps`).
    """
    from ilocalg.pdr import count_steps
    from ilocalg.pdr.signals import acc_from_log

    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {sorted(METHODS)}")
    acc, t = acc_from_log(rec.imu)
    return count_steps(method, acc, t, **METHODS[method])


def run(args) -> dict:
    rows = []
    dup = getattr(args, "duplicate_timestamps", "error")
    heel = getattr(args, "heel_bounces", "keep")
    for path in args.paths:
        p = Path(path)
        try:
            if _is_archive(p):
                recs = load_oxford_archive(p, args.member, duplicate_timestamps=dup, heel_bounces=heel)
                where = [f"{p}:{r.name}" for r in recs]
            else:
                recs = [load_oxford_step_counter(p, duplicate_timestamps=dup, heel_bounces=heel)]
                where = [str(p)]
        except ValueError as exc:  # name the command-line option, not the loader's argument
            raise ValueError(str(exc).replace("pass duplicate_timestamps='drop'",
                                              "pass --duplicate-timestamps drop")) from None
        for w, rec in zip(where, recs, strict=True):
            t = rec.imu.index.to_numpy()
            if t[-1] - t[0] < MIN_DURATION_S:
                raise ValueError(f"{w}: the recording lasts {t[-1] - t[0]:.3g} s ({t.size} samples); step counting "
                                 f"needs at least {MIN_DURATION_S:g} s of walking")
            if rec.true_steps <= 0:
                raise ValueError(f"{w}: the recording has no true steps; accuracy is undefined")
            try:
                n = count(rec, args.method)
            except ValueError as exc:
                raise ValueError(f"{w}: --method {args.method} cannot count this recording "
                                 f"({t[-1] - t[0]:.3g} s, {t.size} samples): {exc}") from None
            rows.append({"path": w, "name": rec.name, "true_steps": int(rec.true_steps), "detected_steps": int(n),
                         "accuracy": float(1.0 - abs(n - rec.true_steps) / rec.true_steps),
                         "hardware_steps": rec.hardware_steps,
                         "duplicate_timestamps_dropped": int(rec.n_duplicate_timestamps_dropped),
                         "heel_bounces": int(rec.n_heel_bounces),
                         "heel_bounces_merged": int(rec.n_heel_bounces_merged)})
    return {"method": args.method, "recordings": rows,
            "mean_accuracy": float(np.mean([r["accuracy"] for r in rows])), "heel_bounces_policy": heel}
