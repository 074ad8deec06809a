"""Published values of the INS papers, as labelled references beside reproduced values (never used to compute).

Liao, Chiang, Zhou, Li (2016), Tables 4-11: ``LIAO_TABLES[(phone, method, stat, kind)]`` with ``kind``
"pos" -> (N, E, H) errors in metres and "att" -> (Roll, Pitch, Heading) errors in degrees; ``stat`` is
"max", "rms" or "std"; :func:`paper_value` reads one value and :func:`side_by_side` lays a table of
reproduced errors out as the paper does, each paper value beside the reproduced one.

Hartmann et al. (2010) as summarised by Yeh & Huang's image/inertial survey, Table 2 (overall row):
``HARTMANN_TABLE2_OVERALL``.

References
----------
Liao, Chiang, Zhou, Li (2016), "Using the on-line smoothing and constraint algorithms to improve the
accuracy of pedestrian indoor navigation", Tables 4-11.
Yeh & Huang, image/inertial positioning survey (teaching report, undated), sec. 5, Table 2, after
Hartmann, Link, Trommer (2010), IEEE/ION PLANS, pp. 319-326.
"""

from __future__ import annotations

import pandas as pd

from ilocalg.papers import PAPERS

__all__ = ["LIAO_2016", "LIAO_TABLES", "paper_value", "side_by_side", "HARTMANN_2010", "HARTMANN_TABLE2_OVERALL"]

#: Label of Liao et al. (2016) in comparison rows (the paper's one short name).
LIAO_2016 = PAPERS["liao"]
#: Label of Hartmann et al. (2010)'s results in comparison rows: the survey that reports them (its Table 2).
HARTMANN_2010 = PAPERS["survey"]

