"""Loaders for real recordings and the schemas of the toolkit's data types.

Every loader takes a path (file, folder or archive) and returns the types documented in
:mod:`ilocalg`; bad input raises :class:`ValueError` naming the file, line or column.

- :func:`load_ujiindoorloc`: UJIIndoorLoc ``trainingData.csv`` / ``validationData.csv`` (plain or .gz)
- :func:`load_oxford_step_counter`: an Oxford step counter recording (folder, archive member or
  validation-style CSV)
- :func:`load_ilc_trace`, :func:`load_ilc_floor`: Indoor Location Competition 2.0 traces and floors
  (folder or archive, read in memory)
- :func:`load_ipin_logfile`: IPIN competition smartphone logfiles
- :class:`Recording`, :func:`load_recording`: any walk as one type, the loader picked from the content;
  :func:`write_ipin_logfile`, :func:`write_ilc_trace` write any recording in those formats

One policy for every text file: UTF-8 (a non-UTF-8 byte is an error naming its line), a leading
byte-order mark stripped, CRLF line ends and trailing blank lines accepted, ``.gz`` / ``.xz``
files read transparently (corrupt data, archives and JSON are errors naming the file and the
archive member). Every value is checked against its valid range, declared once in
:data:`ilocalg.io.schema.FIELD_RANGES`; errors read ``FILE: line N, column COL: value V is outside
[a, b] unit``. Quirks that real files have are accepted only through an explicit policy argument
that counts what it changes, and the error message names it: ``duplicate_bssid="keep_latest"``
(ILC), ``duplicate_timestamps="drop"`` (Oxford), ``truncated_last_line="drop"`` (IPIN, ILC). A quirk
of a set's ground truth that no error can flag (the Oxford heel sensors' bounces) is counted on every
load and changed only under its policy (``heel_bounces="merge"``, Oxford).
"""

from ilocalg.io.ilc import load_ilc_floor, load_ilc_trace
from ilocalg.io.ilc_write import write_ilc_trace
from ilocalg.io.ipin import load_ipin_logfile
from ilocalg.io.ipin_write import write_ipin_logfile
from ilocalg.io.oxford import load_oxford_step_counter
from ilocalg.io.recording import LocalFrame, Recording, as_recording, load_recording
from ilocalg.io.schema import FingerprintSet
from ilocalg.io.ujiindoorloc import load_ujiindoorloc

__all__ = [
    "FingerprintSet",
    "load_ujiindoorloc",
    "load_oxford_step_counter",
    "load_ilc_trace",
    "load_ilc_floor",
    "load_ipin_logfile",
    "Recording",
    "LocalFrame",
    "as_recording",
    "load_recording",
    "write_ipin_logfile",
    "write_ilc_trace",
]
