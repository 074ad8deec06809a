"""Parsing helpers shared by the text-log loaders (private to :mod:`ilocalg.io`).

Every loader reports bad content the same way: ``FILE: line N: what is wrong`` or
``FILE: line N, column COL: what is wrong``, where N is the 1-based line of the file a person
opens in an editor, never a table row.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NoReturn

import numpy as np
import pandas as pd

__all__ = ["fail", "to_float", "first_not_increasing", "check_increasing", "decode_text", "decompress",
           "read_bytes", "read_text", "strip_trailing_blank_lines", "ArchiveReader", "TRUNCATED_POLICIES",
           "check_truncated_policy", "cut_last_line", "parse_record_log", "check_record_types", "TypedLines",
           "split_by_type",
           "read_block", "count_per_line"]


def fail(source, lineno, msg: str, column: str | None = None) -> NoReturn:
    """Raise ``ValueError("SOURCE: line N[, column COL]: MSG")``."""
    where = f"line {lineno}" if column is None else f"line {lineno}, column {column}"
    raise ValueError(f"{source}: {where}: {msg}")


def to_float(rows: Sequence[Sequence[str]], linenos: Sequence[int], source, label: Callable[[int], str],
             ncols: int, finite: bool = False) -> np.ndarray:
    """Text cells as a float64 array ``(len(rows), ncols)``, naming the first bad cell's line.

    Parameters
    ----------
    rows : sequence of sequences of str
        The cells, one inner sequence (of length ``ncols``) per record.
    linenos : sequence of int
        The file line of each record.
    source : str
        File name for the message.
    label : callable
        ``label(j)`` describes cell ``j`` of a record in the message (e.g. ``"ACCE field 3 (X)"``).
    ncols : int
    finite : bool
        Also refuse ``nan`` / ``inf`` (the message then says "a finite number").

    Raises
    ------
    ValueError
        ``SOURCE: line N: LABEL must be numeric, got 'abc'`` (or "must be a finite number").
    """
    try:
        out = np.asarray(rows, dtype=np.float64).reshape(len(rows), ncols)
    except ValueError:
        out = None
    if out is not None and (not finite or np.isfinite(out).all()):
        return out
    need = "a finite number" if finite else "numeric"
    for ln, r in zip(linenos, rows, strict=True):
        for j, v in enumerate(r):
            try:
                ok = np.isfinite(float(v)) or not finite
            except ValueError:
                ok = False
            if not ok:
                fail(source, ln, f"{label(j)} must be {need}, got {v!r}")
    raise AssertionError("unreachable")  # pragma: no cover


def first_not_increasing(t: np.ndarray, strict: bool = True) -> tuple[int, str] | None:
    """Index of the first time that does not increase, and ``"duplicate"`` or ``"decreasing"``.

    ``strict=False`` accepts equal consecutive times (only a decrease is reported).
    Returns ``None`` when the times increase throughout.
    """
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0 if strict else d < 0)
    if not bad.size:
        return None
    return int(bad[0]) + 1, ("duplicate" if d[bad[0]] == 0 else "decreasing")


def check_increasing(t: np.ndarray, linenos, source, message: Callable[[int, str], str], strict: bool = True,
                     column: str | None = None) -> None:
    """Raise naming the line of the first non-increasing time; ``message(i, kind)`` says what is wrong."""
    hit = first_not_increasing(t, strict)
    if hit is not None:
        i, kind = hit
        fail(source, linenos[i], message(i, kind), column)


# ----------------------------------------------------------------------------------------------
# one text policy for every loader: bytes -> str
# ----------------------------------------------------------------------------------------------

_BOM = b"\xef\xbb\xbf"
_GZIP_MAGIC = b"\x1f\x8b"
_XZ_MAGIC = b"\xfd7zXZ\x00"
_COMPRESSED = {".gz": "gzip", ".xz": "xz"}


def decode_text(data: bytes, source) -> str:
    """UTF-8 bytes as text: a leading byte-order mark is stripped; a non-UTF-8 byte is an error.

    CRLF line ends and trailing blank lines are left to ``str.splitlines`` and the loaders, which
    accept both.

    Raises
    ------
    ValueError
        ``SOURCE: line N: byte 0xE9 (column C) is not UTF-8; the loaders read UTF-8 text only
        (re-save the file as UTF-8)``.
    """
    if isinstance(data, str):
        return data[1:] if data.startswith("\ufeff") else data
    start = len(_BOM) if data.startswith(_BOM) else 0
    try:
        return data[start:].decode("utf-8", errors="strict")
    except UnicodeDecodeError as exc:
        pos = start + exc.start
        line = data.count(b"\n", 0, pos) + 1
        col = pos - (data.rfind(b"\n", 0, pos) + 1) + 1
        fail(source, line, f"byte 0x{data[pos]:02X} (character {col}) is not UTF-8; the loaders read UTF-8 text "
                           "only (re-save the file as UTF-8)")


def decompress(data: bytes, source, name: str | None = None) -> bytes:
    """Bytes of a ``.gz`` / ``.xz`` file decompressed (by name or by magic number), others unchanged.

    Raises
    ------
    ValueError
        ``SOURCE: corrupt or truncated gzip data (...)`` when the stream cannot be read.
    """
    import gzip
    import lzma
    import zlib

    name = str(name if name is not None else source)
    suffix = "." + name.rsplit(".", 1)[-1].lower() if "." in name else ""
    kind = None
    if data.startswith(_GZIP_MAGIC):
        kind = "gzip"
    elif data.startswith(_XZ_MAGIC):
        kind = "xz"
    elif suffix in _COMPRESSED:
        raise ValueError(f"{source}: not {_COMPRESSED[suffix]} data although the name ends in {suffix} "
                         "(rename the file or compress it properly)")
    if kind is None:
        return data
    try:
        return gzip.decompress(data) if kind == "gzip" else lzma.decompress(data)
    except (OSError, EOFError, zlib.error, lzma.LZMAError) as exc:
        raise ValueError(f"{source}: corrupt or truncated {kind} data ({type(exc).__name__}: {exc})") from None


def read_bytes(path) -> bytes:
    """A file's bytes (``.gz`` / ``.xz`` decompressed), any read error as ValueError naming the file."""
    from pathlib import Path

    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"{p}: no such file")
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise ValueError(f"{p}: cannot read ({exc.strerror or exc})") from None
    return decompress(data, str(p))


