"""Reader of Siemens SINUMERIK 840D sl milling programs (``.MPF``/``.SPF``) into the IR.

What it accepts, the semantics chosen and what it refuses: docs/readers/siemens840d.md.
The parts live in :mod:`gcode.siemens`; this module is the reader contract of
:mod:`gcode.readers` (``interpret``, ``interpret_text``: generators raising a located
``SIEM-*`` :class:`~kernel.diagnostics.Diagnostic` at the first error).
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from gcode.ngc.interpreter import LANE_MIN_BYTES, InterpreterOptions
from gcode.siemens.executor import Executor
from gcode.siemens.flow import Runner
from gcode.siemens.program import Program
from kernel.ir import canon


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the 840D program in ``path`` (streaming)."""
    opts = options or InterpreterOptions()
    program = Program.load(os.fspath(path))
    return Runner(Executor(opts), program).run()


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret`, with the runs of plain blocks of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays (gcode.siemens.lane); ``arcs``: runs may
    hold arcs. ``cnc convert`` reads its 840D output back through it."""
    opts = options or InterpreterOptions()
    program = Program.load(os.fspath(path))
    lane = None
    if opts.fast_lane and len(program.text) >= LANE_MIN_BYTES:
        # imported here: numpy and the kernels load only for a large program
        from gcode.siemens.lane import SiemensLane

        lane = SiemensLane.for_program(program, arcs)
    return Runner(Executor(opts), program).chunks(lane)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of an 840D program given as text (``name`` is used in locations)."""
    opts = options or InterpreterOptions()
    return Runner(Executor(opts), Program(name, text)).run()
