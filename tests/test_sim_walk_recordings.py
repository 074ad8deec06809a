"""ilocalg.sim.walk_recordings: seeded walks with IMU, Wi-Fi, barometer and ground truth."""

import numpy as np
import pytest

from ilocalg.sim import walk_recordings as wr


@pytest.fixture(scope="module")
def sim():
    return wr.simulate_recordings(4, seed=4, n_floors=2, n_nodes=30, floor_changes=True)


def test_same_seed_same_bytes(sim):
    _, again = wr.simulate_recordings(4, seed=4, n_floors=2, n_nodes=30, floor_changes=True)
    for a, b in zip(sim[1], again, strict=True):
        assert a.content_id == b.content_id and a.truth.equals(b.truth) and a.pressure.equals(b.pressure)


def test_walks_are_physical(sim):
    b, walks = sim
    for w in walks:
        assert w.frame == b.frame and w.has_floors
        r = w.wifi["rssi_dbm"].to_numpy()
        assert (r >= -95).all() and (r <= -20).all() and (r == np.round(r)).all()
        per_scan = w.wifi.groupby("scan_id").size()
        assert 3 <= per_scan.median() <= 30
        dt = np.diff(w.wifi.groupby("scan_id")["t_s"].first().to_numpy())
        assert (dt >= 1.9).all() and (dt <= 4.1).all()
        # ground truth points are corridor nodes, latitude/longitude agree with the frame
        d = np.hypot(*(w.truth[["x_m", "y_m"]].to_numpy()[:, None, :] - b.nodes_xy_m[None]).transpose(2, 0, 1))
        assert d.min(axis=1).max() < 1e-9
        np.testing.assert_allclose(w.frame.to_xy(w.truth["lat_deg"], w.truth["lon_deg"]),
                                   w.truth[["x_m", "y_m"]].to_numpy(), atol=1e-6)


def test_climbing_walk_changes_pressure_by_one_storey(sim):
    _, walks = sim
    climb = [w for w in walks if w.meta["floor_to"] is not None]
    assert climb
    for w in climb:
        p = w.pressure["pressure_hpa"].to_numpy()
        dp = np.mean(p[-25:]) - np.mean(p[:25])        # last and first 5 s
        # ICAO standard atmosphere near sea level: about -0.12 hPa per metre, 3.5 m storey
        assert dp * np.sign(w.meta["floor"] - w.meta["floor_to"]) == pytest.approx(0.42, abs=0.08)
        assert set(w.truth["floor"]) == {w.meta["floor"], w.meta["floor_to"]}
    # the near floor is heard better than the far one: more APs of the walk's own floor
    w0 = next(w for w in walks if w.meta["floor_to"] is None)
    own = w0.wifi["bssid"].isin([sim[0].bssids[i] for i in np.flatnonzero(sim[0].ap_floor == w0.meta["floor"])])
    assert own.mean() > 0.5


def test_bad_parameters():
    with pytest.raises(ValueError, match="unknown simulator parameters"):
        wr.simulate_building(0, storey=3.0)
    with pytest.raises(ValueError, match="floors must be in"):
        wr.simulate_recording(wr.simulate_building(0), 0, floor=2)
