"""The claims of the i-Loc thesis (Chiu 2013), as data (:mod:`ilocalg.papers.claims`).

One :class:`~ilocalg.papers.claims.Claim` per statement of substance, read from the whole text
(/work/shared/papers/000_42091e6b84aac0f5.txt; ``line`` is the line of that file): ch. 3 Wi-Fi
(Simplified-RADAR, Simplified-Horus), ch. 4 PTS (SAM, SLM, WDM), ch. 5 the Kalman filter, ch. 6 photo
positioning (ST against VA). Where the thesis contradicts itself, a ``consistency`` claim recomputes
the contradiction from the thesis's own printed numbers (:data:`TABLE2_CORR`, :data:`TABLE4_VAR`,
:data:`TABLE5_VAR_M2`, ...: the printed tables, used only by those checks).

Ordering, improvement and trend claims are judged on their direction; value claims on agreement with
the printed figure. Every reproduced scalar is named with :func:`~ilocalg.papers.claims.M`; the ranges of
the values the text does not fix are :class:`~ilocalg.papers.claims.Assumption` s of the experiment's
``run()`` keywords.

References
----------
Chiu, P.-J. (2013). Implement an Integrated Indoor Positioning System (i-Loc). M.S. thesis,
National Chiao Tung University.
"""

from __future__ import annotations

import math

import numpy as np

from ilocalg.papers._claim_helpers import decided
from ilocalg.papers.claims import Assumption, Claim, M, Stat, constant, diff, ratio, spearman, value

__all__ = ["CLAIMS", "KEY", "FILE", "PUBLISHED", "TABLE2_CORR", "TABLE4_VAR", "TABLE5_VAR_M2",
           "table5_error_quantile_m"]

KEY = "iloc"
#: The text copy the line numbers refer to (in the shared papers folder).
FILE = "000_42091e6b84aac0f5.txt"


# The thesis's printed tables, as printed (used only by the consistency claims below).
#: Table 2 (L440-448): correlation of each step feature with the step length.
TABLE2_CORR = {"A1": 0.53, "A2": 0.5, "A": 0.55, "T1": 0.25, "T2": 0.06, "T": 0.32, "X1": 0.37, "I": 0.61}
#: Table 4 (L604-605): sigma_SL^2 per fixed step length 40-80 cm (no unit printed).
TABLE4_VAR = (0.054, 0.054, 0.036, 0.053, 0.065)
#: Table 5 (L609-616): sigma_RF^2 at the 28 test points, m^2 (the Wi-Fi fix error variance, R = sigma^2 I).
TABLE5_VAR_M2 = (15.072, 8.184, 0.523, 5.995, 2.853, 0.899, 4.305,
                 0.171, 11.219, 1.616, 1.891, 7.055, 1.960, 3.365,
                 6.400, 8.238, 5.533, 2.054, 1.929, 2.883, 1.985,
                 3.250, 1.789, 2.255, 3.453, 2.985, 1.145, 2.596)


#: The thesis's published values that the experiments show beside theirs (``paper_ref``), by experiment:
#: reference only, never used to compute. Lines of the text copy in the comments.
PUBLISHED = {
    # ch. 3: L297 (RADAR median 4.5 m, 80 % within 14 m, k = 5 best), L333 (Horus median 4.5 m, 80 % within 9 m)
    "wifi_iloc": {"radar_median_m": 4.5, "radar_p80_m": 14.0, "radar_best_k": 5, "horus_median_m": 4.5,
                  "horus_p80_m": 9.0},
    # ch. 4.1: L430, SAM step-count error on 8 testers x 100 steps (a fraction)
    "pdr_step_features": {"sam_count_error": 0.0413},
    # ch. 4.2: Table 2 (L440-448), Table 3 (L466-469, cm), RMSE (L462, cm), Fig 14 mean error and Fig 15
    # 20 m accuracy (L478, fractions)
    "pdr_step_length": {"corr": dict(TABLE2_CORR), "p_linear_cm": (50.66, -0.42, 0.75),
                        "p_quad_cm": (54.49, -2.90, 1.50, -0.02, 0.15, -0.01),
                        "rmse_cm": {"linear": 12.32, "quadratic": 12.15}, "fixed_error": 0.1843,
                        "free20_accuracy": 0.9641},
    # ch. 4.3-4.4: L508 (WDM mean heading error, deg), L517 (PTS mean error, m)
    "pdr_heading_trajectory": {"heading_error_deg": 13.87, "pts_error_m": 5.2},
    # ch. 5: L618 ("5.15 m -> 2.82 m"; 5.15 m read as the PTS mean, claim iloc-kf-start-is-pts)
    "fusion_iloc_kf": {"pts_mean_m": 5.15, "kf_mean_m": 2.82},
    # ch. 6.3: L702 (Fig 30: ST and VABIG with 2 and 7 PoIs; overall means of ST, VAGIG, VABIG), cm
    "photo_positioning": {"fig30_ST_k2_cm": 112.0, "fig30_ST_k7_cm": 48.0, "fig30_VABIG_k2_cm": 870.0,
                          "fig30_VABIG_k7_cm": 50.0, "mean_ST_cm": 74.3, "mean_VAGIG_cm": 88.9,
                          "mean_VABIG_cm": 246.0},
}


