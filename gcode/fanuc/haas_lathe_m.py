"""Haas lathe M codes that are machine functions (Haas lathe operator's manual, NGC
control, "M-codes" chapter), beyond the Fanuc ones the lathe reader shares.

:data:`THROUGH_SPINDLE` are the IR's through-tool coolant (NISTIR 5970 ``THROUGH_TOOL_ON``
/ ``THROUGH_TOOL_OFF``). :data:`MACHINE_FUNCTIONS` switch a device the IR has no command
for (chuck, air jet, tailstock, conveyor, outputs, door, ...): the reader names each one in
a ``COMMENT`` and hands it to the machine as a ``MACHINE_FUNCTION`` event, as any M code the
control passes to its PLC. Every other M code is handled as the Fanuc
lathe reader handles it.
"""

from __future__ import annotations

#: M88 / M89: high-pressure through-spindle coolant on / off
THROUGH_SPINDLE: dict[int, bool] = {88: True, 89: False}

#: M code -> the manual's name for it
MACHINE_FUNCTIONS: dict[int, str] = {
    10: "chuck clamp",
    11: "chuck unclamp",
    12: "auto air jet on",
    13: "auto air jet off",
    14: "main spindle brake on",
    15: "main spindle brake off",
    21: "tailstock advance",
    22: "tailstock retract",
    23: "angle out of thread on",
    24: "angle out of thread off",
    31: "chip conveyor forward",
    33: "chip conveyor stop",
    36: "parts catcher on",
    37: "parts catcher off",
    38: "spindle speed variation on",
    39: "spindle speed variation off",
    59: "output relay set",
    69: "output relay clear",
    85: "automatic door open",
    86: "automatic door close",
}
