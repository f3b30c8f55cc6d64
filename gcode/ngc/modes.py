"""Mode changes shared by the interpreter and the M codes: spindle mode (G96/G97), feed
mode (G93/G94/G95), length units (G20/G21) and path control (G61/G61.1/G64). M72 and the
end of an M73 subroutine restore modes through the same functions, so the commands they
print are those of the G codes."""

from __future__ import annotations

from gcode.core.codes import Words
from gcode.core.state import INCH_MM, ControlCode, FeedCode
from gcode.ngc.context import NgcContext
from kernel.ir import canon
from kernel.ir.canon import FeedMode, Units

#: feed modes as the compat comment names them
_FEED_MODE_NAMES = {
    FeedMode.UNITS_PER_MINUTE: "units per minute",
    FeedMode.INVERSE_TIME: "inverse time",
    FeedMode.UNITS_PER_REVOLUTION: "units per revolution",
}


def spindle_mode(ctx: NgcContext, code: int, v: dict[str, float]) -> None:
    """G96 (constant surface speed, D the maximum speed) / G97 (RPM)."""
    s = ctx.s
    if code == 960:
        s.css = True
        s.css_max = v.get("d", s.css_max)
    else:
        s.css = False
    ctx.emit(canon.SetSpindleMode(s.css_max if s.css else 0.0, s.css, source=ctx.loc))


def feed_mode(ctx: NgcContext, code: FeedCode) -> None:
    """G93 / G94 / G95; outside inverse time the feed rate starts at 0 (LinuxCNC)."""
    s = ctx.s
    mode = code.mode
    s.feed_mode = mode
    loc = ctx.loc
    if ctx.compat:
        name = _FEED_MODE_NAMES[mode]
        ctx.emit(canon.Comment(f"interpreter: feed mode set to {name}", source=loc))
    ctx.emit(canon.SetFeedMode(mode, source=loc))
    if mode is not FeedMode.INVERSE_TIME:
        s.feed_rate = 0.0
        ctx.emit(canon.SetFeedRate(0.0, source=loc))


def units(ctx: NgcContext, new: Units) -> None:
    """G20 / G21: stored lengths follow the units (the compensator too)."""
    s = ctx.s
    if s.units is not new:
        s.scale_lengths(1.0 / INCH_MM if new is Units.INCHES else INCH_MM)
        s.units = new
    if ctx.comp is not None:
        ctx.comp.set_units(new is Units.INCHES)
    ctx.emit(canon.UseLengthUnits(new, source=ctx.loc))


def control_mode(ctx: NgcContext, code: ControlCode, w: Words, check: bool = True) -> None:
    """G61 / G61.1 / G64 (P blending tolerance, Q naive-CAM tolerance, default P)."""
    s = ctx.s
    loc = ctx.loc
    if check:
        ctx.comp_off("control mode")
    s.control_mode = code
    if code is ControlCode.G61:
        ctx.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_PATH, source=loc))
    elif code is ControlCode.G61_1:
        ctx.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP, source=loc))
    else:
        p = w.values.get("p", -1.0)
        q = w.values.get("q", -1.0)
        if p < 0:
            p = 0.0
        if q < 0:
            q = p
        s.blend_p, s.blend_q = p, q
        ctx.emit(canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, p, source=loc))
        ctx.emit(canon.SetNaivecamTolerance(q, source=loc))
