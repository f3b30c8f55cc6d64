"""The real shop-program suite (tests/realworld/shop): its manifest and how a program is read.

``tests/realworld/shop/manifest.toml`` lists every public program of the suite with the
dialect its control speaks and what reading it must give: ``runs`` (the golden IR
``<file>.canon`` beside it, checked a second way where the manifest says so) or
``refused`` (the diagnostic code and line, and the reason: a construct the control itself
refuses, or one the reader documents as not read). Sources and licences:
tests/realworld/SOURCES.md, section "Fanuc, Haas, Siemens and lathes".
"""

from __future__ import annotations

import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table

HERE = Path(__file__).resolve().parent / "realworld" / "shop"
MANIFEST = HERE / "manifest.toml"
TOOL_TABLE = HERE / "sim.tbl"
#: what a manifest entry may name as its second check
CHECKS = frozenset({"rs274", "peer", "hand"})


@dataclass(frozen=True)
class Entry:
    """One program of the manifest."""

    name: str  # path under tests/realworld/shop
    dialect: str
    expect: str  # runs | refused
    code: str | None
    line: int | None
    reason: str
    checks: tuple[str, ...]
    slow: bool

    @property
    def path(self) -> Path:
        return HERE / self.name

    @property
    def golden(self) -> Path:
        return self.path.parent / (self.path.name + ".canon")

    @property
    def second(self) -> Path:
        """rs274's reading of our IR written as RS274/NGC."""
        return self.path.parent / (self.path.name + ".rs274.canon")

    @property
    def rs274(self) -> bool:
        return "rs274" in self.checks


def entries() -> list[Entry]:
    data = tomllib.loads(MANIFEST.read_text())
    out = []
    for item in data["program"]:
        out.append(
            Entry(
                name=item["file"],
                dialect=item["dialect"],
                expect=item["expect"],
                code=item.get("code"),
                line=item.get("line"),
                reason=item.get("reason", ""),
                checks=tuple(item.get("checks", ())),
                slow=bool(item.get("slow", False)),
            )
        )
    return out


def options(entry: Entry) -> InterpreterOptions:
    """The reader's options: subprograms are looked up beside the program."""
    return InterpreterOptions(search_path=(str(entry.path.parent),))


def our_ir(entry: Entry) -> list[canon.Command]:
    """The IR our reader gives for the program (raises its Diagnostic when it refuses)."""
    return list(read(entry.path, entry.dialect, options(entry)))


def refusal(entry: Entry) -> Diagnostic | None:
    """The diagnostic our reader stops the program with, or None when it runs."""
    try:
        our_ir(entry)
    except Diagnostic as exc:
        return exc
    return None


def ngc_text(ir: Sequence[canon.Command]) -> str:
    """The IR as RS274/NGC (``cnc convert --to ngc``), for rs274 to read back."""
    return "\n".join(write(ir, "rs274ngc", WriterOptions(), ConversionReport())) + "\n"


def tool_table() -> object:
    return read_tool_table(TOOL_TABLE.read_text().splitlines(), str(TOOL_TABLE))
