"""The registry of Wi-Fi estimator factories: one name -> one factory, used by experiments and the CLI.

A factory is ``factory(k=None, metric="euclidean", not_heard_dbm=...) -> estimator`` (an unfitted
scikit-learn style estimator of :mod:`ilocalg.wifi`); ``k`` is the method's main count (neighbours
K for the KNN family, strongest APs k for RADAR and Horus; ``None``: the method's default).
Adding a method is one decorator::

    @register_estimator("my_method")
    def _my_method(k=None, metric="euclidean", not_heard_dbm=-104.0): return MyEstimator(...)

:data:`PAPER_ESTIMATORS` names the three configurations the papers use (Chiu 2013: Simplified-RADAR
with N = 3, Simplified-Horus with 1 dB bins; Luo et al. 2017: KNN, Manhattan, K = 5), built through
the same factories by :func:`paper_estimators`.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 3.
Luo, S. et al. (2017). Indoor positioning technology based on location fingerprint and pedestrian
track. Computer Systems & Applications.
Eq. (1)-(2).
"""

from __future__ import annotations

from collections.abc import Callable

from ilocalg.wifi.horus import SimplifiedHorus
from ilocalg.wifi.knn import KnnFingerprint
from ilocalg.wifi.radar import SimplifiedRadar

__all__ = [
    "ESTIMATORS",
    "METRICS",
    "BEST_CONFIG",
    "PAPER_ESTIMATORS",
    "register_estimator",
    "make_estimator",
    "paper_estimators",
]

#: name -> factory (filled by :func:`register_estimator`).
ESTIMATORS: dict[str, Callable] = {}
#: Distances of the KNN family (Minkowski p = 1 and p = 2).
METRICS = {"manhattan": 1, "euclidean": 2}
#: RSSI substituted for "not heard" unless told otherwise (UJIIndoorLoc's weakest reading), dBm.
DEFAULT_NOT_HEARD_DBM = -104.0

#: The "best" configuration on UJIIndoorLoc, chosen on the selection half of its validation set
#: (experiment ``wifi_ujiindoorloc``): Simplified-RADAR's union-of-strongest-APs distance with
#: k = 5 APs, N = 12 neighbours, 1/d^2 weights.
BEST_CONFIG = {"kind": "radar", "k_aps": 5, "n_neighbors": 12}


def register_estimator(name: str):
    """Decorator: register an estimator factory under ``name``."""
    def deco(factory):
        if name in ESTIMATORS and ESTIMATORS[name] is not factory:
            raise ValueError(f"Wi-Fi estimator {name!r} is already registered")
        ESTIMATORS[name] = factory
        return factory

    return deco


def _p(metric: str) -> int:
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {sorted(METRICS)}, got {metric!r}")
    return METRICS[metric]


@register_estimator("radar")
def _radar(k=None, metric="euclidean", not_heard_dbm=DEFAULT_NOT_HEARD_DBM):
    """Simplified-RADAR, the ``k`` strongest APs (default 5), N = 3 nearest training points, each at the
    distance of its nearest stored scan (Chiu 2013 eq. 1-3, L283, L287)."""
    _p(metric)
    return SimplifiedRadar(k_aps=k or 5, n_neighbors=3, not_heard_dbm=not_heard_dbm)


@register_estimator("horus")
def _horus(k=None, metric="euclidean", not_heard_dbm=DEFAULT_NOT_HEARD_DBM):
    """Simplified-Horus, the ``k`` strongest APs (default 5), 1 dB bins (Chiu 2013 eq. 5-7)."""
    _p(metric)
    return SimplifiedHorus(k_aps=k or 5, bin_width_db=1.0, prob_floor=1e-3, not_heard_dbm=not_heard_dbm)


@register_estimator("knn")
def _knn(k=None, metric="euclidean", not_heard_dbm=DEFAULT_NOT_HEARD_DBM):
    """KNN, ``k`` neighbours (default 5), uniform weights (Luo et al. 2017 eq. 1-2)."""
    return KnnFingerprint(n_neighbors=k or 5, p=_p(metric), weights="uniform", not_heard_dbm=not_heard_dbm)


@register_estimator("wknn")
def _wknn(k=None, metric="euclidean", not_heard_dbm=DEFAULT_NOT_HEARD_DBM):
    """Weighted KNN, ``k`` neighbours (default 5), 1/d weights."""
    return KnnFingerprint(n_neighbors=k or 5, p=_p(metric), weights="distance", not_heard_dbm=not_heard_dbm)


@register_estimator("best")
def _best(k=None, metric="euclidean", not_heard_dbm=DEFAULT_NOT_HEARD_DBM):
    """:data:`BEST_CONFIG`: Simplified-RADAR, 5 APs, ``k`` neighbours (default 12)."""
    _p(metric)
    # chosen with one neighbour per reference row (point_distance=None), as it was selected
    return SimplifiedRadar(k_aps=BEST_CONFIG["k_aps"], n_neighbors=k or BEST_CONFIG["n_neighbors"],
                           not_heard_dbm=not_heard_dbm, point_distance=None)


@register_estimator("toolkit")
def _toolkit(k=None, metric="euclidean", not_heard_dbm=DEFAULT_NOT_HEARD_DBM):
    """The toolkit's UJIIndoorLoc headline (:func:`ilocalg.wifi.candidates.toolkit_estimator`: offset searches,
    cascade, spot-averaged and rank members, Sorensen distances), ``k`` neighbours per member (default 8). Fitted on
    ``[x_m, y_m, floor, building]``; it votes floor and building itself. ``metric`` is not used (its members
    fix their own distance)."""
    from ilocalg.wifi.candidates import toolkit_estimator

    _p(metric)
    return toolkit_estimator(k, not_heard_dbm)


def make_estimator(name: str, k: int | None = None, metric: str = "euclidean",
                   not_heard_dbm: float = DEFAULT_NOT_HEARD_DBM):
    """An unfitted estimator from the factory registered as ``name``."""
    if name not in ESTIMATORS:
        raise ValueError(f"method must be one of {tuple(ESTIMATORS)}, got {name!r}")
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {sorted(METRICS)}, got {metric!r}")
    return ESTIMATORS[name](k=k, metric=metric, not_heard_dbm=not_heard_dbm)


#: The papers' three configurations: label -> (registry name, k or None for "the AP count", metric).
PAPER_ESTIMATORS = {
    "Simplified-RADAR": ("radar", None, "euclidean"),
    "Simplified-Horus": ("horus", None, "euclidean"),
    "KNN (Manhattan, K=5)": ("knn", 5, "manhattan"),
}


def paper_estimators(not_heard_dbm: float, k_aps: int = 5) -> dict:
    """The three estimators as configured in the papers (RADAR N = 3; Horus 1 dB bins; KNN a = 1, K = 5).

    ``k_aps`` is the strongest-AP count of RADAR and Horus.
    """
    return {label: make_estimator(name, k_aps if k is None else k, metric, not_heard_dbm)
            for label, (name, k, metric) in PAPER_ESTIMATORS.items()}
