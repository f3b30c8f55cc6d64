"""Execution of one Siemens 840D NC block: its words -> modal state changes and IR.

The order within a block follows the RS274/NGC interpreter's (gcode.ngc.interpreter, NIST v3
Table 8) so the IR reads the same: feed mode, spindle mode, F, S, T, M6/D, spindle and
coolant M codes, dwell, plane, units, work offset, path control, distance mode, motion,
program end. 840D vocabulary: 840D sl programming manual, fundamentals, "List of G
functions" and "List of addresses".
"""

from __future__ import annotations

import math

from gcode.core import linuxcnc as lc
from gcode.core.corners import CornerRequest
from gcode.core.machine_functions import machine_function
from gcode.core.register_marks import ToolLengthRegister, WorkOffsetRegister
from gcode.siemens import motion
from gcode.siemens.blocks import DIAMETER, SUPPRESS, Assign, Block, Word
from gcode.siemens.cycles import run_cycle
from gcode.siemens.expr import Variables, evaluate
from gcode.siemens.machine import Machine, Values
from gcode.siemens.state import PLANES
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

INCH_MM = 25.4
#: G code -> modal group (840D groups: 1 motion, 2 non-modal, 6 plane, 8 settable frame,
#: 10 path control, 13 units, 14 distance, 15 feed type, 11 exact stop non-modal, 47 the
#: NC language: G290 Siemens mode, the mode this reader reads, so selecting it changes
#: nothing; G291, the ISO dialect mode (Fanuc syntax), is refused)
G_GROUPS: dict[int, int] = {
    0: 1, 1: 1, 2: 1, 3: 1, 33: 1,
    4: 2, 9: 11,
    17: 6, 18: 6, 19: 6,
    40: 7, 41: 7, 42: 7,
    54: 8, 55: 8, 56: 8, 57: 8, 500: 8,
    60: 10, 64: 10, 641: 10, 642: 10, 643: 10, 644: 10, 645: 10,
    601: 12, 602: 12, 603: 12,
    450: 18, 451: 18,
    70: 13, 71: 13, 700: 13, 710: 13,
    90: 14, 91: 14,
    53: 9, 153: 9,
    93: 15, 94: 15, 95: 15,
    96: 29, 97: 29,
    290: 47,
}  # fmt: skip
G_GROUPS.update(dict.fromkeys(range(505, 600), 8))
M_CODES = frozenset({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 17, 19, 30})
#: addresses an NC block may carry besides G and M
ADDRESSES = frozenset(
    {"X", "Y", "Z", "A", "B", "C", "I", "J", "K", "F", "S", "T", "D"}
    | {"CR", "AR", "TURN", "SPOS", "LIMS", "ADIS", "MEAS", "I1", "J1", "K1"}
    | {"CHF", "CHR", "RND", "RNDM"}
    | DIAMETER
    | SUPPRESS
)
#: system variables a part program reads (job planning and the system variables list):
#: the active tool and edge, feed and speed, positions per axis, the active settable frame;
#: the PLC inputs, the run-time timer and the block search and test flags read 0 (no
#: signal, at the program start, not in a search or test run)
_SYSTEM_ZERO = frozenset({"$A_IN", "$A_INA", "$AC_TIME", "$AN_SETUP_TIME", "$P_SEARCH"})
_SYSTEM_ZERO_ALSO = frozenset({"$P_ISTEST", "$AC_MARKER", "$AC_PARAM", "$P_DRYRUN"})
_PLANE_OF = {17: "XY", 18: "ZX", 19: "YZ"}
#: the words of a chamfer or rounding (RNDM= sets the modal rounding)
_CORNER_WORDS = frozenset({"CHF", "CHR", "RND", "RNDM"})
#: RS274/NGC's coordinate systems (G54-G59.3): the IR's SET_G5X_OFFSET indexes 1-9
G5X_SLOTS = 9


