"""Where the simulators' numbers come from: measured statistics on real recordings beside the same
statistics measured on the simulated worlds (notebook 16_measured_worlds).

``run(seed, fast, worlds, data_dir)`` simulates each world (the i-Loc floor and walkers on its route),
measures it with the functions that measured data/measured_parameters.csv
(:mod:`ilocalg.measure.simulated`) and returns:

``real_vs_sim``
    One row per compared statistic: the real value and interval (the committed table) and, per
    world (``measured``: calibrated, the default; ``copied``: measured values copied, uncalibrated;
    ``assumed``), the simulated value, interval and ``<world>_calibrated`` (real value inside the
    simulated interval).
``distributions``
    Long table ``quantity, source, value`` of raw samples for the histograms: shadowing residuals,
    scan lag (reading age), WDM misalignment per segment, relative step period and amplitude; the
    real samples only when ../shared/data is present (a subsample of the ILC walks).
``table``
    data/measured_parameters.csv as committed.
``calibrated``
    data/calibrated_parameters.csv as committed: each calibrated simulator parameter with its target
    statistic, the value copied before, the statistic at the copied and at the calibrated value.
``measures``
    Named scalars: how many compared statistics each world reproduces.
``readings``
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.measure import simulated
from ilocalg.measure.stats import N_BOOT, bootstrap
from ilocalg.papers import reading, readings_table
from ilocalg.sim import gait, iloc_floor
from ilocalg.sim.measured import calibrated_table, param, table
from ilocalg.units import as_rng

__all__ = ["run", "real_samples", "readings", "findings", "N_BOOT_FAST"]

#: Bootstrap replicates of the simulated statistics' intervals in fast mode (a smoke run: the intervals are
#: coarser than with the :data:`ilocalg.measure.stats.N_BOOT` of the full run, which the measured table uses too).
N_BOOT_FAST = 100


def readings() -> pd.DataFrame:
    rows = [
        ("real statistics", "", "not in the papers", "data/measured_parameters.csv (python -m ilocalg measure): "
         "UJIIndoorLoc, Oxford step counter InHand walks, ILC 2.0 site1 walks (1/8 subsample)",
         "public recordings, no paper result used"),
        ("simulated statistics", "", "not in the papers", "the same measurement functions on the i-Loc floor survey "
         "and test session and on walkers walking its 28-point route", "ilocalg.measure.simulated"),
        ("calibrated", "", "not in the papers", "the real value lies inside the simulated 95 % bootstrap interval",
         "issue 24 acceptance"),
        ("worlds", "", "not in the papers", "measured = copied values, inverse-calibrated where a copied value does "
         "not come back (data/calibrated_parameters.csv, python -m ilocalg measure --calibrate, seeds 0-2); copied = "
         "the measured values copied into the parameters (uncalibrated); assumed = the published-value world",
         "ilocalg.measure.calibrate; recordings' statistics only"),
        ("scan lag, simulated", "", "silent", "walking_scans reads each AP at a uniform time within the scan and "
         "the scan is stamped at its end: age ~ U(0, latency), latency = the measured scan interval",
         "ilocalg.sim.iloc_floor.walking_scans"),
        ("real samples", "", "not in the papers", "ILC walks with trace id % 16 == 0 (% 32 in fast mode); all "
         "UJIIndoorLoc training scans; the 16 Oxford InHand walks", "deterministic subsample"),
    ]
    return readings_table([reading(*r) for r in rows])


def real_samples(data_dir=None, every: int = 16) -> pd.DataFrame:
    """Raw real samples for the histograms (``quantity, source, value``); empty when the data are absent."""
    from ilocalg.io.paths import data_dir as default_dir
    from ilocalg.measure import gait as mgait
    from ilocalg.measure import heading, radio, scans
    from ilocalg.measure.sources import iter_ilc_site1
    from ilocalg.measure.table import uji_places

    root = Path(data_dir) if data_dir else default_dir()
    out = []
    if (root / "ujiindoorloc").is_dir():
        from ilocalg.io.ujiindoorloc import load_ujiindoorloc

        tr = load_ujiindoorloc(root / "ujiindoorloc" / "trainingData.csv.gz")
        place = uji_places(tr)
        phone = tr.meta["PHONEID"].to_numpy()
        off = radio.device_offsets_db(tr.rssi_dbm, place, phone).reindex(phone).fillna(0.0).to_numpy()
        pm, _ = radio.place_means(tr.rssi_dbm, place, off)
        first = pd.Series(np.arange(len(place))).groupby(place).first().to_numpy()
        pl = radio.path_loss_per_ap(np.column_stack([tr.x_m[first], tr.y_m[first]]), pm,
                                    tr.building[first] * 10 + tr.floor[first])
        res = np.concatenate(list(pl.attrs["residuals"].values()))
        out.append(pd.DataFrame({"quantity": "shadow_residual_db", "source": "real (UJIIndoorLoc)", "value": res}))
    if (root / "ilc2020_site1").is_dir():
        ages, mis = [], []
        hs = []
        for fl, _, trc in iter_ilc_site1(root / "ilc2020_site1", every=every):
            ages.append(scans.reading_ages_s(trc.wifi))
            if len(trc.rotation_vector):
                hs.append(heading.segment_headings(trc.imu, trc.rotation_vector, trc.waypoints).assign(floor=fl))
        H = pd.concat(hs, ignore_index=True)
        mis = np.degrees(heading.misalignment(H["wdm_rad"], H["dir_rad"], H["floor"]))
        out.append(pd.DataFrame({"quantity": "reading_age_s", "source": "real (ILC site1)",
                                 "value": np.concatenate(ages)}))
        out.append(pd.DataFrame({"quantity": "misalignment_deg", "source": "real (ILC site1)", "value": mis}))
    if (root / "oxford_step_counter").is_dir():
        from ilocalg.io.oxford import load_oxford_archive

        arch = root / "oxford_step_counter" / "optimisation_data.tar.xz"
        for r in load_oxford_archive(arch, select=lambda n: "_InHand_" in n):
            s = mgait.step_series(r.imu.to_numpy(), r.imu.index.to_numpy(), r.step_t_s)
            med = s["T_s"].median()
            s = s[(s["T_s"] > mgait.STEADY_BAND[0] * med) & (s["T_s"] < mgait.STEADY_BAND[1] * med)]
            out.append(pd.DataFrame({"quantity": "step_T_rel", "source": "real (Oxford InHand)",
                                     "value": s["T_s"] / s["T_s"].median()}))
            out.append(pd.DataFrame({"quantity": "step_A_rel", "source": "real (Oxford InHand)",
                                     "value": s["A_mps2"] / s["A_mps2"].median()}))
    if not out:
        return pd.DataFrame(columns=["quantity", "source", "value"])
    return pd.concat(out, ignore_index=True)


def _simulate_world(world: str, seed, fast: bool, n_walkers: int):
    rng = as_rng(seed)
    sim = iloc_floor.simulate(rng, scans_per_point=30 if fast else 90, scans_per_test_point=5, world=world)
    n_boot = N_BOOT_FAST if fast else N_BOOT
    rstats, rsamp = simulated.radio_measures(sim, n_boot=n_boot)
    route = iloc_floor.route_xy_m()
    cfg = gait.gait_config(world)
    walks = [gait.simulate_walk(route, w, rng, cfg) for w in gait.make_walkers(n_walkers, rng, world=world)]
    gstats, gsamp = simulated.gait_measures(walks, route, n_boot=n_boot)
    latency = 2.0 if world == "assumed" else param("wifi_scan_interval_s")
    lag = simulated.scan_lag_model_s(latency, n=1000, rng=int(rng.integers(2**31)))
    e = bootstrap(lag[:1000], np.median, n_boot)
    stats = {**rstats, **gstats, "wifi_reading_age_median_s": e.as_dict()}
    samp = {**rsamp, **gsamp, "reading_age_s": lag}
    return stats, samp


def run(seed: int = 0, fast: bool = False, worlds=("measured", "copied", "assumed"), data_dir=None,
        n_walkers: int = 8) -> dict[str, pd.DataFrame]:
    """Real vs simulated statistics; see the module docstring."""
    if fast:
        n_walkers = min(n_walkers, 3)
    sims, dist = {}, []
    for w in worlds:
        st, samp = _simulate_world(w, seed, fast, n_walkers)
        sims[f"sim_{w}"] = st
        for q, v in samp.items():
            dist.append(pd.DataFrame({"quantity": q, "source": f"simulated ({w})", "value": np.asarray(v)}))
    real = table().reset_index(drop=True)
    comp = simulated.side_by_side(real, sims)
    rs = real_samples(data_dir, every=32 if fast else 16)
    distributions = pd.concat([rs, *dist], ignore_index=True)
    meas = [{"quantity": f"calibrated statistics ({w})", "value": float(comp[f"sim_{w}_calibrated"].fillna(False)
                                                                         .astype(bool).sum()),
             "unit": "count", "item": f"of {len(comp)}"} for w in worlds]
    return {"real_vs_sim": comp, "distributions": distributions, "table": real, "measures": pd.DataFrame(meas),
            "calibrated": calibrated_table().reset_index(drop=True), "readings": readings()}


def findings(tables: dict) -> str:
    """Sentences computed from the tables (for the notebook's closing cell)."""
    comp = tables["real_vs_sim"]
    n = len(comp)
    lines = []
    for w in [c[4:-11] for c in comp.columns if c.startswith("sim_") and c.endswith("_calibrated")]:
        ok = comp[f"sim_{w}_calibrated"].fillna(False).astype(bool)
        miss = ", ".join(comp.loc[~ok, "parameter"]) or "none"
        lines.append(f"- {w} world: {int(ok.sum())} of {n} statistics inside the simulated interval; missed: {miss}.")
    cal = tables.get("calibrated")
    if cal is not None and len(cal):
        c = cal[cal["target"].notna()]
        for r in c.itertuples():
            lines.append(f"- {r.parameter}: copied {r.copied:.4g} gave {r.statistic} = {r.at_copied:.4g}; calibrated "
                         f"{r.value:.4g} [{r.ci_low:.4g}, {r.ci_high:.4g}] gives {r.at_value:.4g} (real {r.target:.4g} "
                         f"[{r.target_ci_low:.4g}, {r.target_ci_high:.4g}], mean of the calibration seeds).")
    return "\n".join(lines)
