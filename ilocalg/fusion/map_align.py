"""Whole-walk map matching: place a dead-reckoned track on the floor map using Wi-Fi fixes.

A PDR track is accurate in shape over a short walk but its start and heading offset are unknown;
Wi-Fi fixes locate it only roughly (tens of metres on a sparsely surveyed floor). This module
searches every rigid placement ``p -> R(a) p + t`` of the track (``a`` on a grid of heading offsets,
``t`` on the walkable raster's cells) and scores it by

``log L = sum_fixes log[(1 - eps) N(z_j; R(a) p_j + t, R_j) + eps / area]``
``        + w n_off_map(a, t) log(blocked_weight) - a^2 / (2 sigma_a^2)``

(robust Wi-Fi likelihood, a penalty per track point off the walkable area, a Gaussian prior on
the offset). ``w = min(1, n_fixes / n_points)``: the track's points are strongly correlated, so the map
term counts as many observations as there are fixes, not one per point; and only placements the fixes
accept (Wi-Fi log-likelihood within ``wifi_margin`` nats per fix of the best) are candidates.
The walkable count for every translation at once is a correlation of the raster with
the track's point pattern, computed by shifted sums. The best placement is returned with the score
grid's summary. Offline (uses the whole walk), like the RTS smoother.

Beyond the papers; map matching of PDR tracks in the spirit of the map-constrained particle
filters (Woodman & Harle 2008), solved here by exhaustive search over rigid placements.

References
----------
Woodman O., Harle R., "Pedestrian localisation for indoor environments", UbiComp 2008 (the map
constraint on a PDR track); Umeyama S., IEEE TPAMI 13(4), 1991 (rigid placements).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.fusion.heading_offset import rotate_xy
from ilocalg.fusion.particle_filter import OccupancyGrid

__all__ = ["MapAlignResult", "map_align"]


@dataclass(frozen=True)
class MapAlignResult:
    """Best placement ``R(angle_rad) p + t_m`` and its score; ``track_m`` (n, 2) the placed track;
    ``off_map`` the number of placed track points off the walkable area; ``score_by_angle`` (n_angles,)
    the best score per candidate angle (for diagnostics)."""

    angle_rad: float
    t_m: np.ndarray
    track_m: np.ndarray
    score: float
    off_map: int
    score_by_angle: np.ndarray


def _walkable_counts(mask: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """``out[j, i] = sum_p mask[j + sy_p, i + sx_p]`` (zero outside the raster)."""
    ny, nx = mask.shape
    shifts = np.asarray(shifts, dtype=np.int64).reshape(-1, 2)
    # points in the same cell shift alike: each distinct shift once, times its count; counts up to 255 fit a byte
    uniq, count = np.unique(shifts, axis=0, return_counts=True)
    dtype = np.uint8 if len(shifts) <= 255 else np.int32
    out = np.zeros((ny, nx), dtype=dtype)
    m = mask.astype(dtype)
    for (sx, sy), k in zip(uniq.tolist(), count.tolist(), strict=True):
        # rows j with 0 <= j + sy < ny, columns i with 0 <= i + sx < nx
        j0, j1 = max(0, -sy), min(ny, ny - sy)
        i0, i1 = max(0, -sx), min(nx, nx - sx)
        if j0 >= j1 or i0 >= i1:
            continue
        part = m[j0 + sy:j1 + sy, i0 + sx:i1 + sx]
        out[j0:j1, i0:i1] += part if k == 1 else part * dtype(k)
    return out.astype(np.int32, copy=False)


def _wifi_loglik(q, fi, z, var, tx, ty, outlier_prob: float, area: float) -> np.ndarray:
    """``sum_j log[(1 - eps) N(z_j; q_{fi_j} + t, var_j I) + eps / area]`` for every translation ``t`` of the
    raster's cell centres ``(tx, ty)`` (ny, nx), the fixes added one after another.

    Far from a fix the Gaussian term is below an eighth of the floating-point spacing of ``eps / area``, so the
    fix's term there is exactly ``log(eps / area)``: each fix's Gaussian is evaluated only in the box of cells
    where it can change that sum (a disc of squared radius ``s_min``), the rest of the raster takes the constant,
    computed as the same array operation. Every cell gets the same floating-point operations in the same order
    as evaluating the Gaussian on the whole raster for every fix, so the same bits.
    """
    ny, nx = ty.size, tx.size
    floor = outlier_prob / area
    const = np.log(np.full((ny, nx), floor))      # log(eps / area), as the whole-raster expression gives it
    # (1 - eps) g < ulp(floor) / 8 (a margin of 2 under the half-spacing that rounding absorbs) wherever
    # (1 - eps) exp(-s / (2 var)) / (2 pi var) < ulp / 8, i.e. beyond the squared distance s_min
    tiny = np.spacing(floor) / 8.0
    sw = np.zeros((ny, nx))
    for j in range(fi.size):
        cx, cy = z[j] - q[fi[j]]
        dx2 = (tx - cx) ** 2
        dy2 = (ty - cy) ** 2
        v = var[j]
        peak = (1 - outlier_prob) / (2 * np.pi * v)
        s_min = 2.0 * v * np.log(peak / tiny) if peak > tiny else 0.0
        rows = np.flatnonzero(dy2 < s_min)
        cols = np.flatnonzero(dx2 < s_min)
        if rows.size and cols.size:
            r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
            e = dy2[r0:r1, None] + dx2[None, c0:c1]
            e *= -0.5                   # the whole-raster expression's operations, in place where exact
            e /= v
            g = np.exp(e)
            g /= 2 * np.pi * v
            g *= 1 - outlier_prob
            g += floor
            box = np.log(g)
            box += sw[r0:r1, c0:c1]
            sw += const
            sw[r0:r1, c0:c1] = box
        else:
            sw += const
    return sw


def map_align(track_xy_m, fix_index, fix_xy_m, fix_var_m2, grid: OccupancyGrid, angles_rad=None,
              sigma_angle_rad: float = 0.35, outlier_prob: float = 0.2, blocked_weight: float = 1e-3,
              max_points: int = 200, wifi_margin: float = 1.0, map_weight: float | None = None) -> MapAlignResult:
    """Best rigid placement of a relative track on the walkable map given fixes at some of its states.

    Parameters
    ----------
    track_xy_m : array_like (n, 2)
        Relative track (any origin), metres; rotations are about the origin, translations are
        the placement of the origin (searched over the raster's cell centres).
    fix_index : array_like of int (m,)
        State of the track each fix belongs to.
    fix_xy_m : array_like (m, 2)
    fix_var_m2 : float or array_like (m,)
        Isotropic variance of each fix.
    grid : OccupancyGrid
    angles_rad : array_like, optional
        Candidate heading offsets (default -0.6 .. 0.6 rad in 0.05 rad steps).
    sigma_angle_rad : float
        Prior standard deviation of the offset (centred on 0).
    outlier_prob, blocked_weight : float
        As in :func:`ilocalg.fusion.particle_filter.map_particle_filter`.
    max_points : int
        Track points used for the map term (evenly subsampled).
    wifi_margin : float
        Placements whose Wi-Fi log-likelihood is more than this many nats per fix below the best
        placement's are excluded (1 nat per fix: a mean fix residual about 1.4 sd larger).
    map_weight : float, optional
        Weight ``w`` of the map term (default ``min(1, n_fixes / n_points)``, see the module docstring).

    Returns
    -------
    MapAlignResult
    """
    p = np.asarray(track_xy_m, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 1 or not np.isfinite(p).all():
        raise ValueError(f"track_xy_m must be finite with shape (n >= 1, 2), got {p.shape}")
    fi = np.asarray(fix_index, dtype=np.int64).ravel()
    z = np.asarray(fix_xy_m, dtype=np.float64)
    if z.shape != (fi.size, 2) or not np.isfinite(z).all():
        raise ValueError(f"fix_xy_m must be finite with shape ({fi.size}, 2), got {z.shape}")
    if fi.size and ((fi < 0) | (fi >= p.shape[0])).any():
        raise ValueError(f"fix_index must lie in [0, {p.shape[0] - 1}]")
    var = np.broadcast_to(np.asarray(fix_var_m2, dtype=np.float64), (fi.size,))
    if (var <= 0).any():
        raise ValueError("fix_var_m2 must be > 0")
    if not (0 < outlier_prob < 1 and 0 < blocked_weight < 1 and sigma_angle_rad > 0):
        raise ValueError("need 0 < outlier_prob < 1, 0 < blocked_weight < 1 and sigma_angle_rad > 0")
    angles = np.arange(-0.6, 0.6 + 1e-9, 0.05) if angles_rad is None else np.asarray(angles_rad, dtype=np.float64)
    c = grid.cell_m
    ny, nx = grid.walkable_mask.shape
    tx = grid.x0_m + (np.arange(nx) + 0.5) * c
    ty = grid.y0_m + (np.arange(ny) + 0.5) * c
    sub = np.unique(np.linspace(0, p.shape[0] - 1, min(max_points, p.shape[0])).round().astype(np.int64))
    area = grid.area_m2
    lb = np.log(blocked_weight)
    # neighbouring track points are not independent map observations: the map term counts as many
    # observations as there are fixes (a track of 200 points otherwise outvotes 30 fixes and a wholly
    # walkable placement 20-30 m from every fix wins, as on the densely surveyed ILC site1 floors)
    map_w = min(1.0, max(fi.size, 1) / sub.size) if map_weight is None else float(map_weight)
    best = (-np.inf, 0.0, np.zeros(2), 0)
    by_angle = np.full(angles.size, -np.inf)
    # the Wi-Fi log-likelihood of every placement, per angle
    wifi_terms = [_wifi_loglik(rotate_xy(p, a), fi, z, var, tx, ty, outlier_prob, area) for a in angles]
    # placements the fixes reject (Wi-Fi log-likelihood more than wifi_margin nats per fix below the best
    # placement's) are not candidates, whatever the map says: the map chooses among Wi-Fi-consistent ones
    floor_ll = max(float(w.max()) for w in wifi_terms) - wifi_margin * max(fi.size, 1)
    for ai, a in enumerate(angles):
        q = rotate_xy(p, a)
        shifts = np.round(q[sub] / c).astype(np.int64)
        walk = _walkable_counts(grid.walkable_mask, shifts)
        s = map_w * (sub.size - walk) * lb - 0.5 * (a / sigma_angle_rad) ** 2 + wifi_terms[ai]
        # the origin (start) itself must be walkable
        s = np.where(grid.walkable_mask & (wifi_terms[ai] >= floor_ll), s, -np.inf)
        k = int(np.argmax(s))
        jj, ii = divmod(k, nx)
        by_angle[ai] = s[jj, ii]
        if s[jj, ii] > best[0]:
            best = (float(s[jj, ii]), float(a), np.array([tx[ii], ty[jj]]), int(sub.size - walk[jj, ii]))
    score, a, t, off = best
    if not np.isfinite(score):
        raise ValueError("map_align: no walkable placement")
    return MapAlignResult(a, t, rotate_xy(p, a) + t, score, off, by_angle)
