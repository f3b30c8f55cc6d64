"""Human-readable check output: compiler-style lines, then a rich summary table."""

from __future__ import annotations

import io

from rich.console import Console
from rich.table import Table
from rich.text import Text

from cli.excerpt import detail_lines
from cli.formats.base import CheckReport
from kernel.diagnostics import Severity

_STYLE = {Severity.ERROR: "bold red", Severity.WARNING: "yellow", Severity.NOTE: "cyan"}


def render_text(report: CheckReport, color: bool = False, verbosity: int = 0) -> str:
    """Findings, then (unless ``-q``) a table of flagged files and a summary; ``-qq``
    prints errors only."""
    buf = io.StringIO()
    con = Console(
        file=buf,
        force_terminal=color,
        no_color=not color,
        width=120,
        highlight=False,
        soft_wrap=True,
    )
    summaries = {rule.id: rule.summary for rule, _ in report.rules}
    for r in report.files:
        if r.io_error:
            line = Text(f"{r.file}: ")
            line.append("error[IO-ERROR]", style="bold red")
            line.append(f": {r.io_error}")
            con.print(line)
        for f in r.findings:
            if verbosity <= -2 and f.severity != Severity.ERROR:
                continue
            tag = f"{f.rule}/{f.code}" if f.code else f.rule
            line = Text(f"{f.location}: ")
            line.append(f"{f.severity.value}[{tag}]", style=_STYLE[f.severity])
            line.append(f": {f.message}")
            con.print(line)
            code = f.code or f.rule
            for extra in detail_lines(f.location, code, None, verbosity, summaries.get(f.rule)):
                con.print(Text(extra))
    if verbosity <= -2:
        return buf.getvalue()
    flagged = [r for r in report.files if r.findings or r.io_error]
    if len(report.files) > 1 and flagged and verbosity >= 0:
        table = Table(title="files with findings", show_lines=False)
        for col in ("file", "errors", "warnings", "notes"):
            table.add_column(col, justify="left" if col == "file" else "right")
        for r in flagged:
            errs = r.count(Severity.ERROR) + (1 if r.io_error else 0)
            table.add_row(
                r.file, str(errs), str(r.count(Severity.WARNING)), str(r.count(Severity.NOTE))
            )
        con.print(table)
    e, w, n = (report.total(s) for s in (Severity.ERROR, Severity.WARNING, Severity.NOTE))
    e += report.io_errors
    summary = Text(f"{len(report.files)} file{'s' * (len(report.files) != 1)} checked: ")
    summary.append(f"{e} error{'s' * (e != 1)}", style="bold red" if e else "green")
    summary.append(f", {w} warning{'s' * (w != 1)}", style="yellow" if w else "")
    summary.append(f", {n} note{'s' * (n != 1)}")
    con.print(summary)
    return buf.getvalue()
