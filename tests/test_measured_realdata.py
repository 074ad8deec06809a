"""data/measured_parameters.csv recomputed from ../shared/data: fails when a committed value drifts.

Kept near a minute: the cheap rows are recomputed exactly (Oxford gait rows, UJIIndoorLoc device
offsets and APs per scan, the ILC site1 scan rows on the committed subsample, trace id % 8 == 0,
scans only). The radio fits, the gait segments and the headings are left to ``make measured``.
"""

from __future__ import annotations

import numpy as np
import pytest

from ilocalg.measure import table as mt
from ilocalg.sim import measured


def _committed(name):
    return measured.row(name)


@pytest.mark.realdata
def test_oxford_gait_rows_recompute_exactly(shared_data):
    from ilocalg.io.oxford import list_oxford_archive, load_oxford_archive

    arch = shared_data("oxford_step_counter") / "optimisation_data.tar.xz"
    rows = mt.oxford_gait_rows(load_oxford_archive(arch, [n for n in list_oxford_archive(arch) if "_InHand_" in n]))
    for r in rows:
        c = _committed(r["parameter"])
        for k in ("value", "ci_low", "ci_high"):
            assert r[k] == pytest.approx(c[k], rel=1e-4, abs=1e-9), (r["parameter"], k)


@pytest.mark.realdata
def test_uji_device_offsets_and_aps_per_scan_recompute_exactly(shared_data):
    from ilocalg.io.ujiindoorloc import load_ujiindoorloc
    from ilocalg.measure import radio
    from ilocalg.measure.stats import bootstrap

    tr = load_ujiindoorloc(shared_data("ujiindoorloc") / "trainingData.csv.gz")
    off = radio.device_offsets_db(tr.rssi_dbm, mt.uji_places(tr), tr.meta["PHONEID"].to_numpy())
    e = bootstrap(off.to_numpy(), lambda x: float(np.std(x, ddof=1)))
    assert e.value == pytest.approx(_committed("device_offset_sd_db")["value"], rel=1e-4)
    assert e.ci_high == pytest.approx(_committed("device_offset_sd_db")["ci_high"], rel=1e-4)
    aps = bootstrap(radio.aps_per_scan(tr.rssi_dbm).astype(float), np.median)
    assert aps.value == _committed("aps_per_scan_median")["value"]


@pytest.mark.realdata
def test_ilc_scan_rows_recompute_exactly(shared_data):
    from ilocalg.measure.sources import iter_ilc_site1
    from ilocalg.workflow.commands.measure import DEFAULT_EVERY

    walks = [mt.ilc_walk_measures(t, parts=("scans",))
             for _, _, t in iter_ilc_site1(shared_data("ilc2020_site1"), every=DEFAULT_EVERY)]
    assert len(walks) >= 10
    for r in mt.scan_rows(walks):
        c = _committed(r["parameter"])
        for k in ("value", "ci_low", "ci_high"):
            assert r[k] == pytest.approx(c[k], rel=1e-4), (r["parameter"], k)
