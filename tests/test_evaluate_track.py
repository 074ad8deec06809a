"""The ``evaluate track`` command (JSON contract, leave-one-walk-out, trace files and ids)."""

import argparse
import json
import subprocess
import sys
import tarfile

import numpy as np
import pytest

from ilocalg.workflow.commands import evaluate_track as cmd

TRACE = "5dd5205dd48f840006f149d3"
DB = ["5dd5260750e04e0006f564f1", "5dd52058d48f840006f149d1", "5dd525f4d48f840006f14a47", "5dd3bbd144333f00067aa802"]


def _args(**kw):
    p = argparse.ArgumentParser()
    cmd.add_arguments(p)
    argv = []
    for k, v in kw.items():
        flag = "--" + k.replace("_", "-")
        if v is True:
            argv.append(flag)
        elif isinstance(v, list):
            argv += [flag, *v]
        else:
            argv += [flag, str(v)]
    return p.parse_args(argv)


@pytest.mark.realdata
def test_json_contract_on_trace_ids(shared_data):
    floor = shared_data("ilc2020_site2_F4")
    out = cmd.run(_args(trace=TRACE, fingerprints=DB, floor=floor, particles=100))
    n = out["n_waypoints"]
    assert out["trace"] == TRACE and n == 6
    for k in ("pdr", "wifi", "kf", "kf_rts", "pf", "map_align"):
        assert len(out["errors_m"][k]) == n
        assert out["mean_m"][k] == pytest.approx(np.mean(out["errors_m"][k]))
        assert all(np.isfinite(out["errors_m"][k]))
    json.dumps(out)                                  # plain JSON types


@pytest.mark.realdata
def test_trace_files_and_no_map(shared_data, tmp_path):
    floor = shared_data("ilc2020_site2_F4")
    archive = next(floor.glob("*.tar.xz"))
    files = {}
    with tarfile.open(archive) as tf:
        for m in tf:
            stem = m.name.rsplit("/", 1)[-1].removesuffix(".txt")
            if m.isfile() and stem in [TRACE, *DB[:2]]:
                files[stem] = tmp_path / f"{stem}.txt"
                files[stem].write_bytes(tf.extractfile(m).read())
    out = cmd.run(_args(trace=str(files[TRACE]), fingerprints=[str(files[d]) for d in DB[:2]], no_map=True,
                        floor=tmp_path / "nowhere"))
    assert set(out["errors_m"]) == {"pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts"}
    assert out["n_fingerprint_walks"] == 2


@pytest.mark.realdata
def test_scored_trace_in_fingerprints_is_refused(shared_data):
    floor = shared_data("ilc2020_site2_F4")
    with pytest.raises(ValueError, match="must not contain the scored trace"):
        cmd.run(_args(trace=TRACE, fingerprints=[TRACE, DB[0]], floor=floor))
    with pytest.raises(ValueError, match="neither a file nor a trace id"):
        cmd.run(_args(trace="nosuchtrace", fingerprints=DB[:1], floor=floor))


def test_cli_error_exit_for_missing_trace(tmp_path):
    r = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "track", "--trace", str(tmp_path / "x.txt"),
                        "--fingerprints", "y", "--floor", str(tmp_path / "nowhere"), "--json"],
                       capture_output=True, text=True)
    assert r.returncode != 0
    assert "neither" in r.stderr
