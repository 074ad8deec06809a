"""Experiment pdr_heading_trajectory: WDM and PTS on the shared route with new walkers (notebook 05)."""

import pandas as pd

from ilocalg.experiments import pdr_heading_trajectory
from ilocalg.sim import iloc_floor


def test_fast_run_walks_the_shared_route_and_is_deterministic():
    a = pdr_heading_trajectory.run(seed=0, fast=True)
    b = pdr_heading_trajectory.run(seed=0, fast=True)
    for k in ("heading_summary", "summary", "wdm_sensitivity", "readings"):
        pd.testing.assert_frame_equal(a[k], b[k])
    tp = a["test_points"]
    route = iloc_floor.route_xy_m()
    assert tp["point"].max() == len(route) - 1  # the 27 points after the start
    first = tp[(tp["point"] == 1)].iloc[0]
    assert (first["x_true_m"], first["y_true_m"]) == tuple(route[1])
    assert {"PTS: SAM + SLM + WDM", "PTS (SAM 1%-99%)"} <= set(a["summary"]["method"])
    assert len(a["wdm_sensitivity"]) == 5
