"""What ``cnc run`` makes of a batch's per-program results, in one place for every way the
batch ran (one process, ``--jobs``, ``--scheduler``, ``--resume``): the progress it shows,
the summary table, and the files of the output folder besides the per-program reports.

- ``index.html``: one row per program (status, cycle time as m:ss, findings, the worst
  finding or the error, a link to its report), sortable by clicking a column's header,
  with a total row; self-contained (inline CSS and a few lines of script, nothing fetched).
- ``summary.json``: schema ``cnc-run-summary`` version 1, per program and totals
  (``docs/run-and-machine.md``; seconds stay numbers, ``..._hms`` strings are their m:ss).
- ``junit.xml``: one test case per program; a program with errors is a ``<failure>``, one
  that could not be read an ``<error>``; warnings and notes go to ``<system-out>``.

Progress: a bar with the elapsed time and an estimate of the time left on a terminal; one
line per program as it finishes otherwise (logs, CI); nothing under ``-q``.
"""

from __future__ import annotations

import json
import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from html import escape
from typing import Any
from urllib.parse import quote

from rich.console import Console
from rich.markup import escape as markup_escape
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)
from rich.table import Table

from cli.excerpt import render_line
from cli.main import verbosity
from cli.outputs import open_output
from cli.pipeline import RunResult
from kernel.report.clock import clock, fixed

SUMMARY_SCHEMA = "cnc-run-summary"
SUMMARY_VERSION = 1
INDEX, SUMMARY, JUNIT = "index.html", "summary.json", "junit.xml"
STATUSES = ("ok", "findings", "error", "io-error")
_CODE = re.compile(r"\b(?:error|warning|note)\[([A-Za-z0-9_./-]+)\]")


def batch_files(out_dir: str) -> list[str]:
    """The batch's own files in ``out_dir`` (besides the per-program reports)."""
    return [os.path.join(out_dir, n) for n in (INDEX, SUMMARY, JUNIT)]


def error_code(message: str) -> str:
    """The diagnostic code of a one-line diagnostic (``file:1:2: error[CODE]: ...``; of a
    check finding ``error[RULE/CODE]``, the code)."""
    m = _CODE.search(message)
    return m.group(1).rsplit("/", 1)[-1] if m else "error"


def _cycle_known(r: RunResult) -> bool:
    """Whether the row's cycle time is the program's (it was planned and measured)."""
    return r.measured and r.status in ("ok", "findings")


# ------------------------------------------------------------------------- progress


class BatchProgress:
    """The batch's progress: a rich bar with ETA on a terminal, else one line per finished
    program on ``console`` (stderr), nothing when ``quiet``."""

    def __init__(self, total: int, console: Console, quiet: bool) -> None:
        self.total, self.console, self.quiet = total, console, quiet
        self.done = 0
        self.bar: Progress | None = None
        self.task = TaskID(0)

    def __enter__(self) -> BatchProgress:
        if self.console.is_terminal and not self.quiet:
            self.bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                TextColumn("ETA"),
                TimeRemainingColumn(),
                console=self.console,
                transient=True,
            )
            self.bar.__enter__()
            self.task = self.bar.add_task("programs", total=self.total)
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.__exit__(None, None, None)

    @contextmanager
    def servo(self, program: str) -> Iterator[Callable[[int, int], None] | None]:
        """A ``tick(done, total)`` following one program's servo samples on the bar (one
        job on a terminal), else None."""
        bar = self.bar
        if bar is None:
            yield None
            return
        sub = bar.add_task(f"  {os.path.basename(program)}: servo samples", total=None)

        def tick(done: int, total: int) -> None:
            bar.update(sub, completed=done, total=total)

        try:
            yield tick
        finally:
            bar.remove_task(sub)

    def finished(self, r: RunResult) -> None:
        """One program is done: advance the bar, or print its line."""
        self.done += 1
        if self.bar is not None:
            self.bar.advance(self.task)
            return
        if self.quiet:
            return
        width = len(str(self.total))
        what = "-"
        if _cycle_known(r):
            what = clock(r.cycle_time)
        elif r.message:
            what = error_code(r.message)
        self.console.print(
            f"[{self.done:>{width}}/{self.total}] {r.status:<8} {what:>9}  {r.file}",
            markup=False,
            highlight=False,
            soft_wrap=True,
        )


# ---------------------------------------------------------------------- text table

_STYLE = {"ok": "green", "findings": "yellow", "error": "bold red", "io-error": "bold red"}


