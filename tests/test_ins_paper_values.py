import pandas as pd
import pytest

from ilocalg.ins.paper_values import HARTMANN_TABLE2_OVERALL, LIAO_TABLES, paper_value, side_by_side


def test_liao_tables_complete_and_lookup():
    assert len(LIAO_TABLES) == 96  # 2 phones x (4 methods + 4 online rows) x 3 stats x 2 kinds
    assert paper_value("Samsung", "Filtering + NHC/ZUPT", "rms", "N") == pytest.approx(14.8002)
    assert paper_value("iPhone", "Online 20sec", "std", "Heading") == pytest.approx(24.3132)
    # the filter row of Tables 8-11 is the Filtering + WVC/ZUPT + GCP row of Tables 4-7
    for phone in ("Samsung", "iPhone"):
        for stat in ("max", "rms", "std"):
            for kind in ("pos", "att"):
                assert LIAO_TABLES[(phone, "Filtering", stat, kind)] == \
                    LIAO_TABLES[(phone, "Filtering + WVC/ZUPT + GCP", stat, kind)]
    with pytest.raises(ValueError, match="axis"):
        paper_value("Samsung", "Filtering", "rms", "X")
    with pytest.raises(ValueError, match="no paper value"):
        paper_value("Nokia", "Filtering", "rms", "N")
    assert set(HARTMANN_TABLE2_OVERALL) >= {"mean_dev_x_m", "max_dev_z_m", "vt_rate_hz"}


def test_side_by_side_layout():
    errors = pd.DataFrame({"phone": ["iPhone", "Samsung", "Samsung"], "method": ["Filtering"] * 3,
                           "stat": ["rms", "std", "max"], "N": [1.0, 2.0, 3.0], "E": [4.0, 5.0, 6.0]})
    t = side_by_side(errors, ("N", "E"))
    assert list(t.columns) == ["phone", "stat", "method", "N paper", "N sim", "E paper", "E sim"]
    assert list(zip(t.phone, t.stat, strict=True)) == [("Samsung", "max"), ("Samsung", "std"), ("iPhone", "rms")]
    assert t.loc[0, "N paper"] == paper_value("Samsung", "Filtering", "max", "N") and t.loc[0, "N sim"] == 3.0
