"""Outputs a batch of programs streams its results into as they arrive, so the client of a
library of 10⁶ programs holds counters and one row group, not every result.

- :class:`ResultTable`: ``cnc check --table FILE``, a Parquet table of every program's result,
  one row per program, written in row groups of :data:`ROWS_PER_GROUP` rows. The columns are
  the same whether the results come from the local pool or a Dask cluster.
- :class:`Counts`: the summary counters of a batch (programs, errors, warnings, I/O errors).
- :class:`LineProgress`: progress on the client: one line redrawn in place on a terminal,
  else one line per N programs (logs of a batch job read well).

pyarrow is imported by :class:`ResultTable` only (the ``parquet`` extra).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field
from importlib.util import find_spec
from typing import Any, TextIO

from cli.formats.base import FileResult
from kernel.diagnostics import Diagnostic, Location, Severity

ROWS_PER_GROUP = 10_000  # rows buffered before a row group is written (a few MiB at most)


def status(result: FileResult) -> str:
    """One word for a program's result: ``io-error``, ``error``, ``warning`` or ``ok``."""
    if result.io_error:
        return "io-error"
    if result.count(Severity.ERROR):
        return "error"
    return "warning" if result.count(Severity.WARNING) else "ok"


@dataclass(slots=True)
class Counts:
    """Summary counters of a batch, updated per result (nothing per program kept)."""

    programs: int = 0
    by_status: dict[str, int] = field(default_factory=dict)
    errors: int = 0
    warnings: int = 0
    seconds: float = 0.0  # summed over programs (worker time)

    def add(self, result: FileResult) -> None:
        """Count ``result``."""
        self.programs += 1
        word = status(result)
        self.by_status[word] = self.by_status.get(word, 0) + 1
        self.errors += result.count(Severity.ERROR)
        self.warnings += result.count(Severity.WARNING)
        self.seconds += result.seconds


def need_pyarrow(path: str) -> None:
    """``IO-PARQUET`` before any work when pyarrow is missing."""
    if find_spec("pyarrow") is None:
        raise Diagnostic(
            "IO-PARQUET",
            "a Parquet table needs pyarrow: pip install 'cnc-toolchain[parquet]'",
            Location(path),
        )


class ResultTable:
    """A Parquet file of one row per program (:meth:`add`), written in row groups as rows
    arrive; :meth:`close` writes the last group (an empty batch gives an empty table).

    Columns: ``program`` (path as given), ``status`` (:func:`status`), ``errors``,
    ``warnings``, ``notes`` (counts), ``rules`` (the rule of each finding, in order),
    ``findings`` (each finding: rule, code, severity, message, line, column), ``io_error``
    (null when the file was read) and ``seconds`` (the check's time on its worker)."""

    def __init__(self, path: str, rows_per_group: int = ROWS_PER_GROUP) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        self._pa = pa
        finding = pa.struct(
            [
                ("rule", pa.string()),
                ("code", pa.string()),
                ("severity", pa.string()),
                ("message", pa.string()),
                ("line", pa.int32()),
                ("column", pa.int32()),
            ]
        )
        self.schema = pa.schema(
            [
                ("program", pa.string()),
                ("status", pa.string()),
                ("errors", pa.int32()),
                ("warnings", pa.int32()),
                ("notes", pa.int32()),
                ("rules", pa.list_(pa.string())),
                ("findings", pa.list_(finding)),
                ("io_error", pa.string()),
                ("seconds", pa.float64()),
            ]
        )
        self._rows: list[dict[str, Any]] = []
        self._per_group = rows_per_group
        self._writer = pq.ParquetWriter(path, self.schema)
        self.rows = 0

    def add(self, result: FileResult) -> None:
        """Buffer the row of ``result``; a full buffer is written as one row group."""
        self._rows.append(
            {
                "program": result.file,
                "status": status(result),
                "errors": result.count(Severity.ERROR),
                "warnings": result.count(Severity.WARNING),
                "notes": result.count(Severity.NOTE),
                "rules": [f.rule for f in result.findings],
                "findings": [
                    {
                        "rule": f.rule,
                        "code": f.code,
                        "severity": f.severity.value,
                        "message": f.message,
                        "line": f.location.line,
                        "column": f.location.column,
                    }
                    for f in result.findings
                ],
                "io_error": result.io_error,
                "seconds": result.seconds,
            }
        )
        self.rows += 1
        if len(self._rows) >= self._per_group:
            self._flush()

    def _flush(self) -> None:
        if self._rows:
            self._writer.write_table(self._pa.Table.from_pylist(self._rows, self.schema))
            self._rows = []

    def close(self) -> None:
        """Write what is buffered and the file's footer."""
        self._flush()
        self._writer.close()


LOG_PROGRESS_FROM = 1000  # programs: a smaller batch logs no progress lines unless -v


def progress_wanted(total: int, verbosity: int, tty: bool | None = None) -> bool:
    """Whether a batch of ``total`` programs shows progress on stderr: never under ``-q`` or
    for one program; on a terminal always; in a log (not a terminal) from
    :data:`LOG_PROGRESS_FROM` programs or under ``-v``, so the reports of small batches read
    by scripts stay as they were."""
    if verbosity < 0 or total <= 1:
        return False
    if tty is None:
        tty = sys.stderr.isatty()
    return tty or verbosity > 0 or total >= LOG_PROGRESS_FROM


class LineProgress:
    """``done/total programs (p %), rate/s, elapsed`` on ``stream`` (stderr): redrawn in
    place at most 10 times a second on a terminal, else one line every ``every`` programs
    (default: every 5 % of the batch, at least 1, at most 10,000) and one at the end."""

    def __init__(
        self,
        total: int,
        label: str = "programs",
        stream: TextIO | None = None,
        every: int | None = None,
        enabled: bool = True,
    ) -> None:
        self.total = total
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.tty = self.stream.isatty()
        self.every = every or max(1, min(10_000, total // 20))
        self.enabled = enabled and total > 0
        self.done = 0
        self._t0 = time.perf_counter()
        self._last = 0.0

    def line(self) -> str:
        """The progress line as it stands."""
        elapsed = time.perf_counter() - self._t0
        rate = self.done / elapsed if elapsed > 0 else 0.0
        pct = 100.0 * self.done / self.total if self.total else 100.0
        return f"{self.done}/{self.total} {self.label} ({pct:.0f} %), {rate:.0f}/s, {elapsed:.1f} s"

    def advance(self, n: int = 1) -> None:
        """``n`` more programs done."""
        self.done += n
        if not self.enabled:
            return
        if self.tty:
            now = time.perf_counter()
            if now - self._last >= 0.1 or self.done >= self.total:
                self._last = now
                self.stream.write(f"\r{self.line()}\x1b[K")
                self.stream.flush()
        elif self.done % self.every == 0 or self.done == self.total:
            self.stream.write(self.line() + "\n")
            self.stream.flush()

    def close(self) -> None:
        """End the in-place line on a terminal (erased: the report follows)."""
        if self.enabled and self.tty:
            self.stream.write("\r\x1b[K")
            self.stream.flush()
