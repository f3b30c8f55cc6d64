"""LinuxCNC's extras in the writer: what ``rs274`` prints beyond NISTIR 5970 (gcode.core.linuxcnc).

Work offset selection (SET_G5X_OFFSET -> G54..G59.3), the G92 offset by value (as G52),
the offset rotation, nine-value tool offsets, tool-table edits, M61, G33.1 and M62-M68.
"""

from __future__ import annotations

from collections.abc import Callable

from gcode.core import linuxcnc as lc
from gcode.core.register_marks import EXTENDED_WORK_OFFSETS, WorkOffsetRegister, WorkOffsetValues
from gcode.write.context import WriterContext
from gcode.write.handlers import comp_active, ignore, tool_length
from kernel.ir import canon


def _axis_list(w: WriterContext, values: tuple[float, ...], scale: bool = True) -> str:
    s = w.fmt.scale if scale else 1.0
    words = []
    for k, v in zip("XYZABC", values, strict=False):
        if k in w.d.axes and abs(v) > 1e-12:
            words.append(k + (w.fmt.angle(v) if k in "ABC" else w.fmt.length(v * s)))
    return w.d.separator.join(words)


def work_offset_register(w: WriterContext, c: WorkOffsetRegister) -> None:
    w.work_register = c.number


def work_offset_code(w: WriterContext, number: int) -> tuple[str, int] | None:
    """Work offset ``number`` (gcode.core.register_marks) in the target's words: the code
    selecting it and the P of its setting (G10 L2 P n, L20 P n); None where it has none."""
    d = w.d
    if 1 <= number <= len(d.work_offsets):
        return d.work_offsets[number - 1], number
    extra = number - EXTENDED_WORK_OFFSETS
    if d.extended_offset is not None and 1 <= extra <= d.extended_offsets:
        return d.extended_offset.format(register=extra), extra
    return None


def _offset_name(number: int) -> str:
    """A work offset number as its own dialects name it."""
    if number > EXTENDED_WORK_OFFSETS:
        return f"G54.1 P{number - EXTENDED_WORK_OFFSETS}"
    if number <= 6:
        return f"G{53 + number}"
    return f"G59.{number - 6}/G5{number:02d}" if number <= 9 else f"G5{number:02d}"


def work_offset(w: WriterContext, c: canon.SetG5xOffset) -> None:
    """SET_G5X_OFFSET: select the work offset (the number the reader marked, else the IR's
    index); its values stay in the machine's table."""
    number, w.work_register = w.work_register or int(c.index), None
    if number == w.e_work:
        return
    comp_active(w, "work offset change")
    w.flush()
    w.invalidate()
    w.e_work = number
    code = work_offset_code(w, number)
    if code is None:  # another offset's values would run the program somewhere else
        w.lacking(
            "CONV-WORK-OFFSET",
            f"work offset {_offset_name(number)} (work offsets keep their numbers)",
        )
        return
    w.block(code[0])


def work_offset_values(w: WriterContext, c: WorkOffsetValues) -> None:
    """G10 L2 / L20: the program sets a work offset's values in the machine's table, written
    in the target's form for the same offset number, else a loss (CONV-WORK-OFFSET)."""
    w.flush_units()
    w.invalidate()
    code = work_offset_code(w, c.number)
    extended = c.number > EXTENDED_WORK_OFFSETS
    form = w.d.extended_offset_set if extended else w.d.work_offset_set
    if code is None or form is None:
        w.lacking(
            "CONV-WORK-OFFSET",
            f"setting of work offset {_offset_name(c.number)}'s values (G10 L2/L20)",
        )
        return
    s = w.fmt.scale
    words = [
        k + (w.fmt.angle(v) if k in "ABC" else w.fmt.length(v * s))
        for k, v in zip(c.axes, c.values, strict=True)
        if k in w.d.axes
    ]
    lost = [k for k in c.axes if k not in w.d.axes]
    if lost:
        w.lacking("CONV-WORK-OFFSET", f"axis {', '.join(lost)} of a work offset setting")
    if words:
        w.block(form.format(register=code[1], axes=w.d.separator.join(words)))


def local_offset(w: WriterContext, c: canon.SetG92Offset) -> None:
    """SET_G92_OFFSET: the G92 offset by value, written as G52 (same effect, no position)."""
    values = tuple(getattr(c, k) for k in "xyzabc")
    if all(abs(a - b) < 1e-12 for a, b in zip(values, w.e_local, strict=True)):
        return
    comp_active(w, "offset change")
    w.flush()
    w.invalidate()
    w.e_local = values
    if w.d.local_offset is None:
        w.lacking("CONV-ORIGIN", "offset by value (G52)")
        return
    if w.d.rotated_offset is not None:
        _frame(w)
        return
    axes = _axis_list(w, values) or "X" + w.fmt.length(0.0)
    w.block(w.d.local_offset.format(axes=axes))


def _frame(w: WriterContext) -> None:
    """Rotation and offset as one frame (Siemens: ``ROT Z a`` then ``ATRANS`` the offset
    in the rotated system, so a point p is at R (p + offset) as after LinuxCNC's G92 and
    G10 L2 R; ``TRANS`` alone without rotation)."""
    d = w.d
    assert d.xy_rotation is not None and d.local_offset is not None
    assert d.rotated_offset is not None
    on = d.xy_rotation.partition("|")[0]
    axes = _axis_list(w, w.e_local)
    blocks: tuple[str, ...]
    if abs(w.e_rotation) < 1e-12:
        blocks = (d.local_offset.format(axes=axes or "X" + w.fmt.length(0.0)),)
    else:
        blocks = (on.format(index=w.e_work, angle=w.fmt.angle(w.e_rotation)),)
        if axes:
            blocks += (d.rotated_offset.format(axes=axes),)
    if blocks == w.frame:
        return
    # an ATRANS after the frame in force adds to it: only the new tail is written
    start = len(w.frame) if w.frame and blocks[: len(w.frame)] == w.frame else 0
    w.frame = blocks
    for text in blocks[start:]:
        w.block(text)


