"""Reader of Fanuc 0i/30i lathe programs (G code system A): the Fanuc reader in lathe mode
(:mod:`gcode.fanuc.reader` with ``lathe=True``), with the readers' two-function
contract so a dialect registry can offer it by name (e.g. ``--from fanuc_lathe``).
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from gcode.fanuc import reader as fanuc_reader
from gcode.ngc.interpreter import InterpreterOptions
from kernel.ir import canon


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the Fanuc lathe program in ``path`` (streaming)."""
    return fanuc_reader.interpret(path, options, lathe=True)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a Fanuc lathe program given as text."""
    return fanuc_reader.interpret_text(text, name, options, lathe=True)
