import numpy as np
import pytest

from ilocalg.pdr import heading as hd
from ilocalg.sim import gait
from ilocalg.units import wrap_angle_rad


def _rot(yaw, pitch, roll):
    """Body->ENU rotation of a phone whose y axis points along map heading ``yaw`` (from east, CCW)."""
    def rz(a):
        return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])

    def rx(a):
        return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])

    def ry(a):
        return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    return rz(yaw - np.pi / 2) @ rx(pitch) @ ry(roll)


@pytest.mark.parametrize("theta_deg", [0, 30, 90, 135, -100, 179])
@pytest.mark.parametrize("pitch_deg,roll_deg", [(0, 0), (30, 5), (-20, -10)])
def test_heading_of_known_attitudes(theta_deg, pitch_deg, roll_deg):
    R = _rot(np.deg2rad(theta_deg), np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    g_n = np.array([0.0, 0.0, 9.81])
    m_n = np.array([0.0, 30.0, -40.0])        # north and downwards
    g_b, m_b = R.T @ g_n, R.T @ m_n
    th = hd.heading_theta_rad(g_b, m_b)
    assert abs(wrap_angle_rad(th - np.deg2rad(theta_deg))) < 1e-9
    T = hd.wdm_rotation(g_b, m_b)
    np.testing.assert_allclose(T @ T.T, np.eye(3), atol=1e-12)
    if pitch_deg == 0 and roll_deg == 0:
        # eq. (19) gives the yaw of the x axis: 90 deg clockwise of the forward (y) axis
        psi_x = hd.wdm_yaw_rad(g_b, m_b)
        assert abs(wrap_angle_rad(psi_x - (np.pi / 2 - np.deg2rad(theta_deg)) - np.pi / 2)) < 1e-9


def test_rotation_matches_eq18_for_level_phone():
    psi = np.deg2rad(40.0)
    # a level phone (x north-east rotated): sensor axes in NED from eq. (18) with theta = phi = 0
    T = np.array([[np.cos(psi), -np.sin(psi), 0], [np.sin(psi), np.cos(psi), 0], [0, 0, 1]])
    g_s = T.T @ np.array([0.0, 0.0, -9.81])       # accelerometer reads up = -down
    m_s = T.T @ np.array([25.0, 0.0, 40.0])       # north, and down
    np.testing.assert_allclose(hd.wdm_rotation(g_s, m_s), T, atol=1e-12)
    assert hd.wdm_yaw_rad(g_s, m_s) == pytest.approx(psi)


def test_wdm_on_simulated_walk_and_gyro_heading():
    # a phone held straight, calibrated, at a site without declination: WDM sees the walking direction
    w = gait.make_walkers(1, 3, misalign_sd_deg=0.0, hard_iron_sd_ut=0.0)[0]
    sw = gait.simulate_walk(gait.loop_route(), w, 4, gait.GaitConfig(declination_deg=0.0))
    acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
    mag = sw.imu[["mag_x_ut", "mag_y_ut", "mag_z_ut"]].to_numpy()
    gyr = sw.imu[["gyr_x_radps", "gyr_y_radps", "gyr_z_radps"]].to_numpy()
    from ilocalg.pdr.signals import moving_mean
    g = np.column_stack([moving_mean(acc[:, j], 25) for j in range(3)])
    th = hd.WDM().heading(g, mag)
    np.testing.assert_allclose(th, hd.heading_theta_rad(g, mag))
    err = np.rad2deg(np.abs(wrap_angle_rad(th - sw.truth["theta_rad"].to_numpy())))
    assert np.median(err) < 20.0
    tg = hd.gyr_heading_theta_rad(gyr, g, sw.imu.index.to_numpy(), sw.truth["theta_rad"].iloc[0])
    eg = np.rad2deg(np.abs(wrap_angle_rad(tg - sw.truth["theta_rad"].to_numpy())))
    assert np.median(eg[sw.imu.index.to_numpy() < 20.0]) < 20.0  # before the gyro bias takes over


def test_misalignment_declination_and_hard_iron_shift_wdm():
    """The phone's axis off the walking direction and the site's declination shift WDM by their angles;
    a known hard-iron offset, subtracted, restores the heading."""
    from ilocalg.pdr.signals import moving_mean

    w0 = gait.make_walkers(1, 3, misalign_sd_deg=0.0, hard_iron_sd_ut=0.0)[0]
    cfg0 = gait.GaitConfig(declination_deg=0.0, n_disturbances_per_100m2=0.0, mag_noise_ut=0.0)
    route = gait.straight_route(20.0, 0.7)

    def wdm(w, cfg, **kw):
        sw = gait.simulate_walk(route, w, 4, cfg, disturbances={"centre_m": np.zeros((0, 2)),
                                                                "vec_ut": np.zeros((0, 3)), "width_m": np.zeros(0)})
        acc = sw.imu[["acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]].to_numpy()
        mag = sw.imu[["mag_x_ut", "mag_y_ut", "mag_z_ut"]].to_numpy()
        g = np.column_stack([moving_mean(acc[:, j], 50) for j in range(3)])
        return np.angle(np.mean(np.exp(1j * hd.heading_theta_rad(g, mag, **kw))))

    base = wdm(w0, cfg0)
    assert np.rad2deg(abs(wrap_angle_rad(base - 0.7))) < 2.0
    import dataclasses
    w_mis = dataclasses.replace(w0, misalign_rad=np.deg2rad(10.0))
    # yaw + 10 deg turns the phone's y axis 10 deg counter-clockwise: heading + 10 deg
    assert np.rad2deg(wrap_angle_rad(wdm(w_mis, cfg0) - base)) == pytest.approx(10.0, abs=1.0)
    cfg_dec = dataclasses.replace(cfg0, declination_deg=-4.5)
    # magnetic north 4.5 deg west of true north: the magnetic azimuth is 4.5 deg larger (clockwise),
    # so an uncorrected heading (from east, counter-clockwise) reads 4.5 deg less
    shift = np.rad2deg(wrap_angle_rad(wdm(w0, cfg_dec) - base))
    assert shift == pytest.approx(-4.5, abs=1.0)
    corrected = np.rad2deg(wrap_angle_rad(wdm(w0, cfg_dec, declination_rad=np.deg2rad(-4.5)) - base))
    assert abs(corrected) < 1.0
    w_hi = dataclasses.replace(w0, hard_iron_ut=(8.0, 0.0, 0.0))
    assert abs(np.rad2deg(wrap_angle_rad(wdm(w_hi, cfg0) - base))) > 3.0
    fixed = wdm(w_hi, cfg0, hard_iron_ut=w_hi.hard_iron_ut)
    assert abs(np.rad2deg(wrap_angle_rad(fixed - base))) < 1.0


def test_bad_input():
    with pytest.raises(ValueError, match="degenerate"):
        hd.wdm_rotation([0, 0, 9.8], [0, 0, 30.0])
    with pytest.raises(ValueError, match="NaN"):
        hd.wdm_rotation([0, 0, np.nan], [0, 1, 0])
    with pytest.raises(ValueError, match="shape"):
        hd.wdm_rotation([0, 9.8], [0, 1, 0])
    with pytest.raises(ValueError, match="strictly increasing"):
        hd.gyr_heading_theta_rad(np.zeros((3, 3)), [0, 0, 1.0], [0.0, 0.0, 1.0])
