"""What the PSO thesis (Chao 2008) claims, as data: published values and the claims ledger.

Line numbers are lines of the thesis's text copy (``/work/shared/papers/003_75bedf25a7e92732.txt``).
Published values are labelled references (never used to compute a reproduced value); consistency
claims check the thesis's own printed numbers against each other.

References
----------
Chao, S.-H. (2008). Pedestrian navigation based on particle swarm optimization. M.S. thesis,
Tunghai University.
"""

from __future__ import annotations

import math

import numpy as np

from ilocalg.papers._claim_helpers import decided, gmean, mean_of, stat
from ilocalg.papers.claims import Assumption, Claim, M, constant, diff, ratio, value

__all__ = ["PAPER_TABLE_5_2", "PAPER_PHASE2_A1", "PAPER_COMPASS_RMS", "K_FIXED_PAPER", "TABLE_3_2", "CLAIMS"]

#: Table 5-2 (L927-935): leg length (cm), PSO k, true and detected steps, GPS and PSO distance (m), accuracy (%).
PAPER_TABLE_5_2 = {
    "A1": {"leg_cm": 94, "k": 0.444, "true_steps": 217, "det_steps": 216, "gps_m": 160.25, "pso_m": 158.28, "acc_pct": 98.7},  # noqa: E501
    "A2": {"leg_cm": 94, "k": 0.489, "true_steps": 116, "det_steps": 115, "gps_m": 93.26, "pso_m": 90.15, "acc_pct": 96.7},  # noqa: E501
    "A3": {"leg_cm": 94, "k": 0.477, "true_steps": 128, "det_steps": 123, "gps_m": 96.65, "pso_m": 91.07, "acc_pct": 94.2},  # noqa: E501
    "B1": {"leg_cm": 100, "k": 0.554, "true_steps": 108, "det_steps": 110, "gps_m": 92.71, "pso_m": 89.53, "acc_pct": 96.6},  # noqa: E501
    "B2": {"leg_cm": 100, "k": 0.494, "true_steps": 118, "det_steps": 116, "gps_m": 95.96, "pso_m": 91.84, "acc_pct": 95.7},  # noqa: E501
    "C": {"leg_cm": 108, "k": 0.522, "true_steps": 106, "det_steps": 107, "gps_m": 93.73, "pso_m": 96.13, "acc_pct": 97.5},  # noqa: E501
}
#: A1's phase-2 walks (Figs 5.14-5.15, L857-862, L873-878, L899): closure m and %, PSO, TAR and GPS distances.
PAPER_PHASE2_A1 = {
    "park": {"closure_m": 2.81, "closure_pct": 1.6, "pso_m": 180.52, "tar_m": 203.18, "gps_m": 277.41},
    "hall": {"closure_m": 5.79, "closure_pct": 1.9, "pso_m": 298.92, "tar_m": 336.10, "gps_m": 423.55},
}
#: Static compass RMS (deg) raw, after MA(nL=nR=2) and after SG(m=2, nL=nR=2) (L718).
PAPER_COMPASS_RMS = {"raw": 0.716, "ma": 0.563, "sg": 0.638}
#: The fixed k of eq. 2.5 the thesis compares with ("TAR", L899).
K_FIXED_PAPER = 0.5
#: Table 3-2 (L462-467): (m, nL, nR) -> printed Savitzky-Golay coefficients c_-nL .. c_nR.
TABLE_3_2 = {
    (2, 2, 2): (-0.086, 0.343, 0.486, 0.343, -0.086),
    (2, 4, 0): (0.886, -0.143, -0.886, 0.257, 0.886),
    (2, 5, 5): (-0.084, 0.021, 0.103, 0.161, 0.196, 0.207, 0.196, 0.161, 0.103, 0.021, -0.084),
    (4, 4, 4): (0.035, -0.128, 0.070, 0.315, 0.417, 0.315, 0.070, -0.128, 0.035),
    (4, 5, 5): (0.042, -0.105, -0.023, 0.140, 0.280, 0.333, 0.280, 0.140, -0.023, -0.105, 0.042),
}