class Executor(Machine):
    """Executes 840D NC blocks on the modal machine of one run."""

    # ------------------------------------------------------------------ start
    def preamble(self, loc: Location) -> None:
        s = self.s
        self.loc = loc
        s.g5x = self._g5x_values(1)
        self.emit(canon.UseLengthUnits(s.units, source=loc))
        self.emit_offsets(g5x=True)
        self.emit(canon.SetFeedReference(canon.FeedReference.XYZ, source=loc))
        if self.compat:
            self.emit(lc.OnReset(source=loc))

    def _g5x_values(self, index: int) -> tuple[float, ...]:
        """A settable frame's offsets: RS274/NGC parameters 5221 + 20 (i - 1) + k from the
        options (the machine's offset table), else zero; G500 is zero, and so are frames
        10-99 (G510-G599), which no parameter of RS274/NGC holds."""
        if index == 0 or index > G5X_SLOTS:
            return (0.0,) * 6
        base = 5221 + 20 * (index - 1)
        return tuple(float(self.params.get(base + k, 0.0)) for k in range(6))

    def emit_offsets(self, g5x: bool = False) -> None:
        """Offsets after a change of the settable frame (``g5x``) or of the programmable
        frame's translation (SET_G92_OFFSET, as RS274/NGC does for G52)."""
        s, loc = self.s, self.loc
        t = (*s.frame.t, 0.0, 0.0, 0.0)
        if not self.compat:
            self.emit(
                canon.SetOriginOffsets(*(a + b for a, b in zip(s.g5x, t, strict=True)), source=loc)
            )
            return
        if g5x:
            if s.work == 0:
                self.emit(canon.SetOriginOffsets(0.0, 0.0, 0.0, source=loc))
            else:
                if self.options.register_marks:  # G510-G599 run in the ninth slot
                    self.emit(WorkOffsetRegister(s.work, source=loc))
                self.emit(lc.SetG5xOffset(min(s.work, G5X_SLOTS), *s.g5x, source=loc))
        self.emit(lc.SetG92Offset(*t, source=loc))
        if g5x and s.work != 0:
            self.emit(lc.SetXYRotation(0.0, source=loc))

    # ------------------------------------------------------------------ one block
    def evaluate(self, block: Block, scope: Variables) -> Values:
        """Words in their order; assignments take effect where they stand."""
        vals = Values()
        file = self.loc.file
        for item in block.items:
            if isinstance(item, Assign):
                value = evaluate(item.value, scope)
                loc = Location(file, block.line, item.col)
                target = item.target[1]
                if isinstance(target, str):  # ("V", name)
                    scope.set(target, value, loc)
                elif item.target[0] == "A":  # ("A", (name, index nodes))
                    name, index = target
                    scope.array_set(name, [evaluate(i, scope) for i in index], value, loc)
                else:  # ("R", index node)
                    scope.r_set(evaluate(target, scope), value, loc)
                continue
            self._word(vals, item, scope, block.line)
        return vals

    def _word(self, vals: Values, w: Word, scope: Variables, line: int) -> None:
        node = w.value
        if node[0] == "tool":
            value = float(self.tool_number(str(node[1])))
        else:
            value = node[1] if node[0] == "num" else evaluate(node, scope)
        self.word(vals, w.address, value, w.col, w.mode)

    def tool_number(self, name: str) -> int:
        """The IR's number for the tool management's tool ``name`` (``T="NAME"``): tools
        get 1, 2, ... in the order their names are first met, each named in a comment."""
        n = self.tool_names.get(name)
        if n is None:
            n = self.tool_names[name] = len(self.tool_names) + 1
            self.emit(canon.Comment(f'T="{name}" is tool {n}', source=self.loc))
        return n

    def system_variable(self, name: str, index: str | None, loc: Location) -> float:
        """The value of the system variable ``$name`` (``$name[index]``) a program reads."""
        s = self.s
        axis = "XYZABC".find(index) if index is not None and len(index) == 1 else -1
        if name in ("$A_IN", "$A_INA"):
            self.input_reads += 1  # a loop waiting on a PLC input never ends here
            return 0.0
        if name in _SYSTEM_ZERO or name in _SYSTEM_ZERO_ALSO:
            return 0.0
        if name == "$P_TOOLNO":
            return float(s.tool)
        if name == "$P_TOOL":
            return float(s.edge)
        if name == "$P_F":
            return s.feed
        if name in ("$P_S", "$AC_S"):
            return s.speed
        if name == "$P_UIFRNUM":
            return float(s.work)
        if name in ("$AA_IW", "$P_EP", "$AA_IM", "$AA_IB") and axis >= 0:
            if name != "$AA_IM":  # the work (program) position
                return motion.program_position(self)[axis] if axis < 3 else s.pos[axis]
            shift = s.frame.t[axis] if axis < 3 else 0.0  # the frame's translation
            return s.pos[axis] + shift + s.g5x[axis]  # the machine position
        what = f"{name}[{index}]" if index is not None else name
        raise Diagnostic("SIEM-UNSUPPORTED", f"system variable {what} is not supported", loc)

    def word(self, vals: Values, a: str, value: float, col: int, mode: str | None = None) -> None:
        """Add one evaluated word to the block's values (G and M codes checked here)."""
        if a == "CIP":
            if 1 in vals.g:
                raise Diagnostic("SIEM-G-GROUP", "CIP with another motion G code", self._col(col))
            vals.g[1] = motion.CIP
            return
        if a == "G":
            code = int(value) if value == int(value) else -1
            group = G_GROUPS.get(code)
            if code == 291:
                raise Diagnostic(
                    "SIEM-G-CODE",
                    "G291 switches to the ISO dialect (Fanuc syntax), which this reader does "
                    "not read (it reads Siemens mode, G290)",
                    self._col(col),
                )
            if group is None:
                raise Diagnostic(
                    "SIEM-G-CODE", f"G{value:g} is not supported by this reader", self._col(col)
                )
            if group in vals.g:
                raise Diagnostic(
                    "SIEM-G-GROUP", f"G{vals.g[group]} and G{code} are of one group", self._col(col)
                )
            vals.g[group] = code
            return
        if a == "M":
            code = int(value) if value == int(value) else -1
            if code < 0:
                raise Diagnostic(
                    "SIEM-M-CODE", f"M{value:g} is not supported by this reader", self._col(col)
                )
            if code in vals.m:
                raise Diagnostic("SIEM-M-CODE", f"M{code} twice in one block", self._col(col))
            vals.m.append(code)
            vals.cols[f"M{code}"] = col  # an M code outside M_CODES: a machine function
            return
        if a in SUPPRESS:
            vals.g[9] = 53
            return
        if a in DIAMETER:
            vals.g[16] = {"DIAMOF": 0, "DIAMON": 1, "DIAM90": 90}[a]
            return
        if a in vals.v:
            raise Diagnostic("SIEM-WORD", f"{a} twice in one block", self._col(col))
        if a not in ADDRESSES:
            raise Diagnostic("SIEM-WORD", f"{a} has no meaning in an NC block here", self._col(col))
        vals.v[a] = value
        vals.cols[a] = col
        if mode:
            vals.modes[a] = mode

    def _col(self, col: int) -> Location:
        return Location(self.loc.file, self.loc.line, col)

    def execute(self, block: Block, scope: Variables) -> bool:
        """Execute an NC block; True at the end of the program level (M2/M17/M30)."""
        return self.execute_values(self.evaluate(block, scope), scope)

    def execute_words(self, words: list[tuple[str, float, int]], scope: Variables) -> bool:
        """Execute a plain block read by the fast path (gcode.siemens.fastpath)."""
        vals = Values()
        for address, value, col in words:
            self.word(vals, address, value, col)
        return self.execute_values(vals, scope)

    def execute_values(self, vals: Values, scope: Variables) -> bool:
        """Execute a block's evaluated words (in the RS274/NGC interpreter's order)."""
        s = self.s
        g, v, m = vals.g, vals.v, vals.m
        dwell = g.get(2) == 4
        if 13 in g:
            self.set_units(g[13])  # the block's own lengths and F are in the new units
        if 15 in g:
            self._feed_mode(g[15])
        if 29 in g:
            self._spindle_mode(g[29], vals)
        elif "LIMS" in v:
            s.css_max = v["LIMS"]
            if s.css:
                self.emit(canon.SetSpindleMode(s.css_max, True, source=self.loc))
        if "F" in v and not dwell:
            self._feed(vals)
        if "S" in v and not dwell:
            if v["S"] < 0:
                raise Diagnostic("SIEM-NEGATIVE", "negative spindle speed", self.at(vals, "S"))
            s.speed = v["S"]
            self.emit(canon.SetSpindleSpeed(s.speed, source=self.loc))
        if "T" in v:
            self._select_tool(vals)
        if 6 in m:
            self._change_tool(vals)
        if "D" in v:
            self._edge(vals)
        self._spindle(vals)
        for code in m:
            if code not in M_CODES:  # the PLC's (M_CODES are the NC's own)
                at = self._col(vals.cols[f"M{code}"])
                self.emit(machine_function(code, None, None, at, "SIEM-M-CODE"))
        if dwell:
            motion.dwell(self, vals)
        if 6 in g:
            self._plane(_PLANE_OF[g[6]])
        if 8 in g:
            self.select_work(g[8])
        if "ADIS" in v:
            if v["ADIS"] < 0:
                raise Diagnostic("SIEM-NEGATIVE", "negative ADIS=", self.at(vals, "ADIS"))
            s.adis = v["ADIS"]
        if g.get(7) in (41, 42):
            self._radius_compensation(g[7])
        if 10 in g:
            self._control(g[10], vals)
        elif "ADIS" in v and s.control == 641:
            self._control(641, vals)
        if 14 in g:
            s.absolute = g[14] == 90
        if 16 in g:
            s.diameter = g[16]
        if s.diameter:
            self._diameters(vals)
        if 9 in g:
            self._machine_positions(vals)
        if 1 in g:
            s.motion = g[1]
        corner = s.rounding or not _CORNER_WORDS.isdisjoint(v)
        start = tuple(s.pos) if corner else ()
        moved = motion.execute(self, vals, g.get(11) == 9)
        if corner:
            self._corner(vals, start, moved)
        if moved and s.mcall is not None:
            if s.mcall[2]:
                self.modal_call_due = True  # a program file: the runner calls it
            else:
                run_cycle(self, s.mcall[0], s.mcall[1] or (), scope)
        for code in (0, 1):
            if code in m:
                cls = canon.ProgramStop if code == 0 else canon.OptionalProgramStop
                self.emit(cls(source=self.loc))
        return any(code in m for code in (2, 17, 30))

    def _corner(self, vals: Values, start: tuple[float, ...], moved: bool) -> None:
        """CHF= / CHR= / RND= (this block's corner) and RNDM= (every corner until RNDM=0)
        after a contour move (840D fundamentals, "Chamfer, rounding"): the runner cuts it
        when the next move comes (gcode.core.corners). As the 840D does, a corner too large
        for its moves is made smaller, and none is cut before a rapid, a move off the
        plane or the end."""
        s, v = self.s, vals.v
        if "RNDM" in v:
            if v["RNDM"] < 0:
                raise Diagnostic("SIEM-NEGATIVE", "negative RNDM=", self.at(vals, "RNDM"))
            s.rounding = v["RNDM"]
        asked = [k for k in ("CHF", "CHR", "RND") if k in v]
        if len(asked) > 1:
            asked.sort(key=lambda k: vals.cols.get(k, 0))
            raise Diagnostic(
                "SIEM-CORNER", f"{asked[0]}= and {asked[1]}= in one block", self.at(vals, asked[1])
            )
        if asked:
            key = asked[0]
            size = v[key]
            if size < 0:
                raise Diagnostic("SIEM-NEGATIVE", f"negative {key}=", self.at(vals, key))
            if not moved:
                raise Diagnostic(
                    "SIEM-CORNER", f"{key}= belongs to a block that moves", self.at(vals, key)
                )
        elif s.rounding > 0 and moved:
            key, size = "RNDM", s.rounding
        else:
            return
        if size == 0 or s.motion not in (1, 2, 3):
            return
        if not _turns_in_plane(s.frame.m, PLANES[s.plane][1][2]):
            raise Diagnostic(
                "SIEM-CORNER",
                f"{key}= under SCALE or a rotation out of the plane is not read",
                self.at(vals, key),
            )
        kind = {"CHF": "chamfer_length", "CHR": "chamfer"}.get(key, "round")
        at = self.at(vals, key)
        self.corner = CornerRequest(
            kind, size, start, PLANES[s.plane][0], at, shrink=True, lenient=True
        )

    # ------------------------------------------------------------------ state words
    def _feed_mode(self, code: int) -> None:
        s = self.s
        s.feed_mode = {94: 0, 93: 1, 95: 2}[code]
        self.emit(canon.SetFeedMode(canon.FeedMode(s.feed_mode), source=self.loc))
        if s.feed_mode != 1:
            s.feed = 0.0  # F must be programmed again after a change of feed type
            self.emit(canon.SetFeedRate(0.0, source=self.loc))

    def _spindle_mode(self, code: int, vals: Values) -> None:
        s = self.s
        s.css = code == 96
        if "LIMS" in vals.v:
            s.css_max = vals.v["LIMS"]
        self.emit(canon.SetSpindleMode(s.css_max if s.css else 0.0, s.css, source=self.loc))

    def _feed(self, vals: Values) -> None:
        s = self.s
        f = vals.v["F"]
        if f < 0:
            raise Diagnostic("SIEM-NEGATIVE", "negative feed", self.at(vals, "F"))
        if s.units_code == 70 and s.feed_mode != 1:
            f /= INCH_MM  # G70: lengths in inches, feed still in the metric basic system
        if s.feed_mode == 1:
            return  # G93: F belongs to the block's motion
        s.feed = f
        self.emit(canon.SetFeedRate(f, source=self.loc))

    def _select_tool(self, vals: Values) -> None:
        t = vals.v["T"]
        n = int(round(t))
        if t < 0 or abs(t - n) > 1e-9:
            raise Diagnostic(
                "SIEM-TOOL", "tool number must be a whole number >= 0", self.at(vals, "T")
            )
        if self.tools is not None and n not in self.tools:
            raise Diagnostic("SIEM-TOOL", f"tool {n} is not in the tool table", self.at(vals, "T"))
        self.s.selected_tool = n
        self.emit(canon.SelectTool(n, source=self.loc))

    def _change_tool(self, vals: Values) -> None:
        """M6: the selected tool goes in the spindle (the change cycle stops the spindle);
        its cutting edge D1 becomes active unless the block programs another D."""
        s = self.s
        n = s.selected_tool if s.selected_tool is not None else s.tool
        s.direction = canon.Direction.STOPPED
        if self.compat:
            self.emit(lc.StartChange(source=self.loc))
        self.emit(canon.StopSpindleTurning(source=self.loc))
        pocket = n
        if self.tools is not None:
            tool = self.tools.get(n)
            pocket = tool.pocket if tool is not None else n
        self.emit(canon.ChangeTool(pocket, source=self.loc))
        s.tool = n
        s.selected_tool = None
        if "D" not in vals.v:
            self.activate_edge(1 if n else 0)

    def _edge(self, vals: Values) -> None:
        d = vals.v["D"]
        n = int(round(d))
        if abs(d - n) > 1e-9 or n not in (0, 1):
            raise Diagnostic(
                "SIEM-TOOL-EDGE",
                f"D{d:g}: the tool table holds one cutting edge per tool (D1; D0 off)",
                self.at(vals, "D"),
            )
        self.activate_edge(n)

    def activate_edge(self, n: int) -> None:
        """Tool length of the active edge from the tool table (its Z offset), in program
        units: the table is in inches, as the RS274/NGC and Fanuc readers take it
        (gcode.ngc.offsets._table_scale)."""
        s = self.s
        s.edge = n
        length = 0.0
        if n and self.tools is not None:
            tool = self.tools.get(s.tool)
            scale = INCH_MM if s.units is canon.Units.MM else 1.0
            length = tool.z_offset * scale if tool is not None else 0.0
        s.pos[2] += s.tool_length - length
        s.tool_length = length
        if self.options.register_marks:  # the tool's edge: G43 H<tool> elsewhere
            mark = ToolLengthRegister("G43", s.tool, source=self.loc) if n and s.tool else None
            self.emit(mark or ToolLengthRegister("G49", None, source=self.loc))
        self.emit(canon.UseToolLengthOffset(length, source=self.loc))

    def _spindle(self, vals: Values) -> None:
        s = self.s
        loc = self.loc
        for code in vals.m:
            if code == 3:
                s.direction = canon.Direction.CLOCKWISE
                self.emit(canon.StartSpindleClockwise(source=loc))
            elif code == 4:
                s.direction = canon.Direction.COUNTERCLOCKWISE
                self.emit(canon.StartSpindleCounterclockwise(source=loc))
            elif code == 5:
                s.direction = canon.Direction.STOPPED
                self.emit(canon.StopSpindleTurning(source=loc))
            elif code == 19:
                self._orient(0.0)
        if "SPOS" in vals.v:
            self._orient(vals.v["SPOS"])
        for code in vals.m:
            if code == 7:
                self.emit(canon.MistOn(source=loc))
            elif code == 8:
                self.emit(canon.FloodOn(source=loc))
            elif code == 9:
                self.emit(canon.MistOff(source=loc))
                self.emit(canon.FloodOff(source=loc))

    def _orient(self, angle: float) -> None:
        """SPOS= (M19: the setting-data angle, taken as 0): spindle in position mode."""
        if not 0.0 <= angle < 360.0:
            raise Diagnostic("SIEM-SPOS", f"SPOS={angle:g} must be within 0..360 degrees", self.loc)
        self.s.direction = canon.Direction.STOPPED
        self.emit(canon.OrientSpindle(angle, canon.Direction.CLOCKWISE, source=self.loc))

    def _plane(self, name: str) -> None:
        self.s.plane = name
        self.emit(canon.SelectPlane(PLANES[name][0], source=self.loc))

    def set_units(self, code: int) -> None:
        s = self.s
        units = canon.Units.INCHES if code in (70, 700) else canon.Units.MM
        if units is not s.units:
            k = 1 / INCH_MM if units is canon.Units.INCHES else INCH_MM
            for i in range(3):
                s.pos[i] *= k
            s.frame = s.frame.scaled(k)
            s.g5x = tuple(v * k if i < 3 else v for i, v in enumerate(s.g5x))
            s.tool_length *= k  # part of pos[2], scaled with it
            s.units = units
            self.emit(canon.UseLengthUnits(units, source=self.loc))
            if s.feed and s.feed_mode != 1:  # the programmed feed keeps its speed
                s.feed *= k
                self.emit(canon.SetFeedRate(s.feed, source=self.loc))
        else:
            self.emit(canon.UseLengthUnits(units, source=self.loc))
        s.units_code = code

    def select_work(self, code: int) -> None:
        """G54-G57, G505-G599 (settable frames 1-4, 5-99) and G500 (none). Frames 10-99
        go to the IR in the last of RS274/NGC's nine coordinate systems (SET_G5X_OFFSET 9
        with the frame's values), as the Fanuc reader does with G54.1 P."""
        s = self.s
        index = 0 if code == 500 else code - 53 if code < 100 else code - 500
        old = s.g5x
        s.work = index
        s.g5x = self._g5x_values(index)
        for i in range(3):
            s.pos[i] += old[i] - s.g5x[i]
        self.emit_offsets(g5x=True)

    def _radius_compensation(self, code: int) -> None:
        """G41/G42 with the active edge's radius from the tool table: a radius of 0 (no tool
        table, D0, a tool without diameter) leaves the path as programmed, as the control's
        compensation of a zero radius does; a radius above 0 is refused (the reader does not
        offset 840D contours)."""
        s = self.s
        tool = self.tools.get(s.tool) if self.tools is not None and s.edge else None
        radius = tool.diameter / 2.0 if tool is not None else 0.0
        if radius > 1e-12:
            raise Diagnostic(
                "SIEM-COMP",
                f"G{code} with tool {s.tool} of radius {radius:g}: tool radius compensation "
                "of a non-zero radius is not computed by this reader",
                self.loc,
            )

    def _diameters(self, vals: Values) -> None:
        """DIAMON: X (and the X of CIP's intermediate point, I1) is a diameter, absolute and
        incremental; DIAM90: a diameter under G90 or AC only. The IR carries radii; centre
        words I stay radii (fundamentals, "Dimensions for turning")."""
        s = self.s
        for letter in ("X", "I1"):
            if letter in vals.v:
                mode = vals.modes.get(letter)
                absolute = mode == "AC" or (mode is None and s.absolute)
                if s.diameter == 1 or absolute:
                    vals.v[letter] /= 2.0

    def _machine_positions(self, vals: Values) -> None:
        """G53, G153, SUPA (non-modal): the block's absolute X Y Z are machine positions of
        the tool's controlled point, all frames suppressed (fundamentals, "Frame
        suppression"); the tool offset stays. They become program positions by taking off
        the work offset and the frame's translation; under a rotated, scaled or mirrored
        frame the block is refused."""
        s = self.s
        if s.frame.linear:
            raise Diagnostic(
                "SIEM-UNSUPPORTED",
                "G53/G153/SUPA under a rotated, scaled or mirrored frame is not read",
                self.loc,
            )
        for k, letter in enumerate("XYZ"):
            if letter in vals.v:
                mode = vals.modes.get(letter)
                if mode == "AC" or (mode is None and s.absolute):
                    vals.v[letter] -= s.g5x[k] + s.frame.t[k]
                    vals.modes[letter] = "AC"

    def _control(self, code: int, vals: Values) -> None:
        s = self.s
        if code in (643, 644, 645):
            code = 642  # blending with the machine's tolerances, as G642
        s.control = code
        if code == 60:
            self.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP, source=self.loc))
            return
        tol = s.adis if code == 641 else 0.0
        self.emit(canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, tol, source=self.loc))


def _turns_in_plane(m: tuple[tuple[float, float, float], ...], normal: int) -> bool:
    """True when the frame's matrix ``m`` turns or mirrors within the plane of ``normal``
    (or is none): lengths, angles and the plane stay as programmed, so the corner cut in
    the IR is the programmed one, moved."""
    for r in range(3):
        for c in range(3):
            dot = sum(m[r][k] * m[c][k] for k in range(3))
            if not math.isclose(dot, 1.0 if r == c else 0.0, abs_tol=1e-12):
                return False
    return math.isclose(m[normal][normal], 1.0, abs_tol=1e-12)
