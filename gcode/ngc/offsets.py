"""Coordinate systems and offsets: G54-G59.3, G10 L1/L2/L10/L11/L20, G92/G92.1-G92.3, G52,
G28/G30 (+ .1), tool selection and change (T, M6, M61), tool length G43/G43.1/G43.2/G49.

Stored setup data lives in the 5xxx parameters (NIST v3 §3.2.1: G28 home 5161-5166, G30 home
5181-5186, G92 5211-5216, coordinate systems 5221-5389 in steps of 20, current system 5220,
XY rotation R at 5230+20n in LinuxCNC). rs274 keeps their lengths in its own units, inches
(so ``#5221`` is 1 after ``G21 G10 L2 P1 X25.4``); the interpreter keeps the same offsets
in current program units (:class:`gcode.core.state.Setup`). The tool
table is in inches, as rs274's stand-alone canon reads it (``../shared/corpus/README.md``).
"""

from __future__ import annotations

import math
from dataclasses import replace

from gcode.core import linuxcnc as lc
from gcode.core.codes import Words
from gcode.core.register_marks import (
    OffsetsStored,
    ToolLengthRegister,
    WorkOffsetRegister,
    WorkOffsetValues,
)
from gcode.core.state import AXES, INCH_MM, Setup, ToolLengthCode
from gcode.ngc.context import NgcContext
from gcode.ngc.motion import find_ends, traverse
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Units

CODES = (540, 550, 560, 570, 580, 590, 591, 592, 593)


def _coord_base(index: int) -> int:
    return 5221 + 20 * (index - 1)


def _inch(ctx: NgcContext) -> float:
    """Program units per inch: stored offsets (5xxx parameters) are in inches in rs274."""
    return 25.4 if ctx.s.units is Units.MM else 1.0


def _from_param(ctx: NgcContext, axis: int, value: float) -> float:
    return value * _inch(ctx) if axis < 3 else value


def _to_param(ctx: NgcContext, axis: int, value: float) -> float:
    return value / _inch(ctx) if axis < 3 else value


def init_offsets(ctx: NgcContext) -> None:
    """Offsets at start-up from the parameters (a .var file or all zero)."""
    s = ctx.s
    p = ctx.params.values
    idx = int(round(p[5220])) or 1
    if not 1 <= idx <= 9:
        idx = 1
    p[5220] = float(idx)
    s.origin_index = idx
    for i in range(1, 10):
        base = _coord_base(i)
        s.coords[i] = [_from_param(ctx, k, p[base + k]) for k in range(6)] + [p[base + 9]]
    s.g5x = s.coords[idx][:6]
    s.rotation = s.coords[idx][6]
    s.g92 = [_from_param(ctx, k, p[5211 + k]) for k in range(6)]
    s.g92_saved = s.g92[:]
    s.g28 = [_from_param(ctx, k, p[5161 + k]) for k in range(6)]
    s.g30 = [_from_param(ctx, k, p[5181 + k]) for k in range(6)]
    s.pos = [0.0 - s.machine_offset(i) for i in range(6)]  # machine at its origin (not -0.0)


def parameter_written(ctx: NgcContext, index: int) -> None:
    """A program assigned a 5xxx parameter: keep the interpreter's copy in step."""
    s = ctx.s
    p = ctx.params.values
    if 5161 <= index <= 5166:
        s.g28[index - 5161] = _from_param(ctx, index - 5161, p[index])
    elif 5181 <= index <= 5186:
        s.g30[index - 5181] = _from_param(ctx, index - 5181, p[index])
    elif 5211 <= index <= 5216:
        s.g92_saved[index - 5211] = _from_param(ctx, index - 5211, p[index])
    elif 5221 <= index <= 5390:
        i, k = divmod(index - 5221, 20)
        if k < 6:
            s.coords[i + 1][k] = _from_param(ctx, k, p[index])
        elif k == 9:
            s.coords[i + 1][6] = p[index]