def read_text(path) -> str:
    """A text file under the common policy: decompressed, BOM stripped, strict UTF-8 (see :func:`decode_text`)."""
    return decode_text(read_bytes(path), str(path))


def strip_trailing_blank_lines(text: str) -> str:
    """Text without the blank lines at its end (each loader accepts them)."""
    end = len(text)
    while end and text[end - 1] in "\r\n \t":
        end -= 1
    return text[:end] + ("\n" if end < len(text) else "")


class ArchiveReader:
    """Context manager that turns archive read errors into ValueError naming the archive and member.

    Usage::

        with ArchiveReader(path) as ar:
            for m in ar.tar:
                ar.member = m.name
                data = ar.tar.extractfile(m).read()
    """

    def __init__(self, path):
        self.path = path
        self.member: str | None = None
        self.tar = None

    def __enter__(self):
        import tarfile

        try:
            self.tar = tarfile.open(self.path, "r:*")
        except FileNotFoundError:
            raise
        except Exception as exc:  # noqa: BLE001 - every tarfile/lzma/zlib/EOF/OS error, named
            raise ValueError(self._message(exc)) from None
        return self

    def _message(self, exc) -> str:
        where = f"{self.path}:{self.member}" if self.member else str(self.path)
        return f"{where}: corrupt or truncated archive ({type(exc).__name__}: {exc})"

    def __exit__(self, et, exc, tb):
        import lzma
        import tarfile
        import zlib

        if self.tar is not None:
            try:
                self.tar.close()
            except Exception:  # noqa: BLE001
                pass
        if exc is not None and isinstance(exc, (tarfile.TarError, lzma.LZMAError, EOFError, zlib.error, OSError)) \
                and not isinstance(exc, FileNotFoundError):
            raise ValueError(self._message(exc)) from None
        return False


