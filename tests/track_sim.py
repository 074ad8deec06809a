"""A simulated walk shared by the track-filter tests (tests/test_track_online.py, tests/test_track_error_sources.py)."""

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
