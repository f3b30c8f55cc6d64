"""AP238 (ISO 10303-238) AIM files, conformance class 1: explicit cutter-location toolpaths
(and the program stop, optional stop and display message NC functions).

The AIM (``FILE_SCHEMA(('INTEGRATED_CNC_SCHEMA'))``) encodes a workplan as action methods
tied by relationships. The paths followed here are those of the AP238 ed. 3 mapping
specification (github.com/stepmfg/ap238, ``data/clause5.htm``; entity attributes from
``data/ap238e3_aim_lf.exp``):

* workplan elements: ``MACHINING_PROCESS_SEQUENCE_RELATIONSHIP`` (a ``sequential_method``:
  name, description, relating_method, related_method, sequence_position) from the
  ``MACHINING_WORKPLAN`` (§5.1.6.43.1), in sequence position order;
* a workingstep's operation: ``MACHINING_OPERATION_RELATIONSHIP`` (§5.1.6.39.3);
* an operation's toolpaths: ``MACHINING_TOOLPATH_SEQUENCE_RELATIONSHIP`` (§5.1.7.4.2), each a
  ``MACHINING_TOOLPATH`` described ``'cutter location trajectory'`` (§5.1.8.10) whose
  ``'basic curve'`` action property holds the curve (§5.1.8.10.1); ``'trajectory type'``
  ``'connect'`` or a ``'speed profile'`` ``'rapid'`` makes it a traverse (§5.1.8.13);
* coolant: the ``'coolant'`` property (``'coolant on'``/``'coolant off'``) of the
  ``MACHINING_FUNCTIONS`` of the operation's ``MACHINING_FUNCTIONS_RELATIONSHIP``
  (§5.1.9.38.1);
* technology: ``MACHINING_TECHNOLOGY_RELATIONSHIP`` from the operation (or the toolpath) to a
  ``MACHINING_TECHNOLOGY`` whose ``'feedrate'`` and ``'spindle'`` properties are measures
  with units (§5.1.7.5);
* the tool: the ``MACHINING_TOOL`` resource whose ``usage`` holds the operation.

Anything else (other trajectory kinds, NC functions, units it cannot convert) stops with
one STEPNC-AP238 diagnostic naming the construct.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterator

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from stepnc.executor import DEFAULT_START, NIST_START, Executor, start_within
from stepnc.frames import Frame
from stepnc.model import Model
from stepnc.p21_values import Instance, Part, Part21File, Ref, Typed
from stepnc.part21 import check_references
from stepnc.schema import GROUPS
from stepnc.toolpaths.code import Code
from stepnc.toolpaths.explicit import follow_curve

_SEQUENCES = frozenset(
    {"MACHINING_PROCESS_SEQUENCE_RELATIONSHIP", "MACHINING_TOOLPATH_SEQUENCE_RELATIONSHIP"}
)
_RELATIONS = frozenset(
    {
        "MACHINING_OPERATION_RELATIONSHIP",
        "MACHINING_TECHNOLOGY_RELATIONSHIP",
        "MACHINING_FUNCTIONS_RELATIONSHIP",
    }
)


class Aim:
    """Indexes of an AP238 AIM file: relationships, action properties, tool usage."""

    def __init__(self, p21: Part21File) -> None:
        self.p21 = p21
        self.children: dict[tuple[str, int], list[tuple[float, int]]] = defaultdict(list)
        self.parents: set[int] = set()
        self.props: dict[tuple[int, str], list[int]] = defaultdict(list)
        self.tools: dict[int, Instance] = {}
        prop_of: dict[int, tuple[int, str]] = {}
        for inst in p21.instances.values():
            name, p = inst.name, inst.params
            if name in _SEQUENCES and len(p) == 5:
                self.children[(name, int(p[2]))].append((float(p[4]), int(p[3])))
                if name == "MACHINING_PROCESS_SEQUENCE_RELATIONSHIP":
                    self.parents.add(int(p[3]))
            elif name in _RELATIONS and len(p) == 4:
                self.children[(name, int(p[2]))].append((0.0, int(p[3])))
            elif name == "ACTION_PROPERTY" and len(p) == 3 and isinstance(p[2], Ref):
                prop_of[inst.id] = (int(p[2]), str(p[0]))
            elif name == "MACHINING_TOOL" and len(p) == 4:
                for used in p[2] if isinstance(p[2], tuple) else ():
                    self.tools[int(used)] = inst
        for inst in p21.instances.values():
            p = inst.params
            if inst.name == "ACTION_PROPERTY_REPRESENTATION" and len(p) == 4:
                key = prop_of.get(int(p[2])) if isinstance(p[2], Ref) else None
                if key is not None and isinstance(p[3], Ref):
                    self.props[key].append(int(p[3]))
        for kids in self.children.values():
            kids.sort()

    def get(self, ref: int) -> Instance:
        inst = self.p21.instances.get(ref)
        if inst is None:
            raise Diagnostic(
                "P21-DANGLING-REF", f"#{ref} is referenced but not defined", self.where(ref)
            )
        return inst

    def where(self, ref: int) -> Location:
        return self.p21.location(ref)

    def related(self, rel: str, ref: int) -> list[int]:
        return [r for _, r in self.children.get((rel, ref), ())]

    def items(self, ref: int, prop: str) -> list[Instance]:
        """The representation items of action property ``prop`` of ``ref``."""
        out: list[Instance] = []
        for rep in self.props.get((ref, prop), ()):
            r = self.get(rep)
            items = r.params[1] if len(r.params) > 1 and isinstance(r.params[1], tuple) else ()
            out.extend(self.get(int(i)) for i in items if isinstance(i, Ref))
        return out

    def description(self, ref: int, prop: str) -> str | None:
        """The description of the descriptive item of property ``prop``, if any."""
        for item in self.items(ref, prop):
            if item.name == "DESCRIPTIVE_REPRESENTATION_ITEM" and len(item.params) == 2:
                return str(item.params[1])
        return None


def refuse(message: str, where: Location) -> Diagnostic:
    return Diagnostic("STEPNC-AP238", message, where)


# ---------------------------------------------------------------------------- units
def _parts(inst: Instance) -> dict[str, tuple]:
    """Partial entity values of a complex instance (or the instance itself)."""
    if inst.name is None:
        return {part.name: part.params for part in inst.params if isinstance(part, Part)}
    return {inst.name: inst.params}


def _named_scale(aim: Aim, ref: int) -> tuple[str, float]:
    """(quantity, scale) of a named unit: length in mm, time in minutes, rotation in
    revolutions, frequency in revolutions per minute."""
    parts = _parts(aim.get(ref))
    si = parts.get("SI_UNIT")
    if si is not None and len(si) == 2:
        prefix = {"MILLI": 1e-3, "CENTI": 1e-2, "KILO": 1e3, None: 1.0}.get(
            str(si[0]) if si[0] is not None else None
        )
        base = str(si[1])
        if prefix is not None and base == "METRE":
            return "length", prefix * 1000.0
        if prefix == 1.0 and base == "SECOND":
            return "time", 1.0 / 60.0
        if prefix == 1.0 and base == "HERTZ":
            return "rate", 60.0
    conv = parts.get("CONVERSION_BASED_UNIT")
    if conv is not None and len(conv) == 2:
        label = str(conv[0]).lower()
        if label in ("inch", "in"):
            return "length", 25.4
        if label in ("minute", "min"):
            return "time", 1.0
        if label in ("revolution", "rev"):
            return "turn", 1.0
        if label in ("rpm", "revolution per minute", "revolutions per minute"):
            return "rate", 1.0
    raise refuse(f"unit #{ref} is not a unit this reader converts", aim.where(ref))


def _unit(aim: Aim, ref: int) -> dict[str, float]:
    """A unit as quantity -> (scale, exponent) folded into {quantity: scale**exponent}."""
    inst = aim.get(ref)
    if inst.name == "DERIVED_UNIT":
        out: dict[str, float] = {}
        for el in inst.params[0]:
            e = aim.get(int(el))
            q, s = _named_scale(aim, int(e.params[0]))
            exp = float(e.params[1])
            out[q] = out.get(q, 1.0) * s**exp
            out[q + "^"] = out.get(q + "^", 0.0) + exp
        return out
    q, s = _named_scale(aim, ref)
    return {q: s, q + "^": 1.0}


def _measure(aim: Aim, item: Instance) -> tuple[float, dict[str, float]]:
    """Value and unit of a MEASURE_REPRESENTATION_ITEM (simple, or complex with a
    MEASURE_WITH_UNIT part)."""
    params = item.params
    if item.name is None:
        mwu = _parts(item).get("MEASURE_WITH_UNIT")
        params = ("", *mwu) if mwu is not None else ()
    if len(params) != 3 or not isinstance(params[2], Ref):
        raise refuse(f"#{item.id} is not a measure with a unit", aim.where(item.id))
    value = params[1]
    if isinstance(value, Typed):
        value = value.value
    if not isinstance(value, (int, float)):
        raise refuse(f"#{item.id} has no numeric value", aim.where(item.id))
    return float(value), _unit(aim, int(params[2]))


def _feed(aim: Aim, tech: int) -> float | None:
    """mm/min of the technology's 'feedrate' property."""
    for item in aim.items(tech, "feedrate"):
        value, u = _measure(aim, item)
        if u.get("length^") == 1.0 and u.get("time^") == -1.0:
            feed = value * u["length"] * u["time"]
            if not 0.0 <= feed < math.inf:  # a negative value or a time unit of 0 s
                raise refuse(f"feedrate #{item.id} is {feed:g} mm/min", aim.where(item.id))
            return feed
        raise refuse(f"feedrate #{item.id} is not a length per time", aim.where(item.id))
    return None


