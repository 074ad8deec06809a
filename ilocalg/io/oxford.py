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
    count. True steps are the increments of the true count (the total is its last minus its first
    value, so that the step times and the total always agree). The cumulative counts must be
    whole numbers that never decrease; a hardware count column that is 0 throughout means the
    phone has no hardware counter (``hardware_steps=None``).

Times are returned in seconds relative to the first accelerometer sample. Nothing is silently
dropped or repaired: a malformed file raises ValueError naming the file, the line and the column.
The real-world quirks with a policy: a timestamp repeated on consecutive lines
(``duplicate_timestamps="drop"``, counted; the error message names that option), and heel-sensor
bounces in the optimisation recordings' ground truth (``heel_bounces="merge"``, counted): a foot
that lands again less than :data:`MIN_STRIDE_S` after its previous landing. The heel sensors are
read at about 11 Hz, and in some recordings a foot state drops to 0 for one to three readings
(0.09-0.29 s) in mid-stance and back; each such drop adds a second 0 -> 1 transition of that foot,
i.e. a "step" that was not taken. Under the default ``"keep"`` the truth is the published count (the
``steps`` column of ``optimisation_stats.csv``); the bounces are counted either way
(:attr:`OxfordRecording.n_heel_bounces`).

References
----------
Oxford step counter DataSet (github.com/Oxford-step-counter/DataSet), CC BY 4.0; its README.
"""

from __future__ import annotations

import csv
import io
import re
import tarfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ilocalg.io._text import ArchiveReader, check_increasing, decode_text, read_bytes, strip_trailing_blank_lines
from ilocalg.io.schema import ACC_COLS, T_S, check_range

__all__ = [
    "OxfordRecording",
    "load_oxford_step_counter",
    "load_oxford_archive",
    "list_oxford_archive",
    "parse_recording_name",
    "DUPLICATE_POLICIES",
    "HEEL_BOUNCE_POLICIES",
    "MIN_STRIDE_S",
    "heel_bounces_mask",
]

#: Policies for a timestamp repeated on consecutive lines (see :func:`load_oxford_step_counter`).
DUPLICATE_POLICIES = ("error", "drop")
#: Policies for heel-sensor bounces in the optimisation recordings' truth (see :func:`load_oxford_step_counter`).
HEEL_BOUNCE_POLICIES = ("keep", "merge")
#: Shortest time between two real heel strikes of one foot (a stride), s: two steps of at least 0.25 s, the
#: step detectors' own shortest step (:data:`ilocalg.pdr.robust.ROBUST_DEFAULTS` ``min_step_s``, 240
#: steps/min, above walking cadences: 100-130 steps/min typical, Tudor-Locke et al. 2011, Int J Behav Nutr
#: Phys Act 8:80). Measured on the 48 optimisation recordings: the intervals between landings of one foot
#: have a bulk at 0.6-1.8 s (per-foot medians 0.98-1.49 s) and a separate cluster of 109 at 0.15-0.50 s,
#: with none in 0.50-0.55 s.
MIN_STRIDE_S = 0.5
_BLANK_LINE = re.compile(r"\n[ \t\r]*\n")

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
        The phone's hardware step counter over the walk (validation layout only); ``None`` when
        the file has no hardware counter (six columns, or a seventh column that is 0 throughout).
    meta : dict
        ``phone``, ``user``, ``surface``, ``position`` parsed from the name when it follows the
        optimisation naming scheme.
    n_duplicate_timestamps_dropped : int
        Rows dropped by ``duplicate_timestamps="drop"`` (0 under ``"error"``).
    n_heel_bounces : int
        Heel-sensor bounces found in the truth (a landing of a foot less than :data:`MIN_STRIDE_S`
        after its last kept landing; optimisation layout only, else 0), whatever the policy.
    n_heel_bounces_merged : int
        Of those, the ones merged into the contact before under ``heel_bounces="merge"`` (0 under
        ``"keep"``); ``true_steps`` is then the published count less this number.
    n_unpaired_landings : int
        Landings (bounces left out) that follow a landing of the same foot with no landing of the other
        foot between: walking alternates the feet, so each is most likely a landing of the other foot
        that its sensor did not register (a step the truth lacks). Counted, never added to the truth.
    step_is_heel_bounce : ndarray of bool or None
        Beside ``step_t_s``: True at the steps that are heel-sensor bounces (optimisation layout; all False
        under ``heel_bounces="merge"``, which leaves them out); None for the validation layout.
        ``step_t_s[~step_is_heel_bounce]`` are the step times with the bounces merged, whatever the policy.
    """

    name: str
    imu: pd.DataFrame
    step_t_s: np.ndarray
    true_steps: int
    hardware_steps: int | None = None
    meta: dict = field(default_factory=dict)
    n_duplicate_timestamps_dropped: int = 0
    n_heel_bounces: int = 0
    n_heel_bounces_merged: int = 0
    n_unpaired_landings: int = 0
    step_is_heel_bounce: np.ndarray | None = None