# ----------------------------------------------------------------------------------------------
# record-type logs (IPIN, ILC): unknown types, a cut last line
# ----------------------------------------------------------------------------------------------

TRUNCATED_POLICIES = ("error", "drop")


def check_truncated_policy(policy: str) -> None:
    if policy not in TRUNCATED_POLICIES:
        raise ValueError(f"truncated_last_line must be one of {TRUNCATED_POLICIES}, got {policy!r}")


def cut_last_line(lines: list[str], text: str, source, policy: str, is_cut: Callable[[str], str | None]):
    """Apply the ``truncated_last_line`` policy to a file's lines.

    A file that does not end with a line end and whose last non-blank line ``is_cut`` (returns a
    description of what is missing, else ``None``) was cut while it was written (a recording
    stopped mid-line, a partial download). ``"error"`` raises naming that line; ``"drop"`` leaves
    it out and counts it.

    Returns
    -------
    lines : list of str
        Unchanged, or without the cut line.
    n_dropped : int
        0 or 1.
    """
    check_truncated_policy(policy)
    if not lines or text.endswith(("\n", "\r")):
        return lines, 0
    k = len(lines) - 1
    while k >= 0 and not lines[k].strip():
        k -= 1
    if k < 0:
        return lines, 0
    why = is_cut(lines[k].strip())
    if why is None:
        return lines, 0
    if policy == "error":
        fail(source, k + 1, f"the file ends inside this record ({why}, no line end): it was cut while being "
                            "written; pass truncated_last_line='drop' to leave it out (counted)")
    return lines[:k], 1


def parse_record_log(text: str | bytes, source, truncated_last_line: str, fast: Callable, slow: Callable,
                     is_cut: Callable[[str], str | None]):
    """The text policy of a record-per-line log (ILC trace, IPIN logfile), then its parser.

    A UTF-8 BOM is stripped and a non-UTF-8 byte is an error naming its line. ``fast(data)`` parses
    well-formed bytes (returning ``None`` for anything it might read differently); otherwise the
    text is decoded, a cut last line goes through :func:`cut_last_line` and ``slow(lines, source)``
    parses line by line, naming a bad line.

    Returns
    -------
    parsed
        What ``fast`` or ``slow`` returned.
    n_cut : int
        Lines left out by the ``truncated_last_line`` policy (0 or 1).
    """
    check_truncated_policy(truncated_last_line)
    data = text.encode("utf-8") if isinstance(text, str) else text
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    if not data.isascii():
        decode_text(data, source)  # a non-UTF-8 byte is an error naming its line
    parsed = fast(data)
    if parsed is not None:
        return parsed, 0
    text = decode_text(data, source)
    lines, n_cut = cut_last_line(text.splitlines(), text, source, truncated_last_line, is_cut)
    return slow(lines, source), n_cut


