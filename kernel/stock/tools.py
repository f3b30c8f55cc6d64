"""Tool shapes for material removal, and the tool library they come from.

A tool is a body of revolution about a vertical axis through its tip: its cutting end
(flat, ball, bull nose with a corner radius, drill with a point angle, chamfer/V with an
included angle and an optional flat tip), the flute length, and above the flutes the
shank and the holder as cylinders (:class:`ToolShape`).

Sources: a tool library (TOML, :func:`library_from_toml`), ``--tool N=KIND:D,...`` specs
(:func:`parse_tool_spec`) and a LinuxCNC ``.tbl`` (flat end mills of its diameters: a
table has no shape column, :func:`shapes_from_table`). Nothing here reads a file.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from kernel.diagnostics import Diagnostic, Location
from kernel.tooltable import ToolTable

KINDS = ("flat", "ball", "bull", "drill", "chamfer", "insert")
#: other names of a kind (``v`` is a V-bit, a chamfer tool with a sharp tip)
ALIASES = {
    "v": "chamfer",
    "vbit": "chamfer",
    "endmill": "flat",
    "bullnose": "bull",
    "lathe": "insert",
    "turning": "insert",
}
#: an insert's width along Z when none is given (mm)
INSERT_WIDTH = 6.0
#: point angle of a drill and included angle of a V-bit when none is given (degrees)
DEFAULT_ANGLE = {"drill": 118.0, "chamfer": 90.0}


@dataclass(frozen=True, slots=True)
class ToolShape:
    """A milling tool seen by the height field (lengths in mm, angles in degrees).

    ``kind``: ``flat`` (end mill; the tip is its flat end), ``ball`` (ball nose), ``bull``
    (flat end of diameter ``diameter - 2 * corner_radius`` with a rounded corner),
    ``drill`` (cone of ``angle`` point angle) or ``chamfer`` (cone of ``angle`` included
    angle from a flat tip of ``tip_diameter``). The programmed point is the lowest point.
    ``flute_length`` 0 means unknown; ``centre_cutting`` False marks a tool that must not
    plunge. The shank (``shank_diameter``, 0: none given) stands from the flutes' top up to
    ``shank_length`` above it, then the holder (``holder_diameter`` x ``holder_length``).
    ``insert`` is a lathe insert (kernel.stock.turning): ``corner_radius`` its nose radius,
    ``width`` its extent along Z, ``diameter`` twice the nose radius."""

    kind: str = "flat"
    diameter: float = 6.0
    flute_length: float = 0.0
    centre_cutting: bool = True
    corner_radius: float = 0.0
    angle: float = 0.0
    tip_diameter: float = 0.0
    shank_diameter: float = 0.0
    shank_length: float = 0.0
    holder_diameter: float = 0.0
    holder_length: float = 0.0
    width: float = 0.0

    @property
    def radius(self) -> float:
        return 0.5 * self.diameter

    @property
    def cone_slope(self) -> float:
        """Rise per mm of radius of a drill's or chamfer tool's cone (cot of half the angle)."""
        return 1.0 / math.tan(math.radians(0.5 * self.angle))

    def height_at(self, rho: float) -> float:
        """Height of the cutting end above the tip at ``rho`` mm from the axis (<= radius)."""
        r = self.radius
        if self.kind == "ball":
            return r - math.sqrt(max(r * r - rho * rho, 0.0))
        if self.kind == "bull":
            a, rc = r - self.corner_radius, self.corner_radius
            e = max(rho - a, 0.0)
            return rc - math.sqrt(max(rc * rc - e * e, 0.0))
        if self.kind in ("drill", "chamfer"):
            return self.cone_slope * max(rho - 0.5 * self.tip_diameter, 0.0)
        return 0.0

    @property
    def end_height(self) -> float:
        """Height of the cutting end's rim above the tip (where the side wall starts)."""
        return self.height_at(self.radius)

    @property
    def shank_bottom(self) -> float | None:
        """Height above the tip where the shank starts (the flutes' top), None without a
        shank diameter and flute length."""
        if self.shank_diameter > 0 and self.flute_length > 0:
            return self.flute_length
        return None

    @property
    def holder_bottom(self) -> float | None:
        """Height above the tip of the holder's face, None without holder data."""
        if self.holder_diameter > 0 and self.flute_length > 0:
            return self.flute_length + self.shank_length
        return None


