import json

import numpy as np
import pandas as pd
import pytest

from ilocalg.sim import gait
from ilocalg.workflow.cli import main


def _validation_csv(path, seed=0):
    """A simulated walk written in the validation layout (ns, acc xyz, app, true, hardware counts)."""
    w = gait.make_walkers(1, seed)[0]
    sw = gait.simulate_walk(gait.straight_route(40.0), w, seed, gait.GaitConfig(rate_hz=200.0))
    t = sw.imu.index.to_numpy()
    true = np.searchsorted(sw.steps["t_strike_s"].to_numpy(), t, side="right")
    acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
    df = pd.DataFrame({"t": (1e9 + t * 1e9).astype(np.int64), "x": acc[:, 0], "y": acc[:, 1], "z": acc[:, 2],
                       "app": 0, "true": true, "hw": true + 7})
    df.to_csv(path, header=False, index=False)
    return int(true[-1])


@pytest.mark.parametrize("method", ["robust", "find_peaks", "peak_window", "sign_change", "sam"])
def test_cli_json_contract(tmp_path, capsys, method):
    p = tmp_path / "walk.csv"
    n = _validation_csv(p)
    assert main(["evaluate", "steps", str(p), "--method", method, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["method"] == method
    rec = out["recordings"][0]
    assert {"path", "true_steps", "detected_steps", "accuracy"} <= set(rec)
    assert rec["true_steps"] == n and rec["hardware_steps"] == n
    assert rec["accuracy"] == pytest.approx(1 - abs(rec["detected_steps"] - n) / n)
    assert out["mean_accuracy"] == pytest.approx(rec["accuracy"])
    if method == "robust":
        assert rec["accuracy"] > 0.95


def test_cli_bad_input(tmp_path, capsys):
    p = tmp_path / "bad.csv"
    p.write_text("1,0,0,9.8,0,0,0\n0,0,0,9.8,0,1,0\n")
    assert main(["evaluate", "steps", str(p)]) == 2
    assert "line 2, column 1" in capsys.readouterr().err
    assert main(["evaluate", "steps", str(tmp_path / "none")]) == 2
