"""The state a block-structured G-code writer keeps, and what its handlers call.

:class:`WriterContext` holds the IR state (what the program set) beside the emitted state
(what the text set), writes blocks and comments, records changes, flushes modal words before
a motion and formats positions. The per-command handlers (:mod:`gcode.write.handlers`,
:mod:`gcode.write.curves`, :mod:`gcode.write.cycles`, :mod:`gcode.write.extras`) and the bulk
writer (:mod:`gcode.write.bulk`) receive it; :class:`gcode.write.writer.BlockWriter` extends it with
the driver that dispatches commands to them, so none of them imports the writer back.
"""

from __future__ import annotations

from typing import NoReturn

from gcode.core.register_marks import ToolLengthRegister
from gcode.ngc.lane.fastlane import GcodeLayout
from gcode.write.options import WriterOptions
from gcode.write.report import Change, ConversionReport, machinist
from gcode.write.spec import Dialect
from gcode.write.state import Formatter
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

#: path control modes as the machinist writes them
_PATH_MODES = {
    canon.MotionMode.EXACT_STOP: "G61.1 (exact stop)",
    canon.MotionMode.EXACT_PATH: "G61 (exact path)",
    canon.MotionMode.CONTINUOUS: "G64 (continuous path)",
}


class WriterContext:
    """A block writer's state and output, without the command dispatch."""

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
        self.e_work = 1  # G54 (a work offset number, gcode.core.register_marks)
        self.work_register: int | None = None  # the next SET_G5X_OFFSET's number (its mark)
        self.e_rotation = 0.0
        self.e_local: tuple[float, ...] = (0.0,) * 6
        self.frame: tuple[str, ...] = ()  # the blocks of the last frame written (_frame)
        self.comp_radius = 0.0
        self.comp_on = False  # G41/G42 written and not yet G40
        self.file: str | None = None  # the source program (locations of bulk runs)
        self.comp_register: int | None = None  # the next G41/G42's D register (CompRegister)
        self.tool_register: ToolLengthRegister | None = None  # the next tool length's mark
        self.length_register: int | None = None  # the G43 H register in force (None: none)
        self.motion: str | None = None
        # positions in output units: the IR's (exact) and what the text set (rounded)
        self.cur = dict.fromkeys("XYZABC", 0.0)
        self.words: dict[str, str | None] = dict.fromkeys("XYZ", None)
        self.words.update({k: k + self.fmt.angle(0.0) for k in "ABC"})  # rotaries start at 0
        self.started = False
        self.noted: set[str] = set()
        self.cycle: tuple[object, ...] | None = None  # the modal cycle block last written
        self.skipping = False  # inside a kept cycle's moves (gcode.write.cycles)
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

    def change(
        self,
        code: str,
        kind: str,
        message: str,
        pieces: int = 0,
        deviation: float | None = None,
        tolerance: float | None = None,
    ) -> None:
        """Record one place where the output differs from the IR (at the command's source)."""
        self.report.add(Change(code, kind, message, self.src, pieces, deviation, tolerance))

    def lacking(self, code: str, what: str, kind: str = "dropped", note: bool = True) -> None:
        """The target lacks ``what``: refuse, or record ``kind`` and go on."""
        if self.o.on_missing == "refuse":
            raise Diagnostic(code, f"{self.d.title} has no {what}", self.src)
        self.change(code, kind, f"{self.d.title} has no {what}")
        if note and kind == "dropped":
            self.comment(f"{what}: not written")

    def refuse(self, code: str, message: str) -> NoReturn:
        """Stop the conversion with a located ``code`` diagnostic."""
        raise Diagnostic(code, message, self.src)

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
        if code is None and mode == canon.MotionMode.EXACT_PATH and self.d.exact_stop:
            # the stricter mode keeps the path; only the stops at block ends are added
            code = self.d.exact_stop
            self.change(
                "CONV-PATH-MODE",
                "substituted",
                f"{_PATH_MODES[mode]} written as {code} (exact stop): the same path",
            )
        if code is None and mode == canon.MotionMode.CONTINUOUS:
            # the target stays in an exact mode: the path is followed closer, not further
            self.lacking("CONV-PATH-MODE", _PATH_MODES[mode])
            return
        if code is None:
            self.lacking("CONV-MOTION-MODE", _PATH_MODES[mode])
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
                    self.lacking("CONV-COOLANT", machinist(kind.upper() + "_ON"))
                else:
                    self.block(code)
                have[kind] = True

    def flush_spindle(self) -> None:
        words: list[str] = []
        if self.css != self.e_css:
            on, top = self.css
            if on:
                css = self.d.css
                if css is None:
                    self.refuse("CONV-CSS", f"{self.d.title} has no constant surface speed")
                for part in css.split("|"):
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
        (as LinuxCNC's ``rs274`` and :mod:`gcode.ngc.interpreter` emit it), so the G93 word is
        rate / length; a dialect without G93 gets the per-minute rate (exact).
        """
        rate = self.feed * self.fmt.scale
        if self.feed_mode == canon.FeedMode.INVERSE_TIME and self.d.feed_modes[1] is not None:
            if not length:
                self.refuse("CONV-INVERSE-TIME", "inverse-time feed on a zero-length motion")
            word = "F" + self.fmt.feed(rate / length)
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
