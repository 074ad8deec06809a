"""Notebook tables show whole numbers without decimals and text in full; track plots zoom without warnings."""

from __future__ import annotations

import warnings

import matplotlib
import numpy as np
import pandas as pd
import pytest

import ilocviz
import ilocviz.fusion

matplotlib.use("Agg")


@pytest.mark.parametrize(("value", "shown"), [(8.0, "8"), (-3.0, "-3"), (1.2345678, "1.235"), (0.012345, "0.01235"),
                                              (12345.67, "12345.7"), (float("nan"), "NaN"), (float("inf"), "inf")])
def test_readable_number(value, shown):
    assert ilocviz.readable_number(value) == shown


def test_table_display_sets_the_kernels_pandas_options():
    with pd.option_context("display.float_format", None, "display.max_colwidth", 50):
        ilocviz.table_display()
        df = pd.DataFrame({"n_ap": [8.0, 12.0], "mean_m": [1.23456, 2.5], "note": ["x" * 80, "y"]})
        html = df._repr_html_()
        assert "8.000000" not in html and ">8<" in html and ">1.235<" in html and "x" * 80 in html


def test_tracks_with_both_limits_fixed_warn_nothing():
    import matplotlib.pyplot as plt

    track = pd.DataFrame({"method": ["truth"] * 3, "x_m": [0.0, 10.0, 20.0], "y_m": [0.0, 5.0, 0.0]})
    fig, ax = plt.subplots()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ilocviz.fusion.tracks(track, ax=ax)
        ax.set_xlim(5, 15)
        ax.set_ylim(0, 4)
        fig.canvas.draw()
    assert ax.get_xlim() == (5, 15) and ax.get_ylim() == (0, 4)
    assert np.isclose(ax.get_data_ratio(), 0.4)
    plt.close(fig)
