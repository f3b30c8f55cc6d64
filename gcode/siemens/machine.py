"""What the 840D motion and cycle code needs of a run: its modal state, where the block
being executed is, and where its IR goes.

:class:`Machine` is the part of :class:`gcode.siemens.executor.Executor` that
:mod:`gcode.siemens.motion` and :mod:`gcode.siemens.cycles` act on; they receive it typed
and never import the executor back (the executor imports them).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from gcode.core.corners import CornerRequest
from gcode.ngc.interpreter import InterpreterOptions
from gcode.siemens.state import State
from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.tooltable import ToolTable


@dataclass
class Values:
    """The evaluated words of one block."""

    g: dict[int, int] = field(default_factory=dict)  # group -> code
    m: list[int] = field(default_factory=list)
    v: dict[str, float] = field(default_factory=dict)
    modes: dict[str, str] = field(default_factory=dict)  # letter -> AC / IC
    cols: dict[str, int] = field(default_factory=dict)


class Machine:
    """Modal machine of one run; :attr:`out` collects the IR of the block being executed."""

    def __init__(self, options: InterpreterOptions) -> None:
        self.options = options
        self.compat = options.linuxcnc_compat
        self.tools: ToolTable | None = options.tool_table
        self.params = options.parameters or {}
        self.s = State()
        self.out: list[canon.Command] = []
        self.loc = Location()
        self.r: dict[int, float] = {}
        self.tool_names: dict[str, int] = {}  # T="NAME" -> the IR's tool number
        self.input_reads = 0  # reads of the PLC inputs $A_IN / $A_INA
        #: a block moved under ``MCALL NAME``: the runner calls NAME after the block
        self.modal_call_due = False
        #: the CHF/CHR/RND/RNDM corner the block just run asks for (the runner cuts it)
        self.corner: CornerRequest | None = None

    def emit(self, cmd: canon.Command) -> None:
        """Append one IR command to the block's output."""
        self.out.append(cmd)

    def at(self, vals: Values, letter: str) -> Location:
        """Where the block's ``letter`` word stands (the block's location without one)."""
        return Location(self.loc.file, self.loc.line, vals.cols.get(letter, self.loc.column))