# Fig 5.12 (A1 phase 1) and Fig 5.14 (A1 phase 2) as printed (L833-840, L857-862, L873-878).
_FIG_5_12 = {"iters": 9, "fitness": 0.093934, "k": 0.444448, "pso_m": 158.157835, "gps_m": 160.257388,
             "diff_m": 2.099552, "diff_rel": 0.013101}
_FIG_5_14 = {"park": {"pso_m": 180.518522, "pso_se_m": 2.807418, "tar_m": 203.182840, "tar_se_m": 3.106687,
                      "gps_m": 277.408257, "diff_m": 96.889735, "diff_rel": 0.604588},
             "hall": {"pso_m": 298.915925, "pso_se_m": 5.791956, "tar_m": 336.096833, "tar_se_m": 6.569617,
                      "gps_m": 423.554008, "diff_m": 124.638083, "diff_rel": 0.777737}}

_P = "pso"
_EXP = "pso_k_factor"
_NB = "10_pso_k_factor"
_COMPASS = decided(_NB, "MA vs Savitzky-Golay on a static compass log (sec. 5.1.3, Figs 5.3-5.5)")
_T52 = decided(_NB, "Table 5-2 beside the paper")
_PH2 = decided(_NB, "Phase 2: learned k vs k = 0.5 vs GPS (Figs 5.13-5.21)")
_METHOD = decided(_NB, "The method: PSO (Chao 2008) eq. (2.5), (3.5)-(3.6), (4.1)-(4.4)")
_PSO_IT = decided(_NB, "PSO iterations for A1 (Figs 5.11-5.12)")
_STUDY = decided("15_sweep_studies", "4 PSO: convergence vs swarm size and inertia schedule")
_COMPASS_ITEM = "Sec 5.1.3"

# Assumptions: the simulated walks' values the thesis does not fix (keywords of pso_k_factor.run), with the
# measured or published range each is swept over.
_A_ACC = Assumption(_EXP, "acc_noise_mps2", 0.05, 0.20, "HAAM-325B accelerometer noise: not in the thesis (ref. "
                    "[34]); 0.05-0.20 m/s^2 around the assumed 0.10 (the +-RMS band follows it)")
_A_AMP = Assumption(_EXP, "step_amp_cv", 0.16, 0.27, "per-step amplitude scatter beyond the pendulum's, from the "
                    "ILC 2020 site2/F4 walks' Amax-Amin CV, IQR 0.18-0.28 over 19 walks (pdr.k_walks.ilc_k_study), "
                    "less the pendulum's 0.085 in quadrature")
_A_STEP = Assumption(_EXP, "step_cv", 0.015, 0.05, "step length and duration CV of normal gait, 1.5-5 % "
                     "(Hausdorff 2005); the thesis says only 'steps as even as possible' (L771)")
_A_TAU = Assumption(_EXP, "gps_open_tau_s", 5.0, 300.0, "correlation time of the open-sky GPS error: not in the "
                    "text (L750-752 give only the bound); 5-300 s (assumption)", log=True)
_A_GPS95 = Assumption(_EXP, "gps_static_95_m", 0.75, 1.5, "the static GPS test: 'better than 1.5 m' (L750-752), "
                      "an upper bound; read as the 95 % radius, half of it to all of it")
_A_ROUTE = Assumption(_EXP, "route_scale", 0.95, 1.05, "true route length over the thesis's GPS distance: the walk's "
                      "length is known only from GPS (Table 5-2); +-5 % (assumption)")
_A_STEPS = (_A_ACC, _A_AMP, _A_STEP)
_A_K = (_A_ACC, _A_AMP, _A_STEP, _A_TAU, _A_GPS95, _A_ROUTE)
_A_GPS = (_A_TAU, _A_GPS95)


def _m(quantity: str, item: str | None = None):
    return M(_EXP, quantity, item=item, table="measures")


