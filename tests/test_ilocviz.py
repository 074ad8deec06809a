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


def test_savefig_formats_from_the_environment(tmp_path, monkeypatch):
    """The reproduce runner's fast mode names PNG only (ilocalg.workflow.reporting.FIGURE_FORMATS_ENV)."""
    from ilocalg.workflow.reporting import FIGURE_FORMATS_ENV

    fig, ax = plt.subplots()
    ax.plot([0, 1])
    monkeypatch.setenv(FIGURE_FORMATS_ENV, "png")
    assert [p.name for p in ilocviz.savefig(fig, "one", tmp_path)] == ["one.png"]
    assert [p.suffix for p in ilocviz.savefig(fig, "two", tmp_path, formats=("pdf",))] == [".pdf"]  # explicit wins
    monkeypatch.setenv(FIGURE_FORMATS_ENV, "png, SVG")
    assert [p.suffix for p in ilocviz.savefig(fig, "three", tmp_path)] == [".png", ".svg"]
    monkeypatch.setenv(FIGURE_FORMATS_ENV, "png,jpeg")
    with pytest.raises(ValueError, match="ILOC_FIGURE_FORMATS='png,jpeg'"):
        ilocviz.savefig(fig, "four", tmp_path)
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


def test_paper_values_select_comparison_rows_and_paper_point_marks_one():
    import pandas as pd

    table = pd.DataFrame({"paper": ["i-Loc (Chiu 2013)"] * 3, "item": ["Fig 3", "Fig 3", "Fig 5"],
                          "quantity": ["RADAR median error", "best AP count k", "Horus median error"],
                          "unit": ["m", "APs", "m"], "paper_value": [4.5, 5.0, 4.5],
                          "reproduced_value": [0.9, 6.0, 0.0]})
    assert ilocviz.paper_values(table, unit="m") == {"RADAR median error (i-Loc (Chiu 2013) Fig 3)": 4.5,
                                                     "Horus median error (i-Loc (Chiu 2013) Fig 5)": 4.5}
    assert list(ilocviz.paper_values(table, item="Fig 3", contains="MEDIAN").values()) == [4.5]
    with pytest.raises(ValueError, match="Fig 9"):
        ilocviz.paper_values(table, item="Fig 9")
    ax = ilocviz.paper_point(ilocviz.new_axes(), 4.5, 0.5, "RADAR median (i-Loc Fig 3)")
    (pt,) = ax.get_lines()
    assert pt.get_label() == "paper: RADAR median (i-Loc Fig 3)"
    assert (pt.get_xdata()[0], pt.get_ydata()[0]) == (4.5, 0.5)
    plt.close("all")


def test_paper_mark_widens_fixed_limits_so_the_paper_value_is_in_view():
    ax = ilocviz.new_axes()
    ax.plot([0, 1], [2, 9])
    ax.set_ylim(0, 10)  # fixed limits, as plots that pin the bottom at 0 have
    ilocviz.paper_mark(ax, 11.38, "Wi-Fi mean", axis="y", band=(1.0, 21.5))
    assert ax.get_ylim()[0] == 0 and ax.get_ylim()[1] >= 21.5
    ilocviz.paper_point(ax, -2.0, 5.0, "a point left of the view")
    assert ax.get_xlim()[0] <= -2.0
    plt.close("all")


def test_window_study_paper_puts_each_online_row_on_its_phone_axis_line():
    import pandas as pd

    import ilocviz.ins as vins

    sweep = pd.DataFrame({"phone": ["iPhone"] * 2, "window_s": [5.0, 10.0], "stat": ["rms"] * 2,
                          "N": [1.0, 0.8], "E": [0.5, 0.4], "H": [0.3, 0.2]})
    ax = vins.window_study(sweep)
    cmp = pd.DataFrame({"paper": ["Liao et al. 2016"] * 3, "item": ["Table 10"] * 3,
                        "quantity": ["iPhone WVC/ZUPT/GCP Online 5sec: RMS N error",
                                     "iPhone WVC/ZUPT/GCP Filtering: RMS N error",
                                     "iPhone WVC/ZUPT/GCP Online 10sec: RMS E error"],
                        "paper_value": [1.0969, 0.9885, 1.2766]})
    vins.window_study_paper(ax, cmp)
    stars = [ln for ln in ax.get_lines() if ln.get_marker() == "*"]
    assert [(s.get_xdata()[0], s.get_ydata()[0]) for s in stars] == [(5.0, 1.0969), (10.0, 1.2766)]
    colours = {ln.get_label(): ln.get_color() for ln in ax.get_lines()}
    assert stars[0].get_color() == colours["iPhone-N"] and stars[1].get_color() == colours["iPhone-E"]
    with pytest.raises(ValueError, match="Online"):
        vins.window_study_paper(ax, cmp.iloc[[1]])
    plt.close("all")


