"""Wi-Fi fingerprinting on the real UJIIndoorLoc set (official split: training -> validation).

``run(seed, fast, data_dir)`` loads ``trainingData.csv(.gz)`` and ``validationData.csv(.gz)``
(:func:`ilocalg.io.ujiindoorloc.load_ujiindoorloc`), runs every method and returns:

* ``methods``: mean / median / p75 / p95 2-D error in the data set's projected (Web-Mercator)
  metres and in ground metres, floor and building hit rates, per method;
* ``errors``: every error per method (for the CDF figure);
* ``best_search``: the configurations tried for the "best" method, scored on the *selection half*
  of the validation set (a seeded random half) and on the other, *held-out* half;
* ``paper_vs_reproduced``: published / independent reference values beside the reproduced ones;
* ``timing`` (non-deterministic): fit and query times.

Protocol: RSSI 100 (not detected) -> NaN -> ``not_heard_dbm`` = -104 dBm (the weakest reading the
set documents); floor and building by the (weighted) majority vote of the neighbours, ties to the
smallest label (as ``scipy.stats.mode``); Horus returns the floor and building of its most likely
reference point. Positions are LONGITUDE/LATITUDE as given (projected metres). The scoring, the
selection-half search and the toolkit ladder live in :mod:`ilocalg.wifi.model_selection`.

The "best" configuration is chosen on the selection half only and reported on both halves and on
all validation rows, so the held-out half is an unbiased estimate of it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import data_dir as default_data_dir
from ilocalg.io.schema import FingerprintSet
from ilocalg.io.ujiindoorloc import load_ujiindoorloc
from ilocalg.papers import paper_ref
from ilocalg.wifi import ESTIMATORS, evaluate_method
from ilocalg.wifi.candidates import TOOLKIT_HEADLINE
from ilocalg.wifi.evaluate import error_budget
from ilocalg.wifi.knn import shared_searches
from ilocalg.wifi.model_selection import (
    ap_loss_cv,
    best_search,
    ladder_cv_diagnostic,
    metrics_row,
    selection_mask,
    toolkit_ladder,
)

__all__ = [
    "PAPER_UJI", "METHODS", "TOOLKIT_READINGS", "AP_LOSS_FRACTIONS", "AP_LOSS_LABELS", "ap_loss",
    "ap_loss_findings", "ap_loss_fractions", "budget_findings", "campaign_shift", "cli_headline",
    "find_files", "load", "run"]

# Settings from the paper
# -----------------------
# PAPER_UJI (reference values, never used to compute): indep_* = an independent re-measurement
# quoted in the data set's SOURCE.txt (not a paper table); paper_dataset_1nn_mean_m =
# Torres-Sospedra et al. (2014) 1-NN baseline (another protocol); paper_evaal_winner_* = the
# EvAAL-ETRI 2015 winner (private test set, floor penalties).
PAPER_UJI = {
    "indep_1nn_mean_m": 9.750,
    "indep_1nn_building": 0.9955,
    "indep_1nn_floor": 0.9001,
    "indep_k5_mean_m": 8.808,
    "indep_k5_building": 0.9973,
    "indep_k5_floor": 0.9028,
    "paper_dataset_1nn_mean_m": 7.9,
    "paper_evaal_winner_mean_m": 6.20,
    "paper_evaal_winner_floor": 0.9374,
}

METHODS = tuple(ESTIMATORS)

#: The literature behind each toolkit step (``toolkit_readings`` table): step, source, what it reports, what the
#: code does. No value of a source is used as a result; settings it fixes appear in the row's parameters.
TOOLKIT_READINGS = (
    ("building -> floor -> position", "Torres-Sospedra et al. 2014 (IPIN, the data set paper)",
     "a multi-building, multi-floor set: locate building and floor, then the position",
     "CascadeFingerprint: distance-weighted KNN votes for building, then floor inside it, WKNN inside the floor"),
    ("powed / exponential / positive RSSI", "Torres-Sospedra et al. 2015 (Expert Syst. Appl. 42), sec. 3",
     "data representations; powed (beta = e) and exponential (alpha = 24) weigh strong readings up",
     "to_features(representation=...); chosen by GroupKFold CV on training in the CV rows"),
    ("Sorensen (Bray-Curtis) distance", "Torres-Sospedra et al. 2015",
     "Sorensen on powed data is among the best distance / representation pairs on UJIIndoorLoc",
     "metric='sorensen' of every KNN; the fixed powed + Sorensen rows take the pair as published"),
    ("per-device offset", "Tsui et al. 2009 (Mobile Netw. Appl. 14)",
     "unsupervised calibration: the RSS offset of an unseen phone that best fits the radio map",
     "OffsetFingerprint: per-query shift within one measured per-phone offset sd"),
    ("AP selection", "Chen et al. 2006 (IEEE Trans. Knowl. Data Eng. 18)",
     "locating with a selected subset of the APs instead of all of them",
     "ApSelector(min_count=1): APs never heard in training dropped before every distance"),
    ("ensemble of estimators", "Torres-Sospedra et al. 2019 (IPIN 2019)",
     "averaging fingerprinting models with different distances / representations is robust",
     "FingerprintEnsemble: mean position, majority floor and building; members chosen by GroupKFold CV"),
    ("merged fingerprints per reference spot", "RADAR (Bahl & Padmanabhan 2000); common on UJIIndoorLoc",
     "average the scans of one spot into one fingerprint",
     "SpotAveragedFingerprint: the offset search fitted on each spot's mean fingerprint, as members beside the "
     "raw ones (raw + averaged), spot K by GroupKFold(PHONEID) CV (spot_grid). Averaged alone (an earlier "
     "session, validation in view; this one, CV only) it raised the error, so it has no row of its own"),
    ("neighbour-weight exponent", "i-Loc thesis eq. (2) (1/d^2); scikit-learn's distance weights (1/d)",
     "weighted KNN with the weights 1/d^a",
     "OffsetFingerprint(weight_power=a), a in SPOT_WEIGHT_POWERS chosen with the spot K by GroupKFold(PHONEID) CV"),
    ("offset search range", "Tsui et al. 2009; the measured per-phone offset sd (data/measured_parameters.csv)",
     "the offset of an unseen phone is unknown; the search must cover the spread of phones",
     "offset search over +-1 sd or +-2 sd of the measured sd (2 dB steps), chosen with the members by "
     "GroupKFold(PHONEID) CV on training (offset_range_grid)"),
    ("a CV that mimics the validation campaign", "Torres-Sospedra et al. 2014 (the data set paper); SOURCE.txt",
     "validation: recorded about four months after the survey, by other users, mostly with other phones (9 of its "
     "11 phones are not in training), at free positions rather than at the survey's reference spots",
     "SpotPhoneKFold ('spot x PHONEID'): each fold scores scans at reference spots and with phones its training "
     "part never saw, at places the rest of the survey covers; it chooses the headline row among headline_grid's "
     "candidates, fixed beforehand (headline_cv). The time gap (access points changed) has no counterpart "
     "inside the training campaign"),
    ("per-device calibration from the phone's own scans", "Tsui et al. 2009 (Mobile Netw. Appl. 14)",
     "a new phone's RSS mapping is learned without labels from the scans the phone collects in use",
     "OffsetFingerprint(device_calibration=True): each scan's shift minimises the search criterion summed over "
     "its phone's scans up to its own time (PHONEID, TIMESTAMP; causal, no position used); on / off for the "
     "headline's members by the spot x PHONEID CV (device_calibration_cv)"),
    ("rank-based fingerprints", "Machaj, Brida & Piche 2011 (IPIN 2011)",
     "a fingerprint as the order of the APs by signal strength, robust to the differences between phones",
     "representation='rank' (each heard AP's rank in its scan over the number heard; the scaling is the toolkit's), "
     "WKNN with the Sorensen distance, no offset search (rank_member); each headline candidate with and without it "
     "(headline_grid), chosen by the spot x PHONEID CV"),
    ("APs gone by query time (a robustness check)", "campaigns table (training and validation columns heard)",
     "the CVs assume every AP of the survey still there; the validation campaign, months later, never hears "
     "some of the training APs",
     "ap_loss: three ladder rows under the spot x PHONEID CV with a random share of the APs removed from the "
     "queries only (0, 0.1, 0.2 and the measured share of training APs the validation never hears); chooses "
     "nothing"),
)


def campaign_shift(train: FingerprintSet, test: FingerprintSet) -> pd.DataFrame:
    """What sets the test campaign apart from the survey, from columns that are neither labels nor positions.

    Users, phones (and the share of test scans taken with phones the survey never used), recording days and
    span, access points heard (and the share of each set's readings on APs the other set never heard), APs per
    scan; and, for the training set only, its reference spots (distinct targets; a label, so never for the test
    set). One row per quantity, a column per set.
    """
    rows = []

    def add(q, a, b):
        rows.append({"quantity": q, "training": a, "validation": b})

    mt, mv = train.meta, test.meta
    new_phone = ~mv["PHONEID"].isin(set(mt["PHONEID"]))
    add("scans", train.n_samples, test.n_samples)
    add("users (USERID; 0 = not recorded)", mt["USERID"].nunique(), mv["USERID"].nunique())
    add("phones (PHONEID)", mt["PHONEID"].nunique(), mv["PHONEID"].nunique())
    add("phones not in the other set", int((~mt["PHONEID"].isin(set(mv["PHONEID"]))).groupby(mt["PHONEID"]).first()
                                           .sum()), int(new_phone.groupby(mv["PHONEID"]).first().sum()))
    add("share of scans with a phone not in training", 0.0, float(new_phone.mean()))
    for name, m in (("training", mt), ("validation", mv)):
        t = pd.to_datetime(m["TIMESTAMP"], unit="s")
        rows.append({"quantity": "first day", name: str(t.min().date())})
        rows.append({"quantity": "last day", name: str(t.max().date())})
        rows.append({"quantity": "days with scans", name: int(t.dt.date.nunique())})
    heard_t, heard_v = np.isfinite(train.rssi_dbm), np.isfinite(test.rssi_dbm)
    ever_t, ever_v = heard_t.any(axis=0), heard_v.any(axis=0)
    add("APs heard", int(ever_t.sum()), int(ever_v.sum()))
    add("APs heard only in this set", int((ever_t & ~ever_v).sum()), int((ever_v & ~ever_t).sum()))
    add("share of readings on APs the other set never heard", float(heard_t[:, ~ever_v].sum() / heard_t.sum()),
        float(heard_v[:, ~ever_t].sum() / heard_v.sum()))
    add("median APs heard per scan", float(np.median(heard_t.sum(axis=1))), float(np.median(heard_v.sum(axis=1))))
    y = np.column_stack([train.xy_m, train.floor, train.building])
    add("reference spots (distinct targets; training only)", len(np.unique(y, axis=0)), None)
    out = pd.DataFrame(rows).groupby("quantity", sort=False).first().reset_index()
    return out.astype({"training": object, "validation": object})


def find_files(data_dir: str | Path | None = None) -> tuple[Path, Path] | None:
    """(training, validation) CSV paths under ``<data_dir>/ujiindoorloc``, or None if absent."""
    root = Path(data_dir) if data_dir else default_data_dir()
    d = root / "ujiindoorloc"
    out = []
    for stem in ("trainingData", "validationData"):
        cands = [d / f"{stem}.csv", d / f"{stem}.csv.gz"]
        hit = [c for c in cands if c.is_file()]
        if not hit:
            return None
        out.append(hit[0])
    return out[0], out[1]


def load(data_dir: str | Path | None = None) -> tuple[FingerprintSet, FingerprintSet] | None:
    """Load the official split, or None when the set is absent."""
    files = find_files(data_dir)
    if files is None:
        return None
    return load_ujiindoorloc(files[0]), load_ujiindoorloc(files[1])


def run(seed: int = 0, fast: bool = False, data_dir: str | Path | None = None, search: bool | None = None,
        fast_train_rows: int = 4000, fast_test_rows: int = 256, toolkit: bool = True,
        cv_diagnostic: bool = False) -> dict[str, pd.DataFrame] | None:
    """Load the official split, run every method and score; None when the set is absent.

    Parameters
    ----------
    seed : int
        Seeds the fast-mode subsample and the selection half.
    fast : bool
        Subsample ``fast_train_rows`` training and ``fast_test_rows`` validation rows (seeded).
    search : bool or None
        Run :func:`ilocalg.wifi.model_selection.best_search` (default: only in full mode).
    toolkit : bool
        Add the toolkit ladder (:func:`ilocalg.wifi.model_selection.toolkit_ladder`): rows
        ``toolkit: ...`` in ``methods`` and ``errors``, tables ``toolkit_ladder``, ``toolkit_cv``,
        ``toolkit_readings`` (:data:`TOOLKIT_READINGS`), ``toolkit_error_budget`` (the headline row's error by
        group of validation scans, :func:`ilocalg.wifi.evaluate.error_budget`), ``toolkit_cli`` (whether
        ``evaluate wifi --method toolkit`` runs the headline row, :func:`cli_headline`), ``toolkit_ap_loss`` (three
        rows' CV error with APs gone at query time, :func:`ap_loss`) and ``measures``.
    cv_diagnostic : bool
        With ``toolkit``, also score every ladder row under the GroupKFold(PHONEID) and spot x PHONEID CVs
        (:func:`ilocalg.wifi.model_selection.ladder_cv_diagnostic`; a diagnostic of the CVs, used to choose
        nothing): tables ``toolkit_cv_diagnostic`` and ``toolkit_cv_agreement``. Off by default (about 80 CPU-s in
        full mode).
    """
    data = load(data_dir)
    if data is None:
        return None
    with shared_searches():  # the CVs refit the same folds for several K and overlapping offset grids
        return _run(data, seed, fast, search, fast_train_rows, fast_test_rows, toolkit, cv_diagnostic)


def _run(data, seed, fast, search, fast_train_rows, fast_test_rows, toolkit, cv_diagnostic=False
         ) -> dict[str, pd.DataFrame]:
    """:func:`run` on the loaded split."""
    train, test = data
    if fast:
        rng = np.random.default_rng(seed)
        train = train.subset(np.sort(rng.choice(train.n_samples, min(fast_train_rows, train.n_samples),
                                                replace=False)))
        test = test.subset(np.sort(rng.choice(test.n_samples, min(fast_test_rows, test.n_samples), replace=False)))
    configs = [
        ("1-NN (Euclidean)", "knn", 1, "euclidean"),
        ("KNN K=5 (Euclidean)", "knn", 5, "euclidean"),
        ("KNN K=5 (Manhattan, Luo et al. 2017)", "knn", 5, "manhattan"),
        ("WKNN K=5 (Euclidean)", "wknn", 5, "euclidean"),
        ("KNN K=5 hierarchical (building -> floor -> position)", "hierarchical", 5, "euclidean"),
        ("Simplified-RADAR k=5 N=3", "radar", 5, "euclidean"),
        ("Simplified-Horus k=5", "horus", 5, "euclidean"),
        ("best (union top-5 APs, N=12)", "best", None, "euclidean"),
    ]
    sel = selection_mask(test.n_samples, seed)
    rows, errs, timing, res_by = [], [], [], {}
    for name, method, k, metric in configs:
        res = evaluate_method(train, test, method, k, metric)
        res_by[name] = res
        rows.append({"method": name, **metrics_row(res, test)})
        errs.append(pd.DataFrame({"method": name, "error_m": res["error_m"]}))
        timing.append({"method": name, "fit_s": res["fit_s"], "predict_s": res["predict_s"],
                       "queries_per_s": test.n_samples / res["predict_s"]})
    ladder = toolkit_ladder(train, test, seed, fast) if toolkit else None
    if ladder is not None:
        for name, res in ladder["results"].items():
            rows.append({"method": name, **metrics_row(res, test)})
            errs.append(pd.DataFrame({"method": name, "error_m": res["error_m"]}))
    methods = pd.DataFrame(rows)
    best = res_by["best (union top-5 APs, N=12)"]
    best_halves = pd.DataFrame([
        {"rows": "selection half", **metrics_row(best, test, np.flatnonzero(sel))},
        {"rows": "held-out half", **metrics_row(best, test, np.flatnonzero(~sel))},
        {"rows": "all validation", **metrics_row(best, test)},
    ])
    m = methods.set_index("method")
    u = "UJIIndoorLoc"
    note_fast = " (fast mode: subsample)" if fast else ""
    ref = [
        paper_ref("independent re-measurement", u, "1-NN mean 2-D error", PAPER_UJI["indep_1nn_mean_m"],
                  m.loc["1-NN (Euclidean)", "mean_m"], "m", "reference protocol" + note_fast),
        paper_ref("independent re-measurement", u, "1-NN building hit rate", PAPER_UJI["indep_1nn_building"],
                  m.loc["1-NN (Euclidean)", "building_hit_rate"], "fraction", note_fast),
        paper_ref("independent re-measurement", u, "1-NN floor hit rate", PAPER_UJI["indep_1nn_floor"],
                  m.loc["1-NN (Euclidean)", "floor_hit_rate"], "fraction", note_fast),
        paper_ref("independent re-measurement", u, "KNN K=5 mean 2-D error", PAPER_UJI["indep_k5_mean_m"],
                  m.loc["KNN K=5 (Euclidean)", "mean_m"], "m", note_fast),
        paper_ref("independent re-measurement", u, "KNN K=5 building hit rate", PAPER_UJI["indep_k5_building"],
                  m.loc["KNN K=5 (Euclidean)", "building_hit_rate"], "fraction", note_fast),
        paper_ref("independent re-measurement", u, "KNN K=5 floor hit rate", PAPER_UJI["indep_k5_floor"],
                  m.loc["KNN K=5 (Euclidean)", "floor_hit_rate"], "fraction", note_fast),
        paper_ref("Torres-Sospedra et al. 2014", u, "1-NN mean 2-D error (dataset paper)",
                  PAPER_UJI["paper_dataset_1nn_mean_m"], m.loc["1-NN (Euclidean)", "mean_m"], "m",
                  "paper used another protocol"),
        paper_ref("EvAAL-ETRI 2015 winner", u, "best mean 2-D error", PAPER_UJI["paper_evaal_winner_mean_m"],
                  m.loc["best (union top-5 APs, N=12)", "mean_m"], "m",
                  "winner: private test set; ours: public validation set"),
        paper_ref("EvAAL-ETRI 2015 winner", u, "best floor hit rate", PAPER_UJI["paper_evaal_winner_floor"],
                  m.loc["best (union top-5 APs, N=12)", "floor_hit_rate"], "fraction",
                  "winner: private test set; ours: public validation set"),
    ]
    tables = {
        "campaigns": campaign_shift(train, test),
        "methods": methods,
        "errors": pd.concat(errs, ignore_index=True),
        "best_halves": best_halves,
        "paper_vs_reproduced": pd.DataFrame(ref),
        "timing": pd.DataFrame(timing),
        "data": pd.DataFrame([{"set": "training", "rows": train.n_samples, "aps": train.n_aps,
                               "source": Path(train.source).name},
                              {"set": "validation", "rows": test.n_samples, "aps": test.n_aps,
                               "source": Path(test.source).name}]),
    }
    if ladder is not None:
        lad = ladder["toolkit_ladder"]
        tk = lad.iloc[-1]
        tables["toolkit_ladder"] = lad
        tables["toolkit_cv"] = ladder["toolkit_cv"]
        tables["toolkit_error_budget"] = error_budget(train, test, ladder["results"][tk["method"]])
        tables["toolkit_cli"] = cli_headline(ladder)
        tables["toolkit_readings"] = pd.DataFrame(list(TOOLKIT_READINGS),
                                                  columns=["step", "source", "source_says", "code_does"])
        tables["paper_vs_reproduced"] = pd.concat([tables["paper_vs_reproduced"], pd.DataFrame([
            paper_ref("EvAAL-ETRI 2015 winner", u, "toolkit mean 2-D error (last ladder row, CV-chosen)",
                      PAPER_UJI["paper_evaal_winner_mean_m"], tk["mean_m"], "m",
                      "toolkit row; winner: private test set; ours: public validation set" + note_fast),
            paper_ref("EvAAL-ETRI 2015 winner", u, "toolkit floor hit rate (last ladder row, CV-chosen)",
                      PAPER_UJI["paper_evaal_winner_floor"], tk["floor_hit_rate"], "fraction",
                      "toolkit row; winner: private test set; ours: public validation set" + note_fast),
        ])], ignore_index=True)
        tables["measures"] = pd.DataFrame([
            {"quantity": "toolkit_mean_error", "value": tk["mean_m"], "unit": "m", "item": tk["method"]},
            {"quantity": "toolkit_median_error", "value": tk["median_m"], "unit": "m", "item": tk["method"]},
            {"quantity": "toolkit_p75_error", "value": tk["p75_m"], "unit": "m", "item": tk["method"]},
            {"quantity": "toolkit_floor_hit_rate", "value": tk["floor_hit_rate"], "unit": "fraction",
             "item": tk["method"]},
            {"quantity": "toolkit_building_hit_rate", "value": tk["building_hit_rate"], "unit": "fraction",
             "item": tk["method"]},
        ])
    if ladder is not None:
        tables["toolkit_ap_loss"] = ap_loss(train, test, ladder, fast)
    if ladder is not None and cv_diagnostic:
        tables["toolkit_cv_diagnostic"], tables["toolkit_cv_agreement"] = ladder_cv_diagnostic(train, ladder, seed)
    if search if search is not None else not fast:
        tables["best_search"] = best_search(train, test, seed)
    return tables


#: Fractions of the survey's access points gone by query time that :func:`ap_loss` sweeps (the measured top of the
#: range, the share of training APs the validation campaign never hears, is added to them).
AP_LOSS_FRACTIONS = (0.0, 0.1, 0.2)
#: Short names of the three rows :func:`ap_loss` scores (column ``label``).
AP_LOSS_LABELS = ("flat WKNN (dBm, Euclidean)", "+ Sorensen distance (powed)", "headline (last ladder row)")


def ap_loss_fractions(train: FingerprintSet, test: FingerprintSet) -> list[float]:
    """:data:`AP_LOSS_FRACTIONS` and, as the top of the sweep, the share of the APs heard in ``train`` that ``test``
    never hears (measured from which columns each set hears, neither labels nor positions: as :func:`campaign_shift`
    counts them)."""
    ever_t, ever_v = np.isfinite(train.rssi_dbm).any(axis=0), np.isfinite(test.rssi_dbm).any(axis=0)
    top = float((ever_t & ~ever_v).sum() / max(int(ever_t.sum()), 1))
    return sorted({*AP_LOSS_FRACTIONS, round(top, 3)})


def ap_loss(train: FingerprintSet, test: FingerprintSet, ladder: dict, fast: bool = False) -> pd.DataFrame:
    """The spot x PHONEID CV error of three ladder rows (the flat WKNN, the Sorensen row and the headline, the last
    row) with a share of the APs gone at query time (:func:`ilocalg.wifi.model_selection.ap_loss_cv`, over
    :func:`ap_loss_fractions`; seeds 0 and 1, at most 300 test scans a fold). A robustness
    check of an assumption the CVs make (the survey's APs all still there when the phone asks); it chooses nothing.
    Fast mode: fractions 0 and 0.2, seed 0."""
    configs = ladder["configs"]
    names = [n for n, _, _ in configs]
    pick = [configs[0], configs[names.index("toolkit: + Sorensen distance")], configs[-1]]
    if fast:
        out = ap_loss_cv(train, pick, (0.0, 0.2), (0,))
    else:
        out = ap_loss_cv(train, pick, ap_loss_fractions(train, test), (0, 1))
    labels = dict(zip([n for n, _, _ in pick], AP_LOSS_LABELS, strict=True))
    out.insert(1, "label", out["row"].map(labels))
    return out


def ap_loss_findings(table: pd.DataFrame, ladder: pd.DataFrame | None = None) -> list[str]:
    """Sentences generated from ``toolkit_ap_loss`` (:func:`ap_loss`) and, when given, ``toolkit_ladder`` (the same
    rows' validation errors, for the ratio of the headline to the flat WKNN)."""
    top = table["fraction_aps_gone"].max()
    lab = dict(zip(table["row"], table["label"], strict=False))
    rows = list(dict.fromkeys(table["row"]))
    at = table[table["fraction_aps_gone"] == top].set_index("row")
    at0 = table[table["fraction_aps_gone"] == 0.0].set_index("row")
    out = []
    for r in rows:
        out.append(f"{lab[r]}: CV error {at0.loc[r, 'cv_mean_error_m']:.2f} m with every AP, "
                   f"{at.loc[r, 'cv_mean_error_m']:.2f} m with {top:.1%} of them gone "
                   f"({at.loc[r, 'increase_m']:+.2f} m, 95 % interval {at.loc[r, 'increase_ci95_lo_m']:.2f} to "
                   f"{at.loc[r, 'increase_ci95_hi_m']:.2f} over {int(at.loc[r, 'n_folds'])} folds)")
    head = rows[-1]
    ratios = table[table["row"] == head].set_index("fraction_aps_gone")["ratio_to_first_row"]
    line = ("headline / flat WKNN, CV error: " + ", ".join(f"{v:.2f} with {f:.1%} gone" for f, v in ratios.items()))
    if ladder is not None:
        m = ladder.set_index("method")["mean_m"]
        if head in m.index and rows[0] in m.index:
            val = m.loc[head] / m.loc[rows[0]]
            near = min(ratios.index, key=lambda f: abs(ratios.loc[f] - val))
            line += (f"; on validation {val:.2f}, nearest the CV ratio with {near:.1%} of the APs gone"
                     + (" (no sign on validation of the flat WKNN's larger loss when APs are gone)"
                        if near == 0.0 else ""))
    out.append(line)
    return out


def cli_headline(ladder: dict) -> pd.DataFrame:
    """Whether ``python -m ilocalg evaluate wifi --method toolkit`` runs the ladder's headline: the last row's members
    and K (as :func:`ilocalg.wifi.model_selection.toolkit_ladder` fitted them) beside
    :data:`ilocalg.wifi.candidates.TOOLKIT_HEADLINE` (what the command builds). One row; ``same`` False when
    the CV's choice has moved away from the command's configuration (fast mode's smaller grids, a changed grid)."""
    method, members, _ = ladder["configs"][-1]
    names, ks = zip(*(m.rsplit("@K", 1) for m, _ in members), strict=True)
    k = sorted({int(v) for v in ks})
    return pd.DataFrame([{
        "command": "python -m ilocalg evaluate wifi --train TRAIN --test TEST --method toolkit",
        "ladder_row": method, "ladder_n_neighbors": ", ".join(map(str, k)), "ladder_members": " + ".join(names),
        "command_n_neighbors": str(TOOLKIT_HEADLINE["n_neighbors"]),
        "command_members": " + ".join(TOOLKIT_HEADLINE["members"]),
        "same": tuple(names) == tuple(TOOLKIT_HEADLINE["members"]) and k == [TOOLKIT_HEADLINE["n_neighbors"]]}])


def budget_findings(budget: pd.DataFrame) -> list[str]:
    """Sentences generated from ``toolkit_error_budget`` (:func:`ilocalg.wifi.evaluate.error_budget`)."""
    b = budget.set_index("group")
    out = []
    allr = b.loc["all located scans"]
    hit, miss = b.loc["floor hit"], b.loc["floor missed"]
    out.append(f"floor misses: {miss['share_of_scans']:.1%} of the scans, {miss['share_of_total_error']:.1%} of the "
               f"total error (mean {miss['mean_error_m']:.2f} m against {hit['mean_error_m']:.2f} m on the right "
               "floor)")
    if "phone not seen in training" in b.index:
        s, u = b.loc["phone seen in training"], b.loc["phone not seen in training"]
        sw = b.loc["phone seen, floor-weighted (floors with both)", "mean_error_m"]
        uw = b.loc["phone not seen, floor-weighted (floors with both)", "mean_error_m"]
        n_all, n_u = allr["n"], u["n"]
        what_if = (allr["mean_error_m"] * n_all - u["mean_error_m"] * n_u + sw * n_u) / n_all
        out.append(f"phones the survey never used: {u['share_of_scans']:.1%} of the scans, mean "
                   f"{u['mean_error_m']:.2f} m "
                   f"against {s['mean_error_m']:.2f} m for its phones ({uw:.2f} against {sw:.2f} m weighted floor by "
                   f"floor); were the unseen phones' scans as good as the seen phones' on the same floors, the mean "
                   f"would be about {what_if:.2f} m (a what-if, not a result)")
    near = b.loc["nearest training reference < 2 m"]
    bound = b.loc["bound: nearest training reference", "mean_error_m"]
    bound3 = b.loc["bound: mean of the 3 nearest references", "mean_error_m"]
    out.append(f"coverage: {near['share_of_scans']:.1%} of the scans lie within 2 m of a training reference on their "
               f"floor and still err by {near['mean_error_m']:.2f} m on average; always picking the nearest "
               f"reference would err by {bound:.2f} m, averaging the 3 nearest by {bound3:.2f} m"
               + (", so most of the error is the radio match, not the survey's coverage"
                  if near["mean_error_m"] > 2 * bound3 else ""))
    far = b.loc[[g for g in b.index if g.startswith("error >")][0]]
    out.append(f"the largest errors ({far.name}): {far['share_of_scans']:.1%} of the scans carry "
               f"{far['share_of_total_error']:.1%} of the total error")
    return out
