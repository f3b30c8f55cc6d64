"""The conversion report: every approximation, expansion or omission a writer made.

A writer appends one :class:`Change` per affected IR command, with the command's source
location, so a user can find each place where the converted program is not a literal
translation (issue 7: "a conversion report of every approximation made"). Each code is
either a *loss* (the converted program makes the machine do something else: spindle,
coolant, tools, offsets, feed mode, stops, outputs, motion beyond the tolerance), which
``cnc convert`` refuses unless the user accepts it by code, or a *note* (the same part,
written another way). Issue 15: "losses are errors".
"""

from __future__ import annotations

from dataclasses import dataclass, field

from kernel.diagnostics import Location

#: codes whose entries change what the machine does (docs/errors.md)
LOSS_CODES: frozenset[str] = frozenset(
    {
        "CONV-SPINDLE",
        "CONV-COOLANT",
        "CONV-TOOL-CHANGE",
        "CONV-TOOL-LENGTH",
        "CONV-ORIGIN",
        "CONV-WORK-OFFSET",
        "CONV-FEED-MODE",
        "CONV-MOTION-MODE",
        "CONV-STOP",
        "CONV-PALLET",
        "CONV-DWELL",
        "CONV-OVERRIDE",
        "CONV-OUTPUT",
        "CONV-PROBE-MOVE",
        "CONV-MACHINE-FUNCTION",
        "CONV-UNSUPPORTED",
        "CONV-TOLERANCE",
    }
)

#: a canonical command as the machinist wrote it: the word and what it does
MACHINIST: dict[str, str] = {
    "START_SPINDLE_CLOCKWISE": "M03 (spindle clockwise)",
    "START_SPINDLE_COUNTERCLOCKWISE": "M04 (spindle counterclockwise)",
    "STOP_SPINDLE_TURNING": "M05 (spindle stop)",
    "SET_SPINDLE_SPEED": "S (spindle speed)",
    "SET_SPINDLE_MODE": "G96/G97 (spindle speed mode)",
    "ORIENT_SPINDLE": "M19 (spindle orientation)",
    "FLOOD_ON": "M08 (flood coolant)",
    "FLOOD_OFF": "M09 (coolant off)",
    "MIST_ON": "M07 (mist coolant)",
    "MIST_OFF": "M09 (coolant off)",
    "OPTIONAL_PROGRAM_STOP": "M01 (optional stop)",
    "PROGRAM_STOP": "M00 (program stop)",
    "PALLET_SHUTTLE": "M60 (pallet change)",
    "CHANGE_TOOL_NUMBER": "M61 (set tool number)",
    "SET_MOTION_CONTROL_MODE": "G61/G64 (path control mode)",
    "DWELL": "G04 (dwell)",
    "MESSAGE": "(MSG,...) (operator message)",
    "ENABLE_FEED_OVERRIDE": "M48/M50 (feed override)",
    "DISABLE_FEED_OVERRIDE": "M49/M50 (feed override)",
    "ENABLE_SPEED_OVERRIDE": "M48/M51 (speed override)",
    "DISABLE_SPEED_OVERRIDE": "M49/M51 (speed override)",
    "STRAIGHT_PROBE": "G38.n (probing move)",
    "SET_ORIGIN_OFFSETS": "G92/G10 L2 (program origin)",
    "SET_G5X_OFFSET": "G54-G59.3 (work offset)",
    "SET_G92_OFFSET": "G92 (axis offset)",
    "SET_XY_ROTATION": "G10 L2 R (work offset rotation)",
    "WORK_OFFSET_VALUES": "G10 L2/L20 (work offset setting)",
    "SET_AUX_OUTPUT_BIT": "M64 (digital output on)",
    "CLEAR_AUX_OUTPUT_BIT": "M65 (digital output off)",
    "SET_MOTION_OUTPUT_BIT": "M62 (digital output on with motion)",
    "CLEAR_MOTION_OUTPUT_BIT": "M63 (digital output off with motion)",
    "SET_AUX_OUTPUT_VALUE": "M68 (analog output)",
    "SET_MOTION_OUTPUT_VALUE": "M67 (analog output with motion)",
    "SET_TOOL_TABLE_ENTRY": "G10 L1 (tool table edit)",
    "USE_TOOL_LENGTH_OFFSET": "G43 (tool length offset)",
    "SPINDLE_RETRACT": "spindle retract",
    "ARC_FEED": "G02/G03 (arc)",
    "ARC_FEED (0 turns)": "G02/G03 (arc of no turn)",
    "NURBS_FEED": "G5.2 (NURBS)",
    "ELLIPSE_FEED": "ellipse (no G-code of its own)",
}