def parse_recording_name(name: str) -> dict:
    """``Pixel_Jamie_Hard_InHand_1`` -> phone, user, surface, position (position case-normalised)."""
    parts = name.split("_")
    if len(parts) != 5:
        return {}
    phone, user, surface, position, _ = parts
    norm = {"armband": "Armband", "backpocket": "BackPocket"}
    return {"phone": phone, "user": user, "surface": surface, "position": norm.get(position.lower(), position)}


def _read_numeric_csv(data: bytes, source: str, ncols, names) -> np.ndarray:
    """Parse a headerless numeric CSV; ValueError naming file, line and column on bad content.

    ``ncols`` is the expected number of columns, or a tuple of accepted numbers (the first
    line decides). Under the common text policy a byte-order mark is stripped, CRLF line ends
    and trailing blank lines are accepted, a blank line inside the data is an error (it would
    shift every later line number). Well-formed files are parsed by pandas' C reader on the
    bytes as they are; anything else line by line, naming the first bad line and column.
    """
    if isinstance(data, list):  # [bytes]: handed over, so that the bytes are freed once parsed
        data = data.pop()
    if isinstance(data, str):
        data = data.encode("utf-8")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    if not data.isascii():
        decode_text(data, source)  # a non-UTF-8 byte is an error naming its line
    end = len(data)
    while end and data[end - 1] in b"\r\n \t":
        end -= 1
    if end == 0:
        raise ValueError(f"{source}: file is empty")
    accepted = (ncols,) if isinstance(ncols, int) else tuple(ncols)
    nl = data.find(b"\n", 0, end)
    first = data[:nl if nl >= 0 else end]
    ncols = first.count(b",") + 1 if first.count(b",") + 1 in accepted else accepted[0]
    # blank lines are kept (skip_blank_lines=False): one inside the data is a row of NaN, refused below, and
    # the line parser names it; trailing blank lines and spaces are left out of what pandas reads
    src = data if data[end:] in (b"", b"\n", b"\r\n") else data[:end]
    try:
        df = pd.read_csv(io.BytesIO(src), header=None, dtype=np.float64, engine="c", quoting=csv.QUOTE_NONE,
                         skip_blank_lines=False, na_filter=False)  # an empty or missing cell fails the parse
    except (ValueError, pd.errors.ParserError):
        df = None
    del src
    # (pandas reads True/False as 1/0; float() refuses them: such files go line by line)
    letters = any(c in data for c in (b"r", b"R", b"l", b"L"))
    if df is not None and df.shape[1] == ncols and all(
            np.isfinite(x.min()) and np.isfinite(x.max()) and not (letters and np.any((x == 0.0) | (x == 1.0)))
            for x in (df[c].to_numpy() for c in df.columns)):
        # the bytes are no longer needed (freed here unless the caller keeps them); then one column at a
        # time into the table, each freed once copied (the frame holds one array per column: to_numpy
        # would keep a second whole copy beside it)
        del data
        v = np.empty(df.shape, dtype=np.float64, order="F")
        for j, c in enumerate(list(df.columns)):
            v[:, j] = df.pop(c).to_numpy()
        return v
    del df
    return _read_numeric_lines(decode_text(data, source), source, ncols, names)


