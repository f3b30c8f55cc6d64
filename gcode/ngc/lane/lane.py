"""The interpreter's use of the compiled fast lane (:mod:`gcode.ngc.lane.fastlane`) for large files.

Runs of plain CAM lines (axis words, F, G0/G1, N) are scanned straight from the file's
bytes by compiled code while the modal state is simple (top level of the main file, G94,
G0 or G1, no cutter compensation, no lathe diameter mode). Everything else, and every
diagnostic, stays with the general interpreter.
"""

from __future__ import annotations

import numpy as np

from gcode.core.program import ProgramFile
from gcode.core.state import PER_MINUTE
from gcode.ngc.context import NgcContext
from gcode.ngc.lane import fastlane
from kernel.diagnostics import Location

#: after a try that took no line, let the general path take this many lines first
_BACKOFF = 8


class Lane:
    """The fast lane over one program file, read in windows of whole lines (bounded memory)."""

    WINDOW = 1 << 20

    def __init__(self, pf: ProgramFile) -> None:
        self.pf = pf
        self._fh = open(pf.path, "rb")  # noqa: SIM115 - closed by close()
        self._start = 0  # file offset of the window
        self._data = b""
        self._buf = np.frombuffer(self._data, dtype=np.uint8)
        self._eof = False
        self._wait = 0

    @staticmethod
    def for_file(pf: ProgramFile) -> Lane | None:
        """A lane for ``pf`` (None if the file cannot be opened or no kernels can load)."""
        try:
            fastlane.kernel_mode()
            return Lane(pf)
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
        s = ctx.s
        flow = ctx.flow
        comp = ctx.comp
        if (
            flow.file is not self.pf
            or flow.calls
            or flow.controls
            or not flow.seen_line
            or s.feed_mode != PER_MINUTE
            or s.motion_mode not in (0, 10)
            or s.diameter_mode
            or (comp is not None and (comp.on or comp.holding))
        ):
            return None
        pf = self.pf
        start = self._window(pf._offset)
        run = fastlane.scan(
            self._buf,
            start,
            s.pos,
            s.feed_rate,
            incremental=not s.absolute,
            traverse=s.motion_mode == 0,
            first_line=pf.line + 1,
        )
        if not run.lines:
            self._wait = _BACKOFF
            return None
        pf.seek_to(self._start + start + run.consumed, pf.line + run.lines)
        s.pos = list(run.end_position)
        s.feed_rate = run.end_feed
        s.motion_mode = 0 if run.end_traverse else 10
        if len(run):
            s.tlo_lag = None
        ctx.loc = Location(pf.path, pf.line, 1)
        return run
