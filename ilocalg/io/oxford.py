"""Loader for the Oxford step counter data set (smartphone accelerometer walks with true steps).

Two layouts are read:

Optimisation recording
    A folder ``<Phone>_<User>_<Surface>_<Position>_<n>/`` (or that member of the
    ``optimisation_data.tar.xz`` archive) holding ``accelerometer.csv`` (no header: timestamp in ns
    since boot, accuracy flag, ax, ay, az in m/s^2) and ``stepcounter.csv`` (no header: timestamp
    in ns, left-foot state, right-foot state; 1 = foot down, from heel pressure sensors). A true
    step is a 0 -> 1 transition of either foot state.
Validation recording
    One headerless CSV with seven columns: timestamp (ns), ax, ay, az (m/s^2), the app's
    cumulative step count, the true cumulative step count, the phone's hardware cumulative step
    count. True steps are the increments of the true count; the total is its last value.

Times are returned in seconds relative to the first accelerometer sample. Nothing is dropped or
repaired: a malformed file raises ValueError naming the file, the line and the column.

References
----------
Oxford step counter DataSet (github.com/Oxford-step-counter/DataSet), CC BY 4.0; its README.
"""

from __future__ import annotations

import io
import tarfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import check_increasing
from ilocalg.io.schema import ACC_COLS, T_S

__all__ = [
    "OxfordRecording",
    "load_oxford_step_counter",
    "load_oxford_archive",
    "list_oxford_archive",
    "parse_recording_name",
]

ACC_FILE = "accelerometer.csv"
STEP_FILE = "stepcounter.csv"


@dataclass(frozen=True)
class OxfordRecording:
    """One walk: the accelerometer log and the true steps.

    Attributes
    ----------
    name : str
        Recording name (folder name, or the CSV file stem).
    imu : DataFrame
        Indexed by ``t_s`` (s from the first sample) with ``acc_x_mps2, acc_y_mps2, acc_z_mps2``.
    step_t_s : ndarray
        Times of the true steps, s (same origin as ``imu``).
    true_steps : int
        Number of true steps.
    hardware_steps : int or None
        The phone's hardware step counter over the walk (validation layout only).
    meta : dict
        ``phone``, ``user``, ``surface``, ``position`` parsed from the name when it follows the
        optimisation naming scheme.
    """

    name: str
    imu: pd.DataFrame
    step_t_s: np.ndarray
    true_steps: int
    hardware_steps: int | None = None
    meta: dict = field(default_factory=dict)


def parse_recording_name(name: str) -> dict:
    """``Pixel_Jamie_Hard_InHand_1`` -> phone, user, surface, position (position case-normalised)."""
    parts = name.split("_")
    if len(parts) != 5:
        return {}
    phone, user, surface, position, _ = parts
    norm = {"armband": "Armband", "backpocket": "BackPocket"}
    return {"phone": phone, "user": user, "surface": surface, "position": norm.get(position.lower(), position)}


def _read_numeric_csv(data: bytes, source: str, ncols: int, names) -> np.ndarray:
    """Parse a headerless numeric CSV; ValueError naming file, line and column on bad content."""
    text = data.decode("utf-8", errors="strict") if isinstance(data, bytes) else data
    rows = [ln for ln in text.splitlines()]
    if not any(r.strip() for r in rows):
        raise ValueError(f"{source}: file is empty")
    try:
        df = pd.read_csv(io.StringIO(text), header=None, dtype=np.float64, engine="c")
    except ValueError:
        df = None
    if df is not None and df.shape[1] == ncols and np.isfinite(df.to_numpy()).all():
        return df.to_numpy()
    # slow path: find and name the first bad line/column
    for k, ln in enumerate(rows, start=1):
        if not ln.strip():
            raise ValueError(f"{source}: line {k} is empty")
        cells = ln.split(",")
        if len(cells) != ncols:
            raise ValueError(f"{source}: line {k} has {len(cells)} columns, expected {ncols} ({', '.join(names)})")
        for j, c in enumerate(cells):
            try:
                v = float(c)
            except ValueError:
                raise ValueError(f"{source}: line {k}, column {j + 1} ({names[j]}): not a number: {c!r}") from None
            if not np.isfinite(v):
                raise ValueError(f"{source}: line {k}, column {j + 1} ({names[j]}): not finite: {c!r}")
    raise ValueError(f"{source}: could not parse as {ncols} numeric columns")


def _check_increasing(t_ns: np.ndarray, source: str) -> None:
    # no header: record i is on line i + 1
    check_increasing(t_ns, range(1, len(t_ns) + 1), source,
                     lambda i, kind: f"{kind} timestamp ({int(t_ns[i])} after {int(t_ns[i - 1])}); "
                                     "timestamps must increase", column="1 (timestamp_ns)")


def _imu_frame(t_ns: np.ndarray, acc: np.ndarray) -> pd.DataFrame:
    t = (t_ns - t_ns[0]) * 1e-9
    df = pd.DataFrame(acc, columns=list(ACC_COLS), index=pd.Index(t, name=T_S))
    return df


