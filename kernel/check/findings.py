"""What ``cnc check`` reports: one finding per problem, tied to a rule and a source location."""

from __future__ import annotations

from dataclasses import dataclass, field

from kernel.diagnostics import Location, Severity


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
        loc = Location(d.get("file"), int(d.get("line") or 0), int(d.get("column") or 0))  # type: ignore[arg-type]
        code = d.get("code")
        return cls(
            str(d["rule"]),
            Severity(str(d["severity"])),
            str(d["message"]),
            loc,
            str(code) if code else None,
        )
