"""Tool tables: LinuxCNC ``.tbl`` files and the NIST v3 tool file (seed 002 §2.3, Table 1).

LinuxCNC lines read ``T<tool> P<pocket> [X.. Y.. Z.. A.. B.. C.. U.. V.. W..] [D<diameter>]
[I<front angle>] [J<back angle>] [Q<orientation>] [;comment]``. The NIST file has header
lines, exactly one empty line, then rows ``POCKET FMS TLO DIAM [comment]``; the FMS number is
the tool id and TLO the length offset.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass, field

from kernel.diagnostics import Diagnostic, Location


@dataclass(frozen=True, slots=True)
class Tool:
    number: int
    pocket: int
    offset: tuple[float, ...] = (0.0,) * 9  # x y z a b c u v w
    diameter: float = 0.0
    front_angle: float = 0.0
    back_angle: float = 0.0
    orientation: int = 0
    comment: str = ""
    # the row LinuxCNC's non-random tool changer puts the tool in (its CHANGE_TOOL slot); 0:
    # the table's order. Each P word read takes the next row, so a line with two P words
    # takes two (LinuxCNC 2.9 tooldata_common.cc, tooldata_read_entry).
    row: int = 0

    @property
    def z_offset(self) -> float:
        return self.offset[2]

    @property
    def x_offset(self) -> float:
        return self.offset[0]


@dataclass
class ToolTable:
    """Tools by number. Tool 0 means 'no tool' and always exists with zero offsets."""

    tools: dict[int, Tool] = field(default_factory=dict)

    def get(self, number: int) -> Tool | None:
        if number == 0:
            return self.tools.get(0, Tool(0, 0))
        return self.tools.get(number)

    def __contains__(self, number: int) -> bool:
        return number == 0 or number in self.tools


_AXIS_INDEX = {c: i for i, c in enumerate("xyzabcuvw")}


def _finite(text: str) -> float:
    """A tool table number: ASCII, finite (``float`` also takes ``nan``, ``inf``, ``1e999``
    and Unicode digits); ValueError otherwise."""
    value = float(text)
    if not text.isascii() or not math.isfinite(value):
        raise ValueError(text)
    return value


def read_linuxcnc_tbl(lines: Iterable[str], file: str | None = None) -> ToolTable:
    table = ToolTable()
    rows = 0  # P words read so far
    for n, line in enumerate(lines, 1):
        text, _, comment = line.partition(";")
        words = text.split()
        if not words:
            continue
        fields: dict[str, float] = {}
        for w in words:
            letter = w[0].lower()
            try:
                fields[letter] = _finite(w[1:])
            except ValueError:
                raise Diagnostic(
                    "TOOL-SYNTAX", f"bad tool table word '{w}'", Location(file, n, line.find(w) + 1)
                ) from None
        if "t" not in fields:
            raise Diagnostic("TOOL-SYNTAX", "tool table line without T word", Location(file, n, 1))
        p_words = sum(1 for w in words if w[0] in "Pp")
        rows += p_words
        offset = [0.0] * 9
        for letter, i in _AXIS_INDEX.items():
            offset[i] = fields.get(letter, 0.0)
        number = int(fields["t"])
        table.tools[number] = Tool(
            number=number,
            pocket=int(fields.get("p", number)),
            offset=tuple(offset),
            diameter=fields.get("d", 0.0),
            front_angle=fields.get("i", 0.0),
            back_angle=fields.get("j", 0.0),
            orientation=int(fields.get("q", 0)),
            comment=comment.strip(),
            row=rows if p_words else 0,
        )
    return table


def read_nist_tool_file(lines: Iterable[str], file: str | None = None) -> ToolTable:
    """NIST v3 tool file: header, one blank line, then ``POCKET FMS TLO DIAM [comment]``."""
    table = ToolTable()
    in_data = False
    for n, line in enumerate(lines, 1):
        if not in_data:
            if line.rstrip("\n") == "":
                in_data = True
            continue
        parts = line.split(None, 4)
        if not parts:
            continue
        try:
            pocket, fms = int(parts[0]), int(parts[1])
            tlo, diam = _finite(parts[2]), _finite(parts[3])
        except (ValueError, IndexError):
            raise Diagnostic(
                "TOOL-SYNTAX", f"bad tool file row: '{line.strip()}'", Location(file, n, 1)
            ) from None
        if fms == 0:
            continue
        table.tools[fms] = Tool(
            number=fms,
            pocket=pocket,
            offset=(0.0, 0.0, tlo) + (0.0,) * 6,
            diameter=diam,
            comment=parts[4].strip() if len(parts) > 4 else "",
        )
    if not in_data:
        raise Diagnostic(
            "TOOL-NO-BLANK", "tool file has no blank line before its data", Location(file, 1, 1)
        )
    return table


_UNITS_HEADER = re.compile(r"^\s*[;(]\s*units\s*[:=]\s*(mm|inch)\b", re.I)


def header_units(lines: Iterable[str]) -> str | None:
    """The length unit a tool table declares in a comment before its first tool line
    (``; units: inch`` or ``; units = mm``; a LinuxCNC ``.tbl`` has no unit of its own: its
    lengths are in the machine's units), or None when it declares none."""
    for line in lines:
        s = line.strip()
        if not s:
            continue
        m = _UNITS_HEADER.match(s)
        if m:
            return m.group(1).lower()
        if not s.startswith((";", "(")):
            return None
    return None


def read_tool_table(lines: list[str], file: str | None = None) -> ToolTable:
    """Detect the format: LinuxCNC lines start with ``T``; anything else is a NIST file."""
    for line in lines:
        s = line.strip()
        if s and not s.startswith(";"):
            if s[0] in "Tt" and len(s) > 1 and (s[1].isdigit() or s[1] in "+-"):
                return read_linuxcnc_tbl(lines, file)
            break
    return read_nist_tool_file(lines, file)