def _optimisation_recording(name: str, acc_bytes: bytes, step_bytes: bytes, source: str) -> OxfordRecording:
    acc_src = f"{source}/{ACC_FILE}"
    step_src = f"{source}/{STEP_FILE}"
    a = _read_numeric_csv(acc_bytes, acc_src, 5, ("timestamp_ns", "accuracy", "ax_mps2", "ay_mps2", "az_mps2"))
    s = _read_numeric_csv(step_bytes, step_src, 3, ("timestamp_ns", "left_foot", "right_foot"))
    if a.shape[0] < 2:
        raise ValueError(f"{acc_src}: needs at least 2 samples, got {a.shape[0]}")
    _check_increasing(a[:, 0], acc_src)
    _check_increasing(s[:, 0], step_src)
    feet = s[:, 1:]
    bad = np.argwhere((feet != 0) & (feet != 1))
    if bad.size:
        k, j = bad[0]
        raise ValueError(f"{step_src}: line {k + 1}, column {j + 2} "
                         f"({('left_foot', 'right_foot')[j]}): foot state must be 0 or 1, got {feet[k, j]}")
    up = (feet[1:] == 1) & (feet[:-1] == 0)
    k_step = np.flatnonzero(up.any(axis=1)) + 1
    n_steps = int(up.sum())
    # a row where both feet land at once counts twice (it never happens in the set)
    step_t = np.repeat((s[k_step, 0] - a[0, 0]) * 1e-9, up[k_step - 1].sum(axis=1))
    return OxfordRecording(name=name, imu=_imu_frame(a[:, 0], a[:, 2:5]), step_t_s=step_t,
                           true_steps=n_steps, hardware_steps=None, meta=parse_recording_name(name))


def _validation_recording(path: Path) -> OxfordRecording:
    src = str(path)
    names = ("timestamp_ns", "ax_mps2", "ay_mps2", "az_mps2", "app_count", "true_count", "hardware_count")
    v = _read_numeric_csv(path.read_bytes(), src, 7, names)
    if v.shape[0] < 2:
        raise ValueError(f"{src}: needs at least 2 samples, got {v.shape[0]}")
    _check_increasing(v[:, 0], src)
    true = v[:, 5]
    d = np.diff(true)
    if np.any(d < 0):
        k = int(np.flatnonzero(d < 0)[0]) + 2
        raise ValueError(f"{src}: line {k}, column 6 (true_count): cumulative count decreases")
    inc = np.flatnonzero(d > 0) + 1
    step_t = np.repeat((v[inc, 0] - v[0, 0]) * 1e-9, d[inc - 1].astype(np.int64))
    hw = v[:, 6]
    return OxfordRecording(name=path.stem, imu=_imu_frame(v[:, 0], v[:, 1:4]), step_t_s=step_t,
                           true_steps=int(round(true[-1])), hardware_steps=int(round(hw[-1] - hw[0])),
                           meta=parse_recording_name(path.stem))


def _is_archive(p: Path) -> bool:
    return p.is_file() and (p.name.endswith((".tar.xz", ".tar", ".tar.gz", ".tgz", ".txz")))


def _archive_members(tf: tarfile.TarFile) -> dict[str, dict[str, tarfile.TarInfo]]:
    recs: dict[str, dict[str, tarfile.TarInfo]] = {}
    for m in tf.getmembers():
        if not m.isfile():
            continue
        parts = m.name.split("/")
        if len(parts) >= 2 and parts[-1] in (ACC_FILE, STEP_FILE):
            recs.setdefault(parts[-2], {})[parts[-1]] = m
    return recs


def list_oxford_archive(path) -> list[str]:
    """Names of the recordings (folders with both CSV files) in an optimisation archive, sorted."""
    p = Path(path)
    if not _is_archive(p):
        raise ValueError(f"{p}: not a tar archive")
    with tarfile.open(p) as tf:
        recs = _archive_members(tf)
    return sorted(k for k, v in recs.items() if len(v) == 2)


def load_oxford_archive(path, names=None) -> list[OxfordRecording]:
    """Every recording (or those named) of an optimisation archive, in one pass, sorted by name."""
    p = Path(path)
    if not _is_archive(p):
        raise ValueError(f"{p}: not a tar archive")
    out = []
    with tarfile.open(p) as tf:
        recs = _archive_members(tf)
        wanted = sorted(k for k, v in recs.items() if len(v) == 2) if names is None else list(names)
        for n in wanted:
            if n not in recs or len(recs[n]) != 2:
                raise ValueError(f"{p}: no recording {n!r} with {ACC_FILE} and {STEP_FILE}; "
                                 f"recordings: {sorted(recs)[:5]}...")
            acc = tf.extractfile(recs[n][ACC_FILE]).read()
            st = tf.extractfile(recs[n][STEP_FILE]).read()
            out.append(_optimisation_recording(n, acc, st, f"{p}:{n}"))
    return sorted(out, key=lambda r: r.name)


def load_oxford_step_counter(path, member: str | None = None) -> OxfordRecording:
    """Load one Oxford step counter recording.

    Parameters
    ----------
    path : str or Path
        A recording folder (holding ``accelerometer.csv`` and ``stepcounter.csv``), the
        ``optimisation_data.tar.xz`` archive (then ``member`` names the recording), or a
        validation-style single headerless CSV (seven columns, see the module docstring).
    member : str, optional
        Recording name inside an archive (e.g. ``"Pixel_Jamie_Hard_InHand_1"``).

    Returns
    -------
    OxfordRecording

    Raises
    ------
    ValueError
        Missing files, malformed lines (naming file, line and column), non-increasing timestamps.
    """
    p = Path(path)
    if not p.exists():
        raise ValueError(f"{p}: no such file or folder")
    if p.is_dir():
        acc, st = p / ACC_FILE, p / STEP_FILE
        for f in (acc, st):
            if not f.is_file():
                raise ValueError(f"{p}: recording folder lacks {f.name}")
        return _optimisation_recording(p.name, acc.read_bytes(), st.read_bytes(), str(p))
    if _is_archive(p):
        if member is None:
            raise ValueError(f"{p}: an archive holds several recordings; pass member= one of "
                             f"{list_oxford_archive(p)[:3]}...")
        return load_oxford_archive(p, [member])[0]
    if p.suffix.lower() in (".csv", ".txt"):
        return _validation_recording(p)
    raise ValueError(f"{p}: expected a recording folder, a .tar.xz archive or a validation .csv file")
