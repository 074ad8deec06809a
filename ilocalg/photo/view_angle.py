"""VA: view-angle photo positioning by gradient descent.

The thesis names VA ("view angle based positioning algorithm", a gradient algorithm whose result
depends on its initial value, Chiu 2013, L694) but gives no VA equation (its eq. 29-30 are the
similar-triangle ST method). The cost function below is therefore the toolkit's own reading of
"view angle" positioning, not the thesis's.

By default the search is on the floor plane: the camera height is known (the phone at the user's
eye height) and kept at its initial value, the unknowns are the floor position (x, y), as a floor
map needs. ``free_z=True`` searches the three coordinates (the thesis's output
``c = [c_x c_y c_z]``, L672), an option.

The angle between the viewing rays of two PoIs does not depend on the phone's orientation: it is
measured in the photo from the two screen points and the focal length
(:func:`ilocalg.photo.camera.ray_angle_rad`). From a candidate centre ``c`` the same angle is
``theta_ij(c) = angle(p_i - c, p_j - c)``. VA minimises

    J(c) = sum_{i<j} (theta_ij(c) - theta_ij_measured)^2

by gradient descent from an initial guess ``c0``. With two PoIs there is one angle for three
unknowns (a surface of solutions), and collinear PoIs leave the rotation of ``c`` about their line
undetermined, so the answer depends on ``c0``; the thesis compares a good and a bad initial guess
(VAGIG, VABIG).

The descent is monotone gradient descent with Barzilai-Borwein step lengths and backtracking
(a step that does not lower ``J`` is rejected and its length multiplied by ``shrink``), vectorised
over a batch of photos. It stops at the local minimum nearest (downhill) from ``c0``; it does not
search globally, which is the behaviour the thesis attributes VA's errors to.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Sec. 6.3, the view-angle algorithm VA, VAGIG and VABIG,
Figs 29-32.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ilocalg.photo.camera import ray_angle_rad, validate_points

__all__ = [
    "pair_index",
    "view_angles_rad",
    "measured_view_angles_rad",
    "va_cost",
    "va_gradient",
    "va_solve_batch",
    "va_solve",
    "VAResult",
    "ViewAngle",
]

_EPS = 1e-12


def pair_index(n: int) -> np.ndarray:
    """All PoI pairs ``(i, j)``, ``i < j``, as an int array (n (n-1) / 2, 2)."""
    if n < 2:
        raise ValueError(f"VA needs at least 2 PoIs, got {n}")
    return np.array(list(combinations(range(n), 2)), dtype=int)


def view_angles_rad(c_m, pois_m) -> np.ndarray:
    """View angles (B, m) between every PoI pair seen from centres ``c_m`` (B, 3); ``pois_m`` (B, n, 3)."""
    c = np.asarray(c_m, dtype=float)
    P = np.asarray(pois_m, dtype=float)
    pr = pair_index(P.shape[-2])
    u = P[..., pr[:, 0], :] - c[..., None, :]
    v = P[..., pr[:, 1], :] - c[..., None, :]
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1))


def measured_view_angles_rad(img_px, f_px: float) -> np.ndarray:
    """View angles (..., m) between every pair of screen points ``img_px`` (..., n, 2), from the photo only."""
    U = np.asarray(img_px, dtype=float)
    pr = pair_index(U.shape[-2])
    return ray_angle_rad(U[..., pr[:, 0], :], U[..., pr[:, 1], :], f_px)


def _pairs(pois_m, B):
    """The pairs' PoIs of :func:`pair_index`, component-major: ``Pi``, ``Pj`` (3, m, B), contiguous (every
    elementwise step of :func:`_cost_grad` then runs over the batch in one long loop, not three numbers at a time)."""
    P = np.broadcast_to(np.asarray(pois_m, dtype=float), (B,) + np.shape(pois_m)[-2:])
    pr = pair_index(P.shape[1])
    Pt = P.transpose(2, 1, 0)                                   # (3, n, B)
    return np.ascontiguousarray(Pt[:, pr[:, 0], :]), np.ascontiguousarray(Pt[:, pr[:, 1], :])


def va_cost(c_m, pois_m, angles_rad) -> np.ndarray:
    """``J(c)`` (B,), the sum of squared view-angle mismatches (rad^2), for ``c_m`` (B, 3), ``pois_m`` (B, n, 3)."""
    c = np.atleast_2d(np.asarray(c_m, dtype=float))
    Pi, Pj = _pairs(pois_m, c.shape[0])
    a = np.broadcast_to(np.asarray(angles_rad, dtype=float), (c.shape[0], Pi.shape[1])).T
    return _cost_grad(c, Pi, Pj, a, False)[0]


def va_gradient(c_m, pois_m, angles_rad) -> np.ndarray:
    """Analytic gradient ``dJ/dc`` (B, 3) in rad^2/m.

    With ``u = p_i - c``, ``v = p_j - c`` and ``theta`` their angle,
    ``d theta / d c = (v^ - cos(theta) u^) / (|u| sin(theta)) + (u^ - cos(theta) v^) / (|v| sin(theta))``.
    """
    c = np.atleast_2d(np.asarray(c_m, dtype=float))
    Pi, Pj = _pairs(pois_m, c.shape[0])
    a = np.broadcast_to(np.asarray(angles_rad, dtype=float), (c.shape[0], Pi.shape[1])).T
    return _cost_grad(c, Pi, Pj, a, True)[1]


def _dot3(u, v):
    """Dot products over the first axis (3 components), summed as numpy's ``einsum`` sums three products of one
    row, ``(u0 v0 + u2 v2) + u1 v1`` (so that this layout gives the row layout's numbers bit for bit)."""
    return (u[0] * v[0] + u[2] * v[2]) + u[1] * v[1]


def _cost_grad(c, Pi, Pj, a, need_grad):
    """Cost (B,) and optionally gradient (B, 3) at centres ``c`` (B, 3); ``Pi``, ``Pj`` (3, m, B) are the pairs'
    PoIs (:func:`_pairs`), ``a`` (m, B) their measured angles."""
    ct = c.T[:, None, :]
    u = Pi - ct
    v = Pj - ct
    cr = np.empty_like(u)
    for k, (i, j) in enumerate(((1, 2), (2, 0), (0, 1))):     # u x v
        np.multiply(u[i], v[j], out=cr[k])
        cr[k] -= u[j] * v[i]
    sin_uv = np.sqrt(_dot3(cr, cr))
    dot = _dot3(u, v)
    r = np.arctan2(sin_uv, dot) - a
    rb = np.ascontiguousarray(r.T)
    J = np.einsum("bm,bm->b", rb, rb)
    if not need_grad:
        return J, None
    nu = np.sqrt(_dot3(u, u))
    nv = np.sqrt(_dot3(v, v))
    nu = np.maximum(nu, _EPS)
    nv = np.maximum(nv, _EPS)
    cos = dot / (nu * nv)
    sin = np.maximum(sin_uv / (nu * nv), 1e-9)
    uh = u / nu
    vh = v / nv
    w = 2.0 * r / sin
    terms = cos * uh                                          # w ((vh - cos uh) / nu + (uh - cos vh) / nv), in place
    np.subtract(vh, terms, out=terms)
    terms /= nu
    other = np.multiply(cos, vh, out=vh)
    np.subtract(uh, other, out=other)
    other /= nv
    terms += other
    terms *= w
    g = terms[:, 0].copy()
    for j in range(1, terms.shape[1]):  # pair after pair, as numpy sums the row layout's pair axis (a sum along a
        g += terms[:, j]                # contiguous axis would add in blocks of eight: other last bits)
    return J, np.ascontiguousarray(g.T)


def va_solve_batch(pois_m, angles_rad, c0_m, max_iter: int = 2000, step0_m: float = 0.5,
                   grow: float = 2.0, shrink: float = 0.5, step_tol_m: float = 1e-10,
                   free_z: bool = False) -> dict[str, np.ndarray]:
    """Gradient descent on ``J(c)`` for a batch of photos.

    Parameters
    ----------
    pois_m : array (B, n, 3) or (n, 3)
        PoI world positions, metres.
    angles_rad : array (B, m)
        Measured view angles for the pairs of :func:`pair_index` ``(n)``.
    c0_m : array (B, 3)
        Initial guesses, metres.
    max_iter : int
        Maximum number of descent iterations.
    step0_m : float
        Length of the first step (m) along the steepest-descent direction.
    grow, shrink : float
        Step factor when the curvature estimate is not positive / after a rejected step.
    step_tol_m : float
        A photo has converged when its next step is shorter than this (m).
    free_z : bool
        ``False`` (default) keeps each ``c``'s height at its initial value (a 2-D search on the
        floor map at a known phone height); ``True`` searches all three coordinates.

    Returns
    -------
    dict with ``c_m`` (B, 3), ``cost`` (B,) in rad^2, ``n_iter`` (B,) and ``converged`` (B,) bool.

    References
    ----------
    i-Loc thesis, sec. 6.3 (VA is "a gradient algorithm" whose result depends on the initial value).
    """
    a = np.asarray(angles_rad, dtype=float)
    c = np.array(c0_m, dtype=float, copy=True)
    if c.ndim != 2 or c.shape[1] != 3:
        raise ValueError(f"c0_m must have shape (B, 3), got {c.shape}")
    P = np.broadcast_to(np.asarray(pois_m, dtype=float), (c.shape[0],) + np.shape(pois_m)[-2:])
    if a.shape != (c.shape[0], pair_index(P.shape[1]).shape[0]):
        raise ValueError(f"angles_rad must have shape (B, n(n-1)/2) = ({c.shape[0]}, "
                         f"{pair_index(P.shape[1]).shape[0]}), got {a.shape}")
    if not (np.isfinite(a).all() and np.isfinite(c).all()):
        raise ValueError("angles_rad and c0_m must be finite")
    B = c.shape[0]
    mask = np.array([1.0, 1.0, 1.0 if free_z else 0.0])
    Pi, Pj = _pairs(P, B)
    at = np.ascontiguousarray(a.T)
    J, g = _cost_grad(c, Pi, Pj, at, True)
    g = g * mask
    gn = np.sqrt(np.sum(g * g, axis=1))
    # first step moves step0_m along the steepest descent direction
    alpha = float(step0_m) / np.where(gn > 0, gn, 1.0)
    n_iter = np.zeros(B, dtype=int)
    active = gn > 0
    idx = np.flatnonzero(active)
    # the active photos' state, pairs and angles, kept compact (gathered again only when photos converge; a
    # converged photo's state is written back then): the same arithmetic per photo as on the full arrays
    ca, Ja, ga, al, ni = c[idx], J[idx], g[idx], alpha[idx], n_iter[idx]
    # (np.take / np.compress keep them C-contiguous: the sums over pairs then add in the same order as always)
    Pi_a, Pj_a, a_a = np.take(Pi, idx, axis=-1), np.take(Pj, idx, axis=-1), np.take(at, idx, axis=-1)
    for _ in range(max_iter):
        if idx.size == 0:
            break
        trial = ca - al[:, None] * ga
        Jt, gt = _cost_grad(trial, Pi_a, Pj_a, a_a, True)
        ok = Jt < Ja
        ni += 1
        if ok.all():  # the branch below with every step accepted, without gathering
            gt = gt * mask
            s_ = trial - ca
            y_ = gt - ga
            sy = np.sum(s_ * y_, axis=1)
            ss = np.sum(s_ * s_, axis=1)
            al = np.where(sy > 0, ss / np.where(sy > 0, sy, 1.0), al * grow)
            ca, Ja, ga = trial, Jt, gt
        else:  # rejected steps: backtrack
            al[~ok] *= shrink
            if ok.any():
                gt = gt[ok] * mask
                s_ = trial[ok] - ca[ok]
                y_ = gt - ga[ok]
                sy = np.sum(s_ * y_, axis=1)
                ss = np.sum(s_ * s_, axis=1)
                # Barzilai-Borwein step for the next iteration (grow when curvature is not positive)
                al[ok] = np.where(sy > 0, ss / np.where(sy > 0, sy, 1.0), al[ok] * grow)
                ca[ok] = trial[ok]
                Ja[ok] = Jt[ok]
                ga[ok] = gt
        steplen = al * np.sqrt(np.sum(ga * ga, axis=1))
        keep = steplen > step_tol_m
        if not keep.all():
            done = ~keep
            d = idx[done]
            c[d], J[d], n_iter[d] = ca[done], Ja[done], ni[done]
            active[d] = False
            idx = idx[keep]
            ca, Ja, ga, al, ni = ca[keep], Ja[keep], ga[keep], al[keep], ni[keep]
            Pi_a, Pj_a, a_a = (np.compress(keep, x, axis=-1) for x in (Pi_a, Pj_a, a_a))
    c[idx], J[idx], n_iter[idx] = ca, Ja, ni  # photos still moving after max_iter
    return {"c_m": c, "cost": J, "n_iter": n_iter, "converged": ~active}


@dataclass(frozen=True)
class VAResult:
    """Result of :func:`va_solve`: centre ``c_m`` (3,), final ``cost`` (rad^2), ``n_iter``, ``converged``."""

    c_m: np.ndarray
    cost: float
    n_iter: int
    converged: bool


def va_solve(pois_m, img_px, f_px: float, c0_m, **kw) -> VAResult:
    """Camera centre of one photo from its PoI view angles (VA), starting at ``c0_m``.

    Parameters
    ----------
    pois_m : array (n, 3)
        PoI world positions, metres, ``n >= 2``.
    img_px : array (n, 2)
        Screen points, pixels from the image centre.
    f_px : float
        Focal length, pixels.
    c0_m : array (3,)
        Initial guess, metres.
    **kw
        Passed to :func:`va_solve_batch`.

    References
    ----------
    i-Loc thesis, sec. 6.3, VA.
    """
    P, U = validate_points(pois_m, img_px, f_px, min_points=2)
    c0 = np.asarray(c0_m, dtype=float)
    if c0.shape != (3,):
        raise ValueError(f"c0_m must have shape (3,), got {c0.shape}")
    out = va_solve_batch(P[None], measured_view_angles_rad(U, f_px)[None], c0[None], **kw)
    return VAResult(c_m=out["c_m"][0], cost=float(out["cost"][0]), n_iter=int(out["n_iter"][0]),
                    converged=bool(out["converged"][0]))


class ViewAngle:
    """Thin wrapper around :func:`va_solve` holding the focal length and descent settings."""

    def __init__(self, f_px: float, max_iter: int = 2000, step0_m: float = 0.5, free_z: bool = False):
        self.f_px = f_px
        self.max_iter = max_iter
        self.step0_m = step0_m
        self.free_z = free_z

    def locate(self, pois_m, img_px, c0_m) -> VAResult:
        """Camera centre of one photo from initial guess ``c0_m``; see :func:`va_solve`."""
        return va_solve(pois_m, img_px, self.f_px, c0_m, max_iter=self.max_iter, step0_m=self.step0_m,
                        free_z=self.free_z)
