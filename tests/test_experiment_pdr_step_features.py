"""Experiment pdr_step_features: SAM ranges and counts (notebook 03), the Oxford real-data row, the rate sweep."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.experiments import pdr_step_features


@pytest.mark.realdata
def test_oxford_leave_one_recording_out(shared_data):
    root = shared_data("oxford_step_counter")
    t = pdr_step_features.oxford_loro(root, max_recordings=3)
    assert len(t) == 3 and (t["position"] == "InHand").all()
    np.testing.assert_allclose(t["error"], (t["counted"] - t["true_steps"]).abs() / t["true_steps"])
    assert t["worst_test"].isin(["A2", "A", "T1", "T2", "T", "X1", "I"]).all()
    assert t["why"].str.contains("true steps fail").all()
    again = pdr_step_features.oxford_loro(root, max_recordings=3)
    pd.testing.assert_frame_equal(t, again)


def test_oxford_missing_data_is_reported_not_raised(tmp_path):
    t = pdr_step_features.oxford_loro(tmp_path)
    assert list(t.columns) == ["missing"]


def test_rate_sweep_x1_scales_with_the_rate():
    r = pdr_step_features.rate_sweep(0, (25.0, 50.0), n_train=2, n_test=1, n_steps=20)
    assert list(r["rate_hz"]) == [25.0, 50.0]
    assert r["X1_max"].iloc[1] > 1.5 * r["X1_max"].iloc[0]  # X1 sums about twice the samples at 50 Hz
    assert list(pdr_step_features.readings().columns) == ["choice", "paper_line", "text_says", "code_does",
                                                          "source"]


@pytest.mark.realdata
def test_oxford_archive_is_found_under_the_data_root_or_its_own_folder(shared_data):
    folder = shared_data("oxford_step_counter")
    assert pdr_step_features._oxford_archive(folder.parent) == folder / pdr_step_features.OXFORD_ARCHIVE
    assert pdr_step_features._oxford_archive(folder) == folder / pdr_step_features.OXFORD_ARCHIVE


def test_the_held_recordings_are_read_once_per_process_and_again_when_the_archive_changes(tmp_path, monkeypatch):
    import os

    archive = tmp_path / pdr_step_features.OXFORD_ARCHIVE
    archive.write_bytes(b"first")
    reads = []

    def fake_load(path, select=None):
        reads.append(path)
        return [f"rec{len(reads)}"]

    monkeypatch.setattr(pdr_step_features, "load_oxford_archive", fake_load)
    monkeypatch.setattr(pdr_step_features, "_HELD", {})
    first = pdr_step_features._held_recordings(archive, "InHand")
    assert pdr_step_features._held_recordings(archive, "InHand") == first == ("rec1",) and len(reads) == 1
    assert pdr_step_features._held_recordings(archive, "InPocket") == ("rec2",)  # another position: read
    archive.write_bytes(b"second, longer")
    os.utime(archive, ns=(1, 1))
    assert pdr_step_features._held_recordings(archive, "InHand") == ("rec3",) and len(reads) == 3
