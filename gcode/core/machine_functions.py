"""M codes a control does not define itself and hands to the machine's PLC (chip conveyor,
clamps, doors, ...): the Fanuc-family and Siemens readers turn them into
:class:`kernel.ir.canon.MachineFunction` events instead of refusing the program.

A control takes M codes of up to eight digits (Fanuc parameter 3030 at 0); a longer one is
still refused with the reader's ``*-UNKNOWN-M`` code.
"""

from __future__ import annotations

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

#: the largest M code a control passes on (eight digits)
MAX_CODE = 99_999_999


def machine_function(
    code: int, p: float | None, q: float | None, loc: Location, error_code: str
) -> canon.MachineFunction:
    """The event for M``code`` at ``loc``; ``error_code`` when the code has too many digits."""
    if not 0 <= code <= MAX_CODE:
        raise Diagnostic(
            error_code, f"M{code} is not an M code a control passes on (at most 8 digits)", loc
        )
    return canon.MachineFunction(code, p, q, source=loc)
