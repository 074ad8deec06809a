"""What Liao et al. (2016) claim, as data: the claims ledger of the smartphone INS paper.

Line numbers are lines of the paper's text copy (``/work/shared/papers/001_2222ac3cfae0589e.txt``). The
published values of Tables 4-11 live in :mod:`ilocalg.ins.paper_values` (``LIAO_TABLES``); every paper
value below is computed from them or from the printed numbers quoted in the claim.

Position claims compare methods on the root sum of squares of the paper's per-axis RMS (or maximum)
errors, N, E and H, per phone, and pool the two phones by the geometric mean of the per-phone ratios.

References
----------
Liao, J.-K., Chiang, K.-W., Zhou, Z.-M., Li, C.-H. (2016). Using the on-line smoothing and constraint
algorithms to improve the accuracy of pedestrian indoor navigation.
"""

from __future__ import annotations

import math

import numpy as np

from ilocalg.ins.paper_values import paper_value as pv
from ilocalg.papers._claim_helpers import decided, gmean, gmean_ratio, max_of, mean_of, mean_spearman, rss, stat
from ilocalg.papers.claims import Assumption, Claim, M, constant, diff

__all__ = ["CLAIMS"]

_P = "liao"
_PHONES = ("Samsung", "iPhone")
_NHC, _WVC, _GCP, _SM = ("Filtering + NHC/ZUPT", "Filtering + WVC/ZUPT", "Filtering + WVC/ZUPT + GCP",
                         "Smoothing + WVC/ZUPT + GCP")
_POS = ("N", "E", "H")
_WINDOWS = (5, 10, 20)

_NB12 = "12_ins_constraints_gcp"
_NB13 = "13_ins_online_window"
_POS12 = decided(_NB12, "Tables 4 and 6: position errors (paper value beside the simulated one, metres)")
_ATT12 = decided(_NB12, "Tables 5 and 7: attitude errors (degrees)")
_SYNC12 = decided(_NB12, "Heading error when the phone's time tags are misaligned with the reference")
_POS13 = decided(_NB13, "Tables 8 and 10: position errors, Filtering vs online windows (m)")
_ATT13 = decided(_NB13, "Tables 9 and 11: attitude errors (deg)")
_FIG19 = decided(_NB13, "Fig 19: error against window size")
_NOGCP = decided(_NB13, "Windows without a control point")
_STUDY = decided("15_sweep_studies", "2 Online INS smoothing: error vs window size, with and without a control "
                                     "point in the window")
_METHOD12 = decided(_NB12, "The method: Liao et al. 2016 eq. (1)-(10)")


def _assumptions(exp: str) -> dict:
    """The simulated phones', beacons' and walkers' values the paper does not fix (keywords of ``exp.run``),
    with the range each is swept over and where it comes from."""
    return {
        "noise": Assumption(exp, "noise_factor", 1.0, 5.0, "white noise over the MPU-6500 datasheet densities: "
                            "no value for these phones (the paper's IMU calibration, Liao et al. 2014, is not "
                            "available here); x1 (datasheet) to x5 about the assumed x3"),
        "bias": Assumption(exp, "bias_instability_factor", 0.0, 3.0, "Gauss-Markov bias instability (0.5 mg / "
                           "20 deg/h, 300 s): not given (L178, L202); x0 to x3 (assumed order of consumer-MEMS "
                           "Allan-variance studies)"),
        "jitter": Assumption(exp, "time_jitter_sd_s", 0.0, 0.03, "time-tag error: 'about 20 Hz, unstable, poor time "
                             "tags' (L324), no value; 0-30 ms about the assumed 10 ms"),
        "rssi": Assumption(exp, "rssi_sd_db", 2.0, 8.0, "the control-point beacons' per-packet RSSI scatter: not "
                           "given (L73, L202); 4-6 dB in vendor stability tests (a weak source), swept 2-8 dB"),
        "speed": Assumption(exp, "speed_mean_mps", 1.24, 1.56, "the walkers' mean level speed: not described; "
                            "1.40 m/s (Bohannon 1997) +- one between-walker sd (0.16 m/s)"),
    }