def check_record_types(counts: dict, first_line: dict, known, source, sep: str, fmt: str) -> None:
    """Refuse a log whose record types are mis-cased or mis-delimited, or in which no known type occurs.

    Parameters
    ----------
    counts : dict
        Record type -> number of lines.
    first_line : dict
        Record type -> file line of its first occurrence.
    known : collection of str
        The types the loader reads.
    sep : str
        The format's field separator (for the message).
    fmt : str
        Format name for the message (``"IPIN logfile"``).
    """
    others = "," if sep != "," else ";"
    for t in sorted((t for t in counts if t not in known), key=lambda t: first_line.get(t, 0)):
        if t.upper() in known:
            fail(source, first_line[t], f"record type {t!r} must be upper case ({t.upper()!r}); an {fmt} writes "
                                        "upper-case types")
        for d in (others, "\t", " "):
            if d != sep and d in t and t.split(d, 1)[0].strip().upper() in known:
                fail(source, first_line[t], f"fields are separated by {d!r}; an {fmt} separates them by {sep!r}")
    if not any(t in known for t in counts):
        first = min(first_line, key=first_line.get)
        raise ValueError(f"{source}: no known record type found ({', '.join(sorted(known))}); "
                         f"{sum(counts.values())} lines of other types (first on line {first_line[first]}: "
                         f"{first[:40]!r}); is this an {fmt}?")


# ----------------------------------------------------------------------------------------------
# fast path for record-type logs: lines grouped by type with numpy, each group parsed by pandas
# ----------------------------------------------------------------------------------------------

# Non-ASCII line ends and spaces (U+0085, U+00A0, U+2000-U+202F, U+3000), same reason.
_NON_ASCII_SPECIAL = (b"\xc2\x85", b"\xc2\xa0", b"\xe2\x80", b"\xe3\x80\x80")


_CHUNK = 1 << 21


def _scan(arr: np.ndarray) -> tuple[int, int, int, int, int]:
    """Counts of bytes < 32, LF, CR, TAB and CRLF pairs, a few megabytes at a time."""
    n = [0, 0, 0, 0, 0]
    for i in range(0, len(arr), _CHUNK):
        sub = arr[i:i + _CHUNK + 1]  # one byte of overlap for CRLF pairs across chunks
        body = sub[:_CHUNK]
        n[0] += int(np.count_nonzero(body < 32))
        n[1] += int(np.count_nonzero(body == 10))
        n[2] += int(np.count_nonzero(body == 13))
        n[3] += int(np.count_nonzero(body == 9))
        if n[2]:
            n[4] += int(np.count_nonzero((sub[:-1] == 13) & (sub[1:] == 10)))
    return n[0], n[1], n[2], n[3], n[4]


def _positions(arr: np.ndarray, value: int) -> np.ndarray:
    """``np.flatnonzero(arr == value)`` without a file-sized temporary."""
    parts = [np.flatnonzero(arr[i:i + _CHUNK] == value) + i for i in range(0, len(arr), _CHUNK)]
    return np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)


def count_per_line(arr: np.ndarray, value: int, starts: np.ndarray, chunk: int = _CHUNK) -> np.ndarray:
    """How often byte ``value`` occurs on each line (lines start at ``starts``), in bounded memory.

    Works through about ``chunk`` bytes at a time, so the temporary arrays stay a few megabytes
    whatever the file size.
    """
    bounds = np.append(starts, len(arr))
    out = np.empty(len(starts), dtype=np.int64)
    i, n = 0, len(starts)
    while i < n:
        j = min(max(int(np.searchsorted(bounds, bounds[i] + chunk, side="right")) - 1, i + 1), n)
        seg = arr[bounds[i]:bounds[j]] == value
        out[i:j] = np.add.reduceat(seg, starts[i:j] - bounds[i], dtype=np.int32)
        i = j
    return out


@dataclass(frozen=True)
class TypedLines:
    """A record-type log split by type (see :func:`split_by_type`)."""

    lines: dict        # known type -> int array, the 1-based file line of each record
    blocks: dict       # known type -> function () -> bytes: its lines, each with its line end (built on
    #                    demand, so that one type's bytes exist at a time)
    counts: dict       # every record type -> number of lines, in order of first occurrence
    header: list       # header lines (str, without line end), in order


