"""Reader of Haas mill programs (NGC control) into the IR: the Fanuc reader with Haas's
differences (:data:`gcode.fanuc.options.HAAS`): five-digit program numbers, ``G04 P`` in
seconds with a decimal point (milliseconds without), ``G187`` smoothness as continuous
blending, ``M97 P`` local subprogram calls, ``M50`` pallet change; ``G47`` engraving is
refused (``HAAS-ENGRAVING``). Semantics: docs/readers/fanuc.md.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from gcode.fanuc.flow import read, read_chunks, read_text
from gcode.fanuc.options import HAAS
from gcode.ngc.interpreter import InterpreterOptions
from kernel.ir import canon


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the Haas program in ``path`` (streaming)."""
    return read(os.fspath(path), options or InterpreterOptions(), HAAS)


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret`, with the runs of plain blocks of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays; ``arcs``: runs may hold arcs."""
    return read_chunks(os.fspath(path), options or InterpreterOptions(), HAAS, arcs)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a Haas program given as text."""
    return read_text(text, name, options or InterpreterOptions(), HAAS)
