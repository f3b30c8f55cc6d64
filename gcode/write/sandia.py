"""The Sandia generic CNC language (SAND96-2499, seed 003; research/seed-sandia.md).

The seed defines commands, not a text syntax; this writer uses the proposal of
research/seed-sandia-full.md §5.3: one command per line, the seed's command name, then
``NAME=value`` arguments. Mapping (§5.4): rapid -> ``point_to_point_positioning`` (never
with a speed), feed -> ``SetSpeed`` + ``MoveTo`` (world space), units -> ``SetUnits``,
tool change -> ``GetTool``, tool length -> ``SetToolLength``, probe -> ``MoveReact``,
``STOP`` -> ``StopMotion``, program end -> ``Deactivate`` (the device goes inactive).
The language has no arcs: arcs, NURBS and ellipses become ``MoveTo`` chords within the
tolerance; runs of straight feeds and arcs are computed and formatted together
(:mod:`gcode.write.sandia_chords`: an arc is tens of lines). Spindle, coolant, dwell
and program stops have no generic command: they are dropped (with a report entry and a
comment); spindle-synchronised motion is refused. The reader is
:mod:`gcode.sandia.reader`.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence

import numpy as np

from gcode.core import linuxcnc as lc
from gcode.core.register_marks import ToolLengthRegister
from gcode.ngc.lane import fastlane
from gcode.ngc.lane.fastlane import ARC, FEED_MOVE, SET_FEED, Run
from gcode.write import approximate
from gcode.write.approximate import nurbs_problem
from gcode.write.bulk import COMMANDS_BEFORE_BULK
from gcode.write.options import WriterOptions
from gcode.write.report import Change, ConversionReport, loss_code, machinist
from gcode.write.sandia_chords import (
    ArcRows,
    batch_points,
    format_many,
    move_lines,
    plane_lines,
)
from gcode.write.spec import Dialect
from gcode.write.state import PLANE_AXES, Formatter, clamped_uniform_knots
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.path.ellipse import ellipse_chords

ATTRIBUTES = "attributes=ABSOLUTE|CS_CURRENT"
#: straight feeds and arcs queued at most before they are written (bounded memory,
#: streaming output)
RUN = 4096
_DEFAULTS: dict[str, object] = {
    "css": False,
    "speed": 0.0,
    "spindle": 0,
    "mist": False,
    "flood": False,
    "work": 1,
    "g92": (0.0,) * 6,
    "rotation": 0.0,
}


class SandiaWriter:
    """IR -> generic command lines (streaming)."""

    def __init__(self, d: Dialect, opts: WriterOptions, report: ConversionReport) -> None:
        self.d, self.o, self.report = d, opts, report
        report.target_dialect = report.target_dialect or d.name
        self.fmt = Formatter(d, opts)
        self.out: list[str] = []
        self.src: Location | None = None
        self.units: canon.Units | None = None
        self.plane = canon.Plane.XY
        self.feed = 0.0
        self.e_feed: str | None = None
        self.speed_key: tuple[float, float] | None = None  # (feed, scale) of e_feed
        self.pending_tool: int | None = None
        self.cur = dict.fromkeys("XYZ", 0.0)
        self.last = {k: f"{k}=0.0" for k in "XYZ"}
        self.known = False
        self.out_mm: float | None = None  # mm per output length unit, once set
        self.ended = False
        self.state: dict[str, object] = {}
        self.pallet = False  # a PALLET_SHUTTLE waiting for its stop or end
        self.per_rev = False  # SET_FEED_MODE per revolution in force
        self.file: str | None = None  # the source program (locations of bulk runs)
        self.queue: list[canon.Command | np.ndarray | ArcRows] = []  # not yet written
        self.queued = 0  # moves in the queue (an array holds several)
        self.marks: list[tuple[int, str]] = []  # (moves queued before it, line) meanwhile
        self.compiled = False  # a large program: the queue is formatted in compiled code

    def run(self, commands: Iterable[canon.Command]) -> Iterator[str]:
        """The program, one line at a time."""
        for block in self.run_blocks(commands):
            yield from "\n".join(block).split("\n")

    def run_text(self, commands: Iterable[canon.Command]) -> Iterator[str]:
        """The program as text chunks of whole lines ending with newlines: the chords of a
        run of moves are joined once, not yielded one by one (the Sandia output is about
        ten times as long as its G-code source)."""
        for block in self.run_blocks(commands):
            yield "\n".join(block) + "\n"

    def run_blocks(self, commands: Iterable[canon.Command]) -> Iterator[list[str]]:
        """The program as lists of entries, each one line or several joined by newlines
        (a run's chords); a list is emptied once the next is asked for."""
        head = self.d.header if self.o.header is None else self.o.header
        foot = self.d.footer if self.o.footer is None else self.o.footer
        if head:
            yield list(head)
        out, report = self.out, self.report
        for cmd in commands:
            if isinstance(cmd, Run):
                if not self.ended:
                    self.bulk(cmd, self.file)
                else:
                    report.commands += len(cmd)
            else:
                self.take(cmd)
            if out:
                report.blocks += sum(entry.count("\n") + 1 for entry in out)
                yield out
                out.clear()
        self.flush_moves()
        report.blocks += sum(entry.count("\n") + 1 for entry in out)
        if out:
            yield out
        out.clear()
        if foot:
            yield list(foot)

    def take(self, cmd: canon.Command) -> None:
        """One IR command: straight feeds and arcs join the queue of moves (the hot path),
        a feed rate is state, anything else writes the queue first and goes to its handler."""
        self.report.commands += 1
        self.place(cmd)

    def place(self, cmd: canon.Command) -> None:
        """:meth:`take` without counting the command (a run's events are counted at once)."""
        if self.ended:
            return
        if type(cmd) is canon.SetFeedRate:
            self.feed = cmd.rate
            return
        if (
            type(cmd) is canon.StraightFeed
            or (type(cmd) is canon.ArcFeed and cmd.rotation and self.o.on_missing != "refuse")
        ) and not (cmd.a or cmd.b or cmd.c):
            self.src = cmd.source
            if self.moving(1):
                self.queue.append(cmd)
                return
        self.flush_moves()
        self.src = cmd.source
        self.handle(cmd)

    def moving(self, rows: int) -> bool:
        """Ready the state for ``rows`` feed moves that join the queue (units, speed: their
        lines go before the moves); False when they are to be written one by one instead
        (no decimals: the batch formatters keep one)."""
        self.ensure_units()
        if self.fmt.places < 1:
            self.flush_moves()
            return False
        self.feeding()
        self.speed()
        if self.queued >= RUN:
            self.flush_moves()
        self.queued += rows
        return True

    def bulk(self, run: Run, file: str | None) -> None:
        """A run of plain lines from the interpreter's fast lane (arrays, no command
        objects): its feed moves join the queue as arrays, as :meth:`take` queues them one
        by one; from here on the queue is formatted in compiled code."""
        self.compiled = True
        if not len(run):
            return
        rotary = run.position[:, 3:]
        if rotary.any() and np.abs(rotary).max() > 1e-9:  # refused in MoveTo, at its line
            for c in run.commands(file):
                self.take(c)
            return
        self.report.commands += len(run)
        kind, pos, feed = run.kind, run.position, run.feed
        if kind.tobytes().count(FEED_MOVE) == len(run):  # the usual run: feeds only
            bounds = [0, len(run)]
        else:
            bounds = [0, *(np.flatnonzero(kind[1:] != kind[:-1]) + 1).tolist(), len(run)]
        commands: list[canon.Command] = []
        arcs = self.queueable_arcs(run)
        for i, j in zip(bounds[:-1], bounds[1:], strict=True):  # stretches of one kind
            k = int(kind[i])
            if k == SET_FEED:
                self.feed = float(feed[j - 1])
                continue
            self.src = canon.Location(file, int(run.line[i]), 1)
            if k == FEED_MOVE and self.moving(j - i):
                self.queue.append(pos[i:j, :3])
                continue
            if k == ARC and arcs is not None and self.moving(0):
                self.queue_arcs(run, arcs, i, j, file)
                continue
            commands = commands or run.commands(file)
            if k == ARC:  # arcs (a run read with arcs) join the queue as take queues them
                for c in commands[i:j]:
                    self.place(c)
                continue
            for c in commands[i:j]:  # rapids, or feeds written one by one
                self.flush_moves()
                self.src = c.source
                self.handle(c)

    def queueable_arcs(self, run: Run) -> np.ndarray | None:
        """The run's arcs as :class:`ArcRows` take them (in-plane end, centre, turns,
        normal end per row), when every one of them joins the queue as :meth:`place`
        would queue its command (turns, no --on-missing refuse); else None."""
        if run.arc is None or self.o.on_missing == "refuse":
            return None
        rows = run.arc
        if not rows[run.kind == ARC, 4].all():  # a zero-turn arc: written by its handler
            return None
        return rows

    def queue_arcs(self, run: Run, rows: np.ndarray, i: int, j: int, file: str | None) -> None:
        """Arcs ``i:j`` of ``run`` join the queue as :class:`ArcRows`, split where one by
        one they would have flushed it (each arc counts as :meth:`place` counts it)."""
        at = i  # moving(0) readied units and speed, and counted nothing
        while at < j:
            if self.queued >= RUN:
                self.flush_moves()
            room = max(RUN - self.queued, 1)
            end = min(j, at + room)
            self.queue.append(ArcRows(rows[at:end], run.line[at:end], file))
            self.queued += end - at
            at = end
        self.src = canon.Location(file, int(run.line[j - 1]), 1)

    def flush_moves(self) -> None:
        """Write the queued moves: all chords computed and formatted at once, with the
        lines written meanwhile (units, speeds) in their places."""
        queue = self.queue
        if not queue:
            return
        marks, self.marks = self.marks, []
        self.queue, self.queued = [], 0
        s = self.fmt.scale
        tol = self.o.tolerance
        pts, counts, sag, rows = batch_points(queue, *self.plane_start(), tol / s)
        before = np.concatenate(([0], np.cumsum(counts)))  # lines before each row
        lines = self.point_lines(pts, s)
        if isinstance(lines, tuple):  # compiled: one text and where each line starts
            text, starts = lines
            pieces: list[str] = []
            at = 0
            for row, line in marks:
                cut = int(starts[before[row]])
                pieces += (text[at:cut], line, "\n")
                at = cut
            pieces.append(text[at:])
            self.out.append("".join(pieces)[:-1])
        else:
            for shift, (row, line) in enumerate(marks):
                lines.insert(int(before[row]) + shift, line)
            self.out.extend(lines)
        message = f"{machinist('ARC_FEED')} as MoveTo chords"
        add = self.report.add
        for c, row in zip(queue, rows, strict=True):
            if type(c) is canon.ArcFeed:
                n, dev = int(counts[row]), float(sag[row])
                add(Change("CONV-ARC-LINES", "approximated", message, c.source, n, dev * s, tol))
            elif type(c) is ArcRows:
                m = len(c.line)
                where = [canon.Location(c.file, ln, 1) for ln in c.line.tolist()]
                for src, n, dev in zip(
                    where,
                    counts[row : row + m].tolist(),
                    (sag[row : row + m] * s).tolist(),
                    strict=True,
                ):
                    add(Change("CONV-ARC-LINES", "approximated", message, src, n, dev, tol))

    def plane_start(self) -> tuple[tuple[int, int, int], tuple[float, float, float]]:
        """For :func:`batch_points`: the indexes in x y z of the plane's first, second and
        normal axes, and where the tool is (program units)."""
        first, second, normal, _, _ = PLANE_AXES[self.plane]
        s = self.fmt.scale
        return (
            ("XYZ".index(first), "XYZ".index(second), "XYZ".index(normal)),
            (self.cur["X"] / s, self.cur["Y"] / s, self.cur["Z"] / s),
        )

    def point_lines(self, pts: np.ndarray, s: float) -> list[str] | tuple[str, np.ndarray]:
        """``MoveTo`` lines to the points (N, 3 in program units; times ``s`` in the
        output's): compiled (text, line starts) in a large program (fast-lane runs came, or
        as many commands as gcode.write.bulk.COMMANDS_BEFORE_BULK), else lines
        formatted at once in Python (:mod:`gcode.write.sandia_chords`)."""
        places = self.fmt.places
        known = self.known
        written = [self.last[k][2:] for k in "XYZ"]  # the texts written last, when known
        last: list[str | None] = list(written) if known else [None] * 3
        done = None
        if self.compiled or self.report.commands >= COMMANDS_BEFORE_BULK:
            self.compiled = True
            if places <= 12:  # the kernel's numbers (as gcode.write.bulk.can_take's)
                done = fastlane.sandia_text(pts, s, places, written if known else None)
        if done is not None:
            text, starts, after = done
            self.last = {k: f"{k}={v}" for k, v in zip("XYZ", after, strict=True)}
            self.cur = {k: float(pts[-1, i]) * s for i, k in enumerate("XYZ")}
            self.known = True
            return text, starts
        pts = pts * s
        moving = [
            i
            for i in range(3)
            if not known
            or not (pts[:, i] == pts[0, i]).all()
            or self.fmt.number(float(pts[0, i])) != last[i]
        ]
        if len(moving) == 2 and known:  # the usual case: motion in a plane, one % for all
            pair = [("XYZ"[i], pts[:, i]) for i in moving]
            lines = plane_lines(pair[0], pair[1], places, written)  # updates written
            texts: Sequence[str | None] = written
        else:
            columns = [format_many(pts[:, i], places) if i in moving else None for i in range(3)]
            if not moving:  # nothing moves: the lines repeat X
                columns[0] = format_many(pts[:, 0], places)
            lines = move_lines(columns[0], columns[1], columns[2], last)  # updates last
            texts = last
        self.last = {k: f"{k}={v}" for k, v in zip("XYZ", texts, strict=True)}
        self.cur = {k: float(pts[-1, i]) for i, k in enumerate("XYZ")}
        self.known = True
        return lines

    # ------------------------------------------------------------------ helpers
    def line(self, text: str) -> None:
        if self.queue:  # before the queued moves' lines yet to come (flush_moves)
            self.marks.append((self.queued, text))
        else:
            self.out.append(text)

    def lacking(self, code: str, what: str) -> None:
        if self.o.on_missing == "refuse":
            raise Diagnostic(code, f"{self.d.title} has no {what}", self.src)
        self.report.add(Change(code, "dropped", f"{self.d.title} has no {what}", self.src))
        if self.o.comments:
            self.line(f"# {what}: not written")

    def ensure_units(self) -> None:
        if self.units is not None and self.fmt.units_out is None:
            out_mm = self.fmt.set_output_units(self.units).mm_per_unit
            if self.out_mm and out_mm != self.out_mm:  # the same place in the new units
                self.cur = {k: v * self.out_mm / out_mm for k, v in self.cur.items()}
            self.out_mm = out_mm
            self.line(f"SetUnits linear={'inch' if self.fmt.inch else 'mm'} angular=deg")

    def axes(self, x: float, y: float, z: float, rot: tuple[float, ...]) -> list[str]:
        """Words of the axes whose written value changes (all after a position reset)."""
        if (rot[0] or rot[1] or rot[2]) and max(abs(v) for v in rot) > 1e-9:
            raise Diagnostic(
                "CONV-AXIS", "MoveTo is world space: rotary axes need a kinematic model", self.src
            )
        s = self.fmt.scale
        words = []
        known, cur, last = self.known, self.cur, self.last
        for k, v in (("X", x * s), ("Y", y * s), ("Z", z * s)):
            if known and v == cur[k]:
                continue
            w = f"{k}={self.fmt.number(v)}"
            if not known or w != last[k]:
                words.append(w)
                last[k] = w
            cur[k] = v
        self.known = True
        return words or [last["X"]]

    def speed(self) -> None:
        """``SetSpeed`` when the written speed differs (MoveTo and MoveReact move at it)."""
        key = (self.feed, self.fmt.scale)
        if key == self.speed_key and self.e_feed is not None:
            return
        speed = self.fmt.feed(self.feed * self.fmt.scale)
        if speed != self.e_feed:
            self.line(f"SetSpeed {speed}")
            self.e_feed = speed
        self.speed_key = key

    def feeding(self) -> None:
        """A feed motion: refused in feed per revolution (the generic language has none)."""
        if self.per_rev:
            raise Diagnostic(
                "CONV-FEED-PER-REV", f"{self.d.title} has no feed per revolution", self.src
            )

    def move(self, x: float, y: float, z: float, rot: tuple[float, ...] = (0, 0, 0)) -> None:
        self.feeding()
        self.ensure_units()
        self.speed()
        self.line("MoveTo " + " ".join(self.axes(x, y, z, rot)))

    def chords(
        self,
        c: canon.Command,
        pts: list[tuple[float, float, float]],
        normal_end: float,
        what: str,
        dev: float,
    ) -> None:
        """``MoveTo`` chords of a curve: ``pts`` are (first, second, fraction of the normal
        axis' travel to ``normal_end``) in the plane in force."""
        first, second, normal, _, _ = PLANE_AXES[self.plane]
        n0 = self.cur[normal] / self.fmt.scale
        xyz = []
        for p1, p2, f in pts:
            axial = normal_end if f == 1.0 else n0 + (normal_end - n0) * f  # exact end
            t = {first: p1, second: p2, normal: axial}
            xyz.append((t["X"], t["Y"], t["Z"]))
        self.moves(c, xyz, what, dev)

    def moves(self, c: canon.Command, xyz: list, what: str, dev: float) -> None:
        """``MoveTo`` lines to the points (x y z, program units) that stand for ``c``, and
        the report entry that says so."""
        self.feeding()
        for x, y, z in xyz:
            self.move(x, y, z)
        self.report.add(
            Change(
                "CONV-ARC-LINES",
                "approximated",
                f"{machinist(what)} as MoveTo chords",
                self.src,
                len(xyz),
                dev * self.fmt.scale,
                self.o.tolerance,
            )
        )

    # ------------------------------------------------------------------ dispatch
    def handle(self, c: canon.Command) -> None:  # noqa: C901 - one branch per command
        s = self.fmt.scale or 1.0
        if isinstance(c, canon.UseLengthUnits):
            if self.units != c.units:
                self.units = c.units
                if self.o.units is None or self.fmt.units_out is None:
                    self.fmt.units_out = None  # declared before the next motion
                    self.known = False
                    self.e_feed = None
                else:
                    self.fmt.set_output_units(c.units)  # same target units, new scale
        elif isinstance(c, canon.SelectPlane):
            self.plane = c.plane
        elif isinstance(c, canon.SetFeedRate):
            self.feed = c.rate
        elif isinstance(c, canon.StraightTraverse):
            self.ensure_units()
            if self.feed or self.e_feed is not None:
                self.speed()  # state only: a rapid never moves at it (App. A §1.2)
            words = self.axes(c.x, c.y, c.z, (c.a, c.b, c.c))
            self.line("point_to_point_positioning " + " ".join(words) + f" {ATTRIBUTES}")
        elif isinstance(c, canon.StraightFeed):
            self.move(c.x, c.y, c.z, (c.a, c.b, c.c))
        elif isinstance(c, canon.StraightProbe):
            self.ensure_units()
            self.speed()
            self.line("MoveReact " + " ".join(self.axes(c.x, c.y, c.z, (c.a, c.b, c.c))))
            self.known = False
        elif isinstance(c, canon.ArcFeed | canon.EllipseFeed):
            self.curve(c)
        elif isinstance(c, canon.NurbsFeed):
            self.nurbs(c)
        elif isinstance(c, canon.SelectTool):
            self.pending_tool = c.slot
        elif isinstance(c, canon.ChangeTool):
            tool = self.pending_tool if self.pending_tool is not None else c.slot
            self.line(f"GetTool {c.name or tool}")
        elif isinstance(c, canon.UseToolLengthOffset | lc.ToolLengthOffsets):
            length = c.length if isinstance(c, canon.UseToolLengthOffset) else c.offset[2]
            self.ensure_units()
            self.line(f"SetToolLength {self.fmt.length(length * s)}")
            self.known = False
        elif isinstance(c, ToolLengthRegister):
            if c.register is not None:  # G43 H n, G43.2 H n: the machine's measured length
                self.lacking(
                    "CONV-TOOL-LENGTH",
                    f"tool length register ({c.code} H{c.register}: the length the machine "
                    "measured; SetToolLength sets a value)",
                )
        elif isinstance(c, canon.PalletShuttle):
            self.pallet = True  # reported with the stop it comes with (M60), not with M30
        elif isinstance(c, canon.Stop):
            if self.pallet:
                self.lacking("CONV-PALLET", f"generic command for {machinist('PALLET_SHUTTLE')}")
            self.pallet = False
            self.line("StopMotion")
        elif isinstance(c, canon.Comment):
            if not c.text.startswith("interpreter:") and self.o.comments:
                self.line(f"# {c.text}")
        elif isinstance(c, canon.SetFeedMode):
            # refused at the first feed motion in it (a lathe reader starts in G99 and may
            # never feed in it); inverse time: the IR's rates are per minute already
            self.per_rev = c.mode == canon.FeedMode.UNITS_PER_REVOLUTION
        elif isinstance(c, canon.StartSpeedFeedSynch) or c.NAME == "RIGID_TAP":
            raise Diagnostic(
                "CONV-THREAD", f"{self.d.title} has no spindle-synchronised motion", self.src
            )
        elif isinstance(c, canon.ProgramEnd):
            self.line("Deactivate")  # the device goes inactive (Figure 3): nothing runs after
            self.line("# end of program")
            self.ended = True
            self.pallet = False  # LinuxCNC's M30 shuttle does nothing without pallets
        elif isinstance(c, canon.MachineFunction):
            self.lacking("CONV-MACHINE-FUNCTION", f"machine function {c.word} (M code for the PLC)")
        elif self.no_op(c):
            return
        else:
            self.lacking(loss_code(c.NAME), f"generic command for {machinist(c.NAME)}")

    def no_op(self, c: canon.Command) -> bool:
        """Commands that leave the default state as it is, or only mirror LinuxCNC's state."""
        if (
            isinstance(
                c,
                canon.InitCanon
                | canon.EndCanon
                | canon.SetFeedReference
                | canon.TurnProbeOn
                | canon.TurnProbeOff
                | canon.SetTraverseRate,
            )
            or c.NAME
            in (
                "ON_RESET",
                "START_CHANGE",
                "FINISH",
                "CANNED_CYCLE",
                "CANNED_CYCLE_END",
                "CUTTER_COMP_REGISTER",
                "WORK_OFFSET_REGISTER",
                # G64 Q: the tolerance of LinuxCNC's naive-CAM merging of collinear moves,
                # used only with G64 P (reported with SET_MOTION_CONTROL_MODE); nothing moves
                "SET_NAIVECAM_TOLERANCE",
            )
            or c.NAME.endswith("WAIT_ORIENT_COMPLETE")
        ):  # M19's wait: the M19 is reported
            return True
        key, value = {
            "SET_SPINDLE_MODE": ("css", getattr(c, "css", False)),
            "SET_SPINDLE_SPEED": ("speed", getattr(c, "speed", 0.0)),
            "START_SPINDLE_CLOCKWISE": ("spindle", 1),
            "START_SPINDLE_COUNTERCLOCKWISE": ("spindle", -1),
            "STOP_SPINDLE_TURNING": ("spindle", 0),
            "MIST_ON": ("mist", True),
            "MIST_OFF": ("mist", False),
            "FLOOD_ON": ("flood", True),
            "FLOOD_OFF": ("flood", False),
            "SET_G5X_OFFSET": ("work", getattr(c, "index", 1)),
            "SET_G92_OFFSET": ("g92", tuple(getattr(c, k, 0.0) for k in "xyzabc")),
            "SET_XY_ROTATION": ("rotation", getattr(c, "angle", 0.0)),
        }.get(c.NAME, (None, None))
        if key is None:
            return False
        unchanged = self.state.get(key, _DEFAULTS[key]) == value
        self.state[key] = value
        return unchanged

    def curve(self, c: canon.ArcFeed | canon.EllipseFeed) -> None:
        if self.o.on_missing == "refuse":
            raise Diagnostic("CONV-ARC-LINES", f"{self.d.title} has no arcs", self.src)
        if max(abs(c.a), abs(c.b), abs(c.c)) > 1e-9:
            raise Diagnostic(
                "CONV-AXIS", "MoveTo is world space: rotary axes need a kinematic model", self.src
            )
        self.ensure_units()
        first, second, normal, _, _ = PLANE_AXES[self.plane]
        s = self.fmt.scale or 1.0
        start = (self.cur[first] / s, self.cur[second] / s)
        end, centre = (c.first_end, c.second_end), (c.first_axis, c.second_axis)
        tol = self.o.tolerance / s
        if isinstance(c, canon.ArcFeed):
            if c.rotation == 0:
                self.chords(c, [(*end, 1.0)], c.axis_end_point, "ARC_FEED (0 turns)", 0.0)
                return
            # one at a time only when not queued (SandiaWriter.take): decimals=0
            xyz, _, sag, _ = batch_points([c], *self.plane_start(), tol)
            self.moves(c, xyz.tolist(), c.NAME, float(sag[0]))
            return
        major, minor, angle = c.major, c.minor, c.angle_to_first
        axial = c.axis_end_point - self.cur[normal] / s
        ch = ellipse_chords(
            start, end, centre, major, minor, angle, c.rotation, axial, tol, c.source
        )
        self.chords(c, ch.plane_points(), c.axis_end_point, c.NAME, ch.deviation)

    def nurbs(self, c: canon.NurbsFeed) -> None:
        problem = nurbs_problem(c)
        if problem:
            raise Diagnostic("CONV-NURBS", problem, self.src)
        if self.o.on_missing == "refuse":
            raise Diagnostic("CONV-NURBS", f"{self.d.title} has no curves", self.src)
        first, second, normal, _, _ = PLANE_AXES[self.plane]
        pts = np.array(c.points, dtype=float)
        knots = np.array(c.knots or clamped_uniform_knots(len(pts), c.order), dtype=float)
        s = self.fmt.scale or 1.0

        def curve(u: np.ndarray) -> np.ndarray:
            return approximate.nurbs_evaluate(c.order, pts, knots, u)

        pieces, dev = approximate.fit_curve(
            curve, knots[0], knots[-1], self.o.tolerance / s, False, knots
        )
        chords = [(p.end[0], p.end[1], 1.0) for p in pieces]
        self.chords(c, chords, self.cur[normal] / s, "NURBS_FEED", dev)