#: the loss code of a command a target has no word for (by its IR name)
LOSS_OF: dict[str, str] = {
    "START_SPINDLE_CLOCKWISE": "CONV-SPINDLE",
    "START_SPINDLE_COUNTERCLOCKWISE": "CONV-SPINDLE",
    "STOP_SPINDLE_TURNING": "CONV-SPINDLE",
    "SET_SPINDLE_SPEED": "CONV-SPINDLE",
    "SET_SPINDLE_MODE": "CONV-SPINDLE",
    "ORIENT_SPINDLE": "CONV-SPINDLE",
    "FLOOD_ON": "CONV-COOLANT",
    "FLOOD_OFF": "CONV-COOLANT",
    "MIST_ON": "CONV-COOLANT",
    "MIST_OFF": "CONV-COOLANT",
    "OPTIONAL_PROGRAM_STOP": "CONV-STOP",
    "PROGRAM_STOP": "CONV-STOP",
    "PROGRAM_END": "CONV-STOP",
    "PALLET_SHUTTLE": "CONV-PALLET",
    "CHANGE_TOOL_NUMBER": "CONV-TOOL-CHANGE",
    "SET_MOTION_CONTROL_MODE": "CONV-MOTION-MODE",
    "DWELL": "CONV-DWELL",
    "MESSAGE": "CONV-MESSAGE",
    "ENABLE_FEED_OVERRIDE": "CONV-OVERRIDE",
    "DISABLE_FEED_OVERRIDE": "CONV-OVERRIDE",
    "ENABLE_SPEED_OVERRIDE": "CONV-OVERRIDE",
    "DISABLE_SPEED_OVERRIDE": "CONV-OVERRIDE",
    "STRAIGHT_PROBE": "CONV-PROBE-MOVE",
    "SET_ORIGIN_OFFSETS": "CONV-ORIGIN",
    "SET_G5X_OFFSET": "CONV-ORIGIN",
    "SET_G92_OFFSET": "CONV-ORIGIN",
    "SET_XY_ROTATION": "CONV-ORIGIN",
    "WORK_OFFSET_VALUES": "CONV-WORK-OFFSET",
    "SET_AUX_OUTPUT_BIT": "CONV-OUTPUT",
    "CLEAR_AUX_OUTPUT_BIT": "CONV-OUTPUT",
    "SET_MOTION_OUTPUT_BIT": "CONV-OUTPUT",
    "CLEAR_MOTION_OUTPUT_BIT": "CONV-OUTPUT",
    "SET_AUX_OUTPUT_VALUE": "CONV-OUTPUT",
    "SET_MOTION_OUTPUT_VALUE": "CONV-OUTPUT",
    "SET_TOOL_TABLE_ENTRY": "CONV-TOOL-LENGTH",
    "USE_TOOL_LENGTH_OFFSET": "CONV-TOOL-LENGTH",
}


def loss_code(name: str) -> str:
    """The code of a report entry for a command a target has no word for."""
    return LOSS_OF.get(name, "CONV-UNSUPPORTED")


def machinist(name: str) -> str:
    """An IR command's name in the control's terms (the IR name where none is known)."""
    return MACHINIST.get(name, name)


