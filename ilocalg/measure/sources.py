"""Iterators over the shared public recordings used by the measurements.

Nothing is copied or extracted: the ILC 2.0 site1 archive is streamed member by member.
"""

from __future__ import annotations

import tarfile
from pathlib import Path

from ilocalg.io.ilc import parse_ilc_trace
from ilocalg.io.paths import data_dir

__all__ = ["ILC_SITE1", "ilc_site1_archive", "iter_ilc_site1"]

ILC_SITE1 = "ilc2020_site1"


def ilc_site1_archive(root=None) -> Path:
    """Path of ``site1_F1_F2.tar.xz`` under the data directory (ValueError when absent)."""
    base = Path(root) if root is not None else data_dir() / ILC_SITE1
    p = base if base.is_file() else base / "site1_F1_F2.tar.xz"
    if not p.is_file():
        raise ValueError(f"{p}: ILC 2.0 site1 archive not found (set ILOC_DATA_DIR or see README 'Real data')")
    return p


def iter_ilc_site1(root=None, every: int = 1):
    """Yield ``(floor, trace_id, IlcTrace)`` for the site1 walks, in archive order.

    Parameters
    ----------
    root : path, optional
        The data-set folder or the archive (default: ``data_dir()/ilc2020_site1``).
    every : int
        Keep the walks whose trace id (hex) is divisible by ``every`` (a deterministic subsample,
        about 1/every of the walks; 1 = all). Duplicate BSSIDs within a scan are resolved with the loader's
        ``duplicate_bssid="keep_latest"`` policy.
    """
    if every < 1:
        raise ValueError(f"every must be >= 1, got {every}")
    arch = ilc_site1_archive(root)
    with tarfile.open(arch) as tar:
        for m in tar:
            if not (m.isfile() and "/path_data_files/" in m.name and m.name.endswith(".txt")):
                continue
            stem = Path(m.name).stem
            if _pick(stem, every):
                data = tar.extractfile(m).read()
                floor = m.name.split("/")[0].replace("site1_", "")
                yield floor, stem, parse_ilc_trace(data, f"{arch}:{m.name}", duplicate_bssid="keep_latest",
                                                     relisted_wifi="keep")  # the scan measures drop re-listings


def _pick(stem: str, every: int) -> bool:
    """Deterministic subsample: the trace id (a hex object id) modulo ``every`` is 0."""
    if every == 1:
        return True
    try:
        return int(stem, 16) % every == 0
    except ValueError:
        return sum(stem.encode()) % every == 0
