"""Dialects: one module per language, each holding the :class:`Dialect` value its writer
uses; the reader of each is ``<name>_reader.py`` beside it (registered in
:mod:`gcode.readers`).

``get_dialect(name)`` returns a dialect by name or alias; ``NAMES`` lists them.
"""

from __future__ import annotations

import importlib

from gcode.dialects.spec import Dialect
from kernel.diagnostics import Diagnostic

NAMES: tuple[str, ...] = (
    "rs274ngc",
    "nist_v3",
    "fanuc",
    "fanuc_lathe",
    "grbl",
    "haas",
    "siemens840d",
    "sandia",
)
ALIASES: dict[str, str] = {
    "ngc": "rs274ngc",
    "linuxcnc": "rs274ngc",
    "nist": "nist_v3",
    "siemens": "siemens840d",
    "840d": "siemens840d",
    "generic": "sandia",
}


def get_dialect(name: str) -> Dialect:
    """The dialect called ``name`` (or an alias); ``CONV-DIALECT`` if there is none."""
    key = ALIASES.get(name.lower(), name.lower())
    if key not in NAMES:
        raise Diagnostic("CONV-DIALECT", f"unknown dialect {name!r}; known: {', '.join(NAMES)}")
    return importlib.import_module(f"gcode.dialects.{key}").DIALECT


__all__ = ["NAMES", "Dialect", "get_dialect"]