def table5_error_quantile_m(q: float, var_m2=TABLE5_VAR_M2) -> float:
    """The ``q`` quantile of the Wi-Fi fix error that Table 5 implies.

    Each test point's fix error is zero-mean Gaussian with variance ``var_m2`` per axis (eq. 23, R = sigma^2 I),
    so its distance error is Rayleigh; the 28 points weigh equally. Solves
    ``mean_k (1 - exp(-r^2 / (2 sigma_k^2))) = q`` for ``r`` by bisection.
    """
    if not 0.0 < q < 1.0:
        raise ValueError(f"q must be in (0, 1), got {q!r}")
    v = np.asarray(var_m2, dtype=np.float64)
    if v.ndim != 1 or v.size == 0 or (v <= 0).any():
        raise ValueError("var_m2 must be a non-empty 1-D sequence of positive variances")
    lo, hi = 0.0, 10.0 * math.sqrt(float(v.max()))
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if float(np.mean(1.0 - np.exp(-mid ** 2 / (2.0 * v)))) < q:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _x1_rank() -> float:
    """X1's rank (1 = most correlated) among Table 2's eight features."""
    return float(1 + sum(c > TABLE2_CORR["X1"] for f, c in TABLE2_CORR.items() if f != "X1"))


def _ab_margin(*c: float) -> float:
    """min(|corr A|, |corr X1|) - max(|corr| of the six other features); refs in _CORR_FEATURES order."""
    a = dict(zip(_CORR_FEATURES, (abs(x) for x in c), strict=True))
    return min(a["A"], a["X1"]) - max(v for f, v in a.items() if f not in ("A", "X1"))


_CORR_FEATURES = ("A1", "A2", "A", "T1", "T2", "T", "X1", "I")

# Experiments (ilocalg.experiments.<name>).
_W, _SW, _F, _SL, _H, _KF, _PH = ("wifi_iloc", "study_wifi", "pdr_step_features", "pdr_step_length",
                                  "pdr_heading_trajectory", "fusion_iloc_kf", "photo_positioning")

# Assumptions: the values the text does not fix, with their measured or published ranges.
_A_SURVEY = (
    Assumption(_W, "scans_per_point", 30, 300, "thesis L295: '300 scans, varying' per point; the lower end is an "
               "assumption (a tenth of the stated count)", integer=True),
    Assumption(_W, "scans_per_test_point", 1, 20, "silent in the thesis; 1 scan to the toolkit's 20 (assumption)",
               integer=True),
)
_A_RADIO = (
    Assumption(_SW, "drift_sd_db", 3.0, 5.0, "day-to-day change of an AP's mean RSSI 3-5 dB (Kaemarungsi & "
               "Krishnamurthy 2004; Chapre et al. 2013)"),
    Assumption(_SW, "body_loss_db", 0.0, 5.0, "user's body between phone and AP: up to about 5 dB (Bahl & "
               "Padmanabhan 2000, RADAR)"),
    Assumption(_SW, "scans_per_point", 30, 300, "thesis L295: '300 scans, varying' per point; lower end assumed",
               integer=True),
)
_A_WALKERS = (Assumption(_F, "n_train", 3, 8, "thesis L399: 'several walkers of different builds' (count not "
                         "given); L430: 8 testers", integer=True),)
