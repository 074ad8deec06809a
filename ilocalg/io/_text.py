"""Parsing helpers shared by the text-log loaders (private to :mod:`ilocalg.io`).

Every loader reports bad content the same way: ``FILE: line N: what is wrong`` or
``FILE: line N, column COL: what is wrong``, where N is the 1-based line of the file a person
opens in an editor, never a table row.
"""

from __future__ import annotations

import io
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NoReturn

import numpy as np
import pandas as pd

__all__ = ["fail", "to_float", "first_not_increasing", "check_increasing", "decode_text", "decompress",
           "read_bytes", "read_text", "strip_trailing_blank_lines", "ArchiveReader", "TRUNCATED_POLICIES",
           "check_truncated_policy", "cut_last_line", "parse_record_log", "check_record_types", "TypedLines",
           "split_by_type",
           "Records", "read_records", "count_per_line", "byte_positions"]


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

    A UTF-8 BOM is stripped and a non-UTF-8 byte is an error naming its line. ``fast(data, is_ascii)``
    parses well-formed bytes (returning ``None`` for anything it might read differently); otherwise the
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
    is_ascii = data.isascii()
    if not is_ascii:
        decode_text(data, source)  # a non-UTF-8 byte is an error naming its line
    parsed = fast(data, is_ascii)
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
#: Bytes of selected lines parsed per piece by :func:`read_records` (bounded memory; with 4 MB pieces a
#: `bench_io` IPIN load often faulted in 35-45 MB of fresh pages for the parser's buffers, with 2 MB ones rarely).
_PIECE = 1 << 21
#: Records whose first bytes are gathered at a time to find their types.
_ROWS = 1 << 16
#: Bytes gathered from the start of each line of an unknown record type to find its type.
_TYPE_WINDOW = 64


