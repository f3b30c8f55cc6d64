"""Reader of Haas lathe programs (NGC control) into the IR: the Fanuc engine in lathe mode
with Haas's options (:data:`gcode.fanuc.options.HAAS_LATHE`): ``G04 P`` in seconds with a
decimal point, ``M97 P`` local subprograms, five-digit program numbers, the one-block
``G71``/``G72 P Q U W D F`` and ``G73 P Q U W I K D F`` roughing cycles, and the Haas lathe
machine-function M codes (``M88``/``M89`` through-spindle coolant, ``M10``-``M86`` devices
named in comments). Semantics: docs/readers/fanuc_turning.md, "Haas lathes".
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from gcode.fanuc.flow import read, read_text
from gcode.fanuc.options import HAAS_LATHE
from gcode.ngc.interpreter import InterpreterOptions
from kernel.ir import canon


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the Haas lathe program in ``path`` (streaming)."""
    return read(os.fspath(path), options or InterpreterOptions(), HAAS_LATHE)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a Haas lathe program given as text."""
    return read_text(text, name, options or InterpreterOptions(), HAAS_LATHE)
