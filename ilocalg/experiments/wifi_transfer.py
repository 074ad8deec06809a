"""Does the toolkit's UJIIndoorLoc headline carry over to another site? The ILC 2.0 walks' Wi-Fi scans.

The headline configuration (:func:`ilocalg.wifi.candidates.toolkit_estimator`, ``evaluate wifi --method toolkit``)
was chosen by cross-validation on UJIIndoorLoc's training set alone. Here it is fitted, unchanged, on another
site's scans, beside the plain WKNN the track pipeline takes as its Wi-Fi reference
(:data:`ilocalg.track.lowo.PLAIN_WKNN`: K = 5, Euclidean on dBm, 1/d weights, readings at
most 2 s old). Nothing is chosen here, on these walks or any other.

Protocol: per floor, every scan of every walk (its readings at most :data:`MAX_AGE_S` old; a scan left with none is
dropped) positioned on the walk's ground truth (:class:`ilocalg.track.WifiDatabase`); 5-fold GroupKFold by walk
(whole walks held out: a phone and a day the fold's training part never saw); the access points heard in the
fold's training part. Floor and building are one label each (the floor's walks), so only the 2-D error counts.
The two methods see the same folds; the ratio of their mean errors has a 95 % interval from resampling walks
(:func:`ilocalg.measure.stats.bootstrap_many`).

``run(seed, fast, data_dir)`` returns None without the ILC data, else tables ``transfer`` (per floor and method:
scans, walks, mean [CI], median, p75 of the 2-D error), ``transfer_ratio`` (per floor: the toolkit's mean error over
WKNN's, with its interval) and ``readings``. ``fast``: the 19-walk site 2 floor only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io.paths import data_dir as default_data_dir

__all__ = ["FLOORS", "FLOORS_FAST", "N_FOLDS", "MAX_AGE_S", "METHODS", "floor_scans", "cross_validate", "run",
           "findings"]

#: The ILC 2.0 floors: site 1's two densely surveyed floors, site 2's fourth floor.
FLOORS = ("ilc2020_site1/site1_F1", "ilc2020_site1/site1_F2", "ilc2020_site2_F4")
FLOORS_FAST = ("ilc2020_site2_F4",)
#: Folds of the GroupKFold by walk.
N_FOLDS = 5
#: Oldest reading kept in a scan, s (the track pipeline's plain Wi-Fi reference, PLAIN_WKNN).
MAX_AGE_S = 2.0
#: Row labels: the plain reference and the headline.
METHODS = ("WKNN K=5 (Euclidean, dBm; the track pipeline's plain reference)",
           "toolkit headline (evaluate wifi --method toolkit)")


def floor_scans(data_dir, dataset: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(rssi_dbm (n, n_aps), xy_m (n, 2), walk (n,))`` of every scan of a floor hearing at least one access point
    within :data:`MAX_AGE_S` (:meth:`ilocalg.track.WifiDatabase.from_traces`), positioned on its walk's truth."""
    from ilocalg.track.database import WifiDatabase
    from ilocalg.track.lowo import load_floor

    fl = load_floor(data_dir, dataset)
    db = WifiDatabase.from_traces([fl.traces[n] for n in fl.names], max_age_s=MAX_AGE_S)
    heard = np.isfinite(db.rssi_dbm).any(axis=1)
    return db.rssi_dbm[heard], db.xy_m[heard], np.asarray(db.walk)[heard]


def cross_validate(x: np.ndarray, xy: np.ndarray, walk: np.ndarray, n_folds: int = N_FOLDS) -> np.ndarray:
    """2-D errors (n, 2) of the two :data:`METHODS` for every scan, each scan predicted by the fold that holds out
    its walk (GroupKFold by walk; access points heard in the fold's training part)."""
    from sklearn.model_selection import GroupKFold

    from ilocalg.track.lowo import PLAIN_WKNN
    from ilocalg.wifi.candidates import toolkit_estimator
    from ilocalg.wifi.ensemble import ApSelector
    from ilocalg.wifi.knn import KnnFingerprint

    err = np.full((xy.shape[0], 2), np.nan)
    zeros = np.zeros((xy.shape[0], 2))
    for tr, te in GroupKFold(n_folds).split(x, xy, walk):
        aps = ApSelector(1).fit(x[tr])
        a, b = aps.transform(x[tr]), aps.transform(x[te])
        wknn = KnnFingerprint(n_neighbors=PLAIN_WKNN["k_neighbors"], p=PLAIN_WKNN["p"],
                              weights=PLAIN_WKNN["weights"], not_heard_dbm=-100.0).fit(a, xy[tr])
        tk = toolkit_estimator().fit(a, np.column_stack([xy[tr], zeros[tr]]))
        for j, pr in enumerate((wknn.predict(b), tk.predict(b)[:, :2])):
            err[te, j] = np.hypot(pr[:, 0] - xy[te, 0], pr[:, 1] - xy[te, 1])
    return err


