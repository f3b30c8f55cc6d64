"""Reader of Siemens SINUMERIK 840D sl milling programs (``.MPF``/``.SPF``) into the IR.

What it accepts, the semantics chosen and what it refuses: docs/readers/siemens840d.md.
The parts live in :mod:`gcode.siemens`; this module is the reader contract of
:mod:`gcode.readers` (``interpret``, ``interpret_text``: generators raising a located
``SIEM-*`` :class:`~kernel.diagnostics.Diagnostic` at the first error).
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from gcode.ngc.interpreter import InterpreterOptions
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


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of an 840D program given as text (``name`` is used in locations)."""
    opts = options or InterpreterOptions()
    return Runner(Executor(opts), Program(name, text)).run()
