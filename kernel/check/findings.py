"""What ``cnc check`` reports: one finding per problem, tied to a rule and a source location."""

from __future__ import annotations

from dataclasses import dataclass, field

from kernel.diagnostics import Location, Severity


def _int(v: object) -> int:
    """A line or column of a finding's dict: a number (or its text); missing or 0 is 0."""
    if not v:
        return 0
    if isinstance(v, int | float | str):
        return int(v)
    raise TypeError(f"a line or column must be a number, not {v!r}")


@dataclass(frozen=True, slots=True)
class Finding:
    """A problem a rule found. ``code`` is the underlying diagnostic code when the finding
    wraps an interpreter error (rule CNC001), e.g. ``NGC-ARC-RADIUS``."""

    rule: str
    severity: Severity
    message: str
    location: Location = field(default_factory=Location)
    code: str | None = None

    def format(self) -> str:
        """``file:line:col: warning[CNC203]: message`` (compiler style, DESIGN.md)."""
        tag = f"{self.rule}/{self.code}" if self.code else self.rule
        return f"{self.location}: {self.severity.value}[{tag}]: {self.message}"

    def to_dict(self) -> dict[str, object]:
        loc = self.location
        return {
            "rule": self.rule,
            "code": self.code,
            "severity": self.severity.value,
            "message": self.message,
            "file": loc.file,
            "line": loc.line,
            "column": loc.column,
        }

    @classmethod
    def from_dict(cls, d: dict[str, object]) -> Finding:
        """Inverse of :meth:`to_dict` (a finding passed back from a worker process)."""
        file = d.get("file")
        loc = Location(
            None if file is None else str(file), _int(d.get("line")), _int(d.get("column"))
        )
        code = d.get("code")
        return cls(
            str(d["rule"]),
            Severity(str(d["severity"])),
            str(d["message"]),
            loc,
            str(code) if code else None,
        )
