"""M codes: I/O (M62-M68), tool change (M6, M61), spindle (M3 M4 M5 M19), coolant (M7 M8
M9), overrides (M48-M53), modal state save/restore (M70-M73) and program stops (M0 M1 M2
M30 M60). Order within a line follows LinuxCNC ``convert_m``; M2/M30 reset the modes the
NIST v3 report §3.6.1 lists (and LinuxCNC's additions)."""

from __future__ import annotations

from gcode.core import linuxcnc as lc
from gcode.core.codes import Words
from gcode.core.state import G1, CompCode, CycleWords, FeedCode, SavedModes
from gcode.ngc import modes, offsets
from gcode.ngc.context import NgcContext
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Direction, Plane


def _int_word(ctx: NgcContext, w: Words, letter: str, what: str) -> int:
    if letter not in w.values:
        raise Diagnostic(
            "NGC-M-WORD-MISSING", f"{letter.upper()} word missing with {what}", ctx.loc
        )
    return int(round(w.values[letter]))


def check_user_m(ctx: NgcContext, w: Words) -> None:
    """A user M code (M100-M199) is refused when the block is read, before its words are
    checked: rs274 2.9 does so when the code has no program file ("Unknown m code used"),
    and we run none."""
    code = w.m.get(10)
    if code is not None and code >= 100:
        loc = ctx.loc
        raise Diagnostic(
            "NGC-USER-M",
            f"unknown M code used: M{code} (a user M code needs its program, not available)",
            Location(loc.file, loc.line, w.columns.get("m", loc.column)),
        )


def m_codes(ctx: NgcContext, w: Words) -> None:
    m = w.m
    s = ctx.s
    loc = ctx.loc
    v = w.values
    if 10 in m and m[10] == 70:
        ctx.m70[len(ctx.flow.calls)] = save_state(ctx)
    if 10 in m and m[10] == 73 and ctx.flow.calls:
        call = ctx.flow.calls[-1]
        call.saved_state = save_state(ctx)
        call.autorestore = True
    if 5 in m:
        code = m[5]
        ctx.comp_off(
            {62: "M62/M63", 63: "M62/M63", 64: "M64/M65", 65: "M64/M65"}.get(code, f"M{code}")
        )
        if code in (62, 63, 64, 65):
            p = _int_word(ctx, w, "p", f"M{code}")
            ctx.emit(lc.DigitalOutput(p, code in (62, 64), code in (62, 63), source=loc))
        elif code == 66:
            if "p" not in v and "e" not in v:
                raise Diagnostic(
                    "NGC-M66-INPUT",
                    "need to have either a valid P or a valid E word with M66",
                    loc,
                )
            ctx.params.values[5399] = -1.0
        else:
            e = _int_word(ctx, w, "e", f"M{code}")
            q = v.get("q", 0.0)
            ctx.emit(lc.AnalogOutput(e, q, code == 67, source=loc))
    if 6 in m:
        if m[6] == 6:
            offsets.change_tool(ctx)
        else:
            offsets.set_tool_number(ctx, w)
    if 7 in m:
        code = m[7]
        if code == 3:
            s.spindle = Direction.CLOCKWISE
            ctx.emit(canon.StartSpindleClockwise(source=loc))
        elif code == 4:
            s.spindle = Direction.COUNTERCLOCKWISE
            ctx.emit(canon.StartSpindleCounterclockwise(source=loc))
        elif code == 5:
            s.spindle = Direction.STOPPED
            ctx.emit(canon.StopSpindleTurning(source=loc))
        else:
            r = v.get("r", 0.0)
            if not 0.0 <= r <= 360.0:
                raise Diagnostic("NGC-M19-R", "R value must be within 0..360 with M19", loc)
            p = int(round(v.get("p", 0.0)))
            if p not in (0, 1, 2):
                raise Diagnostic("NGC-M19-P", "M19 P must be 0, 1 or 2", loc)
            s.spindle = Direction.STOPPED
            d = Direction.COUNTERCLOCKWISE if p == 2 else Direction.CLOCKWISE
            ctx.emit(canon.OrientSpindle(r, d, source=loc))
            if "q" in v and ctx.compat:
                ctx.emit(lc.WaitOrientComplete(v["q"], source=loc))
    if 8 in m:
        code = m[8]
        if code == 7:
            s.mist = True
            ctx.emit(canon.MistOn(source=loc))
        elif code == 8:
            s.flood = True
            ctx.emit(canon.FloodOn(source=loc))
        else:
            s.mist = s.flood = False
            ctx.emit(canon.MistOff(source=loc))
            ctx.emit(canon.FloodOff(source=loc))
    if 9 in m:
        ctx.comp_off("enable overrides" if m[9] == 48 else "disable overrides")
        _overrides(ctx, m[9], v)
    if 10 in m:
        code = m[10]
        if code == 71:
            ctx.m70.pop(len(ctx.flow.calls), None)
        elif code == 72:
            saved = ctx.m70.get(len(ctx.flow.calls))
            if saved is None:
                raise Diagnostic(
                    "NGC-M72-NO-STATE",
                    "cannot restore context from invalid stack frame - missing M70/M73?",
                    loc,
                )
            restore_state(ctx, saved)


def _overrides(ctx: NgcContext, code: int, v: dict[str, float]) -> None:
    s = ctx.s
    loc = ctx.loc
    on = v.get("p", 1.0) != 0.0
    if code in (48, 49):
        s.feed_override = s.speed_override = code == 48
        if code == 48:
            ctx.emit(canon.EnableFeedOverride(source=loc))
            ctx.emit(canon.EnableSpeedOverride(source=loc))
        else:
            ctx.emit(canon.DisableFeedOverride(source=loc))
            ctx.emit(canon.DisableSpeedOverride(source=loc))
    elif code == 50:
        s.feed_override = on
        cls = canon.EnableFeedOverride if on else canon.DisableFeedOverride
        ctx.emit(cls(source=loc))
    elif code == 51:
        s.speed_override = on
        cls2 = canon.EnableSpeedOverride if on else canon.DisableSpeedOverride
        ctx.emit(cls2(source=loc))
    elif code == 52:
        s.adaptive_feed = on
    elif code == 53:
        s.feed_hold = on