@dataclass(frozen=True, slots=True)
class Change:
    """One place where the output differs in form or exactness from the IR."""

    code: str  # the CONV-* code the writer would raise when refusing
    kind: str  # approximated | expanded | substituted | dropped
    message: str
    source: Location | None = None
    pieces: int = 0  # blocks written in its place
    deviation: float | None = None  # largest distance from the original path (output units)
    tolerance: float | None = None

    @property
    def loss_code(self) -> str | None:
        """The loss this entry is, where the machine would do something else: its own code,
        or CONV-TOLERANCE for a path further from the original than the tolerance."""
        if self.code in LOSS_CODES:
            return self.code
        dev, tol = self.deviation, self.tolerance
        if dev is not None and tol is not None and dev > tol * (1 + 1e-9) + 1e-12:
            return "CONV-TOLERANCE"
        return None

    @property
    def loss(self) -> bool:
        """True where the converted program makes the machine do something else."""
        return self.loss_code is not None

    def to_dict(self) -> dict[str, object]:
        src = self.source
        return {
            "code": self.code,
            "kind": self.kind,
            "message": self.message,
            "file": src.file if src else None,
            "line": src.line if src else None,
            "pieces": self.pieces,
            "deviation": self.deviation,
            "tolerance": self.tolerance,
            "loss": self.loss_code,
        }


@dataclass(frozen=True, slots=True)
class Group:
    """Entries of one kind (code, kind and message): the first, how many, their totals."""

    first: Change
    count: int
    pieces: int
    deviation: float | None

    def to_dict(self) -> dict[str, object]:
        src = self.first.source
        return {
            "code": self.first.code,
            "kind": self.first.kind,
            "message": self.first.message,
            "file": src.file if src else None,
            "line": src.line if src else None,
            "count": self.count,
            "pieces": self.pieces,
            "deviation": self.deviation,
            "tolerance": self.first.tolerance,
        }


def group(changes: list[Change]) -> list[Group]:
    """One :class:`Group` per kind of entry, in the order of their first occurrence."""
    order: dict[tuple[str, str, str], list[Change]] = {}
    for c in changes:
        order.setdefault((c.code, c.kind, c.message), []).append(c)
    out: list[Group] = []
    for items in order.values():
        devs = [c.deviation for c in items if c.deviation is not None]
        out.append(
            Group(items[0], len(items), sum(c.pieces for c in items), max(devs) if devs else None)
        )
    return out


@dataclass
class ConversionReport:
    """Filled while the writer's generator runs; complete once it is exhausted."""

    source_dialect: str = ""
    target_dialect: str = ""
    changes: list[Change] = field(default_factory=list)
    commands: int = 0
    blocks: int = 0
    allowed: frozenset[str] = frozenset()  # loss codes the user accepted (--allow-loss)

    def add(self, change: Change) -> None:
        self.changes.append(change)

    def refused(self) -> list[Change]:
        """Losses the user did not accept: the conversion must not be written."""
        return [c for c in self.changes if c.loss and c.loss_code not in self.allowed]

    def accepted(self) -> list[Change]:
        """Losses accepted by ``--allow-loss``."""
        return [c for c in self.changes if c.loss and c.loss_code in self.allowed]

    def notes(self) -> list[Change]:
        """Entries that leave the part and the machine's behaviour as they were."""
        return [c for c in self.changes if not c.loss]

    def to_dict(self) -> dict[str, object]:
        counts: dict[str, int] = {}
        for c in self.changes:
            counts[c.code] = counts.get(c.code, 0) + 1
        return {
            "from": self.source_dialect,
            "to": self.target_dialect,
            "commands": self.commands,
            "blocks": self.blocks,
            "summary": counts,
            "allowed": sorted(self.allowed),
            "losses": [g.to_dict() for g in group(self.refused())],
            "accepted": [g.to_dict() for g in group(self.accepted())],
            "notes": [g.to_dict() for g in group(self.notes())],
            "changes": [c.to_dict() for c in self.changes],
        }