def _read_numeric_lines(text: str, source: str, ncols: int, names) -> np.ndarray:
    """The line-by-line parser of :func:`_read_numeric_csv`."""
    text = strip_trailing_blank_lines(text)
    m = _BLANK_LINE.search(text)
    if m is not None:
        raise ValueError(f"{source}: line {text.count(chr(10), 0, m.start() + 1) + 1} is empty "
                         "(blank lines are accepted only at the end of the file)")
    rows = []
    for k, ln in enumerate(text.splitlines(), start=1):
        cells = ln.split(",")
        if len(cells) != ncols:
            raise ValueError(f"{source}: line {k} has {len(cells)} columns, expected {ncols} "
                             f"({', '.join(names[:ncols])})")
        row = []
        for j, c in enumerate(cells):
            try:
                v = float(c)
            except ValueError:
                raise ValueError(f"{source}: line {k}, column {j + 1} ({names[j]}): not a number: {c!r}") from None
            if not np.isfinite(v):
                raise ValueError(f"{source}: line {k}, column {j + 1} ({names[j]}): not finite: {c!r}")
            row.append(v)
        rows.append(row)
    return np.asarray(rows, dtype=np.float64).reshape(len(rows), ncols)


def _check_increasing(t_ns: np.ndarray, source: str, policy: str = "error") -> np.ndarray:
    """Rows to keep: all (times strictly increase), or, under ``duplicate_timestamps="drop"``,
    all but the later row of each repeated timestamp. A decreasing time is always an error.
    """
    lines = np.arange(1, len(t_ns) + 1)  # no header: record i is on line i + 1
    hint = ("; pass duplicate_timestamps='drop' to drop the later row of each repeated timestamp (counted)"
            if policy == "error" else "")
    check_increasing(t_ns, lines, source,
                     lambda i, kind: f"{kind} timestamp ({int(t_ns[i])} after {int(t_ns[i - 1])}); "
                                     f"timestamps must increase{hint if kind == 'duplicate' else ''}",
                     strict=policy == "error", column="1 (timestamp_ns)")
    keep = np.ones(len(t_ns), dtype=bool)
    keep[1:] = np.diff(t_ns) != 0
    return keep


def _check_span(t_ns: np.ndarray, source: str) -> None:
    """At most one day from the first sample (bounds the memory of any later resampling)."""
    check_range((t_ns - t_ns[0]) * 1e-9, "elapsed_s", source, np.arange(1, len(t_ns) + 1),
                "1 (timestamp_ns, seconds after the first line)")


def _imu_frame(t_ns: np.ndarray, acc: np.ndarray) -> pd.DataFrame:
    t = (t_ns - t_ns[0]) * 1e-9
    df = pd.DataFrame(acc, columns=list(ACC_COLS), index=pd.Index(t, name=T_S))
    return df


def _check_policy(duplicate_timestamps: str, heel_bounces: str = "keep") -> None:
    if duplicate_timestamps not in DUPLICATE_POLICIES:
        raise ValueError(f"duplicate_timestamps must be one of {DUPLICATE_POLICIES}, got {duplicate_timestamps!r}")
    if heel_bounces not in HEEL_BOUNCE_POLICIES:
        raise ValueError(f"heel_bounces must be one of {HEEL_BOUNCE_POLICIES}, got {heel_bounces!r}")


def heel_bounces_mask(t_ns: np.ndarray, feet: np.ndarray, min_stride_s: float = MIN_STRIDE_S) -> np.ndarray:
    """Which 0 -> 1 transitions of the foot states are heel-sensor bounces.

    Parameters
    ----------
    t_ns : ndarray, shape (n,)
        Increasing reading times, ns.
    feet : ndarray, shape (n, 2)
        Left and right foot states (1 = down).
    min_stride_s : float
        A foot that lands less than this long after its last landing that was kept bounced; the
        first landing of a run is kept, so a run of bounces counts one step.

    Returns
    -------
    ndarray of bool, shape (n - 1, 2)
        True at row ``k`` (transition from reading ``k`` to ``k + 1``) and foot ``j`` for a bounce.
    """
    if not min_stride_s > 0:
        raise ValueError(f"min_stride_s must be > 0, got {min_stride_s}")
    up = (feet[1:] == 1) & (feet[:-1] == 0)
    out = np.zeros_like(up)
    lim_ns = min_stride_s * 1e9
    t1 = t_ns[1:]
    for j in range(feet.shape[1]):
        ku = np.flatnonzero(up[:, j])
        if ku.size < 2 or not (np.diff(t1[ku]) < lim_ns).any():
            continue
        last = -np.inf
        for k in ku:                                   # few landings: a plain loop
            if t1[k] - last < lim_ns:
                out[k, j] = True
            else:
                last = t1[k]
    return out


