"""Simulated walks shared by the track-filter tests (tests/test_track_online.py, tests/test_track_error_sources.py) and
the small real site1 floor of the real-data track tests."""

import numpy as np


def gained_walk(rng, n: int, scale: float, bias_rad: float):
    """A winding walk of ``n`` 0.7 m steps (heading a random walk, 0.08 rad per step, drawn first from ``rng``)
    whose PDR steps are off by the walk's own gain ``g = scale exp(i bias_rad)``.

    Returns ``(truth (n+1, 2), g, pdr (n,) complex)``: the true positions from the origin, the gain, and the
    steps the PDR reports (true step / g)."""
    th = np.cumsum(rng.normal(0, 0.08, n))
    true_d = 0.7 * np.column_stack([np.cos(th), np.sin(th)])
    truth = np.vstack([[0.0, 0.0], np.cumsum(true_d, 0)])
    g = scale * np.exp(1j * bias_rad)
    return truth, g, (true_d[:, 0] + 1j * true_d[:, 1]) / g


#: The site1 F1 walk the real-data track tests score (an even index in the sorted walk list: a development walk).
SITE1_WALK = "5dd9efa7c5b77e0006b17367"


def site1_floor(root):
    """Every 4th site1 F1 walk of ``root`` (the shared ``ilc2020_site1``) besides :data:`SITE1_WALK`, and that walk:
    the small real floor of the track tests (:class:`ilocalg.io.ilc.IlcFloor`, relisted readings kept)."""
    from ilocalg.io.ilc import list_ilc_traces, load_ilc_floor

    names = [n for n in list_ilc_traces(root, floor_name="site1_F1") if n != SITE1_WALK][::4] + [SITE1_WALK]
    return load_ilc_floor(root, names=names, duplicate_bssid="keep_latest", relisted_wifi="keep",
                          floor_name="site1_F1")