def work_number(s: Setup, index: int) -> int:
    """The work offset number (gcode.core.register_marks) of slot ``index``."""
    return s.slot9_number if index == 9 else index


def emit_g5x(ctx: NgcContext) -> None:
    s = ctx.s
    if ctx.options.register_marks:
        ctx.emit(WorkOffsetRegister(work_number(s, s.origin_index), source=ctx.loc))
    ctx.emit(lc.SetG5xOffset(s.origin_index, *s.g5x, source=ctx.loc))


def emit_origin(ctx: NgcContext) -> None:
    s = ctx.s
    total = [s.g5x[i] + s.g92[i] for i in range(6)]
    ctx.emit(canon.SetOriginOffsets(*total, source=ctx.loc))


def _emit_offsets(ctx: NgcContext, g5x: bool = True, g92: bool = True) -> None:
    if not ctx.g5x_style:
        emit_origin(ctx)
        return
    s = ctx.s
    if g5x:
        emit_g5x(ctx)
    if g92:
        ctx.emit(lc.SetG92Offset(*s.g92, source=ctx.loc))
    if g5x:
        ctx.emit(lc.SetXYRotation(s.rotation, source=ctx.loc))


def _set_g5x(ctx: NgcContext, values: list[float], rotation: float | None = None) -> None:
    """New work offset (and XY rotation): the same machine point in the new program frame."""
    s = ctx.s
    old_pos, old_g5x = s.pos, s.g5x
    machine = s.to_machine(s.pos)
    s.g5x = values[:]
    if rotation is not None:
        s.rotation = rotation
    s.pos = s.to_program(machine)
    if s.rotation or rotation:
        # rs274's canon moves its own position by the offset only, not the rotation
        lag = s.tlo_lag or [0.0] * 6
        for i in range(6):
            lag[i] += (old_g5x[i] - values[i]) - (s.pos[i] - old_pos[i])
        s.tlo_lag = lag


def select_coordinate_system(ctx: NgcContext, code: int) -> None:
    s = ctx.s
    ctx.comp_off("coordinate system")
    idx = CODES.index(code) + 1
    ctx.params.values[5220] = float(idx)
    if idx == s.origin_index:
        if ctx.compat:
            ctx.emit(
                canon.Comment(
                    "interpreter: continuing to use same coordinate system", source=ctx.loc
                )
            )
        return
    s.origin_index = idx
    _set_g5x(ctx, s.coords[idx][:6], s.coords[idx][6])
    if ctx.compat:
        ctx.emit(canon.Comment("interpreter: setting coordinate system origin", source=ctx.loc))
    _emit_offsets(ctx)


def reset_to_g54(ctx: NgcContext) -> None:
    """M2/M30: back to G54 (LinuxCNC prints the G54 offset and rotation)."""
    s = ctx.s
    s.origin_index = 1
    ctx.params.values[5220] = 1.0
    _set_g5x(ctx, s.coords[1][:6], s.coords[1][6])
    if ctx.g5x_style:
        emit_g5x(ctx)
        ctx.emit(lc.SetXYRotation(s.rotation, source=ctx.loc))
    else:
        emit_origin(ctx)


# --------------------------------------------------------------------------- group 0
def modal_0(ctx: NgcContext, w: Words) -> None:
    code = w.g[0]
    if code == 100:
        g10(ctx, w)
    elif code in (280, 300):
        go_home(ctx, w, code)
    elif code in (281, 301):
        s = ctx.s
        if ctx.options.store_marks:
            ctx.emit(OffsetsStored("G28.1" if code == 281 else "G30.1", source=ctx.loc))
        home = s.g28 if code == 281 else s.g30
        base = 5161 if code == 281 else 5181
        home[:] = s.to_machine(s.pos)
        for i in range(6):
            ctx.params.values[base + i] = _to_param(ctx, i, home[i])
    elif code in (920, 520):
        ctx.comp_off("axis offsets")
        g92(ctx, w, code == 520)
    elif code in (921, 922):  # allowed with cutter comp on, as in rs274 (only G52/G92 refuse)
        s = ctx.s
        for i in range(6):
            s.pos[i] += s.g92[i]
            s.g92[i] = 0.0
        if code == 921:
            for i in range(6):
                ctx.params.values[5211 + i] = 0.0
                s.g92_saved[i] = 0.0
        # G92.1 and G92.2 both mark the offsets not applied; G92.2 keeps #5211-#5219
        # (LinuxCNC 2.9, interp_convert.cc convert_axis_offsets)
        ctx.params.values[5210] = 0.0
        _emit_offsets(ctx, g5x=False)
    elif code == 923:
        s = ctx.s
        for i in range(6):
            s.pos[i] += s.g92[i] - s.g92_saved[i]
            s.g92[i] = s.g92_saved[i]
        ctx.params.values[5210] = 1.0
        _emit_offsets(ctx, g5x=False)


