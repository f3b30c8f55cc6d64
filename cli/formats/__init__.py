"""Renderers of ``cnc check`` results: text (rich), JSON, JUnit XML and SARIF 2.1.0.

Every renderer takes the same :class:`CheckReport` and returns the document as a string
(text may carry ANSI colour when asked for).
"""

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


def render(report: CheckReport, fmt: str, color: bool = False, verbosity: int = 0) -> str:
    """Dispatch to the renderer of ``fmt`` (one of :data:`FORMATS`)."""
    if fmt == "json":
        from cli.formats.json_report import render_json

        return render_json(report)
    if fmt == "junit":
        from cli.formats.junit import render_junit

        return render_junit(report)
    if fmt == "sarif":
        from cli.formats.sarif import render_sarif

        return render_sarif(report)
    from cli.formats.text import render_text

    return render_text(report, color=color, verbosity=verbosity)
