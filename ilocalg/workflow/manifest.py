"""Which experiments each notebook runs, and which of them reproduce re-runs over seeds.

One explicit table, read by the reproduce runner (what to sweep for confidence intervals, which
seed-0 runs a notebook records for the sweep) and checked by a test against the notebooks and the
experiment modules on disk, so adding a notebook or an experiment means adding one line here.

An experiment is *swept* when its comparison rows depend on the simulation seed: reproduce then
re-runs it over ``--seeds`` seeds and gives every row a 95 % confidence interval. Not swept:
experiments on real recordings (nothing depends on the seed), the data tour (no comparison rows),
and the studies (``study_*``), which run their own parameter sweeps. An experiment is swept in at
most one notebook: the one whose run at the base seed the sweep reuses.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

__all__ = ["MANIFEST", "SWEEP_KWARGS", "COST_S", "experiments_of", "swept_experiments", "notebook_stems"]

#: notebook stem -> {experiment module under ``ilocalg.experiments``: swept over seeds?}
MANIFEST: dict[str, dict[str, bool]] = {
    "00_data_tour": {"data_tour": False},  # no comparison rows
    "01_wifi_radar_horus_knn": {"wifi_iloc": True},
    "02_wifi_ujiindoorloc": {"wifi_ujiindoorloc": False, "wifi_transfer": False},  # real recordings
    "03_pdr_step_features": {"pdr_step_features": True},
    "04_pdr_step_length": {"pdr_step_length": True},
    # pso_k_factor: only its compass filter study here; swept with notebook 10
    "05_pdr_heading_trajectory": {"pdr_heading_trajectory": True, "pso_k_factor": False},
    "06_pdr_real_steps": {"pdr_real_steps": False},  # real recordings
    "07_fusion_iloc_kf": {"fusion_iloc_kf": True},
    "08_fusion_knn_pdr": {"fusion_knn_pdr": True},
    "09_fusion_real_walks": {"fusion_real_walks": False},  # real recordings, no paper comparison
    "10_pso_k_factor": {"pso_k_factor": True},
    "11_photo_positioning": {"photo_positioning": True},
    "12_ins_constraints_gcp": {"ins_constraints": True},
    "13_ins_online_window": {"ins_online": True},
    "14_imu_video_ekf": {"ins_hartmann": True},
    "15_sweep_studies": {"study_wifi": False, "study_ins_window": False, "study_kf_noise": False,
                         "study_pso": False},  # each study sweeps its own parameters
    "16_measured_worlds": {"measured_worlds": False},  # real vs simulated statistics, no paper comparison
}

#: Keywords with which every sweep task of an experiment runs (the seed sweep's runs at the other seeds, the
#: claims' robustness samples, ``python -m ilocalg sweep``; a task's own parameters override them): they leave out
#: side studies whose tables the sweep does not read (only comparison rows, ``sweep_*`` and ``measures*`` tables
#: are kept, :func:`ilocalg.papers.claims.tables_to_long`), so a task gives the same long results with or without
#: them in a fraction of the time (each experiment's tests check it; tests/test_manifest.py that every keyword is one
#: of the experiment's ``run()``). The notebook's own run keeps every table.
SWEEP_KWARGS: dict[str, dict] = {
    "ins_constraints": {"side_studies": False},  # 232 -> about 20 CPU-s per full-mode seed
    "ins_hartmann": {"noise_scales": (), "outage_factors": ()},  # tracker-noise and outage sweeps
    "fusion_knn_pdr": {"sweeps": False},  # survey/detector/latency sweeps; full-mode seed 12.0 -> 3.1 CPU-s
    "pso_k_factor": {"side_studies": False},  # PSO repeats, sensitivity, ILC study; 10.5 -> 2.1 CPU-s
    "fusion_iloc_kf": {"wifi_methods": (), "latencies_s": ()},  # estimator/latency sweeps; 9.5 -> 3.0 CPU-s
    "photo_positioning": {"side_studies": False},  # the thesis's methods only; 7.5 -> 5.7 CPU-s
    # one timing pass instead of the best of 3 (the time per query is measured, never the same twice; every other
    # long result is unchanged); full-mode seed 21.6 -> 10.2 CPU-s
    "wifi_iloc": {"timing_repeats": 1},
}


#: Wall time in seconds of each notebook and of one seed-sweep run of each experiment (``sweep:<name>``), full
#: mode, measured by a ``reproduce --seeds 5`` on a busy 2-core machine. Only their order matters: jobs run
#: longest first when notebooks run side by side; the runner prefers the times it measured on the last run
#: (``.ilocalg-cache/timings.json``).
COST_S: dict[str, float] = {
    "00_data_tour": 42,
    "01_wifi_radar_horus_knn": 27,
    "02_wifi_ujiindoorloc": 120,
    "03_pdr_step_features": 12,
    "04_pdr_step_length": 15,
    "05_pdr_heading_trajectory": 13,
    "06_pdr_real_steps": 53,
    "07_fusion_iloc_kf": 18,
    "08_fusion_knn_pdr": 15,
    "09_fusion_real_walks": 118,
    "10_pso_k_factor": 42,
    "11_photo_positioning": 61,
    "12_ins_constraints_gcp": 69,
    "13_ins_online_window": 18,
    "14_imu_video_ekf": 26,
    "15_sweep_studies": 186,
    "16_measured_worlds": 120,
    "sweep:fusion_iloc_kf": 3,
    "sweep:fusion_knn_pdr": 1,
    "sweep:ins_constraints": 66,
    "sweep:ins_hartmann": 25,
    "sweep:ins_online": 7,
    "sweep:pdr_heading_trajectory": 1,
    "sweep:pdr_step_features": 1,
    "sweep:pdr_step_length": 2,
    "sweep:photo_positioning": 15,
    "sweep:pso_k_factor": 12,
    "sweep:wifi_iloc": 1,
}


def notebook_stems() -> list[str]:
    """Every notebook the manifest knows, in run order."""
    return sorted(MANIFEST)


def experiments_of(stem: str, manifest: Mapping[str, Mapping[str, bool]] | None = None) -> list[str]:
    """Experiments the notebook ``stem`` runs (ValueError for a notebook missing from the manifest)."""
    manifest = MANIFEST if manifest is None else manifest
    if stem not in manifest:
        raise ValueError(f"notebook {stem!r} is not in ilocalg/workflow/manifest.py MANIFEST; add it there "
                         f"with the experiments it runs")
    return list(manifest[stem])


def swept_experiments(stems: Iterable[str], swept_only: bool = True,
                      manifest: Mapping[str, Mapping[str, bool]] | None = None) -> list[str]:
    """Experiments the notebooks ``stems`` run (only the seed-swept ones by default), in notebook order."""
    manifest = MANIFEST if manifest is None else manifest
    out: list[str] = []
    for stem in stems:
        experiments_of(stem, manifest)  # validates the stem
        for exp, swept in manifest[stem].items():
            if (swept or not swept_only) and exp not in out:
                out.append(exp)
    return out
