"""STEP-NC (ISO 14649) program -> canonical machining commands.

``canon_from_file(path, tool_file=None, mode="nist")`` reads, validates and executes the
project's main workplan and yields :mod:`kernel.ir.canon` commands, one workingstep at a time
(bounded memory). Every command carries ``source=Location(file, line, column, entity=<op
#id>, workingstep=<ws #id>)``.

``mode="nist"`` reproduces NIST's ISO 14649 interpreter command for command (its strategy
defaults, state-change-only output and start-up state; ``corpus/stepnc/ex1.can``);
``mode="default"`` starts from a known machine state and follows the standard where NIST
chose otherwise. The differences are listed in ``docs/stepnc.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import kernel.limits as limits
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc.ap238 import canon_from_aim
from stepnc.executor import DEFAULT_START, NIST_START, Executor, start_within
from stepnc.frames import Frame, coords, frame_of
from stepnc.model import Entity, Model, load
from stepnc.part21 import read_file
from stepnc.tooling import ToolEntry, load_tool_file
from stepnc.toolpaths import drilling, explicit, facing, open_pocket, pocket, slot, step, turning

FAMILIES = {
    "PLANE_ROUGH_MILLING": facing,
    "PLANE_FINISH_MILLING": facing,
    "BOTTOM_AND_SIDE_ROUGH_MILLING": pocket,
    "BOTTOM_AND_SIDE_FINISH_MILLING": pocket,
    "DRILLING": drilling,
    "MULTISTEP_DRILLING": drilling,
    "REAMING": drilling,
    "BORING": drilling,
    "CENTER_DRILLING": drilling,
    "COUNTER_SINKING": drilling,
    "TAPPING": drilling,
    "FREEFORM_OPERATION": explicit,
}
#: side and bottom-and-side milling by feature (pockets: FAMILIES above)
_BY_FEATURE = {"SLOT": slot, "STEP": step, "OPEN_POCKET": open_pocket}
_SIDE_MILLING = frozenset(
    {
        "SIDE_ROUGH_MILLING",
        "SIDE_FINISH_MILLING",
        "BOTTOM_AND_SIDE_ROUGH_MILLING",
        "BOTTOM_AND_SIDE_FINISH_MILLING",
    }
)
#: families that set their own coolant and technology (NIST ``cut_feature``)
_SELF_TECHNOLOGY = frozenset({"DRILLING", "FREEFORM_OPERATION"})


@dataclass(frozen=True)
class Job:
    """One machining workingstep ready for a toolpath generator."""

    ws: Entity
    feature: Entity
    op: Entity
    frame: Frame  # feature placement in setup coordinates


def canon_from_file(
    path: str, tool_file: str | None = None, mode: str = "nist", z_max: float | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a Part 21 program (raises :class:`Diagnostic` on bad input).

    ``z_max``: the machine's Z travel limit; a start-up retract height above it is lowered
    to it, with a comment saying so."""
    try:
        model = load(path)
    except Diagnostic as exc:
        if exc.code != "STEPNC-AP238":
            raise
        # an AP238 AIM file: its cutter-location toolpaths (conformance class 1)
        yield from canon_from_aim(read_file(path), mode, z_max)
        return
    tools = load_tool_file(tool_file) if tool_file else None
    yield from canon_from_model(model, tools, mode, z_max)


