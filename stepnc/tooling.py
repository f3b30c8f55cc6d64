"""Tools: NIST's ISO 14649 tool file and the program's own tool descriptions.

The tool file (``iso14649.tool_ex1``) has header lines, one blank line, then rows
``POCKET FMS TLO DIAM HOLDER description`` where FMS is the tool's ``its_id`` from the
program, bare or quoted with ``'`` or ``"`` (corpus/README.md).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from kernel.diagnostics import Diagnostic, Location

_ROW = re.compile(r"""\s*(\d+)\s+('[^']*'|"[^"]*"|\S+)\s+(\S+)\s+(\S+)(?:\s+(\S+))?\s*(.*)$""")


@dataclass(frozen=True, slots=True)
class ToolEntry:
    pocket: int
    id: str
    length: float
    diameter: float
    description: str = ""


def read_tool_file(lines: Iterable[str], file: str | None = None) -> dict[str, ToolEntry]:
    """Tool entries by id. Raises ``STEPNC-TOOL-FILE`` on a malformed row."""
    tools: dict[str, ToolEntry] = {}
    in_data = False
    for n, line in enumerate(lines, 1):
        text = line.rstrip("\n")
        if not in_data:
            in_data = text.strip() == ""
            continue
        if not text.strip():
            continue
        m = _ROW.match(text)
        try:
            if m is None:
                raise ValueError
            ident = m.group(2).strip("'\"")
            entry = ToolEntry(
                int(m.group(1)), ident, float(m.group(3)), float(m.group(4)), m.group(6).strip()
            )
        except ValueError:
            raise Diagnostic(
                "STEPNC-TOOL-FILE", f"bad tool file row: {text.strip()!r}", Location(file, n, 1)
            ) from None
        tools.setdefault(ident, entry)
    return tools


def load_tool_file(path: str) -> dict[str, ToolEntry]:
    with open(path, encoding="latin-1") as fh:
        return read_tool_file(fh, path)
