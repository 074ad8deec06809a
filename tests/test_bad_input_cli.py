"""Bad input through the command line: every case ends as one line ``error: FILE: line N: ...`` on
stderr with exit status 2 (never a traceback), or is accepted by an option whose count is in the JSON."""

from __future__ import annotations

import gzip
import json
import resource

import numpy as np
import pytest

from ilocalg.io.ujiindoorloc import META_COLUMNS, POSITION_COLUMNS, WAP_COLUMNS
from ilocalg.workflow.cli import main


def _err(capsys, argv) -> str:
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (code, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    return lines[0]


# ------------------------------------------------------------------------------------ evaluate wifi

def _uji(path, rows):
    head = ",".join(WAP_COLUMNS + POSITION_COLUMNS + META_COLUMNS)
    out = []
    for k, rssi in enumerate(rows):
        r = [100] * 520
        r[:len(rssi)] = rssi
        out.append(",".join(map(str, r)) + f",{-7600 + k},{4864800 + k},0,0,1,2,1,1,{1371713733 + k}")
    path.write_text(head + "\n" + "\n".join(out) + "\n")
    return str(path)


def test_wifi_rssi_out_of_range(tmp_path, capsys):
    train = _uji(tmp_path / "train.csv", [[-60, -70], [-65, 50], [-70, -60]] * 3)
    test = _uji(tmp_path / "test.csv", [[-60, -70]])
    line = _err(capsys, ["evaluate", "wifi", "--train", train, "--test", test])
    assert line == f"error: {train}: line 3, column WAP002: value 50 is outside [-110, 0] dBm"


def test_wifi_fewer_training_rows_than_k(tmp_path, capsys):
    train = _uji(tmp_path / "train.csv", [[-60, -70], [-65, -50], [-70, -60]])
    test = _uji(tmp_path / "test.csv", [[-60, -70]])
    line = _err(capsys, ["evaluate", "wifi", "--train", train, "--test", test, "--method", "knn"])
    assert line == (f"error: {train}: 3 training rows, fewer than the 5 neighbours --method knn averages; "
                    "pass --k 3 or less, or give more training rows")


def test_wifi_corrupt_gzip_and_missing_file(tmp_path, capsys):
    p = tmp_path / "train.csv.gz"
    p.write_bytes(gzip.compress(b"WAP001,WAP002\n" * 100)[:30])
    assert _err(capsys, ["evaluate", "wifi", "--train", str(p), "--test", str(p)]).startswith(
        f"error: {p}: corrupt or truncated gzip data")
    assert _err(capsys, ["evaluate", "wifi", "--train", str(tmp_path / "no.csv"), "--test", str(p)]) == \
        f"error: {tmp_path / 'no.csv'}: no such file"


# ----------------------------------------------------------------------------------- evaluate steps

def _validation(path, n=1200, rate_hz=200.0, dup_at=(), hw=True, gap_ns=0):
    t = 10**12 + (np.arange(n) * 1e9 / rate_hz).astype(np.int64)
    t[n // 2:] += gap_ns
    rows = []
    for i in range(n):
        a = 9.81 + 3.0 * np.sin(2 * np.pi * 1.8 * i / rate_hz)
        row = f"{t[i]},0.1,0.2,{a:.4f},{i // 110},{i // 110}" + (f",{500 + i // 110}" if hw else "")
        rows.append(row)
        if i in dup_at:
            rows.append(row)
    path.write_text("\n".join(rows) + "\n")
    return str(path)


def test_steps_duplicate_timestamps_error_names_the_option_and_drop_counts(tmp_path, capsys):
    p = _validation(tmp_path / "dup.csv", dup_at=(100, 700))
    line = _err(capsys, ["evaluate", "steps", p])
    assert line.startswith(f"error: {p}: line 102, column 1 (timestamp_ns): duplicate timestamp")
    assert line.endswith("pass --duplicate-timestamps drop to drop the later row of each repeated timestamp "
                         "(counted)")
    assert main(["evaluate", "steps", p, "--duplicate-timestamps", "drop"]) == 0
    rec = json.loads(capsys.readouterr().out)["recordings"][0]
    assert rec["duplicate_timestamps_dropped"] == 2 and rec["true_steps"] == 10 and rec["hardware_steps"] == 10


def test_steps_hardware_steps_null_without_a_counter(tmp_path, capsys):
    p = _validation(tmp_path / "six.csv", hw=False)
    assert main(["evaluate", "steps", p]) == 0
    rec = json.loads(capsys.readouterr().out)["recordings"][0]
    assert rec["hardware_steps"] is None and rec["duplicate_timestamps_dropped"] == 0


def test_steps_huge_time_gap_fails_fast_in_bounded_memory(tmp_path, capsys):
    p = _validation(tmp_path / "gap.csv", gap_ns=10**17)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    with open("/proc/self/status") as fh:
        vm = next(int(ln.split()[1]) * 1024 for ln in fh if ln.startswith("VmSize:"))
    limit = vm + 2 * 2**30  # 2 GiB more than now: a 74 GiB resampling would raise MemoryError
    resource.setrlimit(resource.RLIMIT_AS, (limit if hard == resource.RLIM_INFINITY else min(limit, hard), hard))
    try:
        line = _err(capsys, ["evaluate", "steps", p])
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
    assert line.startswith(f"error: {p}: line 601, column 1 (timestamp_ns, seconds after the first line): value ")
    assert line.endswith("is outside [0, 86400] s")


def test_steps_two_samples_and_fractional_truth(tmp_path, capsys):
    p = _validation(tmp_path / "two.csv", n=2)
    assert _err(capsys, ["evaluate", "steps", p]) == (
        f"error: {p}: the recording lasts 0.005 s (2 samples); step counting needs at least 2 s of walking")
    q = tmp_path / "frac.csv"
    q.write_text(open(_validation(tmp_path / "v.csv")).read().replace(",0,0,500\n", ",0,0.5,500\n", 1))
    assert _err(capsys, ["evaluate", "steps", str(q)]) == (
        f"error: {q}: line 1, column 6 (true_count): value 0.5 is not a whole number")


def test_steps_corrupt_archive(tmp_path, capsys):
    p = tmp_path / "optimisation_data.tar.xz"
    p.write_bytes(b"\xfd7zXZ\x00" + b"\x00" * 100)
    assert _err(capsys, ["evaluate", "steps", str(p)]).startswith(f"error: {p}: corrupt or truncated archive")


# ----------------------------------------------------------------------------------- evaluate track

HEADER = "#\tstartTime:1574149352216\n"


def _trace(path, n_wp=3, cut=False, lower=False):
    t0 = 1574149352216
    lines = []
    for i in range(200):
        t = t0 + 20 * i
        lines += [f"{t}\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t3", f"{t}\tTYPE_GYROSCOPE\t0\t0\t0\t3",
                  f"{t}\tTYPE_MAGNETIC_FIELD\t20\t-5\t-30\t3"]
        if i % 50 == 10:
            lines.append(f"{t}\tTYPE_WIFI\tnet\taa:bb:cc:dd:ee:01\t-50\t2412\t{t}")
        if n_wp and i % (200 // n_wp) == 0 and i // (200 // n_wp) < n_wp:
            lines.append(f"{t}\tTYPE_WAYPOINT\t{i / 10}\t1.0")
    text = HEADER + "\n".join(lines) + "\n"
    if lower:
        text = text.replace("TYPE_GYROSCOPE", "type_gyroscope")
    if cut:
        text = text.rstrip("\n")[:-8]
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("kind, expect", [
    ("cut", r"line 608: the file ends inside this record \(1 of the 4 values of TYPE_MAGNETIC_FIELD"),
    ("lower", r"line 3: record type 'type_gyroscope' must be upper case"),
    ("wp1", r"the walk has 1 waypoint \(TYPE_WAYPOINT records\); at least 2 are needed"),
])
def test_track_bad_traces(tmp_path, capsys, kind, expect):
    import re

    fp = _trace(tmp_path / "fp.txt")
    bad = _trace(tmp_path / "bad.txt", n_wp=1 if kind == "wp1" else 3, cut=kind == "cut", lower=kind == "lower")
    line = _err(capsys, ["evaluate", "track", "--trace", bad, "--fingerprints", fp, "--no-map"])
    assert re.match(rf"error: {re.escape(bad)}: {expect}", line), line
    line = _err(capsys, ["evaluate", "track", "--trace", fp, "--fingerprints", bad, "--no-map"])
    assert re.match(rf"error: {re.escape(bad)}: {expect}", line), line


def test_track_bad_map_json(tmp_path, capsys):
    fp, tr = _trace(tmp_path / "fp.txt"), _trace(tmp_path / "tr.txt")
    d = tmp_path / "F4"
    (d / "path_data_files").mkdir(parents=True)
    (d / "floor_info.json").write_text('{"map_info": {"width": 10,}}')
    (d / "geojson_map.json").write_text("{}")
    line = _err(capsys, ["evaluate", "track", "--trace", tr, "--fingerprints", fp, "--map", str(d)])
    assert line.startswith(f"error: {d}/floor_info.json: line 1, column 27: not valid JSON")