def print_summary(results: list[RunResult], console: Console, seconds: float) -> None:
    """The summary table (a row per program and a total row), the first error of each
    program with one, and the one-line count."""
    t = Table(title=f"cnc run: {len(results)} program{'s' * (len(results) != 1)}")
    heads = (
        "program",
        "status",
        "cycle [m:s]",
        "samples",
        "follow [µm]",
        "contour [µm]",
        "errors",
        "warnings",
    )
    for col in heads:  # names and codes fold rather than lose their end to an ellipsis
        t.add_column(
            markup_escape(col),
            justify="left" if col in heads[:2] else "right",
            overflow="fold",
        )
    for r in results:
        known = _cycle_known(r)
        cycle = clock(r.cycle_time) if known else f"[red]{error_code(r.message)}[/]"
        if not known and not r.message:
            cycle = "-"
        t.add_row(
            markup_escape(os.path.basename(r.file)),
            f"[{_STYLE[r.status]}]{r.status}[/]",
            cycle,
            str(r.samples) if known else "-",
            fixed(r.following_error * 1000, 2) if known else "-",
            fixed(r.contour_error * 1000, 2) if known else "-",
            str(r.errors),
            str(r.warnings),
        )
    tot = totals(results)
    t.add_section()
    t.add_row(
        "total",
        f"{tot['status']['ok']}/{len(results)} ok",
        clock(tot["cycle_seconds"]),
        str(sum(r.samples for r in results if _cycle_known(r))),
        fixed(max((r.following_error for r in results if _cycle_known(r)), default=0) * 1000, 2),
        fixed(max((r.contour_error for r in results if _cycle_known(r)), default=0) * 1000, 2),
        str(tot["findings"]["error"]),
        str(tot["findings"]["warning"]),
    )
    console.print(t)
    for r in results:
        if r.message:
            console.print(render_line(r.message, verbosity()), markup=False, highlight=False)
    bad = sum(1 for r in results if r.status != "ok")
    console.print(
        f"{len(results) - bad} ok, {bad} with problems, in {clock(seconds)}", highlight=False
    )


# ---------------------------------------------------------------------- summary.json


def totals(results: list[RunResult]) -> dict[str, Any]:
    """The batch's totals: programs per status, the sum of the known cycle times, findings
    per severity and the seconds spent on the programs."""
    cycle = sum(r.cycle_time for r in results if _cycle_known(r))
    stages: dict[str, float] = {}
    for r in results:
        for k, v in r.stages.items():
            stages[k] = stages.get(k, 0.0) + v
    return {
        "programs": len(results),
        "status": {s: sum(1 for r in results if r.status == s) for s in STATUSES},
        "cycle_seconds": cycle,
        "cycle_hms": clock(cycle),
        "findings": {
            "error": sum(r.errors for r in results),
            "warning": sum(r.warnings for r in results),
            "note": sum(r.notes for r in results),
        },
        "seconds": sum(r.seconds for r in results),
        "stages": stages,
    }


def _link(r: RunResult, html: bool) -> str | None:
    """The file name (in the output folder) of the program's report: its HTML page when
    one was asked for and written, else its JSON report; None when there is none."""
    if not r.report:
        return None
    page = r.report.removesuffix(".json") + ".html"
    for f in (page, r.report) if html else (r.report,):
        if os.path.exists(f):
            return os.path.basename(f)
    return None


def program_row(r: RunResult, html: bool) -> dict[str, Any]:
    """One program of ``summary.json``."""
    known = _cycle_known(r)
    return {
        "program": r.file,
        "report": _link(r, False),
        "page": _link(r, html),
        "status": r.status,
        "cycle_seconds": r.cycle_time if known else None,
        "cycle_hms": clock(r.cycle_time) if known else None,
        "findings": {"error": r.errors, "warning": r.warnings, "note": r.notes},
        "worst": r.worst or None,
        "error": r.message if r.status in ("error", "io-error") and r.message else None,
        "samples": r.samples,
        "following_error": r.following_error,
        "contour_error": r.contour_error,
        "seconds": r.seconds,
        "stages": r.stages,
    }


def summary_doc(
    results: list[RunResult], machine: str, seconds: float, html: bool
) -> dict[str, Any]:
    """``summary.json``: the programs in the order given and their totals."""
    return {
        "schema": SUMMARY_SCHEMA,
        "version": SUMMARY_VERSION,
        "machine": machine,
        "wall_seconds": seconds,
        "programs": [program_row(r, html) for r in results],
        "totals": totals(results),
    }


