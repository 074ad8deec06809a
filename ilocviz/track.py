"""Tracks of one walk drawn on its floor plan (the ILC ``floor_image.png``)."""

from __future__ import annotations

import numpy as np

__all__ = ["tracks_on_plan", "save_tracks_on_plan"]


def tracks_on_plan(track, truth_xy_m, image=None, size_m=None, methods=("wifi", "kf_rts", "lsq"), ax=None,
                   margin_m: float | None = 15.0):
    """Draw the ground truth and the ``methods`` rows of a long track table (``method, x_m, y_m``).

    ``image``: the floor plan as an array (``plt.imread``), stretched over ``[0, width] x [0, height]``
    metres (``size_m``). ``margin_m``: the view is the box around the truth and the drawn tracks plus this
    margin (a walk of a few tens of metres is unreadable on a 240 m floor); None shows the whole plan.
    Returns the Axes.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(8, 6))
    if image is not None and size_m is not None:
        ax.imshow(image, extent=(0, size_m[0], 0, size_m[1]), origin="upper", alpha=0.6)
    t = np.asarray(truth_xy_m, dtype=np.float64)
    ax.plot(t[:, 0], t[:, 1], "k.-", lw=2, label="ground truth (waypoints)")
    drawn = [t]
    for m in methods:
        d = track[track["method"] == m]
        if len(d):
            ax.plot(d["x_m"], d["y_m"], "-" if m != "wifi" else ".", lw=1.2, label=m)
            drawn.append(d[["x_m", "y_m"]].to_numpy(dtype=np.float64))
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    xy = np.concatenate(drawn)
    xy = xy[np.isfinite(xy).all(axis=1)]
    if margin_m is not None and len(xy):
        lo, hi = xy.min(axis=0) - margin_m, xy.max(axis=0) + margin_m
        half = (hi - lo).max() / 2.0  # a square view: equal metres on both axes without stretching the box
        mid = (lo + hi) / 2.0
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_aspect("equal", adjustable="box")
    else:
        ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=8)
    return ax


def save_tracks_on_plan(path, track, truth_xy_m, png_bytes=None, size_m=None, title="", methods=None) -> None:
    """:func:`tracks_on_plan` into an image file (the ``evaluate track --plot`` output); ``png_bytes``: the
    floor plan image file's content (or None)."""
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    img = None if png_bytes is None else plt.imread(io.BytesIO(png_bytes), format="png")
    ax = tracks_on_plan(track, truth_xy_m, img, size_m, **({} if methods is None else {"methods": methods}))
    ax.set_title(title)
    ax.figure.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(ax.figure)
