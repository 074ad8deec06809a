"""How the toolkit reads Liao et al. (2016): the readings of experiments ``ins_constraints`` and ``ins_online``.

One row per modelling choice (:mod:`ilocalg.papers._reading_rows`): the paper's line, what it says, what the
code does, and the source of each value the text does not give. The run's choices fill the rows: the
stair handling and the simulated phone's and walker's assumed values (:func:`constraints_readings`), the
window-grid offsets (:func:`online_readings`). Line numbers are lines of the paper's text copy
(``/work/shared/papers/001_2222ac3cfae0589e.txt``).

References
----------
Liao, J.-K., Chiang, K.-W., Zhou, Z.-M., Li, C.-H. (2016). Using the on-line smoothing and constraint
algorithms to improve the accuracy of pedestrian indoor navigation.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers._reading_rows import Fmt, Pick, render

__all__ = ["CITE", "CONSTRAINTS_ROWS", "ONLINE_ROWS", "GCP_RSSI_SD_SWEEP_DB", "BIAS_INSTABILITY_FACTORS",
           "TIME_JITTERS_S", "NOISE_FACTORS", "constraints_readings", "online_readings"]

CITE = "Liao et al. (2016), "

#: Readings of ins_constraints (Tables 4-7).
CONSTRAINTS_ROWS = (
    ("filter state and update", "L109-L134", "21-state EKF, eq. (1)-(6), Joseph update",
     "ilocalg.ins.eskf.run_eskf, closed loop", "paper"),
    ("WVC forward speed", "L151-L158", "step model of Chen et al. (2011), eq. (7), default height and "
     "parameters", "eq. (7), h = 1.75 m, a = 0.371, b = 0.227, c = 1",
     "a, b, c: the widely reproduced Chen et al. (2011) values, not checked against that paper"),
    ("step frequency", "L151", "from the step counter in real time", "1 / time since the previous step "
     "(option: F = 1 / (0.8 dt_k + 0.2 dt_(k-1)))", "smoothing: the same step-model lineage, unchecked"),
    ("WVC / NHC weights", "L146", "WVC lowers the lateral / vertical weights of NHC", "NHC sd 0.05 m/s; "
     "WVC forward 0.15 m/s, lateral / vertical 0.3 m/s", "assumption (the paper gives no numbers)"),
    ("stairs", "L200 (route climbs stairs); L202 (both phones' data processed by the same algorithm)",
     "nothing on the filter's stair behaviour; the same algorithm for both phones",
     (Fmt("stairs={stairs!r}, stair_action={stair_action!r}"),
      Pick("stairs", {"none": ": no stair handling on either phone (eq. 7 everywhere), the one processing both "
                              "phones share (the iPhone 5S has no barometer)",
                      "baro": ": WVC forward and vertical rows dropped where the barometric height rises or falls "
                              "faster than 0.1 m/s (iPhone 5S: no barometer, so the phones are NOT processed alike)"},
           other=": the simulator's true stair flag on both phones (an upper bound, not a detector)")),
     "text (L202): the default processes both phones alike; barometric handling (Samsung only) and the true "
     "flag are labelled alternatives in the stair_handling table (threshold 0.1 m/s: half of 0.17 m x 1.3 Hz)"),
    ("walker on stairs", "-", "not described", "one tread (0.29 m) per step, cadence 1.62 Hz up / "
     "1.80 Hz down (horizontal speed about 0.47 m/s up, derived)", "Blondel's rule; Riener et al. (2002), "
     "Protopapadaki et al. (2007): recalled, not re-read (Kretz et al. 2008, cited earlier for the horizontal "
     "speed, does not give it: dropped); covered by the gait_sensitivity table (stair cadence +- 1 sd, the "
     "earlier 0.5 m/s walker) and the stair_handling table (WVC on stairs off / barometer / true flag)"),
    ("walker on level ground", "-", "not described", Fmt("speed N({speed_mean_mps:.2f}, 0.16) m/s, walk ratio per "
                                                         "height"),
     "Bohannon (1997); Sekiya & Nagasaki (1998); Hof (1996): recalled, not re-read (independent of eq. 7); "
     "covered by the gait_sensitivity table (level speed and walk ratio means +- 1 sd, the eq. 7 walker)"),
    ("ZUPT", "L146", "stand still 1-3 s after turns", "ZUPT at detected standstills, sd 0.05 m/s",
     "paper (stops); sd assumed"),
    ("control points", "L73, L109, L202", "4 surveyed points sent by Bluetooth, cm (survey) / m (Bluetooth) "
     "level, about every 15 s; the user is taken to be at the point when its beacon is sensed (L73)",
     Fmt("fix = surveyed coordinate when the phone sees the beacon: packets every 100 ms (+0-10 ms advDelay), "
         "RSSI -59 dBm at 1 m, path-loss exponent 2, {rssi_sd_db:g} dB per-packet scatter, averaged over 1 s "
         "ranging cycles, fix at the end of the first cycle at or above the RSSI of 0.5 m (immediate); filter sd "
         "1 m"),
     "iBeacon 100 ms advertising and 0.5 m immediate zone, iOS 1 s ranging: recalled, not re-read; -59 dBm "
     "calibrated power (Blue Charm chart; cancels); 4-6 dB scatter (vendor stability tests, weak source): "
     "swept 2 / 8 dB; the earlier truth-gate model (0.6 m gate, U(0, 1 s) delay, 0.5 m offset) and the "
     "ideal fix are rows of the gcp_grade table, with the fixes' count and mean horizontal error"),
    ("phone sampling", "L171, L324", "15-17 Hz; about 20 Hz, unstable, poor time tags",
     Fmt("14.3-20 Hz irregular, point samples, time-tag error sd {time_jitter_ms:g} ms (clipped at 2 sd, monotonic "
         "tags)"),
     "10 ms: no published measurement for these phones; swept 0 / 10 / 30 ms in the sensor_sensitivity "
     "table; on/off in sensor_grade"),
    ("sensor errors", "L178, L202", "the phones' IMUs calibrated in Liao et al. (2014), similar; no values "
     "in this paper", Fmt("MPU-6500 class turn-on bias (30 / 20 mg, 0.3 / 0.2 deg/s), scale factor; white noise "
                          "{noise_factor:g} x the datasheet densities (300 ug/sqrt(Hz), 0.01 deg/s/sqrt(Hz))"),
     "InvenSense MPU-6500 product specification (zero-g offset, sensitivity tolerance): recalled, not "
     "re-read; Liao et al. (2014)'s calibration values not available here; the x3 noise factor is an "
     "assumption swept x1 / x3 / x5 in the sensor_sensitivity table (noise_factor); the whole sensor grade "
     "in the reference_grade table"),
    ("bias instability", "-", "not given",
     Fmt("first-order Gauss-Markov, {bi_acc_mg:g} mg / {bi_gyr_dph:g} deg/h, 300 s"),
     "no published measurement used (assumed order of consumer-MEMS Allan-variance studies); swept x0 / x1 / "
     "x3 in the sensor_sensitivity table; on/off in sensor_grade"),
    ("barometer", "-", "not mentioned (stair handling is this code's)", "Samsung S5 heights, noise sd 0.1 m; "
     "used only by the stair_handling alternatives (no effect on the default rows)",
     "BMP280-class RMS noise about 1.2 Pa: recalled, not re-read; covered by the stair_handling table "
     "(barometric detection vs the true stair flag)"),
    ("GNSS", "L109, L202", "only the two outdoor loops (initialisation)", "1 Hz, sd 2.5 / 2.5 / 4 m",
     "assumption (phone grade)"),
    ("reference", "L178-L191", "MIDG-II (Table 3) on the same walk, NHC/ZUPT, smoothed", "the simulated "
     "truth (reference_grade table processes a MIDG-II-grade IMU like the paper's reference; it has no "
     "barometer, so its WVC rows use the same stair handling as the phones only when that handling needs "
     "none: column 'barometer used' labels each row)", "Table 3"),
    ("scored part", "L202", "the GNSS-aided start removed", "indoor part after the outdoor loops", "paper"),
)

#: The values ins_constraints' sensitivity tables sweep, one at a time (sources in :data:`CONSTRAINTS_ROWS`): the
#: control-point beacons' RSSI scatters (dB, gcp_grade; the default is 5 dB), factors on the Gauss-Markov bias
#: instability (0.5 mg / 20 deg/h, 300 s) and time-tag error sds (s) (the defaults are 1 and 10 ms), and factors on
#: the MPU-6500 datasheet white-noise densities (300 ug/sqrt(Hz), 0.01 deg/s/sqrt(Hz); the profiles carry 3).
GCP_RSSI_SD_SWEEP_DB = (2.0, 8.0)
BIAS_INSTABILITY_FACTORS = (0.0, 1.0, 3.0)
TIME_JITTERS_S = (0.0, 0.01, 0.03)
NOISE_FACTORS = (1.0, 3.0, 5.0)

#: Readings of ins_online (Tables 8-11, Fig 19).
ONLINE_ROWS = (
    ("online smoother", "L169-L171, Fig 3", "RTS (eq. 8-10) on fixed time windows, run as each window fills",
     "RTS on consecutive fixed windows; the last epoch of a window keeps its filtered value",
     "paper"),
    ("RTS gain", "L165 (eq. 10)", "G_k = P_k^update Phi_(k+1) P_(k+1)^predict as printed",
     "G_k = P_k^update Phi_(k+1)^T (P_(k+1)^predict)^-1 (standard RTS gain)", "Shin (2005), as cited"),
    ("window sizes", "L328-L330, Tables 8-11, Fig 19", "5, 10, 20 s; best 20 s", "5, 10, 20 s and a sweep",
     "paper"),
    ("window grid", "-", "not given (where the first window starts)",
     Fmt("averaged over grid offsets {offsets} x window and over seeds; spread reported"),
     "no value in the paper: averaged instead of chosen"),
    ("filter", "L328; L202", "WVC/ZUPT + indoor control points; both phones by the same algorithm",
     (Fmt("as notebook 12 (stairs={stairs!r}: "),
      Pick("stairs", {"none": "no stair handling on either phone)"},
           other="not the same on both phones: the iPhone has no barometer)")),
     "see ins_constraints readings"),
    ("does the error fall with the window", "L464, L471-L473, Fig 19",
     "best window 20 s; but Samsung N is worse at 20 s than at 10 s (mid-window error of windows without a "
     "control point)", "fig19_monotonicity: RMS at 10 vs 20 s per phone and axis beside the paper's, rises "
     "along the window sweep, Spearman correlation", "paper (Tables 8, 10 for the paper's differences)"),
)


def constraints_readings(stairs: str, stair_action: str, noise_factor: float, bias_instability_factor: float,
                         time_jitter_sd_s: float, rssi_sd_db: float, speed_mean_mps: float) -> pd.DataFrame:
    """The readings table of one ins_constraints run (its stair handling and assumed phone and walker values)."""
    return render(CONSTRAINTS_ROWS, CITE, stairs=stairs, stair_action=stair_action, noise_factor=noise_factor,
                  bi_acc_mg=0.5 * bias_instability_factor, bi_gyr_dph=20.0 * bias_instability_factor,
                  time_jitter_ms=1e3 * time_jitter_sd_s, rssi_sd_db=rssi_sd_db, speed_mean_mps=speed_mean_mps)


def online_readings(stairs: str, offsets) -> pd.DataFrame:
    """The readings table of one ins_online run (its stair handling and window-grid offsets)."""
    return render(ONLINE_ROWS, CITE, stairs=stairs, offsets=tuple(offsets))