def _optimisation_recording(name: str, acc_bytes: bytes, step_bytes: bytes, source: str,
                            duplicate_timestamps: str = "error", heel_bounces: str = "keep") -> OxfordRecording:
    acc_src = f"{source}/{ACC_FILE}"
    step_src = f"{source}/{STEP_FILE}"
    held = [acc_bytes]  # handed over: freed by the parser once parsed (see _read_numeric_csv)
    del acc_bytes
    a = _read_numeric_csv(held, acc_src, 5, ("timestamp_ns", "accuracy", "ax_mps2", "ay_mps2", "az_mps2"))
    held = [step_bytes]
    del step_bytes
    s = _read_numeric_csv(held, step_src, 3, ("timestamp_ns", "left_foot", "right_foot"))
    if a.shape[0] < 2:
        raise ValueError(f"{acc_src}: needs at least 2 samples, got {a.shape[0]}")
    lines_a = np.arange(1, a.shape[0] + 1)
    check_range(a[:, 2:5], "acc_mps2", acc_src, lines_a, ("3 (ax_mps2)", "4 (ay_mps2)", "5 (az_mps2)"))
    keep_a = _check_increasing(a[:, 0], acc_src, duplicate_timestamps)
    keep_s = _check_increasing(s[:, 0], step_src, duplicate_timestamps)
    _check_span(a[:, 0], acc_src)
    _check_span(s[:, 0], step_src)
    feet = s[:, 1:]
    bad = np.argwhere((feet != 0) & (feet != 1))
    if bad.size:
        k, j = bad[0]
        raise ValueError(f"{step_src}: line {k + 1}, column {j + 2} "
                         f"({('left_foot', 'right_foot')[j]}): foot state must be 0 or 1, got {feet[k, j]}")
    n_dup = int((~keep_a).sum() + (~keep_s).sum())
    a, s = a[keep_a], s[keep_s]
    if a.shape[0] < 2:
        raise ValueError(f"{acc_src}: needs at least 2 samples with distinct timestamps, got {a.shape[0]}")
    feet = s[:, 1:]
    up = (feet[1:] == 1) & (feet[:-1] == 0)
    bounce = heel_bounces_mask(s[:, 0], feet)
    n_bounce = int(bounce.sum())
    foot = np.nonzero(up & ~bounce)[1]              # the foot of each landing, in time order (rows, then left/right)
    n_unpaired = int((foot[1:] == foot[:-1]).sum())
    if heel_bounces == "merge":
        up &= ~bounce
    k_step = np.flatnonzero(up.any(axis=1)) + 1
    n_steps = int(up.sum())
    # a row where both feet land at once counts twice (it never happens in the set)
    step_t = np.repeat((s[k_step, 0] - a[0, 0]) * 1e-9, up[k_step - 1].sum(axis=1))
    step_bounce = bounce[np.nonzero(up)]           # the same (row, foot) order as step_t
    return OxfordRecording(name=name, imu=_imu_frame(a[:, 0], a[:, 2:5]), step_t_s=step_t,
                           true_steps=n_steps, hardware_steps=None, meta=parse_recording_name(name),
                           n_duplicate_timestamps_dropped=n_dup, n_heel_bounces=n_bounce,
                           n_heel_bounces_merged=n_bounce if heel_bounces == "merge" else 0,
                           n_unpaired_landings=n_unpaired, step_is_heel_bounce=step_bounce)


_VALIDATION_NAMES = ("timestamp_ns", "ax_mps2", "ay_mps2", "az_mps2", "app_count", "true_count", "hardware_count")


def _cumulative(v: np.ndarray, j: int, src: str, lines) -> np.ndarray:
    """Column ``j`` (0-based) of a validation CSV: whole, non-negative and never decreasing."""
    col = f"{j + 1} ({_VALIDATION_NAMES[j]})"
    check_range(v[:, j], "count", src, lines, col)
    d = np.diff(v[:, j])
    if np.any(d < 0):
        k = int(np.flatnonzero(d < 0)[0]) + 1
        raise ValueError(f"{src}: line {lines[k]}, column {col}: cumulative count decreases "
                         f"({v[k, j]:g} after {v[k - 1, j]:g})")
    return d


