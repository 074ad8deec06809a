"""Study: mean error of the i-Loc step Kalman filter vs Wi-Fi noise scale and vs fix rate.

Walks are the seeded synthetic walks of :mod:`ilocalg.fusion.synthetic` (a zig-zag with a 90 deg
turn every ``turn_every`` steps, true step 0.7 m, heading noise 0.05 rad per step). Their inputs:

* step-length error sd: the i-Loc thesis' Table 4 at 0.7 m (:func:`ilocalg.fusion.sigma_sl_paper_m`);
* Wi-Fi fix error sd: ``noise_scale`` times :data:`SIGMA_RF_BASE_M`, the square root of the median
  of the thesis' Table 5 variances at its 28 test points (paper value, an input);
* a fix every ``fix_every`` steps (the thesis assumes about two steps per second, so a fix every 2
  steps is about one fix per second);
* the walk starts at a known point (the filter's ``x0`` is the true start with 1 m^2 covariance).

The filter is :func:`ilocalg.fusion.filter_walks` with the paper's model (``Q`` along the heading
only, ``R = sigma_RF^2 I`` with the true ``sigma_RF``, no gate); beside it the whole-walk RTS
smoother (:func:`ilocalg.fusion.rts_smooth`), the raw fixes and the dead-reckoned track (the same
filter given no fix). Errors are 2-D, averaged over every state (fixes: over the states that carry
one) and over the ``n_walks`` walks of the run.

Returns ``{"sweep_kf_noise": ...}`` with quantity ``mean error`` (m) per ``method`` (in ``item``);
the swept values are the task parameters ``noise_scale`` and ``fix_every``.

References
----------
Chiu, P.-J. (2013). Implement an integrated indoor positioning system. M.S. thesis, NCTU.
Ch. 5, eq. (20)-(26), Tables 4-5.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ilocalg.fusion import PAPER_TABLE5_SIGMA_RF_VAR_M2, filter_walks, rts_smooth, sigma_sl_paper_m, straight_walk
from ilocalg.workflow.studies import select, study_row, study_tasks

__all__ = ["run", "SIGMA_RF_BASE_M", "STEP_M", "GRIDS", "BASE", "tasks", "findings", "METHODS"]

EXPERIMENT = "study_kf_noise"
# Settings from the paper
# -----------------------
# SIGMA_RF_BASE_M: square root of the median of Chiu (2013) Table 5's Wi-Fi error variances.
#: Base Wi-Fi fix sd (m): sqrt of the median Table 5 variance of the i-Loc thesis (derived from paper values).
SIGMA_RF_BASE_M = float(np.sqrt(np.median(PAPER_TABLE5_SIGMA_RF_VAR_M2)))
STEP_M = 0.7
HEADING_SD_RAD = 0.05
METHODS = ("step KF", "RTS smoother", "Wi-Fi fixes", "dead reckoning")

BASE = {"noise_scale": 1.0, "fix_every": 3}
GRIDS = {
    False: {"noise_scale": [0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0], "fix_every": [1, 2, 3, 5, 8, 12, 20]},
    True: {"noise_scale": [0.5, 1.0, 3.0], "fix_every": [1, 3, 10]},
}


def run(seed: int = 0, fast: bool = False, noise_scale: float = 1.0, fix_every: int = 3,
        n_walks: int | None = None, n_steps: int | None = None, turn_every: int = 20) -> dict[str, pd.DataFrame]:
    """Step KF, RTS, fixes and dead reckoning on ``n_walks`` synthetic walks (module docstring).

    Parameters
    ----------
    seed : int
    fast : bool
        Defaults of 20 walks of 100 steps instead of 100 walks of 200 steps.
    noise_scale : float, > 0
        Multiplies the Wi-Fi fix sd :data:`SIGMA_RF_BASE_M`.
    fix_every : int, >= 1
        Steps between two Wi-Fi fixes.
    n_walks, n_steps, turn_every : int
    """
    if not np.isfinite(noise_scale) or noise_scale <= 0:
        raise ValueError(f"noise_scale must be > 0, got {noise_scale!r}")
    if int(fix_every) != fix_every or fix_every < 1:
        raise ValueError(f"fix_every must be an integer >= 1, got {fix_every!r}")
    nw = int(n_walks or (20 if fast else 100))
    ns = int(n_steps or (100 if fast else 200))
    sigma_rf = noise_scale * SIGMA_RF_BASE_M
    sigma_sl = float(sigma_sl_paper_m(STEP_M))
    children = np.random.SeedSequence([int(seed), 61]).spawn(nw)
    walks = [straight_walk(ns, rng=np.random.default_rng(c), step_true_m=STEP_M, sigma_sl_m=sigma_sl,
                           sigma_heading_rad=HEADING_SD_RAD, sigma_rf_m=sigma_rf, fix_every=int(fix_every),
                           turn_every=turn_every) for c in children]
    truth = np.stack([w.truth_xy_m for w in walks])
    theta = np.stack([w.theta_rad for w in walks])
    step = np.stack([w.step_m for w in walks])
    z = np.stack([w.z_m for w in walks])
    common = dict(x0_m=truth[:, 0], P0_m2=np.eye(2), theta_rad=theta, step_m=step, sigma_sl_m=sigma_sl,
                  r_var_m2=sigma_rf**2)
    kf = filter_walks(z_m=z, **common)
    dr = filter_walks(z_m=np.full_like(z, np.nan), **common)
    sm = rts_smooth(kf)

    def err(est):
        return np.hypot(*(est - truth).transpose(2, 0, 1))

    has = ~np.isnan(z[..., 0])
    values = {
        "step KF": err(kf.x).mean(),
        "RTS smoother": err(sm.x).mean(),
        "Wi-Fi fixes": err(np.where(has[..., None], z, truth))[has].mean(),
        "dead reckoning": err(dr.x).mean(),
    }
    rows = [study_row("mean error", v, "m", method=m) for m, v in values.items()]
    rows.append(study_row("Wi-Fi fix sd", sigma_rf, "m"))
    return {"sweep_kf_noise": pd.DataFrame(rows)}


def tasks(seeds, fast: bool = False) -> list:
    """Sweep tasks of the two one-factor curves (noise scale, fix interval) around :data:`BASE`."""
    grids = [{**{k: [v] for k, v in BASE.items()}, name: vals} for name, vals in GRIDS[fast].items()]
    return study_tasks(EXPERIMENT, grids, seeds, fast=fast)


def findings(cv: pd.DataFrame) -> str:
    """Sentences computed from the study's curves (:func:`ilocalg.workflow.studies.curves`)."""
    out = []
    for vary, fixed, label in (("noise_scale", "fix_every", "noise scale"), ("fix_every", "noise_scale",
                                                                              "fix interval (steps)")):
        kf = select(cv, "mean error", method="step KF", **{fixed: BASE[fixed]}).sort_values(vary)
        fx = select(cv, "mean error", method="Wi-Fi fixes", **{fixed: BASE[fixed]}).sort_values(vary)
        rts = select(cv, "mean error", method="RTS smoother", **{fixed: BASE[fixed]}).sort_values(vary)
        gain = 1.0 - kf["mean"].to_numpy() / fx["mean"].to_numpy()
        out.append(f"Over {label} {kf[vary].iloc[0]:g}..{kf[vary].iloc[-1]:g}: step-KF mean error "
                   f"{kf['mean'].iloc[0]:.2f}..{kf['mean'].iloc[-1]:.2f} m (Wi-Fi fixes alone "
                   f"{fx['mean'].iloc[0]:.2f}..{fx['mean'].iloc[-1]:.2f} m; the filter removes "
                   f"{100 * gain.min():.0f}-{100 * gain.max():.0f} % of it); RTS "
                   f"{rts['mean'].iloc[0]:.2f}..{rts['mean'].iloc[-1]:.2f} m (N={int(kf['n'].min())} seeds).")
    dr = select(cv, "mean error", method="dead reckoning", **BASE)
    out.append(f"Dead reckoning alone (no fixes): {dr['mean'].iloc[0]:.2f} m mean error.")
    return "\n".join(out)
