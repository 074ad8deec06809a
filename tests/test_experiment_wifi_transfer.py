"""The UJIIndoorLoc headline on the ILC 2.0 walks (ilocalg.experiments.wifi_transfer)."""

import numpy as np
import pytest

from ilocalg.experiments import wifi_transfer


def _walks(rng, n_walks, n_per_walk, aps):
    """Walks across a 30 m x 10 m corridor, log-distance RSSI with 3 dB noise, one row per scan."""
    xy, walk = [], []
    for w in range(n_walks):
        t = np.linspace(0, 1, n_per_walk)
        y0 = rng.uniform(1, 9)
        xy.append(np.column_stack([30 * t if w % 2 else 30 * (1 - t), np.full(t.size, y0)]))
        walk.append(np.full(t.size, w))
    xy = np.vstack(xy)
    d = np.linalg.norm(xy[:, None] - aps[None], axis=2)
    x = -35 - 25 * np.log10(d + 1) + rng.normal(0, 3, d.shape)
    x[x < -95] = np.nan                                                # out of range: not heard
    return x, xy, np.concatenate(walk)


def test_cross_validation_holds_whole_walks_out_and_locates_every_scan():
    rng = np.random.default_rng(0)
    aps = np.array([[0, 0], [10, 10], [20, 0], [30, 10], [15, 5]], dtype=float)
    x, xy, walk = _walks(rng, 10, 40, aps)
    err = wifi_transfer.cross_validate(x, xy, walk)
    assert err.shape == (400, 2) and np.isfinite(err).all()
    assert np.median(err, axis=0).max() < 5.0                          # 30 m corridor, 5 APs, 3 dB noise
    # a walk's own scans are never its references: with every other walk moved 100 m away, every error is large
    far = xy.copy()
    far[walk != 0] += 100.0
    err0 = wifi_transfer.cross_validate(x, far, walk)
    assert (err0[walk == 0] > 50).all()


@pytest.mark.realdata
def test_fast_run_on_site2(shared_data):
    d = shared_data("ilc2020_site2_F4")
    t = wifi_transfer.run(seed=0, fast=True, data_dir=d.parent)
    tr = t["transfer"]
    assert list(tr["method"]) == list(wifi_transfer.METHODS) and (tr["floor"] == "ilc2020_site2_F4").all()
    assert tr["n_scans"].nunique() == 1 and tr["n_walks"].iloc[0] == 19
    assert ((tr["mean_ci95_lo_m"] <= tr["mean_m"]) & (tr["mean_m"] <= tr["mean_ci95_hi_m"])).all()
    r = t["transfer_ratio"].iloc[0]
    assert r["ratio_toolkit_over_wknn"] == pytest.approx(tr["mean_m"].iloc[1] / tr["mean_m"].iloc[0])
    assert r["ci95_hi"] < 1.0                       # the headline beats plain WKNN on the site 2 floor
    assert list(t["readings"].columns[:5]) == ["choice", "paper_line", "text_says", "code_does", "source"]
    assert "lower" in wifi_transfer.findings(t)[0]
    assert wifi_transfer.run(data_dir=d.parent / "nowhere") is None
