"""ilocalg.pdr.sam_evaluate: SAM leave one recording out, on seeded simulated recordings."""

from types import SimpleNamespace

import numpy as np

from ilocalg.pdr.sam_evaluate import sam_leave_one_out
from ilocalg.sim import gait


def test_leave_one_out_counts_each_recording_with_the_others_ranges():
    rng = np.random.default_rng(11)
    recs = []
    for i, w in enumerate(gait.make_walkers(4, rng)):
        sw = gait.simulate_walk(gait.straight_route(25.0), w, rng)
        recs.append(SimpleNamespace(name=f"rec{i}", imu=sw.imu, step_t_s=sw.steps["t_mid_s"].to_numpy(),
                                    true_steps=len(sw.steps)))
    t = sam_leave_one_out(recs, (0.0, 1.0), describe=lambda n: {"walker": n[-1]})
    assert list(t["recording"]) == [r.name for r in recs] and list(t["walker"]) == ["0", "1", "2", "3"]
    assert (t["true_steps"] == [r.true_steps for r in recs]).all()
    assert np.allclose(t["error"], (t["counted"] - t["true_steps"]).abs() / t["true_steps"])
    assert t["waves_matched"].between(0, 1).all() and t["steps_passing"].between(0, 1).all()
    assert set(t["worst_test"]) <= {"A2", "A", "T1", "T2", "T", "X1", "I"}
    assert all(f"fail {w}" in why for w, why in zip(t["worst_test"], t["why"], strict=True))
