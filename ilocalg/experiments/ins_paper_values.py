"""Published error tables of Liao, Chiang, Zhou, Li (2016), Tables 4-11 (reference values only).

Keys: ``(phone, method, stat, kind)`` with ``kind`` "pos" -> (N, E, H) in metres and "att" ->
(Roll, Pitch, Heading) in degrees; ``stat`` is "max", "rms" or "std". Every value is the paper's
reference, never used to compute anything.
"""

from __future__ import annotations

__all__ = ["INS_PAPER_TABLES", "paper_value"]

INS_PAPER_TABLES = {  # paper Tables 4-11 (reference values)
    ('Samsung', 'Filtering + NHC/ZUPT', 'max', 'pos'): (42.4434, 17.8689, 9.1891),  # paper Table 4
    ('Samsung', 'Filtering + WVC/ZUPT', 'max', 'pos'): (8.2482, 12.6542, 8.1319),  # paper Table 4
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'max', 'pos'): (5.2678, 3.451, 4.2113),  # paper Table 4
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'max', 'pos'): (0.9934, 1.5437, 0.8396),  # paper Table 4
    ('Samsung', 'Filtering + NHC/ZUPT', 'rms', 'pos'): (14.8002, 5.1419, 3.6398),  # paper Table 4
    ('Samsung', 'Filtering + WVC/ZUPT', 'rms', 'pos'): (1.979, 5.4046, 3.7849),  # paper Table 4
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'rms', 'pos'): (1.23, 0.9918, 0.8697),  # paper Table 4
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'pos'): (0.347, 0.3967, 0.1928),  # paper Table 4
    ('Samsung', 'Filtering + NHC/ZUPT', 'std', 'pos'): (10.8298, 4.5642, 2.8352),  # paper Table 4
    ('Samsung', 'Filtering + WVC/ZUPT', 'std', 'pos'): (1.9672, 4.501, 2.6703),  # paper Table 4
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'std', 'pos'): (1.2023, 0.9531, 0.6861),  # paper Table 4
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'std', 'pos'): (0.3471, 0.3735, 0.1917),  # paper Table 4
    ('Samsung', 'Filtering + NHC/ZUPT', 'max', 'att'): (3.9337, 30.9506, 165.9032),  # paper Table 5
    ('Samsung', 'Filtering + WVC/ZUPT', 'max', 'att'): (3.9861, 10.7497, 76.7442),  # paper Table 5
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'max', 'att'): (3.6279, 10.7743, 152.7002),  # paper Table 5
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'max', 'att'): (3.3745, 4.3051, 163.9725),  # paper Table 5
    ('Samsung', 'Filtering + NHC/ZUPT', 'rms', 'att'): (1.6547, 2.2114, 11.2172),  # paper Table 5
    ('Samsung', 'Filtering + WVC/ZUPT', 'rms', 'att'): (1.6406, 1.6758, 8.8643),  # paper Table 5
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'rms', 'att'): (1.6132, 1.6947, 8.9252),  # paper Table 5
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'att'): (1.515, 1.301, 13.896),  # paper Table 5
    ('Samsung', 'Filtering + NHC/ZUPT', 'std', 'att'): (0.863, 1.9621, 10.3672),  # paper Table 5
    ('Samsung', 'Filtering + WVC/ZUPT', 'std', 'att'): (0.8259, 1.2997, 6.1352),  # paper Table 5
    ('Samsung', 'Filtering + WVC/ZUPT + GCP', 'std', 'att'): (0.8141, 1.2968, 8.7811),  # paper Table 5
    ('Samsung', 'Smoothing + WVC/ZUPT + GCP', 'std', 'att'): (0.6065, 0.8834, 13.8562),  # paper Table 5
    ('iPhone', 'Filtering + NHC/ZUPT', 'max', 'pos'): (18.0619, 82.6971, 6.8075),  # paper Table 6
    ('iPhone', 'Filtering + WVC/ZUPT', 'max', 'pos'): (15.2382, 10.5535, 4.2622),  # paper Table 6
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'max', 'pos'): (3.6413, 8.8276, 4.2631),  # paper Table 6
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'max', 'pos'): (1.8793, 2.8986, 0.7766),  # paper Table 6
    ('iPhone', 'Filtering + NHC/ZUPT', 'rms', 'pos'): (4.6846, 14.599, 3.449),  # paper Table 6
    ('iPhone', 'Filtering + WVC/ZUPT', 'rms', 'pos'): (8.9068, 3.7412, 1.1919),  # paper Table 6
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'rms', 'pos'): (0.9885, 1.6341, 0.9695),  # paper Table 6
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'pos'): (0.5507, 0.581, 0.2295),  # paper Table 6
    ('iPhone', 'Filtering + NHC/ZUPT', 'std', 'pos'): (3.8666, 14.5965, 2.9353),  # paper Table 6
    ('iPhone', 'Filtering + WVC/ZUPT', 'std', 'pos'): (5.8658, 3.5451, 1.1807),  # paper Table 6
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'std', 'pos'): (0.9784, 1.6314, 0.9493),  # paper Table 6
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'std', 'pos'): (0.548, 0.5714, 0.2037),  # paper Table 6
    ('iPhone', 'Filtering + NHC/ZUPT', 'max', 'att'): (5.6265, 5.9168, 118.4948),  # paper Table 7
    ('iPhone', 'Filtering + WVC/ZUPT', 'max', 'att'): (5.5191, 6.572, 121.1888),  # paper Table 7
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'max', 'att'): (5.404, 6.1171, 119.2676),  # paper Table 7
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'max', 'att'): (4.78, 6.0273, 124.9589),  # paper Table 7
    ('iPhone', 'Filtering + NHC/ZUPT', 'rms', 'att'): (1.283, 1.8301, 23.4859),  # paper Table 7
    ('iPhone', 'Filtering + WVC/ZUPT', 'rms', 'att'): (1.2675, 1.6899, 23.6683),  # paper Table 7
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'rms', 'att'): (1.2703, 1.6635, 23.7835),  # paper Table 7
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'rms', 'att'): (1.2498, 1.5886, 23.6394),  # paper Table 7
    ('iPhone', 'Filtering + NHC/ZUPT', 'std', 'att'): (1.2305, 1.7372, 23.2259),  # paper Table 7
    ('iPhone', 'Filtering + WVC/ZUPT', 'std', 'att'): (1.2155, 1.6706, 23.4418),  # paper Table 7
    ('iPhone', 'Filtering + WVC/ZUPT + GCP', 'std', 'att'): (1.2209, 1.6239, 23.7836),  # paper Table 7
    ('iPhone', 'Smoothing + WVC/ZUPT + GCP', 'std', 'att'): (1.1879, 1.4946, 23.6151),  # paper Table 7
    ('Samsung', 'Filtering', 'max', 'pos'): (5.2678, 3.451, 4.2113),  # paper Table 8
    ('Samsung', 'Online 5sec', 'max', 'pos'): (5.9395, 3.9361, 3.2414),  # paper Table 8
    ('Samsung', 'Online 10sec', 'max', 'pos'): (3.8347, 3.3244, 1.5016),  # paper Table 8
    ('Samsung', 'Online 20sec', 'max', 'pos'): (4.9408, 2.48, 1.4568),  # paper Table 8
    ('Samsung', 'Filtering', 'rms', 'pos'): (1.23, 0.9918, 0.8697),  # paper Table 8
    ('Samsung', 'Online 5sec', 'rms', 'pos'): (1.0854, 0.9195, 0.5467),  # paper Table 8
    ('Samsung', 'Online 10sec', 'rms', 'pos'): (0.6484, 0.7452, 0.3804),  # paper Table 8
    ('Samsung', 'Online 20sec', 'rms', 'pos'): (0.6913, 0.6346, 0.3586),  # paper Table 8
    ('Samsung', 'Filtering', 'std', 'pos'): (1.2023, 0.9531, 0.6861),  # paper Table 8
    ('Samsung', 'Online 5sec', 'std', 'pos'): (1.0858, 0.8942, 0.4833),  # paper Table 8
    ('Samsung', 'Online 10sec', 'std', 'pos'): (0.6417, 0.7448, 0.3633),  # paper Table 8
    ('Samsung', 'Online 20sec', 'std', 'pos'): (0.6898, 0.628, 0.3589),  # paper Table 8
    ('Samsung', 'Filtering', 'max', 'att'): (3.6279, 10.7743, 152.7002),  # paper Table 9
    ('Samsung', 'Online 5sec', 'max', 'att'): (3.5914, 4.8251, 144.6131),  # paper Table 9
    ('Samsung', 'Online 10sec', 'max', 'att'): (3.5304, 5.1947, 121.8075),  # paper Table 9
    ('Samsung', 'Online 20sec', 'max', 'att'): (3.601, 4.7899, 176.2538),  # paper Table 9
    ('Samsung', 'Filtering', 'rms', 'att'): (1.6132, 1.6947, 8.9252),  # paper Table 9
    ('Samsung', 'Online 5sec', 'rms', 'att'): (1.5722, 1.4565, 9.2053),  # paper Table 9
    ('Samsung', 'Online 10sec', 'rms', 'att'): (1.6012, 1.4674, 6.8155),  # paper Table 9
    ('Samsung', 'Online 20sec', 'rms', 'att'): (1.569, 1.3635, 12.2263),  # paper Table 9
    ('Samsung', 'Filtering', 'std', 'att'): (0.8141, 1.2968, 8.7811),  # paper Table 9
    ('Samsung', 'Online 5sec', 'std', 'att'): (0.655, 1.0274, 9.1029),  # paper Table 9
    ('Samsung', 'Online 10sec', 'std', 'att'): (0.6675, 0.9689, 6.6363),  # paper Table 9
    ('Samsung', 'Online 20sec', 'std', 'att'): (0.6652, 0.9149, 12.2072),  # paper Table 9
    ('iPhone', 'Filtering', 'max', 'pos'): (3.6413, 8.8276, 4.2631),  # paper Table 10
    ('iPhone', 'Online 5sec', 'max', 'pos'): (4.768, 8.8186, 4.1972),  # paper Table 10
    ('iPhone', 'Online 10sec', 'max', 'pos'): (4.2114, 8.2043, 3.15),  # paper Table 10
    ('iPhone', 'Online 20sec', 'max', 'pos'): (3.2674, 5.6132, 3.9008),  # paper Table 10
    ('iPhone', 'Filtering', 'rms', 'pos'): (0.9885, 1.6341, 0.9695),  # paper Table 10
    ('iPhone', 'Online 5sec', 'rms', 'pos'): (1.0969, 1.553, 0.8141),  # paper Table 10
    ('iPhone', 'Online 10sec', 'rms', 'pos'): (0.8574, 1.2766, 0.6265),  # paper Table 10
    ('iPhone', 'Online 20sec', 'rms', 'pos'): (0.6907, 0.7679, 0.4985),  # paper Table 10
    ('iPhone', 'Filtering', 'std', 'pos'): (0.9784, 1.6314, 0.9493),  # paper Table 10
    ('iPhone', 'Online 5sec', 'std', 'pos'): (1.0967, 1.5431, 0.8072),  # paper Table 10
    ('iPhone', 'Online 10sec', 'std', 'pos'): (0.858, 1.2591, 0.6222),  # paper Table 10
    ('iPhone', 'Online 20sec', 'std', 'pos'): (0.69, 0.7572, 0.4989),  # paper Table 10
    ('iPhone', 'Filtering', 'max', 'att'): (5.404, 6.1171, 119.2676),  # paper Table 11
    ('iPhone', 'Online 5sec', 'max', 'att'): (5.3331, 6.0057, 124.9439),  # paper Table 11
    ('iPhone', 'Online 10sec', 'max', 'att'): (5.3331, 5.9968, 113.9289),  # paper Table 11
    ('iPhone', 'Online 20sec', 'max', 'att'): (5.468, 5.6365, 125.4649),  # paper Table 11
    ('iPhone', 'Filtering', 'rms', 'att'): (1.2703, 1.6635, 23.7835),  # paper Table 11
    ('iPhone', 'Online 5sec', 'rms', 'att'): (1.2434, 1.5994, 23.6365),  # paper Table 11
    ('iPhone', 'Online 10sec', 'rms', 'att'): (1.2427, 1.5391, 23.0376),  # paper Table 11
    ('iPhone', 'Online 20sec', 'rms', 'att'): (1.193, 1.5398, 24.3203),  # paper Table 11
    ('iPhone', 'Filtering', 'std', 'att'): (1.2209, 1.6239, 23.7836),  # paper Table 11
    ('iPhone', 'Online 5sec', 'std', 'att'): (1.2101, 1.5776, 23.6481),  # paper Table 11
    ('iPhone', 'Online 10sec', 'std', 'att'): (1.2127, 1.5115, 23.0553),  # paper Table 11
    ('iPhone', 'Online 20sec', 'std', 'att'): (1.1745, 1.5056, 24.3132),  # paper Table 11
}  # end of paper tables


def paper_value(phone: str, method: str, stat: str, axis: str) -> float:
    """One published value (paper reference), e.g. ``paper_value("Samsung", "Filtering", "rms", "N")``."""
    if axis in ("N", "E", "H"):
        kind, i = "pos", "NEH".index(axis)
    elif axis in ("Roll", "Pitch", "Heading"):
        kind, i = "att", ("Roll", "Pitch", "Heading").index(axis)
    else:
        raise ValueError(f"axis must be N, E, H, Roll, Pitch or Heading, got {axis!r}")
    try:
        return INS_PAPER_TABLES[(phone, method, stat, kind)][i]  # paper reference value
    except KeyError:
        raise ValueError(f"no paper value for {(phone, method, stat, axis)}") from None
