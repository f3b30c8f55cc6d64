"""The interpreter's use of the compiled fast lane (:mod:`gcode.ngc.lane.fastlane`) for large files.

Runs of plain CAM lines (axis words, F, G0/G1, N) are scanned straight from the file's
bytes by compiled code while the modal state is simple (top level of the main file, G94,
G0 or G1, no cutter compensation, no lathe diameter mode). A lane opened with ``arcs``
also takes G2/G3 lines in centre and radius format (and a bare G0/G1) for a consumer that reads
``ARC_FEED`` events from a run (``Run.commands``, ``fastlane.events_text``). Everything else,
and every diagnostic, stays with the general interpreter.
"""

from __future__ import annotations

import numpy as np

from gcode.core.arcs import (
    R_REACH_INCH,
    R_REACH_MM,
    RADIUS_TOLERANCE_INCH,
    RADIUS_TOLERANCE_MM,
    ZERO_RADIUS_INCH,
    ZERO_RADIUS_MM,
)
from gcode.core.program import ProgramFile
from gcode.core.state import PER_MINUTE
from gcode.ngc.context import NgcContext
from gcode.ngc.lane import fastlane
from kernel.diagnostics import Location
from kernel.ir.canon import Plane, Units

#: after a try that took no line, let the general path take this many lines first
_BACKOFF = 8
_PLANE_NAMES = {Plane.XY: "XY", Plane.XZ: "XZ", Plane.YZ: "YZ"}
_LINES = (0, 10)
_LINES_AND_ARCS = (0, 10, 20, 30)


class Lane:
    """The fast lane over one program file, read in windows of whole lines (bounded memory)."""

    WINDOW = 1 << 20

    def __init__(self, pf: ProgramFile, arcs: bool = False) -> None:
        self.pf = pf
        self.arcs = arcs
        self._fh = open(pf.path, "rb")  # noqa: SIM115 - closed by close()
        self._start = 0  # file offset of the window
        self._data = b""
        self._buf = np.frombuffer(self._data, dtype=np.uint8)
        self._eof = False
        self._wait = 0

    @staticmethod
    def for_file(pf: ProgramFile, arcs: bool = False) -> Lane | None:
        """A lane for ``pf`` (None if the file cannot be opened or no kernels can load);
        ``arcs``: its runs may hold arcs and bare G0/G1 moves."""
        try:
            fastlane.kernel_mode()
            return Lane(pf, arcs)
        except (OSError, ImportError):
            return None

    def close(self) -> None:
        self._fh.close()

    def _window(self, offset: int) -> int:
        """Make the window hold whole lines from ``offset``; the offset inside it."""
        end = self._start + len(self._data)
        if self._start <= offset and (end - offset > self.WINDOW // 4 or self._eof):
            return offset - self._start
        self._fh.seek(offset)
        data = self._fh.read(self.WINDOW)
        self._eof = len(data) < self.WINDOW
        if not self._eof:
            cut = data.rfind(b"\n") + 1
            data = data[:cut] if cut else data
        self._start, self._data = offset, data
        self._buf = np.frombuffer(data, dtype=np.uint8)
        return 0

    def take(self, ctx: NgcContext) -> fastlane.Run | None:
        """Scan the plain lines at the current position; advance the file past them."""
        if self._wait:
            self._wait -= 1
            return None
        flow = ctx.flow
        if flow.file is not self.pf or flow.calls or flow.controls or not flow.seen_line:
            return None
        if not ctx.lane_open():
            return None
        arcs = modal_arcs(ctx, self.arcs)
        if arcs is None:
            return None
        pf = self.pf
        start = self._window(pf._offset)
        run = scan_at(ctx, self._buf, start, pf.line + 1, arcs, self.arcs)
        if not run.lines:
            self._wait = _BACKOFF
            return None
        pf.seek_to(self._start + start + run.consumed, pf.line + run.lines)
        advance(ctx, run)
        ctx.loc = Location(pf.path, pf.line, 1)
        return run


def modal_arcs(ctx: NgcContext, arcs: bool) -> bool | None:
    """None where the machine's modes keep the lane off (a motion mode other than G0 or G1,
    G2 or G3 with ``arcs``; not G94; cutter compensation; lathe diameter mode); else
    whether the run may hold arcs (not the first move after G40, which must be straight:
    comp.check_arc_allowed)."""
    s = ctx.s
    comp = ctx.comp
    if (
        s.feed_mode != PER_MINUTE
        or s.motion_mode not in (_LINES_AND_ARCS if arcs else _LINES)
        or s.diameter_mode
        or (comp is not None and (comp.on or comp.holding))
    ):
        return None
    arcs = arcs and (comp is None or not comp.arc_not_allowed)
    if s.motion_mode not in _LINES and not arcs:
        return None
    return arcs


def scan_at(
    ctx: NgcContext,
    buf: np.ndarray,
    start: int,
    first_line: int,
    arcs: bool,
    bare: bool,
    slots: np.ndarray | None = None,
    point_slots: int = 0,
) -> fastlane.Run:
    """The run of plain lines at byte ``start`` of ``buf`` (line ``first_line``) from the
    machine state of ``ctx`` (:func:`fastlane.scan`; ``slots`` and ``point_slots`` as
    there)."""
    s = ctx.s
    inches = s.units is Units.INCHES
    return fastlane.scan(
        buf,
        start,
        s.pos,
        s.feed_rate,
        incremental=not s.absolute,
        traverse=s.motion_mode == 0,
        first_line=first_line,
        motion=s.motion_mode,
        arcs=arcs,
        bare=bare,
        plane=_PLANE_NAMES[s.plane],
        arc_tolerance=(
            (RADIUS_TOLERANCE_INCH, ZERO_RADIUS_INCH, R_REACH_INCH)
            if inches
            else (RADIUS_TOLERANCE_MM, ZERO_RADIUS_MM, R_REACH_MM)
        ),
        ijk_absolute=s.ijk_absolute,
        slots=slots,
        point_slots=point_slots,
    )


def advance(ctx: NgcContext, run: fastlane.Run) -> None:
    """The machine state after ``run``, as the general path leaves it after its lines
    (gcode.ngc.motion: position, feed rate, motion mode, the tool length offset applied,
    a straight move made since G40)."""
    s = ctx.s
    comp = ctx.comp
    s.pos = list(run.end_position)
    s.feed_rate = run.end_feed
    s.motion_mode = run.end_motion
    if len(run):
        s.tlo_lag = None
        if comp is not None and bool((run.kind != fastlane.SET_FEED).any()):
            comp.arc_not_allowed = False  # a straight move was made (motion.feed)
