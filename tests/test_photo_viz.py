"""Smoke-and-content tests of ilocviz.photo on a tiny experiment run."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from ilocalg.experiments import photo_positioning as pp  # noqa: E402
from ilocviz import photo as photoviz  # noqa: E402


@pytest.fixture(scope="module")
def tables():
    return pp.run(seed=0, n_photos=1, ks=(2, 3, 7), va_max_iter=200)


def test_every_plot_returns_labelled_axes(tables):
    calls = [
        lambda ax: photoviz.layout(tables["layout_pois"], tables["layout_shots"], ax=ax),
        lambda ax: photoviz.layout(tables["layout_pois"], tables["layout_shots"], ax=ax, view="front"),
        lambda ax: photoviz.error_per_shot(tables["per_shot"], ax=ax),
        lambda ax: photoviz.error_vs_k(tables["per_k"], ax=ax, comparison=tables["comparison"]),
        lambda ax: photoviz.error_per_combo(tables["per_combo"], ax=ax),
        lambda ax: photoviz.conditioning_scatter(tables["per_combo"], ax=ax),
        lambda ax: photoviz.propagation(tables["propagation"], ax=ax),
    ]
    for call in calls:
        fig, ax = plt.subplots()
        assert call(ax) is ax
        assert "[" in ax.get_xlabel() or ax.get_xticklabels()
        assert "[" in ax.get_ylabel()
        plt.close(fig)


def test_per_combo_highlights_the_thesis_combinations(tables):
    fig, ax = plt.subplots()
    photoviz.error_per_combo(tables["per_combo"], ax=ax)
    n_hi = len(ax.containers[1].patches)
    assert n_hi == 4  # {1,3}, {1,4}, {5,6}, {1,3,4}
    plt.close(fig)
    with pytest.raises(ValueError, match="view"):
        photoviz.layout(tables["layout_pois"], tables["layout_shots"], view="side")