DEFAULT_TOOL = ToolShape()

_NUMBERS = {
    "flute": "flute_length",
    "flute_length": "flute_length",
    "corner": "corner_radius",
    "corner_radius": "corner_radius",
    "angle": "angle",
    "point_angle": "angle",
    "tip": "tip_diameter",
    "tip_diameter": "tip_diameter",
    "shank": "shank_diameter",
    "shank_diameter": "shank_diameter",
    "shank_length": "shank_length",
    "holder": "holder_diameter",
    "holder_diameter": "holder_diameter",
    "holder_length": "holder_length",
    "nose_radius": "corner_radius",
    "nose": "corner_radius",
    "width": "width",
}


def make_tool(
    kind: str, diameter: float, what: str, where: Location | None = None, **kw: Any
) -> ToolShape:
    """A checked :class:`ToolShape` (``SIM-TOOL`` when a value does not fit the kind).
    ``what`` names the tool in the message."""

    def bad(msg: str) -> Diagnostic:
        return Diagnostic("SIM-TOOL", f"{what}: {msg}", where)

    kind = ALIASES.get(kind.strip().lower(), kind.strip().lower())
    if kind not in KINDS:
        raise bad(f"type must be one of {', '.join(KINDS)}")
    for key, value in kw.items():
        if key != "centre_cutting" and not (math.isfinite(value) and value >= 0):
            raise bad(f"{key} must be a number >= 0")
    if kind == "insert":
        return _insert(diameter, kw, bad)
    if not (math.isfinite(diameter) and diameter > 0):
        raise bad("diameter must be > 0")
    if kind in DEFAULT_ANGLE and not kw.get("angle"):
        kw["angle"] = DEFAULT_ANGLE[kind]
    tool = ToolShape(kind, float(diameter), **kw)
    if kind == "bull" and not 0 < tool.corner_radius <= tool.radius:
        raise bad("a bull nose needs 0 < corner_radius <= diameter / 2")
    if kind in DEFAULT_ANGLE and not 0 < tool.angle < 180:
        raise bad("the angle must be between 0 and 180 degrees")
    if tool.tip_diameter >= tool.diameter:
        raise bad("tip_diameter must be below the diameter")
    if kind == "flat" and tool.corner_radius > 0:
        tool = replace(tool, kind="bull")
    return tool


def _insert(nose: float, kw: dict[str, Any], bad: Callable[[str], Diagnostic]) -> ToolShape:
    """A lathe insert of nose radius ``nose`` (>= 0) and ``kw``'s ``width`` (along Z, at
    least twice the nose radius; :data:`INSERT_WIDTH` when absent)."""
    kw = dict(kw)
    nose = kw.pop("corner_radius", nose)
    width = kw.pop("width", 0.0) or max(INSERT_WIDTH, 2.0 * nose)
    if not (math.isfinite(nose) and nose >= 0):
        raise bad("an insert's nose radius must be >= 0")
    if not (math.isfinite(width) and width >= 2.0 * nose and width > 0):
        raise bad("an insert's width must be > 0 and at least twice its nose radius")
    for key in ("angle", "tip_diameter", "shank_diameter", "holder_diameter"):
        if kw.get(key):
            raise bad(f"{key} does not apply to a lathe insert")
    return ToolShape("insert", 2.0 * nose, corner_radius=nose, width=width, **kw)


def parse_tool_spec(text: str, where: Location | None = None) -> tuple[int, ToolShape]:
    """``N=KIND:DIAMETER[,flute=L][,corner=R][,angle=A][,tip=D][,shank=D][,shank_length=L]
    [,holder=D][,holder_length=L][,nocentre]`` -> (tool number, shape); ``SIM-TOOL`` when
    the text does not read so. ``N`` 0 is the tool used when none was loaded."""
    num, eq, rest = text.partition("=")
    head, *opts = rest.split(",")
    kind, colon, dia = head.partition(":")
    try:
        if not eq or not colon:
            raise ValueError
        number, diameter = int(num), float(dia)
    except ValueError:
        raise Diagnostic(
            "SIM-TOOL", f"tool {text!r} is not N=KIND:DIAMETER[,flute=L][,nocentre]", where
        ) from None
    if number < 0:
        raise Diagnostic("SIM-TOOL", f"tool {text!r}: the number must be >= 0", where)
    kw: dict[str, Any] = {}
    for opt in opts:
        key, _, value = opt.strip().partition("=")
        if key == "nocentre" and not value:
            kw["centre_cutting"] = False
        elif key in _NUMBERS:
            try:
                kw[_NUMBERS[key]] = float(value)
            except ValueError:
                kw[_NUMBERS[key]] = -1.0
            if key in ("flute", "flute_length") and not kw[_NUMBERS[key]] > 0:
                raise Diagnostic("SIM-TOOL", f"tool {text!r}: flute length must be > 0", where)
        else:
            raise Diagnostic("SIM-TOOL", f"tool {text!r}: unknown option {opt!r}", where)
    return number, make_tool(kind, diameter, f"tool {text!r}", where, **kw)


