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
    assert set(out["errors_m"]) == {"pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts", "lsq",
                                    "lsq_online", "kf_gain", "kf_gain_lag5s", "lsq_paths", "lsq_grid"}
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


@pytest.fixture(scope="module")
def ipin_files(tmp_path_factory):
    """Simulated walks on two floors (some climbing), written as IPIN logfiles."""
    from ilocalg.io import write_ipin_logfile
    from ilocalg.sim import walk_recordings as wr

    d = tmp_path_factory.mktemp("ipin")
    _, walks = wr.simulate_recordings(8, seed=21, n_floors=2, n_nodes=30, floor_changes=True)
    return [write_ipin_logfile(w, d / f"{w.name}.txt") for w in walks]


def test_ipin_logfile_scored_against_other_logfiles(ipin_files):
    trace, db = ipin_files[1], ipin_files[2:]
    out = cmd.run(_args(trace=str(trace), fingerprints=[str(p) for p in db], particles=100))
    n = out["n_waypoints"]
    assert out["trace"] == "sim001" and out["n_fingerprint_walks"] == len(db)
    # no floor map for geographic walks: the map-constrained methods are left out, as for ILC with --no-map
    assert set(out["errors_m"]) == {"pdr", "wifi", "kf", "kf_rts", "aligned", "aligned_rot", "aligned_kf_rts", "lsq",
                                    "lsq_online", "kf_gain", "kf_gain_lag5s", "lsq_paths", "lsq_grid"}
    for k, e in out["errors_m"].items():
        assert len(e) == n and all(np.isfinite(e)) and out["mean_m"][k] == pytest.approx(np.mean(e))
    assert out["mean_m"]["kf_rts"] < 10 and out["mean_m"]["wifi"] < 10
    assert set(out["floor_hit_rate"]) == set(out["errors_m"]) and out["floor_hit_rate"]["kf_rts"] >= 0.8
    assert out["info"]["floor_source"] == "wifi+barometer" and out["info"]["n_scans_outside_walk"] == 0
    json.dumps(out)
    same = cmd.run(_args(trace=str(trace), fingerprints=[str(p) for p in db], particles=100, format="ipin"))
    assert same["errors_m"] == out["errors_m"]                         # the format from the content, or given


def test_ipin_scored_walk_under_another_name_is_refused(ipin_files, tmp_path):
    copy = tmp_path / "renamed_walk.txt"
    copy.write_bytes(ipin_files[1].read_bytes())
    with pytest.raises(ValueError, match="renamed_walk.txt: same sensor content"):
        cmd.run(_args(trace=str(ipin_files[1]), fingerprints=[str(copy), *map(str, ipin_files[2:5])], particles=100))
    with pytest.raises(ValueError, match="pass --no-map"):
        cmd.run(_args(trace=str(ipin_files[1]), fingerprints=[str(p) for p in ipin_files[2:5]], map=str(tmp_path)))


def test_ipin_from_the_command_line(ipin_files):
    p = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "track", "--trace", str(ipin_files[0]),
                        "--fingerprints", *map(str, ipin_files[1:5]), "--format", "ipin", "--particles", "50",
                        "--json"], capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["trace"] == "sim000" and "floor_hit_rate" in out
    bad = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "track", "--trace", str(ipin_files[0]),
                          "--fingerprints", str(ipin_files[1]), "--format", "ilc", "--json"],
                         capture_output=True, text=True, timeout=600)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and "sim000.txt" in bad.stderr


def test_table_by_default_out_track_and_help(ipin_files, tmp_path):
    csv = tmp_path / "track.csv"
    p = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "track", "--trace", str(ipin_files[0]),
                        "--fingerprints", *map(str, ipin_files[1:5]), "--particles", "50", "--quiet",
                        "--out-track", str(csv)], capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].startswith("walk sim000") and lines[1].split()[:4] == ["method", "mean", "m", "median"]
    rows = {ln.split()[0]: float(ln.split()[1]) for ln in lines[2:] if ln.split() and ln.split()[0] in cmd.METHOD_HELP}
    assert {"wifi", "kf_rts", "lsq", "lsq_online"} <= set(rows)
    import pandas as pd

    t = pd.read_csv(csv)
    assert {"t_s", "method", "x_m", "y_m", "floor"} <= set(t.columns) and "lsq" in set(t["method"])
    h = subprocess.run([sys.executable, "-m", "ilocalg", "evaluate", "track", "--help"], capture_output=True, text=True)
    assert "lsq_online" in h.stdout and "examples" in h.stdout


def test_two_floor_archive_names_the_floors(tmp_path):
    import io

    arch = tmp_path / "site_F1_F2.tar.xz"
    with tarfile.open(arch, "w:xz") as tf:
        for fl in ("site_F1", "site_F2"):
            for name, data in (("floor_info.json", b"{}"), ("geojson_map.json", b"{}")):
                ti = tarfile.TarInfo(f"{fl}/{name}")
                ti.size = len(data)
                tf.addfile(ti, io.BytesIO(data))
    from ilocalg.io.ilc import load_ilc_floor_map

    with pytest.raises(ValueError, match=r"found 2 floors \(site_F1, site_F2\); pick one with floor_name='site_F1'"):
        load_ilc_floor_map(arch)


def test_every_method_is_explained():
    """The table's last column and --help name every method the track package runs (a new estimator
    without a line of help would print an empty cell)."""
    from ilocalg.track._config import METHODS

    assert set(METHODS) <= set(cmd.METHOD_HELP), sorted(set(METHODS) - set(cmd.METHOD_HELP))
    assert all(cmd.METHOD_HELP[m].split(":")[0].startswith(("online", "offline")) for m in METHODS)
