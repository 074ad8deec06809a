"""Model selection and scoring of fingerprint estimators on a training / test split.

* :func:`metrics_row`: error statistics (projected and ground metres) and hit rates of one result;
* :func:`selection_mask`, :func:`best_search`: candidate configurations scored on a seeded selection
  half of the test set and on the other, held-out half;
* :class:`SubsampledGroupKFold`, :func:`toolkit_cv`: parameters chosen by GroupKFold cross-validation on
  the training set only (groups: a meta column such as USERID or PHONEID);
* :func:`toolkit_ladder`: what each toolkit step buys, fitted on training only, scored on the test set
  with a 95 % percentile-bootstrap interval of the mean error (:func:`bootstrap_mean_ci`).

The experiment ``wifi_ujiindoorloc`` applies them to the UJIIndoorLoc official split.

References
----------
Torres-Sospedra, J. et al. (2015). Comprehensive analysis of distance and similarity measures for
Wi-Fi fingerprinting indoor positioning systems. Expert Systems with Applications 42(23).
Tsui, A. W., Chuang, Y.-H., Chu, H.-H. (2009). Unsupervised learning for solving RSS hardware variance
problem in WiFi localization. Mobile Networks and Applications 14(5).
Efron, B. & Tibshirani, R. (1993). An Introduction to the Bootstrap, ch. 13 (percentile interval).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.io.schema import FingerprintSet
from ilocalg.io.ujiindoorloc import WEAKEST_DBM, ground_scale
from ilocalg.metrics import hit_rate
from ilocalg.wifi.candidates import (  # noqa: F401 (re-exported: the grids the CVs below choose among)
    HEADLINE_NEIGHBORS,
    SPOT_NEIGHBORS,
    SPOT_WEIGHT_POWERS,
    TOOLKIT_HEADLINE,
    ensemble_grid,
    ensemble_members,
    ensemble_pipeline,
    headline_grid,
    headline_members,
    offset_grid,
    offset_range_grid,
    offset_shifts_db,
    spot_grid,
    toolkit_estimator,
)
from ilocalg.wifi.evaluate import evaluate_method, nearest_same_floor
from ilocalg.wifi.hierarchical import locate_flat
from ilocalg.wifi.knn import KnnFingerprint, neighbour_weights, smallest_k, vote
from ilocalg.wifi.radar import union_topk_sq_distances

__all__ = [
    "metrics_row",
    "selection_mask",
    "best_search",
    "TOOLKIT_GRID",
    "TOOLKIT_GRID_FAST",
    "SubsampledGroupKFold",
    "SpotPhoneKFold",
    "SPOT_PHONE",
    "group_cv",
    "toolkit_cv",
    "toolkit_ladder",
    "bootstrap_mean_ci",
    "offset_shifts_db",
    "offset_grid",
    "ensemble_members",
    "ensemble_grid",
    "ensemble_pipeline",
    "ensemble_cv",
    "offset_range_grid",
    "SPOT_WEIGHT_POWERS",
    "SPOT_NEIGHBORS",
    "spot_grid",
    "HEADLINE_NEIGHBORS",
    "headline_grid",
    "headline_cv",
    "TOOLKIT_HEADLINE",
    "headline_members",
    "toolkit_estimator",
    "fit_members",
    "rows_cv",
    "drop_aps",
    "ap_loss_cv",
    "ladder_cv_diagnostic",
    "with_device_calibration",
    "device_calibration_cv",
]


def metrics_row(res: dict, test: FingerprintSet, rows=None) -> dict:
    """Error statistics (projected and ground metres) and hit rates of one result.

    A scan sharing no access point with the references it is compared with has no position (NaN, the
    estimators' documented no-AP result): it is counted in ``n_unlocated``, left out of the error
    statistics and counted as a miss in the hit rates.
    """
    rows = np.arange(test.n_samples) if rows is None else np.asarray(rows)
    e_all = res["error_m"][rows]
    located = np.isfinite(e_all)
    e = e_all[located]
    eg = e * ground_scale(test.y_m[rows][located])
    return {
        "n": int(e_all.size),
        "n_unlocated": int((~located).sum()),
        "mean_m": float(np.mean(e)),
        "median_m": float(np.median(e)),
        "p75_m": float(np.percentile(e, 75)),
        "p95_m": float(np.percentile(e, 95)),
        "mean_ground_m": float(np.mean(eg)),
        "median_ground_m": float(np.median(eg)),
        "floor_hit_rate": hit_rate(res["floor"][rows], test.floor[rows]),
        "building_hit_rate": hit_rate(res["building"][rows], test.building[rows]),
    }


def selection_mask(n: int, seed: int = 0) -> np.ndarray:
    """Boolean mask of the selection half (seeded random half of the validation rows)."""
    perm = np.random.default_rng(seed).permutation(n)
    m = np.zeros(n, dtype=bool)
    m[perm[: n // 2]] = True
    return m


def _score(xy, fl, bd, test, sel):
    e = np.hypot(xy[:, 0] - test.x_m, xy[:, 1] - test.y_m)
    out = {}
    for tag, m in (("selection", sel), ("heldout", ~sel)):
        out[f"{tag}_mean_m"] = float(e[m].mean())
        out[f"{tag}_floor_hit_rate"] = hit_rate(fl[m], test.floor[m])
        out[f"{tag}_building_hit_rate"] = hit_rate(bd[m], test.building[m])
    return out


def best_search(train: FingerprintSet, test: FingerprintSet, seed: int = 0, k_aps_values=(3, 5, 8),
                n_neighbors_values=(3, 5, 8, 12), knn_k_values=(5, 8)) -> pd.DataFrame:
    """Score candidate configurations on the selection half and the held-out half.

    Candidates: Simplified-RADAR union distance for each (k_aps, N) with 1/d^2 weights; WKNN
    (Euclidean, 1/d weights) in the positive / exponential / powed representations for each K.
    Sorted by selection-half mean error; the first row is the configuration to use.
    """
    sel = selection_mask(test.n_samples, seed)
    rows = []
    for ka in k_aps_values:
        d2 = union_topk_sq_distances(test.rssi_dbm, train.rssi_dbm, ka, WEAKEST_DBM)
        for n in n_neighbors_values:
            idx = smallest_k(d2, n)
            w = neighbour_weights(np.sqrt(np.take_along_axis(d2, idx, axis=1).astype(np.float64)), "distance", 2.0)
            xy = np.einsum("qk,qkd->qd", w, train.xy_m[idx])
            rows.append({"config": f"radar k_aps={ka} N={n}", "kind": "radar", "k_aps": ka, "n_neighbors": n,
                         "representation": "dBm",
                         **_score(xy, vote(train.floor[idx], w), vote(train.building[idx], w), test, sel)})
    for rep in ("positive", "exponential", "powed"):
        for k in knn_k_values:
            est = KnnFingerprint(k, p=2, weights="distance", representation=rep).fit(train.rssi_dbm, train.xy_m)
            df = locate_flat(est, test.rssi_dbm, train.floor, train.building)
            rows.append({"config": f"wknn {rep} K={k}", "kind": "wknn", "k_aps": 0, "n_neighbors": k,
                         "representation": rep,
                         **_score(df[["x_m", "y_m"]].to_numpy(), df["floor"].to_numpy(), df["building"].to_numpy(),
                                  test, sel)})
    return pd.DataFrame(rows).sort_values("selection_mean_m", kind="stable").reset_index(drop=True)


# Toolkit ladder (beyond the papers)
# ----------------------------------
#: Candidates the cross-validation on the training set chooses among (Torres-Sospedra et al. 2015:
#: data representations and distances; K of the position WKNN). Pruned for time: the Euclidean candidates
#: and K=3 ranked 9th-16th and 3rd/8th in the full GroupKFold(USERID) grid (the Euclidean ones 3 m
#: behind), which chose positive, Sorensen, K=8; the pruned grid chooses the same.
TOOLKIT_GRID = {"representation": ["positive", "powed"], "metric": ["sorensen"], "n_neighbors": [5, 8, 12]}
TOOLKIT_GRID_FAST = {"representation": ["positive", "powed"], "metric": ["minkowski", "sorensen"],
                     "n_neighbors": [5]}


def ensemble_cv(train: FingerprintSet, grid: dict, n_neighbors: int, seed: int = 0, n_splits: int = 3,
                max_test: int = 300, group: str = "PHONEID", cache: dict | None = None) -> tuple[dict, pd.DataFrame]:
    """:func:`toolkit_cv` of :func:`ensemble_pipeline` over ``grid`` (``{"est__estimators": [members, ...]}``),
    with each distinct member fitted once per fold: a candidate's fold score is
    :func:`ilocalg.wifi.ensemble.combine_predictions` of its members' fold predictions, which is what the
    pipeline's ``predict`` returns. ``group``: as :func:`toolkit_cv` (a meta column, or :data:`SPOT_PHONE`). Same
    folds, scorer, table and choice (first of the best rank) as
    ``toolkit_cv(train, seed, group=group, max_test=max_test, estimator=ensemble_pipeline(n_neighbors),
    grid=grid)`` (a test checks the equality); the members shared by the candidates are not refitted.
    ``cache`` (a dict, filled in place): fold predictions by (fold setting, fold, member name), so that a second
    call on the same training set reuses the members the first one fitted (a member's name must then stand for
    one configuration).
    """
    return _ensemble_cv_at(train, grid, (n_neighbors,), seed, n_splits, max_test, group, cache)[0]


def _ensemble_cv_at(train: FingerprintSet, grid: dict, ks, seed: int = 0, n_splits: int = 3, max_test: int = 300,
                    group: str = "PHONEID", cache: dict | None = None) -> list[tuple[dict, pd.DataFrame]]:
    """``[ensemble_cv(train, grid, k, ...) for k in ks]``, each member fitted once per fold for every K
    (:func:`_fit_members_at`): the same tables and choices, and the same ``cache`` entries."""
    from scipy.stats import rankdata

    from ilocalg.metrics import mean_horizontal_error_m
    from ilocalg.wifi.ensemble import ApSelector, combine_predictions

    ks = list(ks)
    cands = list(grid["est__estimators"])
    groups = _cv_groups(train, group)
    cv = group_cv(group, min(n_splits, len(np.unique(groups))), max_test, seed)
    y = _target(train)
    scores = np.empty((len(ks), len(cands), cv.get_n_splits()))
    for f, (tr, te) in enumerate(cv.split(train.rssi_dbm, y, groups)):
        aps = ApSelector(1).fit(train.rssi_dbm[tr])
        x_tr, x_te = aps.transform(train.rssi_dbm[tr]), aps.transform(train.rssi_dbm[te])
        preds, need = {k: {} for k in ks}, {}
        for members in cands:
            for name, est in members:
                for k in ks:
                    key = (group, n_splits, max_test, seed, k, f, name)
                    if name in preds[k] or name in need:
                        continue
                    if cache is not None and key in cache:
                        preds[k][name] = cache[key]
                    else:
                        need[name] = est
        new = _fit_members_at(list(need.items()), x_tr, y[tr], x_te, ks, _query_meta(train, te))
        for k in ks:
            got = {n: v for n, v in new[k].items() if n not in preds[k]}
            preds[k].update(got)
            if cache is not None:
                cache.update({(group, n_splits, max_test, seed, k, f, n): v for n, v in got.items()})
            for c, members in enumerate(cands):
                scores[ks.index(k), c, f] = -mean_horizontal_error_m(
                    y[te], combine_predictions([preds[k][n] for n, _ in members]))
    out = []
    for i in range(len(ks)):
        mean = scores[i].mean(axis=1)
        rank = rankdata(-mean, method="min").astype(np.int32)
        table = pd.DataFrame({"groups": group, "estimators": [_fmt(m) for m in cands], "cv_mean_error_m": -mean,
                              "cv_sd_m": scores[i].std(axis=1), "rank": rank})
        out.append(({"est__estimators": cands[int(np.argmin(rank))]},
                    table.sort_values("rank", kind="stable").reset_index(drop=True)))
    return out


def rows_cv(train: FingerprintSet, rows, group: str = "PHONEID", seed: int = 0, n_splits: int = 3,
            max_test: int = 300, drop_ap_fraction: float = 0.0) -> pd.DataFrame:
    """CV mean error of fixed configurations (no choice): each row's estimator fitted on every fold's training part.

    ``rows``: ``(name, members, aps)`` with ``members`` a list of ``(member name, estimator)`` (one member: that
    estimator; several: their :func:`ilocalg.wifi.ensemble.combine_predictions`, as
    :class:`ilocalg.wifi.FingerprintEnsemble`; each member keeps its own K) and ``aps`` whether
    :class:`ilocalg.wifi.ApSelector` (``min_count=1``) comes first. A member name must stand for one configuration
    (members of the same name are fitted once per fold and AP setting). Folds as :func:`ensemble_cv` with the same
    ``group``, ``n_splits``, ``max_test`` and ``seed``. ``drop_ap_fraction``: the share of access points gone by
    the time of the queries (:func:`drop_aps`; 0: none). Returns one row per configuration: ``groups``, ``row``,
    ``cv_mean_error_m``, ``cv_sd_m`` (over folds).
    """
    rows = list(rows)
    scores = _rows_cv_scores(train, rows, group, seed, n_splits, max_test, (drop_ap_fraction,))[0]
    return pd.DataFrame({"groups": group, "row": [n for n, _, _ in rows], "cv_mean_error_m": scores.mean(axis=1),
                         "cv_sd_m": scores.std(axis=1)})


def drop_aps(x_query: np.ndarray, fraction: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Queries as if a random ``fraction`` of the access points had been removed after the survey.

    Each column (access point) is gone with probability ``fraction``, drawn from ``rng``; a gone AP's readings
    become NaN (not heard) in every query. Returns the new query matrix and the boolean mask of the gone columns.
    The survey (training) side is left as it was: its scans still hear those APs, as a radio map that has aged.
    """
    if not 0.0 <= fraction < 1.0:
        raise ValueError(f"drop_ap_fraction must lie in [0, 1), got {fraction}")
    gone = rng.random(x_query.shape[1]) < fraction
    out = np.array(x_query, dtype=np.float64, copy=True)
    out[:, gone] = np.nan
    return out, gone


def _rows_cv_scores(train: FingerprintSet, rows, group: str, seed: int, n_splits: int, max_test: int,
                    fractions=(0.0,)) -> np.ndarray:
    """:func:`rows_cv`'s mean error per share of APs gone, row and fold, shape ``(len(fractions), len(rows),
    n_folds)``. The APs gone in fold ``f`` (:func:`drop_aps`) are drawn from ``default_rng((seed, f))``, the same for
    every row and, draw for draw, for every share (a larger share loses the smaller one's APs and more). Each
    member is fitted once per fold and AP setting and predicts the queries of every share at once, unless it
    calibrates per device (its phones' scans in time order; then once per share): the same values as one
    :func:`rows_cv` per share."""
    from ilocalg.metrics import mean_horizontal_error_m
    from ilocalg.wifi.ensemble import ApSelector, combine_predictions, wants_devices

    fractions = [float(fr) for fr in fractions]
    groups = _cv_groups(train, group)
    cv = group_cv(group, min(n_splits, len(np.unique(groups))), max_test, seed)
    y = _target(train)
    scores = np.empty((len(fractions), len(rows), cv.get_n_splits()))
    for f, (tr, te) in enumerate(cv.split(train.rssi_dbm, y, groups)):
        x_q = train.rssi_dbm[te]
        queries = [x_q if fr == 0 else drop_aps(x_q, fr, np.random.default_rng((seed, f)))[0] for fr in fractions]
        preds: list[dict] = [{} for _ in fractions]
        for aps in sorted({bool(a) for _, _, a in rows}):
            x_tr, xs = train.rssi_dbm[tr], queries
            if aps:
                sel = ApSelector(1).fit(x_tr)
                x_tr, xs = sel.transform(x_tr), [sel.transform(q) for q in xs]
            need = {n: e for _, members, a in rows if bool(a) == aps for n, e in members}
            alone = {n: e for n, e in need.items() if wants_devices(e)}
            shared = [(n, e) for n, e in need.items() if n not in alone]
            if shared:
                got = fit_members(shared, x_tr, y[tr], np.vstack(xs), None)
                for n, v in got.items():
                    for q, part in enumerate(np.split(v, len(xs))):
                        preds[q][(n, aps)] = part
            for q, x_te in enumerate(xs):
                if alone:
                    preds[q].update({(n, aps): v for n, v in fit_members(list(alone.items()), x_tr, y[tr], x_te,
                                                                          None, _query_meta(train, te)).items()})
        for q in range(len(fractions)):
            for r, (_, members, aps) in enumerate(rows):
                scores[q, r, f] = mean_horizontal_error_m(y[te], combine_predictions([preds[q][(n, bool(aps))]
                                                                                      for n, _ in members]))
    return scores


def ap_loss_cv(train: FingerprintSet, rows, fractions=(0.0, 0.1, 0.2), seeds=(0, 1),
               group: str | None = None, max_test: int = 300) -> pd.DataFrame:
    """How each fixed configuration's CV error grows when access points are gone by the time of the queries.

    A robustness check of the CV's silent assumption that the survey's APs are all still there (a diagnostic: it
    chooses nothing). For each fraction of ``fractions`` (:func:`drop_aps`, query side only) and each seed, every
    row of ``rows`` (as :func:`rows_cv`) is scored on the same folds. Returns one row per fraction and
    configuration: ``fraction_aps_gone``, ``row``, ``cv_mean_error_m`` (over seeds and folds), ``increase_m``
    (paired against the same folds with no AP gone) and ``increase_sd_m`` (its standard deviation over the
    seeds' and folds' paired differences) with a 95 % Student-t interval over them (``increase_ci95_lo_m``,
    ``increase_ci95_hi_m``; the folds of one seed share training scans, so it is indicative), ``ratio_to_first_row``
    (the row's CV error over the first row's at the same fraction), ``n_folds``. ``group``: the CV kind
    (:func:`group_cv`; default :data:`SPOT_PHONE`).
    """
    from scipy.stats import t as student_t

    group = SPOT_PHONE if group is None else group
    rows = list(rows)
    fractions = [float(f) for f in fractions]
    if 0.0 not in fractions:
        fractions = [0.0] + fractions
    got = np.concatenate([_rows_cv_scores(train, rows, group, s, 3, max_test, fractions) for s in seeds], axis=2)
    per = dict(zip(fractions, got, strict=True))
    out = []
    for fr in fractions:
        d = per[fr] - per[0.0]
        half = student_t.ppf(0.975, d.shape[1] - 1) * d.std(axis=1, ddof=1) / np.sqrt(d.shape[1])
        for r, (name, _, _) in enumerate(rows):
            out.append({"fraction_aps_gone": fr, "row": name, "cv_mean_error_m": float(per[fr][r].mean()),
                        "increase_m": float(d[r].mean()), "increase_sd_m": float(d[r].std(ddof=1)),
                        "increase_ci95_lo_m": float(d[r].mean() - half[r]),
                        "increase_ci95_hi_m": float(d[r].mean() + half[r]),
                        "ratio_to_first_row": float(per[fr][r].mean() / per[fr][0].mean()),
                        "n_folds": int(per[fr].shape[1])})
    return pd.DataFrame(out)


def _weight_power_param(est) -> str | None:
    """The parameter holding ``est``'s neighbour-weight exponent (``weight_power``, or ``estimator__weight_power``
    of a wrapper) when ``est`` can predict several exponents from one search (``predict_weight_powers``)."""
    keys = [k for k in est.get_params(deep=True) if k == "weight_power" or k.endswith("__weight_power")]
    return keys[0] if len(keys) == 1 and hasattr(est, "predict_weight_powers") else None


def fit_members(members, x_tr: np.ndarray, y_tr: np.ndarray, x_te: np.ndarray, n_neighbors: int | None,
                meta: dict | None = None) -> dict:
    """``{name: prediction on x_te}`` of each ``(name, estimator)`` (cloned, ``n_neighbors`` set where it has such a
    parameter, as :class:`ilocalg.wifi.FingerprintEnsemble` does) fitted on ``(x_tr, y_tr)``.

    Members that differ only in their neighbour-weight exponent (:class:`ilocalg.wifi.OffsetFingerprint`'s
    ``weight_power``, also inside :class:`ilocalg.wifi.SpotAveragedFingerprint`) share one fit and one neighbour
    search (``predict_weight_powers``): the same values as fitting each alone. Spot-averaged members
    (:class:`ilocalg.wifi.SpotAveragedFingerprint`) share one :func:`ilocalg.wifi.spots.spot_fingerprints` of
    ``x_tr`` per ``min_heard_fraction`` (what each one's ``fit`` computes). Names must be distinct. ``meta``
    (``{"devices": ..., "times": ...}`` of the rows of ``x_te``) goes to the members that calibrate per device
    (:func:`ilocalg.wifi.ensemble.wants_devices`).
    """
    return _fit_members_at(members, x_tr, y_tr, x_te, (n_neighbors,), meta)[n_neighbors]


def _query_meta(s: FingerprintSet, rows=None) -> dict:
    """Each scan's phone and time (UJIIndoorLoc's PHONEID and TIMESTAMP) for device-calibrated members, or ``{}``
    when the set has no such columns."""
    if s.meta is None or not {"PHONEID", "TIMESTAMP"} <= set(s.meta.columns):
        return {}
    rows = slice(None) if rows is None else rows
    return {"devices": s.meta["PHONEID"].to_numpy()[rows], "times": s.meta["TIMESTAMP"].to_numpy()[rows]}


def _fit_members_at(members, x_tr: np.ndarray, y_tr: np.ndarray, x_te: np.ndarray, ks, meta: dict | None = None
                    ) -> dict:
    """``{k: fit_members(members, x_tr, y_tr, x_te, k)}`` for each ``k`` of ``ks``, each member fitted once: a member
    with ``_at_n_neighbors`` (:class:`ilocalg.wifi.OffsetFingerprint`, :class:`ilocalg.wifi.CascadeFingerprint`:
    their fit does not depend on K) predicts every K from one fit; a member without an ``n_neighbors`` parameter
    (a spot-averaged one keeps its own K) predicts once for all K; any other is fitted per K."""
    from sklearn.base import clone

    from ilocalg.wifi.ensemble import wants_devices
    from ilocalg.wifi.spots import SpotAveragedFingerprint, spot_fingerprints

    ks = list(dict.fromkeys(ks))
    groups: dict = {}
    for name, est in members:
        e = clone(est)
        has_k = ks[0] is not None and "n_neighbors" in e.get_params()
        if has_k:
            e.set_params(n_neighbors=ks[0])
        wk = _weight_power_param(e)
        key = ("alone", name) if wk is None else (type(e).__name__, tuple(sorted(
            (k, repr(v)) for k, v in e.get_params(deep=True).items() if k != wk and not hasattr(v, "get_params"))))
        groups.setdefault(key, []).append((name, e, wk, has_k))
    out: dict = {k: {} for k in ks}
    spots: dict = {}
    for items in groups.values():
        name0, e0, wk, has_k = items[0]
        per_k = has_k and len(ks) > 1 and not (hasattr(e0, "_at_n_neighbors") and all(
            1 <= int(k) <= x_tr.shape[0] for k in ks))
        for j, k in enumerate(ks if per_k else ks[:1]):
            e = clone(e0).set_params(n_neighbors=k) if j else e0
            if isinstance(e, SpotAveragedFingerprint):  # the spot members share one averaging of the same scans
                frac = float(e.min_heard_fraction)
                if frac not in spots:
                    spots[frac] = spot_fingerprints(x_tr, y_tr, frac)
                e._fit_spots(*(a.copy() for a in spots[frac]), x_tr.shape[1])
            else:
                e.fit(x_tr, y_tr)
            got = None
            kw = dict(meta or {}) if wants_devices(e) else {}
            for kk in ([k] if per_k else ks):
                if got is None or has_k:  # without an n_neighbors parameter, one prediction stands for every K
                    view = e._at_n_neighbors(kk) if has_k and not per_k and kk != ks[0] else e
                    if wk is None:
                        got = {name0: view.predict(x_te, **kw)}
                    else:
                        powers = [m.get_params(deep=True)[wk] for _, m, _, _ in items]
                        got = {n: pr for (n, _, _, _), pr in zip(items, view.predict_weight_powers(x_te, powers, **kw),
                                                                 strict=True)}
                out[kk].update(got)
    return out


def _target(s: FingerprintSet) -> np.ndarray:
    return np.column_stack([s.xy_m, s.floor, s.building]).astype(np.float64)


class SubsampledGroupKFold:
    """GroupKFold whose test folds are a seeded subsample of at most ``max_test`` rows (for speed).

    Training parts are whole (every row of the other groups); only the number of scored rows shrinks.
    """

    def __init__(self, n_splits: int = 3, max_test: int = 400, seed: int = 0):
        self.n_splits = n_splits
        self.max_test = max_test
        self.seed = seed

    def get_n_splits(self, X=None, y=None, groups=None) -> int:
        return self.n_splits

    def split(self, X, y=None, groups=None):
        from sklearn.model_selection import GroupKFold

        rng = np.random.default_rng(self.seed)
        for tr, te in GroupKFold(self.n_splits).split(X, y, groups):
            if te.size > self.max_test:
                te = np.sort(rng.choice(te, self.max_test, replace=False))
            yield tr, te


class SpotPhoneKFold(SubsampledGroupKFold):
    """Folds whose test scans were taken at reference spots *and* with phones that the training part never saw.

    Mimics what sets a later campaign apart from the survey (UJIIndoorLoc's validation set: recorded four months
    later by other users, mostly with other phones, at free positions rather than at the survey's reference spots;
    Torres-Sospedra et al. 2014). A spot is a distinct row of the target ``y`` (``[x_m, y_m, floor, building]``);
    the spots are dealt at random (seeded) into ``spot_groups`` groups, the phones (``groups``) into ``n_splits``
    groups by :class:`sklearn.model_selection.GroupKFold`. Fold ``f`` tests the scans whose spot is in spot group
    ``f`` and whose phone is in phone group ``f`` (a seeded subsample of at most ``max_test`` of them) and trains
    on the scans whose spot is not in spot group ``f`` and whose phone is not in phone group ``f``: no test
    position is a reference position of the training part, and no test phone is in it. Each fold drops one spot in
    ``spot_groups`` (default 10: the rest of the survey keeps its density, so that a test position lies between
    reference spots as a free position does) and the phones of one phone group (about ``1 / n_splits`` of them,
    as :class:`SubsampledGroupKFold`). An area only those phones surveyed is lost with them, where no later campaign
    at a surveyed place would be: with ``coverage_quantile`` (default 0.9), a fold scores only the test scans whose
    position lies within the survey's own spot spacing of a training-part reference on the same floor and building
    (the ``coverage_quantile`` quantile, over the survey's spots, of the distance to the nearest other spot of the
    floor; measured on ``y`` itself; UJIIndoorLoc: about 6.3 m). ``None``: every test scan.

    GroupKFold by phone alone (:class:`SubsampledGroupKFold`) scores scans at spots other phones recorded (a
    query then meets references at its own position, which favours spot-averaged fingerprints) and drops whole
    areas only the held-out phones surveyed.
    """

    def __init__(self, n_splits: int = 3, max_test: int = 300, seed: int = 0, spot_groups: int = 10,
                 coverage_quantile: float | None = 0.9):
        super().__init__(n_splits, max_test, seed)
        self.spot_groups = spot_groups
        self.coverage_quantile = coverage_quantile

    def split(self, X, y=None, groups=None):
        from sklearn.model_selection import GroupKFold

        if self.spot_groups < self.n_splits:
            raise ValueError(f"spot_groups={self.spot_groups} must be at least n_splits={self.n_splits}")
        if y is None or groups is None:
            raise ValueError("SpotPhoneKFold needs y (identical rows are one spot) and groups (the phone of each row)")
        yy = np.asarray(y, dtype=np.float64).reshape(len(groups), -1)
        _, spot = np.unique(yy, axis=0, return_inverse=True)
        spot = spot.ravel()
        n_phones, n_spots = len(np.unique(groups)), int(spot.max()) + 1
        if n_phones < self.n_splits or n_spots < self.spot_groups:
            raise ValueError(f"SpotPhoneKFold needs at least n_splits={self.n_splits} phones and spot_groups="
                             f"{self.spot_groups} spots, got {n_phones} phones and {n_spots} spots")
        radius = None
        if self.coverage_quantile is not None:
            u = np.unique(yy, axis=0)
            radius = float(np.quantile(_nearest_reference_m(u, u, exclude_self=True), self.coverage_quantile))
        rng = np.random.default_rng(self.seed)
        spot_fold = (rng.permutation(spot.max() + 1) % self.spot_groups)[spot]
        phone_fold = np.empty(len(groups), dtype=np.int64)
        for f, (_, te) in enumerate(GroupKFold(self.n_splits).split(yy, yy, groups)):
            phone_fold[te] = f
        for f in range(self.n_splits):
            te = np.flatnonzero((spot_fold == f) & (phone_fold == f))
            tr = np.flatnonzero((spot_fold != f) & (phone_fold != f))
            if radius is not None and te.size and tr.size:
                te = te[_nearest_reference_m(yy[tr], yy[te]) <= radius]
            if te.size == 0 or tr.size == 0:
                raise ValueError(f"SpotPhoneKFold fold {f} has no test or no training rows: too few spots or phones "
                                 f"for n_splits={self.n_splits}")
            if te.size > self.max_test:
                te = np.sort(rng.choice(te, self.max_test, replace=False))
            yield tr, te


def _nearest_reference_m(ref: np.ndarray, query: np.ndarray, exclude_self: bool = False) -> np.ndarray:
    """Distance (m) from each ``query`` row's position (columns 0-1) to the nearest ``ref`` position on the same
    floor and building (columns 2-3, where present); inf where that floor has no reference. ``exclude_self``: the
    nearest *other* reference (``query`` rows are distinct rows of ``ref``)."""
    k = 2 if exclude_self else 1
    return nearest_same_floor(ref, query, k)[0][:, k - 1]


def group_cv(kind: str, n_splits: int = 3, max_test: int = 300, seed: int = 0):
    """The CV splitter of a CV ``kind``: ``"PHONEID"`` / ``"USERID"`` (:class:`SubsampledGroupKFold`, grouped by
    that meta column) or ``"spot x PHONEID"`` (:class:`SpotPhoneKFold`, phones from the PHONEID column)."""
    if kind == SPOT_PHONE:
        return SpotPhoneKFold(n_splits, max_test, seed)
    return SubsampledGroupKFold(n_splits, max_test, seed)


#: Name of the :class:`SpotPhoneKFold` CV in tables (``groups`` column) and in :func:`ensemble_cv`'s ``group``.
SPOT_PHONE = "spot x PHONEID"


def _cv_groups(train: FingerprintSet, group: str) -> np.ndarray:
    """The group column of a CV kind (:func:`group_cv`): PHONEID for ``"spot x PHONEID"``."""
    col = "PHONEID" if group == SPOT_PHONE else group
    if train.meta is None or col not in train.meta:
        raise ValueError(f"group must be a meta column of the training set (USERID, PHONEID) or {SPOT_PHONE!r}, "
                         f"got {group!r}")
    return train.meta[col].to_numpy()


def toolkit_cv(train: FingerprintSet, seed: int = 0, fast: bool = False, n_splits: int = 3,
               max_test: int = 400, group: str = "USERID", estimator=None, grid: dict | None = None
               ) -> tuple[dict, pd.DataFrame]:
    """Choose an estimator's parameters by GroupKFold CV on the training set only.

    ``estimator`` / ``grid``: by default the cascade (:class:`ilocalg.wifi.CascadeFingerprint`) over
    :data:`TOOLKIT_GRID` (representation, distance and K). ``group`` is a meta column of the training
    set: ``USERID`` (each fold scores users the fit never saw) or ``PHONEID`` (phones the fit never saw;
    the validation campaign used other phones, four months later), or :data:`SPOT_PHONE` (:class:`SpotPhoneKFold`:
    reference spots and phones the fit never saw, phones from PHONEID). Scoring: minus the mean 2-D error (m).
    Returns the chosen parameters and the CV table (one row per candidate, one column per parameter).
    """
    from sklearn.model_selection import GridSearchCV

    from ilocalg.metrics import horizontal_error_scorer
    from ilocalg.wifi.cascade import CascadeFingerprint

    if grid is None:
        grid = TOOLKIT_GRID_FAST if fast else TOOLKIT_GRID
    estimator = CascadeFingerprint(p=2) if estimator is None else estimator
    groups = _cv_groups(train, group)
    cv = group_cv(group, min(n_splits, len(np.unique(groups))), max_test, seed)
    got = _k_shared_grid_search(estimator, grid, horizontal_error_scorer(), cv, train.rssi_dbm, _target(train), groups)
    if got is None:
        gs = GridSearchCV(estimator, grid, scoring=horizontal_error_scorer(), cv=cv, refit=False)
        gs.fit(train.rssi_dbm, _target(train), groups=groups)
        got = gs.cv_results_, gs.best_params_
    r, best = got
    table = pd.DataFrame({"groups": group, **{k.split("__")[-1]: [_fmt(v) for v in r[f"param_{k}"]] for k in grid},
                          "cv_mean_error_m": -r["mean_test_score"], "cv_sd_m": r["std_test_score"],
                          "rank": r["rank_test_score"]})
    return dict(best), table.sort_values("rank", kind="stable").reset_index(drop=True)


def _k_shared_grid_search(estimator, grid: dict, scorer, cv, X: np.ndarray, y: np.ndarray, groups):
    """``GridSearchCV(estimator, grid, scoring=scorer, cv=cv, refit=False).fit(X, y, groups=groups)``'s
    ``(cv_results_, best_params_)`` (the entries :func:`toolkit_cv` reads: ``param_*``, ``mean_test_score``,
    ``std_test_score``, ``rank_test_score``, the same values) with one fit per fold for the candidates that differ
    only in ``n_neighbors``: each is scored on the fitted estimator's ``_at_n_neighbors(k)`` (the fit of
    :class:`ilocalg.wifi.CascadeFingerprint` and :class:`ilocalg.wifi.OffsetFingerprint` does not depend on K). The
    same candidates (scikit-learn's ParameterGrid order), folds, scorer and statistics as GridSearchCV's
    (``_store``: mean and population sd over the folds, rank of the mean, ties to the smallest rank). ``None``
    (the caller runs GridSearchCV) when the estimator has no ``_at_n_neighbors``, ``grid`` has no ``n_neighbors``,
    a K is outside a fold's training size, or a fit or score fails (GridSearchCV's own handling then applies)."""
    from scipy.stats import rankdata
    from sklearn.base import clone
    from sklearn.model_selection import ParameterGrid

    if not hasattr(estimator, "_at_n_neighbors") or "n_neighbors" not in grid:
        return None
    cands = list(ParameterGrid(grid))
    splits = list(cv.split(X, y, groups))
    if any(not 1 <= int(c["n_neighbors"]) <= len(tr) for c in cands for tr, _ in splits):
        return None
    shared: dict = {}
    for i, c in enumerate(cands):
        shared.setdefault(repr(sorted((k, v) for k, v in c.items() if k != "n_neighbors")), []).append(i)
    scores = np.empty((len(cands), len(splits)))
    try:
        for f, (tr, te) in enumerate(splits):
            x_tr, y_tr, x_te, y_te = X[tr], y[tr], X[te], y[te]
            for members in shared.values():
                est = clone(estimator).set_params(**cands[members[0]]).fit(x_tr, y_tr)
                for i in members:
                    scores[i, f] = scorer(est._at_n_neighbors(cands[i]["n_neighbors"]), x_te, y_te)
    except Exception:  # noqa: BLE001 (GridSearchCV reports it its own way)
        return None
    if not np.isfinite(scores).all():
        return None
    means = np.average(scores, axis=1)
    results = {f"param_{k}": [c[k] for c in cands] for k in grid}
    results.update(mean_test_score=means,
                   std_test_score=np.sqrt(np.average((scores - means[:, np.newaxis]) ** 2, axis=1)),
                   rank_test_score=rankdata(-means, method="min").astype(np.int32, copy=False))
    return results, cands[int(results["rank_test_score"].argmin())]


def _fmt(v):
    """A grid value as a table cell (a tuple of shifts as text, ensemble members by name)."""
    if isinstance(v, list) and v and all(isinstance(m, tuple) and len(m) == 2 for m in v):
        return " + ".join(name for name, _ in v)
    return ", ".join(f"{x:g}" for x in v) if isinstance(v, tuple) else v


def bootstrap_mean_ci(e: np.ndarray, seed: int, n_boot: int = 1000) -> tuple[float, float]:
    """95 % percentile-bootstrap interval of the mean of ``e`` (seeded; one (n_boot, n) resample matrix).

    :func:`ilocalg.measure.bootstrap` draws the same resamples one replicate at a time but sums them in
    another order (its bounds can differ in the last bit), so the ladder keeps this vectorised form.
    """
    rng = np.random.default_rng(seed)
    m = e[rng.integers(0, e.size, (n_boot, e.size))].mean(axis=1)
    return float(np.percentile(m, 2.5)), float(np.percentile(m, 97.5))


def toolkit_ladder(train: FingerprintSet, test: FingerprintSet, seed: int = 0, fast: bool = False,
                   cv_groups: tuple[str, ...] = ("USERID",), offset: bool = True, ensemble: bool = True,
                   offset_range: bool = True, spots: bool = True, headline: bool = True,
                   device_calibration: bool = True) -> dict:
    """What each toolkit step buys, fitted on training only and scored on validation.

    Rows (each adds one step to the previous): flat WKNN K=5 (Euclidean, dBm); building -> floor ->
    position cascade; powed representation; Sorensen distance (the order of Torres-Sospedra et al.
    2015's comparison, each at K=5); then, per entry of ``cv_groups``, representation, distance and K
    chosen by GroupKFold CV on the training set grouped by that meta column (:func:`toolkit_cv`).
    Grouping by ``PHONEID`` instead of ``USERID`` picks the same configuration on the full set
    (positive, Sorensen, K=8), so one CV is run by default.

    With ``offset``, two rows of :class:`ilocalg.wifi.OffsetFingerprint` (flat WKNN with a per-query
    device offset search over :func:`offset_shifts_db`): the Sorensen row's setting plus the search, and
    the representation, search and K chosen by GroupKFold(PHONEID) CV on training (:func:`offset_grid`;
    phones are what the search is for, and the validation campaign used phones the survey never saw).

    With ``ensemble`` (and ``offset``), three more rows: the offset row with AP selection
    (:class:`ilocalg.wifi.ApSelector`, APs never heard in training dropped); the mean of three members
    (:func:`ensemble_members`: offset search on powed data, cascade on powed data, offset search on
    exponential data; floor and building by majority, :class:`ilocalg.wifi.FingerprintEnsemble`), at K=5;
    and the members chosen by GroupKFold(PHONEID) CV on training (:func:`ensemble_grid`) at the K of the
    offset-search CV. Each member is fitted once per K and its predictions reused across rows
    (:func:`ilocalg.wifi.ensemble.combine_predictions` is what the ensemble's ``predict`` returns).

    With ``offset_range`` (and ``ensemble``), one more row, the last: the offset search's range (+-1 or +-2 sd of
    the measured per-phone offset) and the members chosen together by the same GroupKFold(PHONEID) CV on training
    (:func:`offset_range_grid`, at the same K; the folds' member predictions shared with the previous CV). Its
    CV rows carry ``grid = "offset range x members"``.

    With ``spots`` (and ``offset_range``), one more row, the last: the offset-range row's members plus the same
    searches fitted on the per-spot mean fingerprints (:class:`ilocalg.wifi.SpotAveragedFingerprint`, "raw +
    averaged"), the spot members' K and the neighbour-weight exponent chosen by the same GroupKFold(PHONEID) CV
    on training (:func:`spot_grid`; candidates without spot members included; fold predictions shared with the
    earlier CVs). Its CV rows carry ``grid = "spots x weight exponent"``.

    With ``headline`` (and ``spots``), one more row, the last and the headline: the members, search range, spot
    members, weight exponent and K chosen among :func:`headline_grid`'s candidates at each K of
    :data:`HEADLINE_NEIGHBORS` by the spot x PHONEID CV (:class:`SpotPhoneKFold`: each fold scores scans at reference
    spots and with phones its training part never saw, at places the rest of the survey covers), the CV that mimics
    a later campaign at free positions. Its CV rows carry ``groups = "spot x PHONEID"``, ``grid = "headline
    candidates"`` and their K; ``rank`` is over both K.

    With ``device_calibration`` (and ``headline``), one more row, the last and the headline: the headline's members
    with or without the per-device calibration of their offset searches (:func:`device_calibration_cv`; each scan's
    shift pooled over its phone's scans so far, :func:`ilocalg.wifi.offset.device_shift_choice`), the choice made by
    the same spot x PHONEID CV (test phones unseen, their scans in time order). Its CV rows carry ``grid = "device
    calibration"``. Only when both sets have the PHONEID and TIMESTAMP meta columns.
    """
    from ilocalg.wifi.cascade import CascadeFingerprint
    from ilocalg.wifi.ensemble import ApSelector, combine_predictions
    from ilocalg.wifi.offset import OffsetFingerprint

    cvs = [toolkit_cv(train, seed, fast, group=g) for g in cv_groups]
    steps = [
        ("toolkit: flat WKNN K=5 (Euclidean, dBm)", None),
        ("toolkit: + building -> floor -> position cascade", dict(representation="positive", metric="minkowski")),
        ("toolkit: + powed RSSI", dict(representation="powed", metric="minkowski")),
        ("toolkit: + Sorensen distance", dict(representation="powed", metric="sorensen")),
        *[(f"toolkit: + representation, distance, K by GroupKFold({g}) CV", best)
          for g, (best, _) in zip(cv_groups, cvs, strict=True)],
    ]
    if offset:
        off_best, off_table = toolkit_cv(train, seed, fast, group="PHONEID", max_test=300,  # 300: for time
                                         estimator=OffsetFingerprint(), grid=offset_grid(fast))
        cvs.append((off_best, off_table))
        steps += [
            ("toolkit: flat powed Sorensen WKNN + per-query device offset search",
             dict(estimator="offset", representation="powed", metric="sorensen", shifts_db=offset_shifts_db())),
            ("toolkit: offset search, representation, K by GroupKFold(PHONEID) CV",
             dict(estimator="offset", metric="sorensen", **off_best)),
        ]
    cv_table = pd.concat([t for _, t in cvs], ignore_index=True)
    rows, res_by, configs = [], {}, []
    for i, (name, par) in enumerate(steps):
        if par is None:
            res = evaluate_method(train, test, "wknn", 5, "euclidean")
            # the same neighbours and positions (Euclidean distances ignore the representation's offset)
            est = OffsetFingerprint(5, (0.0,), "positive", "minkowski", p=2)
        else:
            kw = {"n_neighbors": 5, **par}
            est = (OffsetFingerprint(**{k: v for k, v in kw.items() if k != "estimator"}) if
                   kw.get("estimator") == "offset" else CascadeFingerprint(p=2, **kw))
            res = _prediction_result(est.fit(train.rssi_dbm, _target(train)).predict(test.rssi_dbm), test)
        configs.append((name, [(f"row{i}", est)], False))
        res_by[name] = res
        rows.append(_ladder_row(name, res, test, seed, "" if par is None else ", ".join(
            f"{k}={_fmt(v)}" for k, v in {"n_neighbors": 5, **par}.items() if k != "estimator")))
    if offset and ensemble:
        k_cv = int(off_best.get("n_neighbors", 5))
        cache: dict = {}
        ens_best, ens_table = ensemble_cv(train, ensemble_grid(fast), k_cv, seed, max_test=300,  # 300: for time
                                          cache=cache)
        cv_table = pd.concat([cv_table, ens_table], ignore_index=True)
        chosen = ens_best["est__estimators"]
        ranged = spotted = None
        if offset_range:
            rng_best, rng_table = ensemble_cv(train, offset_range_grid(fast), k_cv, seed, max_test=300, cache=cache)
            cv_table = pd.concat([cv_table, rng_table.assign(grid="offset range x members")], ignore_index=True)
            ranged = rng_best["est__estimators"]
            if spots:
                sp_best, sp_table = ensemble_cv(train, spot_grid(ranged, fast), k_cv, seed, max_test=300, cache=cache)
                cv_table = pd.concat([cv_table, sp_table.assign(grid="spots x weight exponent")], ignore_index=True)
                spotted = sp_best["est__estimators"]
        top = None
        if offset_range and spots and headline:
            top, hl_table = headline_cv(train, seed, fast, cache)
            cv_table = pd.concat([cv_table, hl_table], ignore_index=True)
        for name, pr, par, k, members in _ensemble_rows(train, test, k_cv, chosen, ranged, spotted, top):
            res_by[name] = res = _prediction_result(pr, test)
            rows.append(_ladder_row(name, res, test, seed, par))
            configs.append((name, [(f"{n}@K{k}", _with_k(e, k)) for n, e in members], True))
        if top is not None and device_calibration and _query_meta(train) and _query_meta(test):
            k_top, members = top
            on, dc_table = device_calibration_cv(train, [(n, _with_k(e, k_top)) for n, e in members], seed)
            cv_table = pd.concat([cv_table, dc_table], ignore_index=True)
            use = with_device_calibration(members) if on else members
            aps = ApSelector(1).fit(train.rssi_dbm)
            got = fit_members(use, aps.transform(train.rssi_dbm), _target(train), aps.transform(test.rssi_dbm),
                              k_top, _query_meta(test))
            name = ("toolkit: + per-device calibration from the phone's own earlier scans (on / off by spot x "
                    "PHONEID CV)")
            res_by[name] = res = _prediction_result(combine_predictions([got[n] for n, _ in use]), test)
            rows.append(_ladder_row(name, res, test, seed, f"device_calibration={'on' if on else 'off'}, "
                                    f"n_neighbors={k_top}, min_count=1, members={_fmt(use)}"))
            configs.append((name, [(f"{n}@K{k_top}", _with_k(e, k_top)) for n, e in use], True))
    return {"toolkit_ladder": pd.DataFrame(rows), "toolkit_cv": cv_table, "results": res_by, "configs": configs}


def with_device_calibration(members) -> list:
    """``members`` with every offset search calibrated per device (``device_calibration=True`` where an estimator,
    or the estimator inside it, has that parameter; those members' names gain ``_dev``); the others unchanged."""
    from sklearn.base import clone

    from ilocalg.wifi.ensemble import device_calibration_keys

    out = []
    for n, e in members:
        keys = device_calibration_keys(e)
        out.append((f"{n}_dev", clone(e).set_params(**dict.fromkeys(keys, True))) if keys else (n, e))
    return out


def device_calibration_cv(train: FingerprintSet, members, seed: int = 0, n_splits: int = 3, max_test: int = 300
                          ) -> tuple[bool, pd.DataFrame]:
    """Whether per-device calibration (:func:`with_device_calibration`) lowers the spot x PHONEID CV error of the
    ensemble ``members`` (each with its own K): :func:`rows_cv` of the members as they are and calibrated, on the
    same folds (each fold's test phones unseen in its training part; each test scan calibrated from its phone's
    test scans up to its time). Returns the choice (True when the calibrated CV mean error is smaller) and the CV
    table (``grid = "device calibration"``, ``device_calibration``, ``rank``)."""
    dev = with_device_calibration(members)
    t = rows_cv(train, [("off", members, True), ("on", dev, True)], SPOT_PHONE, seed, n_splits, max_test)
    t = t.rename(columns={"row": "device_calibration"}).assign(grid="device calibration", estimators=[
        _fmt(members), _fmt(dev)])
    t["rank"] = t["cv_mean_error_m"].rank(method="min").astype(np.int32)
    on = bool(t["cv_mean_error_m"].iloc[1] < t["cv_mean_error_m"].iloc[0])
    return on, t.sort_values("rank", kind="stable").reset_index(drop=True)


def _with_k(est, k: int):
    """A clone of ``est`` with ``n_neighbors=k`` where it has that parameter (as :func:`fit_members` sets it)."""
    from sklearn.base import clone

    e = clone(est)
    return e.set_params(n_neighbors=k) if "n_neighbors" in e.get_params() else e


def ladder_cv_diagnostic(train: FingerprintSet, ladder: dict, seed: int = 0,
                         groups: tuple[str, ...] = ("PHONEID", SPOT_PHONE)) -> tuple[pd.DataFrame, pd.DataFrame]:
    """How well each CV ranks the ladder's rows as the test set does: a diagnostic of the CV, used to choose nothing.

    Every row of :func:`toolkit_ladder`'s result ``ladder`` (its configuration as fitted, ``ladder["configs"]``) is
    scored by :func:`rows_cv` under each CV of ``groups``, beside its test-set mean error. Returns the long table
    (``row``, ``groups``, ``cv_mean_error_m``, ``cv_sd_m``, ``test_mean_m``) and one row per CV with Spearman's
    rank correlation between CV and test errors over all rows and over the rows from the offset search on
    (``spearman_all``, ``spearman_offset_rows``: the rows the CVs chose among).
    """
    from scipy.stats import spearmanr

    test_mean = ladder["toolkit_ladder"].set_index("method")["mean_m"]
    long = pd.concat([rows_cv(train, ladder["configs"], g, seed) for g in groups], ignore_index=True)
    long["test_mean_m"] = test_mean.loc[long["row"]].to_numpy()
    first_offset = next((i for i, (n, _, _) in enumerate(ladder["configs"]) if "offset search" in n),
                        len(ladder["configs"]))
    summary = []
    for g, t in long.groupby("groups", sort=False):
        off = t.iloc[first_offset:]
        summary.append({"groups": g, "spearman_all": float(spearmanr(t["cv_mean_error_m"], t["test_mean_m"])[0]),
                        "spearman_offset_rows": float(spearmanr(off["cv_mean_error_m"], off["test_mean_m"])[0])
                        if len(off) > 2 else np.nan, "n_rows": len(t)})
    return long, pd.DataFrame(summary)


def _prediction_result(pr: np.ndarray, test: FingerprintSet) -> dict:
    """2-D error, floor and building of a cascade-style prediction (n, 4: x, y, floor, building)."""
    return {"error_m": np.hypot(pr[:, 0] - test.x_m, pr[:, 1] - test.y_m), "floor": pr[:, 2], "building": pr[:, 3]}


def _ladder_row(name: str, res: dict, test: FingerprintSet, seed: int, params: str) -> dict:
    """One ladder row: the metrics of ``res``, a bootstrap interval of its mean error and the row's parameters."""
    e = res["error_m"][np.isfinite(res["error_m"])]
    lo, hi = bootstrap_mean_ci(e, seed)
    return {"method": name, **metrics_row(res, test), "mean_ci95_lo_m": lo, "mean_ci95_hi_m": hi, "params": params}


def headline_cv(train: FingerprintSet, seed: int = 0, fast: bool = False, cache: dict | None = None
                ) -> tuple[tuple[int, list], pd.DataFrame]:
    """The headline row's choice: :func:`headline_grid`'s candidates at each K of :data:`HEADLINE_NEIGHBORS` (fast
    mode: K = 5) scored by :func:`ensemble_cv` with the spot x PHONEID CV (:class:`SpotPhoneKFold`, 300 test scans
    per fold); the smallest CV mean error wins (ties: the first K, then the first candidate). Returns ``(K,
    members)`` and the CV table (``grid = "headline candidates"``, ``n_neighbors``, ``rank`` over every K)."""
    from scipy.stats import rankdata

    tables, best = [], None
    ks = (5,) if fast else HEADLINE_NEIGHBORS
    for k, (b, t) in zip(ks, _ensemble_cv_at(train, headline_grid(fast), ks, seed, max_test=300, group=SPOT_PHONE,
                                             cache=cache), strict=True):
        tables.append(t.assign(grid="headline candidates", n_neighbors=k))
        score = float(t["cv_mean_error_m"].min())
        if best is None or score < best[0]:
            best = (score, k, b["est__estimators"])
    table = pd.concat(tables, ignore_index=True)
    table["rank"] = rankdata(table["cv_mean_error_m"], method="min").astype(np.int32)
    return (best[1], best[2]), table.sort_values("rank", kind="stable").reset_index(drop=True)


def _ensemble_rows(train: FingerprintSet, test: FingerprintSet, k_cv: int, chosen: list, ranged: list | None = None,
                   spotted: list | None = None, top: tuple[int, list] | None = None):
    """(name, prediction (n, 4), params) of the AP-selection, ensemble and CV-chosen ensemble rows, with
    ``ranged`` the CV-chosen offset-range row, and with ``spotted`` the CV-chosen spot row; each member fitted once
    per K on the selected APs (the same as the rows' pipelines, :func:`ensemble_pipeline`; a member without an
    ``n_neighbors`` parameter, such as a spot-averaged one, keeps its own K, as in the pipeline)."""
    from ilocalg.wifi.ensemble import ApSelector, combine_predictions

    aps = ApSelector(1).fit(train.rssi_dbm)
    x_tr, x_te, y = aps.transform(train.rssi_dbm), aps.transform(test.rssi_dbm), _target(train)
    three = ensemble_members(three=True)
    need: dict = {}
    for k, members in ((5, three), (k_cv, chosen), (k_cv, ranged or []), (k_cv, spotted or []),
                       top or (k_cv, [])):
        need.setdefault(k, {}).update(dict(members))
    cache = {(n, k): pr for k, m in need.items() for n, pr in fit_members(list(m.items()), x_tr, y, x_te, k).items()}

    def member(name, est, k):
        return cache[(name, k)]

    names = " + ".join(n for n, _ in three)
    yield ("toolkit: offset search row + AP selection (APs heard in training)", member(*three[0], 5),
           "n_neighbors=5, min_count=1, representation=powed, metric=sorensen, "
           f"shifts_db={_fmt(offset_shifts_db())}", 5, three[:1])
    yield ("toolkit: + ensemble (mean position, majority floor and building)",
           combine_predictions([member(n, e, 5) for n, e in three]), f"n_neighbors=5, min_count=1, members={names}",
           5, three)
    yield ("toolkit: ensemble members by GroupKFold(PHONEID) CV, K of the offset-search CV",
           combine_predictions([member(n, e, k_cv) for n, e in chosen]),
           f"n_neighbors={k_cv}, min_count=1, members={_fmt(chosen)}", k_cv, chosen)
    if ranged is not None:
        sh = next((e.get_params()["shifts_db"] for _, e in ranged if "shifts_db" in e.get_params()), None)
        yield ("toolkit: offset range (1 or 2 sd) and members by GroupKFold(PHONEID) CV, K of the offset-search CV",
               combine_predictions([member(n, e, k_cv) for n, e in ranged]),
               f"n_neighbors={k_cv}, min_count=1, members={_fmt(ranged)}"
               + ("" if sh is None else f", shifts_db={_fmt(tuple(sh))}"), k_cv, ranged)
    if ranged is not None and spotted is not None:
        wp = next((e.get_params()["weight_power"] for _, e in spotted if "weight_power" in e.get_params()), 1.0)
        yield ("toolkit: + spot-averaged fingerprints (raw + averaged members), spot K and weight exponent by "
               "GroupKFold(PHONEID) CV",
               combine_predictions([member(n, e, k_cv) for n, e in spotted]),
               f"n_neighbors={k_cv}, min_count=1, members={_fmt(spotted)}, weight_power={wp:g}"
               + ("" if sh is None else f", shifts_db={_fmt(tuple(sh))}"), k_cv, spotted)
    if top is not None:
        k_top, members = top
        wp = next((e.get_params()["weight_power"] for _, e in members if "weight_power" in e.get_params()), 1.0)
        sh_top = sorted({tuple(e.get_params()["shifts_db"]) for _, e in members if "shifts_db" in e.get_params()}
                        - {(0.0,)}, key=len)      # the searches' ranges (a member without a search, as ranks, has 0)
        yield ("toolkit: members (a rank member or not), offset range, spots, weight exponent and K by spot x PHONEID "
               "CV (test spots and phones unseen)",
               combine_predictions([member(n, e, k_top) for n, e in members]),
               f"n_neighbors={k_top}, min_count=1, members={_fmt(members)}, weight_power={wp:g}"
               + "".join(f", shifts_db={_fmt(v)}" for v in sh_top), k_top, members)
