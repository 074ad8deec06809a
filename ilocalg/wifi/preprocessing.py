"""RSSI matrices: validation, not-heard substitution and data representations.

An RSSI matrix ``rssi_dbm`` has shape (n_samples, n_aps), dBm, ``NaN`` = access point not heard
(see :mod:`ilocalg`). Every estimator substitutes a value ``not_heard_dbm`` for ``NaN`` (a
parameter: UJIIndoorLoc documents -104 dBm as its weakest reading; simulated data use the
simulator's detection threshold).

The *representations* map RSSI to non-negative features in which "not heard" is exactly 0, which
is what the fast distance kernels of :mod:`ilocalg.wifi.knn` exploit (most APs are not heard in
most scans):

``"positive"``     ``rssi - not_heard_dbm``                          (dB above the floor)
``"exponential"``  ``exp(pos / alpha) / exp(-not_heard_dbm / alpha)``  with ``alpha = 24``
``"powed"``        ``(pos / -not_heard_dbm) ** beta``                 with ``beta = e``
``"rank"``         each heard reading's rank in its scan (weakest 1 ... strongest n, ties averaged) over n,
                   the number of APs the scan hears above ``not_heard_dbm``: the same features for any
                   increasing map of a phone's readings (an offset, a gain), so a phone's calibration drops out

No shared access point
----------------------
A query scan that hears none of the access points heard in the training set (including a scan
hearing nothing) carries no information about its position. Every estimator's ``predict`` gives
it a NaN position (and NaN floor/building), the documented "not located" result; count them with
:func:`shares_no_ap` or ``np.isnan(pred[:, 0])``. Their ``kneighbors`` / ``predict_index`` (which
must name references) raise instead, naming the row. Without this, the distance to every reference
is just the reference's own heard APs, and the references with the weakest fingerprints would be
returned. A training set in which no access point is heard is an error at ``fit``
(:func:`heard_aps`). :func:`ilocalg.metrics.mean_horizontal_error_m` scores NaN positions.

References
----------
Torres-Sospedra J., Montoliu R., Trilles S., Belmonte O., Huerta J., "Comprehensive analysis of
distance and similarity measures for Wi-Fi fingerprinting indoor positioning systems", Expert
Systems with Applications 42 (2015) 9263-9278, sec. 3 (positive, exponential, powed data
representations; alpha = 24, beta = e).
Machaj J., Brida P., Piche R., "Rank based fingerprinting algorithm for indoor positioning", IPIN 2011
(fingerprints as the order of the APs by signal strength, robust to the differences between phones). The
``"rank"`` representation's scaling by the number of heard APs (so that a scan hearing many APs and one
hearing few are on one scale) is the toolkit's.
"""

from __future__ import annotations

import numpy as np

from ilocalg.io.schema import FIELD_RANGES, RSSI_DBM

__all__ = [
    "RSSI_RANGE_DBM",
    "REPRESENTATIONS",
    "check_rssi",
    "check_positions",
    "fill_not_heard",
    "to_features",
    "checked_features",
    "strongest_ap_mask",
    "mean_fingerprints",
    "RssiPositionTags",
    "heard_aps",
    "shares_no_ap",
    "check_shared_aps",
    "predict_located",
]

REPRESENTATIONS = ("positive", "exponential", "powed", "rank")


#: Physical range of a heard Wi-Fi reading, dBm: the loaders' range (:data:`ilocalg.io.schema.FIELD_RANGES`),
#: also the default ``rssi_range_dbm`` of every estimator.
RSSI_RANGE_DBM = (FIELD_RANGES[RSSI_DBM].lo, FIELD_RANGES[RSSI_DBM].hi)


