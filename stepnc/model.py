"""Typed view of an ISO 14649 program and its validation.

:class:`Model` wraps a :class:`~stepnc.part21.Part21File`; :class:`Entity` gives attribute
access by the schema names of :mod:`stepnc.schema` (``ws.its_operation.its_tool.its_id``),
with references resolved, logicals as ``bool`` and typed parameters unwrapped.

:func:`validate` checks the file against the schema and some physics, collecting located
diagnostics: unknown entity, wrong attribute count or type, missing mandatory value,
dangling reference, unreferenced instances, and impossible geometry (a tool wider than a
pocket or its corners, a bottom fillet smaller than the tool's edge radius, a drill larger
than its hole; research/seed-book-stepnc.md §7.2 "good validation-rule tests").
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from kernel.diagnostics import Diagnostic, Location, Severity
from stepnc import schema
from stepnc.part21 import Enum, Part21File, Ref, Typed, check_references, references


class Entity:
    """One instance seen through the schema. Unknown attribute names raise AttributeError."""

    __slots__ = ("model", "inst")

    def __init__(self, model: Model, inst) -> None:  # noqa: ANN001
        self.model = model
        self.inst = inst

    @property
    def id(self) -> int:
        return self.inst.id

    @property
    def type(self) -> str:
        return self.inst.name or "<complex>"

    def is_a(self, *names: str) -> bool:
        return any(schema.accepts(n, self.inst.name) for n in names)

    def __getattr__(self, name: str) -> Any:
        """The schema attribute ``name``, resolved: an :class:`Entity`, a number, a string,
        a bool, a tuple of these or None, as the file says (so its static type is Any)."""
        attrs = schema.ATTRS.get(self.inst.name or "")
        if attrs is not None:
            for i, a in enumerate(attrs):
                if a.name == name:
                    params = self.inst.params
                    return self.model.resolve(params[i]) if i < len(params) else None
        raise AttributeError(f"{self.type} #{self.id} has no attribute {name!r}")

    def raw(self, name: str) -> object:
        """The attribute as stored (references not resolved)."""
        attrs = schema.ATTRS[self.inst.name or ""]
        for i, a in enumerate(attrs):
            if a.name == name:
                return self.inst.params[i] if i < len(self.inst.params) else None
        raise AttributeError(name)

    def where(self, workingstep: int | None = None) -> Location:
        loc = self.model.p21.location(self.id)
        if workingstep is None:
            return loc
        return Location(loc.file, loc.line, loc.column, loc.entity, workingstep)

    def __repr__(self) -> str:
        return f"<{self.type} #{self.id}>"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Entity) and other.inst is self.inst

    def __hash__(self) -> int:
        return hash(self.inst.id)


class Model:
    """A Part 21 file as ISO 14649 objects."""

    def __init__(self, p21: Part21File) -> None:
        self.p21 = p21
        self.file = p21.file

    def entity(self, ref: int) -> Entity:
        inst = self.p21.instances.get(int(ref))
        if inst is None:
            raise Diagnostic(
                "P21-DANGLING-REF",
                f"#{int(ref)} is referenced but not defined",
                Location(self.file, entity=int(ref)),
            )
        return Entity(self, inst)

    def resolve(self, value: object) -> object:
        if isinstance(value, Ref):
            return self.entity(value)
        if isinstance(value, Enum):
            return True if value == "T" else False if value == "F" else value
        if isinstance(value, Typed):
            return self.resolve(value.value)
        if isinstance(value, tuple):
            return tuple(self.resolve(v) for v in value)
        return value

    def all(self, name: str) -> Iterator[Entity]:
        return (Entity(self, i) for i in self.p21.instances.values() if i.name == name)

    def project(self) -> Entity:
        projects = list(self.all("PROJECT"))
        if len(projects) != 1:
            raise Diagnostic(
                "STEPNC-PROJECT",
                f"a program needs exactly one PROJECT, found {len(projects)}",
                Location(self.file),
            )
        return projects[0]


# --------------------------------------------------------------------------- validation
class _Sink:
    def __init__(self, diagnostics: list[Diagnostic] | None) -> None:
        self.diags = diagnostics

    def add(
        self, code: str, message: str, loc: Location, severity: Severity = Severity.ERROR
    ) -> None:
        diag = Diagnostic(code, message, loc, severity)
        if self.diags is None:
            if severity is Severity.ERROR:
                raise diag
            return
        self.diags.append(diag)


def validate(model: Model, diagnostics: list[Diagnostic] | None = None) -> None:
    """Check ``model`` against the schema and geometry rules.

    With ``diagnostics=None`` the first error is raised; otherwise every problem (errors and
    warnings) is appended to the list.
    """
    p21 = model.p21
    sink = _Sink(diagnostics)
    referenced: set[int] = set()
    for inst in p21.instances.values():
        referenced.update(references(inst.params))
    for inst in p21.instances.values():
        _check_instance(model, inst, sink, referenced)
    check_references(p21, diagnostics)
    for inst in p21.instances.values():
        if inst.id not in referenced and inst.name not in ("PROJECT", None):
            sink.add(
                "STEPNC-ORPHAN",
                f"#{inst.id} ({inst.name}) is defined but never referenced",
                p21.location(inst.id),
                Severity.WARNING,
            )
    _check_geometry(model, sink)


def _check_instance(model: Model, inst, sink: _Sink, referenced: set[int]) -> None:  # noqa: ANN001
    loc = model.p21.location(inst.id)
    if inst.name is None:
        for part in inst.params:
            if part.name not in schema.ATTRS:
                sink.add(
                    "STEPNC-UNKNOWN-ENTITY",
                    f"#{inst.id}: unknown entity {part.name} in complex instance",
                    loc,
                )
        return
    attrs = schema.ATTRS.get(inst.name)
    if attrs is None:
        sink.add(
            "STEPNC-UNKNOWN-ENTITY",
            f"#{inst.id}: {inst.name} is not an ISO 14649 entity this reader knows",
            loc,
        )
        return
    params = inst.params
    # an integer equal to an unreferenced instance id: probably a reference missing its '#'
    for i, v in enumerate(params):
        if type(v) is int and v in model.p21.instances and v not in referenced:
            sink.add(
                "STEPNC-MISSING-HASH",
                f"#{inst.id}: attribute {i + 1} is the number "
                f"{v}; #{v} is defined but never referenced, so '#{v}' was probably "
                "meant",
                loc,
            )
    if len(params) != len(attrs):
        if inst.id in model.p21.salvaged:
            return  # already reported as unterminated
        names = ", ".join(a.name for a in attrs)
        sink.add(
            "STEPNC-ATTR-COUNT",
            f"#{inst.id}: {inst.name} has {len(attrs)} attributes ({names}), found {len(params)}",
            loc,
        )
        return
    for a, v in zip(attrs, params, strict=True):
        _check_attr(model, inst, a, v, sink, loc)


_IDENTIFIER_LABELS = frozenset({"name", "its_id"})
"""Mandatory labels that only name an instance: ``$`` there is a warning, not an error."""


def _check_attr(
    model: Model,
    inst,
    a: schema.Attr,
    v: object,
    sink: _Sink,  # noqa: ANN001
    loc: Location,
) -> None:
    where = f"#{inst.id}: {inst.name}.{a.name}"
    if v is None:
        if a.optional:
            return
        if a.kind == "label" and a.name in _IDENTIFIER_LABELS:
            # A name carries no machining meaning; STEP readers accept an unset one.
            sink.add(
                "STEPNC-LENIENT",
                f"{where} is mandatory but is $; read as an unnamed {inst.name}",
                loc,
                Severity.WARNING,
            )
            return
        sink.add("STEPNC-ATTR-MISSING", f"{where} is mandatory but is $", loc)
        return
    values: tuple = (v,)
    if a.is_list:
        if not isinstance(v, tuple):
            sink.add(
                "STEPNC-ATTR-TYPE",
                f"{where} must be a list (...) of {a.describe()[8:]}, found {_show(v)}",
                loc,
            )
            return
        values = v
    elif isinstance(v, tuple):
        sink.add("STEPNC-ATTR-TYPE", f"{where} must be {a.describe()}, found a list", loc)
        return
    for x in values:
        problem = schema.check_scalar(a, x)
        if problem:
            sink.add("STEPNC-ATTR-TYPE", f"{where} must be {problem}, found {_show(x)}", loc)
            return
        if a.kind == "ref" and a.arg and isinstance(x, Ref):
            target = model.p21.instances.get(int(x))
            if target is not None and not schema.accepts(a.arg, target.name):
                sink.add(
                    "STEPNC-REF-TYPE",
                    f"{where} must refer to {a.arg}, but #{int(x)} is {target.name}",
                    loc,
                )
                return


def _show(v: object) -> str:
    from stepnc.part21 import format_value

    try:
        return format_value(v)
    except (TypeError, ValueError):
        return repr(v)


# --------------------------------------------------------------------------- geometry rules
def measure(e: object) -> float | None:
    """Theoretical size of a TOLERANCED_LENGTH_MEASURE (or a plain number)."""
    if isinstance(e, Entity):
        if e.type == "TOLERANCED_LENGTH_MEASURE":
            return float(e.theoretical_size)
        if e.type == "NUMERIC_PARAMETER":
            return float(e.its_parameter_value)
        return None
    return float(e) if isinstance(e, (int, float)) else None


def tool_dimension(tool: Entity) -> Entity:
    return tool.its_tool_body.dimension


def _check_geometry(model: Model, sink: _Sink) -> None:
    """Per workingstep; a workingstep whose entities are malformed (already reported by the
    schema checks) is skipped."""
    for ws in model.all("MACHINING_WORKINGSTEP"):
        try:
            _check_workingstep(ws, sink)
        except Diagnostic as exc:
            if exc.code != "P21-DANGLING-REF":
                raise  # a geometry finding in strict mode
        except (AttributeError, TypeError, ValueError, IndexError):
            continue


def _check_workingstep(ws: Entity, sink: _Sink) -> None:
    feature, op = ws.its_feature, ws.its_operation
    if not isinstance(feature, Entity) or not isinstance(op, Entity):
        return
    dim = tool_dimension(op.its_tool)
    diameter = float(dim.diameter)
    edge = dim.edge_radius
    loc = op.where(ws.id)
    if not diameter > 0:
        # toolpaths offset by a negative radius cut outside the feature
        sink.add(
            "STEPNC-TOOL-DIAMETER",
            f"tool {op.its_tool.its_id!r} has diameter {diameter:g}: it must be positive",
            loc,
        )
        return
    if feature.type in ("CLOSED_POCKET", "OPEN_POCKET") and op.is_a(
        "BOTTOM_AND_SIDE_ROUGH_MILLING",
        "BOTTOM_AND_SIDE_FINISH_MILLING",
        "SIDE_ROUGH_MILLING",
        "SIDE_FINISH_MILLING",
    ):
        side = op.allowance_side or 0.0
        corner = measure(feature.orthogonal_radius)
        if corner is not None and diameter / 2 > corner - side + 1e-9:
            sink.add(
                "STEPNC-TOOL-CORNER",
                f"tool {op.its_tool.its_id!r} of radius "
                f"{diameter / 2:g} cannot reach the corners of {feature.its_id!r} "
                f"(corner radius {corner:g} minus side allowance {side:g})",
                loc,
            )
        fillet = measure(feature.planar_radius)
        if fillet and edge and fillet < float(edge):
            sink.add(
                "STEPNC-FILLET-EDGE",
                f"bottom fillet radius {fillet:g} of "
                f"{feature.its_id!r} is below the tool edge radius {edge:g}",
                loc,
            )
        boundary = getattr(feature, "feature_boundary", None)
        if isinstance(boundary, Entity) and boundary.type == "RECTANGULAR_CLOSED_PROFILE":
            # the narrow side, whichever of width and length it is (ISO 14649-10 does not
            # order them)
            width = min(
                measure(boundary.profile_width) or 0.0, measure(boundary.profile_length) or 0.0
            )
            if corner is not None and corner > width / 2 + 1e-9:
                sink.add(
                    "STEPNC-POCKET",
                    f"corner radius {corner:g} of {feature.its_id!r} exceeds half the pocket "
                    f"width {width:g}",
                    loc,
                )
            if diameter > width - 2 * side + 1e-9:
                sink.add(
                    "STEPNC-TOOL-WIDTH",
                    f"tool diameter {diameter:g} does not fit "
                    f"pocket width {width:g} minus side allowances",
                    loc,
                )
    shape = getattr(feature, "swept_shape", None) if feature.type == "SLOT" else None
    if (
        isinstance(shape, Entity)
        and shape.type == "SQUARE_U_PROFILE"
        and op.is_a(
            "BOTTOM_AND_SIDE_ROUGH_MILLING",
            "BOTTOM_AND_SIDE_FINISH_MILLING",
            "SIDE_ROUGH_MILLING",
            "SIDE_FINISH_MILLING",
        )
    ):
        side = op.allowance_side or 0.0
        width = measure(shape.width) or 0.0
        if diameter > width - 2 * side + 1e-9:
            sink.add(
                "STEPNC-TOOL-WIDTH",
                f"tool diameter {diameter:g} does not fit slot {feature.its_id!r} of width "
                f"{width:g} minus side allowances {side:g}",
                loc,
            )
    if feature.type == "ROUND_HOLE" and op.is_a(
        "DRILLING", "REAMING", "BORING", "MULTISTEP_DRILLING", "TAPPING"
    ):
        hole = measure(feature.diameter)
        if hole is not None and diameter > hole + 1e-9:
            sink.add(
                "STEPNC-TOOL-HOLE",
                f"tool diameter {diameter:g} is larger than the "
                f"hole diameter {hole:g} of {feature.its_id!r}",
                loc,
            )


def load(path: str, diagnostics: list[Diagnostic] | None = None) -> Model:
    """Read and validate a program (strict unless ``diagnostics`` is a list)."""
    from stepnc.part21 import read_file

    return _validated(Model(read_file(path, diagnostics)), path, diagnostics)


def load_text(text: str, name: str, diagnostics: list[Diagnostic] | None = None) -> Model:
    """:func:`load` of a program given as text (``name`` is used in locations: standard
    input is ``<stdin>``)."""
    from stepnc.part21 import parse

    return _validated(Model(parse(text, name, diagnostics)), name, diagnostics)


def _validated(model: Model, path: str, diagnostics: list[Diagnostic] | None) -> Model:
    """``model`` after the AP238 and validity checks of :func:`load`."""
    schemas = file_schemas(model)
    if any(name in _AIM_SCHEMAS for name in schemas):
        # One message instead of one unknown-entity error per AIM instance.
        diag = Diagnostic(
            "STEPNC-AP238",
            f"FILE_SCHEMA {', '.join(schemas)} is the AP238 AIM (integrated CNC) form; this "
            "reader takes the ISO 14649 ARM (MACHINING_SCHEMA) form only",
            Location(path, 1, 1),
        )
        if diagnostics is None:
            raise diag
        diagnostics.append(diag)
        return model
    validate(model, diagnostics)
    return model


#: FILE_SCHEMA names of AP238's implementation form (ISO 10303-238 AIM)
_AIM_SCHEMAS = frozenset({"INTEGRATED_CNC_SCHEMA", "AP238_INTEGRATED_CNC_SCHEMA"})


def file_schemas(model: Model) -> tuple[str, ...]:
    """The schema names of the file's FILE_SCHEMA header entry, upper case."""
    for word, params in model.p21.header:
        if word == "FILE_SCHEMA" and params:
            names = params[0] if isinstance(params[0], tuple) else (params[0],)
            return tuple(str(n).upper() for n in names if isinstance(n, str))
    return ()
