"""Experiment fusion_real_walks on the real ILC 2.0 site2/F4 walks (notebook 09)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import fusion_real_walks as frw
from ilocalg.track import METHODS, RealWalkConfig
from ilocalg.track.lowo import lowo_findings, sweep_summary

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
    # scored at the waypoints only, the drawn walks' tracks are whole: every state of every method
    assert t["tracks"][["x_m", "y_m"]].notna().all().all()
    assert set(t["tracks"]["method"]) >= {"lsq_online", "lsq_online_map", "lsq_online_map_start5s"}
    from ilocalg.io.paths import dataset_path

    assert frw.load_floor(dataset_path(frw.DATASET)) is floor  # the same files are read once per process
    assert "Wi-Fi only" in frw.findings(t)


@pytest.mark.realdata
def test_shards_pool_to_the_unsharded_run(shared_data, floor):
    from ilocalg.papers.claims import tables_to_long

    shared_data(frw.DATASET)
    cfg = RealWalkConfig(n_particles=100, grid_cell_m=1.0)
    kw = dict(seed=0, floor=floor, cfg=cfg, names=SHORT, select=False, methods=("wifi", "kf", "lsq", "lsq_online"))
    whole = frw.run(**kw)
    parts = [frw.run(shard=i, n_shards=2, **kw) for i in range(2)]
    assert [set(p["waypoints"]["walk"]) for p in parts] == [{SHORT[0]}, {SHORT[1]}]
    long = tables_to_long({"sweep_waypoints": pd.concat([p["sweep_waypoints"] for p in parts])})
    s = sweep_summary(long)["summary"].set_index(["floor", "method"])
    for m in ("wifi", "kf", "lsq", "lsq_online", "wifi_plain_knn"):
        np.testing.assert_allclose(s.loc[("pooled", m), "mean_m"], whole["waypoints"][m].mean())
        np.testing.assert_allclose(s.loc[("pooled", m), "p75_m"], whole["waypoints"][m].quantile(0.75))
    assert s.loc[("pooled", "wifi"), "ratio_to_wifi"] == 1.0
    assert s.loc[(frw.DATASET, "kf"), "n_walks"] == 2
    assert "best offline: lsq" in lowo_findings(s.reset_index())
    with pytest.raises(ValueError, match="shard"):
        frw.run(shard=2, n_shards=2, **kw)
    with pytest.raises(ValueError, match="shard 2 of 3 scores no walk"):  # two walks cannot fill three shards
        frw.run(shard=2, n_shards=3, **kw)
    with pytest.raises(ValueError, match="sweep_waypoints"):
        sweep_summary(tables_to_long({"measures": whole["measures"]}))
    assert frw.sweep_summary is sweep_summary                      # the sweep command finds it on the experiment


@pytest.mark.realdata
def test_fix_ablation_in_one_pass_gives_one_run_per_configuration(shared_data, floor):
    """The ablation scores its fix-model configurations in one pass over the walks (each walk's model, steps,
    nested Wi-Fi choice and plain fixes once): the same tables, bit for bit, as one run per configuration."""
    import dataclasses

    shared_data(frw.DATASET)
    base = RealWalkConfig(n_particles=100, grid_cell_m=1.0)
    methods = ("wifi", "lsq", "lsq_online", "kf_gain")
    configs = dict(list(frw.FIX_ABLATION.items())[::3])          # isotropic + independent, and everything on
    abl = frw.fix_ablation(configs, methods=methods, cfg=base, floor=floor, names=SHORT, select=True)
    for label, kw in configs.items():
        t = frw.run(cfg=dataclasses.replace(base, **kw), methods=methods, floor=floor, names=SHORT, select=True)
        got = abl["waypoints"][abl["waypoints"]["config"] == label].drop(columns="config").reset_index(drop=True)
        pd.testing.assert_frame_equal(got, t["waypoints"], check_exact=True)
    a, b = (abl["table"][abl["table"]["config"] == c].set_index("method")["mean_m"] for c in configs)
    assert (a != b).any()                                        # the configurations do differ
    with pytest.raises(ValueError, match="changes more than the fix model"):
        frw._run({"other K": {"k_neighbors": 7}}, floor=floor, names=SHORT)


def test_leave_one_walk_out_refuses_a_pooled_summary_with_failed_tasks(monkeypatch):
    """A failed task would leave its walks out of the pooled summary: leave_one_walk_out raises instead."""
    from ilocalg.workflow import sweep as sw

    seen = {}

    def fake_sweep(tasks, **kw):
        seen["shards"] = sorted({dict(t.params)["n_shards"] for t in tasks})
        return sw.SweepResult(pd.DataFrame({"x": [1.0]}), failures=[{"task": tasks[1].describe(), "error": "boom"}],
                              n_tasks=len(tasks))

    monkeypatch.setattr(sw, "sweep", fake_sweep)
    with pytest.raises(ValueError, match="1 of 2 tasks failed; first: .*boom"):
        frw.leave_one_walk_out(workers=0, progress=False)
    assert seen["shards"] == [1]  # in this process: one task per floor
    with pytest.raises(ValueError, match="tasks failed"):
        frw.leave_one_walk_out(workers=2, progress=False)
    assert seen["shards"] == [4]


def test_ablation_findings_never_count_a_declared_latency_as_offline():
    t = pd.DataFrame([{"config": "default", "method": m, "online": on, "ratio_to_wifi": r, "start_mean_m": 3.0}
                      for m, on, r in (("wifi", True, 1.0), ("kf_gain", True, 0.8), ("lsq_map", False, 0.6),
                                       ("kf_gain_lag5s", False, 0.5))])
    text = frw.ablation_findings(t)
    assert "best online kf_gain 0.800" in text and "best offline lsq_map 0.600" in text
    assert "kf_gain_lag5s" not in text


@pytest.mark.realdata
def test_a_saved_floor_model_lets_run_read_only_the_scored_walks(shared_data, floor, tmp_path, monkeypatch):
    """With the floor model saved (every walk's name and walked-path graph in it), run reads only the walks it
    scores, and its tables are the same, bit for bit, as the run that read the whole floor and built the model."""
    from ilocalg.io.paths import dataset_path
    from ilocalg.track import floor as floor_mod

    shared_data(frw.DATASET)
    kw = dict(seed=0, data_dir=dataset_path(frw.DATASET), cfg=RealWalkConfig(n_particles=100, grid_cell_m=1.0),
              names=SHORT, select=False, methods=("wifi", "lsq", "lsq_online", "lsq_paths"), cache_dir=tmp_path)
    first = frw.run(**kw)                       # the whole floor (read by the fixture); the model built and saved
    frw._FLOORS.clear()
    floor_mod._LAST_MODEL.clear()
    read = []
    from ilocalg.track import lowo

    real = lowo.load_ilc_floor                  # the reader load_floor (ilocalg.track.lowo) calls
    monkeypatch.setattr(lowo, "load_ilc_floor", lambda *a, **k: read.append(k.get("names")) or real(*a, **k))
    again = frw.run(**kw)
    assert read == [tuple(sorted(SHORT))]
    for k in ("waypoints", "per_walk", "summary", "tracks", "truth", "sweep_waypoints"):
        pd.testing.assert_frame_equal(again[k], first[k], check_exact=True)
    frw._FLOORS.clear()
    floor_mod._LAST_MODEL.clear()