_A_SLM = (Assumption(_SL, "n_train", 3, 8, "thesis L399, L478: several walkers / 8 testers (count of the "
                     "training walkers not given)", integer=True),)
_A_PTS = (Assumption(_H, "n_train", 3, 8, "thesis L399: several training walkers (count not given)", integer=True),)
_A_KF = (
    Assumption(_KF, "scan_latency_s", 1.0, 3.0, "smartphone Wi-Fi scan durations 1-3 s (the readings' 'phones "
               "take 1-3 s per scan'); the thesis gives none"),
    Assumption(_KF, "n_cal", 5, 20, "standing scans per test point behind Table 5's variances: not given "
               "(assumption)", integer=True),
)
_A_PHOTO = (
    Assumption(_PH, "drag_sd_px", 2.0, 48.0, "finger placement 0.17 mm (Berard & Rochet-Capellan 2012) to 4 mm "
               "(Holz & Baudisch 2011) at 12.05 px/mm (ilocalg.sim.photo_poi)"),
    Assumption(_PH, "tilt_sd_deg", 0.5, 3.4, "accelerometer zero-g offset 10-60 mg (Bosch BMA2xx datasheets): "
               "atan(0.01-0.06)"),
    Assumption(_PH, "yaw_sd_deg", 1.0, 9.0, "smartphone magnetic azimuth 1-3 deg after calibration, 2-3 times "
               "that without (Lviv Polytechnic field study; ilocalg.sim.photo_poi)"),
)
_A_VAGIG = _A_PHOTO + (Assumption(_PH, "good_guess_sd_m", 0.5, 4.0, "the rough position the user gives "
                                  "(L652): not quantified; 0.5-4 m per axis, GOOD_GUESS_SD_M (assumption)"),)

_NB01, _NB03, _NB04, _NB05, _NB07, _NB11 = ("01_wifi_radar_horus_knn", "03_pdr_step_features",
                                            "04_pdr_step_length", "05_pdr_heading_trajectory",
                                            "07_fusion_iloc_kf", "11_photo_positioning")

_RADAR_MED = M(_W, "Simplified-RADAR median error (k=5)")
_HORUS_MED = M(_W, "Simplified-Horus median error (k=5)")
_KF_MEAN = "mean error at the test points"
_PK = "mean error by PoI count"

# Notebook sections that decide the claims.
_S_FLOOR = decided(_NB01, "The simulated floor (Fig 2)")
_S_FIG3 = decided(_NB01, "Fig 3: how many strongest APs (k) should Simplified-RADAR compare?")
_S_CDF = decided(_NB01, "Figs 3 and 5: error CDFs of the three methods")
_S_TIME = decided(_NB01, "Time per query (the thesis: Horus is cheaper than RADAR)")
_S_STUDY = decided("15_sweep_studies", "1 Wi-Fi: error vs k, training-point spacing and scans per point")
_S_SAM_READ = decided(_NB03, "Readings: each modelling choice against the thesis's text")
_S_SAM_END = decided(_NB03, "Conclusion")
_S_SLM = decided(_NB04, "The method: i-Loc (Chiu 2013) eq. (16)-(17), the step length model (SLM)")
_S_FIG14 = decided(_NB04, "Fixed-length error boxes (Fig 14) and 20 m free walks (Fig 15)")
_S_TABLE4 = decided(_NB04, "Table 4's unit: the fixed-length errors as relative and as m^2 variances")
_S_FIG16 = decided(_NB05, "Per-step heading (Fig 16)")
_S_FIG17 = decided(_NB05, "Trajectory along the test route and error CDF (Figs 17-18)")
_S_KF = decided(_NB07, "Mean errors of every variant")
_S_TABLE5 = decided(_NB07, "Fix variances: calibrated on the simulated floor beside the thesis' Table 5")
_S_PHOTO = decided(_NB11, "Paper vs reproduced")
_S_FIG30 = decided(_NB11, "Fig 30: error against the number of PoIs (stars: the thesis's values)")
_S_FIG29 = decided(_NB11, "Fig 29: mean error per shooting point")
_S_FIG31 = decided(_NB11, "Figs 31-32: error per PoI combination, near-collinear combinations")