def _scan_lines(arr: np.ndarray, sep_b: int) -> tuple[np.ndarray, np.ndarray, int]:
    """One pass over text ending with ``\\n``, a few megabytes at a time: the position of every ``\\n``,
    the number of ``sep_b`` bytes on each line, and the number of bytes up to 32 (controls and spaces).

    The separators are counted as bits: each chunk's separator mask is packed into 64-bit words, and a
    line's count is the difference of the bits set up to its line end and up to the previous one (a
    running sum per word plus the bits of one partial word), so no sum runs over the bytes themselves."""
    dt = np.int32 if len(arr) < 2**31 - 1 else np.int64
    ends, n_sep = [], []
    n_low = 0
    before = 0  # separators before the current chunk
    prev = 0  # separators up to the previous line end
    for i in range(0, len(arr), _CHUNK):
        a = arr[i:i + _CHUNK]
        n_low += int(np.count_nonzero(a <= 32))
        e = np.flatnonzero(a == 10)
        bits = np.packbits(a == sep_b, bitorder="little")
        words = np.zeros(-(-len(bits) // 8), dtype="<u8")
        words.view(np.uint8)[:len(bits)] = bits
        cum = np.zeros(len(words) + 1, dtype=np.int64)
        np.cumsum(np.bitwise_count(words), out=cum[1:])
        if len(e):
            w = e >> 6
            upto = cum[w] + np.bitwise_count(words[w] & ((np.uint64(1) << (e & 63).astype(np.uint64)) - np.uint64(1)))
            upto += before  # separators before each line end (the \n itself is not one)
            c = np.empty(len(e), dtype=np.int32)
            c[0] = upto[0] - prev
            c[1:] = np.diff(upto)
            prev = int(upto[-1])
            ends.append((e + i).astype(dt))
            n_sep.append(c)
        before += int(cum[-1])
    return np.concatenate(ends), np.concatenate(n_sep), n_low


def byte_positions(arr: np.ndarray, value: int) -> np.ndarray:
    """``np.flatnonzero(arr == value)`` without a file-sized temporary (int32 below 2 GB)."""
    dt = np.int32 if len(arr) < 2**31 - 1 else np.int64
    parts = [(np.flatnonzero(arr[i:i + _CHUNK] == value) + i).astype(dt) for i in range(0, len(arr), _CHUNK)]
    return np.concatenate(parts) if parts else np.zeros(0, dtype=dt)


def count_per_line(arr: np.ndarray, value: int, starts: np.ndarray, chunk: int = _CHUNK, dtype=np.int64) -> np.ndarray:
    """How often byte ``value`` occurs on each line (lines start at ``starts``), in bounded memory.

    Works through about ``chunk`` bytes at a time, so the temporary arrays stay a few megabytes
    whatever the file size.
    """
    bounds = np.append(starts, len(arr))
    out = np.empty(len(starts), dtype=dtype)
    i, n = 0, len(starts)
    while i < n:
        j = min(max(int(np.searchsorted(bounds, bounds[i] + chunk, side="right")) - 1, i + 1), n)
        seg = (arr[bounds[i]:bounds[j]] == value).view(np.uint8)
        longest = int(np.diff(bounds[i:j + 1]).max())  # a line of < 2**k bytes holds < 2**k hits: k-bit sums
        acc = np.uint8 if longest < 2**8 else np.uint16 if longest < 2**16 else np.int64
        out[i:j] = np.add.reduceat(seg, starts[i:j] - bounds[i], dtype=acc)
        i = j
    return out


def _gather(arr: np.ndarray, data: bytes, pos: np.ndarray, size: int) -> np.ndarray:
    """``(len(pos), size)`` uint8: the ``size`` bytes from each position, zeros outside the data."""
    n = len(arr)
    if n < size:
        out = np.zeros((len(pos), size), dtype=np.uint8)
        edge = np.arange(len(pos))
    else:
        # one item of ``size`` bytes starting at every byte: a one-dimensional gather (faster than rows of a 2-D view)
        items = np.ndarray(shape=(n - size + 1,), dtype=f"V{size}", buffer=arr, strides=(1,))
        out = items[np.clip(pos, 0, n - size)].view(np.uint8).reshape(len(pos), size)
        edge = np.flatnonzero((pos < 0) | (pos > n - size))
    for i in edge.tolist():  # positions near either end of the data: padded slices
        p = int(pos[i])
        chunk = b"\0" * max(-p, 0) + data[max(p, 0):max(p + size, 0)]
        out[i] = np.frombuffer(chunk[:size].ljust(size, b"\0"), dtype=np.uint8)
    return out


def _not_digits(words: np.ndarray, width: int) -> bool:
    """Whether any row of ``words`` (little-endian 64-bit words) holds a byte other than ``0``-``9`` in the
    ``width`` bytes before its last byte (eight at a time: ``y = byte ^ 0x30`` is a digit's value iff
    neither ``y`` nor ``y + 0x76`` has its high bit set; a carry out of a byte only adds to the next)."""
    n_bytes = 8 * words.shape[1]
    ones = 0x0101010101010101
    bad = np.zeros(len(words), dtype=np.uint64)
    for w in range(words.shape[1]):
        high = sum(0x80 << (8 * (b - 8 * w)) for b in range(n_bytes - 1 - width, n_bytes - 1) if 8 * w <= b < 8 * w + 8)
        if high:
            y = words[:, w] ^ np.uint64(0x30 * ones)
            bad |= ((y + np.uint64(0x76 * ones)) | y) & np.uint64(high)
    return bool(bad.any())


def _words(kb: bytes, nw: int) -> tuple[list, list]:
    """``kb`` as ``nw`` little-endian 64-bit words and the masks of their used bytes."""
    parts = [kb[8 * w:8 * w + 8] for w in range(nw)]
    return ([int.from_bytes(p.ljust(8, b"\0"), "little") for p in parts],
            [(1 << (8 * len(p))) - 1 for p in parts])


_LABEL_TABLES: dict = {}


def _label_tables(names: tuple, sep: bytes, nw: int):
    """The known types as words and masks, and the perfect hash of their first words (or None), for
    :func:`_type_labels` (made once per set of types)."""
    got = _LABEL_TABLES.get((names, sep, nw))
    if got is not None:
        return got
    kbs = [n.encode() + sep for n in names]
    keys = np.zeros((len(kbs) + 1, nw), dtype=np.uint64)
    masks = np.zeros((len(kbs) + 1, nw), dtype=np.uint64)
    for c, kb in enumerate(kbs, start=1):
        k, m = _words(kb, nw)
        keys[c], masks[c] = k, m
    first = {int(k) for k in keys[1:, 0]}
    hashed = None
    if len({int(m) for m in masks[1:, 0]}) == 1 and len(first) == len(kbs):
        for bits in range(max(1, (len(kbs) - 1).bit_length()), 9):
            for mult in (0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0xD6E8FEB86659FD93):
                slot = [((k * mult) % (1 << 64)) >> (64 - bits) for k in keys[1:, 0].tolist()]
                if len(set(slot)) == len(kbs):
                    break
            else:
                continue
            break
        else:
            bits = 0
        if bits:
            table = np.zeros(1 << bits, dtype=np.intp)
            table[slot] = np.arange(1, len(kbs) + 1)
            hashed = (table, mult, bits)
            keys, masks = keys.T.copy(), masks.T.copy()  # one small table per word
    got = (kbs, keys, masks, hashed)
    if len(_LABEL_TABLES) < 64:
        _LABEL_TABLES[(names, sep, nw)] = got
    return got


def _type_labels(type_words: np.ndarray, names: list, sep: bytes) -> np.ndarray:
    """Code (1-based index into ``names``) of each record's type, 0 for another type.

    ``type_words`` holds each record's first bytes from its type on, as 64-bit words (past its
    line end: the next line's bytes, or zeros at the end of the data). A record is of type ``name``
    when it starts with ``name`` and ``sep`` (which hold no line end, so a match lies within the line).
    The first word picks one candidate type per record through a perfect hash of the known types'
    first words (a multiply and a shift), so each further word costs one compare per record
    whatever the number of types.
    """
    nw = type_words.shape[1]
    kbs, keys, masks, hashed = _label_tables(tuple(names), sep, nw)
    if hashed is not None:
        table, mult, bits = hashed
        head = type_words[:, 0] & masks[0, 1]
        code = table[(head * np.uint64(mult)) >> np.uint64(64 - bits)]
        ok = keys[0][code] == head
        for w in range(1, nw):
            ok &= (type_words[:, w] & masks[w][code]) == keys[w][code]
        code[~ok] = 0
        return code.astype(np.int8)
    label = np.zeros(len(type_words), dtype=np.int8)  # types of several first-word lengths: one type at a time
    for c, kb in enumerate(kbs, start=1):
        cand = np.flatnonzero((type_words[:, 0] & masks[c, 0]) == keys[c, 0])
        for w in range(1, -(-len(kb) // 8)):
            cand = cand[(type_words[cand, w] & masks[c, w]) == keys[c, w]]
        label[cand] = c
    return label


@dataclass(frozen=True)
class TypedLines:
    """A record-type log split by type (see :func:`split_by_type`; its records are read by :func:`read_records`)."""

    lines: dict        # known type -> int array, the 1-based file line of each record
    counts: dict       # every record type -> number of lines, in order of first occurrence
    header: list       # header lines (str, without line end), in order
    data: bytes        # the file
    starts: np.ndarray  # first byte of every line of the file
    ends: np.ndarray    # its line-end byte (``\n``)
    n_sep: np.ndarray   # its number of separators


def split_by_type(data: bytes, sep: bytes, type_col: int, known: dict, comment: bytes = b"", header: bytes = b"",
                  spaces_ok: bool = False, is_ascii: bool | None = None) -> TypedLines | None:
    """Group the lines of a record-type log by record type, vectorised (no Python loop per known line).

    The fast path of the IPIN and ILC parsers. It returns ``None`` whenever the file holds
    anything it might not handle exactly like the line-by-line parser (no final line end, a lone
    ``\\r``, other line-end or space characters, a space next to a separator unless
    ``spaces_ok``, a line starting with a space, an unknown type that looks like a mis-cased or
    mis-delimited known type, no known type at all); the caller then parses line by line, which
    names the offending line. The number of fields of each known line is checked when its
    records are read (:func:`read_records`).

    Parameters
    ----------
    data : bytes
        UTF-8 text without byte-order mark.
    sep : bytes
        One-byte field separator.
    type_col : {0, 1}
        Column of the record type (1: after a first column of digits of equal width on every
        line, such as a 13-digit time in milliseconds).
    known : dict
        Record type -> number of separators on its lines; these types' lines are returned,
        the others are only counted.
    comment, header : bytes
        First byte of lines that are skipped (not counted) / returned as header lines.
    spaces_ok : bool
        Whether a space next to a separator is kept verbatim by the line-by-line parser.
    is_ascii : bool, optional
        ``data.isascii()``, if the caller knows it.
    """
    if not data.endswith(b"\n") or len(data) < 8:
        return None
    arr = np.frombuffer(data, dtype=np.uint8)
    sep_b = sep[0]
    ends, n_sep, n_le32 = _scan_lines(arr, sep_b)
    n_tab = int(n_sep.sum()) if sep_b == 9 else 0
    n_cr = 0
    plain = n_le32 == len(ends) + n_tab  # no space, no control byte but line ends and separating tabs
    sp = []
    k = -1 if plain else data.find(b" ")
    while k >= 0 and len(sp) < 256:  # few spaces (a header line): found one by one, and so counted
        sp.append(k)
        k = data.find(b" ", k + 1)
    if sp:
        sp = np.array(sp, dtype=np.int64) if k < 0 else byte_positions(arr, 32)
    n_low = n_le32 - len(sp)
    if n_low != len(ends) + n_tab:  # bytes below 32 other than line ends and separating tabs: looked at
        if sep_b != 9 and b"\t" in data:
            return None  # a tab is a space to str.strip
        if b"\r" in data:
            cr = byte_positions(arr, 13)
            if np.any(arr[cr + 1] != 10):  # data ends with \n, so cr + 1 is inside
                return None  # a lone \r ends a line for str.splitlines
            n_cr = len(cr)
            del cr
        if n_low != len(ends) + n_cr + n_tab:
            return None  # other control bytes (line ends or spaces for str.splitlines / str.strip)
    starts = np.empty_like(ends)
    starts[0] = 0
    starts[1:] = ends[:-1] + 1
    if not (data.isascii() if is_ascii is None else is_ascii) and any(b in data for b in _NON_ASCII_SPECIAL):
        return None
    if len(sp):
        nxt, prv = arr[np.minimum(sp + 1, len(arr) - 1)], arr[np.maximum(sp - 1, 0)]
        if np.any(sp == 0) or np.any(prv == 10) or np.any((nxt == 10) | (nxt == 13)):
            return None
        if not spaces_ok and (np.any(nxt == sep_b) or np.any(prv == sep_b)):
            return None
        del nxt, prv
    del sp
    nw = -(-max(len(k) + 1 for k in known) // 8)  # words holding the longest known type and its separator
    names = sorted(known)

    def label_records(rec, h, t_end):
        """Line starts, content ends, type starts and type codes of the records ``rec`` (lines ``h..t_end-1``
        when ``rec`` is None), or None when a record's first column is not digits."""
        rs, stop = (starts[h:t_end], ends[h:t_end]) if rec is None else (starts[rec], ends[rec])
        if n_cr:
            stop = stop - (arr[np.maximum(stop - 1, 0)] == 13)  # content end (before \r\n)
        off = width = 0
        if type_col == 0:
            t0 = rs
        else:
            width = data.find(sep, int(rs[0])) - int(rs[0])
            if width <= 0 or width > 18 or np.any(stop - rs <= width):
                return None
            t0 = rs + width + 1
            off = 8 * -(-(width + 1) // 8)  # the first column and its separator, right-aligned in whole words
        label = np.empty(len(rs), dtype=np.int8)
        for i in range(0, len(rs), _ROWS):  # a few thousand records at a time: bounded memory
            g = _gather(arr, data, t0[i:i + _ROWS] - off, off + 8 * nw).view("<u8")  # [first column, sep,] type
            if off and (np.any((g[:, off // 8 - 1] >> np.uint64(56)) != sep_b) or _not_digits(g[:, :off // 8], width)):
                return None  # only digits (int64, as int() reads them: no sign, point, exponent or separator)
            label[i:i + _ROWS] = _type_labels(g[:, off // 8:], names, sep)
        return rs, stop, t0, label

    n_lines = len(starts)
    found = None
    not_rec = {10, 13, *header[:1], *comment[:1]}  # first bytes of blank, header and comment lines
    if type_col == 1 or not any(ord(t[0]) in not_rec for t in known):
        # a header and a trailer found line by line from either end are the only lines to leave out when every
        # line between them is a record: type_col 1, every record's first column is checked to be digits (so it
        # starts with no blank, header or comment byte); type_col 0, a line of a known type is a record and
        # the others' first bytes are checked; otherwise the lines are sorted out below, one first byte per line
        h, t_end = 0, n_lines
        while h < t_end and int(arr[starts[h]]) in not_rec:
            h += 1
        while t_end > h and int(arr[starts[t_end - 1]]) in not_rec:
            t_end -= 1
        if h < t_end:
            rec = None
            found = label_records(None, h, t_end)
            if found is not None and type_col == 0:
                first = arr[starts[h:t_end][found[3] == 0]]  # the first bytes of lines of other types
                if np.isin(first, np.array(sorted(not_rec), dtype=np.uint8)).any():
                    found = None
            hl = [i for i in (*range(h), *range(t_end, n_lines)) if header and arr[starts[i]] == header[0]]
    if found is None:
        first = arr[starts]  # a blank line's first byte is its \n (or the \r of \r\n)
        is_rec = (first != 10) & (first != 13)
        is_head = is_rec & (first == header[0]) if header else None
        if header:
            is_rec &= ~is_head
        if comment:
            is_rec &= first != comment[0]
        h = int(np.argmax(is_rec))  # the first record (0 if none: then is_rec[0] is False)
        t_end = n_lines - int(np.argmax(is_rec[::-1]))
        if is_rec[h] and is_rec[h:t_end].all():  # the usual layout: a header, records, a trailer: views, no gathers
            rec = None  # line index of record i: h + i
        else:
            rec = np.flatnonzero(is_rec).astype(ends.dtype)
            if not rec.size:
                return None
        hl = np.flatnonzero(is_head).tolist() if header else []
        del is_rec, first, is_head
        found = label_records(rec, h, t_end)
        if found is None:
            return None
    rs, stop, t0, label = found
    unknown = np.flatnonzero(label == 0)
    other, first_other = _count_types(data, arr, sep_b, unknown + h if rec is None else rec[unknown], t0[unknown],
                                      stop[unknown])
    for t in other:
        ts = t.decode("utf-8", errors="replace")
        if ts.upper() in known or any(d in ts for d in (",", ";", "\t", " ") if d != sep.decode()):
            return None
    n_label = np.array([np.count_nonzero(label == c) for c in range(len(names) + 1)])  # (no int8 -> intp copy)
    present = np.flatnonzero(n_label[1:]) + 1
    if not present.size:
        return None
    by_label = np.argsort(label, kind="stable")  # grouped by type, file order within each (a radix sort)
    by_label = by_label.astype(ends.dtype) + h if rec is None else rec[by_label]  # as line indices
    at = np.cumsum(n_label)
    rows = {names[c - 1]: by_label[at[c - 1]:at[c]] for c in present.tolist()}
    del by_label
    first_of = {t: int(r[0]) for t, r in rows.items()}
    first_of.update({t.decode(): i for t, i in first_other.items()})
    n_of = {t: len(r) for t, r in rows.items()}
    n_of.update({t.decode(): n for t, n in other.items()})
    counts = {t: n_of[t] for t in sorted(first_of, key=first_of.get)}
    head_lines = [data[int(starts[i]):int(ends[i])].decode("utf-8").rstrip("\r") for i in hl]
    return TypedLines(lines={t: r + 1 for t, r in rows.items()}, counts=counts, header=head_lines, data=data,
                      starts=starts, ends=ends, n_sep=n_sep)


def _count_types(data: bytes, arr: np.ndarray, sep_b: int, rec, t0, stop) -> tuple[dict, dict]:
    """Record type -> count and -> first line index, for lines of unknown types (types start at ``t0``)."""
    other: dict[bytes, int] = {}
    first_other: dict[bytes, int] = {}
    if not len(rec):
        return other, first_other
    long_ = np.arange(len(rec))
    for width in (16, _TYPE_WINDOW):  # most types are short: a narrow window first, the others in a wide one
        win = _gather(arr, data, t0[long_], width)
        is_sep = win == sep_b
        end = np.where(is_sep.any(axis=1), np.argmax(is_sep, axis=1), width)
        end = np.minimum(end, stop[long_] - t0[long_])  # a type without separator ends with its line
        short = long_[end < width]  # (types of different lengths: no type is found in both windows)
        if short.size:
            j = np.arange(width)
            mat = np.where(j < end[end < width, None], win[end < width], 0).astype(np.uint8)
            keys = np.ascontiguousarray(mat).view(f"S{width}").ravel()
            uniq, first, n = np.unique(keys, return_index=True, return_counts=True)
            for u, f, c in zip(uniq.tolist(), first.tolist(), n.tolist(), strict=True):
                other[u] = c
                first_other[u] = int(rec[short[f]])
        long_ = long_[end >= width]  # types that may run past the window
        if not long_.size:
            break
    for i in long_.tolist():
        a, b = int(t0[i]), int(stop[i])
        e = data.find(bytes([sep_b]), a, b)
        t = data[a:b if e < 0 else e]
        if t in other:
            other[t] += 1
            first_other[t] = min(first_other[t], int(rec[i]))
        else:
            other[t] = 1
            first_other[t] = int(rec[i])
    return other, first_other


class _LineReader(io.RawIOBase):
    """A file-like object that reads the byte ranges ``[lo[i], hi[i])`` of ``data`` one after the other.

    pandas reads it a few hundred kilobytes at a time, so the selected lines are never joined into
    one more copy of the file; each read joins the whole ranges that fit.
    """

    def __init__(self, data: bytes, lo: np.ndarray, hi: np.ndarray):
        self._data = data
        self._mv = memoryview(data)  # slices of it are joined without a copy of their own
        self._lo, self._hi = lo.tolist(), hi.tolist()
        self._cum = np.cumsum(hi - lo)  # bytes up to the end of each range
        self._k = 0
        self._at = self._lo[0] if self._lo else 0

    def readable(self) -> bool:
        return True

    def read(self, size: int = -1) -> bytes:
        k, lo, hi = self._k, self._lo, self._hi
        if k >= len(lo):
            return b""
        if size is None or size < 0:
            size = int(self._cum[-1])
        if hi[k] - self._at >= size:  # within the current range
            out = self._data[self._at:self._at + size]
            self._at += size
            if self._at == hi[k]:
                self._next(k + 1)
            return out
        mv = self._mv
        parts = [mv[self._at:hi[k]]]
        j = int(np.searchsorted(self._cum, self._cum[k] + size - len(parts[0]), side="right"))  # whole ranges
        parts += [mv[a:b] for a, b in zip(lo[k + 1:j], hi[k + 1:j], strict=True)]
        self._next(j)
        return b"".join(parts)

    def readall(self) -> bytes:
        return self.read(-1)

    def _next(self, k: int) -> None:
        self._k = k
        if k < len(self._lo):
            self._at = self._lo[k]


@dataclass(frozen=True)
class Records:
    """One record type's lines read by :func:`read_records`: numeric fields, integer fields, text fields."""

    num: np.ndarray    # (n, len(num)) float64
    ints: list         # one int64 array (n,) per integer field
    strings: list      # one list of str per text field
    block: np.ndarray | None = None  # types read in turns: the (n, n_types * len(num)) array ``num`` is part of,
    col: int = 0                     # from its column ``col`` on (columns contiguous)


def read_records(tl: TypedLines, types, sep: str, n_sep: int, num, ints=(), strings=()) -> dict | None:
    """The records of ``types`` (lines with ``n_sep`` separators each), parsed by pandas, or ``None``.

    The lines of all ``types`` are read together, a few megabytes at a time, in file order, and
    each type's rows are written to its own contiguous part of one array (or, when the types take
    turns in a fixed order, one row per turn: each type's fields are their own columns of one array,
    ``Records.block``, so a caller may use the columns of several types as one table without a copy). ``num``,
    ``ints`` and
    ``strings`` are field indices (0-based, over the whole line) read as float64, int64 and
    verbatim text (``ints``: a first column that :func:`split_by_type` found to be digits only).
    ``None`` (then the caller parses line by line and names the line) if a line has another number
    of separators, a numeric cell is empty, non-numeric or not finite, or pandas read a
    ``True``/``False`` word as 1/0.

    Returns
    -------
    dict
        Type -> :class:`Records`.
    """
    import csv

    types = list(types)
    parts = [tl.lines[t] - 1 for t in types]
    n_of = [len(p) for p in parts]
    nt = len(types)
    turn, merged = _turns(parts) if nt > 1 else (None, None)
    periodic = turn is not None
    if nt == 1:
        rows, dest, code = parts[0], None, None  # every row is of type 0
    elif periodic:  # the types take turns in a fixed order: each type's rows are every k-th row, no reordering
        rows, dest, code = merged, None, None  # row i is of type turn[i % nt]
    else:
        code = np.repeat(np.arange(nt), n_of)  # each row's index in ``types``
        cat = np.concatenate(parts)
        dest = np.argsort(cat, kind="stable")  # file order -> position in the type-ordered output
        rows, code = cat[dest], code[dest]
        del cat
    n = len(rows)
    if np.any(tl.n_sep[rows] != n_sep):
        return None
    _, _, run_lo, run_hi, bounds = _runs(tl, rows)
    names = [f"c{j}" for j in range(n_sep + 1)]
    use = sorted([*num, *ints, *strings])
    dtype = {names[j]: (object if j in strings else np.int64 if j in ints else np.float64) for j in use}
    nn = len(num)
    if periodic:  # one row per turn, each type's fields in its own columns (in the order of ``types``)
        m = n // nt
        out_num = np.empty((m, nt * nn), dtype=np.float64, order="F")  # columns contiguous
        out_int = [np.empty((m, nt), dtype=np.int64, order="F") for _ in ints]
        out_str = [np.empty((m, nt), dtype=object, order="F") for _ in strings]
    else:
        out_num = np.empty((n, nn), dtype=np.float64, order="F")  # columns contiguous
        out_int = [np.empty(n, dtype=np.int64) for _ in ints]
        out_str = [np.empty(n, dtype=object) for _ in strings]
    # one parser over all the selected lines, read a piece at a time: its buffers are reused from piece to piece
    # low_memory=False: one type inference over each column of the piece, not per chunk; no NA words
    try:
        reader = pd.read_csv(_LineReader(tl.data, run_lo, run_hi), sep=sep, header=None, names=names,
                             usecols=[names[j] for j in use], dtype=dtype, quoting=csv.QUOTE_NONE, na_filter=False,
                             engine="c", skip_blank_lines=False, index_col=False, low_memory=False, iterator=True)
    except (ValueError, TypeError, pd.errors.ParserError):
        return None
    with reader:  # closes the parser's handles
        for a, b in zip(bounds[:-1], bounds[1:], strict=True):
            try:
                df = reader.get_chunk(b - a)  # an empty numeric cell fails the parse
            except (ValueError, TypeError, pd.errors.ParserError, StopIteration):
                return None
            if len(df) != b - a:
                return None
            cols = [df[names[j]].to_numpy(dtype=np.float64) for j in num]
            iv = [df[names[j]].to_numpy(dtype=np.int64) for j in ints]
            lims = [(x.min(), x.max()) for x in cols]  # NaN if a cell is NaN
            if not all(np.isfinite(m) and np.isfinite(x) for m, x in lims):
                return None
            # pandas reads a column made only of true/false words (any case) as 1/0 (float() and int() refuse
            # them): a column whose values are all 0 or 1 has its lines checked
            maybe01 = [x for x, (m, mx) in zip(cols, lims, strict=True) if m >= 0 and mx <= 1]
            maybe01 += [x for x in iv if x.min() >= 0 and x.max() <= 1]
            if any(np.all((x == 0) | (x == 1)) for x in maybe01):
                au = np.array([sum(c in b"au" for c in t.lower().encode()) for t in types])  # letters a/u of each type
                plo, phi = tl.starts[rows[a:b]], tl.ends[rows[a:b]] + 1
                pcode = (code[a:b] if code is not None else np.asarray(turn)[np.arange(a, b) % nt] if periodic
                         else np.zeros(b - a, dtype=np.intp))
                if not _no_bool_words(tl.data, plo, phi - plo, au[pcode], sep.encode(), num, ints, not strings):
                    return None
            sv = [df[names[j]].to_numpy(dtype=object) for j in strings]
            if periodic:  # row r of the file order is turn r // nt of type turn[r % nt]
                for p, ti in enumerate(turn):
                    r = a + (p - a) % nt  # the first row of phase p in this piece
                    if r >= b:
                        continue
                    e = slice(r // nt, r // nt + len(range(r, b, nt)))
                    for k, x in enumerate(cols):
                        out_num[e, ti * nn + k] = x[r - a::nt]
                    for o, x in zip([*out_int, *out_str], [*iv, *sv], strict=True):
                        o[e, ti] = x[r - a::nt]
            else:
                d = slice(a, b) if dest is None else dest[a:b]
                for k, x in enumerate(cols):
                    out_num[d, k] = x
                for o, x in zip([*out_int, *out_str], [*iv, *sv], strict=True):
                    o[d] = x
            del df, cols, iv, sv
    out = {}
    o = 0
    for i, (t, m) in enumerate(zip(types, n_of, strict=True)):
        if periodic:
            out[t] = Records(num=out_num[:, i * nn:(i + 1) * nn], ints=[x[:, i] for x in out_int],
                             strings=[x[:, i].tolist() for x in out_str], block=out_num, col=i * nn)
        else:
            sel = slice(o, o + m)
            out[t] = Records(num=out_num[sel], ints=[x[sel] for x in out_int],
                             strings=[x[sel].tolist() for x in out_str])
        o += m
    return out


def _runs(tl: TypedLines, rows: np.ndarray):
    """The runs of consecutive file lines among ``rows`` (increasing line indices) and the pieces to parse.

    Returns the index (into ``rows``) of each run's first and last line, the byte range
    ``[run_lo, run_hi)`` of each run, and ``bounds``: row indices cutting ``rows`` into pieces of about
    ``_PIECE`` bytes (computed per run, so no array over every row is made)."""
    n = len(rows)
    brk = np.flatnonzero(np.diff(rows) != 1)
    run_first = np.append(0, brk + 1)
    run_last = np.append(brk, n - 1)
    run_lo = tl.starts[rows[run_first]]
    run_hi = tl.ends[rows[run_last]] + 1
    cum = np.cumsum(run_hi - run_lo)  # selected bytes up to the end of each run
    target = np.arange(_PIECE, int(cum[-1]), _PIECE)
    j = np.searchsorted(cum, target, side="right")  # the run holding selected byte ``target``
    pos = run_hi[j] - (cum[j] - target)  # that byte in the file
    cuts = run_first[j] + (np.searchsorted(tl.ends, pos) - rows[run_first[j]])  # its line, as an index into rows
    bounds = [0] + [int(c) for c in np.unique(cuts) if 0 < c < n] + [n]
    return run_first, run_last, run_lo, run_hi, bounds


def _turns(parts: list) -> tuple[list | None, np.ndarray | None]:
    """The order in which record types take turns line after line (indices into ``parts``, each an increasing
    array of line indices) and their lines in that order, or ``(None, None)`` when they do not: each type once
    per turn, always in the same order."""
    n = len(parts[0])
    if n == 0 or any(len(p) != n for p in parts):
        return None, None
    turn = sorted(range(len(parts)), key=lambda i: int(parts[i][0]))
    merged = np.column_stack([parts[i] for i in turn]).ravel()
    return (turn, merged) if bool(np.all(merged[1:] > merged[:-1])) else (None, None)


def _no_bool_words(data: bytes, lo, ln, au_line, sep: bytes, num, ints, vectorised: bool) -> bool:
    """Whether the cells pandas read as 0 or 1 on the lines at ``lo`` (``ln`` bytes each) are numbers, not
    True/False words.

    pandas reads a column made only of true/false words (any case) as 1/0, where ``float()``
    refuses them. Every such word holds an ``a`` or a ``u``, which no number does: a line whose
    count of these letters is its record type's (``au_line``) holds none (``vectorised``: no
    text field may hold them either); the other lines are checked cell by cell.
    """
    rows = np.arange(len(lo))
    if vectorised and int(ln.max()) <= 256:
        width = int(ln.max())
        w = _gather(np.frombuffer(data, dtype=np.uint8), data, lo, width) | 0x20
        hit = ((w == 97) | (w == 117)) & (np.arange(width) < ln[:, None])
        rows = rows[np.count_nonzero(hit, axis=1) != au_line]
    for i in rows.tolist():
        cells = data[int(lo[i]):int(lo[i] + ln[i])].rstrip(b"\r\n").split(sep)
        try:
            for j in num:
                float(cells[j])
            for j in ints:
                int(cells[j])
        except ValueError:
            return False
    return True
