"""Long scan table -> RSSI matrix (the one pivot of the toolkit)."""

import numpy as np
import pandas as pd
import pytest

from ilocalg.io.scans import scan_matrix


def _scans():
    return pd.DataFrame({"t_s": [1.0, 1.0, 1.0, 3.0, 2.0, 2.0],
                         "scan_id": [0, 0, 0, 2, 1, 1],
                         "bssid": ["a", "b", "z", "b", "c", "a"],
                         "rssi_dbm": [-50.0, -60.0, -70.0, -65.0, -80.0, -55.0]})


def test_pivot_matches_a_pandas_pivot_over_the_given_aps():
    s = _scans()
    sids, t, X = scan_matrix(s, ("a", "b", "c"))
    np.testing.assert_array_equal(sids, [0, 1, 2])
    np.testing.assert_array_equal(t, [1.0, 2.0, 3.0])
    ref = s.pivot(index="scan_id", columns="bssid", values="rssi_dbm").reindex(columns=["a", "b", "c"])
    np.testing.assert_array_equal(X, ref.to_numpy())          # "z" is not a column; NaN = not heard


def test_keep_mask_leaves_nan_but_keeps_every_scan_row():
    s = _scans()
    keep = s["bssid"].ne("b").to_numpy() & s["scan_id"].ne(2).to_numpy()
    sids, t, X = scan_matrix(s, ["a", "b", "c"], keep=keep)
    assert X.shape == (3, 3) and np.isnan(X[2]).all()
    assert np.isnan(X[:, 1]).all() and X[0, 0] == -50.0 and X[1, 2] == -80.0
    with pytest.raises(ValueError, match="keep must have shape"):
        scan_matrix(s, ["a"], keep=[True])
    with pytest.raises(ValueError, match="rssi_dbm"):
        scan_matrix(s.drop(columns="rssi_dbm"), ["a"])


def test_string_dtypes_and_a_repeated_column_id():
    """The loaders' pyarrow strings give the same matrix as Python strings; a column id listed twice gets its
    readings in its last column (what a dict {id: column} gives), the other column stays NaN."""
    s = _scans()
    _, _, X = scan_matrix(s, ["a", "b", "c"])
    for dtype in ("string[pyarrow]", "string[python]", "category"):
        _, _, Y = scan_matrix(s.astype({"bssid": dtype}), ["a", "b", "c"])
        np.testing.assert_array_equal(Y, X)
    _, _, R = scan_matrix(s, ["a", "b", "a"])
    assert np.isnan(R[:, 0]).all()
    np.testing.assert_array_equal(R[:, 2], X[:, 0])
    np.testing.assert_array_equal(R[:, 1], X[:, 1])
