import numpy as np
import pandas as pd
import pytest

from ilocalg.io import schema
from ilocalg.io.schema import FingerprintSet


def test_check_time_index_names_the_offending_row():
    assert schema.check_time_index([0.0, 0.1, 0.2]).dtype == np.float64
    with pytest.raises(ValueError, match="duplicate timestamp at row 2"):
        schema.check_time_index([0.0, 1.0, 1.0], source="log.csv")
    with pytest.raises(ValueError, match="log.csv: .*decreasing timestamp at row 1"):
        schema.check_time_index([1.0, 0.5], source="log.csv")
    with pytest.raises(ValueError, match="not finite at row 1"):
        schema.check_time_index([0.0, np.nan])
    with pytest.raises(ValueError, match="empty"):
        schema.check_time_index([])


def test_check_imu_rejects_unknown_columns_and_nan():
    idx = pd.Index([0.0, 0.01], name="t_s")
    ok = pd.DataFrame({"acc_x_mps2": [0.0, 1.0]}, index=idx)
    schema.check_imu(ok)
    with pytest.raises(ValueError, match="unknown IMU columns"):
        schema.check_imu(pd.DataFrame({"ax": [0.0, 1.0]}, index=idx))
    with pytest.raises(ValueError, match="'acc_x_mps2' is not finite at row 1"):
        schema.check_imu(pd.DataFrame({"acc_x_mps2": [0.0, np.nan]}, index=idx))
    with pytest.raises(ValueError, match="lacks required"):
        schema.check_imu(ok, required=schema.GYR_COLS)


def test_check_wifi_scans_finds_duplicates_and_disorder():
    df = pd.DataFrame({"t_s": [0.0, 0.0, 1.0], "scan_id": [0, 0, 1], "bssid": ["a", "b", "a"],
                       "rssi_dbm": [-50.0, -60.0, -55.0]})
    schema.check_wifi_scans(df)
    dup = df.copy()
    dup.loc[1, "bssid"] = "a"
    with pytest.raises(ValueError, match="twice"):
        schema.check_wifi_scans(dup)
    with pytest.raises(ValueError, match="not sorted"):
        schema.check_wifi_scans(df.iloc[::-1].reset_index(drop=True))


def test_fingerprint_set_validates_shapes():
    fs = FingerprintSet(np.full((3, 2), np.nan), ("a", "b"), np.zeros(3), np.ones(3), floor=np.array([0, 1, 1]))
    assert (fs.n_samples, fs.n_aps) == (3, 2)
    assert fs.subset([True, False, True]).n_samples == 2
    assert list(fs.to_frame().columns) == ["a", "b", "x_m", "y_m", "floor"]
    with pytest.raises(ValueError, match="ap_ids"):
        FingerprintSet(np.zeros((3, 2)), ("a",), np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="not unique"):
        FingerprintSet(np.zeros((3, 2)), ("a", "a"), np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match=r"y_m has shape \(2,\)"):
        FingerprintSet(np.zeros((3, 2)), ("a", "b"), np.zeros(3), np.zeros(2))
