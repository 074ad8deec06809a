"""Study plumbing (ilocalg.workflow.studies) and the study plots (ilocviz.studies)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from ilocalg.experiments import study_kf_noise  # noqa: E402
from ilocalg.workflow import studies as sc  # noqa: E402
from ilocalg.workflow import sweep as sw  # noqa: E402
from ilocviz import studies as vs  # noqa: E402


def test_item_round_trip_and_errors():
    s = sc.item_label(method="KNN (Manhattan, K=5)", window_s=5)
    assert s == "method=KNN (Manhattan, K=5);window_s=5"
    assert sc.parse_item(s) == {"method": "KNN (Manhattan, K=5)", "window_s": "5"}
    assert sc.parse_item("") == {}
    with pytest.raises(ValueError, match=";"):
        sc.item_label(method="a;b")
    with pytest.raises(ValueError, match="NAME=VALUE"):
        sc.parse_item("oops")


def test_study_tasks_removes_the_shared_base_point():
    grids = [{"a": [1, 2, 3], "b": [0]}, {"a": [1], "b": [0, 5]}]
    t = sc.study_tasks("study_kf_noise", grids, range(2))
    assert len(t) == 2 * (3 + 1)
    assert len({x.key for x in t}) == len(t)


def test_curves_expand_params_and_items_and_plots_draw_them():
    tasks = sc.study_tasks("study_kf_noise", [{"noise_scale": [0.5, 2.0], "fix_every": [3], "n_walks": [3],
                                               "n_steps": [30]}], range(3))
    res = sw.sweep(tasks, workers=0, cache_dir=None, progress=False)
    agg = sw.aggregate(res.results)
    cv = sc.curves(agg, "study_kf_noise")
    assert {"noise_scale", "fix_every", "method", "mean", "ci95_low", "ci95_high", "n"} <= set(cv.columns)
    assert cv["noise_scale"].dtype.kind == "f" and (cv["n"] == 3).all()
    d = sc.select(cv, "mean error", fix_every=3)
    assert set(d["method"].dropna()) == set(study_kf_noise.METHODS)
    assert (d["ci95_low"] <= d["mean"]).all() and (d["mean"] <= d["ci95_high"]).all()
    with pytest.raises(ValueError, match="no column"):
        sc.select(cv, "mean error", nope=1)
    with pytest.raises(ValueError, match="no aggregated rows"):
        sc.curves(agg, "study_pso")
    fig, ax = plt.subplots()
    out = vs.ci_curves(d, "noise_scale", by="method", ax=ax, xlabel="noise scale [-]", logx=True)
    assert out is ax and ax.get_ylabel() == "mean error [m]" and ax.get_xscale() == "log"
    assert len(ax.get_legend().get_texts()) == len(study_kf_noise.METHODS)
    vs.ci_reference(d.iloc[0], ax=ax, label="ref")
    assert np.isclose(ax.lines[-1].get_ydata()[0], d.iloc[0]["mean"])
    plt.close(fig)


def test_notebook_tasks_are_the_studies_tasks_in_the_notebooks_order():
    import importlib

    for stem, names in sc.NOTEBOOK_STUDIES.items():
        seeds = sc.study_seeds(3, fast=True)
        want = [t for n in names for t in importlib.import_module(f"ilocalg.experiments.{n}").tasks(seeds, True)]
        assert [t.key for t in sc.notebook_tasks(stem, 3, True)] == [t.key for t in want]
    assert list(sc.study_seeds(5, False)) == list(range(5, 17))
    with pytest.raises(ValueError, match="not a study notebook"):
        sc.notebook_tasks("01_wifi_radar_horus_knn", 0, True)


def test_under_reproduce_the_tasks_come_from_the_pools_cache_and_equal_a_run_here(tmp_path, monkeypatch):
    tasks = study_kf_noise.tasks(range(1), True)[:3]
    here = sw.sweep(tasks, workers=0, cache_dir=None, progress=False).results
    sw.sweep(tasks[:2], workers=0, cache_dir=tmp_path, progress=False)  # what the pool ran before the notebook
    monkeypatch.setenv(sc.STUDY_CACHE_ENV, str(tmp_path))
    res, how = sc.run_notebook_tasks(tasks)
    assert how == "reproduce pool" and res.n_cached == 2 and res.n_tasks == 3 and not res.failures
    pd.testing.assert_frame_equal(res.results, here, check_exact=True)
