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


def _optimisation_folder(folder, feet, rate_hz=100.0, n=400, row_s=0.1):
    """A recording folder in the optimisation layout: a 1.6 Hz |a| wave and heel-sensor rows every ``row_s``."""
    folder.mkdir(parents=True)
    t_ns = (1_000_000_000 + np.arange(n) * 1e9 / rate_hz).astype(np.int64)
    z = 9.8 + 2.0 * np.sin(2 * np.pi * 1.6 * np.arange(n) / rate_hz)
    pd.DataFrame({"t": t_ns, "k": 3, "x": 0.0, "y": 0.0, "z": z}).to_csv(folder / "accelerometer.csv", header=False,
                                                                       index=False)
    rows = [(t_ns[0] + int((k + 1) * row_s * 1e9), left, right) for k, (left, right) in enumerate(feet)]
    pd.DataFrame(rows).to_csv(folder / "stepcounter.csv", header=False, index=False)


def test_cli_heel_bounces_policy(tmp_path, capsys):
    # the left foot lands, lifts for one reading and lands again 0.2 s after (a bounce, < MIN_STRIDE_S), then lands
    # 0.8 s after; the right foot lands once: 4 landings published, 3 steps with the bounce merged
    feet = [(0, 0), (1, 0), (0, 0), (1, 0), (0, 0), (0, 1), (0, 1), (0, 0), (0, 0), (1, 0)]
    d = tmp_path / "Pixel_Jamie_Hard_Armband_1"
    _optimisation_folder(d, feet)
    out = {}
    for policy in (None, "keep", "merge"):
        extra = [] if policy is None else ["--heel-bounces", policy]
        assert main(["evaluate", "steps", str(d), "--json", *extra]) == 0
        out[policy] = json.loads(capsys.readouterr().out)
    assert out[None] == out["keep"]                        # keep is the default
    keep, merge = out["keep"]["recordings"][0], out["merge"]["recordings"][0]
    assert out["keep"]["heel_bounces_policy"] == "keep" and out["merge"]["heel_bounces_policy"] == "merge"
    assert (keep["true_steps"], keep["heel_bounces"], keep["heel_bounces_merged"]) == (4, 1, 0)
    assert (merge["true_steps"], merge["heel_bounces"], merge["heel_bounces_merged"]) == (3, 1, 1)
    assert merge["detected_steps"] == keep["detected_steps"]   # the policy changes the truth, not the count
    assert merge["accuracy"] == pytest.approx(1 - abs(merge["detected_steps"] - 3) / 3)
    with pytest.raises(SystemExit) as exc:                 # argparse refuses an unknown policy, status 2
        main(["evaluate", "steps", str(d), "--heel-bounces", "drop"])
    assert exc.value.code == 2 and "--heel-bounces" in capsys.readouterr().err