# ------------------------------------------------------------------------ index.html

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em;color:#222}
h1{font-size:1.4em}table{border-collapse:collapse}td,th{border:1px solid #ccc;
padding:.25em .6em;text-align:left;vertical-align:top}th{background:#f3f3f3;cursor:pointer;
user-select:none}td.num{text-align:right;font-variant-numeric:tabular-nums}
tfoot td{font-weight:bold;background:#fafafa}
.ok{color:#176f2c}.findings{color:#9a6700}.error,.io-error{color:#b42318;font-weight:bold}
"""

# click a header to sort by that column (numbers by data-sort), again to reverse it
_SCRIPT = """
document.querySelectorAll("th").forEach(function(th, col){
  th.addEventListener("click", function(){
    var body = th.closest("table").tBodies[0];
    var rows = Array.prototype.slice.call(body.rows);
    var dir = th.dataset.dir === "asc" ? -1 : 1;
    th.dataset.dir = dir === 1 ? "asc" : "desc";
    rows.sort(function(a, b){
      var x = a.cells[col].dataset.sort || a.cells[col].textContent;
      var y = b.cells[col].dataset.sort || b.cells[col].textContent;
      var nx = parseFloat(x), ny = parseFloat(y);
      if (!isNaN(nx) && !isNaN(ny)) return dir * (nx - ny);
      return dir * x.localeCompare(y);
    });
    rows.forEach(function(r){ body.appendChild(r); });
  });
});
"""


def render_index(results: list[RunResult], machine: str, seconds: float, html: bool) -> str:
    """``index.html`` of a batch."""
    head = ["program", "status", "cycle [m:s]", "errors", "warnings", "notes", "worst finding"]
    rank = {s: i for i, s in enumerate(STATUSES)}
    rows = []
    for r in results:
        link = _link(r, html)
        name = escape(r.file)
        cell = f'<a href="{escape(quote(link))}">{name}</a>' if link else name
        known = _cycle_known(r)
        cycle = clock(r.cycle_time) if known else "-"
        if not known and r.message:
            cycle = escape(error_code(r.message))
        sort = f"{r.cycle_time:.6f}" if known else "-1"
        status = escape(r.status)
        rows.append(
            "<tr>"
            f"<td>{cell}</td>"
            f'<td class="{status}" data-sort="{rank[r.status]}">{status}</td>'
            f'<td class="num" data-sort="{sort}">{cycle}</td>'
            f'<td class="num">{r.errors}</td><td class="num">{r.warnings}</td>'
            f'<td class="num">{r.notes}</td>'
            f"<td>{escape(r.worst)}</td>"
            "</tr>"
        )
    tot = totals(results)
    foot = (
        f"<tr><td>total: {len(results)} programs</td>"
        f"<td>{tot['status']['ok']} ok</td>"
        f'<td class="num">{clock(tot["cycle_seconds"])}</td>'
        f'<td class="num">{tot["findings"]["error"]}</td>'
        f'<td class="num">{tot["findings"]["warning"]}</td>'
        f'<td class="num">{tot["findings"]["note"]}</td><td></td></tr>'
    )
    counts = ", ".join(f"{n} {s}" for s, n in tot["status"].items() if n)
    return (
        "\n".join(
            [
                "<!DOCTYPE html>",
                '<html lang="en"><head><meta charset="utf-8">',
                f"<title>cnc run: {len(results)} programs</title>",
                f"<style>{_CSS}</style></head><body>",
                f"<h1>cnc run: {len(results)} program{'s' * (len(results) != 1)}</h1>",
                f"<p>machine: {escape(machine)} &middot; {escape(counts)} &middot; "
                f"total cycle time {clock(tot['cycle_seconds'])} &middot; "
                f"batch wall time {clock(seconds)}</p>",
                "<table><thead><tr>",
                "".join(f"<th>{escape(h)}</th>" for h in head),
                "</tr></thead><tbody>",
                *rows,
                f"</tbody><tfoot>{foot}</tfoot></table>",
                f"<script>{_SCRIPT}</script>",
                "</body></html>",
            ]
        )
        + "\n"
    )


# ------------------------------------------------------------------------ junit.xml


def render_junit(results: list[RunResult], seconds: float) -> str:
    """``junit.xml``: one suite, one test case per program."""
    root = ET.Element("testsuites", name="cnc run")
    suite = ET.SubElement(root, "testsuite", name="cnc run")
    failures = errors = 0
    for r in results:
        case = ET.SubElement(
            suite,
            "testcase",
            name=r.file,
            classname=os.path.dirname(r.file) or ".",
            time=f"{r.seconds:.3f}",
        )
        text = r.message or r.worst
        if r.status == "io-error":
            ET.SubElement(case, "error", type=error_code(text), message=text).text = text
            errors += 1
        elif r.status in ("error", "findings"):
            ET.SubElement(case, "failure", type=error_code(text), message=text).text = text
            failures += 1
        elif r.worst:
            ET.SubElement(case, "system-out").text = r.worst
    for el in (suite, root):
        el.set("tests", str(len(results)))
        el.set("failures", str(failures))
        el.set("errors", str(errors))
        el.set("time", f"{seconds:.3f}")
    suite.set("skipped", "0")
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_batch(
    results: list[RunResult], out_dir: str, machine: str, seconds: float, html: bool
) -> None:
    """Write ``index.html``, ``summary.json`` and ``junit.xml`` into ``out_dir`` (each
    renamed into place when complete; the caller has refused existing ones)."""
    with open_output(os.path.join(out_dir, SUMMARY)) as fh:
        json.dump(summary_doc(results, machine, seconds, html), fh, indent=2)
    with open_output(os.path.join(out_dir, INDEX)) as fh:
        fh.write(render_index(results, machine, seconds, html))
    with open_output(os.path.join(out_dir, JUNIT)) as fh:
        fh.write(render_junit(results, seconds))


__all__ = [
    "BatchProgress",
    "batch_files",
    "error_code",
    "print_summary",
    "render_index",
    "render_junit",
    "summary_doc",
    "totals",
    "write_batch",
]