# ---- published values: Liao et al. (2016), Tables 4 (Samsung position), 5 (Samsung attitude), 6-7 (iPhone),
# ---- 8-11 (Filtering vs online smoothing windows, Samsung then iPhone) --------------------------------------
LIAO_TABLES = {
    ('Samsung', 'Filtering + NHC/ZUPT', 'max', 'pos'): (42.4434, 17.8689, 9.1891),
    ('Samsung', 'Filtering + WVC/ZUPT', 'max', 'pos'): (8.2482, 12.6542, 8.1319),
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'max', 'pos'): (5.2678, 3.451, 4.2113),
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'max', 'pos'): (0.9934, 1.5437, 0.8396),
    ('Samsung', 'Filtering + NHC/ZUPT', 'rms', 'pos'): (14.8002, 5.1419, 3.6398),
    ('Samsung', 'Filtering + WVC/ZUPT', 'rms', 'pos'): (1.979, 5.4046, 3.7849),
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'rms', 'pos'): (1.23, 0.9918, 0.8697),
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'pos'): (0.347, 0.3967, 0.1928),
    ('Samsung', 'Filtering + NHC/ZUPT', 'std', 'pos'): (10.8298, 4.5642, 2.8352),
    ('Samsung', 'Filtering + WVC/ZUPT', 'std', 'pos'): (1.9672, 4.501, 2.6703),
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'std', 'pos'): (1.2023, 0.9531, 0.6861),
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'std', 'pos'): (0.3471, 0.3735, 0.1917),
    ('Samsung', 'Filtering + NHC/ZUPT', 'max', 'att'): (3.9337, 30.9506, 165.9032),
    ('Samsung', 'Filtering + WVC/ZUPT', 'max', 'att'): (3.9861, 10.7497, 76.7442),
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'max', 'att'): (3.6279, 10.7743, 152.7002),
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'max', 'att'): (3.3745, 4.3051, 163.9725),
    ('Samsung', 'Filtering + NHC/ZUPT', 'rms', 'att'): (1.6547, 2.2114, 11.2172),
    ('Samsung', 'Filtering + WVC/ZUPT', 'rms', 'att'): (1.6406, 1.6758, 8.8643),
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'rms', 'att'): (1.6132, 1.6947, 8.9252),
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'att'): (1.515, 1.301, 13.896),
    ('Samsung', 'Filtering + NHC/ZUPT', 'std', 'att'): (0.863, 1.9621, 10.3672),
    ('Samsung', 'Filtering + WVC/ZUPT', 'std', 'att'): (0.8259, 1.2997, 6.1352),
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'std', 'att'): (0.8141, 1.2968, 8.7811),
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'std', 'att'): (0.6065, 0.8834, 13.8562),
    ('iPhone', 'Filtering + NHC/ZUPT', 'max', 'pos'): (18.0619, 82.6971, 6.8075),
    ('iPhone', 'Filtering + WVC/ZUPT', 'max', 'pos'): (15.2382, 10.5535, 4.2622),
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'max', 'pos'): (3.6413, 8.8276, 4.2631),
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'max', 'pos'): (1.8793, 2.8986, 0.7766),
    ('iPhone', 'Filtering + NHC/ZUPT', 'rms', 'pos'): (4.6846, 14.599, 3.449),
    ('iPhone', 'Filtering + WVC/ZUPT', 'rms', 'pos'): (8.9068, 3.7412, 1.1919),
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'rms', 'pos'): (0.9885, 1.6341, 0.9695),
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'pos'): (0.5507, 0.581, 0.2295),
    ('iPhone', 'Filtering + NHC/ZUPT', 'std', 'pos'): (3.8666, 14.5965, 2.9353),
    ('iPhone', 'Filtering + WVC/ZUPT', 'std', 'pos'): (5.8658, 3.5451, 1.1807),
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'std', 'pos'): (0.9784, 1.6314, 0.9493),
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'std', 'pos'): (0.548, 0.5714, 0.2037),
    ('iPhone', 'Filtering + NHC/ZUPT', 'max', 'att'): (5.6265, 5.9168, 118.4948),
    ('iPhone', 'Filtering + WVC/ZUPT', 'max', 'att'): (5.5191, 6.572, 121.1888),
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'max', 'att'): (5.404, 6.1171, 119.2676),
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'max', 'att'): (4.78, 6.0273, 124.9589),
    ('iPhone', 'Filtering + NHC/ZUPT', 'rms', 'att'): (1.283, 1.8301, 23.4859),
    ('iPhone', 'Filtering + WVC/ZUPT', 'rms', 'att'): (1.2675, 1.6899, 23.6683),
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'rms', 'att'): (1.2703, 1.6635, 23.7835),
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'att'): (1.2498, 1.5886, 23.6394),
    ('iPhone', 'Filtering + NHC/ZUPT', 'std', 'att'): (1.2305, 1.7372, 23.2259),
    ('iPhone', 'Filtering + WVC/ZUPT', 'std', 'att'): (1.2155, 1.6706, 23.4418),
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'std', 'att'): (1.2209, 1.6239, 23.7836),
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'std', 'att'): (1.1879, 1.4946, 23.6151),
    ('Samsung', 'Filtering', 'max', 'pos'): (5.2678, 3.451, 4.2113),
    ('Samsung', 'Online 5sec', 'max', 'pos'): (5.9395, 3.9361, 3.2414),
    ('Samsung', 'Online 10sec', 'max', 'pos'): (3.8347, 3.3244, 1.5016),
    ('Samsung', 'Online 20sec', 'max', 'pos'): (4.9408, 2.48, 1.4568),
    ('Samsung', 'Filtering', 'rms', 'pos'): (1.23, 0.9918, 0.8697),
    ('Samsung', 'Online 5sec', 'rms', 'pos'): (1.0854, 0.9195, 0.5467),
    ('Samsung', 'Online 10sec', 'rms', 'pos'): (0.6484, 0.7452, 0.3804),
    ('Samsung', 'Online 20sec', 'rms', 'pos'): (0.6913, 0.6346, 0.3586),
    ('Samsung', 'Filtering', 'std', 'pos'): (1.2023, 0.9531, 0.6861),
    ('Samsung', 'Online 5sec', 'std', 'pos'): (1.0858, 0.8942, 0.4833),
    ('Samsung', 'Online 10sec', 'std', 'pos'): (0.6417, 0.7448, 0.3633),
    ('Samsung', 'Online 20sec', 'std', 'pos'): (0.6898, 0.628, 0.3589),
    ('Samsung', 'Filtering', 'max', 'att'): (3.6279, 10.7743, 152.7002),
    ('Samsung', 'Online 5sec', 'max', 'att'): (3.5914, 4.8251, 144.6131),
    ('Samsung', 'Online 10sec', 'max', 'att'): (3.5304, 5.1947, 121.8075),
    ('Samsung', 'Online 20sec', 'max', 'att'): (3.601, 4.7899, 176.2538),
    ('Samsung', 'Filtering', 'rms', 'att'): (1.6132, 1.6947, 8.9252),
    ('Samsung', 'Online 5sec', 'rms', 'att'): (1.5722, 1.4565, 9.2053),
    ('Samsung', 'Online 10sec', 'rms', 'att'): (1.6012, 1.4674, 6.8155),
    ('Samsung', 'Online 20sec', 'rms', 'att'): (1.569, 1.3635, 12.2263),
    ('Samsung', 'Filtering', 'std', 'att'): (0.8141, 1.2968, 8.7811),
    ('Samsung', 'Online 5sec', 'std', 'att'): (0.655, 1.0274, 9.1029),
    ('Samsung', 'Online 10sec', 'std', 'att'): (0.6675, 0.9689, 6.6363),
    ('Samsung', 'Online 20sec', 'std', 'att'): (0.6652, 0.9149, 12.2072),
    ('iPhone', 'Filtering', 'max', 'pos'): (3.6413, 8.8276, 4.2631),
    ('iPhone', 'Online 5sec', 'max', 'pos'): (4.768, 8.8186, 4.1972),
    ('iPhone', 'Online 10sec', 'max', 'pos'): (4.2114, 8.2043, 3.15),
    ('iPhone', 'Online 20sec', 'max', 'pos'): (3.2674, 5.6132, 3.9008),
    ('iPhone', 'Filtering', 'rms', 'pos'): (0.9885, 1.6341, 0.9695),
    ('iPhone', 'Online 5sec', 'rms', 'pos'): (1.0969, 1.553, 0.8141),
    ('iPhone', 'Online 10sec', 'rms', 'pos'): (0.8574, 1.2766, 0.6265),
    ('iPhone', 'Online 20sec', 'rms', 'pos'): (0.6907, 0.7679, 0.4985),
    ('iPhone', 'Filtering', 'std', 'pos'): (0.9784, 1.6314, 0.9493),
    ('iPhone', 'Online 5sec', 'std', 'pos'): (1.0967, 1.5431, 0.8072),
    ('iPhone', 'Online 10sec', 'std', 'pos'): (0.858, 1.2591, 0.6222),
    ('iPhone', 'Online 20sec', 'std', 'pos'): (0.69, 0.7572, 0.4989),
    ('iPhone', 'Filtering', 'max', 'att'): (5.404, 6.1171, 119.2676),
    ('iPhone', 'Online 5sec', 'max', 'att'): (5.3331, 6.0057, 124.9439),
    ('iPhone', 'Online 10sec', 'max', 'att'): (5.3331, 5.9968, 113.9289),
    ('iPhone', 'Online 20sec', 'max', 'att'): (5.468, 5.6365, 125.4649),
    ('iPhone', 'Filtering', 'rms', 'att'): (1.2703, 1.6635, 23.7835),
    ('iPhone', 'Online 5sec', 'rms', 'att'): (1.2434, 1.5994, 23.6365),
    ('iPhone', 'Online 10sec', 'rms', 'att'): (1.2427, 1.5391, 23.0376),
    ('iPhone', 'Online 20sec', 'rms', 'att'): (1.193, 1.5398, 24.3203),
    ('iPhone', 'Filtering', 'std', 'att'): (1.2209, 1.6239, 23.7836),
    ('iPhone', 'Online 5sec', 'std', 'att'): (1.2101, 1.5776, 23.6481),
    ('iPhone', 'Online 10sec', 'std', 'att'): (1.2127, 1.5115, 23.0553),
    ('iPhone', 'Online 20sec', 'std', 'att'): (1.1745, 1.5056, 24.3132),
}