def canon_from_model(
    model: Model,
    tools: dict[str, ToolEntry] | None = None,
    mode: str = "nist",
    z_max: float | None = None,
) -> Iterator[canon.Command]:
    start = NIST_START if mode == "nist" else DEFAULT_START
    fitted = start if z_max is None else start_within(start, z_max)
    ex = Executor(model.file, tools, mode, fitted)
    project = model.project()
    ex.source = project.where()
    plan = project.main_workplan
    setup_z, wp_frame = _setup(model, project, plan)
    ex.preamble(start)
    ex.security_z = setup_z
    yield from ex.take()
    for element in _walk(plan, ex):
        try:
            _execute(ex, element, wp_frame, setup_z)
        except Diagnostic as exc:
            if exc.location.file is not None:
                raise
            # a limit reached inside a toolpath generator: at the operation
            where = ex.source if ex.source.entity is not None else element.where()
            raise Diagnostic(exc.code, exc.message, where) from None
        except (AttributeError, TypeError, ValueError, IndexError, ZeroDivisionError) as exc:
            # a valid file can still combine entities in ways no generator expects
            raise Diagnostic(
                "STEPNC-UNSUPPORTED",
                f"cannot execute {element.type} #{element.id}: {exc}",
                ex.source if ex.source.entity is not None else element.where(),
            ) from None
        yield from ex.take()
    ex.source = project.where()
    ex.emit(canon.ProgramEnd())
    yield from ex.take()


def _setup(model: Model, project: Entity, plan: Entity) -> tuple[float, Frame]:
    """(security Z of the setup, workpiece frame in setup coordinates)."""
    setup = plan.its_setup
    if setup is None:
        return 0.0, Frame()
    sec = setup.its_secplane
    z = coords(sec.position.location)[2] if sec is not None else 0.0
    frame = Frame()
    workpieces = project.its_workpieces or ()
    for wps in setup.its_workpiece_setup or ():
        if not workpieces or wps.its_workpiece == workpieces[0]:
            frame = frame_of(wps.its_origin)
            break
    # Coordinates are setup coordinates (NIST): the setup's own placement (its_origin) is
    # where the machinist puts the setup on the machine, so it is not applied here.
    return z, frame


#: the setup's security Z and workpiece frame (for modules that place features as the
#: executor does)
setup_frames = _setup


def _walk(
    element: Entity, ex: Executor, active: tuple[int, ...] = (), count: list[int] | None = None
) -> Iterator[Entity]:
    """Executables in execution order (ISO 14649-10 §4.6.1). A workplan that contains
    itself is STEPNC-CYCLE; nesting past ``kernel.limits`` nesting is LIMIT-NESTING and more
    executables than ``cycle_passes`` (a plan of plans, each twice) LIMIT-COUNT."""
    t = element.type
    count = [0] if count is None else count
    if t == "WORKPLAN" or t == "NON_SEQUENTIAL" or t == "SELECTIVE" or t == "PARALLEL":
        if element.id in active:
            raise Diagnostic("STEPNC-CYCLE", f"{t} #{element.id} contains itself", element.where())
        lim = limits.current()
        if len(active) >= lim.nesting:
            loc = element.where()
            raise limits.nesting_error(loc.file, loc.line, loc.column)
        inner = (*active, element.id)
        if t == "PARALLEL":
            elements = element.branches or ()
        else:
            elements = element.its_elements or ()
            if t == "SELECTIVE":
                elements = elements[:1]  # the controller may choose: take the first alternative
        for e in elements:
            yield from _walk(e, ex, inner, count)
    elif t in ("IF_STATEMENT", "WHILE_STATEMENT"):
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            f"{t} needs run-time conditions, which this interpreter does not evaluate",
            element.where(),
        )
    else:
        count[0] += 1
        limit = limits.current().cycle_passes
        if count[0] > limit:
            raise limits.count_error(
                "executables of the workplan", count[0], limit, "cycle_passes", element.where()
            )
        yield element


