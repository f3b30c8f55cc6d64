"""Read-only parameters computed from interpreter state (LinuxCNC 2.9 "predefined named
parameters" ``#<_x>``, ``#<_metric>``, ... and numbered 5400-5428)."""

from __future__ import annotations

from gcode.core.state import INCH_MM, INVERSE_TIME, PER_MINUTE, PER_REV, ToolLengthCode
from gcode.ngc.context import NgcContext
from kernel.ir.canon import Direction, Plane, Units

_AXES = "xyzabc"
_PLANE_CODE = {Plane.XY: 170.0, Plane.XZ: 180.0, Plane.YZ: 190.0}


def named_parameter(ctx: NgcContext, name: str) -> float | None:
    """Value of a predefined ``#<_name>`` or None when ``name`` is not one of them."""
    s = ctx.s
    n = name[1:]
    if len(n) == 1 and n in _AXES:
        return s.pos[_AXES.index(n)]
    if n in ("u", "v", "w"):
        return 0.0
    if n.startswith("abs_") and len(n) == 5 and n[4] in _AXES:
        # machine coordinates: G92, the XY rotation, the G5x and the tool offsets (LinuxCNC
        # 2.9, interp_namedparams.cc lookup_named_param)
        return s.to_machine(list(s.pos))[_AXES.index(n[4])]
    if n in ("abs_u", "abs_v", "abs_w"):
        return 0.0
    if n.startswith("ini[") and "]" in n:
        return _ini_value(ctx, n)
    table = {
        "line": lambda: float(ctx.loc.line),
        "motion_mode": lambda: float(s.motion_mode if s.motion_mode is not None else 800),
        "plane": lambda: _PLANE_CODE[s.plane],
        "ccomp": lambda: float(s.comp_side),
        "metric": lambda: 1.0 if s.units is Units.MM else 0.0,
        "imperial": lambda: 1.0 if s.units is Units.INCHES else 0.0,
        "absolute": lambda: 1.0 if s.absolute else 0.0,
        "incremental": lambda: 0.0 if s.absolute else 1.0,
        "inverse_time": lambda: 1.0 if s.feed_mode == INVERSE_TIME else 0.0,
        "units_per_minute": lambda: 1.0 if s.feed_mode == PER_MINUTE else 0.0,
        "units_per_rev": lambda: 1.0 if s.feed_mode == PER_REV else 0.0,
        "coord_system": lambda: float(_coord_code(s.origin_index)),
        "tool_offset": lambda: 1.0 if s.tool_length_mode is not ToolLengthCode.G49 else 0.0,
        "retract_r_plane": lambda: 1.0 if s.retract_r else 0.0,
        "retract_old_z": lambda: 0.0 if s.retract_r else 1.0,
        "spindle_rpm_mode": lambda: 0.0 if s.css else 1.0,
        "spindle_css_mode": lambda: 1.0 if s.css else 0.0,
        "ijk_absolute_mode": lambda: 1.0 if s.ijk_absolute else 0.0,
        "lathe_diameter_mode": lambda: 0.0,
        "lathe_radius_mode": lambda: 1.0,
        "spindle_on": lambda: 0.0 if s.spindle is Direction.STOPPED else 1.0,
        "spindle_cw": lambda: 1.0 if s.spindle is Direction.CLOCKWISE else 0.0,
        "mist": lambda: 1.0 if s.mist else 0.0,
        "flood": lambda: 1.0 if s.flood else 0.0,
        "speed_override": lambda: 1.0 if s.speed_override else 0.0,
        "feed_override": lambda: 1.0 if s.feed_override else 0.0,
        "adaptive_feed": lambda: 1.0 if s.adaptive_feed else 0.0,
        "feed_hold": lambda: 1.0 if s.feed_hold else 0.0,
        "feed": lambda: s.feed_rate,
        "rpm": lambda: s.speed,
        "current_tool": lambda: float(s.current_tool),
        "current_pocket": lambda: float(s.current_pocket),
        "selected_tool": lambda: float(s.selected_tool),
        "selected_pocket": lambda: float(s.selected_pocket),
        "call_level": lambda: float(ctx.flow.call_level),
        "remap_level": lambda: 0.0,
        "task": lambda: 0.0,
        # PACKAGE_VERSION read as "%lf%lf": "2.9.0" gives 2.9 and .0 (rs274 2.9.0)
        "vmajor": lambda: 2.9,
        "vminor": lambda: 0.0,
        "value": lambda: ctx.flow.return_value,
        "value_returned": lambda: 1.0 if ctx.flow.value_returned else 0.0,
    }
    fn = table.get(n)
    return fn() if fn is not None else None


def _ini_value(ctx: NgcContext, name: str) -> float | None:
    """``#<_ini[section]name>``: the INI file's number (LinuxCNC 2.9 INI_VARS), else None."""
    values = ctx.options.ini_values
    if not values:
        return None
    section, key = name[4:].split("]", 1)
    return values.get((section.upper(), key.upper()))


def _coord_code(index: int) -> int:
    return (540, 550, 560, 570, 580, 590, 591, 592, 593)[index - 1]


def numbered_parameter(ctx: NgcContext, index: int) -> float | None:
    """Live value of numbered parameters LinuxCNC keeps up to date (None: use the store)."""
    s = ctx.s
    if 5420 <= index <= 5425:
        return s.pos[index - 5420]
    if 5426 <= index <= 5428:
        return 0.0
    if 5400 <= index <= 5413:
        # the tool table entry of the tool M6 loaded (rs274 2.9: neither G43 nor M61
        # changes them; G10 L1 on that tool does), lengths in the program's units
        n = s.loaded_tool
        if index == 5400:
            return float(n)
        tool = ctx.tools.get(n)
        if tool is None:
            return 0.0
        if index <= 5409:
            length = index - 5401 in (0, 1, 2, 6, 7, 8)
            scale = INCH_MM if s.units is Units.MM and length else 1.0
            return tool.offset[index - 5401] * scale
        return (tool.diameter, tool.front_angle, tool.back_angle, float(tool.orientation))[
            index - 5410
        ]
    return None