def run(seed: int = 0, fast: bool = False, data_dir: str | Path | None = None) -> dict[str, pd.DataFrame] | None:
    """The tables of the module docstring; ``seed`` seeds the bootstrap only. None without the ILC data."""
    from ilocalg.measure.stats import bootstrap_many
    from ilocalg.papers import reading, readings_table

    root = Path(default_data_dir() if data_dir is None else data_dir)
    floors = FLOORS_FAST if fast else FLOORS
    if not all((root / ds.partition("/")[0]).is_dir() for ds in floors):
        return None
    rows, ratios = [], []
    for ds in floors:
        x, xy, walk = floor_scans(root, ds)
        err = cross_validate(x, xy, walk)
        groups = [err[walk == w] for w in np.unique(walk)]
        est = bootstrap_many(groups, lambda v: (v[:, 0].mean(), v[:, 1].mean(), v[:, 1].mean() / v[:, 0].mean()),
                             rng=seed)
        for j, name in enumerate(METHODS):
            e = err[:, j]
            rows.append({"floor": ds, "method": name, "n_scans": int(e.size), "n_walks": len(groups),
                         "mean_m": float(e.mean()), "mean_ci95_lo_m": est[j].ci_low, "mean_ci95_hi_m": est[j].ci_high,
                         "median_m": float(np.median(e)), "p75_m": float(np.percentile(e, 75))})
        ratios.append({"floor": ds, "ratio_toolkit_over_wknn": est[2].value, "ci95_lo": est[2].ci_low,
                       "ci95_hi": est[2].ci_high, "n_walks": len(groups)})
    readings = readings_table([
        reading("toolkit configuration", "", "no paper: the toolkit's own headline (issue 27)",
                "TOOLKIT_HEADLINE as notebook 02's spot x PHONEID CV chose it on UJIIndoorLoc training; only the "
                "radio map is fitted to these walks", "notebook 02, wifi.candidates.TOOLKIT_HEADLINE"),
        reading("plain reference", "", "silent",
                "KnnFingerprint K=5, Euclidean (p=2), 1/d weights, not heard = -100 dBm",
                "track.lowo.PLAIN_WKNN, the track pipeline's Wi-Fi reference"),
        reading("reading age", "", "silent", f"readings older than {MAX_AGE_S:g} s left out of a scan",
                "PLAIN_WKNN's max_age_s"),
        reading("folds", "", "silent",
                f"GroupKFold({N_FOLDS}) by walk, the same folds for both methods; walks resampled for the interval",
                "a choice of this diagnostic, fixed before any score"),
    ])
    return {"transfer": pd.DataFrame(rows), "transfer_ratio": pd.DataFrame(ratios), "readings": readings}


def findings(tables: dict) -> list[str]:
    """One sentence per floor, generated from ``transfer_ratio``."""
    out = []
    for r in tables["transfer_ratio"].itertuples():
        t = tables["transfer"].query("floor == @r.floor").set_index("method")["mean_m"]
        verdict = ("lower" if r.ci95_hi < 1 else "higher" if r.ci95_lo > 1 else "not distinguishable")
        out.append(f"{r.floor} ({r.n_walks} walks): toolkit {t[METHODS[1]]:.2f} m against WKNN {t[METHODS[0]]:.2f} m, "
                   f"ratio {r.ratio_toolkit_over_wknn:.2f} [{r.ci95_lo:.2f}, {r.ci95_hi:.2f}] (walks resampled): "
                   f"the toolkit's error is {verdict}")
    return out
