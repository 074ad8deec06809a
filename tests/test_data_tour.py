import numpy as np

from ilocalg.experiments import data_tour
from ilocalg.io.summaries import dataset_availability, real_dataset_summaries


def test_absent_real_sets_are_reported_not_raised(tmp_path):
    av = dataset_availability(tmp_path)
    assert not av["present"].any()
    assert real_dataset_summaries(tmp_path) == {}


def test_embedded_summary_is_deterministic_and_plausible():
    a = data_tour.embedded_summary(seed=1, fast=True)
    b = data_tour.embedded_summary(seed=1, fast=True)
    assert a["embedded"].equals(b["embedded"])
    emb = a["embedded"].set_index("set")
    assert set(emb.index) == {"iloc_floor", "gait", "pso_walks", "ins_walk", "hartmann", "photo_poi"}
    assert abs(emb.loc["hartmann", "rate_hz"] - 400.0) < 1e-6
    assert abs(emb.loc["pso_walks", "rate_hz"] - 8.0) < 1e-9
    assert 4 <= emb.loc["iloc_floor", "aps_per_scan_median"] <= 18
    assert np.isfinite(emb.loc["gait", "distance_m"])


def test_real_summaries_on_the_shared_copies(shared_data):
    root = shared_data("ujiindoorloc").parent
    shared_data("oxford_step_counter")
    shared_data("ilc2020_site2_F4")
    out = real_dataset_summaries(root, fast=True)
    uji = out["ujiindoorloc"].set_index("file")
    assert uji.loc["trainingData.csv.gz", "rows"] == 19937 and uji.loc["validationData.csv.gz", "rows"] == 1111
    assert (out["oxford_step_counter"]["true_steps"] > 0).all()
    assert out["ilc2020_site2_F4"]["imu_rate_hz"].between(49, 51).all()
