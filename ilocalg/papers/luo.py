"""The claims of Luo et al. 2017 (fingerprint + PDR), as data (:mod:`ilocalg.papers.claims`).

One :class:`~ilocalg.papers.claims.Claim` per statement of substance, read from the whole text
(/work/shared/papers/004_b095b672cff2e388.txt; ``line`` is the line of that file): the KNN fingerprint
(eq. 1-2, Manhattan, K = 5), the Kalman filter of sec. 3.1-3.2, the sliding-window peak detector with
its 0.2-2 s time window (sec. 3.4.2), the step length eq. (4), the position update eq. (5)-(6), and the
results of sec. 4 (Fig 6: Wi-Fi 11.38 m, combined 6.74 m, PDR better for the first 6 points).

The paper's building, survey and walks are not published: every testable claim is tested on the
simulated i-Loc floor (:mod:`ilocalg.experiments.fusion_knn_pdr`, notebook 08) or its Wi-Fi experiment
(:mod:`ilocalg.experiments.wifi_iloc`, notebook 01).

References
----------
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
"""

from __future__ import annotations

from ilocalg.papers._claim_helpers import decided
from ilocalg.papers.claims import Assumption, Claim, M, Stat, diff, ratio, spearman, value

__all__ = ["CLAIMS", "KEY", "FILE", "PUBLISHED"]

KEY = "luo"
#: The text copy the line numbers refer to (in the shared papers folder).
FILE = "004_b095b672cff2e388.txt"


#: The paper's published values that the experiments show beside theirs (``paper_ref``): reference only,
#: never used to compute. Sec. 4 item 2 (L239: Wi-Fi only mean error, smallest and largest per-point error)
#: and item 3 (L241: combined mean error; PDR better than the combination for the first 6 points).
PUBLISHED = {"wifi_mean_m": 11.38, "wifi_min_m": 1.0, "wifi_max_m": 21.5, "combined_mean_m": 6.74,
             "pdr_better_points": 6}


_X, _W = "fusion_knn_pdr", "wifi_iloc"
_NB08, _NB01 = "08_fusion_knn_pdr", "01_wifi_radar_horus_knn"
_COMBINED = "combined (Wi-Fi start + fingerprint adjustment)"
_WIFI = "Wi-Fi only (KNN)"

# Assumptions: the values the paper does not fix, with their ranges and where they come from.
_A_SURVEY = Assumption(_X, "scans_per_point", 10, 300, "survey scans per sample point: not given (L9, L91); 10 "
                       "to the i-Loc thesis's 300 (Chiu 2013 L295)", log=True, integer=True)
_A_LATENCY = Assumption(_X, "scan_latency_s", 1.0, 3.0, "smartphone Wi-Fi scan durations 1-3 s; not given "
                        "(L222)")
_A_WEIGHT = Assumption(_X, "adjust_weight", 0.25, 1.0, "how far a fingerprint fix pulls the PDR position: not "
                       "given (L245); a quarter to all of the gap (assumption)")
_A_WIFI = (_A_SURVEY, _A_LATENCY)
_A_FUSED = (_A_SURVEY, _A_LATENCY, _A_WEIGHT)
_A_KNN = (Assumption(_W, "scans_per_point", 10, 300, "survey scans per sample point: not given (L9, L91)",
                     log=True, integer=True),
          Assumption(_W, "scans_per_test_point", 1, 20, "scans per located position: not given (assumption)",
                     integer=True))
_A_PDR = (Assumption(_X, "n_train", 3, 8, "walks of known length behind eq. (4)'s k: not given (k itself is not "
                     "given, L202)", integer=True),)

_SENS = decided(_NB08, "Sensitivity: adjustment weight, survey scans per point, peak rule and threshold, scan latency")
_FIG6 = decided(_NB08, "Error at each point (Fig 6)")
_METHOD = decided(_NB08, "The method: Luo et al. 2017 eq. (1)-(2), (4), (5)-(6)")
_DET = "detected / true steps"

# Notebook sections that decide the claims.
_S_KNN = decided(_NB01, "Figs 3 and 5: error CDFs of the three methods")

