"""How the toolkit reads the PSO thesis (Chao 2008): the readings of experiment ``pso_k_factor``, as data.

One row per modelling choice (:mod:`ilocalg.papers._reading_rows`): the thesis's line, what it says, what the
code does, and the source of each value the text does not give. The run's choices fill the rows
(``prefilter``, ``band``, ``fitness`` and the simulator's assumed values, see :func:`readings`).
Line numbers are lines of the thesis's text copy (``/work/shared/papers/003_75bedf25a7e92732.txt``).

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers._reading_rows import Fmt, Pick, render
from ilocalg.papers.pso import K_FIXED_PAPER
from ilocalg.pdr.k_factor import K_BOUNDS, PSO_SETTINGS_PAPER

__all__ = ["ROWS", "SENSITIVITY_VARIANTS", "readings"]

ROWS = (
    ("MA on the walking acceleration", "L692, L718, L713, L735-743",
     "processing chain: 'signal correction and filtering (MA Signal Filter)', then the step detection "
     "algorithm (L692); 'MA filtering is adopted for the experiments' (L718); the only width given is "
     "nL=nR=2 (compass Fig 5.4, accelerometer Figs 5.6-5.8)",
     Pick("prefilter", {"none": "no moving average", "ma1": "MA nL=nR=1", "ma2": "MA nL=nR=2"}),
     "thesis (default MA nL=nR=2); no MA (the toolkit's earlier default) is the labelled alternative "
     "reading (comparison rows 'Table 5-2 (none, ...)', tables *_no_ma), MA 1 a sensitivity row. "
     "MA(2,2) at 8 Hz zeroes 1.6 Hz (pdr.filters.smoother_gain), inside the step-rate band"),
    ("+-RMS band of Fig 3.9", "L519-520; eq. 3.4 L440-444; L699-701",
     "reject extrema inside [-RMS, +RMS]; RMS (eq. 3.4) measures the static error; the static experiment "
     "gives 'the error range for the correction of eq. 4.4'",
     Pick("band", {"static": "static-noise RMS of a simulated 60 s static log, after the walk's pre-filter",
                   "signal": "RMS of the walking signal itself"}, other="fixed {band} m/s^2"),
     Fmt("thesis reading (the band is the static RMS); its size follows the accelerometer noise, which the "
         "text does not give (HAAM-325B, ref. [34]): {acc_noise_mps2:.2f} m/s^2 assumed, swept 0.05-0.20 m/s^2; "
         "band 0 and the walking-signal RMS are sensitivity rows (sensitivity table)")),
    ("fitness, eq. 4.4", "L632-634; Fig 5.12 L834, L840",
     "f(k) = |S_gps - S_ins| with S the step length; A1: Fitness 0.0939 with Diff(GPS) 2.0996 m",
     Pick("fitness", {"per_step": "mean over steps of |D_gps/N - k q_j|"},
          other="|D_gps - k sum q_j| over the walk"),
     "per step: the only reading compatible with Fig 5.12; walk-total (the toolkit's earlier default) is a "
     "sensitivity row"),
    ("Table 5-2 accuracy", "L927-935, L845",
     "accuracy (%) beside GPS (PSO) distance; A1 158.28 m vs 160.25 m -> 98.7 %",
     "100 (1 - |GPS - PSO| / GPS) on the learning walk itself (PSO = DR path length with the learned k)",
     "thesis"),
    ("PSO settings", "L807-812",
     Fmt("maxIters {s[max_iters]}, particles {s[n_particles]}, weight {s[w_init]} -> {s[w_final]}, maxSpeed "
         "{s[max_speed]}, minFitness {s[min_fitness]}, c1 = c2 = {s[c1]}"),
     "the same (ilocalg.optim.pso_minimize)", "thesis"),
    ("what sets the PSO's k", "L811", "stop when the fitness is below minFitness (0.1)",
     "the PSO stops anywhere in [k_stop_lo, k_stop_hi] (fitness < 0.1); k_closed is the exact minimiser",
     "a property of the 1-D problem: the PSO result is set by its stop rule"),
    ("initial search box", "", "silent", Fmt("initial swarm uniform in k in {k_bounds}"), "toolkit's choice"),
    ("true route length", "L927-935 (Table 5-2)", "the walk's length is known only from GPS",
     Fmt("true length = route_scale x the thesis's GPS distance, route_scale {route_scale:g}"),
     Fmt("assumption; route_scale {route_scales} are sensitivity rows")),
    ("GPS error", "L750-752 (sec. 5.1.3, Fig 5.9)", "static ~30 s, accuracy better than 1.5 m",
     Fmt("Gauss-Markov per axis, sd {gps_sd_m:.2f} m ({gps_static_95_m:g} m as the 95 % radius), tau "
         "{gps_open_tau_s:g} s, no white part"),
     "thesis bound; tau is not in the text (assumed) and sets the GPS distance's bias (the 1 Hz track "
     "sums the fixes' noise: GPS/true distance 1.028 at tau 20 s); swept tau 5-300 s and bound 0.75 m "
     "(sensitivity table, column gps_over_true_mean)"),
    ("step-to-step scatter", "L771 (walk at a normal, steady pace, steps as even as possible)",
     "no variability value",
     Fmt("step length and duration CV {step_cv_pct:g} % (Hausdorff 2005); vertical-acceleration amplitude "
         "scatter CV {step_amp_cv:g} per step beyond the pendulum's"),
     "amplitude CV measured on the ILC 2020 site2/F4 walks (per-step Amax-Amin CV 0.20, median of the 19 walks; "
     "ilc_walks.amp_cv) minus the pendulum's 0.085; swept 0-0.27 and step CV 1.5-5 % (sensitivity table)"),
    ("hand sway, magnetic disturbance", "L769", "the device is held in the hand; no sway or disturbance values",
     "yaw sway 4.5 deg at the stride rate; heading error along the route, sd 2 deg, 10 m correlation",
     "Crosbie et al. 1997 (trunk axial rotation ~9 deg); smartphone azimuth RMSE <= 2 deg (Lviv field study); "
     "correlation length assumed"),
    ("step heading", "L718", "MA used on the compass", "compass yaw after MA(2,2) at each detected step",
     "thesis (compass calibration, Fig 5.4)"),
    ("fixed k of the comparison (TAR)", "L899", "eq. 2.5 with k = 0.5", Fmt("k = {k_fixed}"), "thesis"),
)


#: The labelled alternative readings and assumed values that pso_k_factor.sensitivity sweeps, one at a time:
#: (name, prefilter, band, fitness, route_scale[, simulator overrides]); the first is the default. ``band`` is
#: "static", "signal" or a half-width in m/s^2.
SENSITIVITY_VARIANTS = (
    ("default (text reading)", "ma2", "static", "per_step", 1.0),
    ("alternative reading: no MA", "none", "static", "per_step", 1.0),
    ("MA nL=nR=1", "ma1", "static", "per_step", 1.0),
    ("band: walking-signal RMS", "ma2", "signal", "per_step", 1.0),
    ("band 0 (no rejection)", "ma2", 0.0, "per_step", 1.0),
    ("accelerometer noise 0.05 m/s^2 (band follows)", "ma2", "static", "per_step", 1.0, {"acc_noise_mps2": 0.05}),
    ("accelerometer noise 0.20 m/s^2 (band follows)", "ma2", "static", "per_step", 1.0, {"acc_noise_mps2": 0.20}),
    ("fitness: walk total", "ma2", "static", "total", 1.0),
    ("earlier reading (MA 2, signal RMS, walk total)", "ma2", "signal", "total", 1.0),
    ("route 0.95 x GPS distance", "ma2", "static", "per_step", 0.95),
    ("route 1.05 x GPS distance", "ma2", "static", "per_step", 1.05),
    ("amplitude scatter 0 (earlier simulator)", "ma2", "static", "per_step", 1.0, {"step_amp_cv": 0.0}),
    ("amplitude scatter CV 0.10", "ma2", "static", "per_step", 1.0, {"step_amp_cv": 0.10}),
    ("amplitude scatter CV 0.27 (ILC IQR top)", "ma2", "static", "per_step", 1.0, {"step_amp_cv": 0.27}),
    ("step CV 1.5 %", "ma2", "static", "per_step", 1.0, {"step_cv": 0.015}),
    ("step CV 5 %", "ma2", "static", "per_step", 1.0, {"step_cv": 0.05}),
    ("GPS tau 5 s", "ma2", "static", "per_step", 1.0, {"gps_open_tau_s": 5.0}),
    ("GPS tau 60 s", "ma2", "static", "per_step", 1.0, {"gps_open_tau_s": 60.0}),
    ("GPS tau 300 s", "ma2", "static", "per_step", 1.0, {"gps_open_tau_s": 300.0}),
    ("GPS 95 % bound 0.75 m", "ma2", "static", "per_step", 1.0, {"gps_static_95_m": 0.75}),
)


def readings(prefilter: str, band, fitness: str, sensors: dict, route_scale: float, route_scales,
             gps_sd_m: float) -> pd.DataFrame:
    """The readings table of one run: ``sensors`` are the simulator's settings used
    (:data:`ilocalg.sim.pso_walks.SENSORS` with the run's overrides), ``gps_sd_m`` the per-axis GPS sd they give."""
    return render(ROWS, "Chao 2008, ", prefilter=prefilter, band=band, fitness=fitness, s=PSO_SETTINGS_PAPER,
                  k_bounds=K_BOUNDS, route_scale=route_scale, route_scales=route_scales, k_fixed=K_FIXED_PAPER,
                  gps_sd_m=gps_sd_m, gps_static_95_m=sensors["gps_static_95_m"],
                  gps_open_tau_s=sensors["gps_open_tau_s"], acc_noise_mps2=sensors["acc_noise_mps2"],
                  step_cv_pct=100 * sensors["step_cv"], step_amp_cv=sensors["step_amp_cv"])
