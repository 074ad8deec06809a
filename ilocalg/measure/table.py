"""The measured-parameter table ``data/measured_parameters.csv``: build it from the shared data.

One row per parameter: ``parameter, value, ci_low, ci_high, unit, dataset, method``. Every interval
is a seeded 95 % percentile bootstrap (:func:`ilocalg.measure.stats.bootstrap`), resampling walks,
APs or recordings as the ``method`` column says. ``python -m ilocalg measure`` (or ``make measured``)
rewrites the file; ``tests/test_measured_realdata.py`` recomputes it on a deterministic subsample
and fails when a value leaves its interval.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import REPO_ROOT
from ilocalg.measure import gait, heading, radio, scans
from ilocalg.measure.stats import Estimate, bootstrap

__all__ = ["COLUMNS", "TABLE_PATH", "build_table", "write_table", "scan_rows", "ilc_walk_measures",
           "PARTS", "uji_radio_rows", "oxford_gait_rows", "ilc_gait_rows", "heading_rows", "uji_places"]

COLUMNS = ("parameter", "value", "ci_low", "ci_high", "unit", "dataset", "method")
TABLE_PATH = REPO_ROOT / "data" / "measured_parameters.csv"
PARTS = ("scans", "radio", "gait", "heading")
_ILC = "ILC 2.0 site1 (F1+F2 walks)"


def _row(name: str, est: Estimate, unit: str, dataset: str, method: str) -> dict:
    return {"parameter": name, "value": est.value, "ci_low": est.ci_low, "ci_high": est.ci_high,
            "unit": unit, "dataset": dataset, "method": f"{method} [n={est.n}]"}


def _iqr(x):
    q = np.quantile(x, [0.25, 0.75])
    return float(q[1] - q[0])


def ilc_walk_measures(trace, parts=PARTS) -> dict:
    """Per-walk raw measurements of one ILC trace (arrays), the input of the ``*_rows`` builders.

    ``parts`` limits the work (``"scans"``; ``"gait"`` and ``"heading"`` need the IMU).
    """
    out = {}
    w = trace.wifi
    if len(w) and "scans" in parts:
        out["scan_interval_s"] = scans.scan_intervals_s(w)
        out["age_distinct_s"] = scans.reading_ages_s(w, distinct=True)
        out["age_listed_s"] = scans.reading_ages_s(w, distinct=False)
        out["n_listed"] = np.array([len(w)])
        out["n_distinct"] = np.array([out["age_distinct_s"].size])
        out["aps_per_scan"] = w.groupby("scan_id").size().to_numpy()
        fresh = scans.distinct_readings(w)
        out["fresh_aps_per_scan"] = fresh.groupby("scan_id").size().reindex(
            np.unique(w["scan_id"]), fill_value=0).to_numpy()
    imu, wp = trace.imu, trace.waypoints
    if len(imu) > 100 and len(wp) >= 2 and ("gait" in parts or "heading" in parts):
        acc = imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
        try:
            out["segments"] = gait.segment_gait(acc, imu.index.to_numpy(), wp["t_s"].to_numpy(),
                                                wp[["x_m", "y_m"]].to_numpy())
        except ValueError:
            out["segments"] = None
        if len(trace.rotation_vector) > 10:
            out["headings"] = heading.segment_headings(imu, trace.rotation_vector, wp)
        out["mag_norm_ut"] = np.linalg.norm(imu[["mag_x_ut", "mag_y_ut", "mag_z_ut"]].to_numpy(), axis=1)
    return out


def scan_rows(walks: list[dict], dataset: str = _ILC) -> list[dict]:
    """Scan interval and reading-age rows from per-walk measures (resampled by walk)."""
    iv = [m["scan_interval_s"] for m in walks if "scan_interval_s" in m and m["scan_interval_s"].size]
    ad = [m["age_distinct_s"] for m in walks if "age_distinct_s" in m]
    al = [m["age_listed_s"] for m in walks if "age_listed_s" in m]
    frac = [np.array([[m["n_distinct"][0], m["n_listed"][0]]]) for m in walks if "n_listed" in m]
    rows = [
        _row("wifi_scan_interval_s", bootstrap(iv, np.median), "s", dataset,
             "median time between consecutive scans while walking; bootstrap over walks"),
        _row("wifi_scan_interval_iqr_s", bootstrap(iv, _iqr), "s", dataset,
             "interquartile range of the scan interval; bootstrap over walks"),
        _row("wifi_scan_interval_p90_s", bootstrap(iv, lambda x: np.quantile(x, 0.9)), "s", dataset,
             "90th percentile of the scan interval; bootstrap over walks"),
        _row("wifi_reading_age_median_s", bootstrap(ad, np.median), "s", dataset,
             "median of t_scan - last_seen over distinct readings (re-listed cached readings: same AP, "
             "same RSSI, last_seen within 5 ms, dropped; age at first listing); bootstrap over walks"),
        _row("wifi_reading_age_iqr_s", bootstrap(ad, _iqr), "s", dataset,
             "interquartile range of the distinct readings' age; bootstrap over walks"),
        _row("wifi_reading_age_p90_s", bootstrap(ad, lambda x: np.quantile(x, 0.9)), "s", dataset,
             "90th percentile of the distinct readings' age; bootstrap over walks"),
        _row("wifi_listed_age_median_s", bootstrap(al, np.median), "s", dataset,
             "median of t_scan - last_seen over every listed row (re-listings included); bootstrap over walks"),
        _row("wifi_relisted_fraction", bootstrap(frac, lambda a: 1.0 - a[:, 0].sum() / a[:, 1].sum()), "1",
             dataset, "share of TYPE_WIFI rows that re-list an earlier reading; bootstrap over walks"),
    ]
    return rows


def ilc_gait_rows(walks: list[dict], dataset: str = _ILC) -> list[dict]:
    """Gait correlations across waypoint segments (resampled by walk)."""
    segs = [m["segments"].assign(walk=i) for i, m in enumerate(walks)
            if m.get("segments") is not None and len(m["segments"])]
    arrs = [s[["A_mps2", "SL_m", "T_s", "speed_mps"]].to_numpy() for s in segs]

    def stat(key):
        def f(a):
            return gait.gait_correlations(pd.DataFrame(a, columns=["A_mps2", "SL_m", "T_s", "speed_mps"]))[key]
        return f

    how = ("across waypoint-to-waypoint segments (steps counted by the robust detector, SL = straight distance / "
           "steps); bootstrap over walks")
    return [
        _row("gait_corr_A_SL", bootstrap(arrs, stat("corr_A_SL")), "1", dataset,
             "Pearson corr(mean step amplitude, mean step length) " + how),
        _row("gait_corr_T_SL", bootstrap(arrs, stat("corr_T_SL")), "1", dataset,
             "Pearson corr(mean step period, mean step length) " + how),
        _row("gait_A_resid_rel", bootstrap(arrs, stat("A_resid_rel")), "1", dataset,
             "residual sd of A ~ 1 + SL + speed over mean A (amplitude spread at equal length and speed) " + how),
        _row("gait_step_length_median_m", bootstrap([a[:, 1] for a in arrs], np.median), "m", dataset,
             "median segment mean step length " + how),
        _row("gait_speed_median_mps", bootstrap([a[:, 3] for a in arrs], np.median), "m/s", dataset,
             "median segment speed " + how),
    ]


def heading_rows(walks: list[dict], floors: list[str], dataset: str = _ILC) -> list[dict]:
    """Misalignment (rotation vector and WDM) and magnetic disturbance rows (resampled by walk)."""
    hs = []
    for i, (m, f) in enumerate(zip(walks, floors, strict=True)):
        h = m.get("headings")
        if h is not None and len(h):
            hs.append(h.assign(walk=i, floor=f))
    H = pd.concat(hs, ignore_index=True)
    H["mis_rv"] = heading.misalignment(H["rv_rad"], H["dir_rad"], H["floor"])
    H["mis_wdm"] = heading.misalignment(H["wdm_rad"], H["dir_rad"], H["floor"])
    H["wdm_minus_rv"] = heading.wrap_rad(H["mis_wdm"] - H["mis_rv"])
    groups = [g for _, g in H.groupby("walk")]

    def col_stat(col, fn):
        return lambda a: fn(np.degrees(a))

    def rms(x):
        return float(np.sqrt(np.mean(np.square(x))))

    rows = []
    for col, what in (("mis_rv", "rotation-vector heading of the phone's y axis"),
                      ("mis_wdm", "WDM heading (gravity + raw magnetometer, eq. 18-19)"),
                      ("wdm_minus_rv", "WDM minus rotation-vector heading")):
        arr = [g[col].to_numpy() for g in groups]
        rows.append(_row(f"heading_{col}_rms_deg", bootstrap(arr, col_stat(col, rms)), "deg", dataset,
                         f"rms over waypoint segments of {what} minus walking direction, each floor's circular "
                         f"median removed; bootstrap over walks"))
        rows.append(_row(f"heading_{col}_mad_deg", bootstrap(arr, col_stat(col, lambda x: 1.4826 * np.median(
            np.abs(x - np.median(x))))), "deg", dataset,
                         "1.4826 MAD (robust sd) of the same; bootstrap over walks"))
    wm = np.array([[np.degrees(heading.circ_mean_rad(g["mis_rv"]))] for g in groups if len(g) >= 2])
    rows.append(_row("heading_mis_rv_walk_sd_deg", bootstrap(wm[:, 0], lambda x: float(np.std(x, ddof=1))), "deg",
                     dataset, "sd over walks (>= 2 segments) of the walk's circular mean rotation-vector heading minus "
                     "walking direction (between-walk misalignment; floor medians removed); bootstrap over walks"))
    within = [np.degrees(heading.wrap_rad(g["mis_rv"].to_numpy() - heading.circ_mean_rad(g["mis_rv"])))
              for g in groups if len(g) >= 2]
    rows.append(_row("heading_mis_rv_within_rms_deg", bootstrap(within, rms), "deg", dataset,
                     "rms over segments of the rotation-vector misalignment about its walk's mean (within-walk "
                     "part); bootstrap over walks"))
    mags = []
    for m, f in zip(walks, floors, strict=True):
        if "mag_norm_ut" in m:
            mags.append((f, m["mag_norm_ut"]))
    med = {f: np.median(np.concatenate([x for ff, x in mags if ff == f])) for f in {f for f, _ in mags}}
    dev = [x - med[f] for f, x in mags]
    rows.append(_row("mag_norm_sd_ut", bootstrap(dev, lambda x: float(np.std(x))), "uT", dataset,
                     "sd of the magnetometer field magnitude about its floor median (indoor disturbance; "
                     "uncalibrated hard iron of the phone included); bootstrap over walks"))
    return rows


def uji_places(fs):
    """Place ids (building, floor, SPACEID, RELATIVEPOSITION) of a UJIIndoorLoc set."""
    m = fs.meta
    return pd.MultiIndex.from_arrays([fs.building, fs.floor, m["SPACEID"], m["RELATIVEPOSITION"]]).factorize()[0]


def uji_radio_rows(train, test, dataset: str = "UJIIndoorLoc (training; validation months later)") -> list[dict]:
    """Radio rows from UJIIndoorLoc: device offsets, path loss, shadowing, fading, detection, drift, APs/scan."""
    m = train.meta
    place = uji_places(train)
    phone = m["PHONEID"].to_numpy()
    off = radio.device_offsets_db(train.rssi_dbm, place, phone)
    rows = [_row("device_offset_sd_db", bootstrap(off.to_numpy(), lambda x: float(np.std(x, ddof=1))), "dB",
                 dataset, "sd over phones of the per-PHONEID offset (additive place x AP + phone model on places "
                 "read by >= 2 phones; phone and user confounded); bootstrap over phones")]
    o = off.reindex(phone).fillna(0.0).to_numpy()
    pm, _ = radio.place_means(train.rssi_dbm, place, o)
    first = pd.Series(np.arange(len(place))).groupby(place).first().to_numpy()
    pxy = np.column_stack([train.x_m[first], train.y_m[first]])
    pg = train.building[first] * 10 + train.floor[first]
    pl = radio.path_loss_per_ap(pxy, pm, pg)
    how = ("per-AP log-distance fit with unknown AP position on device-corrected place means of the AP's "
           "strongest floor (walls absorbed, heard readings only)")
    rows.append(_row("shadow_sd_db", bootstrap(pl["sigma_db"].to_numpy(), np.median), "dB", dataset,
                     f"median over APs of the residual sd, {how}; bootstrap over APs"))
    rows.append(_row("path_loss_exponent", bootstrap(pl["n"].to_numpy(), np.median), "1", dataset,
                     f"median over APs of n, {how}; bootstrap over APs"))
    rows.append(_row("path_loss_p0_dbm", bootstrap(pl["p0_dbm"].to_numpy(), np.median), "dBm", dataset,
                     f"median over APs of P0 (RSSI at 1 m, fitted jointly with n), {how}; bootstrap over APs"))
    cell = pd.MultiIndex.from_arrays([place, phone]).factorize()[0]
    sd = radio.within_place_sd_db(train.rssi_dbm, cell)
    rows.append(_row("fade_sd_db", bootstrap(sd, lambda x: float(np.sqrt(np.mean(x**2)))), "dB", dataset,
                     "pooled (rms) sd of RSSI over the scans of one phone at one place, per AP heard in all of "
                     "them; bootstrap over (place, phone, AP) cells"))
    mm, ff, kk = radio.detection_curve(train.rssi_dbm, cell)
    grp = [np.column_stack([mm[kk == k], ff[kk == k]]) for k in np.unique(kk)]
    for key, name, unit in (("m50_dbm", "detect_m50_dbm", "dBm"), ("scale_db", "detect_scale_db", "dB"),
                            ("p_max", "detect_p_max", "1")):
        rows.append(_row(name, bootstrap(grp, lambda a, key=key: radio.fit_detection(a[:, 0], a[:, 1])[key],
                                         n_boot=50), unit, dataset,
                         f"logistic fit p = p_max / (1 + exp(-(m - m50) / s)) of the share of a cell's scans "
                         f"hearing an AP vs its mean heard RSSI: {key}; bootstrap over (place, phone) cells"))
    r = train.rssi_dbm
    heard = np.isfinite(r).any(axis=1)
    weakest = np.nanmin(r[heard], axis=1)
    rows.append(_row("rssi_floor_dbm", bootstrap(weakest, lambda x: float(np.quantile(x, 0.01))), "dBm", dataset,
                     "1st percentile of each scan's weakest reported RSSI (the phones' reporting floor); "
                     "bootstrap over scans"))
    dr = radio.drift_per_ap_db(pm, pxy, pg, test.rssi_dbm, np.column_stack([test.x_m, test.y_m]),
                               test.building * 10 + test.floor, test.meta["PHONEID"].to_numpy())
    rows.append(_row("drift_sd_db", bootstrap(dr.to_numpy(), lambda x: float(np.std(x, ddof=1))), "dB", dataset,
                     "sd over APs of the validation-minus-training mean RSSI within 3 m on the same floor, each "
                     "validation phone's median offset removed; bootstrap over APs"))
    rows.append(_row("aps_per_scan_median", bootstrap(radio.aps_per_scan(train.rssi_dbm).astype(float), np.median),
                     "1", dataset, "median APs heard per training scan; bootstrap over scans"))
    return rows


def oxford_gait_rows(recs, dataset: str = "Oxford step counter (16 InHand walks, heel-sensor steps)") -> list[dict]:
    """Step-to-step variability of period and amplitude from true steps (resampled by recording)."""
    v = []
    for r in recs:
        s = gait.step_series(r.imu.to_numpy(), r.imu.index.to_numpy(), r.step_t_s)
        v.append(gait.step_variability(s))
    V = pd.DataFrame(v)
    rows = []
    for key, name, what in (("rcv_T", "gait_step_period_cv", "step period"),
                            ("rcv_A", "gait_step_amp_cv", "step peak-to-trough amplitude (3 Hz low-passed norm)"),
                            ("cv_stride", "gait_stride_period_cv", "two-step stride period")):
        rows.append(_row(name, bootstrap(V[key].to_numpy(), np.median), "1", dataset,
                         f"median over recordings of the within-walk robust CV (1.4826 MAD / median) of the "
                         f"{what}, steady steps between heel-sensor contacts; bootstrap over recordings"))
    return rows


def build_table(root=None, every: int = 1, parts=PARTS) -> pd.DataFrame:
    """Measure every parameter from the shared data and return the table (columns :data:`COLUMNS`).

    Parameters
    ----------
    root : path, optional
        The data directory (default :func:`ilocalg.io.paths.data_dir`).
    every : int
        ILC site1 subsample (:func:`ilocalg.measure.sources.iter_ilc_site1`); 1 = all walks.
    parts : iterable of str
        Which groups of rows to measure (:data:`PARTS`).
    """
    from ilocalg.measure.sources import iter_ilc_site1

    parts = tuple(parts)
    bad = [p for p in parts if p not in PARTS]
    if bad:
        raise ValueError(f"unknown part(s) {bad}; known: {list(PARTS)}")
    base = Path(root) if root is not None else None
    rows: list[dict] = []
    from ilocalg.io.paths import data_dir

    ds = _ILC if every == 1 else f"ILC 2.0 site1 (F1+F2 walks with trace id % {every} == 0)"

    droot = base if base is not None else data_dir()
    if any(p in parts for p in ("scans", "heading", "gait")):
        walks, floors = [], []
        for fl, _, tr in iter_ilc_site1(droot / "ilc2020_site1", every=every):
            walks.append(ilc_walk_measures(tr))
            floors.append(fl)
        if "scans" in parts:
            rows += scan_rows(walks, ds)
            aps = [m["aps_per_scan"].astype(float) for m in walks if "aps_per_scan" in m]
            fr = [m["fresh_aps_per_scan"].astype(float) for m in walks if "fresh_aps_per_scan" in m]
            rows.append(_row("ilc_aps_per_scan_median", bootstrap(aps, np.median), "1", ds,
                             "median APs listed per scan (re-listings included); bootstrap over walks"))
            rows.append(_row("ilc_fresh_aps_per_scan_median", bootstrap(fr, np.median), "1", ds,
                             "median APs per scan with a new reading (re-listings removed); bootstrap over walks"))
        if "gait" in parts:
            rows += ilc_gait_rows(walks, ds)
        if "heading" in parts:
            rows += heading_rows(walks, floors, ds)
    if "radio" in parts:
        from ilocalg.io.ujiindoorloc import load_ujiindoorloc

        u = droot / "ujiindoorloc"
        rows += uji_radio_rows(load_ujiindoorloc(u / "trainingData.csv.gz"),
                               load_ujiindoorloc(u / "validationData.csv.gz"))
    if "gait" in parts:
        from ilocalg.io.oxford import load_oxford_archive

        arch = droot / "oxford_step_counter" / "optimisation_data.tar.xz"
        rows += oxford_gait_rows(load_oxford_archive(arch, select=lambda n: "_InHand_" in n))
    df = pd.DataFrame(rows, columns=list(COLUMNS))
    if df["parameter"].duplicated().any():
        raise ValueError(f"duplicate parameters: {df.loc[df['parameter'].duplicated(), 'parameter'].tolist()}")
    return df


def write_table(df: pd.DataFrame, path=TABLE_PATH) -> Path:
    """Write the table as CSV (6 significant digits) and return the path."""
    path = Path(path)
    out = df.copy()
    for c in ("value", "ci_low", "ci_high"):
        out[c] = out[c].map(lambda v: float(f"{v:.6g}"))
    path.parent.mkdir(parents=True, exist_ok=True)
    out.to_csv(path, index=False)
    return path