def _execute(ex: Executor, element: Entity, wp_frame: Frame, setup_z: float) -> None:
    t = element.type
    ex.source = element.where(element.id)
    if t == "MACHINING_WORKINGSTEP":
        _machining(ex, element, wp_frame)
        ex.security_z = setup_z
    elif t == "RAPID_MOVEMENT":
        _rapid(ex, element)
    elif t == "DISPLAY_MESSAGE":
        ex.emit(canon.Message(str(element.its_text)))
    elif t == "PROGRAM_STOP":
        ex.emit(canon.ProgramStop())
    elif t == "OPTIONAL_STOP":
        ex.emit(canon.OptionalProgramStop())
    elif t == "LOAD_TOOL":
        ex.handle_tool(element.its_tool)
    elif t == "UNLOAD_TOOL":
        if ex.tool_id is not None:
            if ex.spindle is not canon.Direction.STOPPED:
                ex.emit(canon.StopSpindleTurning())
                ex.spindle = canon.Direction.STOPPED
            ex.emit(canon.SpindleRetract())
            ex.emit(canon.UseToolLengthOffset(0.0))
            ex.emit(canon.ChangeTool(0))
            ex.tool_id = None
    elif t == "EXCHANGE_PALLET":
        ex.emit(canon.PalletShuttle())
    else:
        raise Diagnostic("STEPNC-UNSUPPORTED", f"{t} cannot be executed", element.where())


def _machining(ex: Executor, ws: Entity, wp_frame: Frame) -> None:
    feature, op = ws.its_feature, ws.its_operation
    if op.type in turning.TURNING_OPS:
        if op not in (feature.its_operations or ()):
            raise Diagnostic(
                "STEPNC-OP-FEATURE",
                f"operation #{op.id} is not one of the operations of feature #{feature.id}",
                ws.where(ws.id),
            )
        ex.at(op, ws)
        turning.generate(ex, ws, feature, op, wp_frame)
        return
    family = FAMILIES.get(op.type)
    if op.type in _SIDE_MILLING and feature.type in _BY_FEATURE:
        family = _BY_FEATURE[feature.type]
    if family is None:
        raise Diagnostic(
            "STEPNC-UNSUPPORTED", f"no toolpath generator for {op.type}", op.where(ws.id)
        )
    if op not in (feature.its_operations or ()):
        raise Diagnostic(
            "STEPNC-OP-FEATURE",
            f"operation #{op.id} is not one of the operations of feature #{feature.id}",
            ws.where(ws.id),
        )
    ex.at(op, ws)
    ex.handle_tool(op.its_tool)
    frame = wp_frame.compose(frame_of(feature.feature_placement))
    if not frame.vertical:
        raise Diagnostic(
            "STEPNC-PLACEMENT",
            f"feature #{feature.id} must have its Z axis along the machine Z axis",
            feature.where(ws.id),
        )
    secplane = ws.its_secplane
    ex.security_z = frame.origin[2] + coords(secplane.position.location)[2]
    if op.type not in _SELF_TECHNOLOGY:
        ex.machine_functions(op.its_machine_functions)
        ex.technology(op.its_technology, op.its_tool)
    family.generate(ex, Job(ws, feature, op, frame))


def _rapid(ex: Executor, rapid: Entity) -> None:
    """A rapid movement along its explicit toolpath, in setup coordinates."""
    tpl = rapid.its_toolpath
    if tpl is None:
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            "a RAPID_MOVEMENT without a toolpath leaves the path to the controller; give one",
            rapid.where(rapid.id),
        )
    for seg in tpl.its_list:
        curve = seg.basiccurve if seg.type == "CUTTER_LOCATION_TRAJECTORY" else None
        if curve is None or curve.type != "POLYLINE":
            raise Diagnostic(
                "STEPNC-UNSUPPORTED",
                "rapid movements support polyline trajectories",
                seg.where(rapid.id),
            )
        pts = [coords(p) for p in curve.points]
        if max(abs(a - b) for a, b in zip(pts[0], (ex.x, ex.y, ex.z), strict=True)) > 1e-4:
            raise Diagnostic(
                "STEPNC-RAPID-START",
                "a rapid movement must start at the current tool position",
                seg.where(rapid.id),
            )
        for p in pts[1:]:
            ex.emit(canon.StraightTraverse(*p))
        ex.x, ex.y, ex.z = pts[-1]


__all__ = ["Job", "canon_from_file", "canon_from_model", "setup_frames"]
