"""Compiled fast lane for the commonest CAM lines: plain axis, feed and G0/G1 words.

A CAM post's output is mostly lines like ``X12.5 Y-3.25 Z-1.0`` or ``F800`` while the
modal state stays simple (G0 or G1, G94, no cutter compensation, no canned cycle).
Interpreting them one by one through the general machinery costs microseconds a line;
this module scans a run of such lines straight from the program's bytes with a
numba-compiled loop and returns the resulting events as arrays (:func:`scan`), and
formats events as canonical text in compiled code too (:func:`events_text`).

Semantics are exactly those of the general interpreter for these lines (NIST RS274/NGC v3
§3.3 and §3.8 order of execution; LinuxCNC): blanks and tabs are ignored; an ``F`` word
emits ``SET_FEED_RATE`` each time it appears, before the line's motion; a line with axis
words emits one ``STRAIGHT_TRAVERSE`` (G0) or ``STRAIGHT_FEED`` (G1) to the new position
even when it equals the current one; in G91 the words are increments. A line is *plain*
when it holds an optional integer ``N`` word first, then words among X Y Z A B C F and one
G0/G1 (only beside an axis word), each letter at most once, each with a plain decimal
number, and ``F`` positive.
A run ends before the first line that is not plain or that would feed at a zero feed rate;
the general interpreter takes that line, and owns every diagnostic.

Numbers are parsed as an integer mantissa over a power of ten: the correctly rounded
value, the same as ``float()``, for mantissas of up to 15 digits (longer ones end the run).
Formatting matches ``f"{v:.4f}"``; the rare values on a rounding tie within floating-point
noise are flagged and re-formatted in Python.

The kernels (:mod:`gcode.ngc.lane.fastlane_kernels`) are compiled ahead of time by numba.pycc into
a plain extension module, built once in a child process on first use and kept in a cache
directory (:func:`cache_dir`) under a name keyed by the kernel source and the Python and
numpy versions; loading it takes under a millisecond and imports no numba. Where it cannot
be built (no C compiler, read-only cache), the same kernels run through numba's JIT, whose
start-up costs a few tenths of a second; ``CNC_FASTLANE_JIT=1`` forces that path. The
interpreter uses the lane only for large programs either way.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from kernel import aot
from kernel.ir import canon

#: event kinds
TRAVERSE = 0  # STRAIGHT_TRAVERSE to ``position``
FEED_MOVE = 1  # STRAIGHT_FEED to ``position``
SET_FEED = 2  # SET_FEED_RATE(``feed``)
ARC = 3  # ARC_FEED: the row of ``Run.arc``, then ``position``'s A B C

#: the words' letters in slot order: 0-5 axes X Y Z A B C, 6 F, 7 G (0-3), 8 N, 9-11 I J
#: K, 12 R
LETTERS = "XYZABCFGNIJKR"


def slot_table(letters: str) -> np.ndarray:
    """Byte -> slot of :data:`LETTERS` for the words in ``letters`` (either case); -1 for
    every other byte."""
    table = np.full(256, -1, dtype=np.int64)
    for c in letters:
        table[ord(c)] = table[ord(c.lower())] = LETTERS.index(c)
    return table


#: letter -> slot for the RS274/NGC lines the lane takes
SLOTS = slot_table(LETTERS)
_POW10 = 10.0 ** np.arange(23)


@dataclass(frozen=True, slots=True)
class Run:
    """Events of a run of plain lines, in program order.

    ``kind[i]`` is :data:`TRAVERSE`, :data:`FEED_MOVE` or :data:`SET_FEED`;
    ``position[i]`` (x y z a b c, program coordinates) is the position after the event,
    ``feed[i]`` the feed rate in force, ``line[i]`` the 1-based program line. ``consumed``
    is the number of bytes and ``lines`` the number of program lines taken; the state after
    the run is ``end_position``, ``end_feed`` and ``end_traverse`` (True in G0), and
    ``end_motion`` the motion code after it (0, 10, 20, 30; None where the run was not
    scanned). A scan with ``arcs`` has :data:`ARC` events: ``arc[i]`` holds the in-plane end,
    the centre, the signed turns and the end on the plane's normal axis, as ``ARC_FEED``
    takes them (None when the run has no arc columns).
    """

    kind: np.ndarray
    position: np.ndarray
    feed: np.ndarray
    line: np.ndarray
    consumed: int
    lines: int
    end_position: tuple[float, ...]
    end_feed: float
    end_traverse: bool
    arc: np.ndarray | None = None
    end_motion: int | None = None

    def __len__(self) -> int:
        return int(self.kind.shape[0])

    def commands(self, file: str | None = None) -> list[canon.Command]:
        """The events as IR command objects, each with its source line."""
        out: list[canon.Command] = []
        loc = canon.Location
        arcs = self.arc.tolist() if self.arc is not None else [()] * len(self)
        for k, pos, fv, ln, arc in zip(
            self.kind.tolist(),
            self.position.tolist(),
            self.feed.tolist(),
            self.line.tolist(),
            arcs,
            strict=True,
        ):
            src = loc(file, ln, 1)
            if k == TRAVERSE:
                out.append(canon.StraightTraverse(*pos, source=src))
            elif k == FEED_MOVE:
                out.append(canon.StraightFeed(*pos, source=src))
            elif k == ARC:
                e1, e2, c1, c2, turns, normal = arc
                out.append(canon.ArcFeed(e1, e2, c1, c2, int(turns), normal, *pos[3:], source=src))
            else:
                out.append(canon.SetFeedRate(fv, source=src))
        return out


#: scan's plane argument: the in-plane axes, the normal axis and the centre words' slots
#: (gcode.core.state.PLANE_AXES and PLANE_CENTRE), by plane name
PLANES = {
    "XY": np.array([0, 1, 2, 9, 10, 11], dtype=np.int64),
    "XZ": np.array([2, 0, 1, 11, 9, 10], dtype=np.int64),
    "YZ": np.array([1, 2, 0, 10, 11, 9], dtype=np.int64),
}


def scan(
    buf: np.ndarray,
    start: int,
    position: tuple[float, ...] | list[float],
    feed: float,
    *,
    incremental: bool,
    traverse: bool,
    first_line: int,
    max_events: int = 8192,
    motion: int | None = None,
    arcs: bool = False,
    bare: bool = False,
    plane: str = "XY",
    arc_tolerance: tuple[float, float, float] = (0.0, 0.0, 0.0),
    ijk_absolute: bool = False,
    slots: np.ndarray | None = None,
    point_slots: int = 0,
) -> Run:
    """The run of plain lines that starts at byte ``start`` of ``buf`` (a uint8 array).

    ``position`` (x y z a b c, program coordinates) and ``feed`` are the interpreter's
    state before the run, ``incremental`` is G91 and ``traverse`` G0 (else G1). The run
    ends at the first line the lane cannot take, at the end of the buffer, or after about
    ``max_events`` events. ``buf`` must end at a line end or at the end of the file.

    With ``arcs`` the run also takes G2/G3 lines in ``plane`` in centre format (helices and
    G90.1 centres too) and in radius format (R; no P); ``motion`` is then the modal motion
    code, 0, 10, 20 or 30, instead of ``traverse``. ``arc_tolerance`` holds LinuxCNC's
    radius tolerance, smallest radius and R reach in program units, which
    :func:`gcode.core.arcs.centre_format` and :func:`gcode.core.arcs.radius_format` check
    (an R arc's centre is computed by the same operations, with ``math.hypot`` to the last
    bit). With ``bare`` it takes a G0/G1 with no axis word (a move to the current point).

    ``slots`` maps each byte to a word's slot (:data:`SLOTS`, the RS274/NGC letters; a
    reader whose lines hold fewer of them passes its own table, -1 for a letter that ends
    the run); a word whose slot's bit is set in ``point_slots`` ends the run when its
    number has no decimal point (a Fanuc length without one counts increments).
    """
    start_pos = np.array(position, dtype=np.float64)
    if start_pos.shape != (6,) or start < 0:
        raise ValueError("position must hold 6 axes and start must be >= 0")
    code = (0 if traverse else 10) if motion is None else motion
    if code not in (0, 10, 20, 30) or (code >= 20 and not arcs):
        raise ValueError("motion must be 0 or 10 (20 or 30 with arcs)")
    kind, pos, feed_arr, line, arc, end, line_no, cur, end_feed, end_motion = _kernels().scan(
        np.ascontiguousarray(buf, dtype=np.uint8).reshape(-1),
        int(start),
        SLOTS if slots is None else slots,
        _POW10,
        start_pos,
        float(feed),
        bool(incremental),
        code // 10,
        int(first_line),
        max(int(max_events), 2),
        bool(arcs),
        bool(bare),
        PLANES[plane],
        np.array(arc_tolerance, dtype=np.float64),
        bool(ijk_absolute),
        int(point_slots),
    )
    return Run(
        kind,
        pos,
        feed_arr,
        line,
        int(end - start),
        int(line_no - first_line),
        tuple(cur.tolist()),
        float(end_feed),
        end_motion == 0,
        arc if arcs else None,
        int(end_motion) * 10,
    )


_NAMES = (b"STRAIGHT_TRAVERSE", b"STRAIGHT_FEED", b"SET_FEED_RATE", b"ARC_FEED")
_NAME_TABLE = np.zeros((len(_NAMES), max(len(n) for n in _NAMES)), dtype=np.uint8)
for _k, _n in enumerate(_NAMES):
    _NAME_TABLE[_k, : len(_n)] = np.frombuffer(_n, dtype=np.uint8)
_NAME_LEN = np.array([len(n) for n in _NAMES], dtype=np.int64)


def events_text(run: Run, seq0: int) -> str:
    """Canonical text of a run's events numbered from ``seq0``.

    Identical to ``kernel.ir.canon.write_text(run.commands(), seq0)`` joined with newlines
    (each line ends in a newline).
    """
    if len(run) == 0:
        return ""
    m = len(run)
    kind = np.ascontiguousarray(run.kind, dtype=np.int8)
    pos = np.ascontiguousarray(run.position, dtype=np.float64).reshape(m, 6)
    feed = np.ascontiguousarray(run.feed, dtype=np.float64).reshape(m)
    if run.arc is None:
        raw, python, flagged = _kernels().format(kind, pos, feed, int(seq0), _NAME_TABLE, _NAME_LEN)
    else:
        arc = np.ascontiguousarray(run.arc, dtype=np.float64).reshape(m, 6)
        raw, python, flagged = _kernels().format_arcs(
            kind, pos, feed, arc, int(seq0), _NAME_TABLE, _NAME_LEN
        )
    text = raw.tobytes().decode("ascii")
    if not flagged:
        return text
    lines = text.split("\n")
    cmds = run.commands()
    for r in np.flatnonzero(python).tolist():
        lines[r] = f"{seq0 + r:5d} N..... {cmds[r].to_text()}"
    return "\n".join(lines)


@dataclass(frozen=True, slots=True)
class GcodeLayout:
    """What :func:`gcode_text` needs of a dialect, as the kernel takes it (made once per
    writer): its rapid, linear, clockwise and counter-clockwise arc motion codes, the axes
    it has among X Y Z A B C, and those written as a diameter (twice the coordinate)."""

    codes: tuple[str, ...]
    axes: list[int]
    code_buf: np.ndarray
    code_len: np.ndarray
    letters: np.ndarray
    axes_arr: np.ndarray
    factor: np.ndarray
    absent: np.ndarray

    @classmethod
    def of(cls, codes: tuple[str, ...], dialect_axes: str, diameter: str = "") -> GcodeLayout:
        axes = [i for i, letter in enumerate("XYZABC") if letter in dialect_axes]
        code_buf = np.zeros((len(codes), 8), dtype=np.uint8)
        for k, code in enumerate(codes):
            code_buf[k, : len(code)] = np.frombuffer(code.encode("ascii"), dtype=np.uint8)
        return cls(
            codes,
            axes,
            code_buf,
            np.array([len(c) for c in codes], dtype=np.int64),
            np.array([ord("XYZABC"[i]) for i in axes], dtype=np.uint8),
            np.array(axes, dtype=np.int64),
            np.array([2.0 if "XYZABC"[i] in diameter else 1.0 for i in axes]),
            np.array([i for i in range(6) if i not in axes], dtype=np.int64),
        )


def _state(words: list[str]) -> np.ndarray:
    """Words as the kernels read them: each followed by a zero byte (read-only bytes)."""
    return np.frombuffer(("\0".join(words) + "\0").encode("ascii"), dtype=np.uint8)


def gcode_text(
    run: Run,
    scale: float,
    layout: GcodeLayout,
    places: int,
    point: bool,
    last: list[str | None],
    motion: int,
    feed: tuple[str | None, float],
    separator: str,
    plane: np.ndarray | None = None,
) -> tuple[str, list[str], int, str, int, int] | None:
    """G-code blocks of a run formatted in compiled code (gcode.write.bulk.write_run's
    rules): X Y Z and F times ``scale`` are the output's; ``last`` the words last written
    of ``layout.axes``, ``motion`` the index in ``layout.codes`` of the motion code in force
    (-1: none), ``feed`` the F word last written and the feed rate in force. Returns (text
    with a newline after each block, the axis words after, the motion index after, the F
    word after, the longest block, the number of blocks), or None where the kernel cannot
    write the run (a number of 1e12 or more, an axis the dialect lacks off zero), so that
    the caller writes it command by command. A run with arcs needs ``plane`` (the
    kernel's, :func:`arc_plane`) and the layout's four codes; an arc of more than one turn
    is not written either."""
    head: tuple[np.ndarray, ...] = (
        np.ascontiguousarray(run.kind, dtype=np.int8),
        np.ascontiguousarray(run.position, dtype=np.float64),
        np.ascontiguousarray(run.feed, dtype=np.float64),
    )
    if run.arc is not None:
        if plane is None:
            raise ValueError("a run with arcs needs the arc plane")
        kernel = _kernels().gcode_arcs
        head = (*head, np.ascontiguousarray(run.arc, dtype=np.float64).reshape(len(run), 6))
    else:
        kernel = _kernels().gcode
    raw, cannot, motion_after, longest, blocks, state = kernel(
        *head,
        float(scale),
        layout.axes_arr,
        layout.factor,
        layout.absent,
        layout.letters,
        int(places),
        bool(point),
        _state([w or "" for w in last] + [feed[0] or ""]),
        layout.code_buf,
        layout.code_len,
        int(motion),
        float(feed[1]),
        np.uint8(ord(separator)),
        *(() if run.arc is None else (plane,)),
    )
    if cannot:
        return None
    words = state.tobytes().decode("ascii").split("\0")
    na = len(layout.axes)
    return raw.tobytes().decode("ascii"), words[:na], int(motion_after), words[na], longest, blocks


def arc_plane(
    layout: GcodeLayout, first: str, second: str, normal: str, centres: str
) -> np.ndarray | None:
    """The kernel's plane argument for arcs in the plane of ``first`` and ``second`` (axis
    letters; ``normal`` the third, ``centres`` their centre words' letters), or None when
    the arcs are not the kernel's: an in-plane axis the dialect lacks or writes as a
    diameter."""
    spots = []
    for letter in (first, second):
        i = "XYZABC".index(letter)
        if i not in layout.axes or layout.factor[layout.axes.index(i)] != 1.0:
            return None
        spots.append(layout.axes.index(i))
    swap = centres[1] < centres[0]
    order = sorted(centres)
    return np.array(
        [*spots, "XYZ".index(normal), ord(order[0]), ord(order[1]), int(swap)], dtype=np.int64
    )


def sandia_text(
    points: np.ndarray, scale: float, places: int, last: list[str] | None
) -> tuple[str, np.ndarray, list[str]] | None:
    """``MoveTo`` lines to ``points`` (N, 3 in program units; times ``scale`` in the
    output's) formatted in compiled code, writing an axis when its text changes
    (gcode.write.sandia_chords.move_lines' rule); ``last``: the X, Y, Z texts written
    last (None: every axis on the first line). Returns (text with a newline after each
    line, the offset where each line starts and the text's length, the texts after), or
    None where a number is too large for the kernel."""
    raw, starts, too_large, state = _kernels().sandia(
        np.ascontiguousarray(points, dtype=np.float64),
        float(scale),
        int(places),
        _state(last or ["", "", ""]),
        last is not None,
    )
    if too_large:
        return None
    return raw.tobytes().decode("ascii"), starts, state.tobytes().decode("ascii").split("\0")[:3]


# ---------------------------------------------------------------- loading the kernels
#: the compiled kernels (kernel.aot: built once into the user's cache, JIT fallback)
KERNELS = aot.Kernels(
    "gcode.ngc.lane.fastlane_kernels", "_fastlane_aot", "fast kernels", "CNC_FASTLANE_JIT"
)
cache_dir = aot.cache_dir
private_dir = aot.private_dir


def aot_name() -> str:
    """Module name of the AOT build of the current kernel source (kernel.aot)."""
    return KERNELS.aot_name()


def load_aot(directory: Path) -> ModuleType | None:
    """The AOT kernel module from ``directory``, built there first if missing (kernel.aot)."""
    return KERNELS.load_aot(directory)


def load_jit() -> ModuleType:
    """The kernels through numba's JIT (imports numba)."""
    return KERNELS.load_jit()


def kernel_mode() -> str:
    """``"aot"`` or ``"jit"``: how this process runs the kernels (loads them if not yet).

    Raises ImportError when neither an AOT module nor numba is available.
    """
    return KERNELS.mode()


def _kernels() -> Any:
    """The kernel module in use: AOT if possible, else JIT (loaded once per process)."""
    return KERNELS.module()
