"""The compiled fast lane (:mod:`gcode.ngc.lane`) in the Siemens 840D reader.

``cnc convert`` reads its 840D output back to verify it (cli.verify). That output is mostly
blocks like ``X12.5 Y-3.25``, ``G1 Z-0.5`` or ``G2 X17.28 Y0.24 I2.2 J0``, which the reader's
plain-block path (:mod:`gcode.siemens.fastpath`, then ``Executor.execute_words``) turns into
the same motions the RS274/NGC machine model would: absolute or incremental (G90/G91) end
points, an F word emitting ``SET_FEED_RATE`` before the block's motion, G2/G3 centres
incremental from the start with LinuxCNC's radius check (gcode.siemens.arcs). While the main
program runs at its top level (no subprogram, control structure or section repetition) and
nothing makes such a block special (:meth:`SiemensLane.take`: G0-G3 in force, G94, no G70
feed conversion, no DIAMON, no rotated/scaled/mirrored frame, no modal call), the lane scans
a run of them from the file's bytes with the RS274/NGC lane's compiled kernel
(:func:`gcode.ngc.lane.fastlane.scan`).

It takes fewer lines than the RS274/NGC lane, only those the 840D reads as plain blocks:
upper-case X Y Z F G I J K words (no N, no rotary axes, no R), each number right after its
letter and each word ended by a blank or the line's end (the kernel also reads ``X 1.5`` and
``G1X1``, which the 840D reads otherwise or refuses), a G word only beside an axis word (a
bare ``G1`` moves nowhere on the 840D, where RS274/NGC moves to the current point). Every
other block, and every diagnostic, is the general path's.
"""

from __future__ import annotations

from array import array

import numpy as np

import kernel.limits as limits
from gcode.core.arcs import (
    R_REACH_INCH,
    R_REACH_MM,
    RADIUS_TOLERANCE_INCH,
    RADIUS_TOLERANCE_MM,
    ZERO_RADIUS_INCH,
    ZERO_RADIUS_MM,
)
from gcode.ngc.lane import fastlane
from gcode.siemens.machine import Machine
from gcode.siemens.program import Program
from kernel.diagnostics import Location
from kernel.ir.canon import Units

#: the words a block the lane takes may hold: upper case only (byte -> the kernel's slot)
SLOTS = np.full(256, -1, dtype=np.int64)
for _letter in "XYZFGIJK":
    SLOTS[ord(_letter)] = fastlane.LETTERS.index(_letter)
#: the kernel reads numbers of up to this many digits; a smaller --limit digits is the
#: general path's to enforce
KERNEL_DIGITS = 15
#: after a try that took no line, let the general path take this many lines first
_BACKOFF = 8
#: the 840D's plane names as the kernel's
_PLANES = {"XY": "XY", "ZX": "XZ", "YZ": "YZ"}


def _byte_class(members: bytes) -> np.ndarray:
    """Byte -> whether it is one of ``members`` (a table lookup costs less than np.isin)."""
    table = np.zeros(256, dtype=np.bool_)
    table[np.frombuffer(members, dtype=np.uint8)] = True
    return table


_NUMBER_STARTS = _byte_class(b"+-.0123456789")
_NUMBER_ENDS = _byte_class(b".0123456789")


def _split_words(buf: np.ndarray) -> np.ndarray:
    """Offsets ``i`` where bytes ``i``, ``i + 1`` are a blank then a number's character
    (``X 1.5``, ``X1 .5``, ``X- 5``) or a number's end then a letter (``G1X1``): a block the
    kernel would read as plain words and the 840D's plain-block path does not. Found from
    the blanks and the capitals (a few per block) rather than from every pair of bytes."""
    if len(buf) < 2:
        return np.zeros(0, dtype=np.int64)
    first, second = buf[:-1], buf[1:]
    blanks = np.flatnonzero((first == ord(" ")) | (first == ord("\t")))
    blank_number = blanks[_NUMBER_STARTS[second[blanks]]]
    capitals = np.flatnonzero(np.subtract(second, ord("A"), dtype=np.uint8) < 26)
    glued = capitals[_NUMBER_ENDS[first[capitals]]]
    if not len(glued):
        return blank_number
    if not len(blank_number):
        return glued
    return np.union1d(blank_number, glued)  # never the same offset: a number or a capital


class SiemensLane:
    """The lane over one 840D program file held in memory (:class:`Program`)."""

    def __init__(self, program: Program, data: bytes, arcs: bool) -> None:
        self.program = program
        self.arcs = arcs
        self._data = data
        self._buf = np.frombuffer(data, dtype=np.uint8)
        self._split = _split_words(self._buf)
        self._wait = 0
        # every line start at once (the text is ASCII: its offsets are the bytes')
        starts = np.flatnonzero(self._buf == ord("\n")).astype(np.int64)
        starts += 1
        if len(data) and not data.endswith(b"\n"):
            starts = np.append(starts, len(data) + 1)  # past the last line, as if it ended
        program.index_lines(array("q", np.concatenate((np.zeros(1, np.int64), starts)).tobytes()))

    @staticmethod
    def for_program(program: Program, arcs: bool = False) -> SiemensLane | None:
        """A lane over ``program`` (None where no kernels can load, where the digit limit
        is below what the kernel reads, or where the text is not ASCII: the kernel reads
        bytes at the text's offsets); ``arcs``: its runs may hold G2/G3 arcs."""
        if limits.current().digits < KERNEL_DIGITS or not program.text.isascii():
            return None
        try:
            fastlane.kernel_mode()
        except ImportError:
            return None
        return SiemensLane(program, program.text.encode("ascii"), arcs)

    def _limit(self, start: int) -> int:
        """The start of the first line at or after byte ``start`` that holds a split word
        (the end of the file without one): the kernel's buffer ends there."""
        found = int(np.searchsorted(self._split, start))
        if found == len(self._split):
            return len(self._data)
        return self._data.rfind(b"\n", 0, int(self._split[found])) + 1

    def take(self, ex: Machine, index: int) -> fastlane.Run | None:
        """The run of plain blocks from line ``index`` (0-based) of the main program, with
        the machine's state advanced past it; None where the general path runs the line."""
        if self._wait:
            self._wait -= 1
            return None
        s = ex.s
        if (
            s.motion not in (0, 1, 2, 3)
            or (s.motion >= 2 and not self.arcs)
            or s.feed_mode != 0
            or s.units_code == 70  # F in mm/min while lengths are inches: converted
            or s.diameter
            or s.frame.linear
            or s.mcall is not None
        ):
            return None
        start = self.program.line_offset(index)
        limit = self._limit(start)
        run = None
        if limit > start:
            inch = s.units is Units.INCHES
            run = fastlane.scan(
                self._buf[:limit],
                start,
                s.pos,
                s.feed,
                incremental=not s.absolute,
                traverse=s.motion == 0,
                first_line=index + 1,
                motion=s.motion * 10,
                arcs=self.arcs,
                bare=False,
                plane=_PLANES[s.plane],
                arc_tolerance=(
                    (RADIUS_TOLERANCE_INCH, ZERO_RADIUS_INCH, R_REACH_INCH)
                    if inch
                    else (RADIUS_TOLERANCE_MM, ZERO_RADIUS_MM, R_REACH_MM)
                ),
                ijk_absolute=False,
                slots=SLOTS,
            )
        if run is None or not run.lines:
            self._wait = _BACKOFF
            return None
        s.pos = list(run.end_position)
        s.feed = run.end_feed
        s.motion = (run.end_motion or 0) // 10
        ex.loc = Location(self.program.name, index + run.lines, 1)
        return run
