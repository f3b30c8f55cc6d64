"""The compiled read-back lane of the Sandia generic language (issue 15).

``cnc convert --to sandia`` reads its output back to verify it (cli.verify), and that output
is millions of lines: every arc becomes ``MoveTo`` chords within the tolerance, about eleven
lines per source line of a CAM program. Read by :class:`gcode.sandia.reader.Reader` they
cost microseconds each (a command object and its location per line). Here the lines the
writer emits by the million, ``MoveTo X= Y= Z=``, ``SetSpeed v`` and
``point_to_point_positioning ... attributes=ABSOLUTE|CS_CURRENT``, are scanned from the
file's bytes by a compiled kernel (:mod:`gcode.sandia.lane_kernels`, built once through
:mod:`kernel.aot`) into the fast lane's arrays (:class:`gcode.ngc.lane.fastlane.Run`), as the
reader would read them: the same commands, positions, speeds and source lines. Every other
line (units, tools, comments, indented or malformed lines, a move without a speed) goes to
the general reader, which owns every diagnostic.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any, Protocol

import numpy as np

from gcode.ngc.lane.fastlane import Run
from kernel import aot
from kernel.ir import canon

#: the compiled kernel (kernel.aot: built once into the user's cache, JIT fallback)
KERNELS = aot.Kernels(
    "gcode.sandia.lane_kernels", "_sandia_aot", "Sandia read-back kernel", "CNC_SANDIA_JIT"
)
#: events per run at most (the kernel's arrays are sized for it)
MAX_EVENTS = 1 << 16
#: after a try that took no line, let the general reader take this many lines first
_BACKOFF = 8
_WORDS = np.frombuffer(
    b"\0".join(
        (
            b"MoveTo",
            b"SetSpeed",
            b"point_to_point_positioning",
            b"speed=",
            b"attributes=",
            b"ABSOLUTE|CS_CURRENT",
            b"",
        )
    ),
    dtype=np.uint8,
)


class LineReader(Protocol):
    """What the lane needs of :class:`gcode.sandia.reader.Reader`: its state (position,
    speed, current line) and its per-line reading."""

    pos: list[float]
    speed: float | None
    line: int
    ended: bool

    def preamble(self) -> Iterator[canon.Command]: ...

    def body(self, numbered: Iterable[tuple[int, str]]) -> Iterator[canon.Command]: ...


def kernels() -> Any:
    """The kernel module (AOT or JIT); ImportError where neither loads."""
    return KERNELS.module()


def scan(
    buf: np.ndarray, start: int, pos: list[float], speed: float | None, first_line: int
) -> tuple[Run, bool]:
    """The run of lane lines from byte ``start`` of ``buf`` (a line start) with the
    reader's position and speed before it, and whether it read a SetSpeed."""
    kind, position, feed, line, end, line_no, cur, speed_after, set_any = kernels().scan(
        buf,
        int(start),
        np.array(pos, dtype=np.float64),
        float(speed or 0.0),
        int(first_line),
        MAX_EVENTS,
        _WORDS,
    )
    run = Run(
        kind,
        position,
        feed,
        line,
        int(end - start),
        int(line_no - first_line),
        tuple(cur.tolist()),
        float(speed_after),
        False,
    )
    return run, bool(set_any)


def chunks(reader: LineReader, data: bytes) -> Iterator[canon.Command | Run]:
    """The program ``data`` (its bytes, lines ended by LF only) read by ``reader``: runs of
    lane lines as :class:`Run` arrays, every other line through ``reader.body``."""
    yield from reader.preamble()
    buf = np.frombuffer(data, dtype=np.uint8)
    size = len(data)
    at, line, wait = 0, 1, 0
    while at < size:
        if wait:
            wait -= 1
        else:
            run, set_speed = scan(buf, at, reader.pos, reader.speed, line)
            if run.lines:
                reader.pos = list(run.end_position)
                if set_speed:
                    reader.speed = run.end_feed
                at += run.consumed
                line += run.lines
                reader.line = line - 1
                if len(run):
                    yield run
                continue
            wait = _BACKOFF
        end = data.find(b"\n", at)
        end = size if end < 0 else end + 1
        yield from reader.body(((line, data[at:end].decode("utf-8", errors="replace")),))
        if reader.ended:
            return
        at, line = end, line + 1