def _savgol(m: int, nl: int, nr: int) -> np.ndarray:
    """Savitzky-Golay weights c_-nL .. c_nR (scipy, applied as a dot product over f(t-nL) .. f(t+nR))."""
    from scipy.signal import savgol_coeffs

    return savgol_coeffs(nl + nr + 1, m, pos=nl, use="dot")


def _table_dev(keys) -> float:
    """Largest |printed - exact| Savitzky-Golay weight over the Table 3-2 rows ``keys``."""
    return max(float(np.max(np.abs(np.asarray(TABLE_3_2[k]) - _savgol(*k)))) for k in keys)


def _noise_gain(key) -> float:
    """Sum of squared weights of a Table 3-2 row: the variance a white noise keeps after the filter."""
    return float(np.sum(np.square(TABLE_3_2[key])))


def _w_printed(i: int, iters: int = 100, w_init: float = 1.0, w_final: float = 0.1) -> float:
    """Eq. 4.3 exactly as printed (L564): ``w_i = A / (iters + 1) + B`` (no ``i`` on the right)."""
    a = (w_init - w_final) * (iters + 1) / iters
    return a / (iters + 1) + (w_init - a)


def _eq33_lon_step_sign() -> float:
    """Sign of lambda_2 - lambda_1 from eq. 3.2-3.3 as printed for a 1 m step due east (theta = 90 deg) at
    Tunghai's latitude (24.18 deg N, east-positive longitude as GPS/NMEA give it); eq. 3.1 for the new
    latitude is not printed, so phi = phi_1 (a due-east step keeps it to first order)."""
    R = 6371000.0
    d = 1.0 / R
    phi1 = math.radians(24.18)
    th = math.radians(90.0)
    dlam = math.atan2(math.sin(th) * math.sin(d) * math.cos(phi1), math.cos(d) - math.sin(phi1) * math.sin(phi1))
    lam1 = math.radians(120.6)
    lam2 = lam1 - dlam  # eq. 3.3 without the wrap
    return math.copysign(1.0, lam2 - lam1)


def _closure_scaling_gap() -> float:
    """Largest gap, over A1's two phase-2 walks, between TAR/PSO closure and TAR/PSO path length (Fig 5.14)."""
    return max(abs(v["tar_se_m"] / v["pso_se_m"] - v["tar_m"] / v["pso_m"]) for v in _FIG_5_14.values())


_T = PAPER_TABLE_5_2
_K = [v["k"] for v in _T.values()]
_STEP_ERR_PCT = 100 * float(np.mean([abs(v["det_steps"] - v["true_steps"]) / v["true_steps"] for v in _T.values()]))
_ACC_GAP_PCT = 100 - float(np.mean([v["acc_pct"] for v in _T.values()]))

