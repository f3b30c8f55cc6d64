"""The compiled fast lane (:mod:`gcode.ngc.lane`) in the Fanuc reader.

A large Fanuc program is mostly blocks like ``G01 X12.5 Y-3.25`` or ``G02 X.. Y.. R..``
that :meth:`gcode.fanuc.executor.Executor._plain` hands straight to the RS274/NGC machine
model. While the main program runs at its top level (no loop, subprogram or macro call)
and nothing makes such a block special (``Executor.plain_ok``: no transform, NURBS, modal
call or lathe; G00-G03 in force; G94; no cutter compensation), the lane scans a run of
them from the file's bytes with the RS274/NGC lane's compiled kernel and machine-state
rules (:func:`gcode.ngc.lane.lane.scan_at`, :func:`~gcode.ngc.lane.lane.advance`). It
takes fewer words than the RS274/NGC lane: no ``N`` (the flow keeps the sequence
number), no A B C (not a plain Fanuc block), and a length (X Y Z I J K R) only with a
decimal point, since one without counts least input increments. Every other block, and
every diagnostic, is the general path's.
"""

from __future__ import annotations

from array import array

import numpy as np

import kernel.limits as limits
from gcode.fanuc.executor import Executor
from gcode.fanuc.program import Source
from gcode.ngc.lane import fastlane
from gcode.ngc.lane.lane import advance, modal_arcs, scan_at
from kernel.diagnostics import Location

#: the words of a block the lane takes
SLOTS = fastlane.slot_table("XYZFGIJKR")
#: the words whose numbers must have a decimal point (lengths)
POINT_SLOTS = sum(1 << fastlane.LETTERS.index(c) for c in "XYZIJKR")
#: the kernel reads numbers of up to this many digits; a smaller --limit digits is the
#: general path's to enforce
KERNEL_DIGITS = 15
#: after a try that took no line, let the general path take this many lines first
_BACKOFF = 8
_MOTIONS = (0, 10, 20, 30)


class FanucLane:
    """The lane over one Fanuc program file held in memory (:class:`Source`)."""

    def __init__(self, src: Source, arcs: bool) -> None:
        self.src = src
        self.arcs = arcs
        self._buf = np.frombuffer(src.lines.data, dtype=np.uint8)
        self._wait = 0
        if not src.lines.indexed:  # the line starts, found here in a pass over the bytes
            starts = np.flatnonzero(self._buf == ord("\n")).astype(np.int64)
            starts += 1
            src.lines.index(array("q", np.concatenate((np.zeros(1, np.int64), starts)).tobytes()))

    @staticmethod
    def for_source(src: Source, arcs: bool = False) -> FanucLane | None:
        """A lane over ``src`` (None where no kernels can load, or where the digit limit
        is below what the kernel reads); ``arcs``: its runs may hold G02/G03 arcs."""
        if limits.current().digits < KERNEL_DIGITS:
            return None
        try:
            fastlane.kernel_mode()
        except ImportError:
            return None
        return FanucLane(src, arcs)

    def take(self, ex: Executor, index: int) -> fastlane.Run | None:
        """The run of plain blocks from line ``index`` (0-based) of the main program, with
        the executor's state advanced past it; None where the general path runs the line."""
        if self._wait:
            self._wait -= 1
            return None
        ip = ex.ip
        if (
            ex.lathe is not None
            or ex.nurbs is not None
            or ex.modal_call is not None
            or ex.motion not in _MOTIONS
            or ex.group01 != ex.motion
            or ip.s.motion_mode != ex.motion
            or not ex.plain_ok
        ):
            return None
        arcs = modal_arcs(ip, self.arcs)
        if arcs is None:
            return None
        src = self.src
        start = src.lines.starts[index]
        run = scan_at(ip, self._buf, start, index + 1, arcs, False, SLOTS, POINT_SLOTS)
        if not run.lines:
            self._wait = _BACKOFF
            return None
        advance(ip, run)
        ex.motion = ex.group01 = ip.s.motion_mode
        if len(run):
            ex.last_comment = None  # a block without a comment ran
        ip.loc = Location(src.path, index + run.lines, 1)
        return run