def check_rssi(rssi_dbm, name: str = "X", n_aps: int | None = None, allow_empty_rows: bool = True,
               owner: str = "the database", valid_dbm: tuple[float, float] | None = None,
               copy: bool = True) -> np.ndarray:
    """Validate an RSSI matrix and return it as float64.

    Parameters
    ----------
    rssi_dbm : array_like, shape (n_samples, n_aps)
        dBm, NaN = not heard. +/-inf is rejected.
    name : str
        Name used in error messages.
    n_aps : int, optional
        Expected number of columns (the fitted database's AP count).
    allow_empty_rows : bool
        When False, a row with no heard AP (all NaN) raises.
    owner : str
        Who expects ``n_aps`` columns (named in the error message).
    valid_dbm : (float, float), optional
        Physical range of a heard reading (an estimator's ``rssi_range_dbm``, by default
        :data:`RSSI_RANGE_DBM`); a finite value outside it raises. ``None`` checks no range.
    copy : bool
        ``True``: the result is a new array. ``False``: a float64 input is returned itself (no copy of the
        matrix), for callers that neither keep nor modify it (the estimators' checks on their way to features).

    Raises
    ------
    ValueError
        Not 2-D, no rows, wrong column count, infinite values or (optionally) all-NaN rows,
        naming the first offending row.
    """
    if hasattr(rssi_dbm, "tocsr") or hasattr(rssi_dbm, "to_coo"):
        raise ValueError(f"Sparse data was passed for {name}, but dense data is required (an RSSI matrix with "
                        "NaN for not heard)")
    try:
        raw = np.asarray(rssi_dbm)
        if np.iscomplexobj(raw):
            raise ValueError(f"Complex data not supported: {name} must be real RSSI in dBm")
        x = raw.astype(np.float64, copy=bool(copy))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a numeric RSSI matrix in dBm: {exc}") from None
    if x.ndim != 2:
        raise ValueError(f"{name} must be 2-D (n_samples, n_aps), got shape {x.shape}. Reshape your data")
    if x.shape[0] == 0:
        raise ValueError(f"{name} has no rows: 0 sample(s) (shape={x.shape}) while a minimum of 1 is required.")
    if x.shape[1] == 0:
        raise ValueError(f"{name} has no access-point columns: 0 feature(s) (shape={x.shape}) while a minimum of 1 "
                         "is required.")
    if n_aps is not None and x.shape[1] != n_aps:
        raise ValueError(f"{name} has {x.shape[1]} features, but {owner} is expecting {n_aps} features as input "
                         f"({name} has {x.shape[1]} AP columns, the fitted database {n_aps}; columns must be the "
                         "same access points in the same order)")
    # one pass for the smallest and largest reading (NaN ignored): when both are finite and in range, nothing is
    # infinite or out of range and the element-wise checks below (which name the first offender) are skipped
    lo_v, hi_v = np.fmin.reduce(x, axis=None), np.fmax.reduce(x, axis=None)
    fine = bool(np.isnan(lo_v)) or (bool(np.isfinite(lo_v)) and bool(np.isfinite(hi_v)) and (
        valid_dbm is None or (lo_v >= valid_dbm[0] and hi_v <= valid_dbm[1])))
    bad = None if fine else np.isinf(x)
    if bad is not None and bad.any():
        r, c = np.argwhere(bad)[0]
        raise ValueError(f"{name} is infinite at row {r}, column {c}; use NaN for 'not heard'")
    if valid_dbm is not None and not fine:
        lo, hi = valid_dbm
        out = (x < lo) | (x > hi)
        if out.any():
            r, c = np.argwhere(out)[0]
            raise ValueError(f"{name} row {r}, column {c}: RSSI {x[r, c]:g} dBm is outside [{lo:g}, {hi:g}] dBm "
                             f"({int(out.sum())} such value(s)); NaN means 'not heard' (an estimator's "
                             "rssi_range_dbm=None accepts any value)")
    if not allow_empty_rows:
        empty = np.flatnonzero(np.isnan(x).all(axis=1))
        if empty.size:
            raise ValueError(f"{name} row {empty[0]} hears no access point (all NaN); "
                             f"{empty.size} such rows")
    return x


def fill_not_heard(rssi_dbm, not_heard_dbm: float) -> np.ndarray:
    """Return a copy with NaN replaced by ``not_heard_dbm`` (float64)."""
    x = np.array(rssi_dbm, dtype=np.float64)
    x[np.isnan(x)] = float(not_heard_dbm)
    return x