def g92(ctx: NgcContext, w: Words, g52: bool) -> None:
    s = ctx.s
    v = w.values
    if not any(a in v for a in AXES):
        raise Diagnostic("NGC-G92-NO-AXES", "all axes missing with G52 or G92", ctx.loc)
    for i, a in enumerate(AXES):
        if a in v:
            new = v[a] if g52 else s.pos[i] + s.g92[i] - v[a]
            s.pos[i] += s.g92[i] - new
            s.g92[i] = new
            s.g92_saved[i] = new
            ctx.params.values[5211 + i] = _to_param(ctx, i, new)
    ctx.params.values[5210] = 1.0
    _emit_offsets(ctx, g5x=False)


def g10(ctx: NgcContext, w: Words) -> None:
    v = w.values
    s = ctx.s
    loc = ctx.loc
    if "l" not in v:
        raise Diagnostic(
            "NGC-G10-L", "line with G10 does not have L0, L1, L10, L11, L2, or L20", loc
        )
    lword = int(round(v["l"]))
    if lword in (1, 10, 11):
        set_tool_entry(ctx, w, lword)
        return
    if lword not in (2, 20):
        raise Diagnostic(
            "NGC-G10-L", "line with G10 does not have L0, L1, L10, L11, L2, or L20", loc
        )
    p = v.get("p")
    if p is None or round(p) < 0 or round(p) > 9 or abs(p - round(p)) > 1e-4:
        raise Diagnostic("NGC-G10-P", f"P value out of range (0-9) with G10 L{lword}", loc)
    idx = int(round(p)) or s.origin_index
    if idx == s.origin_index:
        ctx.comp_off("active coordinate system")
    if ctx.options.store_marks:
        ctx.emit(OffsetsStored(f"G10 L{lword}", source=loc))
    row = s.coords[idx]
    if lword == 20 and "r" in v:
        col = w.columns.get("r", loc.column)
        raise Diagnostic(
            "NGC-G10-L20-R", "R not allowed in G10 L20", Location(loc.file, loc.line, col)
        )
    values = row[:6]
    if lword == 2:
        for i, a in enumerate(AXES):
            if a in v:
                values[i] = v[a]
    else:
        values = _l20_offset(ctx, row, {i: v[a] for i, a in enumerate(AXES) if a in v})
    if ctx.options.register_marks:  # the setting itself, for a writer (register_marks)
        changed = [i for i, a in enumerate(AXES) if a in v or values[i] != row[i]]
        ctx.emit(
            WorkOffsetValues(
                work_number(s, idx),
                "".join(AXES[i].upper() for i in changed),
                tuple(values[i] for i in changed),
                source=loc,
            )
        )
    load_system(ctx, idx, values, v.get("r"))


def load_system(ctx: NgcContext, idx: int, values: list[float], rotation: float | None) -> None:
    """Coordinate system ``idx`` takes ``values`` (and the XY ``rotation`` where given):
    its parameters, and the offsets in force where it is the active system."""
    s = ctx.s
    row = s.coords[idx]
    base = _coord_base(idx)
    for i in range(6):
        if values[i] != row[i]:
            row[i] = values[i]
            ctx.params.values[base + i] = _to_param(ctx, i, row[i])
    if rotation is not None:
        row[6] = rotation
        ctx.params.values[base + 9] = row[6]
    if idx == s.origin_index:
        _set_g5x(ctx, row[:6], row[6])
        _emit_offsets(ctx, g92=False)


