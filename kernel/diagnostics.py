"""User-facing diagnostics: one exception type with a stable code and a source location.

Every problem a user can cause (a malformed program, an impossible arc, a missing file, a
broken Part 21 reference) is reported as a :class:`Diagnostic` carrying a stable code such as
``NGC-ARC-RADIUS``, a message and where it happened. The CLI prints them like a compiler
(``cli.excerpt``), with the source line the front end attached (``source_line``)::

    prog.ngc:12:5: error[NGC-ARC-RADIUS]: radius to end of arc differs from radius to start
       |
    12 | g2 x10 y0 i3 j0
       | ^~

and exits non-zero. Codes are documented in ``docs/errors.md``; never reuse or rename one.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from enum import Enum

from kernel.record import record


class Severity(str, Enum):
    """How bad a diagnostic is; ``check`` reports all three, errors make the exit code 1."""

    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


@record
class Location:
    """Where something came from: a file, 1-based line and column, or a Part 21 entity id."""

    file: str | None = None
    line: int = 0
    column: int = 0
    entity: int | None = None
    workingstep: int | None = None

    def __str__(self) -> str:
        name = self.file or "<input>"
        if self.entity is not None:
            where = f"{name}:#{self.entity}"
            return f"{where}:{self.line}:{self.column}" if self.line else where
        if self.line:
            return f"{name}:{self.line}:{self.column or 1}"
        return name


@dataclass(frozen=True, slots=True)
class DiagnosticRecord:
    """A diagnostic as plain data, for collect-all modes and machine-readable reports."""

    code: str
    message: str
    location: Location = field(default_factory=Location)
    severity: Severity = Severity.ERROR
    #: the text of the source line at ``location`` as the reader had it (original case,
    #: tabs kept), when the front end attached it: the CLI shows it under the message
    source_line: str | None = None

    def format(self) -> str:
        """Compiler-style one-line rendering: ``file:line:col: error[CODE]: message``."""
        return f"{self.location}: {self.severity.value}[{self.code}]: {self.message}"

    def to_dict(self) -> dict[str, object]:
        loc = self.location
        return {
            "code": self.code,
            "severity": self.severity.value,
            "message": self.message,
            "file": loc.file,
            "line": loc.line,
            "column": loc.column,
            "entity": loc.entity,
        }


class Diagnostic(Exception):
    """The one exception type for user-facing problems (DESIGN.md, *Errors and diagnostics*)."""

    def __init__(
        self,
        code: str,
        message: str,
        location: Location | None = None,
        severity: Severity = Severity.ERROR,
    ) -> None:
        super().__init__(message)
        self.record = DiagnosticRecord(code, message, location or Location(), severity)

    @property
    def code(self) -> str:
        return self.record.code

    @property
    def message(self) -> str:
        return self.record.message

    @property
    def location(self) -> Location:
        return self.record.location

    def with_source_line(self, text: str) -> Diagnostic:
        """This diagnostic with the text of its source line attached (a front end that has
        the line in memory calls it as the diagnostic leaves it); returns ``self``."""
        if self.record.source_line is None:
            self.record = replace(self.record, source_line=text)
        return self

    def __str__(self) -> str:
        return self.record.format()