def split_by_type(data: bytes, sep: bytes, type_col: int, known: dict, comment: bytes = b"", header: bytes = b"",
                  spaces_ok: bool = False) -> TypedLines | None:
    """Group the lines of a record-type log by record type, vectorised (no Python loop per known line).

    The fast path of the IPIN and ILC parsers. It returns ``None`` whenever the file holds
    anything it might not handle exactly like the line-by-line parser (no final line end, a lone
    ``\\r``, other line-end or space characters, a space next to a separator unless
    ``spaces_ok``, a line starting with a space, a line of a known type with another number of
    fields, an unknown type that looks like a mis-cased or mis-delimited known type, no known
    type at all); the caller then parses line by line, which names the offending line.

    Parameters
    ----------
    data : bytes
        UTF-8 text without byte-order mark.
    sep : bytes
        One-byte field separator.
    type_col : {0, 1}
        Column of the record type (1: after a first column of equal width on every line, such as
        a 13-digit time in milliseconds).
    known : dict
        Record type -> number of separators on its lines; these types are returned as blocks,
        the others are only counted.
    comment, header : bytes
        First byte of lines that are skipped (not counted) / returned as header lines.
    spaces_ok : bool
        Whether a space next to a separator is kept verbatim by the line-by-line parser.
    """
    if not data.endswith(b"\n"):
        return None
    arr = np.frombuffer(data, dtype=np.uint8)
    sep_b = sep[0]
    n_low, n_lf, n_cr, n_tab, n_crlf = _scan(arr)
    if n_low != n_lf + n_cr + n_tab:
        return None  # other control bytes (line ends or spaces for str.splitlines / str.strip)
    if (sep_b != 9 and n_tab) or n_cr != n_crlf:
        return None
    if not data.isascii() and any(b in data for b in _NON_ASCII_SPECIAL):
        return None
    sp = _positions(arr, 32)
    if sp.size:
        nxt, prv = arr[np.minimum(sp + 1, len(arr) - 1)], arr[np.maximum(sp - 1, 0)]
        if np.any(sp == 0) or np.any(prv == 10) or np.any((nxt == 10) | (nxt == 13)):
            return None
        if not spaces_ok and (np.any(nxt == sep_b) or np.any(prv == sep_b)):
            return None
    ends = _positions(arr, 10)
    if len(arr) < 2**31 - 1:
        ends = ends.astype(np.int32)  # half the memory of the per-line arrays
    starts = np.empty_like(ends)
    starts[0] = 0
    starts[1:] = ends[:-1] + 1
    stop = ends - ((arr[np.maximum(ends - 1, 0)] == 13) & (ends > starts))  # content end (before \r\n)
    nonblank = stop > starts
    first = np.where(nonblank, arr[np.minimum(starts, len(arr) - 1)], 0)
    is_head = nonblank & (first == header[0]) if header else np.zeros(len(starts), dtype=bool)
    is_rec = nonblank & ~is_head
    if comment:
        is_rec &= first != comment[0]
    rec = np.flatnonzero(is_rec).astype(ends.dtype)
    del is_rec, first, nonblank
    if not rec.size:
        return None
    rs, re_ = starts[rec], stop[rec]
    if len(arr) < 8:
        return None
    win = np.lib.stride_tricks.as_strided(arr, shape=(len(arr) - 7, 8), strides=(1, 1), writeable=False)
    top = len(arr) - 8

    def bytes8(pos):
        """The 8 bytes from each position (clamped at the end of the file), as (n, 8) uint8."""
        return win[np.minimum(pos, top)]

    def words(pos, nw):
        """``(n, nw)`` uint64: word ``j`` holds the 8 bytes from ``pos + 8 j`` (clamped at the end of the
        file as :func:`bytes8` clamps them), from one gather of ``8 nw`` bytes per position."""
        size = 8 * nw
        if len(arr) < size:
            return np.column_stack([bytes8(pos + 8 * j).view("<u8").ravel() for j in range(nw)])
        wide = np.lib.stride_tricks.as_strided(arr, shape=(len(arr) - size + 1, size), strides=(1, 1),
                                               writeable=False)
        out = wide[np.minimum(pos, len(arr) - size)].view("<u8")
        tail = np.flatnonzero(pos > len(arr) - size)  # the last few lines: word by word, clamped as bytes8
        for j in range(nw):
            out[tail, j] = bytes8(pos[tail] + 8 * j).view("<u8").ravel()
        return out

    if type_col == 0:
        t0 = rs
    else:
        width = data.find(sep, int(rs[0])) - int(rs[0])
        if width <= 0 or np.any(re_ - rs <= width) or np.any(arr[rs + width] != sep_b):
            return None
        first_col = words(rs, -(-width // 8)).view(np.uint8)[:, :width]
        if np.any(first_col == sep_b):
            return None
        del first_col
        t0 = rs + width + 1
    label = np.zeros(len(rec), dtype=np.int8)
    names = sorted(known)
    type_words = words(t0, -(-max(len(k) + 1 for k in known) // 8))  # each record's type bytes, 8 per word
    head = type_words[:, 0]
    span = re_ - t0
    for code, name in enumerate(names, start=1):
        kb = name.encode() + sep  # the name and the separator that ends it
        first = kb[:8]
        mask = np.uint64((1 << (8 * len(first))) - 1)
        key = np.uint64(int.from_bytes(first.ljust(8, b"\0"), "little"))
        cand = np.flatnonzero(((head & mask) == key) & (span > len(kb) - 1))  # one word compare per record
        for o in range(8, len(kb), 8):  # then one word per comparison, on the candidates only
            part = kb[o:o + 8]
            mask = np.uint64((1 << (8 * len(part))) - 1)
            key = np.uint64(int.from_bytes(part.ljust(8, b"\0"), "little"))
            cand = cand[(type_words[cand, o // 8] & mask) == key]
        label[cand] = code
    del type_words, head
    unknown = np.flatnonzero(label == 0)
    other, first_other = _count_types(data, arr, sep_b, rec[unknown], t0[unknown], re_[unknown])
    for t in other:
        ts = t.decode("utf-8", errors="replace")
        if ts.upper() in known or any(d in ts for d in (",", ";", "\t", " ") if d != sep.decode()):
            return None
    present = [c for c in range(1, len(names) + 1) if np.any(label == c)]
    if not present:
        return None
    # every line of a known type holds its number of separators
    n_sep = count_per_line(arr, sep_b, starts)[rec]
    for c in present:
        if np.any(n_sep[label == c] != known[names[c - 1]]):
            return None
    del n_sep
    first_of = {names[c - 1]: int(rec[np.argmax(label == c)]) for c in present}
    first_of.update({t.decode(): i for t, i in first_other.items()})
    n_of = {names[c - 1]: int(np.count_nonzero(label == c)) for c in present}
    n_of.update({t.decode(): n for t, n in other.items()})
    counts = {t: n_of[t] for t in sorted(first_of, key=first_of.get)}
    lines, blocks = {}, {}
    head = [data[a:b].decode("utf-8") for a, b in zip(starts[is_head].tolist(), stop[is_head].tolist(),
                                                      strict=True)]
    del stop, is_head, rs, re_
    for c in present:
        sel = label == c
        lines[names[c - 1]] = rec[sel] + 1
        blocks[names[c - 1]] = _block_maker(data, starts, ends, rec[sel])
    return TypedLines(lines=lines, blocks=blocks, counts=counts, header=head)


def _block_maker(data: bytes, starts, ends, rows):
    """A function that returns the bytes of lines ``rows`` (each with its line end), joined.

    Few lines are sliced out one by one; many are selected with a byte mask built a few
    megabytes of the file at a time (bounded memory, no Python loop per line).
    """
    def make() -> bytes:
        if rows.size < 20000:
            return b"".join(data[a:b] for a, b in zip(starts[rows].tolist(), (ends[rows] + 1).tolist(), strict=True))
        arr = np.frombuffer(data, dtype=np.uint8)
        n = int(rows[-1]) + 1  # the lines from the first to the last of ``rows``
        on = np.zeros(n, dtype=bool)
        on[rows] = True
        parts = []
        i = int(rows[0])
        while i < n:
            j = min(max(int(np.searchsorted(starts, starts[i] + _CHUNK, side="left")), i + 1), n)
            lo, hi = int(starts[i]), int(ends[j - 1]) + 1
            mask = np.repeat(on[i:j], (ends[i:j] - starts[i:j] + 1))
            parts.append(arr[lo:hi][mask].tobytes())
            i = j
        return b"".join(parts)
    return make


def _count_types(data: bytes, arr: np.ndarray, sep_b: int, rec, t0, stop) -> tuple[dict, dict]:
    """Record type -> count and -> first line index, for lines of unknown types."""
    other: dict[bytes, int] = {}
    first_other: dict[bytes, int] = {}
    if len(rec) > 20000:  # many: the type's end via the separators' positions, one np.unique
        seps = np.flatnonzero(arr == sep_b)
        k = np.searchsorted(seps, t0)
        end = np.minimum(np.append(seps, len(arr))[k], stop)
        del seps, k
        width = int((end - t0).max())
        if 0 < width <= 64:
            j = np.arange(width)
            idx = np.minimum(t0[:, None] + j, len(arr) - 1)
            mat = np.where(j < (end - t0)[:, None], arr[idx], 0).astype(np.uint8)
            keys = np.ascontiguousarray(mat).view(f"S{width}").ravel()
            uniq, first, n = np.unique(keys, return_index=True, return_counts=True)
            for u, f, c in zip(uniq.tolist(), first.tolist(), n.tolist(), strict=True):
                other[u] = c
                first_other[u] = int(rec[f])
            return other, first_other
    for i, a, b in zip(rec.tolist(), t0.tolist(), stop.tolist(), strict=True):
        e = data.find(bytes([sep_b]), a, b)
        t = data[a:b if e < 0 else e]
        if t in other:
            other[t] += 1
        else:
            other[t] = 1
            first_other[t] = i
    return other, first_other


def read_block(block: bytes, sep: str, names, usecols, strings=(), ints=(), type_name: str = "") -> tuple | None:
    """One type's records (from :func:`split_by_type`) as ``(DataFrame, float64 array of the numeric
    columns)``, or ``None`` if any is malformed.

    ``names`` lists the fields after the type, ``usecols`` those to read (float64, except the
    text columns ``strings``, read verbatim: no NA conversion, no quoting, and the int64 columns
    ``ints``, digits only; ``type_name`` is the record type written on every line). An empty numeric cell
    or a non-numeric one (pandas raises) returns ``None``: the caller then parses line by line
    and names the line.
    """
    import csv
    import io

    num = [c for c in usecols if c not in strings and c not in ints]
    dtype = {c: (str if c in strings else np.int64 if c in ints else np.float64) for c in usecols}
    try:
        df = pd.read_csv(io.BytesIO(block), sep=sep, header=None, names=list(names), usecols=list(usecols),
                         dtype=dtype, quoting=csv.QUOTE_NONE, keep_default_na=False,
                         na_values={c: [""] for c in num}, engine="c", skip_blank_lines=False)
    except (ValueError, TypeError, pd.errors.ParserError):
        return None
    v = df[num].to_numpy(dtype=np.float64)
    if not np.isfinite(v).all():
        return None
    if np.any((v == 0.0) | (v == 1.0)) and any(block.count(b) > len(df) * type_name.count(b.decode())
                                                for b in (b"r", b"R", b"l", b"L")):
        return None  # pandas reads True/False as 1.0/0.0 in a float column; float() refuses them
    return df.drop(columns=num), v