def _l20_offset(ctx: NgcContext, row: list[float], given: dict[int, float]) -> list[float]:
    """G10 L20: the offset of system ``row`` (its XY rotation ``row[6]`` kept) that puts the
    current point at the ``given`` coordinates (axis index -> value) of that system.

    As rs274 2.9 computes it: the current point in machine coordinates (the active system,
    G92 and rotation, without the tool length offset) is expressed in the target system; the
    given axes take their values there and the other axes keep theirs, so with a rotation an
    ``X`` word alone can move the Y offset too.
    """
    s = ctx.s
    m = [p + g for p, g in zip(s.pos[:6], s.g92, strict=True)]
    _rotate(m, s.rotation)
    m = [a + b for a, b in zip(m, s.g5x, strict=True)]
    local = [a - b for a, b in zip(m, row[:6], strict=True)]
    _rotate(local, -row[6])
    for i, value in given.items():
        local[i] = value + s.g92[i]
    _rotate(local, row[6])
    return [a - b for a, b in zip(m, local, strict=True)]


def _rotate(p: list[float], degrees: float) -> None:
    """Turn the XY part of ``p`` by ``degrees`` about the origin (in place)."""
    if degrees:
        a = math.radians(degrees)
        x, y = p[0], p[1]
        p[0], p[1] = x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)


def go_home(ctx: NgcContext, w: Words, code: int) -> None:
    """G28 / G30: traverse through the given point (if any) to the stored home position."""
    s = ctx.s
    ctx.comp_off("G28/G30")
    home = s.g28 if code == 280 else s.g30
    v = w.values
    given = [a in v for a in AXES]
    end = find_ends(ctx, w)
    traverse(ctx, end)
    machine = s.to_machine(end)
    for i in range(6):
        if given[i] or not any(given):
            machine[i] = home[i]
    traverse(ctx, s.to_program(machine))


# --------------------------------------------------------------------------- tools
def _table_scale(ctx: NgcContext) -> float:
    """Program units per tool-table unit (the table is in inches)."""
    return INCH_MM if ctx.s.units is Units.MM else 1.0


def select_tool(ctx: NgcContext, w: Words) -> None:
    t = w.values["t"]
    loc = ctx.loc
    if t < 0 or abs(t - round(t)) > 1e-4:
        raise Diagnostic("NGC-NEGATIVE-T", "negative or non-integer tool number", loc)
    n = int(round(t))
    tool = ctx.tools.get(n)
    if tool is None:
        raise Diagnostic("NGC-TOOL-UNKNOWN", f"requested tool {n} not found in the tool table", loc)
    ctx.s.selected_tool = n
    ctx.s.selected_pocket = tool.pocket if n else 0
    ctx.emit(canon.SelectTool(n, source=loc))


def change_tool(ctx: NgcContext) -> None:
    s = ctx.s
    loc = ctx.loc
    ctx.comp_off("tool change")
    n = s.selected_tool if s.selected_tool >= 0 else s.current_tool
    if ctx.compat:
        ctx.emit(lc.StartChange(source=loc))
    s.spindle = canon.Direction.STOPPED
    ctx.emit(canon.StopSpindleTurning(source=loc))
    ctx.emit(canon.ChangeTool(_slot(ctx, n), source=loc))
    s.resync_pending = True
    s.current_tool = n
    s.loaded_tool = n
    s.current_pocket = s.selected_pocket if s.selected_pocket >= 0 else 0


def resync(ctx: NgcContext) -> None:
    """After a tool change rs274 continues from its canon's idea of the position.

    It re-reads that position when it reads the next block, so this runs at the end of the
    block holding the M6/M61: a G43/G43.1/G49 in that block is taken back as well.
    """
    s = ctx.s
    s.resync_pending = False
    if s.tlo_lag is not None:
        s.pos = [p + d for p, d in zip(s.pos, s.tlo_lag, strict=True)]
        s.tlo_lag = None


