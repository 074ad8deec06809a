"""Loaders for real recordings and the schemas of the toolkit's data types.

Every loader takes a path (file, folder or archive) and returns the types documented in
:mod:`ilocalg`; bad input raises :class:`ValueError` naming the file, line or column.
"""

from ilocalg.io.schema import FingerprintSet

__all__ = ["FingerprintSet"]