def _spindle(aim: Aim, tech: int) -> float | None:
    """rpm of the technology's 'spindle' property (positive counterclockwise)."""
    for item in aim.items(tech, "spindle") or aim.items(tech, "spindle speed"):
        value, u = _measure(aim, item)
        speed = math.nan
        if u.get("rate^") == 1.0:
            speed = value * u["rate"]
        elif u.get("turn^") == 1.0 and u.get("time^") == -1.0:
            speed = value * u["turn"] * u["time"]
        else:
            raise refuse(f"spindle speed #{item.id} is not a rotational speed", aim.where(item.id))
        if not math.isfinite(speed):  # a time unit of 0 s
            raise refuse(f"spindle speed #{item.id} is {speed:g} rpm", aim.where(item.id))
        return speed
    return None


# ---------------------------------------------------------------------------- execution
def canon_from_aim(
    p21: Part21File, mode: str = "default", z_max: float | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of an AP238 AIM file's cutter-location toolpaths (``z_max``: the
    machine's Z travel, as for :func:`stepnc.to_canon.canon_from_model`). A reference to an
    instance the file does not define is ``P21-DANGLING-REF`` at its first referrer, as in
    an ISO 14649 file, before anything is read."""
    check_references(p21)
    aim = Aim(p21)
    start = NIST_START if mode == "nist" else DEFAULT_START
    fitted = start if z_max is None else start_within(start, z_max)
    ex = Executor(p21.file, None, mode, fitted)
    plans = [
        i
        for i in p21.instances.values()
        if i.name == "MACHINING_WORKPLAN" and i.id not in aim.parents
    ]
    if not plans:
        raise refuse("the file has no MACHINING_WORKPLAN", Location(p21.file, 1, 1))
    _check_length_units(aim)
    ex.source = aim.where(plans[0].id)
    ex.preamble(start)
    ex.security_z = ex.z
    yield from ex.take()
    model = Model(p21)
    for ws in _walk(aim, plans[0].id, ()):
        if aim.get(ws).name == "MACHINING_NC_FUNCTION":
            _nc_function(aim, ex, ws)
        else:
            _workingstep(aim, model, ex, ws)
        yield from ex.take()
    ex.emit(canon.ProgramEnd())
    yield from ex.take()


def _check_length_units(aim: Aim) -> None:
    """Coordinates are read as mm: a geometric context in another length unit is refused."""
    for inst in aim.p21.instances.values():
        ctx = _parts(inst).get("GLOBAL_UNIT_ASSIGNED_CONTEXT")
        if not ctx or not isinstance(ctx[0], tuple):
            continue
        for unit in ctx[0]:
            if not isinstance(unit, Ref) or "LENGTH_UNIT" not in _parts(aim.get(int(unit))):
                continue
            quantity, scale = _named_scale(aim, int(unit))
            if quantity == "length" and abs(scale - 1.0) > 1e-12:
                raise refuse(
                    f"the geometry is in a length unit of {scale:g} mm (#{int(unit)}); only "
                    "millimetre coordinates are read",
                    aim.where(inst.id),
                )


def _walk(aim: Aim, plan: int, active: tuple[int, ...]) -> Iterator[int]:
    if plan in active or len(active) > 32:
        raise Diagnostic("STEPNC-CYCLE", f"workplan #{plan} contains itself", aim.where(plan))
    for child in aim.related("MACHINING_PROCESS_SEQUENCE_RELATIONSHIP", plan):
        name = aim.get(child).name
        if name == "MACHINING_WORKPLAN":
            yield from _walk(aim, child, (*active, plan))
        elif name == "MACHINING_WORKINGSTEP" or name == "MACHINING_NC_FUNCTION":
            yield child
        else:
            raise refuse(
                f"{name} #{child} in a workplan: only workingsteps with cutter-location "
                "toolpaths (AP238 conformance class 1) are read",
                aim.where(child),
            )


def _nc_function(aim: Aim, ex: Executor, ref: int) -> None:
    """Program stop, optional stop and display message (§5.1.6.3, .20, .23)."""
    inst = aim.get(ref)
    desc = str(inst.params[1]) if len(inst.params) > 1 else ""
    loc = aim.where(ref)
    ex.source = Location(loc.file, loc.line, loc.column, ref, ref)
    if desc == "program stop":
        ex.emit(canon.ProgramStop())
    elif desc == "optional stop":
        ex.emit(canon.OptionalProgramStop())
    elif desc == "display message":
        ex.emit(canon.Message(aim.description(ref, "message text") or ""))
    else:
        raise refuse(
            f"MACHINING_NC_FUNCTION #{ref} ({desc!r}): only program stop, optional stop and "
            "display message are read",
            loc,
        )


def _workingstep(aim: Aim, model: Model, ex: Executor, ws: int) -> None:
    ops = aim.related("MACHINING_OPERATION_RELATIONSHIP", ws)
    if len(ops) != 1:
        raise refuse(f"workingstep #{ws} needs exactly one operation", aim.where(ws))
    op = ops[0]
    loc = aim.where(op)
    ex.source = Location(loc.file, loc.line, loc.column, op, ws)
    tool = aim.tools.get(op)
    if tool is None:
        raise refuse(f"operation #{op} has no MACHINING_TOOL", aim.where(op))
    ident = str(tool.params[0])
    if ident != ex.tool_id:
        ex.stop_for_tool_change()  # an AP238 program never turns mist on
        if ex.z != ex.retracted_z:
            ex.emit(canon.SpindleRetract())
            ex.z = ex.retracted_z
        ex.emit(canon.ChangeTool(ex.pocket_of(ident, model.entity(tool.id)), ident))
        ex.tool_id = ident
    for funcs in aim.related("MACHINING_FUNCTIONS_RELATIONSHIP", op):
        coolant = aim.description(funcs, "coolant")  # §5.1.9.38.1
        if coolant in ("coolant on", "coolant off") and (coolant == "coolant on") is not ex.flood:
            ex.flood = coolant == "coolant on"
            ex.emit(canon.FloodOn() if ex.flood else canon.FloodOff())
    op_tech = aim.related("MACHINING_TECHNOLOGY_RELATIONSHIP", op)
    paths = aim.related("MACHINING_TOOLPATH_SEQUENCE_RELATIONSHIP", op)
    if not paths:
        raise refuse(f"operation #{op} has no toolpath (conformance class 1)", aim.where(op))
    join = None
    for tp in paths:
        inst = aim.get(tp)
        desc = str(inst.params[1]) if len(inst.params) > 1 else ""
        if inst.name != "MACHINING_TOOLPATH" or desc != "cutter location trajectory":
            raise refuse(
                f"{inst.name} #{tp} ({desc!r}): only cutter location trajectories are read",
                aim.where(tp),
            )
        tech = aim.related("MACHINING_TECHNOLOGY_RELATIONSHIP", tp) or op_tech
        if tech:
            _technology(aim, ex, tech[0])
        rapid = aim.description(tp, "trajectory type") == "connect" or (
            aim.description(tp, "speed profile") == "rapid"
        )
        if aim.items(tp, "tool axis"):
            raise refuse(
                f"toolpath #{tp} has a tool axis curve: multi-axis toolpaths are not read",
                aim.where(tp),
            )
        items = aim.items(tp, "basic curve")
        curves = [i for i in items if i.name in GROUPS["curve"]]
        if len(curves) != 1:
            kinds = ", ".join(sorted({i.name or "complex instance" for i in items})) or "none"
            raise refuse(
                f"toolpath #{tp} needs one basic curve this reader follows (found: {kinds})",
                aim.where(tp),
            )
        code = Code()
        first = join is None
        join = follow_curve(ex, model.entity(curves[0].id), code, rapid, join, [], Frame())
        if first:
            ex.security_z = max(ex.z, code[0][3])
            ex.start_and_run(code)
        else:
            ex.run(code)


def _technology(aim: Aim, ex: Executor, tech: int) -> None:
    rpm = _spindle(aim, tech)
    if rpm is not None:
        if rpm > 0:
            ex.spin(rpm, canon.Direction.COUNTERCLOCKWISE)
        elif rpm < 0:
            ex.spin(-rpm, canon.Direction.CLOCKWISE)
    feed = _feed(aim, tech)
    if feed is not None:
        ex.set_feed(feed)


__all__ = ["Aim", "canon_from_aim"]
