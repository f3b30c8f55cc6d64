"""Register marks: which tool length register, work offset or work offset setting a
canonical command came from.

USE_TOOL_LENGTH_OFFSET (NISTIR 5970 §3.8) carries only the length, which the reader found
in the tool table it was given (zero without one). A converted program must instead say
``G43 H n`` so the control takes the length it measured itself. A reader run with
``InterpreterOptions(register_marks=True)`` (``cnc convert``) emits this mark just before
each tool length offset; a writer keeps the register in the target's own form
(``gcode.write.handlers.tool_length``). Work offsets are marked the same way: the number
of the offset a SET_G5X_OFFSET selects (its IR index holds only nine), and a program's
G10 L2/L20 setting of an offset's values, which no NISTIR command carries
(``gcode.write.extras``). ``cnc canon`` never asks for marks, so its text is rs274's.
"""

from __future__ import annotations

from typing import ClassVar

from kernel.ir import canon
from kernel.record import record


@record
class ToolLengthRegister(canon.Command):
    """The next tool length offset is ``code`` (``G43``: register ``register``;
    ``G43.2``: register ``register`` added to the current offset; ``G43.1``: by value,
    register None; ``G49``: cancelled, register None)."""

    NAME: ClassVar[str] = "TOOL_LENGTH_REGISTER"
    code: str
    register: int | None


#: work offset numbers: 1-9 are RS274/NGC's G54-G59.3 and Siemens's settable frames G54-G57,
#: G505-G509, on to 99 (G599); the additional offsets of Fanuc G54.1 P n and Haas G154 P n
#: are EXTENDED_WORK_OFFSETS + n. A number is one register of the machine's table in every
#: dialect that has it (G59.1 is not G54.1 P1: no control documents them as one).
EXTENDED_WORK_OFFSETS = 100


@record
class WorkOffsetRegister(canon.Command):
    """The next SET_G5X_OFFSET selects work offset ``number`` (see
    :data:`EXTENDED_WORK_OFFSETS`): the IR's index names one of RS274/NGC's nine slots, and
    a reader puts every further system (G54.1 P n, G510...) in the ninth."""

    NAME: ClassVar[str] = "WORK_OFFSET_REGISTER"
    number: int


@record
class WorkOffsetValues(canon.Command):
    """The program sets work offset ``number``'s values in the machine's table (G10 L2,
    G10 L20): the axes it changed (``axes``, letters of XYZABC) and their new values
    (program units, degrees for A B C), in that order."""

    NAME: ClassVar[str] = "WORK_OFFSET_VALUES"
    number: int
    axes: str
    values: tuple[float, ...]


@record
class OffsetsStored(canon.Command):
    """The program stores offsets in the machine's memory here (``code``: ``G10 L2``,
    ``G10 L20``, ``G28.1``, ``G30.1``), which no NISTIR command says for a system not in
    force or a home position. Emitted by a reader whose control empties its motion buffer
    before it writes them (Grbl 1.1: settings.c ``settings_write_coord_data``), so that a
    planner model can stop there; a writer drops it (the target control stores as it
    does)."""

    NAME: ClassVar[str] = "OFFSETS_STORED"
    code: str
