"""Tests of ilocalg.io.ipin on small crafted IPIN logfiles (no real file is available)."""

from __future__ import annotations

import numpy as np
import pytest

from ilocalg.io import ipin

GOOD = """\
% Logfile crafted for the tests
% ACCE;AppTimestamp(s);SensorTimestamp(s);Acc_X(m/s^2);Acc_Y(m/s^2);Acc_Z(m/s^2);Accuracy(integer)
POSI;0.100;1;39.000000;-3.000000;0;0
ACCE;0.110;1000.010;0.1;0.2;9.8;3
GYRO;0.112;1000.012;0.01;0.02;0.03;3
MAGN;0.115;1000.015;20.0;-5.0;-30.0;3
ACCE;0.130;1000.030;0.2;0.3;9.7;3
AHRS;0.131;1000.031;1.0;2.0;3.0;0.1;0.2;0.3
PRES;0.132;1000.032;1013.2;3
ACCE;0.150;1000.050;0.3;0.4;9.6;3
GYRO;0.152;1000.052;0.04;0.05;0.06;3
WIFI;0.500;1000.400;eduroam;00:0B:86:27:36:C1;2412;-65
WIFI;0.500;1000.450;;00:0b:86:27:36:c2;5180;-80
WIFI;1.500;1001.400;eduroam;00:0b:86:27:36:c1;2412;-62
BLE4;1.600;1001.5;12;-70;ab:cd
POSI;2.100;2;39.000100;-3.000000;1;0
"""


def _write(tmp_path, text, name="log.txt"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_good_file_parses(tmp_path):
    log = ipin.load_ipin_logfile(_write(tmp_path, GOOD))
    np.testing.assert_allclose(log.acc.index.to_numpy(), [0.11, 0.13, 0.15])
    np.testing.assert_allclose(log.acc["acc_z_mps2"].to_numpy(), [9.8, 9.7, 9.6])
    assert list(log.gyr.columns) == ["gyr_x_radps", "gyr_y_radps", "gyr_z_radps"]
    assert len(log.gyr) == 2 and len(log.mag) == 1
    np.testing.assert_allclose(log.sensor_t_s["acc"], [1000.01, 1000.03, 1000.05])
    assert log.wifi["scan_id"].tolist() == [0, 0, 1]
    assert log.wifi["bssid"].tolist() == ["00:0b:86:27:36:c1", "00:0b:86:27:36:c2", "00:0b:86:27:36:c1"]
    assert log.wifi["rssi_dbm"].tolist() == [-65.0, -80.0, -62.0]
    assert log.wifi["freq_mhz"].tolist() == [2412.0, 5180.0, 2412.0]
    assert log.positions["floor"].tolist() == [0, 1]
    # 0.0001 deg of latitude is ~11.1 m north
    np.testing.assert_allclose(log.positions["y_m"].to_numpy(), [0.0, 11.119], atol=1e-3)
    np.testing.assert_allclose(log.positions["x_m"].to_numpy(), [0.0, 0.0], atol=1e-9)
    assert log.kept == {"POSI": 2, "ACCE": 3, "GYRO": 2, "MAGN": 1, "WIFI": 3}
    assert log.skipped == {"AHRS": 1, "PRES": 1, "BLE4": 1}


def test_sensor_time_option(tmp_path):
    log = ipin.load_ipin_logfile(_write(tmp_path, GOOD), time="sensor")
    np.testing.assert_allclose(log.acc.index.to_numpy(), [1000.01, 1000.03, 1000.05])
    with pytest.raises(ValueError, match="time must be 'app' or 'sensor'"):
        ipin.load_ipin_logfile(_write(tmp_path, GOOD), time="gps")


def _replace(old, new):
    assert old in GOOD
    return GOOD.replace(old, new)


@pytest.mark.parametrize("text, match", [
    (_replace("ACCE;0.130;1000.030;0.2;0.3;9.7;3", "ACCE;0.130;1000.030;0.2;0.3"),
     r"line 7: ACCE expects 6 fields after the type, got 4"),
    (_replace("ACCE;0.130;1000.030;0.2;0.3;9.7;3", "ACCE;0.130;1000.030;0.2;x;9.7;3"),
     r"line 7: ACCE field 5 \(Y\) must be a finite number, got 'x'"),
    (_replace("ACCE;0.130;1000.030;0.2;0.3;9.7;3", "ACCE;0.130;1000.030;0.2;nan;9.7;3"),
     r"line 7: ACCE field 5 \(Y\) must be a finite number, got 'nan'"),
    (_replace("ACCE;0.130;1000.030", "ACCE;0.110;1000.030"),
     r"line 7: duplicate ACCE timestamp 0.11 after 0.11.*try time='sensor'"),
    (_replace("ACCE;0.150;1000.050", "ACCE;0.120;1000.050"), r"line 10: decreasing ACCE timestamp 0.12 after 0.13"),
    (_replace("WIFI;1.500;", "WIFI;0.400;"), r"line 14: decreasing WIFI timestamp 0.4 after 0.5"),
    (_replace("WIFI;0.500;1000.450;;00:0b:86:27:36:c2", "WIFI;0.500;1000.450;;00:0b:86:27:36:C1"),
     r"line 13: WIFI bssid '00:0b:86:27:36:c1' appears twice"),
    (_replace("WIFI;1.500;1001.400;eduroam;00:0b:86:27:36:c1;2412;-62", "WIFI;1.500;1001.400;eduroam"),
     r"line 14: WIFI expects 6 fields"),
    (_replace("POSI;2.100;2;39.000100;-3.000000;1;0", "POSI;2.100;2;39.000100;-3.000000;1.5;0"),
     r"line 16, column 6 \(floor_ID\): value 1.5 is not a whole number"),
    (_replace("POSI;2.100;2;39.000100", "POSI;0.100;2;39.000100"), r"line 16: duplicate POSI timestamp"),
    (_replace("POSI;2.100;2;39.000100", "POSI;2.100;2;99.000100"),
     r"line 16, column 4 \(Latitude\): value 99.0001 is outside \[-90, 90\] deg"),
])
def test_bad_input_names_file_line_and_field(tmp_path, text, match):
    p = _write(tmp_path, text, name="bad_log.txt")
    with pytest.raises(ValueError, match=match) as e:
        ipin.load_ipin_logfile(p)
    assert "bad_log.txt" in str(e.value)


def test_empty_and_comment_only_files_raise(tmp_path):
    with pytest.raises(ValueError, match="empty.txt: no records"):
        ipin.load_ipin_logfile(_write(tmp_path, "", name="empty.txt"))
    with pytest.raises(ValueError, match="no records"):
        ipin.load_ipin_logfile(_write(tmp_path, "% only a comment\n\n"))


def test_file_without_imu_or_wifi_gives_empty_tables(tmp_path):
    log = ipin.load_ipin_logfile(_write(tmp_path, "POSI;0.1;1;39.0;-3.0;0;0\nPRES;0.2;0.2;1013;3\n"))
    assert log.acc.empty and log.gyr.empty and log.mag.empty and log.wifi.empty
    assert log.acc.index.name == "t_s" and list(log.mag.columns) == ["mag_x_ut", "mag_y_ut", "mag_z_ut"]
    assert len(log.positions) == 1 and log.skipped == {"PRES": 1}
