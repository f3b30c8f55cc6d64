"""Resource limits: what keeps a hostile or broken program from running away.

Each limit has a stable code (``LIMIT-*``, docs/errors.md), is reported at the line that
reaches it, and has a default no real program comes near (docs/reliability.md says why each
default is safe). They are process-wide settings: the CLI sets them from the machine
profile's ``[limits]`` table and ``--limit NAME=VALUE`` (:func:`configure`) before reading a
program; the readers and the kernel read :func:`current`.

A leaf module: the front ends and the kernel import it, it imports only diagnostics.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, fields, replace

from kernel.diagnostics import Diagnostic, Location


@dataclass(frozen=True)
class Limits:
    """The limits of one run (defaults: far beyond any real program, well within memory and
    Python's recursion limit)."""

    #: digits in one number (G-code words, parameters, canonical text, Part 21): CAM output
    #: has at most ~20; 100 keeps every value finite (below 1e100) and far from Python's
    #: 4,300-digit integer conversion limit
    digits: int = 100
    #: brackets, functions and unary signs nested in one expression (parser recursion)
    nesting: int = 64
    #: depth of one expression's tree, chained binary operators included (evaluation)
    expression_depth: int = 256
    #: passes, pecks and repeats one canned-cycle block or generated operation may produce
    cycle_passes: int = 100_000
    #: passes of one loop in a row (per entry into it) in every dialect's flow control: an
    #: endless loop that moves ends in about a second of CPU
    loop_passes: int = 100_000
    #: passes of all loops of one run together (nested loops multiply: eight nested loops
    #: of 1,000 passes each would run for ever, each loop within ``loop_passes``)
    loop_total: int = 1_000_000
    #: interpolation samples of one move (a move longer than this at the machine's period)
    samples_per_move: int = 50_000_000
    #: chords one arc becomes in the Grbl model (each a row of the segment table)
    arc_chords: int = 1_000_000
    #: full turns of one arc that cnc convert writes as blocks of their own, for a control
    #: without a turns word (Fanuc, Haas, Grbl, 840D): each is a written and re-read block
    arc_turns: int = 10_000
    #: control points of one NURBS curve
    nurbs_points: int = 100_000
    #: characters in one line of a G-code program (rs274 reads 256; CAM writes under 300):
    #: a 100 MB line would be decoded, lower-cased and split whole, several copies of it
    line_chars: int = 1_000_000
    #: toolpath passes (lines, rings, levels) one STEP-NC operation may generate
    toolpath_passes: int = 1_000_000
    #: CPU seconds per program in batch commands (cnc check and cnc run); 0: no limit
    seconds: float = 0.0


_current = Limits()
NAMES = tuple(f.name for f in fields(Limits))


def current() -> Limits:
    """The limits in force."""
    return _current


def configure(**values: float) -> Limits:
    """Set some limits by name (the rest keep their value); returns the new limits."""
    global _current
    bad = [k for k in values if k not in NAMES]
    if bad:
        raise Diagnostic(
            "LIMIT-CONFIG", f"unknown limit {', '.join(bad)}; known: {', '.join(NAMES)}"
        )
    typed: dict[str, float | int] = {}
    for f in fields(Limits):
        if f.name in values:
            v = values[f.name]
            if not v < math.inf or v < 0 or (f.name != "seconds" and v < 1):  # NaN too
                raise Diagnostic("LIMIT-CONFIG", f"limit {f.name} must be >= 1, not {v}")
            typed[f.name] = float(v) if f.name == "seconds" else int(v)
    _current = replace(_current, **typed)
    return _current


def reset() -> None:
    """Back to the defaults (tests)."""
    global _current
    _current = Limits()


_LONG_RUNS: dict[int, re.Pattern[str]] = {}


def check_digits(text: str, file: str | None = None, line: int = 0, col0: int = 1) -> None:
    """``LIMIT-DIGITS`` at the first run of more than ``digits`` digits in ``text`` (one
    line, whose first character is at column ``col0``). Cheap: lines shorter than the limit
    are not scanned."""
    limit = _current.digits
    if len(text) <= limit:
        return
    pattern = _LONG_RUNS.get(limit)
    if pattern is None:
        pattern = _LONG_RUNS[limit] = re.compile(r"\d{" + str(limit + 1) + ",}")
    m = pattern.search(text)
    if m is not None:
        raise Diagnostic(
            "LIMIT-DIGITS",
            f"a number of {m.end() - m.start()} digits (limit {limit}, --limit digits=N)",
            Location(file, line, col0 + m.start()) if line else Location(file),
        )


def check_line(length: int, file: str | None, line: int) -> None:
    """``LIMIT-LINE`` when line ``line`` of ``file`` is ``length`` characters (bytes) long,
    more than the ``line_chars`` limit, before it is decoded and parsed."""
    limit = _current.line_chars
    if length > limit:
        raise Diagnostic(
            "LIMIT-LINE",
            f"a line of {length:,} characters (limit {limit:,}, --limit line_chars=N)",
            Location(file, line, limit + 1),
        )


def check_lines(data: bytes | str, file: str | None) -> None:
    """:func:`check_line` for every line of a program read whole (Fanuc, 840D, the Sandia
    lane): ``LIMIT-LINE`` at the first line longer than ``line_chars``. A program no longer
    than the limit cannot hold such a line and is not scanned."""
    limit = _current.line_chars
    if len(data) <= limit:
        return
    import numpy as np  # only for a program larger than the limit

    raw = data if isinstance(data, bytes) else data.encode("utf-8", "surrogatepass")
    buf = np.frombuffer(raw, dtype=np.uint8)
    ends = np.flatnonzero(buf == 10)
    stops = np.append(ends, len(raw))
    starts = np.concatenate(([0], ends + 1))
    lengths = stops - starts
    crlf = (stops > starts) & (buf[np.maximum(stops - 1, 0)] == 13)
    lengths -= crlf
    long = np.flatnonzero(lengths > limit)
    if long.size:
        check_line(int(lengths[long[0]]), file, int(long[0]) + 1)


def nesting_error(file: str | None, line: int, column: int) -> Diagnostic:
    """``LIMIT-NESTING``: an expression nested deeper than the limits allow."""
    lim = _current
    return Diagnostic(
        "LIMIT-NESTING",
        f"expression nested too deeply (limits: {lim.nesting} brackets, functions or signs, "
        f"{lim.expression_depth} levels with operators)",
        Location(file, line, column),
    )


def count_error(what: str, count: float, limit: int, name: str, loc: Location) -> Diagnostic:
    """``LIMIT-COUNT``: a block or operation would generate ``count`` items of ``what``."""
    return Diagnostic(
        "LIMIT-COUNT",
        f"{what}: {count:.6g} would be generated (limit {limit}, --limit {name}=N)",
        loc,
    )