def library_from_toml(doc: dict[str, Any], where: str | None = None) -> dict[int, ToolShape]:
    """A tool library read from TOML::

        units = "mm"            # or "inch": every length below
        [tools.1]
        type = "bull"           # flat, ball, bull, drill, chamfer (v)
        diameter = 10
        corner_radius = 1
        flute_length = 22
        shank_diameter = 10
        shank_length = 15       # shank out of the holder above the flutes
        holder_diameter = 32
        holder_length = 40
        centre_cutting = true

    ``angle`` (or ``point_angle``) is a drill's point angle or a chamfer/V tool's included
    angle in degrees (118 and 90 when left out); ``tip_diameter`` a chamfer tool's flat tip.
    """
    loc = Location(where)
    units = doc.get("units", "mm")
    if units not in ("mm", "inch"):
        raise Diagnostic("SIM-TOOL", 'units must be "mm" or "inch"', loc)
    scale = 25.4 if units == "inch" else 1.0
    tools = doc.get("tools")
    if not isinstance(tools, dict) or not tools:
        raise Diagnostic("SIM-TOOL", "a tool library needs [tools.N] tables", loc)
    out: dict[int, ToolShape] = {}
    for key, table in tools.items():
        what = f"[tools.{key}]"
        try:
            number = int(key)
        except ValueError:
            number = -1
        if number < 0 or not isinstance(table, dict):
            raise Diagnostic("SIM-TOOL", f"{what}: the key must be a tool number >= 0", loc)
        kw: dict[str, Any] = {}
        for name, value in table.items():
            if name in ("type", "diameter", "comment", "name"):
                continue
            if name == "centre_cutting" or name == "center_cutting":
                if not isinstance(value, bool):
                    raise Diagnostic("SIM-TOOL", f"{what}: {name} must be true or false", loc)
                kw["centre_cutting"] = value
            elif (
                name in _NUMBERS and isinstance(value, int | float) and not isinstance(value, bool)
            ):
                field = _NUMBERS[name]
                kw[field] = float(value) * (1.0 if field == "angle" else scale)
            else:
                raise Diagnostic("SIM-TOOL", f"{what}: unknown or bad key {name!r}", loc)
        kind, dia = table.get("type"), table.get("diameter")
        if isinstance(kind, str) and ALIASES.get(kind, kind) == "insert" and dia is None:
            dia = 0.0  # an insert: its nose_radius is its size
        if not isinstance(kind, str) or not isinstance(dia, int | float):
            raise Diagnostic("SIM-TOOL", f"{what}: needs type and diameter", loc)
        size = float(dia) * scale
        if ALIASES.get(kind, kind) == "insert":
            size *= 0.5  # an insert is sized by its nose radius
        out[number] = make_tool(kind, size, what, loc, **kw)
    return out


def shapes_from_table(
    table: ToolTable, mm_per_unit: float = 1.0, lathe: bool = False
) -> dict[int, ToolShape]:
    """Flat end mills of a tool table's diameters (tools with no diameter are left out),
    or for a lathe inserts whose nose radius is half the diameter (LinuxCNC's lathe tool
    table gives the nose's diameter in D)."""
    if lathe:
        return {
            n: _insert(0.5 * t.diameter * mm_per_unit, {}, lambda m: Diagnostic("SIM-TOOL", m))
            for n, t in table.tools.items()
        }
    return {
        n: ToolShape("flat", t.diameter * mm_per_unit)
        for n, t in table.tools.items()
        if t.diameter > 0
    }
