"""Wi-Fi fixes of a walk against a database: WKNN, fix variance, floor votes."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ilocalg.fusion import fix_covariance_from_spread
from ilocalg.io.recording import (
    PRESSURE_HPA,
    as_recording,
    truth_at,
)
from ilocalg.io.scans import scan_matrix
from ilocalg.io.schema import RSSI_DBM, T_S
from ilocalg.pdr.signals import moving_mean
from ilocalg.track._config import DEFAULT_CONFIG, RealWalkConfig
from ilocalg.track.database import WifiDatabase, effective_age_s
from ilocalg.wifi import KnnFingerprint


@dataclass(frozen=True)
class WifiFixes:
    """Fixes of the scored walk: ``t_s`` (m,), ``xy_m`` (m, 2), ``R_m2`` (m, 2, 2), ``true_xy_m`` (m, 2;
    interpolated ground truth, NaN outside its span: for scoring only), ``floor`` (m,; the Wi-Fi floor
    vote, NaN when the database has no floors), ``true_floor`` (m,), and the scans left out:
    ``n_outside_walk`` (outside the walk's IMU time span), ``n_no_shared_ap`` (hearing no access
    point of the database). ``t_read_s`` (m,): when the scan's readings were taken (its time minus
    :func:`ilocalg.track.database.effective_age_s`; the scan time when ages are unknown): the time a
    fix describes, while ``t_s`` is when it becomes known. ``var_m2`` (m,): each fix's own per-axis
    variance (:class:`FixVarModel`), None when the fixes share one variance. ``age_s`` (m,): each fix's age
    (:func:`fix_age_s`; 0 when the readings' ages are unknown), the one :class:`FixVarModel` is fitted and
    predicts on; ``t_read_s`` is ``t_s - age_s`` (not before the walk's start)."""

    t_s: np.ndarray
    xy_m: np.ndarray
    R_m2: np.ndarray
    true_xy_m: np.ndarray
    floor: np.ndarray | None = None
    true_floor: np.ndarray | None = None
    n_outside_walk: int = 0
    n_no_shared_ap: int = 0
    floor_confidence: np.ndarray | None = None
    t_read_s: np.ndarray | None = None
    var_m2: np.ndarray | None = None
    age_s: np.ndarray | None = None



def _wknn(db: WifiDatabase, cfg: RealWalkConfig):
    return KnnFingerprint(n_neighbors=min(cfg.k_neighbors, db.xy_m.shape[0]), p=cfg.p, weights=cfg.weights,
                          not_heard_dbm=cfg.not_heard_dbm, kernel="dense", metric=cfg.metric).fit(db.rssi_dbm, db.xy_m)


def db_matrix(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG) -> np.ndarray:
    """The database RSSI matrix the queries see: readings older than ``cfg.max_age_s`` (when the database
    keeps the readings' ages) are not heard (NaN)."""
    X = db.rssi_dbm
    if cfg.max_age_s is not None and db.age_s is not None:
        X = np.where(db.age_s > cfg.max_age_s, np.nan, X)
    return X


def dense_wknn(db_rssi_dbm, Q_rssi_dbm, k: int, not_heard_dbm: float = -100.0, exclude=None, d2=None):
    """Euclidean K nearest fingerprints of every query (dense numpy; one matrix product).

    Not-heard readings (NaN) take ``not_heard_dbm``. Database rows hearing nothing and the pairs where
    ``exclude`` (bool, (m, n)) is True are never neighbours. Returns ``(idx, dist)``, each (m, k), nearest
    first; ``dist`` is inf where fewer than ``k`` rows were allowed. ``d2`` (m, n): the squared distances
    ``|q|^2 + |a|^2 - 2 q.a`` of the shifted vectors when already computed (e.g. one product for a whole
    floor, :func:`loo_fix_features_nested`); not modified.

    References
    ----------
    Luo et al. (2017), eq. 1 (the RSSI-space distance of KNN fingerprinting).
    """
    A = np.nan_to_num(np.asarray(db_rssi_dbm, dtype=np.float64), nan=not_heard_dbm) - not_heard_dbm
    return _search(A, (A * A).sum(1) if d2 is None else None, ~(A > 0).any(axis=1), Q_rssi_dbm, k, not_heard_dbm,
                   exclude, d2)


def _search(A, sq, empty, Q_rssi_dbm, k: int, not_heard_dbm: float, exclude=None, d2=None, A_sparse=None):
    """:func:`dense_wknn` from the shifted database ``A`` (n, n_aps), its rows' squared norms ``sq`` (n,) and its
    rows hearing nothing ``empty`` (n,). ``A_sparse``: ``A`` as a sparse matrix when its values are whole
    numbers (:class:`QuerySide`): for queries of whole numbers too every product and sum is an exact integer,
    the same in any order, so the product is taken over the heard cells only (same bits)."""
    if d2 is None:
        B = np.nan_to_num(np.asarray(Q_rssi_dbm, dtype=np.float64), nan=not_heard_dbm) - not_heard_dbm
        if A_sparse is not None and _exact_products(A_sparse.data, B):
            G = np.asarray(A_sparse @ B.T).T
        else:
            G = B @ (A.T if A is not None else A_sparse.toarray().T)
        D2 = (B * B).sum(1)[:, None] + sq[None, :] - 2.0 * G
    else:
        D2 = d2
    return _nearest(D2, empty, k, exclude)


def _exact_products(a_values, B) -> bool:
    """Whether every product and partial sum of rows of whole numbers ``a_values`` (the nonzero values of a
    matrix) with the rows of ``B`` is an exact float64 integer: both whole, and the largest possible sum under
    2^53."""
    if not np.array_equal(B, np.round(B)):
        return False
    a = float(np.abs(a_values).max(initial=0.0))
    b = float(np.abs(B).max(initial=0.0))
    return a * b * max(B.shape[1], 1) < 2.0 ** 52


@dataclass(frozen=True)
class QuerySide:
    """What every query against one database with one reading-age limit and not-heard value shares
    (:func:`query_side`): ``A`` (n, n_aps) the database matrix the queries see (:func:`db_matrix`) with not
    heard at ``not_heard_dbm`` and shifted by it (None when ``A_sparse`` holds it), ``A_sparse`` the same as a
    sparse matrix when its values are whole numbers (dBm readings; else None), ``sq`` (n,) its rows' squared
    norms, ``empty`` (n,) its rows hearing nothing, ``heard`` (n_aps, bool) the access points some row hears,
    ``heard_rows`` (n, n_aps, bool)."""

    A: np.ndarray | None
    A_sparse: object
    sq: np.ndarray
    empty: np.ndarray
    heard: np.ndarray
    heard_rows: np.ndarray


def query_side(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG) -> QuerySide:
    """:class:`QuerySide` of ``db`` for ``cfg``'s reading-age limit and not-heard value, made once and kept with
    the database. For a database that is another's :meth:`~ilocalg.track.database.WifiDatabase.without`, its
    rows of the other's (the same numbers: every quantity is per row (whole numbers: the squared norms are exact
    integers), or, for ``heard``, counted).

    References
    ----------
    Luo et al. (2017), eq. 1 (the RSSI-space distance of KNN fingerprinting).
    """
    import scipy.sparse as sp

    key = ("query_side", cfg.max_age_s if db.age_s is not None else None, cfg.not_heard_dbm)
    got = db._memo.get(key)
    if got is not None:
        return got
    if db._parent is not None and query_side(db._parent[0], cfg).A_sparse is not None:
        ps, rows = query_side(db._parent[0], cfg), db._parent[1]
        hr = ps.heard_rows[rows]
        out = QuerySide(None, ps.A_sparse[rows], ps.sq[rows], ps.empty[rows], hr.any(axis=0), hr)
    else:
        if db._parent is not None:
            ps, rows = query_side(db._parent[0], cfg), db._parent[1]
            A, hr = ps.A[rows], ps.heard_rows[rows]
        else:
            D = db_matrix(db, cfg)
            A = np.nan_to_num(np.asarray(D, dtype=np.float64), nan=cfg.not_heard_dbm) - cfg.not_heard_dbm
            hr = ~np.isnan(D)
        whole = np.array_equal(A, np.round(A))
        sq = (A * A).sum(1)
        out = QuerySide(None if whole else A, sp.csr_matrix(A) if whole else None, sq, ~(A > 0).any(axis=1),
                        hr.any(axis=0), hr)
    db._memo[key] = out
    return out


def _nearest(D2, empty_rows, k: int, exclude=None):
    """:func:`dense_wknn` from the squared distances ``D2`` (m, n; not modified): rows ``empty_rows`` (n,) and
    the pairs of ``exclude`` never neighbours."""
    D2 = np.maximum(D2, 0.0)
    D2[:, empty_rows] = np.inf
    if exclude is not None:
        D2[np.asarray(exclude, dtype=bool)] = np.inf
    k = min(k, D2.shape[1])
    idx = np.argpartition(D2, k - 1, axis=1)[:, :k]
    d2 = np.take_along_axis(D2, idx, 1)
    o = np.argsort(d2, axis=1)
    return np.take_along_axis(idx, o, 1), np.sqrt(np.take_along_axis(d2, o, 1))


def _weights(dist, weights: str) -> np.ndarray:
    if weights == "distance":
        w = 1.0 / np.maximum(dist, 1e-9)
    elif weights == "uniform":
        w = np.ones_like(dist)
    else:
        raise ValueError(f"weights must be 'distance' or 'uniform', got {weights!r}")
    return np.where(np.isfinite(dist), w, 0.0)


def locate_wknn(db: WifiDatabase, X, cfg: RealWalkConfig = DEFAULT_CONFIG, return_floor: bool = False,
                exclude=None, d2=None):
    """WKNN fixes (m, 2) of queries ``X`` (m, n_aps in ``db.ap_ids`` order) and their spread covariances.

    Euclidean distance (``cfg.p == 2``, the fast dense path :func:`dense_wknn`) or, for other
    ``cfg.p``/``cfg.metric``, :class:`ilocalg.wifi.KnnFingerprint`. With ``return_floor`` also each
    query's floor: the weighted (``cfg.weights``) majority of its neighbours' floors (NaN when the
    database has no floors), and its confidence (the winning share of the weights). A query sharing
    no access point with the database gets NaN (the estimators' documented no-AP result).
    ``exclude`` (bool (m, n_rows), dense path only): database rows a query may not use. ``d2`` (m, n_rows,
    dense path only): the queries' squared distances to the rows when already computed (:func:`dense_wknn`).

    References
    ----------
    Luo et al. (2017), eq. 1-2 (KNN fingerprinting).
    """
    X = np.asarray(X, dtype=np.float64)
    qs = query_side(db, cfg)
    heard = qs.heard
    miss = ~(~np.isnan(X[:, heard])).any(axis=1) if X.size else np.zeros(X.shape[0], dtype=bool)
    n = X.shape[0]
    xy, C, fl_out, conf = np.full((n, 2), np.nan), np.full((n, 2, 2), np.nan), np.full(n, np.nan), np.full(n, np.nan)
    if (~miss).any():
        if cfg.p == 2 and cfg.metric == "minkowski":
            idx, dist = _search(qs.A, qs.sq if d2 is None else None, qs.empty, X[~miss], cfg.k_neighbors,
                                cfg.not_heard_dbm, None if exclude is None else np.asarray(exclude)[~miss],
                                None if d2 is None else d2[~miss], qs.A_sparse)
        else:
            est = _wknn(db, cfg)
            dist, idx = est.kneighbors(X[~miss])
        sub, idx, w = _place(xy, C, db.xy_m, idx, dist, cfg.weights, np.flatnonzero(~miss))
        if return_floor and db.has_floors:
            fl = db.floor[idx]
            levels = np.unique(fl)
            score = np.stack([(w * (fl == f)).sum(axis=1) for f in levels], axis=1)
            fl_out[sub] = levels[np.argmax(score, axis=1)]
            conf[sub] = score.max(axis=1) / score.sum(axis=1)
    if return_floor == "confidence":
        return xy, C, fl_out, conf
    return (xy, C, fl_out) if return_floor else (xy, C)


def _place(xy, C, db_xy_m, idx, dist, weights: str, rows):
    """Write the WKNN fixes and spread covariances of the queries ``rows`` (their neighbours ``idx``, ``dist``)
    into ``xy`` and ``C``; returns the rows placed (some weight) with their neighbours and weights."""
    w = _weights(dist, weights)
    ok = w.sum(axis=1) > 0
    sub = rows[ok]
    idx, w = idx[ok], w[ok]
    xy[sub] = (w[..., None] * db_xy_m[idx]).sum(1) / w.sum(1)[:, None]
    C[sub] = fix_covariance_from_spread(db_xy_m[idx], w, min_var_m2=1.0)
    return sub, idx, w


def same_walk(walk) -> np.ndarray:
    """(n, n) bool: rows ``i, j`` of the same walk (``walk`` (n,) names), compared as integer codes rather than
    as n^2 Python strings."""
    codes = np.unique(np.asarray(walk), return_inverse=True)[1].ravel()
    return codes[:, None] == codes[None, :]


def loo_fix_errors(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG, without=()) -> np.ndarray:
    """Leave-one-walk-out fix error (m) of every database row: each row located against the rows of the
    *other* walks, never those of ``without`` (nested leave-out); NaN for rows of ``without`` and rows
    hearing nothing the others hear."""
    excl = same_walk(db.walk)
    if len(without):
        excl |= np.isin(db.walk, list(without))[None, :]
    xy, _ = locate_wknn(db, db_matrix(db, cfg), cfg, exclude=excl)
    e = np.hypot(*(xy - db.xy_m).T)
    if len(without):
        e[np.isin(db.walk, list(without))] = np.nan
    return e


#: The fix-quality features of :class:`FixVarModel`, in the order of its coefficients (after the intercept).
FIX_FEATURES = ("log_spread_m2", "log_n_aps", "age_s")


def fix_age_s(age_s, rssi_dbm) -> np.ndarray:
    """The age of a fix (s): how long before its scan's time stamp the readings it is located with were taken,
    :func:`ilocalg.track.database.effective_age_s` of the ages ``age_s`` (m, n_aps) of the readings heard (kept)
    in its RSSI vector ``rssi_dbm`` (m, n_aps; NaN: not heard or not kept). The one definition both the
    database's leave-one-walk-out fixes (:func:`loo_fix_features`, what :class:`FixVarModel` is fitted on) and a
    scored walk's fixes (:func:`wifi_fixes`, what it predicts on) use."""
    return effective_age_s(np.where(np.isnan(np.asarray(rssi_dbm, dtype=np.float64)), np.nan, age_s))


def fix_features(spread_R_m2, n_aps, age_s) -> np.ndarray:
    """The quantities a fix knows about itself, as :class:`FixVarModel`'s regressors (m, 3): the log of the
    trace of its neighbours' weighted spread covariance (m^2, :func:`ilocalg.fusion.fix_covariance_from_spread`
    with 1 m^2 added), the log of the number of access points its scan heard (of the database's, fresh
    readings only) and the fix's age (s, :func:`fix_age_s`)."""
    tr = np.trace(np.asarray(spread_R_m2, dtype=np.float64), axis1=-2, axis2=-1)
    return np.column_stack([np.log(np.maximum(tr, 1e-6)), np.log(np.maximum(np.asarray(n_aps, dtype=np.float64), 1.0)),
                            np.asarray(age_s, dtype=np.float64)])


@dataclass(frozen=True)
class FixVarModel:
    """A per-fix (heteroscedastic) Wi-Fi fix variance: ``E[|e|^2] = exp([1, f] beta) * smear`` for the
    features ``f`` of :func:`fix_features`, fitted by :func:`fit_fix_var_model`. :meth:`predict` gives the
    per-axis variance ``E[|e|^2] / 2`` (m^2) of each fix. ``n``: fixes it was fitted on."""

    beta: np.ndarray
    smear: float
    n: int

    def predict(self, features) -> np.ndarray:
        f = np.atleast_2d(np.asarray(features, dtype=np.float64))
        return np.exp(self.beta[0] + f @ self.beta[1:]) * self.smear / 2.0


def loo_fix_features(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG, d2=None) -> tuple[np.ndarray, np.ndarray]:
    """Leave-one-walk-out fix error vectors (n, 2; m, fix minus truth) and :func:`fix_features` (n, 3) of every
    database row, each row located against the rows of the other walks (Euclidean WKNN, :func:`dense_wknn`);
    NaN errors for rows that cannot be located. ``d2``: the rows' squared distances to each other when already
    computed (see :func:`loo_fix_features_nested`)."""
    if not (cfg.p == 2 and cfg.metric == "minkowski"):
        raise ValueError("loo_fix_features: the per-fix variance is measured with the Euclidean WKNN (p=2)")
    D = db_matrix(db, cfg)
    xy, C = locate_wknn(db, D, cfg, exclude=same_walk(db.walk), d2=d2)
    age = np.zeros(D.shape[0]) if db.age_s is None else fix_age_s(db.age_s, D)
    return xy - db.xy_m, fix_features(np.nan_to_num(C, nan=1.0), (~np.isnan(D)).sum(axis=1), age)


def wknn_key(cfg: RealWalkConfig) -> list:
    """The settings a WKNN fix depends on (``k_neighbors, p, weights, metric, max_age_s, not_heard_dbm``), as a
    JSON-ready list: what :func:`loo_fix_features` of one database depends on besides the database."""
    return [cfg.k_neighbors, cfg.p, cfg.weights, cfg.metric, cfg.max_age_s, cfg.not_heard_dbm]


def loo_fix_features_nested(db: WifiDatabase, walk_cfgs: dict) -> dict:
    """:func:`loo_fix_features` of ``db.without(s)`` with ``walk_cfgs[s]`` for every ``s`` of ``walk_cfgs`` (a
    name that is not a walk of ``db``: of the whole ``db``), the numbers of a leave-one-walk-out sweep's nested
    fix-variance fits. Returns ``{s: (err, features)}``.

    The squared distances of every pair of rows are one matrix product per reading-age limit (and not-heard
    value), each walk taking its rows' block of it, instead of one product per walk. They are the same numbers
    as a product of the walk's own rows when the shifted RSSI values are whole numbers (dBm readings: every
    product and sum is exact); otherwise each walk gets its own product, as before.
    """
    return dict(zip(walk_cfgs, loo_fix_features_shared(db, list(walk_cfgs.items())), strict=True))


def loo_fix_features_shared(db: WifiDatabase, pairs) -> list:
    """:func:`loo_fix_features_nested` for a list of ``(walk, cfg)`` pairs (a walk may come with several
    configurations; a name that is not a walk of ``db``: the whole ``db``). Returns one ``(err, features)`` per
    pair, in order."""
    pairs = list(pairs)
    out, groups = [None] * len(pairs), {}
    for i, (s, c) in enumerate(pairs):
        groups.setdefault((c.max_age_s, c.not_heard_dbm), []).append((i, s, c))
    walks = set(db.walk)
    for members in groups.values():
        c0 = members[0][2]
        G = None
        if all(c.p == 2 and c.metric == "minkowski" for _, _, c in members):
            D = db_matrix(db, c0)
            A = np.nan_to_num(D, nan=c0.not_heard_dbm) - c0.not_heard_dbm
            if np.array_equal(A, np.round(A)) and float(np.abs(A).max(initial=0.0)) ** 2 * A.shape[1] < 2.0 ** 52:
                sq = (A * A).sum(1)
                G = sq[:, None] + sq[None, :] - 2.0 * (A @ A.T)
                # what loo_fix_features computes per row, the same for every walk left out: once
                heard = ~np.isnan(D)
                row_heard, n_aps, empty = heard.any(axis=1), heard.sum(axis=1), ~(A > 0).any(axis=1)
                age = np.zeros(D.shape[0]) if db.age_s is None else fix_age_s(db.age_s, D)
                same = same_walk(db.walk)
                del A, D, heard
        for i, s, c in members:
            if G is None:
                out[i] = loo_fix_features(db.without(s) if s in walks else db, c)
                continue
            # loo_fix_features(db.without(s), c) from the rows' block of G: a row hearing nothing is not located
            keep = np.flatnonzero(db.walk != s) if s in walks else np.arange(len(db.walk))
            q = np.flatnonzero(row_heard[keep])
            xy, C = np.full((keep.size, 2), np.nan), np.full((keep.size, 2, 2), np.nan)
            if q.size:
                idx, dist = _nearest(G.take(keep[q], axis=0).take(keep, axis=1), empty[keep], c.k_neighbors,
                                     same.take(keep[q], axis=0).take(keep, axis=1))
                _place(xy, C, db.xy_m[keep], idx, dist, c.weights, q)
            out[i] = (xy - db.xy_m[keep], fix_features(np.nan_to_num(C, nan=1.0), n_aps[keep], age[keep]))
    return out


def fix_error_correlation(err_m, walk, max_lag: int = 8) -> tuple[float, float, float]:
    """How a walk's Wi-Fi fix errors persist from scan to scan: ``(c0, rho, var_b_m2)`` of the model
    ``corr(lag) = c0 rho^lag`` (a correlated share ``c0`` of the error variance, first-order Gauss-Markov
    from scan to scan with ``rho``, the rest white; ``var_b_m2 = c0 mean(|e|^2) / 2`` the correlated part's
    per-axis variance), fitted to the pooled correlation of the error vectors ``err_m`` (n, 2)
    of consecutive rows of the same ``walk`` (rows in time order) at lags 1..``max_lag`` (least squares in
    logs, weighted by the pairs per lag; lags with a correlation <= 0 left out). Both clipped to [0, 0.95]
    (0, 0, 0: fewer than two lags with a positive correlation).

    References
    ----------
    Bryson A. E., Henrikson L. J., "Estimation using sampled data containing sequentially correlated noise",
    J. Spacecraft 5(6) (1968): coloured measurement noise as a Gauss-Markov state.
    """
    e = np.asarray(err_m, dtype=np.float64).reshape(-1, 2)
    walk = np.asarray(walk)
    lags, r, n = [], [], []
    groups = [e[walk == w] for w in dict.fromkeys(walk)]
    groups = [g[np.isfinite(g).all(axis=1)] for g in groups]
    for lag in range(1, max_lag + 1):
        a = [g[:-lag] for g in groups if len(g) > lag]
        if not a:
            break
        b = np.vstack([g[lag:] for g in groups if len(g) > lag])
        a = np.vstack(a)
        den = np.sqrt((a * a).sum() * (b * b).sum())
        if den > 0 and (a * b).sum() > 0:
            lags.append(lag), r.append((a * b).sum() / den), n.append(len(a))
    if len(lags) < 2:                   # c0 and rho cannot be told apart: no correlation modelled
        return 0.0, 0.0, 0.0
    W = np.sqrt(np.asarray(n, dtype=np.float64))
    X = np.column_stack([np.ones(len(lags)), lags])
    coef = np.linalg.lstsq(X * W[:, None], np.log(r) * W, rcond=None)[0]
    c0 = float(np.clip(np.exp(coef[0]), 0.0, 0.95))
    e2 = (np.vstack(groups) ** 2).sum(axis=1)
    return c0, float(np.clip(np.exp(coef[1]), 0.0, 0.95)), c0 * float(e2.mean()) / 2.0


def fit_fix_var_model(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG) -> FixVarModel:
    """Fit :class:`FixVarModel` on the database walks (never the scored walk: it must not be in ``db``).

    Every row's leave-one-walk-out squared error (:func:`loo_fix_features`) is regressed in logs on its
    features by ordinary least squares (a log-linear variance model, Harvey 1976); the retransformation
    bias of the log is removed with Duan's (1983) smearing factor ``mean(exp(residual))``, so the model's
    mean squared error equals the data's on average without assuming Gaussian residuals.

    References
    ----------
    Harvey A. C., "Estimating regression models with multiplicative heteroscedasticity", Econometrica 44(3)
    (1976); Duan N., "Smearing estimate: a nonparametric retransformation method", JASA 78(383) (1983).
    """
    err, F = loo_fix_features(db, cfg)
    return log_variance_fit((err ** 2).sum(axis=1), F)


def log_variance_fit(e2_m2, features) -> FixVarModel:
    """:class:`FixVarModel` of squared 2-D errors ``e2_m2`` (n,) on ``features`` (n, p): OLS of ``log e2`` on
    ``[1, features]``, Duan's smearing factor for the retransformation (see :func:`fit_fix_var_model`).
    Rows with a non-finite error or feature are left out; fewer than ``10 (p + 1)`` left raises."""
    e2 = np.asarray(e2_m2, dtype=np.float64)
    F = np.atleast_2d(np.asarray(features, dtype=np.float64))
    ok = np.isfinite(e2) & np.isfinite(F).all(axis=1)
    if ok.sum() < 10 * (F.shape[1] + 1):
        raise ValueError(f"fit_fix_var_model: {int(ok.sum())} located fixes with known errors; need at least "
                         f"{10 * (F.shape[1] + 1)} to fit the per-fix variance")
    # a fix exactly on its truth has log error -inf: floor at (1 cm)^2, far below any fix's error
    y = np.log(np.maximum(e2[ok], 1e-4))
    X = np.column_stack([np.ones(ok.sum()), F[ok]])
    beta = np.linalg.lstsq(X, y, rcond=None)[0]
    smear = float(np.mean(np.exp(y - X @ beta)))
    return FixVarModel(beta, smear, int(ok.sum()))


def wifi_fixes(trace, db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG,
               fix_var_m2: float | None = None, fix_var_model: FixVarModel | None = None) -> WifiFixes:
    """WKNN fixes of every scan of ``trace`` against ``db``, which must not contain the walk.

    ``R`` of each fix: with ``fix_var_model`` (:func:`fit_fix_var_model` on other walks) its own
    predicted variance times I (``var_m2``); else ``fix_var_m2 I`` (isotropic, e.g. calibrated on other
    walks by :func:`calibrate_fix_var`) or, when None, the neighbour spread plus ``cfg.fix_min_var_m2``.
    Scans outside the walk's IMU time span and scans hearing no access point of the database are left
    out and counted (``n_outside_walk``, ``n_no_shared_ap``). The walk's ground truth (for
    ``true_xy_m``) is moved into the database's frame.
    """
    rec = as_recording(trace)
    if rec.name and rec.name in set(db.walk):
        raise ValueError(f"the fingerprint database must not contain the scored walk {rec.name!r}")
    same = [k for k, v in db.content_ids.items() if len(rec.imu) and v == rec.content_id]
    if same:
        raise ValueError(f"the fingerprint database must not contain the scored walk {rec.name!r}: its walk "
                         f"{same[0]!r} has the same sensor content")
    if db.frame is not None and len(rec.truth):
        rec = rec.in_frame(db.frame)
    w = rec.wifi
    if not len(w):
        raise ValueError(f"{rec.source or rec.name}: the walk has no Wi-Fi scan")
    # readings without a last-seen time (IPIN logfiles) count as fresh: their age is unknown, not large
    fresh = (None if cfg.max_age_s is None or "last_seen_s" not in w.columns
             else ((w[T_S] - w["last_seen_s"]) <= cfg.max_age_s).to_numpy())
    _, t, X = scan_matrix(w, db.ap_ids, keep=fresh)
    if "last_seen_s" in w.columns:       # how old the kept readings were (module database)
        aged = w.assign(**{RSSI_DBM: (w[T_S] - w["last_seen_s"]).to_numpy(dtype=np.float64)})
        age = fix_age_s(scan_matrix(aged, db.ap_ids, keep=fresh)[2], X)
    else:
        age = np.zeros(t.size)
    t0, t1 = rec.t_span_s
    inside = (t >= t0) & (t <= t1)
    heard = ~np.isnan(X).all(axis=1)          # scans sharing no AP with the database cannot be located
    keep = inside & heard
    t, X, age = t[keep], X[keep], age[keep]
    if not t.size:
        raise ValueError(f"{rec.source or rec.name}: no scan inside the walk's time span shares an access point "
                         f"with the database ({int((~inside).sum())} outside the span, "
                         f"{int((inside & ~heard).sum())} hearing none of its {len(db.ap_ids)} APs)")
    xy, C, fl, conf = locate_wknn(db, X, cfg, return_floor="confidence")
    var = None
    if fix_var_model is not None:
        heard_db = query_side(db, cfg).heard
        var = fix_var_model.predict(fix_features(C, (~np.isnan(X[:, heard_db])).sum(axis=1), age))
        R = var[:, None, None] * np.eye(2)
    elif fix_var_m2 is not None:
        R = fix_var_m2 * np.broadcast_to(np.eye(2), C.shape).copy()
    else:
        R = C + (cfg.fix_min_var_m2 - 1.0) * np.eye(2)
    if len(rec.truth) >= 2:
        true, tfl = truth_at(rec.truth, t, outside="nan")
    else:
        true, tfl = np.full((t.size, 2), np.nan), np.full(t.size, np.nan)
    return WifiFixes(t, xy, R, true, fl, tfl, int((~inside).sum()), int((inside & ~heard).sum()), conf,
                     np.maximum(t - age, t0), var, age)


def calibrate_fix_var(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG,
                      loo_err=None) -> tuple[float, pd.DataFrame]:
    """Isotropic Wi-Fi fix variance (per axis, m^2) by leave-one-walk-out *inside* ``db``.

    Each walk of ``db`` is located against the others (:func:`loo_fix_errors`); ``var = mean(error^2) / 2``.
    Scans sharing no access point with the other walks are not located and not counted (``n_unlocated``).
    Returns the variance and the per-walk errors table (``walk, n, mean_error_m, n_unlocated``; ``n``
    located scans). ``loo_err``: the rows' leave-one-walk-out error vectors when already computed (the first
    of :func:`loo_fix_features` of ``db`` with ``cfg``: the same fixes, so the same numbers).
    """
    if loo_err is not None:
        e_all = np.hypot(*np.asarray(loo_err, dtype=np.float64).T)
    elif cfg.p == 2 and cfg.metric == "minkowski":
        e_all = loo_fix_errors(db, cfg)
    else:
        e_all = np.full(len(db.walk), np.nan)
        for v in dict.fromkeys(db.walk):
            m = db.walk == v
            xy, _ = locate_wknn(db.without(v), db_matrix(db, cfg)[m], cfg)
            e_all[m] = np.hypot(*(xy - db.xy_m[m]).T)
    rows = []
    for v in dict.fromkeys(db.walk):
        e = e_all[db.walk == v]
        ok = np.isfinite(e)
        rows.append({"walk": v, "n": int(ok.sum()), "mean_error_m": float(e[ok].mean()) if ok.any() else np.nan,
                     "n_unlocated": int((~ok).sum())})
    e = e_all[np.isfinite(e_all)]
    if not e.size:
        raise ValueError("calibrate_fix_var: no scan of any fingerprint walk shares an access point with the other "
                         "walks; the Wi-Fi fix variance cannot be learned")
    return float(np.mean(e**2) / 2.0), pd.DataFrame(rows)


#: Wi-Fi configurations :func:`select_wifi` chooses from (label -> RealWalkConfig fields).
WIFI_CANDIDATES = {
    "WKNN Euclidean K=5, readings <= 2 s": {"k_neighbors": 5, "p": 2, "weights": "distance", "max_age_s": 2.0},
    "WKNN Euclidean K=5, readings <= 5 s": {"k_neighbors": 5, "p": 2, "weights": "distance", "max_age_s": 5.0},
    "WKNN Euclidean K=5, every reading": {"k_neighbors": 5, "p": 2, "weights": "distance", "max_age_s": None},
    "WKNN Euclidean K=10, readings <= 5 s": {"k_neighbors": 10, "p": 2, "weights": "distance", "max_age_s": 5.0},
    "KNN Euclidean K=5, readings <= 5 s": {"k_neighbors": 5, "p": 2, "weights": "uniform", "max_age_s": 5.0},
}


def select_wifi(db: WifiDatabase, cfg: RealWalkConfig = DEFAULT_CONFIG, candidates=None):
    """Choose the Wi-Fi configuration with the lowest leave-one-walk-out mean error inside ``db``.

    Returns ``(label, cfg_with_it, fix_var_m2, table)``; ``table`` has one row per candidate
    (``label, mean_error_m, fix_sd_m``). Uses only the walks of ``db`` (model selection nested inside
    the outer leave-one-walk-out).
    """
    cands = WIFI_CANDIDATES if candidates is None else candidates
    rows, best = [], None
    for label, kw in cands.items():
        c = dataclasses.replace(cfg, **kw)
        var, per = calibrate_fix_var(db, c)
        per = per[per["n"] > 0]
        e = float(np.average(per["mean_error_m"], weights=per["n"]))
        rows.append({"label": label, "mean_error_m": e, "fix_sd_m": float(np.sqrt(var))})
        if best is None or e < best[0]:
            best = (e, label, c, var)
    return best[1], best[2], best[3], pd.DataFrame(rows)


@dataclass(frozen=True)
class FloorEstimate:
    """Floors of one walk: ``causal`` and ``offline`` (functions of time, see :func:`estimate_floors`) are
    given as values at ``t_s`` of the queries; ``segments`` (DataFrame ``t0_s, t1_s, height_m``: the
    barometric level segments, one row when there is no barometer); ``source`` ("wifi" or
    "wifi+barometer")."""

    segments: pd.DataFrame
    source: str
    vote_t_s: np.ndarray
    vote_floor: np.ndarray

    def _segment(self, t_s):
        """Segment of each time; a time during a level change belongs to the level it is nearer in time
        (the change's midpoint splits it)."""
        seg = self.segments
        cut = 0.5 * (seg["t1_s"].to_numpy()[:-1] + seg["t0_s"].to_numpy()[1:])
        return np.searchsorted(cut, t_s, side="right")

    def at(self, t_s, causal: bool, n_votes: int = 5) -> np.ndarray:
        """Floor at times ``t_s`` (NaN before the first vote of a causal estimate without a barometer)."""
        t = np.atleast_1d(np.asarray(t_s, dtype=np.float64))
        out = np.full(t.size, np.nan)
        vt, vf = self.vote_t_s, self.vote_floor
        if not vt.size:
            return out
        if self.source == "wifi":
            for i, ti in enumerate(t):
                if causal:
                    sel = vf[max(0, np.searchsorted(vt, ti, side="right") - n_votes):
                             np.searchsorted(vt, ti, side="right")]
                    if not sel.size:
                        sel = vf[:1]            # before the first scan: the first scan's floor
                else:
                    c = int(np.argmin(np.abs(vt - ti)))
                    sel = vf[max(0, c - n_votes // 2): c + n_votes // 2 + 1]
                out[i] = _majority(sel)
            return out
        seg = self._segment(t)
        vseg = self._segment(vt)
        h = self.segments["height_m"].to_numpy()
        for i, (ti, si) in enumerate(zip(t, seg, strict=True)):
            # every vote, referred to this segment by the barometric height difference
            m = (vt <= ti) if causal else np.ones(vt.size, dtype=bool)
            if not m.any():
                m = np.zeros(vt.size, dtype=bool)
                m[0] = True
            here = m & (vseg == si)
            if here.any():
                out[i] = _majority(vf[here])
            else:          # no vote on this level yet: the nearest level's floor + the height change in storeys
                j = vseg[m][np.argmin(np.abs(vseg[m] - si))]
                base = _majority(vf[m & (vseg == j)])
                dz = (h[si] - h[j]) / _STOREY_M
                out[i] = base + (np.sign(dz) * max(1.0, round(abs(dz))) if abs(dz) > 0 else 0.0)
        return out


#: Storey height (m) used only to count storeys of a barometric level change that no Wi-Fi vote covers.
_STOREY_M = 3.5


def _majority(v) -> float:
    v = np.asarray(v, dtype=np.float64)
    v = v[np.isfinite(v)]
    if not v.size:
        return np.nan
    u, c = np.unique(v, return_counts=True)
    return float(u[np.argmax(c)])        # ties: the lowest floor


def barometric_segments(pressure: pd.DataFrame, change_m: float = 2.0, smooth_s: float = 2.0) -> pd.DataFrame:
    """Cut a walk into level segments where the barometric height changes by more than ``change_m``.

    Height from pressure by the ICAO standard atmosphere, ``h = 44330.8 (1 - (p / p_ref)^0.190263)`` m,
    relative to the walk's start, after a moving mean over ``smooth_s``. A segment ends when the height
    leaves its level by more than ``change_m``; the next starts when the height is level again (changes
    by less than ``change_m / 4`` over ``smooth_s``).

    Returns
    -------
    DataFrame
        ``t0_s, t1_s, height_m`` (mean height of the segment), one row per level segment.

    References
    ----------
    ICAO, Manual of the ICAO Standard Atmosphere, Doc 7488 (1993); Ye H. et al., B-Loc, IEEE MASS (2014).
    """
    t = pressure.index.to_numpy(dtype=np.float64)
    p = pressure[PRESSURE_HPA].to_numpy(dtype=np.float64)
    if t.size < 2:
        raise ValueError(f"barometer: need at least 2 pressure samples, got {t.size}")
    if not np.all((p > 300) & (p < 1100)):
        raise ValueError("barometer: pressure outside (300, 1100) hPa")
    rate = 1.0 / float(np.median(np.diff(t)))
    h = 44330.8 * (1.0 - (p / p[0]) ** 0.190263)
    hs = moving_mean(h, max(int(round(smooth_s * rate)), 1))
    lag = max(int(round(smooth_s * rate)), 1)
    rows, start, ref, moving = [], 0, hs[0], False
    for i in range(t.size):
        if not moving and abs(hs[i] - ref) > change_m:
            moving = True
            end = i
            while end > start and abs(hs[end] - ref) > change_m / 4:
                end -= 1
            rows.append((t[start], t[end], float(np.mean(hs[start:end + 1]))))
        elif moving and i >= lag and abs(hs[i] - hs[i - lag]) < change_m / 4:
            moving, start, ref = False, i, hs[i]
    last = (t[start], t[-1], float(np.mean(hs[start:]))) if not moving else (t[end + 1], t[-1], float(hs[-1]))
    rows.append(last)
    return pd.DataFrame(rows, columns=["t0_s", "t1_s", "height_m"])


def estimate_floors(fixes: WifiFixes, pressure: pd.DataFrame | None = None,
                    cfg: RealWalkConfig = DEFAULT_CONFIG) -> FloorEstimate | None:
    """The walk's floors from its Wi-Fi floor votes (and barometric level changes when ``pressure`` is given).

    None when the fixes carry no floor (a database without floor numbers).
    """
    if fixes.floor is None or not np.isfinite(fixes.floor).any():
        return None
    if pressure is not None and len(pressure) >= 2:
        seg = barometric_segments(pressure, cfg.baro_change_m, cfg.baro_smooth_s)
        return FloorEstimate(seg, "wifi+barometer", fixes.t_s, fixes.floor)
    seg = pd.DataFrame({"t0_s": [-np.inf], "t1_s": [np.inf], "height_m": [0.0]})
    return FloorEstimate(seg, "wifi", fixes.t_s, fixes.floor)





def select_wifi_nested(db: WifiDatabase, scored_walks, cfg: RealWalkConfig = DEFAULT_CONFIG, candidates=None) -> dict:
    """:func:`select_wifi` for many held-out walks at once (a leave-one-walk-out sweep over a floor).

    For each walk ``s`` of ``scored_walks``: the candidate with the lowest leave-one-walk-out mean error
    over the *other* walks of ``db`` (never using ``s``'s rows, neither as queries nor as neighbours),
    and its fix variance; the same numbers as ``select_wifi(db.without(s))``, from one distance matrix per
    reading-age limit (candidates differing only in K or weights share it, and those with the same K share
    each walk's neighbours). Returns ``{s: (label, cfg, fix_var_m2)}``.
    """
    cands = WIFI_CANDIDATES if candidates is None else candidates
    walk = db.walk
    same = same_walk(walk)
    groups: dict = {}                 # the candidates seeing the same database matrix: (max_age_s, not heard)
    for i, (label, kw) in enumerate(cands.items()):
        c = dataclasses.replace(cfg, **kw)
        if not (c.p == 2 and c.metric == "minkowski"):
            raise ValueError(f"select_wifi_nested: candidate {label!r} is not Euclidean (p=2)")
        groups.setdefault((c.max_age_s, c.not_heard_dbm), []).append((i, label, c))
    per = {}
    for members in groups.values():
        c0 = members[0][2]
        A = np.nan_to_num(db_matrix(db, c0), nan=c0.not_heard_dbm) - c0.not_heard_dbm
        sq = (A * A).sum(1)
        D2 = np.maximum(sq[:, None] + sq[None, :] - 2.0 * (A @ A.T), 0.0)
        D2[:, ~(A > 0).any(axis=1)] = np.inf
        D2[same] = np.inf
        for s in scored_walks:
            ms = walk == s
            keep = np.flatnonzero(~ms)
            Ds = D2.take(keep, axis=0).take(keep, axis=1)        # = D2[~ms][:, ~ms], one pass fewer
            xy = db.xy_m[~ms]
            near = {}
            for i, label, c in members:
                k = min(c.k_neighbors, Ds.shape[1])
                if k not in near:
                    idx = np.argpartition(Ds, k - 1, axis=1)[:, :k]
                    near[k] = idx, np.sqrt(np.take_along_axis(Ds, idx, 1))
                idx, dist = near[k]
                w = _weights(dist, c.weights)
                ok = w.sum(1) > 0
                est = (w[ok, :, None] * xy[idx[ok]]).sum(1) / w[ok].sum(1)[:, None]
                e = np.hypot(*(est - xy[ok]).T)
                per.setdefault(s, []).append((i, float(e.mean()), label, c, float(np.mean(e ** 2) / 2.0)))
    # the first candidate (in the given order) with the lowest error
    return {s: min(sorted(v, key=lambda r: r[0]), key=lambda r: r[1])[2:] for s, v in per.items()}


def classify_floor(floor_dbs: dict, trace, cfg: RealWalkConfig = DEFAULT_CONFIG, without=None) -> tuple:
    """The floor of a walk among several floors' databases, with a confidence.

    Every scan of the walk (readings older than ``cfg.max_age_s`` left out) votes for the floor holding
    its nearest fingerprint (Euclidean, not-heard readings at ``cfg.not_heard_dbm``; the access points
    of all floors together); the walk's floor is the majority and its confidence the share of the votes
    (0.5-1 for two floors). ``without``: a walk name left out of every database (leave-one-walk-out).

    Returns ``(floor_label, confidence, votes)`` with ``votes`` a dict label -> number of scans.

    References
    ----------
    Torres-Sospedra et al. (2018): floor classification before positioning; the 15 m penalty per wrong floor.
    """
    if len(floor_dbs) < 1:
        raise ValueError("classify_floor: no floor database given")
    rec = as_recording(trace)
    w = rec.wifi
    if not len(w):
        raise ValueError(f"{rec.source or rec.name}: the walk has no Wi-Fi scan")
    aps = sorted(set().union(*[set(db.ap_ids) for db in floor_dbs.values()]))
    fresh = (None if cfg.max_age_s is None or "last_seen_s" not in w.columns
             else ((w[T_S] - w["last_seen_s"]) <= cfg.max_age_s).to_numpy())
    _, _, Q = scan_matrix(w, aps, keep=fresh)
    Q = Q[~np.isnan(Q).all(axis=1)]
    if not Q.shape[0]:
        raise ValueError(f"{rec.source or rec.name}: no scan hears an access point of the floors' databases")
    best = []
    labels = list(floor_dbs)
    for lab in labels:
        db = floor_dbs[lab]
        if without is not None and without in set(db.walk):
            db = db.without(without)
        D = db_matrix(db, cfg)
        col = {a: j for j, a in enumerate(aps)}
        full = np.full((D.shape[0], len(aps)), np.nan)
        full[:, [col[a] for a in db.ap_ids]] = D
        _, dist = dense_wknn(full, Q, 1, cfg.not_heard_dbm)
        best.append(dist[:, 0])
    vote = np.argmin(np.column_stack(best), axis=1)
    counts = {lab: int((vote == i).sum()) for i, lab in enumerate(labels)}
    win = max(counts, key=counts.get)
    return win, counts[win] / vote.size, counts
