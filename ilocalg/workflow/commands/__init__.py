"""``python -m ilocalg evaluate <name>`` commands, one module each (``evaluate_<name>.py``).

Each module defines ``NAME`` (the sub-command), ``HELP`` (one line), ``add_arguments(parser)`` and
``run(args) -> dict`` returning the JSON-serialisable result. These commands and their JSON keys are
a public contract: keep them stable.
"""

from __future__ import annotations

import importlib
import pkgutil

__all__ = ["evaluators"]


def evaluators() -> dict:
    """Map sub-command name -> module, discovered from this package."""
    out = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if info.name.startswith("evaluate_"):
            mod = importlib.import_module(f"{__name__}.{info.name}")
            out[mod.NAME] = mod
    return out