def to_features(rssi_dbm, not_heard_dbm: float = -104.0, representation: str = "positive",
                alpha: float = 24.0, beta: float = np.e, dtype=np.float32, name: str = "X") -> np.ndarray:
    """Map RSSI (dBm, NaN = not heard) to non-negative features with "not heard" = 0.

    Parameters
    ----------
    rssi_dbm : array_like, shape (n, m)
    not_heard_dbm : float
        RSSI substituted for NaN; every heard reading must be >= it (a weaker reading would
        become negative; it raises rather than being clipped).
    representation : {"positive", "exponential", "powed", "rank"}
    alpha, beta : float
        Parameters of the exponential and powed representations.
    dtype : numpy dtype
        Output dtype (float32 keeps the database compact; integer dBm stay exact).

    Returns
    -------
    ndarray, shape (n, m), ``dtype``
        Features >= 0; ``positive`` is distance-equivalent to filling NaN with ``not_heard_dbm``.

    References
    ----------
    Torres-Sospedra et al. 2015, sec. 3 (data representations).
    """
    if representation not in REPRESENTATIONS:
        raise ValueError(f"representation must be one of {REPRESENTATIONS}, got {representation!r}")
    return checked_features(check_rssi(rssi_dbm, name), not_heard_dbm, representation, alpha, beta, dtype, name)


def checked_features(x: np.ndarray, not_heard_dbm: float = -104.0, representation: str = "positive",
                     alpha: float = 24.0, beta: float = np.e, dtype=np.float32, name: str = "X") -> np.ndarray:
    """:func:`to_features` of an RSSI matrix that :func:`check_rssi` has returned (float64, 2-D, no infinity):
    the same values, without checking ``x`` a second time (estimators check their input once, then map it).

    Only the heard readings above the floor are mapped (a scan hears a few of many APs): ``x > not_heard_dbm``
    is where ``x - not_heard_dbm`` is non-zero (NaN compares false), every other feature is exactly 0.
    """
    if representation not in REPRESENTATIONS:
        raise ValueError(f"representation must be one of {REPRESENTATIONS}, got {representation!r}")
    floor = float(not_heard_dbm)
    if not np.isfinite(floor):
        raise ValueError(f"not_heard_dbm must be finite, got {not_heard_dbm!r}")
    if np.fmin.reduce(x, axis=None) < floor:  # NaN (nothing heard) compares false
        weak = x < floor
        r, c = np.argwhere(weak)[0]
        raise ValueError(f"{name} row {r}, column {c} has {x[r, c]} dBm, weaker than not_heard_dbm={floor}; "
                         "lower not_heard_dbm")
    if representation == "powed" and floor >= 0:
        raise ValueError("the powed representation needs not_heard_dbm < 0")
    heard = x > floor
    if representation == "rank":
        return _heard_ranks(x, heard, dtype)
    v = x[heard] - floor  # finite (x >= floor, x finite), unless it overflows
    if v.size and not np.isfinite(v.max()):
        v = np.nan_to_num(v)  # an overflow to inf: nan_to_num's largest float, as before
    f = np.zeros(x.shape, dtype=dtype)
    if representation == "positive":
        f[heard] = v
    else:
        f[heard] = (np.exp(v / alpha) / np.exp(-floor / alpha) if representation == "exponential"
                    else (v / -floor) ** beta)
    return f


def _heard_ranks(x: np.ndarray, heard: np.ndarray, dtype) -> np.ndarray:
    """The ``"rank"`` features: rank of each ``heard`` reading of ``x`` in its row (weakest 1, ties averaged) over
    the row's number of heard readings; 0 elsewhere. Works on the heard readings alone (a scan hears a few of many
    APs): sorted by row, then value, each one's place in its row, averaged over a run of equal values."""
    f = np.zeros(x.shape, dtype=dtype)
    r, c = np.nonzero(heard)
    if r.size == 0:
        return f
    v = x[r, c]
    order = np.lexsort((v, r))
    r, c, v = r[order], c[order], v[order]
    place = np.arange(r.size) - np.searchsorted(r, r, side="left") + 1.0       # 1 ... n within each row
    run = np.cumsum(np.r_[True, (r[1:] != r[:-1]) | (v[1:] != v[:-1])]) - 1     # runs of equal values
    mean_place = np.bincount(run, place) / np.bincount(run)
    f[r, c] = mean_place[run] / np.bincount(r, minlength=x.shape[0])[r]
    return f