def _validation_recording(path: Path, duplicate_timestamps: str = "error") -> OxfordRecording:
    src = str(path)
    v = _read_numeric_csv(read_bytes(path), src, (7, 6), _VALIDATION_NAMES)
    if v.shape[0] < 2:
        raise ValueError(f"{src}: needs at least 2 samples, got {v.shape[0]}")
    lines = np.arange(1, v.shape[0] + 1)
    check_range(v[:, 1:4], "acc_mps2", src, lines, ("2 (ax_mps2)", "3 (ay_mps2)", "4 (az_mps2)"))
    keep = _check_increasing(v[:, 0], src, duplicate_timestamps)
    _check_span(v[:, 0], src)
    _cumulative(v, 4, src, lines)
    _cumulative(v, 5, src, lines)
    has_hw = v.shape[1] == 7 and bool(np.any(v[:, 6] != 0))
    if has_hw:
        _cumulative(v, 6, src, lines)
    n_dup = int((~keep).sum())
    v = v[keep]
    true = v[:, 5]
    d = np.diff(true)
    inc = np.flatnonzero(d > 0) + 1
    step_t = np.repeat((v[inc, 0] - v[0, 0]) * 1e-9, d[inc - 1].astype(np.int64))
    true_steps = int(true[-1] - true[0])
    hw = int(v[-1, 6] - v[0, 6]) if has_hw else None
    return OxfordRecording(name=path.stem, imu=_imu_frame(v[:, 0], v[:, 1:4]), step_t_s=step_t,
                           true_steps=true_steps, hardware_steps=hw, meta=parse_recording_name(path.stem),
                           n_duplicate_timestamps_dropped=n_dup)


def _is_archive(p: Path) -> bool:
    return p.is_file() and (p.name.endswith((".tar.xz", ".tar", ".tar.gz", ".tgz", ".txz")))


def _recording_file(ar: ArchiveReader, m: tarfile.TarInfo, recs: dict) -> tuple[str | None, str | None]:
    """(recording name, file name) of a member holding one of a recording's two CSV files, else (None, None);
    records it in ``recs`` (recording name -> {file name -> member}): the same name in two folders is an error."""
    if not m.isfile():
        return None, None
    parts = m.name.split("/")
    if len(parts) < 2 or parts[-1] not in (ACC_FILE, STEP_FILE):
        return None, None
    have = recs.setdefault(parts[-2], {})
    if parts[-1] in have:
        raise ValueError(f"{ar.path}: recording {parts[-2]!r} appears in two folders ({have[parts[-1]].name} "
                         f"and {m.name}); rename one so that a name picks one recording")
    have[parts[-1]] = m
    return parts[-2], parts[-1]


def _archive_members(ar: ArchiveReader) -> dict[str, dict[str, tarfile.TarInfo]]:
    """Recording name -> {file name -> member}; the same name in two folders is an error."""
    recs: dict[str, dict[str, tarfile.TarInfo]] = {}
    for m in ar.tar:
        _recording_file(ar, m, recs)
    return recs


def list_oxford_archive(path) -> list[str]:
    """Names of the recordings (folders with both CSV files) in an optimisation archive, sorted."""
    p = Path(path)
    if not _is_archive(p):
        raise ValueError(f"{p}: not a tar archive")
    with ArchiveReader(p) as ar:
        recs = _archive_members(ar)
    return sorted(k for k, v in recs.items() if len(v) == 2)