def _slot(ctx: NgcContext, tool: int) -> int:
    """The tool's slot as rs274 prints it in CHANGE_TOOL: its 1-based row in the table."""
    if tool == 0:
        return 0
    entry = ctx.tools.get(tool)
    if entry is not None and entry.row:
        return entry.row
    for i, number in enumerate(ctx.tools.tools, 1):
        if number == tool:
            return i
    return tool


def set_tool_number(ctx: NgcContext, w: Words) -> None:
    q = w.values.get("q")
    loc = ctx.loc
    if q is None:
        raise Diagnostic("NGC-M61-Q", "Q word missing with M61", loc)
    n = int(round(q))
    if n < 0:
        raise Diagnostic("NGC-M61-Q", "need non-negative Q value with M61", loc)
    if ctx.tools.get(n) is None:
        raise Diagnostic("NGC-TOOL-UNKNOWN", f"requested tool {n} not found in the tool table", loc)
    ctx.s.current_tool = n
    ctx.s.resync_pending = True
    if ctx.compat:
        ctx.emit(lc.ChangeToolNumber(_slot(ctx, n), source=loc))
    if ctx.comp is not None and ctx.comp.holding:
        ctx.out.extend(ctx.comp.release())


def _apply_tool_offset(ctx: NgcContext, new: list[float]) -> None:
    s = ctx.s
    lag = s.tlo_lag or [0.0] * 6
    # the offset is in machine axes: the program position moves by it turned back by the
    # XY rotation (G10 L2 R)
    delta = [s.tool_offset[i] - new[i] for i in range(6)]
    _rotate(delta, -s.rotation)
    for i in range(6):
        s.pos[i] += delta[i]
        lag[i] -= delta[i]
    s.tlo_lag = lag
    s.tool_offset = new
    if ctx.compat:
        ctx.emit(lc.ToolLengthOffsets(tuple(new), source=ctx.loc))
    else:
        ctx.emit(canon.UseToolLengthOffset(new[2], source=ctx.loc))


def _tool_offsets(ctx: NgcContext, n: int) -> list[float]:
    tool = ctx.tools.get(n)
    if tool is None:
        raise Diagnostic(
            "NGC-TOOL-UNKNOWN", f"requested tool {n} not found in the tool table", ctx.loc
        )
    k = _table_scale(ctx)
    return [o * k if i in (0, 1, 2, 6, 7, 8) else o for i, o in enumerate(tool.offset)]


def tool_length(ctx: NgcContext, w: Words) -> None:
    s = ctx.s
    code = ToolLengthCode(w.g[8])
    v = w.values
    ctx.comp_off("tool offset")
    s.tool_length_mode = code
    marks = ctx.options.register_marks
    if code is ToolLengthCode.G49:
        if marks:
            ctx.emit(ToolLengthRegister("G49", None, source=ctx.loc))
        _apply_tool_offset(ctx, [0.0] * 9)
    elif code is ToolLengthCode.G43:
        h = v.get("h")
        n = s.current_tool if h is None else int(round(h))
        offsets = _tool_offsets(ctx, n)
        if marks:
            ctx.emit(ToolLengthRegister("G43", n, source=ctx.loc))
        _apply_tool_offset(ctx, offsets)
    elif code is ToolLengthCode.G43_2:
        h = v.get("h")
        n = s.current_tool if h is None else int(round(h))
        add = _tool_offsets(ctx, n)
        if marks:
            ctx.emit(ToolLengthRegister("G43.2", n, source=ctx.loc))
        _apply_tool_offset(ctx, [a + b for a, b in zip(s.tool_offset, add, strict=True)])
    else:  # G43.1
        new = [0.0] * 9
        for i, a in enumerate(AXES):
            if a in v:
                new[i] = v[a]
        if marks:
            ctx.emit(ToolLengthRegister("G43.1", None, source=ctx.loc))
        _apply_tool_offset(ctx, new)


