"""What every ``cnc check`` renderer takes: the :class:`CheckReport` of a run and its
:class:`FileResult` per file, the format names and the rules' documentation address (a leaf,
so the renderers need not import the package that dispatches to them)."""

from __future__ import annotations

from dataclasses import dataclass, field

from kernel.check import Finding, Rule
from kernel.diagnostics import Severity

FORMATS = ("text", "json", "junit", "sarif")
DOCS_URI = "https://github.com/cnc-toolchain/cnc-toolchain/blob/main/docs/check-rules.md"


@dataclass(frozen=True, slots=True)
class FileResult:
    """One checked file: its findings, or the I/O error that kept it from being read."""

    file: str
    findings: tuple[Finding, ...] = ()
    io_error: str | None = None
    seconds: float = 0.0

    def count(self, sev: Severity) -> int:
        return sum(1 for f in self.findings if f.severity == sev)


@dataclass(frozen=True, slots=True)
class CheckReport:
    """All files of one ``cnc check`` run plus the rules that were active."""

    files: tuple[FileResult, ...]
    rules: tuple[tuple[Rule, Severity | None], ...]  # every rule with its effective severity
    machine: str = ""
    version: str = ""
    seconds: float = 0.0
    extra: dict[str, object] = field(default_factory=dict)

    def total(self, sev: Severity) -> int:
        return sum(r.count(sev) for r in self.files)

    @property
    def io_errors(self) -> int:
        return sum(1 for r in self.files if r.io_error)


__all__ = ["DOCS_URI", "FORMATS", "CheckReport", "FileResult"]
