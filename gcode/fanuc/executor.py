"""Executing one evaluated Fanuc block on the RS274/NGC machine model.

The Fanuc layer handles what the RS274/NGC executor (:mod:`gcode.ngc.interpreter`) does not
know or means differently, and hands it the rest as :class:`gcode.core.codes.Words`, so motion,
arcs (:mod:`gcode.core.arcs`), canned cycles (:mod:`gcode.ngc.cycles`), cutter compensation
(:mod:`gcode.ngc.comp.cutter_comp`), offsets (:mod:`gcode.ngc.offsets`) and M codes run exactly as
there. Fanuc-only here: G04 X/P, G05.1, G06.2 NURBS, G09, G10 L10-L13 offsets, G15/G16,
G31 skip (one shot), G50/G51, G50.1/G51.1, G61 = exact stop, G68/G69, G92 S, G44, K repeat
counts, M98/M99/G65/G66 (returned to the flow as actions), Haas G187/G47/M97/M50, and M
codes the control does not define, which go to the machine as MACHINE_FUNCTION events.
"""

from __future__ import annotations

from collections.abc import Sequence

from gcode.core.codes import G_GROUPS, Words
from gcode.core.corners import CornerRequest
from gcode.core.machine_functions import machine_function
from gcode.core.state import CompCode
from gcode.fanuc import cycles, groups, moves, offsets
from gcode.fanuc.lexer import WordValue
from gcode.fanuc.state import Action, ExecutorState, ModalCall
from gcode.fanuc.words import ARGUMENTS, CYCLES, MOTION, resolve
from gcode.ngc.comp.cutter_comp import CutterCompensator
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import MotionMode, Plane, Units

#: NGC-known codes the Fanuc layer passes on unchanged (round(G*10))
_PASS = frozenset(
    {0, 10, 20, 30, 170, 180, 190, 200, 210, 400, 410, 420, 490, 540, 550, 560, 570, 580, 590}
    | {640, 730, 740, 800, 810, 820, 830, 840, 850, 860, 880, 890, 900, 910, 930, 940, 950}
    | {960, 970, 980, 990, 280, 300, 520, 530, 920}
)
#: Fanuc codes handled here
_OWN = frozenset(
    {40, 51, 62, 90, 100, 150, 160, 310, 330, 430, 440, 500, 510, 501, 511, 610, 630, 650}
    | {660, 670, 680, 690, 760, 870, 541}
)
#: codes whose X Y Z ... words are settings (centre, axis, offset), not a move
_SETTING = frozenset({100, 500, 501, 510, 511, 680})
_HAAS = frozenset({1870, 470, 1030, 1540})
_HAAS_MILL = {**groups.MILL, **groups.HAAS_MILL}
#: group 01 codes the NGC words carry (G06.2 runs here)
_GROUP01 = frozenset({0, 10, 20, 30, 330})
_M_PASS = {0: 4, 1: 4, 2: 4, 30: 4, 60: 4, 3: 7, 4: 7, 5: 7, 19: 7, 6: 6, 7: 8, 8: 8, 9: 8}
_M_PASS.update({48: 9, 49: 9})
_M_FLOW = frozenset({98, 99, 97})


def ngc_m_code(m: int, pallet_m50: bool) -> int:
    """The RS274/NGC machine model's M code for a Fanuc one: M30 ends and rewinds like
    M2 (LinuxCNC's M30 also shuttles the pallets, a Fanuc's does not); Haas M50 is the
    pallet change M60."""
    if m == 30:
        return 2
    if m == 50 and pallet_m50:
        return 60
    return m


_PLAIN_LETTERS = {a: a.lower() for a in "XYZIJKRF"}
_PLANES = {170: Plane.XY, 180: Plane.XZ, 190: Plane.YZ}


