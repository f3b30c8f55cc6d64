"""The conversion report: every approximation, expansion or omission a writer made.

A writer appends one :class:`Change` per affected IR command, with the command's source
location, so a user can find each place where the converted program is not a literal
translation (issue 7: "a conversion report of every approximation made").
"""

from __future__ import annotations

from dataclasses import dataclass, field

from kernel.diagnostics import Location


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
        }


@dataclass
class ConversionReport:
    """Filled while the writer's generator runs; complete once it is exhausted."""

    source_dialect: str = ""
    target_dialect: str = ""
    changes: list[Change] = field(default_factory=list)
    commands: int = 0
    blocks: int = 0

    def add(self, change: Change) -> None:
        self.changes.append(change)

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
            "changes": [c.to_dict() for c in self.changes],
        }
