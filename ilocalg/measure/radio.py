"""Radio statistics of Wi-Fi fingerprint sets: path loss, shadowing, device offset, drift, detection.

Every function takes arrays shaped like :class:`ilocalg.io.schema.FingerprintSet` (``rssi_dbm``
(n_samples, n_aps) with NaN = not heard, positions in metres, a place id per sample), so it runs
on UJIIndoorLoc, on ILC walks (scans positioned on the waypoints) and on the simulators' surveys.

Path-loss fit
    Per AP, on the place means where it is heard (place = a surveyed position), the log-distance
    model ``P0 - 10 n log10(max(d, 1 m))`` with the AP position unknown: nonlinear least squares
    over ``(x_ap, y_ap, P0, n)``, ``n`` in [1, 6], started at the RSSI-weighted centroid of the five
    strongest places. Shadowing sigma = the residual standard deviation (ddof 4). Walls are not
    modelled, so their losses are part of ``n`` and sigma. Readings below the sensitivity are
    missing, not observed (censoring): sigma and ``n`` are those of the heard readings.

References
----------
Rappaport, T. S. (2002). Wireless Communications, 2nd ed., sec. 4.9-4.11 (log-distance path loss,
log-normal shadowing).
Torres-Sospedra, J. et al. (2014). UJIIndoorLoc: a new multi-building and multi-floor database for
WLAN fingerprint-based indoor localization problems. IPIN.
Kaemarungsi, K., Krishnamurthy, P. (2004). Properties of indoor received signal strength for WLAN
location fingerprinting. MobiQuitous.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

__all__ = ["fit_path_loss", "path_loss_per_ap", "place_means", "device_offsets_db", "within_place_sd_db",
           "detection_curve", "fit_detection", "drift_per_ap_db", "aps_per_scan"]


#: scipy's relative step of the forward difference (``jac='2-point'``) for float64: sqrt(machine epsilon)
_FD_REL_STEP = np.finfo(np.float64).eps ** 0.5


class _ForwardDiff:
    """A residual function with the Jacobian :func:`scipy.optimize.least_squares` estimates by default
    (``jac='2-point'``: forward differences with steps ``sqrt(eps) * max(1, |x|)``, turned back or shortened at the
    bounds as scipy's ``_adjust_scheme_to_bounds`` does) as a callable: the same numbers in the same layout, so
    ``least_squares(d.fun, x0, jac=d.jac, bounds=(lb, ub))`` takes the default's steps bit for bit, without scipy's
    per-call finite-difference set-up, and reuses the residuals at the point just evaluated (tested against the
    default)."""

    def __init__(self, fun, lb, ub):
        self._fun = fun
        self.lb = np.asarray(lb, dtype=np.float64)
        self.ub = np.asarray(ub, dtype=np.float64)
        self._x = self._f = None

    def fun(self, x):
        f = self._fun(x)
        self._x, self._f = np.array(x, dtype=np.float64), f
        return f

    def jac(self, x):
        x = np.asarray(x, dtype=np.float64)
        f0 = self._f if self._x is not None and np.array_equal(x, self._x) else self._fun(x)
        lb, ub = self.lb, self.ub
        h = _FD_REL_STEP * ((x >= 0).astype(float) * 2 - 1) * np.maximum(1.0, np.abs(x))
        lower, upper = x - lb, ub - x
        violated = ((x + h) < lb) | ((x + h) > ub)
        fitting = np.abs(h) <= np.maximum(lower, upper)
        h_adj = h.copy()
        h_adj[violated & fitting] *= -1
        forward = (upper >= lower) & ~fitting
        h_adj[forward] = upper[forward]
        backward = (upper < lower) & ~fitting
        h_adj[backward] = -lower[backward]
        jt = np.empty((x.size, np.size(f0)))
        for i in range(x.size):
            x1 = x.copy()
            x1[i] = x[i] + h_adj[i]
            jt[i] = (np.atleast_1d(self._fun(x1)) - f0) / ((x[i] + h_adj[i]) - x[i])
        return jt.T


def fit_path_loss(xy_m, rssi_dbm, min_points: int = 12) -> dict | None:
    """Fit ``P0 - 10 n log10(max(d, 1))`` with unknown AP position to one AP's readings.

    Parameters
    ----------
    xy_m : ndarray (n, 2)
        Positions of the readings, metres.
    rssi_dbm : ndarray (n,)
        Readings (heard only; NaN rows are ignored).
    min_points : int
        Fewer heard readings -> ``None``.

    Returns
    -------
    dict or None
        ``x_m, y_m, p0_dbm, n, sigma_db, n_points, residual_db`` (residuals in input order of heard rows).
    """
    xy = np.asarray(xy_m, dtype=np.float64)
    r = np.asarray(rssi_dbm, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[1] != 2 or xy.shape[0] != r.shape[0]:
        raise ValueError(f"xy_m must be (n, 2) and rssi_dbm (n,), got {xy.shape} and {r.shape}")
    ok = np.isfinite(r) & np.isfinite(xy).all(axis=1)
    xy, r = xy[ok], r[ok]
    if r.size < max(min_points, 6):
        return None
    top = np.argsort(r)[-5:]
    w = 10 ** (r[top] / 10.0)
    c0 = (xy[top] * w[:, None]).sum(axis=0) / w.sum()

    def res(q):
        d = np.maximum(np.hypot(xy[:, 0] - q[0], xy[:, 1] - q[1]), 1.0)
        return q[2] - 10.0 * q[3] * np.log10(d) - r

    lo = [xy[:, 0].min() - 30, xy[:, 1].min() - 30, -80.0, 1.0]
    hi = [xy[:, 0].max() + 30, xy[:, 1].max() + 30, 0.0, 6.0]
    q0 = np.clip([c0[0], c0[1], r.max() + 5.0, 2.5], np.add(lo, 1e-6), np.subtract(hi, 1e-6))
    d = _ForwardDiff(res, lo, hi)  # the default Jacobian's numbers, computed with less overhead
    sol = least_squares(d.fun, q0, jac=d.jac, bounds=(lo, hi), loss="linear")
    e = -sol.fun  # observed - model
    dof = max(r.size - 4, 1)
    return {"x_m": sol.x[0], "y_m": sol.x[1], "p0_dbm": sol.x[2], "n": sol.x[3],
            "sigma_db": float(np.sqrt((e**2).sum() / dof)), "n_points": int(r.size), "residual_db": e}


def place_means(rssi_dbm, place, offset_db=None):
    """Mean heard RSSI per place and AP, shape (n_places, n_aps) (NaN where never heard), and the places.

    ``offset_db`` (n_samples,), if given, is subtracted from every sample first (device correction).
    """
    r = np.asarray(rssi_dbm, dtype=np.float64)
    if offset_db is not None:
        r = r - np.asarray(offset_db, dtype=np.float64)[:, None]
    places, inv = np.unique(np.asarray(place), return_inverse=True)
    inv = inv.reshape(-1)
    h = np.isfinite(r)
    x = np.where(h, r, 0.0)
    # per AP, the sums over each place's samples in sample order (as np.add.at would add them, many times faster)
    s = np.zeros((places.size, r.shape[1]))
    c = np.zeros_like(s)
    for j in range(r.shape[1]):
        s[:, j] = np.bincount(inv, weights=x[:, j], minlength=places.size)
        c[:, j] = np.bincount(inv, weights=h[:, j], minlength=places.size)
    with np.errstate(invalid="ignore"):
        return s / np.where(c > 0, c, np.nan), places


def path_loss_per_ap(place_xy_m, means_dbm, group=None, min_points: int = 12) -> pd.DataFrame:
    """:func:`fit_path_loss` for every AP (column of ``means_dbm``), within each ``group`` (e.g. floor).

    An AP is fitted once, in the group where its strongest place mean lies.

    Returns
    -------
    DataFrame
        One row per fitted AP: ``ap, group, n, p0_dbm, sigma_db, n_points``; the residuals in
        ``attrs["residuals"]`` (dict ap -> array).
    """
    xy = np.asarray(place_xy_m, dtype=np.float64)
    m = np.asarray(means_dbm, dtype=np.float64)
    g = np.zeros(len(xy), dtype=np.int64) if group is None else np.asarray(group)
    rows, resid = [], {}
    for j in range(m.shape[1]):
        col = m[:, j]
        if np.isfinite(col).sum() < min_points:
            continue
        gj = g[np.nanargmax(col)]
        sel = (g == gj) & np.isfinite(col)
        f = fit_path_loss(xy[sel], col[sel], min_points)
        if f is None:
            continue
        rows.append({"ap": j, "group": gj, "n": f["n"], "p0_dbm": f["p0_dbm"], "sigma_db": f["sigma_db"],
                     "n_points": f["n_points"]})
        resid[j] = f["residual_db"]
    out = pd.DataFrame(rows, columns=["ap", "group", "n", "p0_dbm", "sigma_db", "n_points"])
    out.attrs["residuals"] = resid
    return out


def device_offsets_db(rssi_dbm, place, device, min_devices: int = 2, n_iter: int = 30) -> pd.Series:
    """Per-device RSSI offset (dB, mean over devices 0) from places read by several devices.

    Additive model ``mean RSSI[place, AP, device] = mu[place, AP] + offset[device]`` fitted by
    alternating least squares on the (place, AP) cells heard by at least ``min_devices`` devices.
    """
    r = np.asarray(rssi_dbm, dtype=np.float64)
    place = np.asarray(place)
    device = np.asarray(device)
    key = pd.MultiIndex.from_arrays([place, device]).factorize()[0]
    cell_means, cells = place_means(r, key)
    first = pd.Series(np.arange(len(key))).groupby(key).first().reindex(cells).to_numpy()
    pl, dv = place[first], device[first]
    df = pd.DataFrame(cell_means)
    df["place"], df["device"] = pl, dv
    long = df.melt(id_vars=["place", "device"], var_name="ap", value_name="rssi").dropna()
    nd = long.groupby(["place", "ap"])["device"].transform("nunique")
    long = long[nd >= min_devices]
    if long.empty:
        raise ValueError(f"no (place, AP) cell is heard by >= {min_devices} devices")
    off = pd.Series(0.0, index=np.unique(long["device"]))
    pa = long.groupby(["place", "ap"]).ngroup().to_numpy()
    dev = long["device"].to_numpy()
    y = long["rssi"].to_numpy()
    for _ in range(n_iter):
        mu = pd.Series(y - off.reindex(dev).to_numpy()).groupby(pa).transform("mean").to_numpy()
        off = pd.Series(y - mu).groupby(dev).mean()
        off = off - off.mean()
    return off


def within_place_sd_db(rssi_dbm, cell, min_samples: int = 5) -> np.ndarray:
    """Per-(cell, AP) standard deviation (ddof 1) of RSSI over samples in the same cell, heard in all.

    A cell is a place read by one device in one visit (UJI: place and phone); this is the scan-to-scan
    (fast fading) spread of a static phone.
    """
    r = np.asarray(rssi_dbm, dtype=np.float64)
    cells, inv = np.unique(np.asarray(cell), return_inverse=True)
    out = []
    for k in range(cells.size):
        blk = r[inv == k]
        if blk.shape[0] < min_samples:
            continue
        full = np.isfinite(blk).all(axis=0)
        if full.any():
            out.append(blk[:, full].std(axis=0, ddof=1))
    return np.concatenate(out) if out else np.array([])


def detection_curve(rssi_dbm, cell, min_samples: int = 8):
    """Per-(cell, AP) mean heard RSSI and the fraction of the cell's scans that heard the AP.

    Only cells in which the AP was heard at least once count (an AP never heard has no mean).
    Returns ``(mean_dbm, frac_heard, cell_index)`` flattened.
    """
    r = np.asarray(rssi_dbm, dtype=np.float64)
    cells, inv = np.unique(np.asarray(cell), return_inverse=True)
    ms, fs, ks = [], [], []
    for k in range(cells.size):
        blk = r[inv == k]
        if blk.shape[0] < min_samples:
            continue
        h = np.isfinite(blk)
        any_h = h.any(axis=0)
        with np.errstate(invalid="ignore"):
            m = np.nanmean(np.where(h, blk, np.nan)[:, any_h], axis=0)
        ms.append(m)
        fs.append(h[:, any_h].mean(axis=0))
        ks.append(np.full(m.size, k))
    if not ms:
        return np.array([]), np.array([]), np.array([], dtype=np.int64)
    return np.concatenate(ms), np.concatenate(fs), np.concatenate(ks)


def fit_detection(mean_dbm, frac) -> dict:
    """Logistic fit ``p = p_max / (1 + exp(-(m - m50) / s))`` of heard fraction vs mean RSSI.

    Returns ``m50_dbm`` (mean RSSI heard half as often as a strong AP), ``scale_db``, ``p_max``.
    """
    m = np.asarray(mean_dbm, dtype=np.float64)
    f = np.asarray(frac, dtype=np.float64)
    if m.size < 10:
        raise ValueError(f"fit_detection needs >= 10 points, got {m.size}")

    def res(q):
        return q[2] / (1.0 + np.exp(-(m - q[0]) / q[1])) - f

    lb, ub = [-120, 0.2, 0.3], [-30, 20, 1.0]
    d = _ForwardDiff(res, lb, ub)  # the default Jacobian's numbers, computed with less overhead
    sol = least_squares(d.fun, [np.median(m) - 5.0, 3.0, 0.95], jac=d.jac, bounds=(lb, ub))
    return {"m50_dbm": float(sol.x[0]), "scale_db": float(sol.x[1]), "p_max": float(sol.x[2])}


def drift_per_ap_db(train_means_dbm, train_xy_m, train_group, test_rssi_dbm, test_xy_m, test_group,
                    test_device=None, radius_m: float = 3.0, min_pairs: int = 10) -> pd.Series:
    """Survey-to-test change of each AP's mean RSSI (dB), device offsets of the test phones removed.

    For every test scan, the survey place means of the same group (building-floor) within
    ``radius_m`` are averaged; ``d = test - survey`` per heard AP. The test device's median ``d``
    (over all its APs) is subtracted (its offset to the survey phones), then ``d`` is averaged per
    AP (APs with at least ``min_pairs`` pairs). Returns the per-AP drift.
    """
    tm = np.asarray(train_means_dbm, dtype=np.float64)
    txy = np.asarray(train_xy_m, dtype=np.float64)
    tg = np.asarray(train_group)
    r = np.asarray(test_rssi_dbm, dtype=np.float64)
    xy = np.asarray(test_xy_m, dtype=np.float64)
    g = np.asarray(test_group)
    dev = np.zeros(len(r)) if test_device is None else np.asarray(test_device)
    d_rows, ap_rows, dv_rows = [], [], []
    for i in range(len(r)):
        near = (tg == g[i]) & (np.hypot(txy[:, 0] - xy[i, 0], txy[:, 1] - xy[i, 1]) <= radius_m)
        if not near.any():
            continue
        blk = tm[near]
        cnt = np.isfinite(blk).sum(axis=0)
        ref = np.where(cnt > 0, np.nansum(blk, axis=0) / np.maximum(cnt, 1), np.nan)
        ok = np.isfinite(ref) & np.isfinite(r[i])
        d_rows.append(r[i, ok] - ref[ok])
        ap_rows.append(np.flatnonzero(ok))
        dv_rows.append(np.full(ok.sum(), dev[i]))
    if not d_rows:
        raise ValueError(f"no test scan has a survey place within {radius_m} m")
    d = pd.DataFrame({"d": np.concatenate(d_rows), "ap": np.concatenate(ap_rows), "dev": np.concatenate(dv_rows)})
    d["d"] = d["d"] - d.groupby("dev")["d"].transform("median")
    cnt = d.groupby("ap")["d"].size()
    return d.groupby("ap")["d"].mean()[cnt >= min_pairs]


def aps_per_scan(rssi_dbm) -> np.ndarray:
    """Number of APs heard in each scan (row)."""
    return np.isfinite(np.asarray(rssi_dbm, dtype=np.float64)).sum(axis=1)
