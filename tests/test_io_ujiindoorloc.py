"""UJIIndoorLoc loader: synthetic files (plain and gzip), bad input, and the real shared copy."""

import gzip

import numpy as np
import pytest

from ilocalg.io.ujiindoorloc import META_COLUMNS, POSITION_COLUMNS, WAP_COLUMNS, ground_scale, load_ujiindoorloc

HEADER = ",".join(WAP_COLUMNS + POSITION_COLUMNS + META_COLUMNS)


def _row(rssi=None, lon=-7541.26, lat=4864921.0, floor=2, b=1):
    r = [100] * 520 if rssi is None else rssi
    return ",".join(str(v) for v in r) + f",{lon},{lat},{floor},{b},106,2,2,23,1371713733"


def _write(tmp_path, lines, name="trainingData.csv", gz=False):
    text = "\n".join(lines) + "\n"
    p = tmp_path / (name + (".gz" if gz else ""))
    if gz:
        with gzip.open(p, "wt") as fh:
            fh.write(text)
    else:
        p.write_text(text)
    return p


@pytest.mark.parametrize("gz", [False, True])
def test_loads_plain_and_gzip(tmp_path, gz):
    rssi = [100] * 520
    rssi[0], rssi[5] = -60, -104
    p = _write(tmp_path, [HEADER, _row(rssi), _row(lon=-7500.5, floor=3, b=2)], gz=gz)
    fs = load_ujiindoorloc(p)
    assert fs.rssi_dbm.shape == (2, 520)
    assert fs.rssi_dbm[0, 0] == -60 and fs.rssi_dbm[0, 5] == -104 and np.isnan(fs.rssi_dbm[0, 1])
    assert np.isnan(fs.rssi_dbm[1]).all()
    np.testing.assert_array_equal(fs.x_m, [-7541.26, -7500.5])
    np.testing.assert_array_equal(fs.floor, [2, 3])
    np.testing.assert_array_equal(fs.building, [1, 2])
    assert list(fs.meta.columns) == list(META_COLUMNS)
    assert fs.ap_ids[0] == "WAP001" and fs.ap_ids[-1] == "WAP520"


def test_bad_input(tmp_path):
    p = _write(tmp_path, [""], name="empty.csv")
    with pytest.raises(ValueError, match="empty.csv: empty file"):
        load_ujiindoorloc(p)
    p = _write(tmp_path, [HEADER.replace("FLOOR,", "")], name="nofloor.csv")
    with pytest.raises(ValueError, match=r"nofloor.csv: line 1 \(header\) lacks columns \['FLOOR'\]"):
        load_ujiindoorloc(p)
    p = _write(tmp_path, [HEADER, _row(), _row()[:-40]], name="trunc.csv")
    with pytest.raises(ValueError, match="trunc.csv: line 3: truncated line"):
        load_ujiindoorloc(p)
    p = _write(tmp_path, [HEADER, _row().replace(",2,1,106", ",two,1,106")], name="nonnum.csv")
    with pytest.raises(ValueError, match="nonnum.csv: line 2, column FLOOR: expected a number, got 'two'"):
        load_ujiindoorloc(p)
    bad = [100] * 520
    bad[7] = 5
    p = _write(tmp_path, [HEADER, _row(), _row(bad)], name="range.csv")
    with pytest.raises(ValueError, match=r"range.csv: line 3, column WAP008: value 5 is outside \[-110, 0\] dBm"):
        load_ujiindoorloc(p)
    p = _write(tmp_path, [HEADER], name="header_only.csv")
    with pytest.raises(ValueError, match="no data rows"):
        load_ujiindoorloc(p)
    p = tmp_path / "broken.csv.gz"
    p.write_bytes(gzip.compress((HEADER + "\n" + _row()).encode())[:200])
    with pytest.raises(ValueError, match="broken.csv.gz: corrupt or truncated gzip data"):
        load_ujiindoorloc(p)
    with pytest.raises(FileNotFoundError):
        load_ujiindoorloc(tmp_path / "missing.csv")


def test_ground_scale_at_castellon():
    assert ground_scale(4864921.0) == pytest.approx(np.cos(np.deg2rad(39.99)), abs=2e-3)


@pytest.mark.realdata
def test_real_copy(shared_data):
    d = shared_data("ujiindoorloc")
    tr = load_ujiindoorloc(d / "trainingData.csv.gz")
    va = load_ujiindoorloc(d / "validationData.csv.gz")
    assert tr.n_samples == 19937 and va.n_samples == 1111 and tr.n_aps == 520
    assert np.nanmin(tr.rssi_dbm) == -104 and np.nanmax(tr.rssi_dbm) == 0
    assert set(np.unique(tr.building)) == {0, 1, 2} and set(np.unique(tr.floor)) == {0, 1, 2, 3, 4}
    assert int(np.isnan(tr.rssi_dbm).all(axis=1).sum()) == 76  # rows that hear nothing (kept, not dropped)