def load_oxford_archive(path, names=None, duplicate_timestamps: str = "error", select=None,
                        heel_bounces: str = "keep") -> list[OxfordRecording]:
    """Every recording (or those named, or those whose name passes ``select``) of an optimisation archive, read
    in one pass over the archive, sorted by name.

    ``names``: recording names, each must be in the archive; ``select``: a predicate on a recording's name
    (e.g. its position, :func:`parse_recording_name`), with ``names`` None. The members are read in the
    archive's own order as the pass reaches them (an xz archive read out of order is decompressed again from
    its start for every step back). A corrupt or truncated archive raises a ValueError naming it and the member
    being read; see :func:`load_oxford_step_counter` for ``duplicate_timestamps`` and ``heel_bounces``.
    """
    _check_policy(duplicate_timestamps, heel_bounces)
    p = Path(path)
    if not _is_archive(p):
        raise ValueError(f"{p}: not a tar archive")
    if names is not None and select is not None:
        raise ValueError("give names or select, not both")
    want = None if names is None else set(names)
    recs: dict[str, dict[str, tarfile.TarInfo]] = {}
    data: dict[tuple[str, str], bytes] = {}
    with ArchiveReader(p) as ar:
        for m in ar.tar:
            rec, fname = _recording_file(ar, m, recs)
            if rec is None or (want is not None and rec not in want) or (select is not None and not select(rec)):
                continue
            ar.member = m.name
            data[rec, fname] = ar.tar.extractfile(m).read()
            ar.member = None
    complete = sorted(k for k, v in recs.items() if len(v) == 2)
    if names is None:
        wanted = [n for n in complete if select is None or select(n)]
        if not wanted:
            raise ValueError(f"{p}: no recording folder with both {ACC_FILE} and {STEP_FILE}"
                             + (" that the selection keeps" if select is not None else ""))
    else:
        wanted = list(names)
        for n in wanted:
            if n not in recs or len(recs[n]) != 2:
                raise ValueError(f"{p}: no recording {n!r} with {ACC_FILE} and {STEP_FILE}; "
                                 f"recordings: {sorted(recs)[:5]}...")
    out = [_optimisation_recording(n, data[n, ACC_FILE], data[n, STEP_FILE], f"{p}:{n}", duplicate_timestamps,
                                   heel_bounces) for n in wanted]
    return sorted(out, key=lambda r: r.name)


def load_oxford_step_counter(path, member: str | None = None, duplicate_timestamps: str = "error",
                             heel_bounces: str = "keep") -> OxfordRecording:
    """Load one Oxford step counter recording.

    Parameters
    ----------
    path : str or Path
        A recording folder (holding ``accelerometer.csv`` and ``stepcounter.csv``), the
        ``optimisation_data.tar.xz`` archive (then ``member`` names the recording), or a
        validation-style single headerless CSV (seven columns, see the module docstring; plain,
        ``.gz`` or ``.xz``).
    member : str, optional
        Recording name inside an archive (e.g. ``"Pixel_Jamie_Hard_InHand_1"``).
    duplicate_timestamps : {"error", "drop"}
        Two consecutive lines with the same timestamp (found in some of the published validation
        CSVs): raise naming the line, or keep the first and drop the later line, counted in
        :attr:`OxfordRecording.n_duplicate_timestamps_dropped`. True steps are counted from the
        kept lines (a cumulative count loses nothing; a step time moves to the next kept line).
    heel_bounces : {"keep", "merge"}
        Optimisation layout: a foot that lands again less than :data:`MIN_STRIDE_S` after its last
        landing (a heel-sensor bounce, see the module docstring): keep each landing as a true step (the
        published count), or merge the bounce into the contact before it, counted in
        :attr:`OxfordRecording.n_heel_bounces_merged`. Bounces are counted under both
        (:attr:`OxfordRecording.n_heel_bounces`). The validation layout carries counts, not foot
        states: the policy does not apply there.

    Returns
    -------
    OxfordRecording

    Raises
    ------
    ValueError
        Missing files, malformed lines (naming file, line and column), values outside their valid
        range (:data:`ilocalg.io.schema.FIELD_RANGES`), a recording longer than a day,
        non-increasing timestamps, a fractional or decreasing cumulative count (true or hardware),
        the same recording name in two archive folders, a corrupt archive or non-UTF-8 text.
    """
    _check_policy(duplicate_timestamps, heel_bounces)
    p = Path(path)
    if not p.exists():
        raise ValueError(f"{p}: no such file or folder")
    if p.is_dir():
        acc, st = p / ACC_FILE, p / STEP_FILE
        for f in (acc, st):
            if not f.is_file():
                raise ValueError(f"{p}: recording folder lacks {f.name}")
        return _optimisation_recording(p.name, read_bytes(acc), read_bytes(st), str(p), duplicate_timestamps,
                                       heel_bounces)
    if _is_archive(p):
        if member is None:
            raise ValueError(f"{p}: an archive holds several recordings; pass member= one of "
                             f"{list_oxford_archive(p)[:3]}...")
        return load_oxford_archive(p, [member], duplicate_timestamps, heel_bounces=heel_bounces)[0]
    if p.name.lower().endswith((".csv", ".txt", ".csv.gz", ".csv.xz", ".txt.gz", ".txt.xz")):
        return _validation_recording(p, duplicate_timestamps)
    raise ValueError(f"{p}: expected a recording folder, a .tar.xz archive or a validation .csv file")