_AC, _AO = _assumptions("ins_constraints"), _assumptions("ins_online")
#: position claims of the filter (all five), attitude claims (no control-point scatter), the time-sync claim
_A_POS = tuple(_AC.values())
_A_ATT = (_AC["noise"], _AC["bias"], _AC["jitter"], _AC["speed"])
_A_SYNC = (_AC["jitter"], _AC["noise"], _AC["bias"])
_A_ONLINE = tuple(_AO.values())


def _c(stat_: str, axis: str, phone: str, method: str):
    """A reproduced error of ins_constraints (mean over seeds): ``_c("rms", "N", "Samsung", _WVC)``."""
    return M("ins_constraints", f"{stat_} {axis} error", item=f"{phone} {method}", table="measures")


def _o(stat_: str, axis: str, phone: str, method: str):
    """A reproduced error of ins_online: method "Filtering", "Online 5sec" ... or "RTS (whole run)"."""
    return M("ins_online", f"{stat_} {axis} error", item=f"{phone} {method}", table="measures")


def _online(w: int) -> str:
    return f"Online {w}sec"


def _ratio_pos(ref, a: str, b: str, stat_: str = "rms", combine=rss, label: str = ""):
    """Geometric mean over phones of combine(errors of a) / combine(errors of b), N, E, H."""
    return gmean_ratio([([ref(stat_, ax, ph, a) for ax in _POS], [ref(stat_, ax, ph, b) for ax in _POS])
                        for ph in _PHONES], combine, label)


def _paper_ratio(a: str, b: str, stat_: str = "rms", combine=rss, ma: str | None = None, mb: str | None = None):
    """The same ratio from the paper's tables (``ma``/``mb``: the tables' method names when they differ)."""
    return gmean([combine([pv(ph, ma or a, stat_, ax) for ax in _POS]) / combine([pv(ph, mb or b, stat_, ax)
                                                                                 for ax in _POS])
                  for ph in _PHONES])


def _max3(v) -> float:
    return float(np.max(v))


def _rms3_paper(ph: str, method: str) -> float:
    return rss([pv(ph, method, "rms", ax) for ax in _POS])


def _gain_ratio_paper(phones=_PHONES) -> float:
    """(sum over phones of RMS10 - RMS20) / (sum of RMS5 - RMS10), 3-D RMS of Tables 8 and 10."""
    g1 = sum(_rms3_paper(ph, _online(10)) - _rms3_paper(ph, _online(20)) for ph in phones)
    g0 = sum(_rms3_paper(ph, _online(5)) - _rms3_paper(ph, _online(10)) for ph in phones)
    return g1 / g0


def _gain_ratio_stat():
    refs = [_o("rms", ax, ph, _online(w)) for ph in _PHONES for w in _WINDOWS for ax in _POS]

    def fn(*v):
        r = np.asarray(v).reshape(len(_PHONES), len(_WINDOWS), 3)
        e = np.sqrt(np.sum(r**2, axis=2))  # 3-D RMS per phone and window
        g0 = float(np.sum(e[:, 0] - e[:, 1]))
        return float(np.sum(e[:, 1] - e[:, 2])) / g0 if g0 != 0 else math.nan

    return stat(refs, fn, "sum(RMS10 - RMS20) / sum(RMS5 - RMS10), 3-D RMS, both phones", "ratio")


def _window_trend_paper() -> float:
    from scipy.stats import spearmanr

    return float(np.mean([spearmanr(_WINDOWS, [pv(ph, _online(w), "rms", ax) for w in _WINDOWS]).statistic
                          for ph in _PHONES for ax in _POS]))


def _rts_gain_printed_over_standard(p: float = 2.0, phi: float = 1.0, q: float = 2.0) -> float:
    """Eq. (10) as printed, G = P Phi P_pred, over the RTS gain G = P Phi^T / P_pred, scalar random walk."""
    p_pred = phi * p * phi + q
    return (p * phi * p_pred) / (p * phi / p_pred)