CLAIMS = (
    # ---- sec. 2 KNN fingerprint -----------------------------------------------------------------------
    Claim("luo-knn-beats-nn", KEY, (73, 83, 87), "ordering",
          "KNN, averaging the K = 5 nearest fingerprints (Manhattan distance, a = 1), is more accurate than the "
          "nearest neighbour alone.",
          paper_text=("KNN算法是从最小距离开始选取K(K>=2)个最接近的数据; 在本文中设 a=1, K=5; "
                      "KNN 近邻算法用平均距离减少了误差, 提高了精确度"),
          statistic=diff(M(_W, "KNN (Manhattan) mean error", item="K=5"),
                         M(_W, "KNN (Manhattan) mean error", item="K=1"), "m"),
          expect="<0", assumptions=_A_KNN, decided_in=_S_KNN,
          note="standing test scans on the simulated i-Loc floor (the paper's library survey is not published); "
               "the paper compares with no other K or metric."),
    # ---- sec. 3.1-3.2 Kalman filter -------------------------------------------------------------------
    Claim("luo-kf-unsuited", KEY, 143, "ordering",
          "A Kalman-filter inertial navigation needs high computing power, sampling rates and sensor precision, "
          "and its rounding errors accumulate until the filter may diverge; PDR is easier on Android phones.",
          paper_text="随着滤波步数的增加, 舍入误差逐渐积累, 可能使增益矩阵的计算值逐渐失去加权作用而导致滤波发散",
          untestable="a statement about phone hardware and numerical round-off, with no measurement in the paper; "
                     "the toolkit runs its filters in float64 on a PC (its i-Loc step KF alternative, over some "
                     "50 steps, shows no divergence, which says nothing about 2016 phones).",
          decided_in=_METHOD),
    # ---- sec. 3.4.2 step detection ----------------------------------------------------------------------
    Claim("luo-sliding-window", KEY, (175, 177), "trend",
          "The sliding search window decides the peaks found: too large a window discards true peaks, too small "
          "a window takes small fluctuations for peaks.",
          paper_text="若窗口值设置得太大,会使很多正确的峰值被舍弃掉;若窗口值设置的过小,则会受到严重的误差干扰,将细微的波动当做是峰值",
          statistic=spearman([M(_X, _DET, item=f"sliding window {w} s") for w in ("0.1", "0.4", "1.2")],
                             (0.1, 0.4, 1.2)),
          expect="<0", assumptions=_A_PDR, decided_in=_SENS,
          note="detected over true steps on new simulated walkers walking the floor's route, windows 0.1, 0.4 "
               "(default) and 1.2 s (the paper gives no window size); the trend is the claim's 'too large' "
               "half, the 'too small' half shows as a ratio above 1 at the smallest window."),
    Claim("luo-time-window", KEY, 189, "ordering",
          "The 0.2-2 s time window between steps (the limits of human walking) counts steps; a range set too "
          "wide misjudges the step count.",
          paper_text="时间窗口的范围为 0.2s-2s 之间; 如果时间窗口值范围设得太大,很可能导致步数的误判",
          statistic=Stat((M(_X, _DET, item="time window 0.05-5 s"), M(_X, _DET, item="time window 0.2-2 s")),
                         lambda wide, paper: abs(wide - 1.0) - abs(paper - 1.0),
                         "|detected/true - 1| with 0.05-5 s minus with 0.2-2 s"),
          expect=">0", assumptions=_A_PDR, decided_in=_SENS,
          note="0.05-5 s stands for 'too wide' (the paper gives no wider range it tried)."),
    # ---- sec. 3.4.2 step length ----------------------------------------------------------------------------
    Claim("luo-eq4-step-length", KEY, (200, 202), "improvement",
          "The nonlinear step-length model eq. (4), k((a_max - a_min) * 3.5 + (a_max - a_min)^(1/4)), estimates "
          "steps of different lengths more accurately (than one constant step length).",
          paper_text=("本文通过一种非线性步长估算模型,提高不同步长下步长估算的精度; "
                      "(a_{\\text{max}} - a_{\\text{min}}) * 3.5"),
          statistic=ratio(M(_X, "fixed-length walks 40-80 cm, mean relative step-length error", item="eq. (4)"),
                          M(_X, "fixed-length walks 40-80 cm, mean relative step-length error",
                            item="one constant step length")),
          expect="<1", assumptions=_A_PDR, decided_in=_SENS,
          note="k (not given) fitted on walks of known length; per detected step, on new walkers at imposed "
               "lengths 40-80 cm. The paper names no baseline; a constant step is the model a step-length "
               "estimator must beat. Eq. (4) adds a term in m/s^2 to one in (m/s^2)^(1/4): with a_max - a_min "
               "above (1/3.5)^(4/3) = 0.19 m/s^2 the linear term dominates, so on walking amplitudes eq. (4) is "
               "nearly linear, and its shape changes with the unit of a."),
    # ---- sec. 3.3-3.4.4 PDR and the position update ------------------------------------------------------
    Claim("luo-pdr-drift", KEY, (147, 235), "trend",
          "PDR alone, started at the true start, accumulates error: its error grows with time along the walk.",
          paper_text=("由于 PDR 的起点与实际起点一致, 因此在起点的误差为 0. "
                      "通过图像可知, 随着时间的延长, PDR 存在的累积误差将越来越大"),
          statistic=value(M(_X, "PDR only per-point error vs point index, Spearman rho", item="PDR only")),
          expect=">0", assumptions=_A_PDR, decided_in=_FIG6,
          note="Spearman rho of the per-point mean error (over walkers) with the point index (Fig 6's x axis). "
               "Eq. (5)-(6) (L214-216) print the displacement sfre x slen x duration x cos/sin(orien) as the "
               "location, without the start position L212 adds; the toolkit adds it, step by step."),
    # ---- sec. 4 results (Fig 6) -----------------------------------------------------------------------------
    Claim("luo-wifi-mean", KEY, 239, "value",
          "Wi-Fi fingerprinting alone has a mean error of 11.38 m along the walk.",
          paper_value=11.38, paper_text="其平均误差为 11.38 米",
          statistic=value(M(_X, "Wi-Fi only (KNN, Manhattan, K=5) mean error"), "m"), assumptions=_A_WIFI,
          decided_in=_FIG6,
          note="the simulated i-Loc floor, not the paper's library (4th floor, Fig 8's sample points are lost)."),
    Claim("luo-wifi-jumps", KEY, 239, "value",
          "The Wi-Fi-only error jumps widely, between 1.0 m and 21.5 m (a spread of 20.5 m).",
          paper_value=21.5 - 1.0, paper_text="图中误差的震荡区间为 [1.0, 21.5]. 实验数据中最大误差距离达到 21.5 米",
          statistic=diff(M(_X, "Wi-Fi only, largest per-point error"), M(_X, "Wi-Fi only, smallest per-point error"),
                         "m"),
          assumptions=_A_WIFI, decided_in=_FIG6,
          note="over every simulated walker and test position (the paper: one walk)."),
    Claim("luo-combined-improves", KEY, (239, 241, 245), "improvement",
          "Combining fingerprinting and PDR lowers the mean error from Wi-Fi's 11.38 m to 6.74 m (0.59 x).",
          paper_value=6.74 / 11.38, paper_text="其平均误差为 11.38 米; 其平均误差为 6.74 米",
          statistic=value(M(_X, "combined / Wi-Fi only mean error"), "ratio"), expect="<1",
          assumptions=_A_FUSED, decided_in=_FIG6),
    Claim("luo-combined-mean", KEY, 241, "value",
          "The combination's mean error is 6.74 m.",
          paper_value=6.74, paper_text="其平均误差为 6.74 米",
          statistic=value(M(_X, "combined mean error (Wi-Fi start + fingerprint adjustment)"), "m"),
          assumptions=_A_FUSED, decided_in=_FIG6),
    Claim("luo-combined-smoother", KEY, 241, "ordering",
          "The combination's error curve is smoother and steadier than Wi-Fi's.",
          paper_text="对比红色虚线, 其趋势比较平滑、稳定",
          statistic=ratio(M(_X, "mean |error change| between successive test positions", item=_COMBINED),
                          M(_X, "mean |error change| between successive test positions", item=_WIFI)),
          expect="<1", assumptions=_A_FUSED, decided_in=_FIG6,
          note="mean absolute change of the error from one test position to the next, within each walk."),
    Claim("luo-pdr-crossover", KEY, 241, "value",
          "PDR alone is better than the combination for the first 6 points; from the 7th on the combination is "
          "better.",
          paper_value=6, paper_text="前 6 个点, 其误差值大于 PDR 算法. 但从第 7 个点开始",
          statistic=value(M(_X, "last point where PDR only beats combined"), "points"),
          assumptions=_A_FUSED, decided_in=_FIG6,
          note="the last test position at which PDR's per-point mean error is below the combination's; a point "
               "is one scan (the paper's x axis is a coordinate number, its scan rate is not given)."),
    Claim("luo-combined-beats-pdr", KEY, (241, 245), "ordering",
          "Over long walks the combination is clearly better than PDR alone, whose accumulated error it removes.",
          paper_text="对于长距离和长时间的定位, 联合定位明显优于 PDR 算法",
          statistic=diff(M(_X, "mean error", item=_COMBINED), M(_X, "mean error", item="PDR only"), "m"),
          expect="<0", assumptions=_A_FUSED, decided_in=_FIG6,
          note="mean over the whole walk (the paper's route length is not given)."),
)
