"""Experiment fusion_real_walks on the real ILC 2.0 site2/F4 walks (notebook 09)."""

import numpy as np
import pytest

from ilocalg.experiments import fusion_real_walks as frw
from ilocalg.track import METHODS, RealWalkConfig

SHORT = ["5dd5205dd48f840006f149d3", "5dd5260750e04e0006f564f1"]


@pytest.fixture(scope="module")
def floor():
    from ilocalg.io.paths import dataset_path

    p = dataset_path(frw.DATASET)
    if not p.is_dir():
        pytest.skip(f"{p} not found")
    return frw.load_floor(p)


@pytest.mark.realdata
def test_run_on_two_walks(shared_data, floor):
    shared_data(frw.DATASET)
    cfg = RealWalkConfig(n_particles=200, grid_cell_m=1.0)
    t = frw.run(seed=0, floor=floor, cfg=cfg, names=SHORT, select=False)
    wp = t["waypoints"]
    assert set(wp["walk"]) == set(SHORT)
    assert len(wp) == sum(len(floor.traces[n].waypoints) for n in SHORT)
    assert np.isfinite(wp[list(METHODS)].to_numpy()).all()
    s = t["summary"].set_index("method")
    assert s.loc["wifi", "ratio_to_wifi"] == 1.0
    assert (s["mean_error_m"] < 60).all()
    # what was learned came from the other walks: a sane step factor and a small floor offset
    pw = t["per_walk"]
    assert (pw["k_weinberg"].between(0.3, 0.7)).all() and (pw["floor_offset_deg"].abs() < 20).all()
    t2 = frw.run(seed=0, floor=floor, cfg=cfg, names=SHORT, select=False)
    assert t2["waypoints"].equals(wp)
    assert "Wi-Fi only" in frw.findings(t)
