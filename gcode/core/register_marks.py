"""Tool length register marks: which register a tool length offset came from.

USE_TOOL_LENGTH_OFFSET (NISTIR 5970 §3.8) carries only the length, which the reader found
in the tool table it was given (zero without one). A converted program must instead say
``G43 H n`` so the control takes the length it measured itself. A reader run with
``InterpreterOptions(register_marks=True)`` (``cnc convert``) emits this mark just before
each tool length offset; a writer keeps the register in the target's own form
(``gcode.write.handlers.tool_length``). ``cnc canon`` never asks for marks, so its text
is rs274's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from kernel.ir import canon


@dataclass(frozen=True, slots=True)
class ToolLengthRegister(canon.Command):
    """The next tool length offset is ``code`` (``G43``: register ``register``;
    ``G43.2``: register ``register`` added to the current offset; ``G43.1``: by value,
    register None; ``G49``: cancelled, register None)."""

    NAME: ClassVar[str] = "TOOL_LENGTH_REGISTER"
    code: str
    register: int | None
