"""``python -m ilocalg evaluate wifi``: score a Wi-Fi fingerprint method on a train/test pair.

Formats: ``ujiindoorloc`` (the data set's own CSV) and ``csv`` (the survey layout the README offers
for one's own data, :mod:`ilocalg.wifi.survey`: ``x_m``, ``y_m`` [, ``floor``, ``building``], then one
RSSI column per access point, empty = not heard). Without floor/building columns the hit rates are
``null``. Survey files may order their access-point columns differently: the test file's columns are
matched to the training file's by name.

Example (gives the independent reference figure for UJIIndoorLoc k=5 Euclidean, 8.808 m)::

    python -m ilocalg evaluate wifi --train trainingData.csv.gz --test validationData.csv.gz \\
        --format ujiindoorloc --method knn --k 5 --metric euclidean --json

``--method toolkit`` runs the toolkit's UJIIndoorLoc headline (notebook 02's last ladder row, chosen by CV on the
training set only; :func:`ilocalg.wifi.candidates.toolkit_estimator`): on the same pair it gives that row's
figures.

JSON keys (a public contract): mean_error_m, median_error_m, p75_error_m, p95_error_m,
floor_hit_rate, building_hit_rate (fractions), n, n_no_shared_ap. Errors are 2-D, in the data set's
metres (projected Web-Mercator metres for UJIIndoorLoc). A test scan sharing no access point with the
training set is not located (NaN, see :mod:`ilocalg.wifi.preprocessing`): counted in
``n_no_shared_ap``, left out of the error statistics and counted as a miss in the hit rates; ``n``
is the number of located test scans.
"""

from __future__ import annotations

import numpy as np

NAME = "wifi"
HELP = "Wi-Fi fingerprinting (RADAR, Horus, KNN, WKNN, best, toolkit) on a train/test fingerprint pair"

#: The registered estimators (:data:`ilocalg.wifi.ESTIMATORS`); kept literal so ``--help`` needs no import.
METHODS = ("radar", "horus", "knn", "wknn", "best", "toolkit")
FORMATS = ("ujiindoorloc", "csv")


def add_arguments(parser) -> None:
    parser.add_argument("--train", required=True, help="training fingerprints (file)")
    parser.add_argument("--test", required=True, help="test fingerprints (file)")
    parser.add_argument("--format", default="ujiindoorloc", choices=FORMATS,
                        help="file format: ujiindoorloc, or csv (x_m, y_m[, floor, building], one RSSI column "
                             "per access point, empty = not heard)")
    parser.add_argument("--method", default="knn", choices=METHODS, help="positioning method")
    parser.add_argument("--k", type=int, default=None,
                        help="knn/wknn: neighbours K (default 5); best: K (default 12); toolkit: each member's K "
                             "(default 8); radar/horus: strongest APs k (default 5)")
    parser.add_argument("--metric", default="euclidean", choices=("manhattan", "euclidean"),
                        help="knn/wknn distance (default euclidean; toolkit's members fix their own)")
    parser.add_argument("--not-heard-dbm", type=float, default=-104.0,
                        help="RSSI substituted for 'not heard' (default -104, UJIIndoorLoc's weakest)")


def _load(path, fmt):
    from ilocalg.io.ujiindoorloc import load_ujiindoorloc
    from ilocalg.wifi.survey import read_survey_csv

    return load_ujiindoorloc(path) if fmt == "ujiindoorloc" else read_survey_csv(path)


def _align_aps(train, test, train_path, test_path):
    """``test`` with its access-point columns in the training file's order (absent ones: not heard)."""
    from dataclasses import replace

    if train.ap_ids == test.ap_ids:
        return test
    pos = {a: j for j, a in enumerate(test.ap_ids)}
    shared = [a for a in train.ap_ids if a in pos]
    if not shared:
        raise ValueError(f"{test_path}: no access-point column in common with {train_path}")
    r = np.full((test.n_samples, len(train.ap_ids)), np.nan)
    for j, a in enumerate(train.ap_ids):
        if a in pos:
            r[:, j] = test.rssi_dbm[:, pos[a]]
    return replace(test, rssi_dbm=r, ap_ids=train.ap_ids)


def _check_references_hear(train, path) -> None:
    """Refuse a training file none of whose reference scans hears an access point, naming its lines.

    A single reference scan hearing nothing is accepted (UJIIndoorLoc's training file has 76); it
    holds no fingerprint information, and every estimator treats it as "all not heard".
    """
    empty = np.isnan(np.asarray(train.rssi_dbm, dtype=np.float64)).all(axis=1)
    if empty.all():
        n = empty.size
        lines = "line 2" if n == 1 else f"lines 2-{n + 1}"
        raise ValueError(f"{path}: {lines}: no reference scan hears an access point (every RSSI is 'not heard'); "
                         "a radio map needs scans that hear at least one access point")


def run(args) -> dict:
    from ilocalg.metrics import hit_rate
    from ilocalg.wifi import evaluate_method, make_estimator

    if args.format not in FORMATS:
        raise ValueError(f"--format must be one of {FORMATS}, got {args.format!r}")
    if args.k is not None and args.k < 1:
        raise ValueError(f"--k must be >= 1, got {args.k}")
    train = _load(args.train, args.format)
    test = _load(args.test, args.format)
    if args.format == "csv":
        test = _align_aps(train, test, args.train, args.test)
    if train.ap_ids != test.ap_ids:
        raise ValueError(f"--train and --test have different access-point columns ({args.train}, {args.test})")
    _check_references_hear(train, args.train)
    est = make_estimator(args.method, args.k, args.metric, args.not_heard_dbm)
    need = int(est.get_params().get("n_neighbors", est.get_params().get("est__n_neighbors", 1)))
    if train.n_samples < need:
        hint = (f"pass --k {train.n_samples} or less, or " if args.method in ("knn", "wknn", "best", "toolkit")
                else "")
        raise ValueError(f"{args.train}: {train.n_samples} training rows, fewer than the {need} neighbours "
                         f"--method {args.method} averages; {hint}give more training rows")
    labelled = {f: getattr(train, f) is not None and getattr(test, f) is not None for f in ("floor", "building")}
    if not all(labelled.values()):
        from dataclasses import replace

        zeros = {f: np.zeros(s.n_samples, dtype=np.int64) for f, s in (("train", train), ("test", test))}
        train = replace(train, **{f: zeros["train"] for f in labelled if not labelled[f]})
        test = replace(test, **{f: zeros["test"] for f in labelled if not labelled[f]})
    res = evaluate_method(train, test, args.method, k=args.k, metric=args.metric, not_heard_dbm=args.not_heard_dbm)
    e = res["error_m"]
    if np.isnan(e).all():
        raise ValueError(f"{args.test}: no test scan shares an access point with the training set {args.train}")
    e = e[~np.isnan(e)]
    return {
        "mean_error_m": float(np.mean(e)),
        "median_error_m": float(np.median(e)),
        "p75_error_m": float(np.percentile(e, 75)),
        "p95_error_m": float(np.percentile(e, 95)),
        "floor_hit_rate": hit_rate(res["floor"], test.floor) if labelled["floor"] else None,
        "building_hit_rate": hit_rate(res["building"], test.building) if labelled["building"] else None,
        "n": int(e.size),
        "n_no_shared_ap": res["n_no_shared_ap"],
    }
