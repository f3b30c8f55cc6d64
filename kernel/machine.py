"""The machine profile: axes, their limits, and the controller settings the planner needs.

A profile is a TOML file (DESIGN.md, *The machine profile*); :data:`DEFAULT_MACHINE` is the
built-in 3-axis mill used when none is given. Units are the kernel's: mm (deg for rotary
axes), seconds, and their powers. Every field is documented in ``docs/machine-profile.md``.

``kind`` says what the machine is (:data:`KINDS`: mill, router, laser, plasma, lathe), so
``cnc check`` judges a program as that machine runs it (:class:`KindTraits`); the
``cnc machine init --kind`` presets are in :mod:`kernel.machine_presets`.

``[m_codes]`` names the M codes the machine's PLC takes (MACHINE_FUNCTION events), with the
time each holds the program and whether it is forbidden. Tables other than ``[axes.*]``,
``[controller]`` and ``[m_codes]`` (``[spindle]``, ``[servo]``, ``[tools]``, ...) belong to
other parts of the toolchain; they are kept verbatim in :attr:`Machine.extra`. Inside the
tables read here an unknown key is an error (``MACH-KEY``), so a misspelt limit never
silently falls back to a default.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, fields
from typing import Any

from kernel.diagnostics import Diagnostic, Location
from kernel.profile_where import ProfileWhere, profile_where

AXIS_NAMES: tuple[str, ...] = ("x", "y", "z", "a", "b", "c")
ROTARY: frozenset[str] = frozenset({"a", "b", "c"})
ACCDEC_TYPES: tuple[str, ...] = ("trapezoid", "scurve")
CORNER_RULES: tuple[str, ...] = ("axis", "angle")
CONTROLLER_MODELS: tuple[str, ...] = ("book", "linuxcnc", "grbl")
#: where LinuxCNC's planner passes an axis limit, the ``linuxcnc`` model does as it does or
#: keeps the limit (Controller.axis_limits)
AXIS_LIMIT_POLICIES: tuple[str, ...] = ("linuxcnc", "strict")
CIRCLE_METHODS: tuple[str, ...] = (
    "exact",
    "euler",
    "improved_euler",
    "taylor",
    "tustin",
    "improved_tustin",
)


@dataclass(frozen=True, slots=True)
class AxisLimits:
    """One axis: travel (mm or deg), velocity, acceleration, jerk (per s, s², s³).

    ``servo`` holds the axis' ``[axes.<name>.servo]`` table untouched, for the servo stage.
    ``steps_per_mm``: the drive's step resolution (Grbl's ``$100..$102``), which the ``grbl``
    model rounds block ends to; 0 (the default): no step grid.
    """

    name: str
    min: float = -math.inf
    max: float = math.inf
    velocity: float = 100.0
    acceleration: float = 1000.0
    jerk: float = 50000.0
    home: float = 0.0
    servo: dict[str, Any] = field(default_factory=dict, compare=False)
    steps_per_mm: float = 0.0

    @property
    def rotary(self) -> bool:
        return self.name in ROTARY


@dataclass(frozen=True, slots=True)
class Controller:
    """Controller settings (book ch. 4 and 6; NISTIR 5970 §3.5.3 for the path modes).

    ``interpolation_period``: sampling period of the interpolator, s (book ch. 6: 1-8 ms).
    ``lookahead``: number of buffered blocks N including the current one (book §4.4; 1 = none).
    ``accdec``: ``trapezoid`` (bounded acceleration) or ``scurve`` (bounded jerk).
    ``corner_rule``: ``axis`` (per-axis speed difference, book §4.3.4) or ``angle`` (§4.3.3).
    ``corner_velocity_step``: allowed per-axis speed step at a corner as a multiple of
    acceleration x interpolation period (ΔV_m of book Eq. 4.91).
    ``blend_tolerance``: path deviation allowed by ``G64`` without ``P``, mm (0: exact path).
    ``chord_tolerance``: chord error allowed on arcs and NURBS, mm (book Eqs. 3.83, 4.98).
    ``arc_acceleration_ratio``: share of the axis acceleration given to centripetal
    acceleration on arcs (the book's performance index α of Eq. 4.97 as a fraction).
    ``rapid_rate``: path speed cap for traverses, mm/s (0: as fast as the axes allow).
    ``max_feed``: path speed cap for feed moves, mm/s (0: none beyond the axes).
    ``tool_change_time``, ``spindle_orient_time``, ``program_stop_time``: durations, s.
    ``circle_method``: arc sampling, ``exact`` or a sampled-data method of book §3.3.2.
    ``feed_override``: feed override factor applied while overrides are enabled.
    ``model``: the planner strategy (kernel.plan.strategy): ``book`` (the ADCBI look-ahead of
    kernel.plan.planner), ``linuxcnc`` (LinuxCNC 2.9's trajectory planner) or ``grbl``
    (Grbl 1.1's planner).
    ``junction_deviation``, ``arc_tolerance``: Grbl's ``$11`` and ``$12``, mm (``grbl`` model).
    ``axis_limits``: where LinuxCNC 2.9's planner itself passes an axis limit (a steep
    helix's tangential share, from its effective radius; a parabolic blend whose two moves
    add up), the ``linuxcnc`` model does the same (``linuxcnc``: the machine's time, and the
    report shows the hit) or keeps every axis within its limit (``strict``).
    """

    interpolation_period: float = 0.001
    lookahead: int = 200
    accdec: str = "trapezoid"
    corner_rule: str = "axis"
    corner_velocity_step: float = 1.0
    blend_tolerance: float = 0.0
    chord_tolerance: float = 0.001
    arc_acceleration_ratio: float = 0.5
    rapid_rate: float = 0.0
    max_feed: float = 0.0
    tool_change_time: float = 5.0
    spindle_orient_time: float = 0.5
    program_stop_time: float = 0.0
    circle_method: str = "exact"
    feed_override: float = 1.0
    model: str = "book"
    junction_deviation: float = 0.01
    arc_tolerance: float = 0.002
    axis_limits: str = "linuxcnc"


@dataclass(frozen=True, slots=True)
class MCode:
    """One ``[m_codes]`` entry: an M code the machine's PLC takes (a MACHINE_FUNCTION).

    ``time``: seconds the machine holds there (the program waits for the PLC's answer);
    ``forbid``: the machine must never be sent it (a located error in plan and check).
    """

    name: str = ""
    time: float = 0.0
    forbid: bool = False


@dataclass(frozen=True, slots=True)
class KindTraits:
    """How a kind of machine runs a program, as far as ``cnc check`` must know.

    ``beam``: the spindle words switch a laser beam or a plasma torch (M3/M4 and M5, or
    M7/M8, or M62-M65 outputs): a feed move with it off is a travel move, not a cut with the
    spindle stopped, S is a power, and there is no tool length to offset.
    ``manual_speed``: the spindle's speed is set by hand (a router's dial), so M3 without S
    is normal. ``turret_offsets``: the T word applies the tool's offsets (a lathe's
    ``T0101``); there is no G43 tool length compensation to forget.
    """

    beam: bool = False
    manual_speed: bool = False
    turret_offsets: bool = False


#: the kinds of machine a profile may name (``kind = "laser"``), with their traits
KINDS: dict[str, KindTraits] = {
    "mill": KindTraits(),
    "router": KindTraits(manual_speed=True),
    "laser": KindTraits(beam=True),
    "plasma": KindTraits(beam=True),
    "lathe": KindTraits(turret_offsets=True),
}


@dataclass(frozen=True, slots=True)
class Machine:
    """A machine profile: named axes in order, controller settings, the PLC's M codes,
    other tables verbatim, and the kind of machine (:data:`KINDS`)."""

    name: str
    axes: tuple[AxisLimits, ...]
    controller: Controller = field(default_factory=Controller)
    extra: dict[str, Any] = field(default_factory=dict, compare=False)
    m_codes: dict[int, MCode] = field(default_factory=dict, hash=False)
    kind: str = "mill"
    # where each key is written in the profile's file (error locations; not part of equality)
    where: ProfileWhere = field(default_factory=ProfileWhere, compare=False, repr=False)

    @property
    def traits(self) -> KindTraits:
        """What the machine's kind means for checking a program."""
        return KINDS[self.kind]

    @property
    def axis_names(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.axes)

    def axis(self, name: str) -> AxisLimits:
        for a in self.axes:
            if a.name == name:
                return a
        raise KeyError(name)

    def limit_vector(self, attr: str) -> tuple[float, ...]:
        """``attr`` (velocity, acceleration, jerk, min, max) for all six axes X..C.

        Axes the machine lacks get 0 for velocity/acceleration/jerk (they cannot move).
        """
        out = []
        for n in AXIS_NAMES:
            try:
                out.append(float(getattr(self.axis(n), attr)))
            except KeyError:
                out.append(
                    0.0
                    if attr in ("velocity", "acceleration", "jerk", "home", "steps_per_mm")
                    else (-math.inf if attr == "min" else math.inf)
                )
        return tuple(out)


def filter_time(machine: Machine) -> float:
    """S-curve smoothing time ``T_f = 2 max_i A_i / J_i`` over the machine's axes (the 2:
    the moving average's jerk is the acceleration difference across ``T_f``, up to 2A).
    kernel.plan.planner smooths with it; kernel.path.curvature cuts lines ``T_f v`` from joints."""
    return 2.0 * max(a.acceleration / a.jerk for a in machine.axes)


DEFAULT_MACHINE = Machine(
    name="default 3-axis mill (mm)",
    axes=(
        AxisLimits("x", -400.0, 400.0, velocity=250.0, acceleration=2000.0, jerk=50000.0),
        AxisLimits("y", -250.0, 250.0, velocity=250.0, acceleration=2000.0, jerk=50000.0),
        AxisLimits("z", -300.0, 200.0, velocity=200.0, acceleration=1500.0, jerk=40000.0),
    ),
    # a P position loop of K_v 30/s with balanced speed feedforward, as current controls
    # ship (book §5.4.3.4): following error = feed x the speed loop's delay, not feed/K_v;
    # the spindle of the `cnc machine init` starter profile
    extra={
        "servo": {"kp": 30.0, "feedforward": "speed"},
        "spindle": {"min_speed": 0.0, "max_speed": 12000.0},
    },
)

_AXIS_KEYS = {f.name for f in fields(AxisLimits)} - {"name"}
_CONTROLLER_FIELDS = {f.name: f for f in fields(Controller)}


def _number(value: object, what: str, loc: Location, *, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise Diagnostic("MACH-TYPE", f"{what} must be a number, not {value!r}", loc)
    v = float(value)
    if math.isnan(v) or (positive and not v > 0):
        raise Diagnostic("MACH-RANGE", f"{what} must be positive, got {value!r}", loc)
    return v


def _axis(name: str, table: object, where: ProfileWhere) -> AxisLimits:
    loc = where.at("axes", name)
    if name not in AXIS_NAMES:
        raise Diagnostic(
            "MACH-AXIS", f"unknown axis {name!r}; axes are {', '.join(AXIS_NAMES)}", loc
        )
    if not isinstance(table, dict):
        raise Diagnostic("MACH-TYPE", f"[axes.{name}] must be a table", loc)
    unknown = sorted(set(table) - _AXIS_KEYS)
    if unknown:
        raise Diagnostic(
            "MACH-KEY",
            f"[axes.{name}]: unknown key(s) {', '.join(unknown)}",
            where.at("axes", name, unknown[0]),
        )
    kw: dict[str, Any] = {}
    for key, value in table.items():
        loc = where.at("axes", name, key)
        if key == "servo":
            if not isinstance(value, dict):
                raise Diagnostic("MACH-TYPE", f"[axes.{name}.servo] must be a table", loc)
            kw[key] = dict(value)
        else:
            pos = key in ("velocity", "acceleration", "jerk")
            kw[key] = _number(value, f"axes.{name}.{key}", loc, positive=pos)
            if key == "steps_per_mm" and not 0 <= kw[key] < math.inf:
                raise Diagnostic("MACH-RANGE", f"axes.{name}.{key} must be finite, >= 0", loc)
    axis = AxisLimits(name, **kw)
    if not axis.min < axis.max:
        raise Diagnostic(
            "MACH-RANGE",
            f"axes.{name}: min {axis.min} must be below max {axis.max}",
            where.at("axes", name, "max" if "max" in table else "min"),
        )
    return axis


def _controller(table: object, where: ProfileWhere) -> Controller:
    if not isinstance(table, dict):
        raise Diagnostic("MACH-TYPE", "[controller] must be a table", where.at("controller"))
    kw: dict[str, Any] = {}
    for key, value in table.items():
        loc = where.at("controller", key)
        if key not in _CONTROLLER_FIELDS:
            raise Diagnostic("MACH-KEY", f"[controller]: unknown key {key!r}", loc)
        what = f"controller.{key}"
        if key == "lookahead":
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 10**6:
                raise Diagnostic("MACH-RANGE", f"{what} must be an integer from 1 to 10**6", loc)
            kw[key] = value
        elif key in ("accdec", "corner_rule", "circle_method", "model", "axis_limits"):
            allowed = {
                "accdec": ACCDEC_TYPES,
                "corner_rule": CORNER_RULES,
                "circle_method": CIRCLE_METHODS,
                "model": CONTROLLER_MODELS,
                "axis_limits": AXIS_LIMIT_POLICIES,
            }[key]
            if value not in allowed:
                raise Diagnostic("MACH-RANGE", f"{what} must be one of {', '.join(allowed)}", loc)
            kw[key] = value
        else:
            pos = key in (
                "interpolation_period",
                "chord_tolerance",
                "feed_override",
                "corner_velocity_step",
                "junction_deviation",
                "arc_tolerance",
            )
            v = _number(value, what, loc, positive=pos)
            if v < 0:
                raise Diagnostic("MACH-RANGE", f"{what} must not be negative", loc)
            if key == "interpolation_period" and v > 1.0:
                # controls interpolate every 0.1-10 ms; a longer period makes the servo's
                # discrete model singular
                raise Diagnostic("MACH-RANGE", f"{what} must be at most 1 s, got {v:g}", loc)
            if key == "arc_acceleration_ratio" and not 0 < v < 1:
                raise Diagnostic("MACH-RANGE", f"{what} must lie strictly between 0 and 1", loc)
            kw[key] = v
    return Controller(**kw)


_M_CODE_KEYS = {"name", "time", "forbid"}


def _m_codes(table: object, where: ProfileWhere) -> dict[int, MCode]:
    """``[m_codes]``: ``31 = {name = "chip conveyor on", time = 2.0, forbid = false}``."""
    if not isinstance(table, dict):
        raise Diagnostic("MACH-TYPE", "[m_codes] must be a table", where.at("m_codes"))
    out: dict[int, MCode] = {}
    for key, entry in table.items():
        loc = where.at("m_codes", key)
        digits = key[1:] if key[:1] in ("M", "m") else key
        if not digits.isdigit() or len(digits) > 8:
            raise Diagnostic(
                "MACH-KEY",
                f"[m_codes]: {key!r} is not an M code (31 or M31, 8 digits at most)",
                loc,
            )
        code = int(digits)
        what = f"m_codes.{key}"
        if code in out:
            raise Diagnostic("MACH-KEY", f"[m_codes]: M{code} given twice", loc)
        if not isinstance(entry, dict):
            raise Diagnostic("MACH-TYPE", f"{what} must be a table (name, time, forbid)", loc)
        unknown = sorted(set(entry) - _M_CODE_KEYS)
        if unknown:
            raise Diagnostic(
                "MACH-KEY",
                f"{what}: unknown key(s) {', '.join(unknown)}",
                where.at("m_codes", key, unknown[0]),
            )
        name = entry.get("name", "")
        if not isinstance(name, str):
            raise Diagnostic(
                "MACH-TYPE", f"{what}.name must be a string", where.at("m_codes", key, "name")
            )
        forbid = entry.get("forbid", False)
        if not isinstance(forbid, bool):
            raise Diagnostic(
                "MACH-TYPE",
                f"{what}.forbid must be true or false",
                where.at("m_codes", key, "forbid"),
            )
        time_at = where.at("m_codes", key, "time")
        time = _number(entry.get("time", 0.0), f"{what}.time", time_at)
        if not 0.0 <= time < math.inf:
            raise Diagnostic("MACH-RANGE", f"{what}.time must be a finite number >= 0", time_at)
        out[code] = MCode(name, time, forbid)
    return out


def machine_from_dict(
    data: dict[str, Any], file: str | None = None, where: ProfileWhere | None = None
) -> Machine:
    """Build a :class:`Machine` from parsed TOML; raises ``MACH-*`` diagnostics, located by
    ``where`` (the positions of the profile's keys) when the text is known."""
    where = where or ProfileWhere(file)
    axes_t = data.get("axes")
    if not isinstance(axes_t, dict) or not axes_t:
        raise Diagnostic(
            "MACH-AXIS", "the profile needs at least one [axes.<name>] table", where.at("axes")
        )
    order = sorted(axes_t, key=lambda n: AXIS_NAMES.index(n) if n in AXIS_NAMES else 99)
    axes = tuple(_axis(n, axes_t[n], where) for n in order)
    controller = _controller(data.get("controller", {}), where)
    name = data.get("name", file or "machine")
    if not isinstance(name, str):
        raise Diagnostic("MACH-TYPE", "name must be a string", where.at("name"))
    m_codes = _m_codes(data.get("m_codes", {}), where)
    kind = data.get("kind", "mill")
    if kind not in KINDS:
        raise Diagnostic(
            "MACH-KIND",
            f"kind must be one of {', '.join(KINDS)}, not {kind!r}",
            where.at("kind"),
        )
    top = ("axes", "controller", "name", "m_codes", "kind")
    extra = {k: v for k, v in data.items() if k not in top}
    return Machine(name, axes, controller, extra, m_codes, kind, where)


def parse_machine(text: str, file: str | None = None) -> Machine:
    """Parse TOML text into a :class:`Machine` (``MACH-TOML`` on a syntax error)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise Diagnostic("MACH-TOML", f"not valid TOML: {exc}", Location(file)) from None
    return machine_from_dict(data, file, profile_where(text, file))


def with_controller(machine: Machine, **changes: Any) -> Machine:
    """A copy of ``machine`` with some controller fields replaced (validated like TOML)."""
    current = {f: getattr(machine.controller, f) for f in _CONTROLLER_FIELDS}
    current.update(changes)
    return Machine(
        machine.name,
        machine.axes,
        _controller(current, ProfileWhere()),
        machine.extra,
        machine.m_codes,
        machine.kind,
        machine.where,
    )
