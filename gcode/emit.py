"""Writer: canonical commands (kernel.canon IR) -> G-code text in a chosen dialect.

:func:`write` is a generator of lines (streaming, bounded memory). It keeps the machine
state the IR sets (units, plane, feed, spindle, coolant, modes) and writes a modal word
only when the emitted state differs, just before the next motion or event that needs it
(modal-minimal emission, research/seed-sandia-full.md §5.1). Positions are written in
absolute program coordinates (G90), as the IR holds them.

A construct the dialect lacks is expanded (multi-turn arcs into full circles),
approximated within ``tolerance`` (NURBS and ellipses by arcs or lines, see
:mod:`gcode.approximate`), substituted or dropped, each recorded in the
:class:`~gcode.convert_report.ConversionReport`; with ``on_missing="refuse"`` the writer
raises a located ``CONV-*`` :class:`~kernel.diagnostics.Diagnostic` instead.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from gcode import emit_bulk
from gcode.convert_report import Change, ConversionReport
from gcode.cycle_marks import CycleEnd
from gcode.dialects import get_dialect
from gcode.dialects.spec import Dialect
from gcode.emit_bulk import can_take, run_of, write_run
from gcode.emit_state import Formatter
from gcode.emit_table import BY_NAME as _BY_NAME
from gcode.emit_table import HANDLERS as _HANDLERS
from gcode.fastlane import GcodeLayout, Run
from kernel import canon
from kernel.diagnostics import Diagnostic, Location

ARC_FORMATS = ("ijk", "ijk-abs", "r")
CYCLE_MODES = ("keep", "expand")
_PLAIN_MOTIONS = frozenset({canon.StraightFeed, canon.StraightTraverse, canon.ArcFeed})


@dataclass(frozen=True)
class WriterOptions:
    """What the user controls. ``units``/``decimals``/``max_line_length`` None: as given."""

    arc_format: str = "ijk"  # ijk (incremental centres) | ijk-abs | r
    units: str | None = None  # None: the program's own | "mm" | "inch"
    line_numbers: int = 0  # increment; 0: no N words
    decimals: int | None = None  # None: the dialect's default for the output units
    header: tuple[str, ...] | None = None  # None: the dialect's program frame
    footer: tuple[str, ...] | None = None
    max_line_length: int | None = None  # None: the dialect's limit
    on_missing: str = "approximate"  # approximate | refuse
    tolerance: float = 0.001  # approximation tolerance, output length units
    comments: bool = True
    cycles: str = "expand"  # keep: drilling cycles as cycle blocks where the target has them


def write(
    commands: Iterable[canon.Command],
    dialect: str | Dialect,
    options: WriterOptions | None = None,
    report: ConversionReport | None = None,
) -> Iterator[str]:
    """Yield the program text, one block per line (no line terminators)."""
    return _writer(dialect, options, report).run(commands)


def write_text(
    commands: Iterable[canon.Command],
    dialect: str | Dialect,
    options: WriterOptions | None = None,
    report: ConversionReport | None = None,
    batch: int = 4096,
    source: str | None = None,
) -> Iterator[str]:
    """The program text as chunks of whole lines, each line ending with a newline: what a
    file or a pipe wants (one write per line costs as much as formatting a Sandia line);
    still streamed, ``batch`` lines at a time."""
    writer = _writer(dialect, options, report)
    writer.file = source
    if isinstance(writer, BlockWriter):
        yield from writer.run_text(commands, batch)
    else:
        yield from writer.run_text(commands)  # Sandia: its chords are joined per run


def _writer(dialect: str | Dialect, options: WriterOptions | None, report: ConversionReport | None):  # noqa: ANN202 - BlockWriter | SandiaWriter
    d = get_dialect(dialect) if isinstance(dialect, str) else dialect
    opts = options or WriterOptions()
    if opts.arc_format not in ARC_FORMATS:
        raise Diagnostic("CONV-OPTION", f"arc format {opts.arc_format!r}: use {ARC_FORMATS}")
    if opts.on_missing not in ("approximate", "refuse") or opts.tolerance <= 0:
        raise Diagnostic("CONV-OPTION", "on_missing is approximate or refuse; tolerance > 0")
    if opts.cycles not in CYCLE_MODES:
        raise Diagnostic("CONV-OPTION", f"cycles {opts.cycles!r}: use {CYCLE_MODES}")
    if d.structure == "commands":
        from gcode.dialects.sandia import SandiaWriter

        return SandiaWriter(d, opts, report or ConversionReport())
    return BlockWriter(d, opts, report or ConversionReport())


class BlockWriter:
    """The state machine behind :func:`write` for block-structured (RS274-like) dialects."""

    def __init__(self, d: Dialect, opts: WriterOptions, report: ConversionReport) -> None:
        self.d, self.o, self.report = d, opts, report
        report.target_dialect = report.target_dialect or d.name
        self.fmt = Formatter(d, opts)
        self.out: list[str] = []
        self.seq = opts.line_numbers
        self.src: Location | None = None
        self.ended = False
        # IR state (desired) and emitted state
        self.units: canon.Units | None = None
        self.plane = canon.Plane.XY
        self.e_plane: canon.Plane | None = None
        self.feed = 0.0
        self.e_feed: str | None = "F" + self.fmt.feed(0.0)  # INIT_CANON: feed 0
        self.feed_mode = canon.FeedMode.UNITS_PER_MINUTE
        self.e_feed_mode = canon.FeedMode(d.initial_feed_mode)
        self.mode: tuple[canon.MotionMode, float] | None = None
        self.naive: float | None = None
        self.e_mode: tuple[canon.MotionMode, float, float | None] | None = None
        self.speed = 0.0
        self.e_speed = 0.0
        self.css: tuple[bool, float] = (False, 0.0)
        self.e_css: tuple[bool, float] = (False, 0.0)
        self.direction = canon.Direction.STOPPED
        self.e_direction = canon.Direction.STOPPED
        self.coolant = {"mist": False, "flood": False}
        self.e_coolant = {"mist": False, "flood": False}
        self.tool: int = 0
        self.pending_select: int | None = None
        self.pallet = False
        self.sync: float | None = None
        self.centre_abs_on = False
        self.e_work = 1  # G54
        self.e_rotation = 0.0
        self.e_local: tuple[float, ...] = (0.0,) * 6
        self.frame: tuple[str, ...] = ()  # the blocks of the last frame written (_frame)
        self.comp_radius = 0.0
        self.comp_on = False  # G41/G42 written and not yet G40
        self.file: str | None = None  # the source program (locations of bulk runs)
        self.comp_register: int | None = None  # the next G41/G42's D register (CompRegister)
        self.motion: str | None = None
        # positions in output units: the IR's (exact) and what the text set (rounded)
        self.cur = dict.fromkeys("XYZABC", 0.0)
        self.words: dict[str, str | None] = dict.fromkeys("XYZ", None)
        self.words.update({k: k + self.fmt.angle(0.0) for k in "ABC"})  # rotaries start at 0
        self.started = False
        self.noted: set[str] = set()
        self.cycle: tuple[object, ...] | None = None  # the modal cycle block last written
        self.skipping = False  # inside a kept cycle's moves (gcode.emit_cycles)
        self.dirty = True
        self.layout: GcodeLayout | None = None  # the dialect as the bulk kernel takes it

    # ------------------------------------------------------------------ output
    def block(self, *words: str) -> None:
        text = self.d.separator.join(w for w in words if w)
        if not text:
            return
        if self.o.line_numbers:
            text = f"N{self.seq}{self.d.separator}{text}"
            self.seq += self.o.line_numbers
            top = self.d.max_sequence_number
            if top is not None and self.seq > top:
                self.seq = self.o.line_numbers
        limit = self.o.max_line_length or self.d.max_line_length
        if limit is not None and len(text) > limit:
            raise Diagnostic(
                "CONV-LINE-LENGTH",
                f"block of {len(text)} characters exceeds the {limit} a {self.d.title} reads: "
                f"{text[:40]}...",
                self.src,
            )
        self.out.append(text)
        self.report.blocks += 1

    def comment(self, text: str) -> None:
        if not (self.o.comments and self.d.comment):
            return
        for ch in self.d.comment_forbidden:
            text = text.replace(ch, {"(": "[", ")": "]"}.get(ch, " "))
        limit = self.o.max_line_length or self.d.max_line_length
        line = self.d.comment.format(text)
        if limit is not None and len(line) > limit:
            keep = max(0, limit - (len(line) - len(text)))
            line = self.d.comment.format(text[:keep])
        self.out.append(line)

    def change(self, code: str, kind: str, message: str, **kw: object) -> None:
        self.report.add(Change(code, kind, message, self.src, **kw))  # type: ignore[arg-type]

    def lacking(self, code: str, what: str, kind: str = "dropped", note: bool = True) -> None:
        """The target lacks ``what``: refuse, or record ``kind`` and go on."""
        if self.o.on_missing == "refuse":
            raise Diagnostic(code, f"{self.d.title} has no {what}", self.src)
        self.change(code, kind, f"{self.d.title} has no {what}")
        if note and kind == "dropped":
            self.comment(f"{what}: not written")

    def refuse(self, code: str, message: str) -> None:
        raise Diagnostic(code, message, self.src)

    # ------------------------------------------------------------------ driver
    def run(self, commands: Iterable[canon.Command]) -> Iterator[str]:
        """The program, a line at a time. ``commands`` may hold the interpreter's runs of
        plain lines (:class:`gcode.fastlane.Run`, from ``interpret_chunks``): those are
        written in bulk where :mod:`gcode.emit_bulk` can, else command by command."""
        for lines in self.run_lines(commands):
            for line in lines:
                if "\n" in line:  # a bulk run's blocks (gcode.emit_bulk)
                    yield from line.split("\n")
                else:
                    yield line

    def run_text(self, commands: Iterable[canon.Command], batch: int = 4096) -> Iterator[str]:
        """The program as text chunks of whole lines, each ending with a newline, about
        ``batch`` lines a chunk (what a file wants: no generator step per line)."""
        pending: list[str] = []
        for lines in self.run_lines(commands):
            pending.extend(lines)
            if len(pending) >= batch:
                pending.append("")
                yield "\n".join(pending)
                pending.clear()
        if pending:
            pending.append("")
            yield "\n".join(pending)

    def run_lines(self, commands: Iterable[canon.Command]) -> Iterator[list[str]]:
        """The blocks of each command or run, as lists (emptied after each step); an entry
        holds several blocks, joined by newlines, where a run was written in bulk."""
        yield list(self.d.header if self.o.header is None else self.o.header)
        plain: list[canon.Command] = []  # plain moves of a large command stream, batched
        report, kinds = self.report, emit_bulk.KIND
        after, batch = emit_bulk.COMMANDS_BEFORE_BULK, emit_bulk.BATCH
        for item in commands:
            batched = type(item) in kinds and report.commands >= after
            if batched:
                plain.append(item)
                if len(plain) < batch:
                    continue
            if plain:
                self.commands_in_bulk(plain)
                plain.clear()
            if isinstance(item, Run):
                self.bulk(item, None)
            elif not batched:
                self.command(item)
            if self.out:
                yield self.out
                self.out.clear()
        if plain:
            self.commands_in_bulk(plain)
        yield [*self.out, *(self.d.footer if self.o.footer is None else self.o.footer)]
        self.out.clear()

    def commands_in_bulk(self, plain: list[canon.Command]) -> None:
        """Plain moves and feed rates of a command stream written as one run (compiled, as
        the fast lane's runs are), else command by command."""
        if len(plain) < emit_bulk.BATCH_MIN or (run := run_of(plain, self.feed)) is None:
            for cmd in plain:
                self.command(cmd)
        else:
            self.bulk(run, plain)

    def bulk(self, run: Run, commands: list[canon.Command] | None) -> None:
        """A run (a fast-lane run of ``self.file``, or made of ``commands``) written by
        :mod:`gcode.emit_bulk` where it can take it exactly, else command by command."""
        if not (can_take(self, run) and write_run(self, run, self.file, commands)):
            for cmd in commands if commands is not None else run.commands(self.file):
                self.command(cmd)

    def command(self, cmd: canon.Command) -> None:
        """One canonical command through its handler (its blocks land in ``self.out``)."""
        self.report.commands += 1
        self.src = cmd.source
        if self.ended:
            return  # LinuxCNC prints M2's resets after it: nothing more to write
        if self.skipping and type(cmd) is not CycleEnd:
            return  # a kept cycle's own moves: the target expands the block itself
        if self.pending_select is not None and not isinstance(
            cmd, canon.ChangeTool | canon.Comment | canon.StartChange | canon.StopSpindleTurning
        ):  # T alone only when no change follows (M6 is SELECT, START_CHANGE, ...)
            self.block(f"T{self.pending_select}")
            self.pending_select = None
        if type(cmd) not in _PLAIN_MOTIONS:
            self.dirty = True  # it may set state that the next flush must write
        handler = _HANDLERS.get(type(cmd)) or _BY_NAME.get(cmd.NAME)
        if handler is None:
            self.lacking("CONV-UNSUPPORTED", f"equivalent of {cmd.NAME}")
        else:
            handler(self, cmd)

    # ------------------------------------------------------------------ state flush
    def flush(self) -> None:
        """Write the modal state the IR set since the last motion or event."""
        if not self.dirty:
            return
        self.dirty = False
        self.flush_units()
        if self.plane != self.e_plane:
            start = "" if self.started else self.d.absolute
            self.block(start, self.d.planes[list(canon.Plane).index(self.plane)])
            self.e_plane = self.plane
            self.started = True
        self.flush_feed_mode()
        self.flush_motion_mode()
        self.flush_coolant()
        self.flush_spindle()

    def flush_units(self) -> None:
        """The units word, once, before the first number (an offset needs no plane yet)."""
        if self.units is None and self.o.units is not None:
            self.refuse("CONV-OPTION", "the program sets no length units: cannot convert them")
        if self.units is not None and self.fmt.units_out is None:
            self.fmt.set_output_units(self.units)
            self.block(self.d.inch if self.fmt.inch else self.d.mm)

    def flush_feed_mode(self) -> None:
        if self.feed_mode == self.e_feed_mode:
            return
        code = self.d.feed_modes[self.feed_mode.value]
        if code is None:
            if self.feed_mode == canon.FeedMode.INVERSE_TIME:
                self.lacking("CONV-INVERSE-TIME", "inverse-time feed (G93)", "substituted")
            else:
                self.refuse("CONV-FEED-PER-REV", f"{self.d.title} has no feed per revolution")
            code = self.d.feed_modes[0] if self.e_feed_mode.value else None
            self.e_feed_mode = self.feed_mode
            if code:
                self.block(code)
            return
        self.e_feed_mode = self.feed_mode
        self.e_feed = "F" + self.fmt.feed(0.0)  # RS274/NGC: a feed mode change zeroes F
        self.block(code)

    def flush_motion_mode(self) -> None:
        if self.mode is None:
            return
        mode, tol = self.mode
        want = (mode, tol, self.naive)
        if want == self.e_mode:
            return
        self.e_mode = want
        code = {
            canon.MotionMode.EXACT_STOP: self.d.exact_stop,
            canon.MotionMode.EXACT_PATH: self.d.exact_path,
            canon.MotionMode.CONTINUOUS: self.d.continuous,
        }[mode]
        if code is None:
            self.lacking("CONV-MOTION-MODE", f"{mode.name.lower()} mode")
            return
        words = [code]
        if mode == canon.MotionMode.CONTINUOUS and tol > 0:
            if self.d.blend_word:
                words.append(self.d.blend_word + self.fmt.length(tol))
                if self.naive is not None and self.d.naive_word and self.naive != tol:
                    words.append(self.d.naive_word + self.fmt.length(self.naive))
            else:
                self.lacking("CONV-MOTION-MODE", "blending tolerance (G64 P)", note=False)
        self.block(*words)

    def flush_coolant(self) -> None:
        want, have = self.coolant, self.e_coolant
        if (have["mist"] and not want["mist"]) or (have["flood"] and not want["flood"]):
            self.block(self.d.coolant_off)
            have["mist"] = have["flood"] = False
        for kind in ("mist", "flood"):
            if want[kind] and not have[kind]:
                code = getattr(self.d, kind)
                if code is None:
                    self.lacking("CONV-UNSUPPORTED", f"{kind} coolant code")
                else:
                    self.block(code)
                have[kind] = True

    def flush_spindle(self) -> None:
        words: list[str] = []
        if self.css != self.e_css:
            on, top = self.css
            if on and self.d.css is None:
                self.refuse("CONV-CSS", f"{self.d.title} has no constant surface speed")
            if on:
                for part in self.d.css.split("|"):  # type: ignore[union-attr]
                    if "{max}" in part and top <= 0:
                        part = " ".join(w for w in part.split() if "{max}" not in w)
                    if part:
                        speed = self.fmt.speed(self.surface(self.speed))
                        self.block(part.format(max=self.fmt.speed(top), speed=speed))
                self.e_speed = self.speed
            elif self.d.css_off:
                self.block(self.d.css_off)
            self.e_css = self.css
        if self.speed != self.e_speed:
            value = self.surface(self.speed) if self.css[0] else self.speed
            words.append("S" + self.fmt.speed(value))
            self.e_speed = self.speed
        if self.direction != self.e_direction:
            words.append(
                {
                    canon.Direction.CLOCKWISE: self.d.spindle_cw,
                    canon.Direction.COUNTERCLOCKWISE: self.d.spindle_ccw,
                    canon.Direction.STOPPED: self.d.spindle_stop,
                }[self.direction]
            )
            self.e_direction = self.direction
        self.block(*words)

    def surface(self, speed: float) -> float:
        """Surface speed in the output's m/min or ft/min (G96 S follows the length units)."""
        k_in = 12.0 if self.units == canon.Units.INCHES else 1000.0
        k_out = 12.0 if self.fmt.inch else 1000.0
        return speed * self.fmt.scale * k_in / k_out

    def feed_word(self, length: float | None = None) -> str:
        """The F word a feed motion needs, or '' when the emitted one is still right.

        In inverse-time mode the IR's feed is the per-minute rate the move works out to
        (as LinuxCNC's ``rs274`` and :mod:`gcode.interpreter` emit it), so the G93 word is
        rate / length; a dialect without G93 gets the per-minute rate (exact).
        """
        rate = self.feed * self.fmt.scale
        if self.feed_mode == canon.FeedMode.INVERSE_TIME and self.d.feed_modes[1] is not None:
            if not length:
                self.refuse("CONV-INVERSE-TIME", "inverse-time feed on a zero-length motion")
            word = "F" + self.fmt.feed(rate / length)  # type: ignore[operator]
            self.e_feed = None
            return word
        word = "F" + self.fmt.feed(rate)
        if word == self.e_feed:
            return ""
        self.e_feed = word
        return word

    # ------------------------------------------------------------------ positions
    def axis_words(self, target: dict[str, float], force: bool = False) -> list[str]:
        """Words for the axes whose written value changes (all when ``force``)."""
        words = []
        cur, known, axes, diameter = self.cur, self.words, self.d.axes, self.d.diameter
        for letter in "XYZABC":
            value = target[letter]
            if letter not in axes:
                if abs(value) > 1e-9:
                    self.refuse("CONV-AXIS", f"{self.d.title} has no {letter} axis")
                continue
            w = known[letter]
            if w is None or value != cur[letter]:  # unchanged floats need no formatting
                w = letter + self.fmt.number(2 * value if letter in diameter else value)
                if w != known[letter]:
                    known[letter] = w
                    cur[letter] = value
                    words.append(w)
                    continue
                cur[letter] = value
            if force:
                words.append(w)
        return words

    def written(self, letter: str) -> float:
        """The coordinate the text leaves the interpreter at (rounded), else the IR's."""
        w = self.words[letter]
        if not w:
            return self.cur[letter]
        return float(w[1:]) / 2 if letter in self.d.diameter else float(w[1:])

    def axis_text(self, letter: str, value: float) -> str:
        """One axis word for ``value`` (output units): doubled on a diameter axis."""
        return letter + self.fmt.length(2 * value if letter in self.d.diameter else value)

    def invalidate(self) -> None:
        """An offset changed: the interpreter's current program position is unknown."""
        self.words.update(dict.fromkeys("XYZ", None))

    def target(self, x: float, y: float, z: float, a: float, b: float, c: float) -> dict:
        s = self.fmt.scale
        return {"X": x * s, "Y": y * s, "Z": z * s, "A": a, "B": b, "C": c}

    def motion_code(self, code: str) -> str:
        if code == self.motion:
            return ""
        self.motion = code
        return code
