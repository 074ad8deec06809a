"""Tracks of one walk drawn on its floor plan (the ILC ``floor_image.png``)."""

from __future__ import annotations

import numpy as np

__all__ = ["tracks_on_plan", "save_tracks_on_plan"]


def tracks_on_plan(track, truth_xy_m, image=None, size_m=None, methods=("wifi", "kf_rts", "lsq"), ax=None):
    """Draw the ground truth and the ``methods`` rows of a long track table (``method, x_m, y_m``).

    ``image``: the floor plan as an array (``plt.imread``), stretched over ``[0, width] x [0, height]``
    metres (``size_m``). Returns the Axes.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(8, 6))
    if image is not None and size_m is not None:
        ax.imshow(image, extent=(0, size_m[0], 0, size_m[1]), origin="upper", alpha=0.6)
    t = np.asarray(truth_xy_m, dtype=np.float64)
    ax.plot(t[:, 0], t[:, 1], "k.-", lw=2, label="ground truth (waypoints)")
    for m in methods:
        d = track[track["method"] == m]
        if len(d):
            ax.plot(d["x_m"], d["y_m"], "-" if m != "wifi" else ".", lw=1.2, label=m)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
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
