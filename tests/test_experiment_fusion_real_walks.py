"""Experiment fusion_real_walks on the real ILC 2.0 site2/F4 walks (notebook 09)."""

import numpy as np
import pytest

from ilocalg.experiments import fusion_real_walks as frw

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
    cfg = frw.RealWalkConfig(n_particles=200, grid_cell_m=1.0)
    t = frw.run(seed=0, floor=floor, cfg=cfg, names=SHORT, select=False)
    wp = t["waypoints"]
    assert set(wp["walk"]) == set(SHORT)
    assert len(wp) == sum(len(floor.traces[n].waypoints) for n in SHORT)
    assert np.isfinite(wp[list(frw.METHODS)].to_numpy()).all()
    s = t["summary"].set_index("method")
    assert s.loc["wifi", "ratio_to_wifi"] == 1.0
    assert (s["mean_error_m"] < 60).all()
    # what was learned came from the other walks: a sane step factor and a small floor offset
    pw = t["per_walk"]
    assert (pw["k_weinberg"].between(0.3, 0.7)).all() and (pw["floor_offset_deg"].abs() < 20).all()
    t2 = frw.run(seed=0, floor=floor, cfg=cfg, names=SHORT, select=False)
    assert t2["waypoints"].equals(wp)
    assert "Wi-Fi only" in frw.findings(t)


@pytest.mark.realdata
def test_leave_one_walk_out_is_enforced(shared_data, floor):
    shared_data(frw.DATASET)
    name = SHORT[0]
    db = frw.WifiDatabase.from_traces(floor.traces)
    with pytest.raises(ValueError, match="must not contain the scored walk"):
        frw.wifi_fixes(floor.traces[name], db)
    fx = frw.wifi_fixes(floor.traces[name], db.without(name))
    assert fx.xy_m.shape == (fx.t_s.size, 2) and np.all(np.diff(fx.t_s) > 0)
    with pytest.raises(ValueError, match="must not include the scored walk"):
        frw.evaluate_track(floor.traces[name], floor.traces)
    assert name not in set(db.without(name).walk)


@pytest.mark.realdata
def test_calibration_recovers_offset_of_rotated_walks(shared_data, floor):
    """The floor offset is learned from waypoints: rotating every walk's waypoints by 30 deg shifts it by 30."""
    shared_data(frw.DATASET)
    import dataclasses

    from ilocalg.fusion.heading_offset import rotate_xy

    names = floor.names[:6]
    steps = {n: frw.walk_steps(floor.traces[n]) for n in names}
    base = frw.calibrate({n: floor.traces[n] for n in names}, steps)
    rot = {}
    for n in names:
        tr = floor.traces[n]
        wp = tr.waypoints.copy()
        wp[["x_m", "y_m"]] = rotate_xy(wp[["x_m", "y_m"]].to_numpy(), np.deg2rad(30.0))
        rot[n] = dataclasses.replace(tr, waypoints=wp)
    r = frw.calibrate(rot, steps)
    assert np.rad2deg(r.offset_rad - base.offset_rad) == pytest.approx(30.0, abs=1e-6)
    assert r.k_weinberg == pytest.approx(base.k_weinberg)