def test_paper_vs_reproduced_labels_at_least_three_plain_ratios():
    import pandas as pd

    table = pd.DataFrame({"item": ["T"] * 3, "quantity": ["a", "b", "c"], "paper_value": [1.0, 1.0, 1.0],
                          "reproduced_value": [0.9, 1.05, 1.2]})
    ax = ilocviz.paper_vs_reproduced(table)
    ax.figure.canvas.draw()
    lo, hi = ax.get_xlim()
    shown = [t for t in ax.get_xticks() if lo <= t <= hi]
    assert len(shown) >= 3
    assert all("10^" not in lab.get_text() and "times" not in lab.get_text() for lab in ax.get_xticklabels())
    plt.close("all")


def test_error_cdf_counts_unlocated_and_ends_below_one():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ilocviz.error_cdf({"KNN": [1.0, 2.0, np.nan, 3.0]}, ax=ax)
    line = ax.get_lines()[0]
    assert line.get_ydata().max() == pytest.approx(0.75)
    assert "1 not located" in line.get_label() and "mean 2.00" in line.get_label()
    with pytest.raises(ValueError, match="all NaN"):
        ilocviz.error_cdf({"KNN": [np.nan]}, ax=ax)
    plt.close(fig)


def test_error_budget_bars_and_weight_sensitivity():
    import pandas as pd

    import ilocviz.fusion

    rows = []
    for m, base in (("KF", 4.0), ("PTS", 8.0)):
        for s, e in (("none (as simulated)", base), ("Wi-Fi fix error", base / 2), ("heading", base * 1.1),
                     ("all of them", 0.2)):
            rows.append({"method": m, "replaced_by_truth": s, "mean_error_m": e, "share_of_error": (base - e) / base})
    ax = ilocviz.fusion.error_budget_bars(pd.DataFrame(rows))
    assert [t.get_text() for t in ax.get_yticklabels()] == ["Wi-Fi fix error", "heading"]
    assert len(ax.patches) == 4 and min(p.get_width() for p in ax.patches) < 0  # a negative share is drawn
    with pytest.raises(ValueError, match="no budget rows"):
        ilocviz.fusion.error_budget_bars(pd.DataFrame(rows), methods=["nope"])
    sw = pd.DataFrame({"weight": [0.1, 0.5, 1.0], "mean_error_m": [3.0, 2.0, 2.5], "wifi_only_mean_m": 2.5,
                       "pdr_only_mean_m": 5.0, "default": [False, True, False]})
    ax2 = ilocviz.fusion.weight_sensitivity(sw)
    assert "[m]" in ax2.get_ylabel() and any("default" in t.get_text() for t in ax2.get_legend().get_texts())
    plt.close("all")


def test_figure_title_prefers_suptitle_then_axes_titles_then_the_name():
    import matplotlib.pyplot as plt

    from ilocviz import figure_title

    fig, (a, b) = plt.subplots(1, 2)
    assert figure_title(fig, "07_fusion_cdf") == "07 fusion cdf"
    a.set_title("Error CDF")
    b.set_title("Tracks\non the floor")
    assert figure_title(fig) == "Error CDF / Tracks on the floor"
    fig.suptitle("KF against Wi-Fi")
    assert figure_title(fig) == "KF against Wi-Fi"
    plt.close(fig)


def test_method_bars_horizontal_names_every_method_and_draws_the_reference():
    import pandas as pd

    import ilocviz.wifi

    df = pd.DataFrame({"method": ["a long method name", "b"], "mean_m": [3.0, 5.0], "median_m": [2.0, 4.0],
                       "p75_m": [4.0, 6.0]})
    fig, ax = plt.subplots()
    ilocviz.wifi.method_bars(df, ax=ax, horizontal=True, reference=(4.5, "paper"))
    assert [t.get_text() for t in ax.get_yticklabels()] == list(df["method"])
    assert ax.get_xlabel() == "2-D error [m]"
    assert [ln.get_xdata()[0] for ln in ax.get_lines()] == [4.5]
    assert "paper" in [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(fig)


def test_error_cdf_curves_past_the_colour_cycle_are_dashed():
    n = len(plt.rcParams["axes.prop_cycle"].by_key()["color"])
    fig, ax = plt.subplots()
    ilocviz.error_cdf({f"m{i}": np.arange(1.0, 4.0) + i for i in range(n + 1)}, ax=ax)
    styles = [ln.get_linestyle() for ln in ax.get_lines()]
    assert styles[:n] == ["-"] * n and styles[n] == "--"
    plt.close(fig)