#: :func:`strongest_ap_mask` takes its k strongest by k passes of argmax up to this k (a stable argsort of every
#: row above it, or when a heard reading is infinite); the same mask either way.
_MASK_ARGMAX_K = 8


def strongest_ap_mask(rssi_dbm, k: int) -> np.ndarray:
    """Boolean mask of the ``k`` strongest heard APs of each row (fewer when fewer are heard).

    Ties in RSSI are broken by column order (lower column first). This is SAP_k(s) of the
    i-Loc thesis: "if fewer than k APs are available, k decreases".

    References
    ----------
    Chiu, i-Loc thesis (NCTU 2013), sec. 3.1, definition of SAP_K(s) and eq. (1).
    """
    x = np.asarray(rssi_dbm, dtype=np.float64)
    if int(k) < 1:
        raise ValueError(f"k_aps must be >= 1, got {k}")
    k = min(int(k), x.shape[1])
    nan = np.isnan(x)
    key = np.where(nan, -np.inf, x)
    mask = np.zeros(x.shape, dtype=bool)
    if k <= _MASK_ARGMAX_K and x.size and not np.isinf(x).any():
        # k passes of argmax (the first column of the strongest left: a stable sort's order), each taken AP set to
        # -inf; a row with fewer than k heard takes not-heard or taken columns, which change nothing below
        rows = np.arange(x.shape[0])
        for _ in range(k):
            j = np.argmax(key, axis=1)
            mask[rows, j] = True
            key[rows, j] = -np.inf
        return mask & ~nan
    order = np.argsort(-key, axis=1, kind="stable")[:, :k]
    np.put_along_axis(mask, order, True, axis=1)
    return mask & ~nan