CLAIMS = (
    # ---- ch. 3 Wi-Fi ------------------------------------------------------------------------------------
    Claim("iloc-floor-area", KEY, 295, "consistency",
          "The test floor is 75.46 m by 50.26 m, 3292.62 m^2 in all.",
          paper_value=3292.62, paper_text="長 75.46 公尺、寬 50.26 公尺，總面積是 3292.62 平方公尺",
          statistic=constant(lambda: 75.46 * 50.26, "75.46 m x 50.26 m", "m^2"),
          decided_in=_S_FLOOR,
          note="75.46 x 50.26 = 3792.62 m^2, not the printed 3292.62 m^2: one digit (7 -> 2) differs; the "
               "printed sides are taken (ilocalg.sim.iloc_floor FLOOR_W_M, FLOOR_H_M)."),
    Claim("iloc-radar-best-k", KEY, 297, "value",
          "Simplified-RADAR is most accurate when it compares the k = 5 strongest APs (Fig 3).",
          paper_value=5, paper_text="k 為 5 的準確度較高",
          statistic=value(M(_W, "best AP count k (lowest median)"), "APs"),
          assumptions=_A_SURVEY, decided_in=_S_FIG3,
          note="k with the lowest median error over k = 1..10; Fig 3 itself is missing from the text."),
    Claim("iloc-radar-median", KEY, 297, "value",
          "Simplified-RADAR's median error is about 4.5 m (k = 5), close to the original RADAR's 3 m.",
          paper_value=4.5, paper_text="中位位置誤差值大約為 4.5 公尺",
          statistic=value(_RADAR_MED, "m"), assumptions=_A_SURVEY,
          decided_in=_S_CDF,
          note="simulated floor (the thesis's radio map is not published); the comparison with RADAR's own 3 m "
               "cannot be tested (RADAR's building)."),
    Claim("iloc-radar-p80", KEY, 297, "value",
          "80 % of Simplified-RADAR's errors are within 14 m.",
          paper_value=14.0, paper_text="80% 以下誤差值在 14 公尺內",
          statistic=value(M(_W, "Simplified-RADAR 80th-percentile error (k=5)"), "m"), assumptions=_A_SURVEY,
          decided_in=_S_CDF),
    Claim("iloc-horus-median", KEY, 333, "value",
          "Simplified-Horus's median error is about 4.5 m.",
          paper_value=4.5, paper_text="中位位置誤差值大約為 4.5 公尺",
          statistic=value(_HORUS_MED, "m"), assumptions=_A_SURVEY,
          decided_in=_S_CDF),
    Claim("iloc-horus-p80", KEY, 333, "value",
          "80 % of Simplified-Horus's errors are within 9 m.",
          paper_value=9.0, paper_text="80% 以下誤差值在 9 公尺內",
          statistic=value(M(_W, "Simplified-Horus 80th-percentile error (k=5)"), "m"), assumptions=_A_SURVEY,
          decided_in=_S_CDF),
    Claim("iloc-horus-beats-radar", KEY, (297, 333, 335), "ordering",
          "Simplified-Horus is more accurate than Simplified-RADAR (80 % within 9 m against 14 m; equal medians).",
          paper_value=9.0 - 14.0,
          paper_text="80% 以下誤差值在 14 公尺內; 80% 以下誤差值在 9 公尺內; 準度高於 Simplified-RADAR",
          statistic=diff(M(_SW, "80th-percentile error", item="method=Simplified-Horus"),
                         M(_SW, "80th-percentile error", item="method=Simplified-RADAR"), "m"),
          expect="<0", assumptions=_A_RADIO, decided_in=_S_CDF,
          note="judged on the 80th percentile, where the thesis's two methods differ (their medians are both "
               "4.5 m); study_wifi's default run is notebook 01's floor, with the radio parameters swept."),
    Claim("iloc-horus-cheaper", KEY, 335, "ordering",
          "Simplified-Horus costs less time per query than Simplified-RADAR.",
          paper_text="時間複雜度也低於 Simplified-RADAR",
          statistic=ratio(M(_W, "time per query", item="Simplified-Horus"),
                          M(_W, "time per query", item="Simplified-RADAR")),
          expect="<1", assumptions=_A_SURVEY[:1],
          decided_in=_S_TIME,
          note="measured wall-clock time per single query on the machine that runs the sweep (a ratio of two "
               "timings in one process, so load affects both). Both estimators prepare their reference data at "
               "fit, so a query times the search only (restacking RADAR's 18 900 reference scans per query, as the "
               "toolkit did before, put the ratio at 0.03-0.04 instead of 0.15-0.28)."),
    Claim("iloc-horus-vs-original", KEY, 333, "value",
          "Simplified-Horus (4.5 m) falls short of the original Horus's 1.38 m median because it has fewer and "
          "sparser training points.",
          paper_value=1.38, paper_text="Horus 本身中位誤差值 1.38 公尺",
          untestable="the 1.38 m is Horus's own testbed and data (Youssef & Agrawala 2005), not available; the "
                     "effect of a sparser grid is swept in study_wifi (spacing_m, notebook 15), which the claims "
                     "ledger cannot read (it reads default-parameter rows only).",
          decided_in=_S_STUDY),
    # ---- ch. 4 PTS: SAM ---------------------------------------------------------------------------------
    Claim("iloc-sam-window-vs-table1", KEY, (357, 425, 426), "consistency",
          "SAM finds each valley within W_wave / 2 = 0.25 s of the peak (W_wave = 0.5 s), and Table 1's step "
          "times T1, T2 (peak to valley) and T fit those windows.",
          paper_text="W_{wave} 設為 0.5 秒; T_2(s)	0.10	0.4; T(s)	0.36	0.62",
          statistic=constant(lambda: max(0.4 / (0.5 / 2), 0.62 / 0.5), "largest Table 1 time / its window"),
          expect="<1", decided_in=_S_SAM_READ,
          note="T2's 95 % point 0.40 s is 1.6 x W_wave / 2 = 0.25 s (T1's 0.35 s is 1.4 x), and T's 0.62 s is "
               "1.24 x W_wave = 0.5 s: the printed windows cannot produce Table 1 (the toolkit searches 0.5 s "
               "either side)."),
    Claim("iloc-sam-count", KEY, 430, "value",
          "SAM miscounts 4.13 % of the steps of 8 testers walking 100 steps each (Fig 12).",
          paper_value=4.13, paper_text="每名測試者分別行走一百步，數據結果如圖十二，此模組誤差值為 4.13%",
          statistic=value(M(_F, "SAM step-count error, 5/95 % ranges", item="new walkers"), "%"),
          assumptions=_A_WALKERS, decided_in=_S_SAM_END,
          note="new walkers (the text does not say whether the testers trained the ranges; the training walkers' "
               "row is in the same measures table)."),
    Claim("iloc-sam-count-800", KEY, 430, "consistency",
          "The 4.13 % SAM error is a count over 8 x 100 steps.",
          paper_value=4.13, paper_text="八名測試者; 行走一百步; 誤差值為 4.13%",
          statistic=constant(lambda: 100 * round(8 * 100 * 0.0413) / 800, "nearest whole count of 800 steps, %",
                             "%"),
          decided_in=_S_SAM_END,
          note="4.13 % of 800 steps = 33.04; 33 / 800 = 4.125 %, which prints as 4.13 %: consistent."),
    # ---- ch. 4 PTS: SLM ---------------------------------------------------------------------------------
    Claim("iloc-slm-a-x1-most-correlated", KEY, 452, "ordering",
          "A and X1 are the step features most correlated with the step length, so the SLM regresses on them.",
          paper_text="A 和 X_1 與步距長度的相關性最大",
          statistic=Stat(tuple(M(_SL, f"corr({f}, step length)") for f in _CORR_FEATURES), _ab_margin,
                         "min(|r_A|, |r_X1|) - max(|r| of the other six)"),
          expect=">0", assumptions=_A_SLM,
          decided_in=_S_SLM,
          note="absolute correlations (the simulated T features correlate negatively)."),
    Claim("iloc-slm-table2-vs-text", KEY, (441, 447, 448, 452), "consistency",
          "Table 2 ranks A and X1 as the two features most correlated with the step length, as the text says.",
          paper_text="A_1	0.53; X_1	0.37; I	0.61; A 和 X_1 與步距長度的相關性最大",
          statistic=constant(_x1_rank, "X1's rank among Table 2's 8 features"), expect="<3",
          decided_in=_S_SLM,
          note="Table 2: I 0.61, A 0.55, A1 0.53, A2 0.5, X1 0.37: X1 is fifth and I is first; the text picks A "
               "and X1."),
    Claim("iloc-slm-quadratic-better", KEY, 462, "ordering",
          "The quadratic SLM (eq. 17) fits better than the linear one (eq. 16): RMSE 12.15 against 12.32.",
          paper_value=12.15 - 12.32, paper_text="分別是 12.32 和 12.15，於是利用二元二次迴歸方程式計算步距長度",
          statistic=diff(M(_SL, "quadratic SLM RMSE"), M(_SL, "linear SLM RMSE"), "cm"), expect="<0",
          assumptions=_A_SLM, decided_in=_S_SLM,
          note="in-sample RMSE on the training steps, as the thesis computes it."),
    Claim("iloc-slm-fixed-error", KEY, 478, "value",
          "At fixed step lengths 40-80 cm the SLM's mean error is 18.43 % (Fig 14).",
          paper_value=18.43, paper_text="平均誤差在 18.43%",
          statistic=value(M(_SL, "mean relative error at fixed lengths 40-80 cm, quadratic SLM (new walkers)"), "%"),
          assumptions=_A_SLM, decided_in=_S_FIG14),
    Claim("iloc-slm-free-walk", KEY, 478, "value",
          "Over a free 20 m walk the SLM's distance is 96.41 % accurate (Fig 15).",
          paper_value=96.41, paper_text="隨意行走 20 公尺來驗證 SLM，推算結果如圖十五，準確度可達 96.41%",
          statistic=value(M(_SL, "20 m free-walk accuracy, quadratic SLM, SAM q0.05-0.95 (new walkers)"), "%"),
          assumptions=_A_SLM, decided_in=_S_FIG14),
    Claim("iloc-table4-vs-slm-error", KEY, (478, 605), "consistency",
          "Table 4's step-length error variances agree with the SLM's 18.43 % mean error.",
          paper_value=18.43, paper_text="平均誤差在 18.43%; 0.054	0.054	0.036	0.053	0.065",
          statistic=constant(lambda: 100 * math.sqrt(2 / math.pi) * float(np.mean(np.sqrt(TABLE4_VAR))),
                             "mean |error| of N(0, Table 4) read as relative variances, %", "%"),
          decided_in=_S_TABLE4,
          note="Table 4 prints no unit. Read as variances of the relative error, the mean absolute error of a "
               "Gaussian is sqrt(2/pi) x mean(sqrt(var)) = 0.798 x 0.228 = 18.2 %, beside the text's 18.43 %; "
               "read as m^2 the sd would be 19-25 cm on 40-80 cm steps. This supports the relative reading "
               "(fusion_iloc_kf table4_reading='relative')."),
    # ---- ch. 4 PTS: WDM and the whole PTS -----------------------------------------------------------------
    Claim("iloc-wdm-error", KEY, 508, "value",
          "The WDM's mean per-step heading error is 13.87 deg (Fig 16).",
          paper_value=13.87, paper_text="WDM 的平均誤差為 13.87 度",
          statistic=value(M(_H, "WDM mean per-step heading error"), "deg"), assumptions=_A_PTS,
          decided_in=_S_FIG16,
          note="depends on phone misalignment, hard-iron residual and indoor field disturbances, which "
               "pdr_heading_trajectory does not take as run() keywords."),
    Claim("iloc-pts-mean", KEY, 517, "value",
          "PTS alone has a mean error of 5.2 m at the 28 test points (Figs 17-18).",
          paper_value=5.2, paper_text="行人軌跡系統平均誤差為 5.2 公尺",
          statistic=value(M(_H, "PTS mean position error at the test points (27 after the start)"), "m"),
          assumptions=_A_PTS, decided_in=_S_FIG17),
    # ---- ch. 5 Kalman filter --------------------------------------------------------------------------------
    Claim("iloc-kf-start-is-pts", KEY, (517, 618), "consistency",
          "The 5.15 m the Kalman filter improves on is ch. 4's PTS mean error (5.2 m).",
          paper_value=5.2, paper_text="平均誤差為 5.2 公尺; 將平均誤差值從 5.15 公尺降到 2.82 公尺",
          statistic=constant(lambda: 5.15, "ch. 5's starting error", "m"),
          decided_in=_S_KF,
          note="5.15 m rounds to ch. 4's 5.2 m PTS mean, and ch. 3 gives Wi-Fi medians only (4.5 m): the reading "
               "'PTS 5.15 m -> KF 2.82 m' (fusion_iloc_kf) is consistent; 'Wi-Fi 5.15 m' has no support in the "
               "text."),
    Claim("iloc-kf-improves-pts", KEY, (618, 829), "improvement",
          "The Kalman filter fusing PTS and Wi-Fi lowers the mean error from 5.15 m to 2.82 m (0.55 x).",
          paper_value=2.82 / 5.15, paper_text="將平均誤差值從 5.15 公尺降到 2.82 公尺",
          statistic=value(M(_KF, "KF mean / PTS mean"), "ratio"), expect="<1", assumptions=_A_KF,
          decided_in=_S_KF),
    Claim("iloc-kf-beats-wifi", KEY, 618, "ordering",
          "The KF track is the closest to the true route: better than Wi-Fi alone (and than PTS).",
          paper_text="經過校正後的路線(KF 軌跡)是最接近實際路線",
          statistic=diff(M(_KF, _KF_MEAN, item="KF (R calibrated)"), M(_KF, _KF_MEAN, item="Wi-Fi only"), "m"),
          expect="<0", assumptions=_A_KF, decided_in=_S_KF,
          note="the thesis prints no Wi-Fi mean for this walk; KF against PTS is iloc-kf-improves-pts."),
    Claim("iloc-kf-mean", KEY, (93, 618), "value",
          "The fused PTS + Wi-Fi error is 2.82 m.",
          paper_value=2.82, paper_text="2.82m; 將平均誤差值從 5.15 公尺降到 2.82 公尺",
          statistic=value(M(_KF, "KF (PTS + Wi-Fi) mean error at the test points"), "m"), assumptions=_A_KF,
          decided_in=_S_KF,
          note="the abstract (L93) calls 2.82 m a median, ch. 5 (L618) and ch. 9 (L829) a mean (平均); the mean "
               "is compared."),
    Claim("iloc-table5-vs-wifi-error", KEY, (333, 588, 610, 612, 614, 616), "consistency",
          "Table 5's Wi-Fi error variances at the 28 test points agree with ch. 3's Wi-Fi error (median 4.5 m).",
          paper_value=4.5, paper_text="中位位置誤差值大約為 4.5 公尺; 15.072; 11.219; 6.400; 3.250",
          statistic=constant(lambda: table5_error_quantile_m(0.5), "median error implied by Table 5", "m"),
          decided_in=_S_TABLE5,
          note="with R = sigma_RF^2 I (eq. 23), Table 5's 28 variances (mean 3.99 m^2 per axis) give a median "
               "distance error of 1.95 m and an 80 % point of 3.39 m, against ch. 3's 4.5 m and 9 m at the same "
               "28 points (L588): unless the variances exclude a per-point bias, Table 5 describes a Wi-Fi fix "
               "twice as good as ch. 3's."),
    # ---- ch. 6 photo positioning -----------------------------------------------------------------------------
    Claim("iloc-photo-st-mean", KEY, (93, 702), "value",
          "ST photo positioning's mean error is 74.3 cm (0.74 m in the abstract).",
          paper_value=74.3, paper_text="0.74m; 平均誤差分別為 74.3 公分",
          statistic=value(M(_PH, "ST overall mean error"), "cm"), assumptions=_A_PHOTO,
          decided_in=_S_PHOTO,
          note="the abstract calls 0.74 m a median; ch. 6 a mean (平均, over 120 combinations x 7 points)."),
    Claim("iloc-photo-st-beats-vagig", KEY, (696, 702), "ordering",
          "ST is more accurate than VA with a good initial guess (74.3 cm against 88.9 cm).",
          paper_value=74.3 - 88.9,
          paper_text="ST 演算法優於 VAGIG 演算法和 VABIG 演算法，平均誤差分別為 74.3 公分、88.9 公分",
          statistic=diff(M(_PH, "ST overall mean error"), M(_PH, "VAGIG overall mean error"), "cm"), expect="<0",
          assumptions=_A_VAGIG, decided_in=_S_PHOTO),
    Claim("iloc-photo-vabig-worst", KEY, (696, 702), "ordering",
          "VA with a bad initial guess is the least accurate (246.0 cm against VAGIG's 88.9 cm).",
          paper_value=88.9 - 246.0, paper_text="VABIG 演算法是誤差最大的定位法; 88.9 公分、246.0 公分",
          statistic=diff(M(_PH, "VAGIG overall mean error"), M(_PH, "VABIG overall mean error"), "cm"),
          expect="<0", assumptions=_A_VAGIG, decided_in=_S_PHOTO),
    Claim("iloc-photo-st-more-pois", KEY, (680, 702), "trend",
          "ST's error falls as PoIs are added: 112 cm with 2 PoIs to 48 cm with 7.",
          paper_text="ST 演算法會從 112 公分降到 48 公分",
          statistic=spearman([M(_PH, _PK, item=f"ST, {k} PoIs") for k in range(2, 8)], range(2, 8)),
          expect="<0", assumptions=_A_PHOTO,
          decided_in=_S_FIG30),
    Claim("iloc-photo-vabig-more-pois", KEY, 702, "trend",
          "VABIG's error falls as PoIs are added: 870 cm with 2 PoIs to 50 cm with 7.",
          paper_text="VABIG 演算法的定位誤差距離會從 870 公分降低到 50 公分",
          statistic=spearman([M(_PH, _PK, item=f"VABIG, {k} PoIs") for k in range(2, 8)], range(2, 8)),
          expect="<0", assumptions=_A_PHOTO,
          decided_in=_S_FIG30),
    Claim("iloc-photo-va-distance", KEY, 696, "trend",
          "Both VA algorithms' errors grow in proportion to the shooting point's distance from p4 (t1 nearest, "
          "t7 farthest).",
          paper_text="會發現和兩種 VA 演算法造成的定位誤差成正比關係",
          statistic=Stat((M(_PH, "error vs distance to p4, Spearman rho", item="VAGIG"),
                          M(_PH, "error vs distance to p4, Spearman rho", item="VABIG")), min,
                         "min Spearman rho (error, distance to p4) of VAGIG and VABIG"),
          expect=">0", assumptions=_A_VAGIG, decided_in=_S_FIG29),
    Claim("iloc-photo-near-combos", KEY, 707, "ordering",
          "PoI combinations near the shooting points ({1,2}, {6,7}) locate better than {3,4}, {3,5}, {4,5}, "
          "{3,4,5}.",
          paper_text="所以 {1,2} 、 {6,7} 比 {3,4} 、 {3,5} 、 {4,5} 、 {3,4,5} 擁有準確的定位結果",
          statistic=value(M(_PH, "ST error, combos {1,2},{6,7} / combos {3,4},{3,5},{4,5},{3,4,5}")),
          expect="<1", assumptions=_A_PHOTO,
          decided_in=_S_FIG31,
          note="ST, mean error of the two named groups (the thesis's Fig 31 is missing)."),
    Claim("iloc-photo-collinear", KEY, 707, "ordering",
          "Nearly collinear PoI combinations ({1,3}, {1,4}, {5,6}, {1,3,4}) give ST larger errors than the other "
          "combinations.",
          paper_text="{1,3} 、 {1,4} 、 {5,6} 和 {1,3,4} 的定位誤差差於其他組合",
          statistic=value(M(_PH, "near-collinear combos' error / mean of same-size combos", item="ST")),
          expect=">1", assumptions=_A_PHOTO,
          decided_in=_S_FIG31,
          note="each named combination's ST error over the mean of the combinations of its size, averaged."),
)
