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