def _chain_stat():
    """Mean over phones of the Spearman rho of the 3-D RMS error against the step NHC, WVC, + GCP, + smoothing."""
    from scipy.stats import spearmanr

    methods = (_NHC, _WVC, _GCP, _SM)
    refs = [_c("rms", ax, ph, m) for ph in _PHONES for m in methods for ax in _POS]

    def fn(*v):
        r = np.sqrt(np.sum(np.asarray(v).reshape(len(_PHONES), len(methods), 3) ** 2, axis=2))
        return float(np.mean([spearmanr(range(len(methods)), row).statistic for row in r]))

    return stat(refs, fn, "mean over phones of Spearman rho (RSS RMS error vs step of the chain)")


_R_MAX = _ratio_pos(_c, _WVC, _NHC, "max", _max3, "largest max error WVC/ZUPT / NHC/ZUPT, geometric mean")
_R_RMS = _ratio_pos(_c, _WVC, _NHC, label="RSS RMS error WVC/ZUPT / NHC/ZUPT, geometric mean of phones")
_ROLL_PITCH = ("Roll", "Pitch")
_SYNC_ITEM = "{ph} " + _GCP + " lag={lag}s"

CLAIMS = (
    Claim(
        "liao-wvc-beats-nhc-rms", _P, (228, 229, 283, 284, 316), "improvement",
        "WVC constrains the pedestrian's inertial errors better than NHC: the filter's RMS position error falls "
        "with WVC/ZUPT against NHC/ZUPT.",
        paper_value=_paper_ratio(_WVC, _NHC),
        paper_text="14.8002 5.1419 3.6398 -> 1.9790 5.4046 3.7849; 4.6846 14.5990 3.4490 -> 8.9068 3.7412 1.1919",
        statistic=_R_RMS,
        expect="<1", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-wvc-beats-nhc-max", _P, (222, 223, 277, 278, 316), "improvement",
        "WVC lowers the filter's maximum position error against NHC (42.4 -> 12.7 m, 82.7 -> 15.2 m).",
        paper_value=_paper_ratio(_WVC, _NHC, "max", _max3),
        paper_text="42.4434 17.8689 9.1891 -> 8.2482 12.6542 8.1319; 18.0619 82.6971 6.8075 -> 15.2382 10.5535 "
                   "4.2622",
        statistic=_R_MAX,
        expect="<1", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-wvc-especially-max", _P, (222, 223, 228, 229, 277, 278, 283, 284, 316), "ordering",
        "WVC helps especially the maximum error: its ratio to NHC is lower on the maximum than on the RMS.",
        paper_value=_paper_ratio(_WVC, _NHC, "max", _max3) / _paper_ratio(_WVC, _NHC), paper_text="",
        statistic=stat(_R_MAX.refs + _R_RMS.refs,
                       lambda *v: _R_MAX(*v[:len(_R_MAX.refs)]) / _R_RMS(*v[len(_R_MAX.refs):]),
                       "(max ratio WVC/NHC) / (RMS ratio WVC/NHC)", "ratio"),
        expect="<1", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-wvc-rms-under-10m", _P, (229, 284, 316), "value",
        "With WVC and no control point the real-time filter keeps the RMS error within 10 m (default model "
        "parameters).",
        paper_value=max(pv(ph, _WVC, "rms", ax) for ph in _PHONES for ax in _POS),
        paper_text="10; 1.9790 5.4046 3.7849; 8.9068 3.7412 1.1919",
        statistic=max_of([_c("rms", ax, ph, _WVC) for ph in _PHONES for ax in _POS],
                         "largest per-axis RMS error, WVC/ZUPT filter, both phones", "m"),
        expect="<10", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-gcp-improves", _P, (229, 230, 284, 285, 318), "improvement",
        "Indoor control points correct the drifted track and the residual WVC error.",
        paper_value=_paper_ratio(_GCP, _WVC),
        paper_text="1.9790 5.4046 3.7849 -> 1.2300 0.9918 0.8697; 8.9068 3.7412 1.1919 -> 0.9885 1.6341 0.9695",
        statistic=_ratio_pos(_c, _GCP, _WVC, label="RSS RMS error WVC/ZUPT + GCP / WVC/ZUPT, geometric mean"),
        expect="<1", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-gcp-1-2m", _P, (230, 285, 318), "value",
        "With control points the position RMSE comes down to 1-2 m.",
        paper_value=max(pv(ph, _GCP, "rms", ax) for ph in _PHONES for ax in _POS),
        paper_text="1 2; 1.2300 0.9918 0.8697; 0.9885 1.6341 0.9695",
        statistic=max_of([_c("rms", ax, ph, _GCP) for ph in _PHONES for ax in _POS],
                         "largest per-axis RMS error, WVC/ZUPT + GCP filter, both phones", "m"),
        expect="<2", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-rts-beats-filter", _P, (230, 231, 285, 286, 320), "improvement",
        "Post-processed (RTS) smoothing lowers the error of the filter with WVC/ZUPT and control points.",
        paper_value=_paper_ratio(_SM, _GCP),
        paper_text="1.2300 0.9918 0.8697 -> 0.3470 0.3967 0.1928; 0.9885 1.6341 0.9695 -> 0.5507 0.5810 0.2295",
        statistic=_ratio_pos(_c, _SM, _GCP, label="RSS RMS error smoothing / filtering (WVC/ZUPT + GCP)"),
        expect="<1", assumptions=_A_POS, decided_in=_POS12),
    Claim(
        "liao-rts-50cm", _P, (231, 286, 320), "value",
        "The post-processed smoothed track's position error is about 50 cm.",
        paper_value=float(np.mean([pv(ph, _SM, "rms", ax) for ph in _PHONES for ax in ("N", "E")])),
        paper_text="50; 0.3470 0.3967; 0.5507 0.5810",
        statistic=mean_of([_c("rms", ax, ph, _SM) for ph in _PHONES for ax in ("N", "E")],
                          "mean horizontal per-axis RMS error, smoothing, both phones", "m"),
        assumptions=_A_POS, decided_in=_POS12, note="read on the horizontal axes (N, E), the 50 cm the text names"),
    Claim(
        "liao-chain", _P, (316, 318, 320), "ordering",
        "The position error falls at every step NHC/ZUPT -> WVC/ZUPT -> + control points -> + smoothing, on both "
        "phones.",
        paper_value=-1.0, paper_text="",
        statistic=_chain_stat(),
        expect="<-0.9", assumptions=_A_POS, decided_in=_POS12,
        note="RSS of the per-axis RMS errors per method; -1 when the error falls at every step on both phones"),
    Claim(
        "liao-pitch-max-30-to-10", _P, (244, 245, 322), "improvement",
        "With WVC the Samsung's maximum pitch error falls from 30 to 10 degrees (Table 5).",
        paper_value=pv("Samsung", _WVC, "max", "Pitch") / pv("Samsung", _NHC, "max", "Pitch"),
        paper_text="30 10; 30.9506; 10.7497",
        statistic=stat([_c("max", "Pitch", "Samsung", _WVC), _c("max", "Pitch", "Samsung", _NHC)],
                       lambda a, b: a / b, "Samsung max pitch error WVC/ZUPT / NHC/ZUPT", "ratio"),
        expect="<1", assumptions=_A_ATT, decided_in=_ATT12),
    Claim(
        "liao-gcp-attitude-flat", _P, (251, 252, 306, 307, 322), "ratio",
        "Control points do not noticeably change the attitude error (position updates barely correct attitude).",
        paper_value=float(np.mean([pv(ph, _GCP, "rms", ax) / pv(ph, _WVC, "rms", ax)
                                   for ph in _PHONES for ax in _ROLL_PITCH])),
        paper_text="1.6406 1.6758; 1.6132 1.6947; 1.2675 1.6899; 1.2703 1.6635",
        statistic=stat([r for ph in _PHONES for ax in _ROLL_PITCH for r in (_c("rms", ax, ph, _GCP),
                                                                             _c("rms", ax, ph, _WVC))],
                       lambda *v: float(np.mean(np.asarray(v[0::2]) / np.asarray(v[1::2]))),
                       "mean RMS roll/pitch ratio, + GCP / WVC/ZUPT, both phones", "ratio"),
        assumptions=_A_ATT, decided_in=_ATT12),
    Claim(
        "liao-attitude-rms-under-2deg", _P, (251, 252, 306, 307, 322), "value",
        "WVC/ZUPT, with or without control points, keeps the roll and pitch RMSE within 2 degrees.",
        paper_value=max(pv(ph, m, "rms", ax) for ph in _PHONES for m in (_WVC, _GCP) for ax in _ROLL_PITCH),
        paper_text="2; 1.6406 1.6758; 1.6132 1.6947; 1.2675 1.6899; 1.2703 1.6635",
        statistic=max_of([_c("rms", ax, ph, m) for ph in _PHONES for m in (_WVC, _GCP) for ax in _ROLL_PITCH],
                         "largest RMS roll/pitch error, WVC/ZUPT with and without GCP", "deg"),
        expect="<2", assumptions=_A_ATT, decided_in=_ATT12),
    Claim(
        "liao-max-roll-pitch-under-10deg", _P, 322, "value",
        "WVC/ZUPT, with or without control points, keeps the maximum roll and pitch error within 10 degrees.",
        paper_value=None, paper_text="10",
        statistic=max_of([_c("max", ax, ph, m) for ph in _PHONES for m in (_WVC, _GCP) for ax in _ROLL_PITCH],
                         "largest max roll/pitch error, WVC/ZUPT with and without GCP", "deg"),
        expect="<10", assumptions=_A_ATT, decided_in=_ATT12),
    Claim(
        "liao-max-attitude-table-vs-text", _P, (245, 246, 322), "consistency",
        "The text's 'maximum attitude error within 10 degrees' with WVC/ZUPT (+ GCP) against Table 5.",
        paper_value=None, paper_text="10; 10.7497; 10.7743",
        statistic=constant(lambda: max(pv("Samsung", _WVC, "max", "Pitch"), pv("Samsung", _GCP, "max", "Pitch")),
                           "Samsung max pitch error, WVC/ZUPT and + GCP (Table 5)", "deg"),
        expect="<10", decided_in=_ATT12, note="Table 5 prints 10.7497 and 10.7743 deg: above the text's 10"),
    Claim(
        "liao-heading-time-sync", _P, 324, "ordering",
        "The phone's poor, unstable time tags (about 20 Hz) against the 200 Hz reference inflate the heading "
        "error: the reference turns while the phone's solution still goes straight.",
        paper_value=None, paper_text="20Hz; 200Hz",
        statistic=stat([M("ins_constraints", "max heading error, reference lag", table="measures",
                          item=_SYNC_ITEM.format(ph=ph, lag=lag)) for ph in _PHONES for lag in ("0.05", "0")],
                       lambda a, b, c, d: gmean([a / b, c / d]),
                       "max heading error with the reference read 0.05 s late / on time, geometric mean", "ratio"),
        expect=">1", assumptions=_A_SYNC, decided_in=_SYNC12,
        note="a lag of one sample at 20 Hz (0.05 s); the paper gives no lag value"),
    Claim(
        "liao-online-beats-filter", _P, (353, 356, 421, 424, 464), "improvement",
        "Online smoothing of the WVC/ZUPT + control-point filter (20 s windows) gives better accuracy than the "
        "filter.",
        paper_value=_paper_ratio(_online(20), "Filtering"),
        paper_text="1.2300 0.9918 0.8697 -> 0.6913 0.6346 0.3586; 0.9885 1.6341 0.9695 -> 0.6907 0.7679 0.4985",
        statistic=_ratio_pos(_o, _online(20), "Filtering", label="RSS RMS error online 20 s / filtering"),
        expect="<1", assumptions=_A_ONLINE, decided_in=_POS13),
    Claim(
        "liao-rts-beats-online", _P, (231, 286, 356, 424), "ordering",
        "Whole-run (post-processed) RTS smoothing stays better than online smoothing with 20 s windows.",
        paper_value=_paper_ratio("RTS", _online(20), ma=_SM),
        paper_text="0.3470 0.3967 0.1928; 0.5507 0.5810 0.2295; 0.6913 0.6346 0.3586; 0.6907 0.7679 0.4985",
        statistic=_ratio_pos(_o, "RTS (whole run)", _online(20), label="RSS RMS error whole-run RTS / online 20 s"),
        expect="<1", assumptions=_A_ONLINE, decided_in=_POS13,
        note="paper: RTS from Tables 4 and 6, online from Tables 8 and 10 (the same walks)"),
    Claim(
        "liao-window-trend", _P, (354, 355, 356, 422, 423, 424, 464, 466), "trend",
        "The larger the online window, the more data and control points it holds and the better the accuracy "
        "(Fig 19).",
        paper_value=_window_trend_paper(),
        paper_text="1.0854 0.9195 0.5467; 0.6484 0.7452 0.3804; 0.6913 0.6346 0.3586; 1.0969 1.5530 0.8141; "
                   "0.8574 1.2766 0.6265; 0.6907 0.7679 0.4985",
        statistic=mean_spearman([[_o("rms", ax, ph, _online(w)) for w in _WINDOWS] for ph in _PHONES for ax in _POS],
                                _WINDOWS, "mean Spearman rho of RMS N/E/H vs window 5/10/20 s, both phones"),
        expect="<0", assumptions=_A_ONLINE, decided_in=_FIG19),
    Claim(
        "liao-samsung-n-20s-rises", _P, (355, 356, 471, 473), "ordering",
        "The error does not fall monotonically with the window: Samsung-N's RMSE is larger with 20 s windows than "
        "with 10 s (a few 20 s windows without a control point).",
        paper_value=pv("Samsung", _online(20), "rms", "N") - pv("Samsung", _online(10), "rms", "N"),
        paper_text="0.6484; 0.6913; 20",
        statistic=diff(_o("rms", "N", "Samsung", _online(20)), _o("rms", "N", "Samsung", _online(10)), "m"),
        expect=">0", assumptions=_A_ONLINE, decided_in=_FIG19),
    Claim(
        "liao-diminishing-returns", _P, (355, 356, 423, 424, 481), "ordering",
        "A 20 s window improves little on a 10 s window: the gain shrinks as the window grows.",
        paper_value=_gain_ratio_paper(), paper_text="20; 10",
        statistic=_gain_ratio_stat(), expect="<1", assumptions=_A_ONLINE, decided_in=_FIG19,
        note="pooled over phones on the RSS of the RMS N, E, H errors"),
    Claim(
        "liao-iphone-gains-grow", _P, (422, 423, 424, 481), "consistency",
        "The text's diminishing gain from 10 to 20 s against the iPhone's Table 10.",
        paper_value=None,
        paper_text="1.0969 1.5530 0.8141; 0.8574 1.2766 0.6265; 0.6907 0.7679 0.4985",
        statistic=constant(lambda: _gain_ratio_paper(("iPhone",)), "iPhone (RMS10 - RMS20) / (RMS5 - RMS10)",
                           "ratio"),
        expect="<1", decided_in=_FIG19,
        note="on the RSS of N, E, H: 2.068 -> 1.661 -> 1.147 m, the 10 -> 20 s gain (0.51 m) exceeds the 5 -> 10 s "
             "gain (0.41 m); the Samsung's shrinks (0.47 -> 0.05 m)"),
    Claim(
        "liao-iphone-5s-above-filter", _P, (421, 422, 464), "consistency",
        "Online smoothing improves on the filter, against Table 10's iPhone N with 5 s windows.",
        paper_value=None, paper_text="0.9885; 1.0969",
        statistic=constant(lambda: pv("iPhone", _online(5), "rms", "N") - pv("iPhone", "Filtering", "rms", "N"),
                           "iPhone RMS N online 5 s - filtering (Table 10)", "m"),
        expect="<0", decided_in=_POS13,
        note="1.0969 > 0.9885 m: the 5 s window is worse than the filter on this axis (Samsung's Table 8 max N "
             "too: 5.9395 > 5.2678 m)"),
    Claim(
        "liao-gcp-windows", _P, 471, "ordering",
        "A window that holds a control point smooths better than one that does not.",
        paper_value=None, paper_text="",
        statistic=stat([M("study_ins_window", q, item=f"phone={ph};window_s={w}", table="sweep_ins_window")
                        for ph in _PHONES for w in (10, 20)
                        for q in ("horizontal RMS error, windows with a control point",
                                  "horizontal RMS error, windows without a control point")],
                       lambda *v: gmean(np.asarray(v[0::2]) / np.asarray(v[1::2])),
                       "horizontal RMS in windows with / without a control point, 10 and 20 s, geometric mean",
                       "ratio"),
        expect="<1", decided_in=_STUDY),
    Claim(
        "liao-fewer-empty-windows", _P, 471, "trend",
        "Long windows leave fewer windows without a control point.",
        paper_value=None, paper_text="",
        statistic=mean_spearman([[M("study_ins_window", "share of windows without a control point",
                                    item=f"phone={ph};window_s={w}", table="sweep_ins_window")
                                  for w in (2, 5, 10, 20, 30)] for ph in _PHONES], (2, 5, 10, 20, 30),
                                "mean Spearman rho of the share of windows without a control point vs window"),
        expect="<0", decided_in=_NOGCP, note="a property of the walk and the control-point layout more than of the "
                                             "smoother (control points met about every 15 s, L202)"),
    Claim(
        "liao-online-attitude", _P, (380, 383, 450, 453, 483), "improvement",
        "Online smoothing slightly lowers the roll and pitch RMSE further.",
        paper_value=gmean([pv(ph, _online(20), "rms", ax) / pv(ph, "Filtering", "rms", ax)
                           for ph in _PHONES for ax in _ROLL_PITCH]),
        paper_text="1.6132 1.6947; 1.5690 1.3635; 1.2703 1.6635; 1.1930 1.5398",
        statistic=stat([r for ph in _PHONES for ax in _ROLL_PITCH for r in (_o("rms", ax, ph, _online(20)),
                                                                             _o("rms", ax, ph, "Filtering"))],
                       lambda *v: gmean(np.asarray(v[0::2]) / np.asarray(v[1::2])),
                       "RMS roll/pitch online 20 s / filtering, geometric mean over phones and axes", "ratio"),
        expect="<1", assumptions=_A_ONLINE, decided_in=_ATT13),
    Claim(
        "liao-roll-pitch-random", _P, (383, 391, 483), "consistency",
        "Comparing the STD and RMSE of pitch and roll, the attitude's systematic error is small and mostly "
        "random.",
        paper_value=None, paper_text="1.5690; 0.6652",
        statistic=constant(lambda: math.sqrt(1.5690**2 - 0.6652**2) / 0.6652,
                           "Samsung roll, online 20 s: sqrt(RMS^2 - STD^2) / STD (Table 9)", "ratio"),
        expect="<1", decided_in=_ATT13,
        note="mean 1.42 deg against STD 0.67 deg: the systematic part is twice the random one for the Samsung's "
             "roll (the iPhone's roll is mostly random: 1.1930 vs 1.1745)"),
    Claim(
        "liao-eq-10-gain", _P, 165, "consistency",
        "Eq. (10) is the RTS smoother gain of Shin (2005).",
        paper_value=1.0, paper_text="(10)",
        statistic=constant(_rts_gain_printed_over_standard, "printed G = P Phi P_pred over P Phi^T P_pred^-1, "
                           "scalar P = 2, Phi = 1, Q = 2", "ratio"),
        decided_in=_METHOD12,
        note="printed without the transpose and the inverse: 8 against 0.5 in the scalar example (a gain above 1 "
             "and with units of P squared); the toolkit uses the standard gain"),
    Claim(
        "liao-wvc-fewer-gcp", _P, (320, 489), "ordering",
        "WVC lowers the number of indoor control points the solution needs.",
        untestable="needs a run() keyword for the number or spacing of control points (ins_constraints has none)",
        decided_in=_POS12),
    Claim(
        "liao-window-matches-gcp-spacing", _P, (202, 481), "trend",
        "The best window (10-20 s) matches the control-point spacing (one about every 15 s); denser control "
        "points or better constraints would shorten it.",
        untestable="needs a run() keyword for the control-point spacing (ins_online / study_ins_window have none)",
        decided_in=_FIG19),
)