def _current_in_system(ctx: NgcContext, system: int, with_g92: bool) -> list[float]:
    """The current point, tool length offset taken off, in coordinate system ``system``
    (LinuxCNC 2.9 interp_find.cc find_current_in_system_without_tlo): machine coordinates,
    less that system's offset, turned back by its rotation, less G92 when ``with_g92``."""
    s = ctx.s
    m = s.to_machine(list(s.pos))
    row = s.coords[system]
    local = [a - b for a, b in zip(m, row[:6], strict=True)]
    _rotate(local, -row[6])
    if with_g92:
        local = [a - b for a, b in zip(local, s.g92, strict=True)]
    return local


def _touch_off(ctx: NgcContext, w: Words, lword: int, offset: list[float], k: float) -> None:
    """G10 L10 / L11: the tool's offsets (``offset``, table units, changed in place) that make
    the current point have the given coordinates in the current system (L10) or in the
    touch-off fixture G59.3 (L11, G92 not counted), as LinuxCNC 2.9's convert_setup_tool.

    In XY the system's rotation turns the result; an X (or Y) word alone keeps the part of
    the tool's XY offset that lies along the system's other axis.
    """
    v = w.values
    system = 9 if lword == 11 else ctx.s.origin_index
    t = _current_in_system(ctx, system, with_g92=lword == 10)
    angle = ctx.s.coords[system][6]
    if "x" in v or "y" in v:
        if "x" in v and "y" in v:
            xy = [t[0] - v["x"], t[1] - v["y"]]
            kept = [0.0, 0.0]
        else:
            kept = [offset[0] * k, offset[1] * k]
            _rotate(kept, -angle)
            axis = 0 if "x" in v else 1
            kept[axis] = 0.0
            _rotate(kept, angle)
            xy = [0.0, 0.0]
            xy[axis] = t[axis] - v["xy"[axis]]
        _rotate(xy, angle)
        offset[0], offset[1] = (xy[0] + kept[0]) / k, (xy[1] + kept[1]) / k
    for i, a in enumerate(AXES[2:], 2):
        if a in v:
            val = t[i] - v[a]
            offset[i] = val / k if i < 3 else val


def set_tool_entry(ctx: NgcContext, w: Words, lword: int) -> None:
    """G10 L1 (values), L10 / L11 (current position becomes the value)."""
    s = ctx.s
    v = w.values
    loc = ctx.loc
    if "p" not in v or round(v["p"]) < 0:
        raise Diagnostic("NGC-G10-L1-P", f"P value out of range with G10 L{lword}", loc)
    n = int(round(v["p"]))
    tool = ctx.tools.get(n)
    if tool is None:
        raise Diagnostic("NGC-TOOL-UNKNOWN", f"requested tool {n} not found in the tool table", loc)
    k = _table_scale(ctx)
    offset = list(tool.offset)
    if lword == 1:
        for i, a in enumerate(AXES):
            if a in v:
                offset[i] = v[a] / k if i < 3 else v[a]
    else:
        _touch_off(ctx, w, lword, offset, k)
    diameter = tool.diameter
    if "r" in v:
        diameter = 2.0 * v["r"] / k
    front = v.get("i", tool.front_angle)
    back = v.get("j", tool.back_angle)
    orientation = int(round(v["q"])) if "q" in v else tool.orientation
    new = replace(
        tool,
        offset=tuple(offset),
        diameter=diameter,
        front_angle=front,
        back_angle=back,
        orientation=orientation,
    )
    ctx.tools.tools[n] = new
    if ctx.compat:
        entry = (tuple(offset), diameter, front, back, orientation)
        ctx.emit(lc.SetToolTableEntry(tool.pocket, n, *entry, source=loc))
        if n == s.current_tool and n != 0:
            ctx.emit(lc.SetToolTableEntry(0, n, *entry, source=loc))
