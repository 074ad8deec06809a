"""A particle filter for PDR + Wi-Fi constrained by the floor map's walkable area.

Beyond the papers (the i-Loc thesis and 罗思奇 et al. fuse with a Kalman filter). Each particle
carries a position, a heading correction ``dtheta`` (the unknown offset between the PDR heading
and the map frame, a slow random walk) and a step-length scale. Per detected step ``k``::

    dtheta_i <- dtheta_i + N(0, sigma_offset_walk_rad^2)
    d_i       = D_k scale_i (1 + sigma_step_rel N(0, 1))
    th_i      = theta_k + dtheta_i + sigma_heading_rad N(0, 1)
    p_i      <- p_i + d_i [cos th_i, sin th_i]

a particle whose new position is not walkable (:class:`OccupancyGrid`) gets weight zero (the map
constraint); a Wi-Fi fix ``z`` with covariance ``R`` multiplies the weights by the robust
likelihood ``(1 - eps) N(z; p_i, R) + eps / area`` (``eps = outlier_prob``: far-off fixes cannot
wipe out the particle set). Systematic resampling when the effective sample size drops below
``resample_frac * N``. If every particle is blocked or the weights underflow, the weights are
reset to uniform (counted in ``n_reset``): the filter never silently stops.

Recovery (``recovery="augmented"``): once the cloud has left the region of the fixes, every
particle gets about the floor ``eps / area`` and the fixes stop being informative; nothing in the
plain filter brings the particles back. Augmented MCL (Thrun, Burgard, Fox 2005, sec. 8.3.5,
Table 8.3) follows the average fix likelihood ``w_avg = sum_i w_i lik_i`` (normalised weights
before the fix) with a short- and a long-term average::

    w_slow <- w_slow + alpha_slow (w_avg - w_slow)
    w_fast <- w_fast + alpha_fast (w_avg - w_fast)

(both start at the first ``w_avg``, as ROS amcl's ``pf_update_sensor`` does) and, at a fix where
``p = max(0, 1 - w_fast / w_slow) > 0``, resamples and replaces each particle with probability
``p`` by a new one drawn from the fix's own distribution ``N(z, R)`` restricted to the walkable
cells (sensor resetting localisation, Lenser & Veloso 2000), with a heading correction and step
scale from their initial distributions. The rates default to the values the ROS amcl
documentation suggests (``recovery_alpha_slow`` 0.001, ``recovery_alpha_fast`` 0.1; also the
defaults of Beluga's ``AmclParams``), not to values fitted here. An injected particle's ancestral
path (for ``x_smooth``) is that of the particle it replaces. ``recovery="amcl"`` is the same with
ROS amcl's one addition (``pf_update_resample``): both averages restart after every injection "to
avoid spiraling off into complete randomness".

Smoothing: every state's particles and their resampling ancestry are kept, and the final
particles' ancestral paths, weighted by the final weights, give a whole-walk estimate (the
"genealogy" smoother; Kitagawa 1996), consistent with the map.

References
----------
Arulampalam, Maskell, Gordon, Clapp, "A tutorial on particle filters ...", IEEE TSP 50(2), 2002
(SIR filter, systematic resampling); Kitagawa G., "Monte Carlo filter and smoother ...", JCGS
5(1), 1996 (smoothing by storing ancestral paths); map-matching particle filters for PDR, e.g.
Woodman & Harle, "Pedestrian localisation for indoor environments", UbiComp 2008.
Thrun, Burgard, Fox, *Probabilistic Robotics*, MIT Press 2005, sec. 8.3.5, Table 8.3
(Augmented MCL); Lenser & Veloso, "Sensor resetting localization for poorly modelled mobile robots",
ICRA 2000; ROS amcl, http://wiki.ros.org/amcl (parameters ``recovery_alpha_slow``,
``recovery_alpha_fast``: "A good value might be 0.001" / "0.1") and its ``pf.c``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ilocalg.units import as_rng

__all__ = ["OccupancyGrid", "PFResult", "systematic_resample", "map_particle_filter", "RECOVERIES"]

#: Recovery mechanisms of :func:`map_particle_filter` (None: none).
RECOVERIES = (None, "augmented", "amcl")


@dataclass(frozen=True)
class OccupancyGrid:
    """A boolean walkable raster.

    Attributes
    ----------
    walkable_mask : ndarray of bool, shape (ny, nx)
        ``walkable_mask[j, i]`` covers ``x in [x0 + i c, x0 + (i+1) c)``, ``y in [y0 + j c, ...)``.
    x0_m, y0_m, cell_m : float
    """

    walkable_mask: np.ndarray
    x0_m: float
    y0_m: float
    cell_m: float

    @classmethod
    def from_polygons(cls, outline, obstacles=(), x_range_m=None, y_range_m=None, cell_m: float = 0.5):
        """Rasterise walkable = inside an outline ring and outside every obstacle ring (OpenCV ``fillPoly``).

        Parameters
        ----------
        outline, obstacles : sequence of array_like (n, 2)
            Rings in metres (e.g. :attr:`ilocalg.io.ilc.IlcFloorMap.outline` / ``obstacles``).
        x_range_m, y_range_m : (min, max), optional
            Raster extent (default: the outline's bounding box).
        cell_m : float

        A cell is walkable when its centre is (up to OpenCV's 1/16-cell sub-pixel precision); several
        outline rings are combined by union, obstacles are cut out of it (the rule of
        :meth:`ilocalg.io.ilc.IlcFloorMap.walkable`). This is the one way the toolkit builds a walkable
        raster.
        """
        import cv2  # imported here so that `import ilocalg` stays light

        if not cell_m > 0:
            raise ValueError(f"cell_m must be > 0, got {cell_m!r}")
        rings = [np.asarray(r, dtype=np.float64) for r in outline]
        if not rings or any(r.ndim != 2 or r.shape[1] != 2 or r.shape[0] < 3 for r in rings):
            raise ValueError("outline must be a non-empty sequence of (n >= 3, 2) rings")
        allp = np.concatenate(rings)
        x0, x1 = x_range_m if x_range_m is not None else (allp[:, 0].min(), allp[:, 0].max())
        y0, y1 = y_range_m if y_range_m is not None else (allp[:, 1].min(), allp[:, 1].max())
        if not (x1 > x0 and y1 > y0):
            raise ValueError("x_range_m and y_range_m must be increasing (min, max) pairs")
        nx, ny = int(np.ceil((x1 - x0) / cell_m)), int(np.ceil((y1 - y0) / cell_m))
        img = np.zeros((ny, nx), dtype=np.uint8)
        shift = 4

        def px(r):
            u = ((np.asarray(r, dtype=np.float64) - [x0, y0]) / cell_m - 0.5) * (1 << shift)
            return [np.round(u).astype(np.int32).reshape(-1, 1, 2)]

        for r in rings:
            cv2.fillPoly(img, px(r), 1, lineType=cv2.LINE_8, shift=shift)
        for r in obstacles:
            r = np.asarray(r, dtype=np.float64)
            if r.ndim != 2 or r.shape[1] != 2 or r.shape[0] < 3:
                raise ValueError(f"obstacle rings must have shape (n >= 3, 2), got {r.shape}")
            cv2.fillPoly(img, px(r), 0, lineType=cv2.LINE_8, shift=shift)
        return cls(img.astype(bool), float(x0), float(y0), float(cell_m))

    @classmethod
    def from_floor_map(cls, floor_map, cell_m: float = 0.5) -> OccupancyGrid:
        """The walkable raster of a floor map over ``[0, width_m] x [0, height_m]`` (:meth:`from_polygons`).

        Parameters
        ----------
        floor_map : object with ``outline``, ``obstacles``, ``width_m``, ``height_m``
            E.g. :class:`ilocalg.io.ilc.IlcFloorMap`.
        cell_m : float
        """
        return cls.from_polygons(floor_map.outline, floor_map.obstacles, (0.0, floor_map.width_m),
                                 (0.0, floor_map.height_m), cell_m)

    def coarsen(self, cell_m: float = 1.0) -> OccupancyGrid:
        """A coarser raster: a coarse cell is walkable if any fine cell in it is.

        The factor is ``round(cell_m / self.cell_m)``; a factor <= 1 returns the grid itself. Rows and
        columns that do not fill a whole coarse cell (at the far edges) are left out.
        """
        if not cell_m > 0:
            raise ValueError(f"cell_m must be > 0, got {cell_m!r}")
        f = int(round(cell_m / self.cell_m))
        if f <= 1:
            return self
        m = self.walkable_mask
        ny, nx = (m.shape[0] // f) * f, (m.shape[1] // f) * f
        c = m[:ny, :nx].reshape(ny // f, f, nx // f, f).any(axis=(1, 3))
        return OccupancyGrid(c, self.x0_m, self.y0_m, self.cell_m * f)

    @property
    def area_m2(self) -> float:
        """Walkable area, m^2."""
        return float(self.walkable_mask.sum()) * self.cell_m**2

    def walkable(self, x_m, y_m) -> np.ndarray:
        """True where the cell containing ``(x, y)`` is walkable (False outside the raster)."""
        x = np.asarray(x_m, dtype=np.float64)
        y = np.asarray(y_m, dtype=np.float64)
        i = np.floor((x - self.x0_m) / self.cell_m)
        j = np.floor((y - self.y0_m) / self.cell_m)
        ny, nx = self.walkable_mask.shape
        inside = (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
        ii = np.where(inside, i, 0).astype(np.int64)
        jj = np.where(inside, j, 0).astype(np.int64)
        return inside & self.walkable_mask[jj, ii]

    def sample(self, n: int, rng=None) -> np.ndarray:
        """``n`` uniformly random walkable positions (n, 2)."""
        r = as_rng(rng)
        jj, ii = np.nonzero(self.walkable_mask)
        if ii.size == 0:
            raise ValueError("the grid has no walkable cell")
        k = r.integers(0, ii.size, n)
        u = r.random((n, 2))
        return np.column_stack([self.x0_m + (ii[k] + u[:, 0]) * self.cell_m,
                                self.y0_m + (jj[k] + u[:, 1]) * self.cell_m])


@dataclass(frozen=True)
class PFResult:
    """Particle-filter output over ``n + 1`` states.

    Attributes
    ----------
    x : ndarray (n+1, 2)
        Filtered estimate (weighted mean after the fix of each state, if any).
    x_smooth : ndarray (n+1, 2)
        Weighted mean of the final particles' ancestral paths (whole-walk estimate).
    n_eff : ndarray (n+1,)
        Effective sample size after each state's update (before resampling).
    n_resample, n_reset, n_blocked : int
        Resampling events; weight resets (every particle blocked or underflow); particle moves
        rejected by the map over the walk.
    dtheta_rad : ndarray (n+1,)
        Weighted mean heading correction of the particles.
    lik_mean : ndarray (n+1,)
        Average fix likelihood ``w_avg`` at each state (normalised weights before the fix; NaN
        without a fix), m^-2; its floor is ``outlier_prob / area``.
    p_inject : ndarray (n+1,)
        Probability of replacing a particle at each state (0 without recovery or without a fix).
    n_injected : int
        Particles replaced by the recovery over the walk.
    """

    x: np.ndarray
    x_smooth: np.ndarray
    n_eff: np.ndarray
    n_resample: int
    n_reset: int
    n_blocked: int
    dtheta_rad: np.ndarray
    lik_mean: np.ndarray | None = None
    p_inject: np.ndarray | None = None
    n_injected: int = 0


def _fix_sampler(grid: OccupancyGrid | None):
    """``draw(z, R, m, rng) -> (m, 2)``: ``N(z, R)`` restricted to the walkable cells of ``grid``.

    The density is taken at the cell centres (the raster's resolution) and a point is uniform within
    its cell; the weights are normalised in the log domain, so a fix far from every walkable cell
    still gives the walkable cells nearest to it (in the metric of ``R``). Without a grid: ``N(z, R)``.
    """
    if grid is None:
        def draw_free(z, R, m, r):
            return z + r.standard_normal((m, 2)) @ np.linalg.cholesky(R).T
        return draw_free
    jj, ii = np.nonzero(grid.walkable_mask)
    if ii.size == 0:
        raise ValueError("the grid has no walkable cell")
    c = np.column_stack([grid.x0_m + (ii + 0.5) * grid.cell_m, grid.y0_m + (jj + 0.5) * grid.cell_m])

    def draw(z, R, m, r):
        e = c - z
        q = np.einsum("ni,ij,nj->n", e, np.linalg.inv(R), e)
        pr = np.exp(-0.5 * (q - q.min()))
        k = r.choice(c.shape[0], size=m, p=pr / pr.sum())
        return c[k] + (r.random((m, 2)) - 0.5) * grid.cell_m
    return draw


def systematic_resample(weights, rng=None) -> np.ndarray:
    """Indices of a systematic resample of normalised ``weights`` (one uniform draw)."""
    w = np.asarray(weights, dtype=np.float64)
    if w.ndim != 1 or w.size == 0 or not np.isfinite(w).all() or (w < 0).any() or not w.sum() > 0:
        raise ValueError("weights must be a non-empty 1-D array, finite, >= 0, with a positive sum")
    n = w.size
    c = np.cumsum(w / w.sum())
    c[-1] = 1.0
    u = (as_rng(rng).random() + np.arange(n)) / n
    return np.searchsorted(c, u, side="right").clip(0, n - 1)


def map_particle_filter(x0_m, P0_m2, theta_rad, step_m, z_m, R_m2, grid: OccupancyGrid | None = None,
                        n_particles: int = 1000, rng=None, sigma_step_rel: float = 0.1,
                        sigma_heading_rad: float = 0.1, sigma_offset0_rad: float = 0.2,
                        sigma_offset_walk_rad: float = 0.005, sigma_scale: float = 0.1,
                        outlier_prob: float = 0.1, resample_frac: float = 0.5, init: str = "gaussian",
                        blocked_weight: float = 0.0, recovery: str | None = "augmented", alpha_slow: float = 0.001,
                        alpha_fast: float = 0.1) -> PFResult:
    """Run the map-constrained particle filter over one walk (see the module docstring).

    Parameters
    ----------
    x0_m : array_like (2,)
        Centre of the initial cloud.
    P0_m2 : array_like (2, 2)
        Its covariance (``init="gaussian"``; draws that are not walkable are redrawn, up to 50 times).
    theta_rad, step_m : array_like (n,)
        PDR heading (map frame, before the particles' own correction) and length of each step.
    z_m : array_like (n+1, 2)
        Fix at each state, NaN rows where none (as for :func:`ilocalg.fusion.filter_walk`).
    R_m2 : array_like (n+1, 2, 2)
        Fix covariances (ignored where there is no fix).
    grid : OccupancyGrid or None
        Walkable area; ``None`` disables the map constraint (then ``eps / area`` uses 1e4 m^2).
    n_particles : int
    rng : Generator, int or None
    sigma_step_rel, sigma_heading_rad, sigma_offset0_rad, sigma_offset_walk_rad, sigma_scale : float
        Per-step relative length noise, per-step heading noise, initial heading-correction spread,
        its per-step random walk, and the spread of the per-particle step scale (mean 1).
    outlier_prob : float in [0, 1)
        Weight of the uniform component of the fix likelihood.
    resample_frac : float in (0, 1]
    init : {"gaussian", "map"}
        Initial positions from ``N(x0, P0)`` or uniformly over the walkable map (needs ``grid``).
    blocked_weight : float in [0, 1)
        Weight factor of a particle whose move ends off the walkable area: 0 is the hard constraint;
        a small positive value (a soft constraint) keeps the filter alive when the PDR track and
        the map disagree everywhere (e.g. an error in the map or a wrong start).
    recovery : {"augmented", "amcl", None}
        ``"augmented"`` (default): Augmented MCL with sensor resetting (see the module docstring);
        ``"amcl"``: the same, the averages restarted after each injection as ROS amcl does;
        None: no recovery (the filter before issue 26: once the particles have lost the fixes, they
        never come back).
    alpha_slow, alpha_fast : float, 0 <= alpha_slow < alpha_fast <= 1
        Rates of the long- and short-term averages of the fix likelihood (with a recovery;
        defaults: ROS amcl's suggested ``recovery_alpha_slow`` / ``recovery_alpha_fast``).

    Returns
    -------
    PFResult
    """
    r = as_rng(rng)
    th = np.asarray(theta_rad, dtype=np.float64).ravel()
    d = np.asarray(step_m, dtype=np.float64).ravel()
    n = th.size
    z = np.asarray(z_m, dtype=np.float64)
    R = np.asarray(R_m2, dtype=np.float64)
    if d.shape != (n,) or not (np.isfinite(th).all() and np.isfinite(d).all()) or (d < 0).any():
        raise ValueError(f"theta_rad and step_m must be finite with the same length; step_m >= 0 (got {d.shape}, {n})")
    if z.shape != (n + 1, 2):
        raise ValueError(f"z_m must have shape ({n + 1}, 2), got {z.shape}")
    if R.shape != (n + 1, 2, 2):
        raise ValueError(f"R_m2 must have shape ({n + 1}, 2, 2), got {R.shape}")
    has = ~np.isnan(z[:, 0])
    if (np.isnan(z[:, 1]) != ~has).any():
        raise ValueError("z_m rows must be both NaN (no fix) or both finite")
    if has.any() and not np.isfinite(R[has]).all():
        raise ValueError("R_m2 must be finite where there is a fix")
    if not (n_particles >= 10 and 0 <= outlier_prob < 1 and 0 < resample_frac <= 1 and 0 <= blocked_weight < 1):
        raise ValueError("need n_particles >= 10, 0 <= outlier_prob < 1, 0 < resample_frac <= 1 and "
                         "0 <= blocked_weight < 1")
    if init not in ("gaussian", "map") or (init == "map" and grid is None):
        raise ValueError("init must be 'gaussian' or 'map' (the latter needs a grid)")
    if recovery not in RECOVERIES:
        raise ValueError(f"recovery must be one of {RECOVERIES}, got {recovery!r}")
    if not 0 <= alpha_slow < alpha_fast <= 1:
        raise ValueError(f"need 0 <= alpha_slow < alpha_fast <= 1, got alpha_slow={alpha_slow!r}, "
                         f"alpha_fast={alpha_fast!r}")
    draw_fix = _fix_sampler(grid) if recovery is not None else None
    N = int(n_particles)
    area = grid.area_m2 if grid is not None else 1e4
    if init == "map":
        p = grid.sample(N, r)
    else:
        L = np.linalg.cholesky(np.asarray(P0_m2, dtype=np.float64))
        p = np.asarray(x0_m, dtype=np.float64) + r.standard_normal((N, 2)) @ L.T
        if grid is not None:
            for _ in range(50):
                bad = ~grid.walkable(p[:, 0], p[:, 1])
                if not bad.any():
                    break
                p[bad] = np.asarray(x0_m, dtype=np.float64) + r.standard_normal((int(bad.sum()), 2)) @ L.T
    dth = sigma_offset0_rad * r.standard_normal(N)
    scale = 1.0 + sigma_scale * r.standard_normal(N)
    w = np.full(N, 1.0 / N)
    pos = np.empty((n + 1, N, 2))
    anc = np.empty((n + 1, N), dtype=np.int64)   # parent (at state k - 1) of particle i at state k
    xf = np.empty((n + 1, 2))
    dmean = np.empty(n + 1)
    neff = np.empty(n + 1)
    lik_mean = np.full(n + 1, np.nan)
    p_inj = np.zeros(n + 1)
    w_slow = w_fast = 0.0
    n_res = n_reset = n_blocked = n_inj = 0
    ident = np.arange(N)
    for k in range(n + 1):
        anc[k] = ident
        if k > 0:
            dth = dth + sigma_offset_walk_rad * r.standard_normal(N)
            dk = d[k - 1] * scale * (1.0 + sigma_step_rel * r.standard_normal(N))
            tk = th[k - 1] + dth + sigma_heading_rad * r.standard_normal(N)
            p = p + dk[:, None] * np.column_stack([np.cos(tk), np.sin(tk)])
            if grid is not None:
                ok = grid.walkable(p[:, 0], p[:, 1])
                n_blocked += int((~ok).sum())
                w = w * np.where(ok, 1.0, blocked_weight)
        if has[k]:
            Rk = R[k]
            Ri = np.linalg.inv(Rk)
            e = z[k] - p
            q = np.einsum("ni,ij,nj->n", e, Ri, e)
            g = np.exp(-0.5 * q) / (2 * np.pi * np.sqrt(np.linalg.det(Rk)))
            lik = (1 - outlier_prob) * g + outlier_prob / area
            s0 = w.sum()
            if s0 > 0 and np.isfinite(s0):
                lik_mean[k] = (w / s0) @ lik
                if recovery is not None and lik_mean[k] > 0:
                    # Thrun et al. (2005), Table 8.3; started at the first average as amcl's pf.c does
                    w_slow = lik_mean[k] if w_slow == 0 else w_slow + alpha_slow * (lik_mean[k] - w_slow)
                    w_fast = lik_mean[k] if w_fast == 0 else w_fast + alpha_fast * (lik_mean[k] - w_fast)
                    p_inj[k] = max(0.0, 1.0 - w_fast / w_slow)
            w = w * lik
        s = w.sum()
        if not (s > 0 and np.isfinite(s)):
            n_reset += 1
            w = np.full(N, 1.0 / N)
        else:
            w = w / s
        neff[k] = 1.0 / np.sum(w**2)
        xf[k] = w @ p
        dmean[k] = np.arctan2(w @ np.sin(dth), w @ np.cos(dth))
        pos[k] = p
        if neff[k] < resample_frac * N or p_inj[k] > 0:
            idx = systematic_resample(w, r)
            p, dth, scale = p[idx], dth[idx], scale[idx]
            if p_inj[k] > 0:
                # each particle replaced with probability p_inj by a draw from the fix (sensor resetting)
                new = np.flatnonzero(r.random(N) < p_inj[k])
                m = new.size
                if m:                     # p, dth, scale are fresh copies (fancy indexing)
                    p[new] = draw_fix(z[k], R[k], m, r)
                    dth[new] = sigma_offset0_rad * r.standard_normal(m)
                    scale[new] = 1.0 + sigma_scale * r.standard_normal(m)
                    n_inj += m
                if recovery == "amcl":
                    w_slow = w_fast = 0.0
            pos[k] = p
            # the particles at state k are now the resampled ones; their parents at k - 1 are those
            # of the particles they copy (an injected particle: those of the particle it replaces)
            anc[k] = anc[k][idx]
            w = np.full(N, 1.0 / N)
            n_res += 1
    # ancestral paths of the final particles
    xs = np.empty((n + 1, 2))
    cur = ident
    for k in range(n, -1, -1):
        xs[k] = w @ pos[k][cur]
        cur = anc[k][cur]
    return PFResult(xf, xs, neff, n_res, n_reset, n_blocked, dmean, lik_mean, p_inj, n_inj)