def mean_fingerprints(rssi_dbm, xy, min_heard_fraction: float = 0.5) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Average the scans of each reference point into one fingerprint (a RADAR-style radio map).

    Parameters
    ----------
    rssi_dbm : ndarray (n, n_aps), dBm, NaN = not heard
    xy : ndarray (n, d), positions; identical rows are one point
    min_heard_fraction : float
        An AP enters a point's fingerprint (mean of the readings where heard) only if heard in at
        least this fraction of the point's scans; otherwise it is NaN (not heard) there.

    Returns
    -------
    fp : ndarray (n_points, n_aps), mean dBm / NaN
    points : ndarray (n_points, d), in the order of first appearance
    point_of_row : ndarray (n,), the point index of each scan

    References
    ----------
    Bahl & Padmanabhan, RADAR (INFOCOM 2000): the radio map holds the mean signal strength per
    point; i-Loc thesis sec. 3.1 ("build each point's signal model").
    """
    x = check_rssi(rssi_dbm, "X", copy=False)  # read only: the sums below make new arrays
    y = np.asarray(xy, dtype=np.float64).reshape(x.shape[0], -1)
    if not 0.0 <= min_heard_fraction <= 1.0:
        raise ValueError(f"min_heard_fraction must be in [0, 1], got {min_heard_fraction}")
    # identical rows are one point (np.unique(axis=0)'s grouping: NaN rows apart, -0.0 = 0.0), points in the order
    # of their first row: one stable lexsort, each group's first row is its first in the sorted order
    srt_rows = np.lexsort(y.T[::-1])
    srt = y[srt_rows]
    new = np.ones(y.shape[0], dtype=bool)
    new[1:] = np.any(srt[1:] != srt[:-1], axis=1)
    first = srt_rows[new]
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    point = np.empty(y.shape[0], dtype=np.intp)
    point[srt_rows] = rank[np.cumsum(new) - 1]
    n_pts, m = order.size, x.shape[1]
    heard = ~np.isnan(x)
    # per (point, AP) sums over the point's rows in row order (bincount adds its weights in order, as np.add.at
    # did: the same sums, bit for bit); not heard adds 0 (check_rssi has rejected +-inf)
    cell = (point[:, None] * m + np.arange(m)).ravel()
    cnt = np.bincount(cell, weights=heard.ravel().astype(np.float64), minlength=n_pts * m).reshape(n_pts, m)
    tot = np.bincount(cell, weights=np.where(heard, x, 0.0).ravel(), minlength=n_pts * m).reshape(n_pts, m)
    n_scans = np.bincount(point, minlength=n_pts)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        fp = tot / cnt
    fp[(cnt == 0) | (cnt < min_heard_fraction * n_scans)] = np.nan
    return fp, y[first[order]], point


class RssiPositionTags:
    """scikit-learn tags shared by the fingerprint estimators: NaN means "not heard" (allowed in X),
    and the target is a 2-D position (multi-output). Put it first among the bases."""

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True
        tags.target_tags.multi_output = True
        return tags


def check_positions(y, n: int) -> np.ndarray:
    """Check the positions ``y`` of ``n`` reference scans: numeric, shape (n,) or (n, d), finite."""
    if y is None:
        raise ValueError("this estimator requires y to be passed, but the target y is None (positions in metres)")
    try:
        yy = np.asarray(y, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"y must be numeric positions: {exc}") from None
    if yy.ndim not in (1, 2) or yy.shape[0] != n:
        raise ValueError(f"y must have shape ({n},) or ({n}, d), got {yy.shape}")
    if not np.isfinite(yy).all():
        raise ValueError(f"y is not finite at row {np.argwhere(~np.isfinite(yy))[0][0]}")
    return yy


def heard_aps(x, owner: str = "the estimator") -> np.ndarray:
    """Boolean mask (n_aps,) of the access points heard at least once in the training matrix ``x``.

    Raises
    ------
    ValueError
        When no access point is heard anywhere in the training set (nothing to locate with).
    """
    heard = ~np.isnan(np.asarray(x, dtype=np.float64)).all(axis=0)
    if not heard.any():
        raise ValueError(f"{owner}: the training set hears no access point (every RSSI is NaN); "
                         "nothing to locate queries with")
    return heard


def shares_no_ap(x, heard) -> np.ndarray:
    """Boolean mask (n,) of the query rows of ``x`` hearing none of the access points in ``heard``."""
    return ~(~np.isnan(np.asarray(x, dtype=np.float64)) & np.asarray(heard, dtype=bool)[None, :]).any(axis=1)


def check_shared_aps(x, heard, owner: str = "the estimator") -> None:
    """Raise, naming the first row, when a query shares no access point with the training set."""
    bad = np.flatnonzero(shares_no_ap(x, heard))
    if bad.size:
        raise ValueError(f"X row {bad[0]} shares no access point with the training set of {owner} "
                         f"({bad.size} such rows); predict() gives such rows a NaN position")


def predict_located(x, heard, predict_rows, out_shape_tail=(2,)) -> np.ndarray:
    """``predict_rows(x[rows])`` on the rows sharing an AP with the training set, NaN on the others.

    Parameters
    ----------
    x : ndarray (n, n_aps)
    heard : ndarray of bool (n_aps,), :func:`heard_aps` of the training set
    predict_rows : callable, ndarray (m, n_aps) -> ndarray (m, ...)
    out_shape_tail : tuple
        Shape of one prediction (used when no row is located).
    """
    miss = shares_no_ap(x, heard)
    if not miss.any():
        return np.asarray(predict_rows(x))
    ok = np.flatnonzero(~miss)
    if not ok.size:
        return np.full((x.shape[0], *out_shape_tail), np.nan)
    part = np.asarray(predict_rows(x[ok]), dtype=np.float64)
    out = np.full((x.shape[0], *part.shape[1:]), np.nan)
    out[ok] = part
    return out