# ---- published values: Hartmann et al. (2010) via Yeh & Huang's survey, Table 2, overall row ---------------
HARTMANN_TABLE2_OVERALL = {
    "mean_dev_x_m": 0.0075, "mean_dev_y_m": 0.0077, "mean_dev_z_m": 0.0164,
    "max_dev_x_m": 0.1540, "max_dev_y_m": 0.1778, "max_dev_z_m": 0.1489,
    "vt_rate_hz": 5.8229, "outage_max_s": 2.2405, "outages_over_1s": 21.5,
}
# ---- end of published values -------------------------------------------------------------------------------


def paper_value(phone: str, method: str, stat: str, axis: str) -> float:
    """One value of Liao et al. (2016), e.g. ``paper_value("Samsung", "Filtering", "rms", "N")``."""
    if axis in ("N", "E", "H"):
        kind, i = "pos", "NEH".index(axis)
    elif axis in ("Roll", "Pitch", "Heading"):
        kind, i = "att", ("Roll", "Pitch", "Heading").index(axis)
    else:
        raise ValueError(f"axis must be N, E, H, Roll, Pitch or Heading, got {axis!r}")
    try:
        return LIAO_TABLES[(phone, method, stat, kind)][i]
    except KeyError:
        raise ValueError(f"no paper value for {(phone, method, stat, axis)}") from None


def side_by_side(errors: pd.DataFrame, axes) -> pd.DataFrame:
    """The paper's table layout (phone, stat, method) with ``<axis> paper`` beside ``<axis> sim``.

    ``errors`` has columns ``phone``, ``method``, ``stat`` and one per axis (e.g. "N", "E", "H").
    """
    out = []
    for _, r in errors.iterrows():
        row = {"phone": r["phone"], "stat": r["stat"], "method": r["method"]}
        for ax in axes:
            row[f"{ax} paper"] = paper_value(r["phone"], r["method"], r["stat"], ax)
            row[f"{ax} sim"] = r[ax]
        out.append(row)
    df = pd.DataFrame(out)
    order = {"max": 0, "rms": 1, "std": 2}
    return df.sort_values(["phone", "stat"], key=lambda c: c.map(order) if c.name == "stat" else c,
                          kind="stable").reset_index(drop=True)