CLAIMS = (
    Claim(
        "pso-ma-beats-sg", _P, 718, "ordering",
        "On the static compass log, the moving average MA(nL=nR=2) lowers the RMS more than the Savitzky-Golay "
        "filter SG(m=2, nL=nR=2), so MA is chosen.",
        paper_value=PAPER_COMPASS_RMS["ma"] - PAPER_COMPASS_RMS["sg"], paper_text="RMS 0.716 -> MA 0.563; SG 0.638",
        statistic=diff(M(_EXP, "static compass RMS, MA nL=nR=2", item=_COMPASS_ITEM),
                       M(_EXP, "static compass RMS, SG m=2 nL=nR=2", item=_COMPASS_ITEM), "deg"),
        expect="<0", decided_in=_COMPASS,
        note="Simulated static compass: AR(1) noise (lag-1 correlation 0.6, assumed) plus rare spikes, scaled to the "
             "raw RMS 0.716 deg (an input); the ordering depends on that spectrum, not on the scale."),
    Claim(
        "pso-ma-ratio", _P, 718, "ratio",
        "MA(nL=nR=2) lowers the static compass RMS from 0.716 to 0.563 deg (to 0.79 of raw).",
        paper_value=PAPER_COMPASS_RMS["ma"] / PAPER_COMPASS_RMS["raw"], paper_text="0.716 -> 0.563",
        statistic=ratio(M(_EXP, "static compass RMS, MA nL=nR=2", item=_COMPASS_ITEM),
                        M(_EXP, "static compass RMS, raw", item=_COMPASS_ITEM)),
        decided_in=_COMPASS, note="the raw RMS is set by input; the ratio is a result of the assumed noise spectrum"),
    Claim(
        "pso-sg-ratio", _P, 718, "ratio",
        "SG(m=2, nL=nR=2) lowers the static compass RMS from 0.716 to 0.638 deg (to 0.89 of raw).",
        paper_value=PAPER_COMPASS_RMS["sg"] / PAPER_COMPASS_RMS["raw"], paper_text="0.716; 0.638",
        statistic=ratio(M(_EXP, "static compass RMS, SG m=2 nL=nR=2", item=_COMPASS_ITEM),
                        M(_EXP, "static compass RMS, raw", item=_COMPASS_ITEM)),
        decided_in=_COMPASS, note="the raw RMS is set by input; the ratio is a result of the assumed noise spectrum"),
    Claim(
        "pso-sg-table-symmetric", _P, (463, 465, 466, 467), "consistency",
        "Table 3-2's symmetric rows (m=2 nL=nR=2, m=2 nL=nR=5, m=4 nL=nR=4, m=4 nL=nR=5) are the Savitzky-Golay "
        "weights (Numerical Recipes, ref. 26).",
        paper_value=None, paper_text="-0.086 0.343 0.486; -0.084 0.021 0.103 0.161 0.196 0.207; "
                                     "0.035 -0.128 0.070 0.315 0.417; 0.042 -0.105 -0.023 0.140 0.280 0.333",
        statistic=constant(lambda: _table_dev([(2, 2, 2), (2, 5, 5), (4, 4, 4), (4, 5, 5)]),
                           "max |printed - exact SG weight| over the symmetric rows"),
        expect="<0.002", decided_in=_METHOD,
        note="exact weights from scipy.signal.savgol_coeffs; 3-decimal rounding allows 0.0005"),
    Claim(
        "pso-sg-table-row-4-0", _P, 464, "consistency",
        "Table 3-2's one-sided row (m=2, nL=4, nR=0) is the Savitzky-Golay weights.",
        paper_value=None, paper_text="2 4 0 0.886 -0.143 -0.886 0.257 0.886",
        statistic=constant(lambda: _table_dev([(2, 4, 0)]), "max |printed - exact SG weight|, row m=2 nL=4 nR=0"),
        expect="<0.002", decided_in=_METHOD,
        note="exact weights 0.086, -0.143, -0.086, 0.257, 0.886: the printed c_-4 = 0.886 and c_-2 = -0.886 should "
             "read 0.086 and -0.086 (the sum stays 1, so a sum check does not see it); deviation 0.8"),
    Claim(
        "pso-sg-larger-m-smoother", _P, (465, 467, 478), "consistency",
        "Larger m, nL, nR give a smoother signal (L478); Table 3-2's own rows say otherwise for m: at nL=nR=5, "
        "m=4 passes more white noise than m=2.",
        paper_value=None, paper_text="2 5 5; 4 5 5",
        statistic=constant(lambda: _noise_gain((4, 5, 5)) / _noise_gain((2, 5, 5)),
                           "sum c^2 (m=4, nL=nR=5) / sum c^2 (m=2, nL=nR=5)", "ratio"),
        expect="<1", decided_in=_METHOD,
        note="sum c^2 = 0.334 (m=4) vs 0.208 (m=2): ratio 1.61 > 1, a higher degree smooths less; the window part "
             "holds (m=2: nL=nR=2 keeps 0.486, nL=nR=5 keeps 0.208)"),
    Claim(
        "pso-step-detection", _P, (799, 930, 931, 932, 933, 934, 935), "value",
        "The slope sign-change detector with the +-RMS band (Fig 3.9) counts the steps within a few: A1 216 of 217, "
        "all six walkers within 1.6 % on average.",
        paper_value=_STEP_ERR_PCT, paper_text="217 216; 217(216) 116(115) 128(123) 108(110) 118(116) 106(107)",
        statistic=value(_m("mean |detected - true| / true steps"), "%"), assumptions=_A_STEPS, decided_in=_T52,
        note="mean over walkers of |detected - true| / true; the true counts are the walk design (input), the "
             "detected ones a result"),
    Claim(
        "pso-k-mean", _P, (930, 931, 932, 933, 934, 935), "value",
        "The Weinberg k learned by PSO for the six walkers averages 0.497 (Table 5-2).",
        paper_value=float(np.mean(_K)), paper_text="0.444 0.489 0.477 0.554 0.494 0.522",
        statistic=value(_m("mean k (PSO)")), assumptions=_A_K, decided_in=_T52,
        note="k emerges from the simulated gait (leg length, step length, cadence), it is not an input"),
    Claim(
        "pso-k-range", _P, (930, 931, 932, 933, 934, 935), "value",
        "The learned k spans 0.444 to 0.554 across the six walkers (a range of 0.110).",
        paper_value=max(_K) - min(_K), paper_text="0.444 0.554",
        statistic=stat([_m("max k (PSO)"), _m("min k (PSO)")], lambda a, b: a - b, "max k - min k"),
        assumptions=_A_K, decided_in=_T52),
    Claim(
        "pso-k-same-leg-differs", _P, (930, 931, 932, 937), "value",
        "Walkers with the same leg length have different k (A1, A2, A3 at 94 cm: 0.444, 0.489, 0.477), contrary to "
        "Lei Fang's one K per leg length.",
        paper_value=0.489 - 0.444, paper_text="A1(94) 0.444; A2(94) 0.489; A3(94) 0.477",
        statistic=value(_m("k range among the 94 cm walkers")), assumptions=_A_K, decided_in=_T52,
        note="range of k among the three 94 cm walkers; the simulated walkers share the leg length and differ in "
             "speed and heel-strike harmonic (literature spreads), not by a k given to them"),
    Claim(
        "pso-accuracy", _P, (930, 931, 932, 933, 934, 935, 937), "value",
        "The learned k reproduces the GPS distance of the learning walk to 94.2-98.7 % (mean 96.6 %; the statistic "
        "is the mean shortfall, 100 - accuracy).",
        paper_value=_ACC_GAP_PCT, paper_text="98.7 96.7 94.2 96.6 95.7 97.5",
        statistic=stat([_m("mean accuracy vs GPS")], lambda a: 100.0 - a, "100 - mean accuracy vs GPS", "%"),
        assumptions=_A_K, decided_in=_T52,
        note="accuracy = 1 - |GPS - PSO| / GPS on the learning walk itself (Table 5-2 arithmetic)"),
    Claim(
        "pso-learned-k-beats-fixed", _P, (858, 860, 874, 876, 899), "improvement",
        "On A1's phase-2 loops the learned k closes the loop better than k = 0.5: start-end 2.807 vs 3.107 m (park) "
        "and 5.792 vs 6.570 m (hall).",
        paper_value=gmean([_FIG_5_14[p]["pso_se_m"] / _FIG_5_14[p]["tar_se_m"] for p in ("park", "hall")]),
        paper_text="2.807418 3.106687; 5.791956 6.569617",
        statistic=stat([_m("closure, PSO k", "A1 park"), _m("closure, k = 0.5", "A1 park"),
                        _m("closure, PSO k", "A1 hall"), _m("closure, k = 0.5", "A1 hall")],
                       lambda a, b, c, d: gmean([a / b, c / d]), "geometric mean of closure(PSO k) / closure(k=0.5)",
                       "ratio"),
        expect="<1", assumptions=_A_K, decided_in=_PH2,
        note="confounded: both tracks share steps and headings and differ only in k, so the closure scales with k "
             "and any k < 0.5 'wins'; the ratio is k_PSO / 0.5"),
    Claim(
        "pso-closure-scaling", _P, (857, 858, 859, 860, 873, 874, 875, 876), "consistency",
        "The PSO and TAR tracks differ only in k (L899), so every distance of one is the other's times 0.5 / k; "
        "Fig 5.14's path lengths scale so (1.1255, 1.1244) but its start-end distances do not (1.1066, 1.1343).",
        paper_value=None,
        paper_text="180.518522 2.807418 203.182840 3.106687; 298.915925 5.791956 336.096833 6.569617",
        statistic=constant(_closure_scaling_gap, "max |TAR/PSO closure - TAR/PSO path length|", "ratio"),
        expect="<0.005", decided_in=_PH2,
        note="a gap of 0.019 (park) and 0.010 (hall); printed to 1e-6 m, so not rounding of the printed values "
             "(coarse coordinate storage could explain it; the thesis does not say)"),
    Claim(
        "pso-closure-share", _P, 899, "value",
        "The learned-k track nearly returns to its start: closure 2.8 m = 1.6 % (park) and 5.79 m = 1.9 % (hall) "
        "of the path.",
        paper_value=(1.6 + 1.9) / 2, paper_text="2.8 1.6% 5.79 1.9%",
        statistic=mean_of([_m("closure / PSO path length", "A1 park"), _m("closure / PSO path length", "A1 hall")],
                          "mean closure / PSO path length", "%"),
        assumptions=_A_STEPS, decided_in=_PH2),
    Claim(
        "pso-gps-slow", _P, (857, 861, 873, 877, 899), "ordering",
        "At walking speed GPS goes badly astray: its path is far longer than the dead-reckoned one (277.4 vs "
        "180.5 m, 423.6 vs 298.9 m).",
        paper_value=float(np.mean([_FIG_5_14[p]["gps_m"] / _FIG_5_14[p]["pso_m"] for p in ("park", "hall")])),
        paper_text="180.518522 277.408257; 298.915925 423.554008",
        statistic=mean_of([_m("GPS / PSO path length", "A1 park"), _m("GPS / PSO path length", "A1 hall")],
                          "mean GPS / PSO path length", "ratio"),
        expect=">1", assumptions=_A_GPS, decided_in=_PH2,
        note="simulated GPS: open-sky error sd 0.61 m per axis (the thesis's 1.5 m, L747-749) and shaded "
             "segments (sd 4 m, 30 % missing: assumed)"),
    Claim(
        "pso-best", _P, 937, "improvement",
        "The thesis's method (k learned per walker) gives the best result, better than a fixed k (0.5, eq. 2.5).",
        paper_value=None, paper_text="",
        statistic=ratio(_m("phase 2 mean |distance error| vs true route, PSO k"),
                        _m("phase 2 mean |distance error| vs true route, k = 0.5")),
        expect="<1", assumptions=_A_K, decided_in=_PH2,
        note="scored on the true route length of every simulated phase-2 walk (the thesis has only GPS there)"),
    Claim(
        "pso-converges", _P, (820, 833), "value",
        "The PSO settles by iteration 5 and stops at iteration 9 with the best k (A1, Fig 5.11-5.12).",
        paper_value=9.0, paper_text="5 9; Iters=9",
        statistic=value(M("study_pso", "iterations to minFitness", table="sweep_pso"), "iterations"),
        decided_in=_STUDY,
        note="one run in the thesis; reproduced: mean over runs and walkers with the thesis's settings. In this 1-D "
             "problem the stop rule (minFitness 0.1) ends the search as soon as one particle is close enough"),
    Claim(
        "pso-fitness-is-per-step", _P, (834, 840), "consistency",
        "Eq. 4.4 read on the walk's total distance makes the fitness the distance difference; Fig 5.12 prints "
        "Fitness 0.093934 beside a difference of 2.099552 m.",
        paper_value=1.0, paper_text="Fitness=0.093934; 2.099552",
        statistic=constant(lambda: _FIG_5_12["diff_m"] / _FIG_5_12["fitness"], "Diff(GPS) / Fitness", "ratio"),
        decided_in=_METHOD,
        note="22.4, not 1: the printed fitness is not eq. 4.4 on walk totals (the toolkit reads it per step)"),
    Claim(
        "pso-table-vs-fig-5-12", _P, (837, 845, 930), "consistency",
        "Table 5-2's A1 PSO distance (158.28 m) is Fig 5.12's and the text's (158.157835, 'about 158.16 m').",
        paper_value=None, paper_text="158.157835; 158.16; 158.28",
        statistic=constant(lambda: abs(_T["A1"]["pso_m"] - _FIG_5_12["pso_m"]), "|Table 5-2 - Fig 5.12| A1 PSO "
                           "distance", "m"),
        expect="<0.01", decided_in=_PSO_IT,
        note="0.12 m apart; with 158.28 the accuracy would be 98.77 %, the text says 98.6 %, Fig 5.12 gives 98.69 %"),
    Claim(
        "pso-fig-5-14-denominator", _P, (839, 861, 862), "consistency",
        "Fig 5.14's relative difference is the PSO distance error over the walk's GPS distance (277.408257 m).",
        paper_value=_FIG_5_14["park"]["gps_m"], paper_text="96.889735(0.604588); 277.408257; 160.257388",
        statistic=constant(lambda: _FIG_5_14["park"]["diff_m"] / _FIG_5_14["park"]["diff_rel"],
                           "Diff / relative Diff (the denominator used)", "m"),
        decided_in=_PH2,
        note="96.889735 / 0.604588 = 160.26 m, the phase-1 GPS distance of Fig 5.12; the hall walk too "
             "(124.638083 / 0.777737 = 160.26)"),
    Claim(
        "pso-eq-4-3-inertia", _P, (564, 568, 809), "consistency",
        "The inertia weight of eq. 4.3 starts at w_init = 1.0 and falls with the iterations (L568).",
        paper_value=1.0, paper_text="1.0~0.1",
        statistic=constant(lambda: _w_printed(0), "w at iteration 0 by eq. 4.3 as printed (iters = 100)"),
        decided_in=_METHOD,
        note="as printed, w_i = A/(iters+1) + B has no i: it is w_final = 0.1 at every iteration; with i in place of "
             "iters it runs 1.0 -> 0.1 as the text says"),
    Claim(
        "pso-eq-3-3-sign", _P, (428, 430), "consistency",
        "Eq. 3.2-3.3 move the longitude the way the walker heads (a step due east raises the east longitude).",
        paper_value=1.0, paper_text="3.2; 3.3",
        statistic=constant(_eq33_lon_step_sign, "sign of lambda2 - lambda1 for a step due east, eq. 3.3 as printed"),
        decided_in=_METHOD,
        note="eq. 3.3 (lambda_2 = lambda_1 - dlambda, from Williams' formulary, ref. 25) assumes west-positive "
             "longitudes; with GPS's east-positive longitude it dead-reckons an eastward walk westward. Eq. 3.1 "
             "(latitude) is not printed and eq. 3.3's mod has one argument"),
    Claim(
        "pso-great-circle-dr", _P, (426, 428, 430), "value",
        "Great-circle dead reckoning from the first fix with step length and heading (eq. 3.1-3.3) positions the "
        "walk: it agrees with a flat-earth sum of the same steps within 1 cm over A1's loops.",
        paper_value=None, paper_text="",
        statistic=value(_m("great-circle vs flat dead reckoning, max difference", "A1 phase 2"), "m"),
        expect="<0.01", decided_in=_PH2,
        note="the toolkit's ilocalg.gnss.dead_reckon_latlon (east-positive longitudes, eq. 3.1 restored), not the "
             "printed eq. 3.3 (claim pso-eq-3-3-sign)"),
    Claim(
        "pso-faster-than-nn", _P, (31, 33, 53), "ordering",
        "PSO computes and converges fast and stably, unlike a neural network, and suits real-time navigation.",
        untestable="no neural-network step-length model (Cho et al.) is implemented and the thesis gives no timing "
                   "of either on its platform",
        decided_in=_METHOD),
)