def save_state(ctx: NgcContext) -> SavedModes:
    """M70/M73: the modal state LinuxCNC saves."""
    return SavedModes.of(ctx.s)


def restore_state(ctx: NgcContext, saved: SavedModes) -> None:
    """M72 (and return from an M73 subroutine): restore, announcing what changed, in the
    order rs274 prints it: units, feed mode or rate, speed, spindle, plane, coordinate
    system, path control, distance mode, coolant."""
    s = ctx.s
    loc = ctx.loc
    if saved.units is not s.units:
        modes.units(ctx, saved.units)
    if saved.feed_mode != s.feed_mode:
        modes.feed_mode(ctx, FeedCode.of(saved.feed_mode))
    elif saved.feed_rate != s.feed_rate:
        s.feed_rate = saved.feed_rate
        ctx.emit(canon.SetFeedRate(s.feed_rate, source=loc))
    if saved.speed != s.speed:
        s.speed = saved.speed
        ctx.emit(canon.SetSpindleSpeed(s.speed, source=loc))
    if saved.spindle is not s.spindle:
        d = saved.spindle
        s.spindle = d
        if d is Direction.CLOCKWISE:
            ctx.emit(canon.StartSpindleClockwise(source=loc))
        elif d is Direction.COUNTERCLOCKWISE:
            ctx.emit(canon.StartSpindleCounterclockwise(source=loc))
        else:
            ctx.emit(canon.StopSpindleTurning(source=loc))
    if saved.plane is not s.plane:
        s.plane = saved.plane
        ctx.emit(canon.SelectPlane(s.plane, source=loc))
    if saved.origin_index != s.origin_index:
        code = offsets.CODES[saved.origin_index - 1]
        offsets.select_coordinate_system(ctx, code)
    if saved.control_mode != s.control_mode:
        words = Words(values={"p": saved.blend_p, "q": saved.blend_q})
        modes.control_mode(ctx, saved.control_mode, words, check=False)
    if saved.absolute != s.absolute:
        s.absolute = saved.absolute
        if ctx.compat:
            mode = "absolute" if s.absolute else "incremental"
            ctx.emit(canon.Comment(f"interpreter: distance mode changed to {mode}", source=loc))
    s.ijk_absolute = saved.ijk_absolute
    s.motion_mode = saved.motion_mode
    s.retract_r = saved.retract_r
    s.css = saved.css
    s.css_max = saved.css_max
    if (s.mist and not saved.mist) or (s.flood and not saved.flood):
        s.mist = s.flood = False
        ctx.emit(canon.MistOff(source=loc))
        ctx.emit(canon.FloodOff(source=loc))
    if saved.mist and not s.mist:
        s.mist = True
        ctx.emit(canon.MistOn(source=loc))
    if saved.flood and not s.flood:
        s.flood = True
        ctx.emit(canon.FloodOn(source=loc))


def program_stop(ctx: NgcContext, code: int) -> bool:
    """M0, M1, M60 (pause) and M2, M30 (end, with LinuxCNC's resets)."""
    loc = ctx.loc
    s = ctx.s
    comp = ctx.comp
    if comp is not None:
        ctx.out.extend(comp.flush(loc))
        if code in (2, 30):
            comp.end_program()
    if code == 0:
        ctx.emit(canon.ProgramStop(source=loc))
        return False
    if code == 1:
        ctx.emit(canon.OptionalProgramStop(source=loc))
        return False
    if code == 60:
        ctx.emit(canon.PalletShuttle(source=loc))
        ctx.emit(canon.ProgramStop(source=loc))
        return False
    # M2 / M30
    offsets.reset_to_g54(ctx)
    if s.plane is not Plane.XY:
        s.plane = Plane.XY
        ctx.emit(canon.SelectPlane(Plane.XY, source=loc))
    s.absolute = True
    s.feed_mode = canon.FeedMode.UNITS_PER_MINUTE
    if ctx.compat:
        ctx.emit(canon.SetFeedMode(canon.FeedMode.UNITS_PER_MINUTE, source=loc))
    s.feed_rate = 0.0
    ctx.emit(canon.SetFeedRate(0.0, source=loc))
    if not s.feed_override or not s.speed_override:
        s.feed_override = s.speed_override = True
        ctx.emit(canon.EnableFeedOverride(source=loc))
        ctx.emit(canon.EnableSpeedOverride(source=loc))
    s.comp_side = CompCode.G40
    s.spindle = Direction.STOPPED
    ctx.emit(canon.StopSpindleTurning(source=loc))
    s.css = False
    if ctx.compat:
        ctx.emit(canon.SetSpindleMode(0.0, False, source=loc))
    s.motion_mode = G1
    if s.mist or s.flood:
        s.mist = s.flood = False
        ctx.emit(canon.MistOff(source=loc))
        ctx.emit(canon.FloodOff(source=loc))
    s.cycle = CycleWords()
    if code == 30:  # M30 exchanges the pallets before ending (LinuxCNC)
        ctx.emit(canon.PalletShuttle(source=loc))
    ctx.emit(canon.ProgramEnd(source=loc))
    if ctx.compat:
        ctx.emit(lc.OnReset(source=loc))
        ctx.emit(lc.OnReset(source=loc))
    return True