def xy_rotation(w: WriterContext, c: canon.SetXYRotation) -> None:
    """SET_XY_ROTATION: the work offset's rotation (LinuxCNC G10 L2 R, Fanuc G68)."""
    angle = float(c.angle)
    if abs(angle - w.e_rotation) < 1e-12:
        return
    w.flush()
    w.invalidate()
    w.e_rotation = angle
    if w.d.xy_rotation is None:
        w.lacking("CONV-ORIGIN", "rotated work offset (G10 L2 R)")
        return
    if w.d.rotated_offset is not None and w.d.local_offset is not None:
        _frame(w)
        return
    on, _, off = w.d.xy_rotation.partition("|")
    if abs(angle) < 1e-12 and off:
        w.block(off)
        return
    w.block(on.format(index=w.e_work, angle=w.fmt.angle(angle)))


def tool_offsets(w: WriterContext, c: lc.ToolLengthOffsets) -> None:
    """LinuxCNC's nine-value tool length offset: G43.1 with the non-zero axes."""
    off = tuple(c.offset)
    by_value = w.tool_register is None or w.tool_register.code == "G43.1"
    if by_value and w.d.tool_length == "G43.1 Z{length}" and any(abs(v) > 1e-12 for v in off[:6]):
        w.flush()
        w.invalidate()
        w.tool_register = None
        w.block("G43.1", _axis_list(w, off[:6]))
        return
    tool_length(w, canon.UseToolLengthOffset(off[2], source=c.source))


def tool_table(w: WriterContext, c: canon.SetToolTableEntry) -> None:
    """SET_TOOL_TABLE_ENTRY as G10 L1. Its values are in the tool table's units, inches
    (LinuxCNC's ``rs274`` and gcode.ngc.interpreter), whatever the program's units: they are
    written in the program's, after the units word."""
    if not w.o.write_tool_table:
        w.refuse(
            "CONV-TOOL-TABLE",
            f"the program sets tool {c.tool}'s entry of the tool table (G10 L1/L10/L11); "
            "it is written only with --write-tool-table",
        )
    if w.d.tool_table_set is None:
        w.lacking("CONV-TOOL-LENGTH", "tool table edit (G10 L1)", note=False)
        return
    w.flush()
    table = 25.4 if w.units is canon.Units.MM else 1.0  # inch -> program units
    offset = tuple(v * table for v in c.offset[:6])
    radius = c.diameter / 2 * table * w.fmt.scale
    w.block(
        w.d.tool_table_set.format(
            tool=c.tool,
            axes=_axis_list(w, offset),
            radius=w.fmt.length(radius),
        )
    )


def tool_number(w: WriterContext, c: canon.ChangeToolNumber) -> None:
    if w.d.tool_number is None:
        w.lacking("CONV-TOOL-CHANGE", "tool number setting (M61)")
        return
    w.flush()
    w.tool = int(c.number)
    w.block(w.d.tool_number.format(tool=w.tool))


def rigid_tap(w: WriterContext, c: canon.RigidTap) -> None:
    w.flush()
    code = w.d.rigid_tap
    if code is None or w.sync is None:
        w.refuse("CONV-THREAD", f"{w.d.title} has no rigid tapping cycle (G33.1)")
    t = w.target(c.x, c.y, c.z, w.cur["A"], w.cur["B"], w.cur["C"])
    words = w.axis_words(t, force=True)
    w.motion = None
    w.block(code, *words, "K" + w.fmt.length(w.sync))
    w.invalidate()


def output(w: WriterContext, c: lc.DigitalOutput | lc.AnalogOutput) -> None:
    if not w.d.io_codes:
        w.lacking("CONV-OUTPUT", "M62-M68 (digital/analog outputs)")
        return
    if isinstance(c, lc.AnalogOutput):
        code = "M67" if c.synchronised else "M68"
        w.block(code, f"E{c.index}", f"Q{w.fmt.number(c.value, 6)}")
        return
    w.block(_DIGITAL[(c.synchronised, c.on)], f"P{c.index}")


_DIGITAL = {(True, True): "M62", (True, False): "M63", (False, True): "M64", (False, False): "M65"}


BY_NAME: dict[str, Callable] = {
    "SET_G5X_OFFSET": work_offset,
    "WORK_OFFSET_REGISTER": work_offset_register,
    "WORK_OFFSET_VALUES": work_offset_values,
    "SET_G92_OFFSET": local_offset,
    "SET_XY_ROTATION": xy_rotation,
    "USE_TOOL_LENGTH_OFFSET": tool_offsets,
    "SET_TOOL_TABLE_ENTRY": tool_table,
    "CHANGE_TOOL_NUMBER": tool_number,
    "RIGID_TAP": rigid_tap,
    "SET_MOTION_OUTPUT_BIT": output,
    "SET_MOTION_OUTPUT_VALUE": output,
    "ON_RESET": ignore,
    "OFFSETS_STORED": ignore,
    "START_CHANGE": ignore,
    "FINISH": ignore,
    "SPINDLE.0.WAIT_ORIENT_COMPLETE": ignore,
}
