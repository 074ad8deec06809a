"""``evaluate wifi``: the README's CSV survey layout (``--format csv``) and a training file none of whose
reference scans hears an access point (one line naming the file and its lines, exit status 2)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from test_bad_input_cli import _err, _uji

from ilocalg.metrics import horizontal_error_m
from ilocalg.wifi import KnnFingerprint
from ilocalg.wifi.survey import read_survey_csv
from ilocalg.workflow.cli import main


def _survey(path, n_points=40, labels=False, seed=0, aps_order=None):
    """The README's made-up survey (log-distance RSSI, NaN below -85 dBm), written in its CSV layout."""
    rng = np.random.default_rng(seed)
    ap_xy = np.random.default_rng(0).uniform(0, 30, (8, 2))
    scan_xy = np.repeat(rng.uniform(0, 30, (n_points, 2)), 3, axis=0)
    d = np.linalg.norm(scan_xy[:, None] - ap_xy[None], axis=2)
    rssi = np.round(-40 - 25 * np.log10(d + 1) + rng.normal(0, 3, d.shape))
    rssi[rssi < -85] = np.nan
    aps = [f"AP{i}" for i in range(8)]
    df = pd.DataFrame(np.column_stack([scan_xy, rssi]), columns=["x_m", "y_m", *aps])
    if labels:
        df.insert(2, "floor", (scan_xy[:, 0] > 15).astype(int))
        df.insert(3, "building", 1)
    if aps_order is not None:
        df = df[[c for c in df.columns if not c.startswith("AP")] + aps_order]
    df.to_csv(path, index=False)
    return str(path)


def _json(capsys, argv) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("method", ["knn", "radar", "horus"])
def test_training_set_hearing_nothing_names_file_and_lines(tmp_path, capsys, method):
    train = _uji(tmp_path / "train.csv", [[]] * 6)
    test = _uji(tmp_path / "test.csv", [[-60, -70]])
    line = _err(capsys, ["evaluate", "wifi", "--train", train, "--test", test, "--method", method, "--k", "3"])
    assert line == (f"error: {train}: lines 2-7: no reference scan hears an access point (every RSSI is "
                    "'not heard'); a radio map needs scans that hear at least one access point")


def test_one_reference_scan_hearing_nothing_is_accepted(tmp_path, capsys):
    # UJIIndoorLoc's own training file has 76 such scans: they must not stop a run.
    train = _uji(tmp_path / "train.csv", [[-60, -70], [-65, -50], [-70, -60]] * 3 + [[]])
    test = _uji(tmp_path / "test.csv", [[-60, -70]])
    out = _json(capsys, ["evaluate", "wifi", "--train", train, "--test", test, "--k", "3", "--json"])
    assert out["n"] == 1 and np.isfinite(out["mean_error_m"])


def test_csv_survey_agrees_with_the_estimator_and_has_no_hit_rates(tmp_path, capsys):
    train = _survey(tmp_path / "train.csv", seed=1)
    test = _survey(tmp_path / "test.csv", n_points=10, seed=2)
    out = _json(capsys, ["evaluate", "wifi", "--train", train, "--test", test, "--format", "csv", "--method", "knn",
                         "--k", "5", "--json"])
    tr, te = read_survey_csv(train), read_survey_csv(test)
    ref = horizontal_error_m(KnnFingerprint(5, p=2).fit(tr.rssi_dbm, tr.xy_m).predict(te.rssi_dbm), te.xy_m)
    located = np.isfinite(ref)
    assert out["n"] == located.sum()
    assert out["mean_error_m"] == pytest.approx(float(ref[located].mean()), rel=1e-9)
    assert out["floor_hit_rate"] is None and out["building_hit_rate"] is None


def test_csv_survey_with_labels_and_reordered_access_points(tmp_path, capsys):
    train = _survey(tmp_path / "train.csv", labels=True, seed=1)
    test = _survey(tmp_path / "test.csv", n_points=10, labels=True, seed=2)
    shuffled = _survey(tmp_path / "test2.csv", n_points=10, labels=True, seed=2,
                       aps_order=[f"AP{i}" for i in (3, 1, 7, 0, 2, 6, 5, 4)])
    argv = ["evaluate", "wifi", "--train", train, "--format", "csv", "--method", "wknn", "--json", "--test"]
    a, b = _json(capsys, argv + [test]), _json(capsys, argv + [shuffled])
    assert a == b
    assert 0.0 <= a["floor_hit_rate"] <= 1.0 and a["building_hit_rate"] == 1.0


def test_csv_survey_bad_cells_name_line_and_column(tmp_path, capsys):
    test = _survey(tmp_path / "test.csv", n_points=5)
    p = tmp_path / "bad.csv"
    p.write_text("x_m,y_m,AP0,AP1\n1,2,-60,\n3,4,-70,12\n")
    assert _err(capsys, ["evaluate", "wifi", "--train", str(p), "--test", test, "--format", "csv"]) == \
        f"error: {p}: line 3, column AP1: value 12 is outside [-110, 0] dBm"
    p.write_text("x_m,y_m,AP0\n1,2,-60\n3,,-70\n")
    assert _err(capsys, ["evaluate", "wifi", "--train", str(p), "--test", test, "--format", "csv"]) == \
        f"error: {p}: line 3, column y_m: is empty"
    p.write_text("x_m,y_m,AP0\n1,2,-60\n3,4,strong\n")
    assert _err(capsys, ["evaluate", "wifi", "--train", str(p), "--test", test, "--format", "csv"]) == \
        f"error: {p}: line 3, column AP0: must be numeric, got 'strong'"
    p.write_text("x,y,AP0\n1,2,-60\n")
    assert _err(capsys, ["evaluate", "wifi", "--train", str(p), "--test", test, "--format", "csv"]).startswith(
        f"error: {p}: line 1: no column 'x_m'")
    q = tmp_path / "other.csv"
    q.write_text("x_m,y_m,B0\n1,2,-60\n")
    assert _err(capsys, ["evaluate", "wifi", "--train", test, "--test", str(q), "--format", "csv"]) == \
        f"error: {q}: no access-point column in common with {test}"


def test_csv_survey_lines_with_another_field_count_are_refused(tmp_path, capsys):
    """A cut or shortened line would otherwise read as access points not heard; blank lines stay accepted."""
    test = _survey(tmp_path / "test.csv", n_points=5)
    p = tmp_path / "bad.csv"
    argv = ["evaluate", "wifi", "--train", str(p), "--test", test, "--format", "csv"]
    p.write_text("x_m,y_m,AP0,AP1\n1,2,-60,-70\n3,4,-6")                       # the last line cut
    assert _err(capsys, argv) == f"error: {p}: line 3: truncated line: 3 fields, expected 4 (the header's)"
    p.write_text("x_m,y_m,AP0,AP1\r\n1,2,-60\r\n3,4,-65,-70\r\n")                 # a short line inside, CRLF
    assert _err(capsys, argv) == f"error: {p}: line 2: truncated line: 3 fields, expected 4 (the header's)"
    p.write_text('x_m,y_m,"AP,0",AP1\n1,2,-60,-70\n3,4,-65,-70,-80\n')           # quoted header, a field too many
    assert _err(capsys, argv) == f"error: {p}: line 3: too many fields: 5 fields, expected 4 (the header's)"
    p.write_text("x_m,y_m,AP0,AP1\n1,2,-60,-70\n\n3,4,-65,\n\n")                 # blank lines; an empty cell
    s = read_survey_csv(p)
    assert s.n_samples == 2 and np.isnan(s.rssi_dbm[1, 1])
