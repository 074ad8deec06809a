"""The Wi-Fi estimator registry (ilocalg.wifi.registry) and evaluate_method (ilocalg.wifi.evaluate)."""

import numpy as np
import pytest
from sklearn.base import clone

from ilocalg.io.schema import FingerprintSet
from ilocalg.wifi import ESTIMATORS, KnnFingerprint, SimplifiedHorus, SimplifiedRadar, evaluate_method, make_estimator
from ilocalg.wifi.registry import PAPER_ESTIMATORS, paper_estimators, register_estimator


def test_registry_names_and_types():
    assert list(ESTIMATORS) == ["radar", "horus", "knn", "wknn", "best", "toolkit"]
    types = {"radar": SimplifiedRadar, "horus": SimplifiedHorus, "knn": KnnFingerprint, "wknn": KnnFingerprint,
             "best": SimplifiedRadar}
    for name, cls in types.items():
        est = make_estimator(name, not_heard_dbm=-100.0)
        assert type(est) is cls and est.not_heard_dbm == -100.0
        clone(est)                                        # scikit-learn contract: parameters stored unchanged
    assert make_estimator("knn", 3, "manhattan").get_params()["p"] == 1
    assert make_estimator("wknn").get_params()["weights"] == "distance"
    assert make_estimator("best").get_params()["n_neighbors"] == 12


def test_toolkit_is_the_headline_configuration():
    from ilocalg.wifi.candidates import TOOLKIT_HEADLINE, headline_members

    est = make_estimator("toolkit", not_heard_dbm=-100.0)
    members = est.get_params()["est__estimators"]
    assert [n for n, _ in members] == list(TOOLKIT_HEADLINE["members"])
    assert est.get_params()["est__n_neighbors"] == TOOLKIT_HEADLINE["n_neighbors"] == 8
    assert make_estimator("toolkit", 5).get_params()["est__n_neighbors"] == 5
    for (_, e), (_, ref) in zip(members, headline_members(), strict=True):   # the grid's members, floor changed
        p, q = e.get_params(), ref.get_params()
        plain = {k for k in p if not hasattr(p[k], "get_params")}                 # not the inner estimator object
        assert {k for k in plain if p[k] != q[k]} == {k for k in plain if k.split("__")[-1] == "not_heard_dbm"}
        assert all(v == -100.0 for k, v in p.items() if k.split("__")[-1] == "not_heard_dbm")
    clone(est)
    with pytest.raises(ValueError, match="not a member of headline_grid"):
        headline_members(("offset_powed", "no_such_member"))


def test_paper_estimators_are_the_papers_configurations():
    ests = paper_estimators(-95.0, k_aps=4)
    assert list(ests) == list(PAPER_ESTIMATORS)
    r, h, k = ests["Simplified-RADAR"], ests["Simplified-Horus"], ests["KNN (Manhattan, K=5)"]
    assert (r.k_aps, r.n_neighbors, r.not_heard_dbm) == (4, 3, -95.0)
    assert (h.k_aps, h.bin_width_db, h.prob_floor) == (4, 1.0, 1e-3)
    assert (k.n_neighbors, k.p, k.weights) == (5, 1, "uniform")


def test_bad_names_fail_clearly_and_duplicates_are_refused():
    with pytest.raises(ValueError, match="method must be one of"):
        make_estimator("svm")
    with pytest.raises(ValueError, match="metric"):
        make_estimator("knn", metric="cosine")
    with pytest.raises(ValueError, match="already registered"):
        register_estimator("knn")(lambda **kw: None)


def _set(rng, n, centres):
    pos = rng.uniform(0, 20, (n, 2))
    d = np.linalg.norm(pos[:, None] - centres[None], axis=2)
    rssi = -40 - 20 * np.log10(d + 1) + rng.normal(0, 2, d.shape)
    floor = (pos[:, 0] > 10).astype(int)
    return FingerprintSet(rssi_dbm=rssi, x_m=pos[:, 0], y_m=pos[:, 1], floor=floor, building=np.zeros(n, int),
                          ap_ids=tuple(f"ap{i}" for i in range(centres.shape[0])))


@pytest.mark.parametrize("method", ["radar", "horus", "knn", "wknn", "best", "toolkit", "hierarchical"])
def test_evaluate_method_locates_a_synthetic_floor(method):
    rng = np.random.default_rng(0)
    aps = rng.uniform(0, 20, (8, 2))
    train, test = _set(rng, 300, aps), _set(rng, 60, aps)
    res = evaluate_method(train, test, method, not_heard_dbm=-110.0)
    assert res["error_m"].shape == (60,) and res["xy_m"].shape == (60, 2)
    assert np.median(res["error_m"]) < 5.0                 # 20 m x 20 m floor, 8 APs, 2 dB noise
    assert np.mean(res["floor"] == test.floor) > 0.6           # chance: 0.5
    assert res["fit_s"] >= 0 and res["predict_s"] >= 0


def test_cli_methods_are_the_registry():
    from ilocalg.workflow.commands import evaluate_wifi

    assert evaluate_wifi.METHODS == tuple(ESTIMATORS)