class Executor(ExecutorState):
    """Executes Fanuc blocks on the per-run state around the RS274/NGC machine model."""

    # ------------------------------------------------------------------ entry
    def block(self, items: list[tuple[str, int | float, int]], loc: Location) -> list[Action]:
        """Execute the evaluated words of one block; the flow actions it asks for."""
        ip = self.ip
        s = ip.s
        ip.loc = loc
        if self.plain_ok and self._plain(items):
            return []
        gs: list[int] = []
        ms: list[int] = []
        raw: dict[str, int | float] = {}
        cols: dict[str, int] = {}
        for letter, val, col in items:
            at = Location(loc.file, loc.line, col)
            if letter == "G":
                gs.append(_code(val, "G", at))
                cols.setdefault(f"G{gs[-1]}", col)
            elif letter == "M":
                m = _code(val, "M", at)
                if m % 10:
                    raise Diagnostic("FANUC-BAD-M", f"bad M code M{val}", at)
                ms.append(m // 10)
                cols.setdefault(f"M{m // 10}", col)
            elif letter in ("N", "O"):
                raise Diagnostic("FANUC-SYNTAX", f"{letter} word inside a block", at)
            else:
                if letter in raw:
                    raise Diagnostic(
                        "FANUC-DUPLICATE-WORD", f"more than one {letter} word in a block", at
                    )
                raw[letter] = val
                cols[letter] = col
        table = self.groups
        for code in gs:
            if code not in table:
                at = Location(loc.file, loc.line, cols[f"G{code}"])
                raise Diagnostic("FANUC-UNKNOWN-G", f"unsupported G code {groups.name(code)}", at)
        gs = groups.last_of_each_group(gs, table)  # of one group, the last code counts
        gset = set(gs)
        if 470 in gset:
            raise Diagnostic(
                "HAAS-ENGRAVING", "G47 engraving is not read (text to strokes is out of scope)", loc
            )
        inch = 200 in gset or (210 not in gset and s.units is Units.INCHES)
        motion = next((c for c in reversed(gs) if c in MOTION), None)
        has_axis = any(a in raw for a in "XYZABCUVW")
        # G80 cancels the cycle; group 01 stays as it was
        motion_now = self.group01 if motion is None and 800 in gset else self.motion
        run_motion = motion if motion is not None else (motion_now if has_axis else None)
        cycle = run_motion in CYCLES and self.lathe is None
        nurbs = 62 in gset or (self.nurbs is not None and motion is None)
        v = resolve(raw, inch, gset, cycle, nurbs, self.fl.dwell_p_point_seconds)
        corner = {k: v.pop(k) for k in (",C", ",R", ",A") if k in v}
        if corner:
            self._corner_allowed(corner, cols, loc)
        start = tuple(s.pos) if corner else ()
        if self.lathe is not None:
            return self.lathe.block(gs, ms, v, cols, raw, loc)
        actions = self.mill(gs, ms, v, cols, loc, motion, has_axis)
        if corner:
            self._corner(corner, start, cols, loc)
        return actions

    @property
    def groups(self) -> dict[int, int]:
        """The G code group table of this control (gcode.fanuc.groups)."""
        if self.lathe is not None:
            return groups.LATHE
        if self.fl.haas_g_codes:
            return _HAAS_MILL
        return groups.MILL

    @property
    def plain_ok(self) -> bool:
        """No state that makes a plain G00-G03 block special (the CAM hot path)."""
        tf = self.tf
        return (
            self.lathe is None
            and self.nurbs is None
            and self.modal_call is None
            and not tf.polar
            and not tf.scale_on
            and not tf.rotate_on
            and tf.mirror == [None, None, None]
        )

    def _plain(self, items: Sequence[tuple[str, WordValue, int]]) -> bool:
        """Run a block of only G00-G03 and X Y Z I J K R F words; False if it is not one."""
        ip = self.ip
        s = ip.s
        code = None
        values: dict[str, float] = {}
        inc = 0.0001 if s.units is Units.INCHES else 0.001
        for letter, val, _ in items:
            if letter == "G":
                if code is not None or type(val) is not int or val > 3:
                    return False
                code = val * 10
            elif letter in _PLAIN_LETTERS:
                low = _PLAIN_LETTERS[letter]
                if low in values:
                    return False
                if type(val) is int:
                    values[low] = float(val) if low == "f" else val * inc
                elif isinstance(val, tuple):  # an expression (never in a plain block)
                    return False
                else:
                    values[low] = val
            else:
                return False
        if code is None:
            motion = self.motion
            moves = len(values) != ("f" in values)
            if moves and motion not in (0, 10, 20, 30):
                return False
            w = Words(values=values)
            if "f" not in values and values and s.motion_mode == motion:
                w.plain = True  # the RS274/NGC executor's own hot path: modal motion
            elif moves and motion is not None:  # G00-G03 (checked above)
                w.g[1] = motion
        else:
            w = Words(g={1: code}, values=values)
            self.motion = code
            self.group01 = code
        ip.execute(w)
        s.motion_mode = self.motion
        return True

    # ------------------------------------------------------------------ mill
    def mill(
        self,
        gs: list[int],
        ms: list[int],
        v: dict[str, float],
        cols: dict[str, int],
        loc: Location,
        motion: int | None,
        has_axis: bool,
    ) -> list[Action]:
        ip = self.ip
        s = ip.s
        gset = set(gs)
        actions: list[Action] = []
        if 650 in gset:  # G65 P L arguments: a call and nothing else
            return [self._g65(v, loc)]
        if 660 in gset:
            self.modal_call = self._g66(v, loc)
            return []
        if 670 in gset:
            self.modal_call = None
        if self.nurbs is not None and (gs or ms) and 62 not in gset:
            raise Diagnostic(
                "FANUC-NURBS-INCOMPLETE", "G06.2 curve ended before its last knots", loc
            )
        if 62 in gset or (self.nurbs is not None and not gs and not ms):
            self.nurbs = moves.nurbs_block(self, v, loc, start=62 in gset)
            self.motion = 62 if self.nurbs is not None else 10
            self.group01 = self.motion
            return []
        for letter in "UVW":
            if letter in v and not (letter == "U" and 40 in gset):
                raise Diagnostic(
                    "FANUC-WORD", f"{letter} word: no such axis or use on this mill", loc
                )
        if "E" in v and 1870 not in gset:
            raise Diagnostic("FANUC-WORD", "E word with no code that uses it", loc)
        # ---- modal settings the NGC executor does not have
        plane = next((_PLANES[c] for c in reversed(gs) if c in _PLANES), s.plane)
        distance = [c for c in gs if c in (900, 910)]
        absolute = distance[-1] == 900 if distance else s.absolute
        if 150 in gset or 160 in gset:
            on = 160 in gset
            self.tf.polar = (not on) if self.fl.polar_book_convention else on
        if 510 in gset:
            moves.start_scaling(self, v, loc)
        elif 500 in gset:
            self.tf.scale_on = False
        if 511 in gset:
            moves.start_mirror(self, v, loc, absolute)
        elif 501 in gset:
            moves.stop_mirror(self, v)
        if 680 in gset:
            moves.start_rotation(self, v, plane, absolute, loc)
        elif 690 in gset:
            self.tf.rotate_on = False
        if 51 in gset:
            self._g05_1(v, loc)
        if 1870 in gset:
            self._g187(v, loc)
        if 541 in gset or 1540 in gset:
            offsets.extended_select(self, v, loc)
        elif any(540 <= c <= 590 for c in gset):
            self.extended_selected = None
        if 100 in gset:
            self._g10(v, loc, absolute)
            if len(gset) == 1 and not ms:
                return []
        if gset & _SETTING:  # their axis and value words are data, not a move
            for letter in "XYZABCIJKRPQL":
                v.pop(letter, None)
        # ---- words for the NGC executor
        w = Words()
        for code in gs:
            if code in _PASS:
                w.g[G_GROUPS[code]] = code  # Fanuc: of one group, the last code counts
        if 610 in gset:
            w.g[13] = 611  # Fanuc G61 = exact stop check mode
        for code in (610, 640):
            if code in gset:
                self.control = code
        if 40 in gset:
            w.g[0] = 40
            if "X" in v or "P" in v or "U" in v:
                w.values["p"] = v.pop("X", v.pop("U", v.pop("P", 0.0)))
            else:
                raise Diagnostic("FANUC-DWELL", "G04 without X, U or P", loc)
        if 430 in gset or 440 in gset or ("H" in v and s.tool_length_mode in (430, 431)):
            self._tool_length(w, v, 440 in gset, loc)
        if "D" in v and (410 in gset or 420 in gset):
            self._radius(w, v)
        new_radius = offsets.comp_reissued(self, w, loc)
        has_axis = any(a in v for a in "XYZABC")
        pass_letters = "XYZABCFSTIJKRQ"
        for code in (760, 870):
            if code in gset:
                w.g[1] = code
        cycle = w.g.get(1) if w.g.get(1) in CYCLES else None
        if cycle is None and motion is None and self.motion in CYCLES and has_axis:
            cycle = self.motion
        if cycle is not None:
            pass_letters += "PL"
            if cycle in (730, 810, 850):  # no dwell in these cycles: a P is not read
                v.pop("P", None)
            if "K" in v:
                k = v.pop("K")
                if k != round(k) or not 0 <= k <= 9999:
                    raise Diagnostic("FANUC-CYCLE-L", f"repeat count K{k:g} not in 0-9999", loc)
                w.values["l"] = k
        if 920 in gset and not any(a in v for a in "XYZABC") and "S" in v:
            self._spindle_clamp(v.pop("S"), loc)
            w.g.pop(0, None)
        for letter in pass_letters:
            if letter in v:
                w.values[letter.lower()] = v[letter]
                w.columns[letter.lower()] = cols.get(letter, loc.column)
        if 330 in gset or (motion is None and self.motion == 330 and has_axis):
            w.g[1] = 330  # G33 Z F(lead): F is the lead (and stays the modal F)
            w.values["k"] = w.values.get("f", s.feed_rate)
        if 310 in gset:
            w.g[1] = 382  # G31 skip: a one-shot probing move
        if 90 in gset:
            ip.emit(canon.SetMotionControlMode(MotionMode.EXACT_STOP, source=loc))
        if 530 in gset:
            w.g[1] = 0  # G53 positions at rapid traverse (one shot)
            if not absolute and w.g.get(0) == 530:
                # G91 G53: an increment in the machine coordinate system (30i), which is the
                # same increment in the program system (no offset changes one)
                del w.g[0]
        # ---- M codes
        machine: list[int] = []  # M codes the control hands to the machine (PLC)
        for m in ms:
            if m in _M_FLOW and (m != 97 or self.fl.local_call):
                continue
            if m == 29:  # rigid tapping mode: G84 taps synchronised anyway
                continue
            m = ngc_m_code(m, self.fl.pallet_m50)
            group = _M_PASS.get(m)
            if group is None:
                machine.append(m)
                continue
            if group in w.m:
                raise Diagnostic("FANUC-M-GROUP-CONFLICT", "two M codes of one group", loc)
            w.m[group] = m
            if m == 19 and "P" in v and self.fl.m19_p_angle:
                w.values["r"] = v["P"] % 360.0  # Haas M19 P angle
            if m == 19 and "q" in w.values:
                w.values.pop("q")
        if machine:
            machine_events(self, machine, gs, ms, v, w, cols, loc)
        # ---- motion group bookkeeping and transforms
        block_g01 = next((c for c in reversed(gs) if c in _GROUP01), None)
        if block_g01 is not None:
            self.group01 = block_g01
        if w.g.get(1) == 800:  # G80 (group 09): the cycle ends, group 01 is untouched
            if block_g01 is not None:
                w.g[1] = block_g01  # G00 G80 X..: the motion runs (and ends NGC's cycle)
            elif has_axis and w.g.get(0) is None:
                w.g[1] = self.group01 if self.group01 is not None else 800
        if 1 in w.g and w.g[1] != 382 and 530 not in gset:
            self.motion = self.group01 if w.g[1] == 800 else w.g[1]
        one_shot = 310 in gset or 530 in gset
        previous = s.motion_mode if s.cycle_series else None
        moving = (1 in w.g and w.g[1] != 800) or (
            has_axis and w.g.get(0) not in (280, 300, 920, 520, 100)
        )
        transformed = moving and (self.tf.active or self.tf.polar) and w.g.get(0) is None
        if transformed and not one_shot:
            moves.transform_block(self, w, plane, absolute, loc)
        if moving and 1 not in w.g and self.motion is not None:
            w.g[1] = self.motion  # Fanuc's modal motion (the NGC one may be a one-shot)
        tapping = w.g.get(1) if w.g.get(1) in cycles.OWN else None
        if tapping is not None:  # Fanuc tapping: the motion runs here, the rest in NGC
            motion_words = Words(values=w.values)
            w = Words(g={k: c for k, c in w.g.items() if k != 1}, m=w.m)
            for letter in "fs":
                if letter in motion_words.values:
                    w.values[letter] = motion_words.values.pop(letter)
        ended = ip.execute(w) if (w.g or w.m or w.values) else False
        if new_radius is not None and isinstance(ip.comp, CutterCompensator):
            ip.comp.change_radius(new_radius, loc)  # Fanuc: from this block's end
        if tapping is not None:
            cycles.run(self, motion_words, tapping, sticky=previous == tapping)
        if transformed:
            s.absolute = absolute
        s.motion_mode = self.motion
        if 90 in gset:
            ip.emit(canon.SetMotionControlMode(_mode(self.control), source=loc))
        if ended:
            return [Action("end")]
        # ---- flow after the block
        if self.modal_call is not None and moving and self.depth == self.modal_call.depth:
            mc = self.modal_call
            actions.append(Action("g65", mc.number, mc.repeats, dict(mc.args)))
        actions += self._flow_m(ms, v, loc)
        return actions

    # ------------------------------------------------------------------ ,C and ,R
    def _corner_allowed(
        self, corner: dict[str, float], cols: dict[str, int], loc: Location
    ) -> None:
        """Refuse the corners this reader does not cut, at their word: ,A (direct drawing
        dimension angles), both ,C and ,R, a lathe's corners, corners under cutter
        compensation or a programmable transform."""
        first = min(cols[k] for k in corner)
        at = Location(loc.file, loc.line, first)
        why = None
        if ",A" in corner:
            why = "direct drawing dimension input (,A angle) is not read"
        elif len(corner) > 1:
            why = "a block asks for both a chamfer (,C) and a corner R (,R)"  # PS0055-style
        elif self.lathe is not None:
            why = "chamfer and corner R (,C / ,R) are read on mills only"
        elif self.ip.s.comp_side is not CompCode.G40 or "G410" in cols or "G420" in cols:
            why = "chamfer and corner R (,C / ,R) under cutter compensation are not read"
        elif self.tf.active or self.tf.polar:
            why = "chamfer and corner R (,C / ,R) under G16/G51/G51.1/G68 are not read"
        if why is not None:
            raise Diagnostic("FANUC-CORNER", why, at)

    def _corner(
        self,
        corner: dict[str, float],
        start: tuple[float, ...],
        cols: dict[str, int],
        loc: Location,
    ) -> None:
        """Mark this block's move for the chamfer (,C leg length) or corner R (,R radius)
        the flow cuts when the next move comes (Fanuc 0i-MF, "Chamfering and corner R":
        G01 or G02/G03 blocks; the next block must move in the same plane)."""
        ((key, size),) = corner.items()
        at = Location(loc.file, loc.line, cols[key])
        if self.motion not in (10, 20, 30):
            raise Diagnostic("FANUC-CORNER", f"{key} belongs to a G01, G02 or G03 block", at)
        if size <= 0:
            raise Diagnostic("FANUC-CORNER", f"{key} must be positive", at)
        kind = "round" if key == ",R" else "chamfer"
        self.corner = CornerRequest(kind, size, start, self.ip.s.plane, at)

    # ------------------------------------------------------------------ helpers
    def _flow_m(self, ms: list[int], v: dict[str, float], loc: Location) -> list[Action]:
        out = []
        for m in ms:
            if m == 98:
                out.append(self._m98(v, loc))
            elif m == 97 and self.fl.local_call:  # else a machine function (block above)
                if "P" not in v:
                    raise Diagnostic("FANUC-CALL", "M97 without P (sequence number)", loc)
                out.append(Action("m97", 0, _count(v.get("L", 1.0), loc), seq=int(v["P"])))
            elif m == 99:
                seq = int(v["P"]) if "P" in v else None
                out.append(Action("m99", seq=seq))
        return out

    def _m98(self, v: dict[str, float], loc: Location) -> Action:
        if "P" not in v:
            raise Diagnostic("FANUC-CALL", "M98 without P (program number)", loc)
        p = int(v["P"])
        repeats = _count(v.get("L", 1.0), loc)
        if self.fl.repeat_in_p and "L" not in v and p > 9999:
            repeats, p = p // 10000, p % 10000
        return Action("m98", p, repeats)

    def _g65(self, v: dict[str, float], loc: Location) -> Action:
        if "P" not in v:
            raise Diagnostic("FANUC-CALL", "G65 without P (program number)", loc)
        args = {ARGUMENTS[k]: val for k, val in v.items() if k in ARGUMENTS}
        return Action("g65", int(v["P"]), _count(v.get("L", 1.0), loc), args)

    def _g66(self, v: dict[str, float], loc: Location) -> ModalCall:
        act = self._g65(v, loc)
        return ModalCall(act.number, act.repeats, act.args, self.depth)

    def _g05_1(self, v: dict[str, float], loc: Location) -> None:
        q = v.get("Q")
        if q is None or q not in (0.0, 1.0):
            raise Diagnostic("FANUC-G05-1", "G05.1 needs Q1 (on) or Q0 (off)", loc)
        mode = MotionMode.CONTINUOUS if q == 1.0 else _mode(self.control)
        self.ip.emit(canon.SetMotionControlMode(mode, source=loc))

    def _g187(self, v: dict[str, float], loc: Location) -> None:
        """Haas G187 P1-P3 smoothness, E corner tolerance: continuous blending."""
        tol = v.get("E", 0.0)
        if "P" in v and int(v["P"]) not in (1, 2, 3):
            raise Diagnostic("HAAS-G187", "G187 P must be 1, 2 or 3", loc)
        self.ip.emit(canon.SetMotionControlMode(MotionMode.CONTINUOUS, tol, source=loc))

    def _g10(self, v: dict[str, float], loc: Location, absolute: bool) -> None:
        offsets.g10(self, v, loc, absolute)

    def _tool_length(self, w: Words, v: dict[str, float], negative: bool, loc: Location) -> None:
        offsets.tool_length(self, w, v, negative, loc)

    def _radius(self, w: Words, v: dict[str, float]) -> None:
        offsets.radius(self, w, v)

    def _spindle_clamp(self, value: float, loc: Location) -> None:
        s = self.ip.s
        s.css_max = value
        if s.css:
            self.ip.emit(canon.SetSpindleMode(value, True, source=loc))


def _mode(control: int) -> MotionMode:
    return MotionMode.EXACT_STOP if control == 610 else MotionMode.CONTINUOUS


def machine_events(
    ex: ExecutorState,
    codes: list[int],
    gs: list[int],
    ms: list[int],
    v: dict[str, float],
    w: Words,
    cols: dict[str, int],
    loc: Location,
) -> None:
    """Emit a MACHINE_FUNCTION for each M code of the block the control does not define,
    before the block's other commands. The block's P and Q go with it when it is the block's only
    such code and no G code or M19/M97/M98/M99 of the block takes them."""
    taken = bool(gs) or any(m in (19, 97, 98, 99) and m not in codes for m in ms)
    own = len(codes) == 1 and not taken
    p = v.get("P") if own else None
    q = v.get("Q") if own else None
    if q is not None:
        w.values.pop("q", None)
    for m in codes:
        at = Location(loc.file, loc.line, cols.get(f"M{m}", loc.column))
        ex.ip.emit(machine_function(m, p, q, at, "FANUC-UNKNOWN-M"))


def _code(val: int | float, letter: str, loc: Location) -> int:
    if type(val) is int:
        return val * 10
    code = round(val * 10)
    if abs(val * 10 - code) > 1e-6 or code < 0:
        raise Diagnostic(f"FANUC-BAD-{letter}", f"bad {letter} code {letter}{val}", loc)
    return code


def _count(value: float, loc: Location) -> int:
    n = round(value)
    if abs(value - n) > 1e-6 or n < 0 or n > 9999:
        raise Diagnostic("FANUC-CALL", f"bad repeat count L{value:g}", loc)
    return n
