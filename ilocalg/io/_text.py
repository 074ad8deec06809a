"""Parsing helpers shared by the text-log loaders (private to :mod:`ilocalg.io`).

Every loader reports bad content the same way: ``FILE: line N: what is wrong`` or
``FILE: line N, column COL: what is wrong``, where N is the 1-based line of the file a person
opens in an editor, never a table row.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NoReturn

import numpy as np

__all__ = ["fail", "to_float", "first_not_increasing", "check_increasing", "decode_text", "decompress",
           "read_bytes", "read_text", "strip_trailing_blank_lines", "ArchiveReader", "TRUNCATED_POLICIES",
           "check_truncated_policy", "cut_last_line", "check_record_types"]


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
