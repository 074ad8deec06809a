"""Tests of ilocalg.measure (measurement functions on synthetic data with known parameters) and of
the accessor ilocalg.sim.measured."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ilocalg.measure import scans
from ilocalg.measure.stats import bootstrap
from ilocalg.sim import measured


def _walk_scans(rng, n_scans=60, n_aps=12, interval_s=2.0, age_s=1.0, relist_p=0.5):
    """Synthetic scans with known interval and fresh-reading age; some readings re-listed (last_seen +1 ms)."""
    rows = []
    last = {}
    for k in range(n_scans):
        t = 100.0 + k * interval_s
        for j in range(n_aps):
            if j in last and rng.random() < relist_p:
                rssi, ls = last[j]
                ls = ls + 0.001 * rng.choice([-1, 1])
            else:
                rssi, ls = float(rng.integers(-90, -40)), t - age_s
            last[j] = (rssi, ls)
            rows.append((t, k, f"ap{j}", rssi, ls))
    return pd.DataFrame(rows, columns=["t_s", "scan_id", "bssid", "rssi_dbm", "last_seen_s"])


def test_scan_interval_and_distinct_age_recover_known_values():
    w = _walk_scans(np.random.default_rng(1))
    assert np.allclose(scans.scan_intervals_s(w), 2.0)
    ages = scans.reading_ages_s(w)
    assert np.allclose(ages, 1.0)  # re-listings removed: every distinct reading is 1 s old at first listing
    listed = scans.reading_ages_s(w, distinct=False)
    assert listed.size > ages.size and np.median(listed) > 1.5  # re-listed rows look older


def test_distinct_keeps_a_new_reading_with_equal_rssi_when_last_seen_moves():
    w = pd.DataFrame({"t_s": [1.0, 3.0, 5.0], "scan_id": [0, 1, 2], "bssid": ["a", "a", "a"],
                      "rssi_dbm": [-60.0, -60.0, -60.0], "last_seen_s": [0.0, 0.001, 4.0]})
    kept = scans.distinct_readings(w)
    assert kept["t_s"].tolist() == [1.0, 5.0]


def test_scans_missing_column_is_named():
    with pytest.raises(ValueError, match="last_seen_s"):
        scans.reading_ages_s(pd.DataFrame({"t_s": [1.0], "bssid": ["a"], "rssi_dbm": [-50.0]}))


def test_bootstrap_is_seeded_and_covers_the_mean():
    x = np.random.default_rng(3).normal(5.0, 1.0, 400)
    a = bootstrap(x, np.mean, rng=7)
    b = bootstrap(x, np.mean, rng=7)
    assert a == b
    assert a.ci_low < 5.0 < a.ci_high and a.ci_high - a.ci_low < 0.4
    with pytest.raises(ValueError, match="n_boot"):
        bootstrap(x, np.mean, n_boot=10)


def test_cluster_bootstrap_is_wider_than_iid_for_correlated_clusters():
    r = np.random.default_rng(4)
    groups = [np.full(50, r.normal()) + r.normal(0, 0.1, 50) for _ in range(20)]
    wide = bootstrap(groups, np.mean, rng=1)
    narrow = bootstrap(np.concatenate(groups), np.mean, rng=1)
    assert (wide.ci_high - wide.ci_low) > 3 * (narrow.ci_high - narrow.ci_low)


def test_accessor_reads_the_committed_table():
    r = measured.row("wifi_scan_interval_s")
    assert r["unit"] == "s" and r["ci_low"] <= r["value"] <= r["ci_high"]
    assert measured.param("wifi_scan_interval_s") == r["value"]
    assert "wifi_scan_interval_s" in measured.cite("wifi_scan_interval_s")


def test_accessor_unknown_parameter_is_named():
    with pytest.raises(ValueError, match="no_such_parameter"):
        measured.param("no_such_parameter")


def test_accessor_rejects_a_table_with_duplicates(tmp_path):
    p = tmp_path / "m.csv"
    p.write_text("parameter,value,ci_low,ci_high,unit,dataset,method\na,1,0,2,s,x,y\na,1,0,2,s,x,y\n")
    with pytest.raises(ValueError, match="line 3"):
        measured.table(p)
