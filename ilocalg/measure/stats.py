"""Bootstrap intervals for measured statistics (seeded, cluster resampling).

References
----------
Efron, B. & Tibshirani, R. (1993), An Introduction to the Bootstrap, ch. 13 (percentile interval).
Davison, A. C. & Hinkley, D. V. (1997), Bootstrap Methods and their Application, sec. 3.8 (resampling
clusters when observations within a cluster are dependent).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Estimate", "bootstrap", "bootstrap_many", "N_BOOT", "SEED"]

#: bootstrap replicates and seed used for every interval in data/measured_parameters.csv
N_BOOT = 400
SEED = 20240


@dataclass(frozen=True)
class Estimate:
    """A measured statistic with its 95 % bootstrap interval.

    Attributes
    ----------
    value : float
        The statistic on all data.
    ci_low, ci_high : float
        2.5 % and 97.5 % percentiles of the bootstrap replicates.
    n : int
        Number of observations (values, or clusters when resampled by cluster).
    """

    value: float
    ci_low: float
    ci_high: float
    n: int

    def as_dict(self) -> dict:
        return {"value": self.value, "ci_low": self.ci_low, "ci_high": self.ci_high, "n": self.n}


def bootstrap(groups, statistic, n_boot: int = N_BOOT, rng=SEED, level: float = 0.95) -> Estimate:
    """Percentile bootstrap of ``statistic`` resampling whole groups (clusters) with replacement.

    Parameters
    ----------
    groups : sequence of array_like, or one 1-D array
        Observations per cluster (a walk, an AP, a recording). A plain 1-D array is resampled
        value by value (each value its own cluster). Clusters may hold rows of a 2-D array.
    statistic : callable
        ``statistic(values) -> float`` applied to the concatenation of the resampled clusters.
    n_boot : int
        Replicates (>= 50).
    rng : np.random.Generator | int | None
        Seed or generator; same seed, same interval.
    level : float
        Coverage of the interval, in (0, 1).

    Returns
    -------
    Estimate
    """
    return bootstrap_many(groups, lambda v: (statistic(v),), n_boot, rng, level)[0]


def bootstrap_many(groups, statistic, n_boot: int = N_BOOT, rng=SEED, level: float = 0.95) -> list[Estimate]:
    """:func:`bootstrap` of a statistic with several outputs on one set of draws.

    ``statistic(values)`` returns a sequence of floats; the result holds one :class:`Estimate` per output, each
    the one :func:`bootstrap` gives for that output alone with the same ``rng`` (the same resampled clusters),
    for the cost of one pass (e.g. several correlations of the same segments).
    """
    if n_boot < 50:
        raise ValueError(f"n_boot must be >= 50, got {n_boot}")
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must be in (0, 1), got {level}")
    r = np.random.default_rng(rng)
    a = (1.0 - level) / 2.0
    if isinstance(groups, np.ndarray) and groups.dtype != object and groups.ndim == 1:
        # each value its own cluster: same draws as the clustered path, vectorised
        x = groups
        k = x.size
        if k < 2:
            raise ValueError(f"bootstrap needs at least 2 non-empty groups, got {k}")
        reps = np.array([statistic(x[r.integers(0, k, size=k)]) for _ in range(n_boot)], dtype=np.float64)
        value = statistic(x)
    else:
        groups = [np.asarray(g) for g in groups if len(g) > 0]
        if len(groups) < 2:
            raise ValueError(f"bootstrap needs at least 2 non-empty groups, got {len(groups)}")
        value = statistic(np.concatenate(groups))
        k = len(groups)
        reps = np.empty((n_boot, len(value)))
        for b in range(n_boot):
            idx = r.integers(0, k, size=k)
            reps[b] = statistic(np.concatenate([groups[i] for i in idx]))
    out = []
    for j, v in enumerate(value):
        lo, hi = np.nanquantile(np.ascontiguousarray(reps[:, j]), [a, 1.0 - a])
        out.append(Estimate(value=float(v), ci_low=float(lo), ci_high=float(hi), n=k))
    return out
