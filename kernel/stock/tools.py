"""Tool shapes for material removal: flat and ball end mills, and what the findings need.

A LinuxCNC ``.tbl`` gives flat end mills of its diameters (a table has no shape column);
``--tool N=ball:6,flute=20,nocentre`` style specs (:func:`parse_tool_spec`) give the rest.
"""

from __future__ import annotations

from dataclasses import dataclass

from kernel.diagnostics import Diagnostic, Location
from kernel.tooltable import ToolTable

KINDS = ("flat", "ball")


@dataclass(frozen=True, slots=True)
class ToolShape:
    """A milling tool seen by the height field: its cutting end and flute data.

    ``kind`` is ``flat`` (end mill, tip is its flat end) or ``ball`` (ball nose, tip is the
    lowest point of the ball). ``flute_length`` 0 means unknown; ``centre_cutting`` False
    marks a tool that must not plunge."""

    kind: str = "flat"
    diameter: float = 6.0
    flute_length: float = 0.0
    centre_cutting: bool = True

    @property
    def radius(self) -> float:
        return 0.5 * self.diameter


DEFAULT_TOOL = ToolShape()


def parse_tool_spec(text: str, where: Location | None = None) -> tuple[int, ToolShape]:
    """``N=KIND:DIAMETER[,flute=L][,nocentre]`` -> (tool number, shape); ``SIM-TOOL`` when
    the text does not read so. ``N`` 0 is the tool used when none was loaded."""
    num, eq, rest = text.partition("=")
    head, *opts = rest.split(",")
    kind, colon, dia = head.partition(":")
    try:
        if not eq or not colon:
            raise ValueError
        number, diameter = int(num), float(dia)
    except ValueError:
        raise Diagnostic(
            "SIM-TOOL", f"tool {text!r} is not N=KIND:DIAMETER[,flute=L][,nocentre]", where
        ) from None
    kind = kind.strip().lower()
    if kind not in KINDS or not diameter > 0 or number < 0:
        raise Diagnostic(
            "SIM-TOOL",
            f"tool {text!r}: kind must be one of {', '.join(KINDS)} with a diameter > 0",
            where,
        )
    flute, centre = 0.0, True
    for opt in opts:
        key, _, value = opt.strip().partition("=")
        if key == "nocentre" and not value:
            centre = False
        elif key == "flute":
            try:
                flute = float(value)
            except ValueError:
                flute = -1.0
            if not flute > 0:
                raise Diagnostic("SIM-TOOL", f"tool {text!r}: flute length must be > 0", where)
        else:
            raise Diagnostic("SIM-TOOL", f"tool {text!r}: unknown option {opt!r}", where)
    return number, ToolShape(kind, diameter, flute, centre)


def shapes_from_table(table: ToolTable, mm_per_unit: float = 1.0) -> dict[int, ToolShape]:
    """Flat end mills of a tool table's diameters (tools with no diameter are left out)."""
    return {
        n: ToolShape("flat", t.diameter * mm_per_unit)
        for n, t in table.tools.items()
        if t.diameter > 0
    }
