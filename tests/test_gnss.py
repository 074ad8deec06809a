"""Tests of ilocalg.gnss (PSO thesis eq. 3.1-3.3, haversine)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg import gnss

LAX = (33 + 57 / 60, -(118 + 24 / 60))
JFK = (40 + 38 / 60, -(73 + 47 / 60))


def test_haversine_known_points():
    # Williams' Aviation Formulary worked example: LAX-JFK d = 0.623585 rad (about 2144 nm)
    d = gnss.haversine_m(*LAX, *JFK, radius_m=1.0)
    assert d == pytest.approx(0.623585, abs=2e-6)
    # one degree of latitude on the mean sphere
    assert gnss.haversine_m(0, 0, 1, 0) == pytest.approx(np.pi / 180 * gnss.EARTH_RADIUS_M)


def test_destination_formulary_example():
    # Formulary: from LAX, 100 nm on the true course 66 deg -> 34d37'N, 116d33'W
    d_m = 100 / (180 * 60 / np.pi)
    lat, lon = gnss.destination(*LAX, 66.0, d_m, radius_m=1.0)
    assert lat == pytest.approx(34 + 37 / 60, abs=1 / 60)
    assert lon == pytest.approx(-(116 + 33 / 60), abs=1 / 60)


@pytest.mark.parametrize("bearing", [0.0, 45.0, 90.0, 180.0, 271.0])
def test_dead_reckoning_matches_haversine(bearing):
    lat, lon = gnss.destination(24.18, 120.60, bearing, 250.0)
    assert gnss.haversine_m(24.18, 120.60, lat, lon) == pytest.approx(250.0, abs=1e-6)
    # east-positive longitudes: heading east increases longitude
    if bearing == 90.0:
        assert lon > 120.60 and lat == pytest.approx(24.18, abs=1e-5)


def test_dead_reckon_closed_square_returns_home():
    b = np.repeat([0.0, 90.0, 180.0, 270.0], 50)
    lat, lon = gnss.dead_reckon_latlon(24.18, 120.60, b, np.full(b.size, 0.8))
    assert lat.shape == (201,)
    assert gnss.haversine_m(lat[0], lon[0], lat[-1], lon[-1]) < 1e-3
    assert gnss.path_length_m(lat, lon) == pytest.approx(160.0, rel=1e-9)


def test_dead_reckon_matches_chained_destination():
    rng = np.random.default_rng(0)
    b, d = rng.uniform(0, 360, 50), rng.uniform(0.5, 1.0, 50)
    lat, lon = gnss.dead_reckon_latlon(24.18, 120.60, b, d)
    la, lo = 24.18, 120.60
    for i in range(50):
        la, lo = gnss.destination(la, lo, b[i], d[i])
        assert (lat[i + 1], lon[i + 1]) == (pytest.approx(la, abs=1e-12), pytest.approx(lo, abs=1e-12))


def test_dateline_wrap():
    lat, lon = gnss.destination(0.0, 179.9999, 90.0, 100.0)
    assert -180 <= lon < -179.99


def test_local_roundtrip():
    x, y = gnss.latlon_to_local_m(24.181, 120.601, 24.18, 120.60)
    lat, lon = gnss.local_to_latlon(x, y, 24.18, 120.60)
    assert (lat, lon) == (pytest.approx(24.181), pytest.approx(120.601))
    assert np.hypot(x, y) == pytest.approx(gnss.haversine_m(24.18, 120.60, 24.181, 120.601), rel=1e-3)


def test_gps_track_length_and_gaps():
    t = np.arange(5.0)
    lat, lon = gnss.dead_reckon_latlon(24.18, 120.60, np.zeros(4), np.full(4, 1.0))
    fixes = pd.DataFrame({"t_s": t, "lat_deg": lat, "lon_deg": lon})
    assert gnss.gps_track_length_m(fixes) == pytest.approx(4.0)
    with pytest.raises(ValueError, match="GPS gap"):
        gnss.gps_track_length_m(fixes.assign(t_s=[0, 1, 2, 10, 11.0]))
    with pytest.raises(ValueError, match="not finite"):
        gnss.gps_track_length_m(fixes.assign(lat_deg=[24.18, np.nan, 24.18, 24.18, 24.18]))
    with pytest.raises(ValueError, match="lon_deg"):
        gnss.gps_track_length_m(fixes.drop(columns="lon_deg"))
    with pytest.raises(ValueError, match="within"):
        gnss.haversine_m(91, 0, 0, 0)
    with pytest.raises(ValueError, match="dist_m"):
        gnss.destination(0, 0, 0, -1)
