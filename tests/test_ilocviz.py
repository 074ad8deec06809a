import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import ilocviz  # noqa: E402


def test_plots_return_axes_with_units_and_savefig_writes_png_pdf(tmp_path):
    with ilocviz.style():
        ax = ilocviz.error_cdf({"a": [1.0, 2.0, 3.0]})
        assert "[m]" in ax.get_xlabel()
        ax2 = ilocviz.trajectory({"truth": np.zeros((3, 2))}, floor_plan=[np.array([[0, 0], [1, 1]])])
        assert ax2.get_xlabel() == "x [m]" and ax2.get_ylabel() == "y [m]"
        paths = ilocviz.savefig(ax.figure, "demo", tmp_path)
    assert [p.suffix for p in paths] == [".png", ".pdf"]
    assert all(p.stat().st_size > 0 for p in paths)
    assert ilocviz.savefig(ax.figure, "demo", None) == []
    plt.close("all")


def test_error_cdf_refuses_nan():
    with pytest.raises(ValueError, match="NaN"):
        ilocviz.error_cdf({"a": [1.0, np.nan]})
    plt.close("all")


def test_style_restores_only_what_it_set_and_keeps_interactive_mode():
    before = {k: matplotlib.rcParams[k] for k in ilocviz.STYLE}
    was_interactive = matplotlib.is_interactive()
    try:
        with ilocviz.style():
            assert matplotlib.rcParams["axes.grid"] is True
            matplotlib.interactive(True)  # what the inline backend does when pyplot first loads in the block
            matplotlib.rcParams["lines.markersize"] = 11.0  # not a STYLE key: kept after the block
        assert matplotlib.is_interactive()
        assert matplotlib.rcParams["lines.markersize"] == 11.0
        assert {k: matplotlib.rcParams[k] for k in ilocviz.STYLE} == before
    finally:
        matplotlib.interactive(was_interactive)
        matplotlib.rcParams["lines.markersize"] = matplotlib.rcParamsDefault["lines.markersize"]


def test_paper_values_are_drawn_beside_reproduced_ones_with_reader_names():
    import pandas as pd

    ax = ilocviz.error_cdf({"kf": [1.0, 2.0, 4.0]}, paper={"KF mean (i-Loc Fig 23)": 2.82})
    labels = ax.get_legend_handles_labels()[1]
    assert labels[0].startswith("Kalman filter (PDR + Wi-Fi) (mean 2.33 m)")
    assert "paper: KF mean (i-Loc Fig 23)" in labels
    line = next(h for h, lab in zip(*ax.get_legend_handles_labels(), strict=True) if lab.startswith("paper"))
    assert line.get_xdata()[0] == pytest.approx(2.82)
    with pytest.raises(ValueError, match="axis"):
        ilocviz.paper_mark(ax, 1.0, "x", axis="z")
    table = pd.DataFrame({"item": ["Fig 23", "Fig 23", "Table 2"], "quantity": ["KF mean", "PTS mean", "corr"],
                          "paper_value": [2.82, 5.15, 0.0], "reproduced_value": [2.82, 10.3, 0.4],
                          "mean": [3.0, 10.3, 0.4], "ci95_low": [2.5, 9.0, 0.3], "ci95_high": [3.5, 11.0, 0.5]})
    ax = ilocviz.paper_vs_reproduced(table, title="i-Loc Fig 23")
    (points,) = [ln for ln in ax.get_lines() if ln.get_label() == "reproduced / paper"]
    assert points.get_xdata() == pytest.approx([3.0 / 2.82, 10.3 / 5.15])  # the paper value 0 is left out
    assert [t.get_text() for t in ax.get_yticklabels()] == ["Fig 23: KF mean", "Fig 23: PTS mean"]
    assert ax.get_xscale() == "log" and ax.get_title() == "i-Loc Fig 23"
    assert ilocviz.legend_name("pf_smooth") == "particle filter + smoother" and ilocviz.legend_name("mine") == "mine"
    plt.close("all")
