"""``cnc stepnc``: inspect ISO 14649 (STEP-NC) programs and turn them into canonical
commands, RS274/NGC or solids."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable

import click

import kernel.limits as limits
from cli.errors import EXIT_PROGRAM_ERROR, EXIT_USAGE, guarded, report
from cli.options import force_option, output_option, program_argument, tool_table_option
from cli.outputs import refuse_output, replacing, write_output
from cli.programs import is_stdin, regular_input, stdin_text
from kernel.diagnostics import Diagnostic, Location, Severity
from stepnc.model import Entity, Model, load, load_text
from stepnc.schema import GROUPS
from stepnc.tooling import ToolEntry, load_tool_file

MODES = click.Choice(["nist", "default"])


def _write_guard(path: str, force: bool, inputs: tuple[str, ...] = ()) -> None:
    """Refuse an output that is an input (always) or exists (a symlink too) without --force."""
    refuse_output(path, force, inputs)


STEPNC_TOOLS = "NIST ISO 14649 tool file"


def _model(file: str, diagnostics: list[Diagnostic] | None = None) -> Model:
    """The program FILE (``<stdin>``: standard input), read and validated
    (:func:`stepnc.model.load`; collect-all when ``diagnostics`` is a list)."""
    if is_stdin(file):
        return load_text(stdin_text(), file, diagnostics)
    regular_input(file)
    return load(file, diagnostics)


def _tools(tool_file: str | None) -> dict[str, ToolEntry] | None:
    """The ``-t`` tool file's tools, or None."""
    if tool_file:
        regular_input(tool_file, "tool file")
    return load_tool_file(tool_file) if tool_file else None


def _raw(text: str | None) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        vals = tuple(float(v) for v in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != 6:
        raise click.BadParameter("give x0,y0,z0,x1,y1,z1", param_hint="--raw")
    return vals


def _interpreting(func):  # noqa: ANN001, ANN202
    """Turn a programming slip on unusual but valid input into a located diagnostic instead
    of a traceback (the model code raises Diagnostic for everything it anticipates)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        try:
            return func(*args, **kwargs)
        except (AttributeError, TypeError, ValueError, IndexError, KeyError) as exc:
            raise Diagnostic(
                "STEPNC-UNSUPPORTED",
                f"cannot interpret this program: {exc}",
                Location(kwargs.get("file")),
            ) from None

    return wrapper


@click.group("stepnc")
def command() -> None:
    """ISO 14649 STEP-NC programs (Part 21 files).

    \b
    Examples:
      cnc stepnc info ex1.stp
      cnc stepnc check book_fragment.stp
      cnc stepnc canon ex1.stp --tool-file iso14649.tool_ex1
      cnc stepnc to-gcode ex1.stp --dialect fanuc -o ex1.nc
      cnc stepnc part ex1.stp --raw 0,0,-45,100,120,5 -o part.step
      cnc stepnc gouge ex1.stp --raw 0,0,-45,100,120,5
    """


@command.command("info")
@program_argument("file")
@guarded
@_interpreting
def info(file: str) -> None:
    """Show the workplan, features, operations and tools as a tree."""
    from rich.console import Console
    from rich.markup import escape
    from rich.tree import Tree

    model = _model(file)
    project = model.project()
    root = Tree(f"[bold]PROJECT #{project.id}[/] {escape(repr(project.its_id))}")
    plan = project.main_workplan

    def walk(node: Tree, element: Entity, active: tuple[int, ...] = ()) -> None:
        label = f"[bold]{element.type}[/] #{element.id} {escape(repr(element.its_id))}"
        if element.id in active or len(active) >= limits.current().nesting:
            raise Diagnostic(
                "STEPNC-CYCLE",
                f"{element.type} #{element.id} contains itself or is nested too deeply",
                element.where(),
            )
        if element.type == "MACHINING_WORKINGSTEP":
            ws = node.add(label)
            f, op = element.its_feature, element.its_operation
            ws.add(f"feature {f.type} #{f.id} {escape(repr(f.its_id))}")
            o = ws.add(f"operation {op.type} #{op.id} {escape(repr(op.its_id))}")
            tool = op.its_tool
            o.add(f"tool #{tool.id} {escape(repr(tool.its_id))} ({_tool_kind(tool)})")
            strat = getattr(op, "its_machining_strategy", None)
            if isinstance(strat, Entity):
                o.add(f"strategy {strat.type} #{strat.id}")
            return
        sub = node.add(label)
        for attr in ("its_elements", "branches"):
            try:
                children = getattr(element, attr)
            except AttributeError:
                continue
            for child in children or ():
                walk(sub, child, (*active, element.id))

    walk(root, plan)
    tools = root.add("[bold]tools[/]")
    for t in model.p21.instances.values():
        if t.name in GROUPS["tool"]:
            tool = model.entity(t.id)
            kind = _tool_kind(tool).replace(", D=", " D=")
            tools.add(f"#{tool.id} {escape(repr(tool.its_id))} {kind}")
    Console().print(root)


def _tool_kind(tool: Entity) -> str:
    """Tool type and size: the body and diameter of a milling tool, the entity of a turning
    tool (with the insert width of a grooving tool)."""
    if tool.type == "MILLING_CUTTING_TOOL":
        body = tool.its_tool_body
        return f"{body.type}, D={float(body.dimension.diameter):g}"
    if tool.type == "GROOVING_TOOL":
        return f"{tool.type}, width {float(tool.cutting_width):g}"
    return tool.type


def _generation_problems(commands: Callable[[], Iterable[object]]) -> list[Diagnostic]:
    """The refusal of the toolpath generators, run to the end: what the model's validation
    cannot see (a B-spline with impossible knots, a feed or a tool that cannot cut) and
    ``stepnc canon``, ``to-gcode`` and ``plan`` would refuse."""
    try:
        for _ in commands():
            pass
    except Diagnostic as exc:
        return [exc]
    return []


@command.command("check")
@program_argument("file")
@guarded
@_interpreting
def check(file: str) -> None:
    """Report every problem in FILE (collect-all, salvaging what can be read), then make
    its toolpaths as ``stepnc canon`` does: AP238 AIM files (cutter-location toolpaths) too."""
    from stepnc.ap238 import canon_from_aim
    from stepnc.part21 import read_file
    from stepnc.to_canon import canon_from_model

    diags: list[Diagnostic] = []
    model = _model(file, diags)
    if not is_stdin(file) and diags and all(d.code == "STEPNC-AP238" for d in diags):
        diags = _generation_problems(lambda: canon_from_aim(read_file(file), "nist"))
    elif not any(d.record.severity is Severity.ERROR for d in diags):
        diags += _generation_problems(lambda: canon_from_model(model))
    for d in diags:
        report(d)
    errors = sum(d.record.severity is Severity.ERROR for d in diags)
    click.echo(f"{file}: {errors} error(s), {len(diags) - errors} warning(s)", err=True)
    if errors:
        raise SystemExit(EXIT_PROGRAM_ERROR)


@command.command("canon")
@program_argument("file")
@tool_table_option("tool_file", STEPNC_TOOLS, ("--tool-file",), must_exist=False)
@click.option("--mode", type=MODES, default="nist", show_default=True)
@click.option("--json", "as_json", is_flag=True, help="JSON lines instead of text")
@guarded
@_interpreting
def canon_cmd(file: str, tool_file: str | None, mode: str, as_json: bool) -> None:
    """Print the canonical machining commands of FILE."""
    from kernel.ir import canon
    from stepnc.to_canon import canon_from_file, canon_from_model

    if is_stdin(file):
        cmds = canon_from_model(_model(file), _tools(tool_file), mode)
    else:  # a file may be AP238's AIM form too
        regular_input(file)
        if tool_file:
            regular_input(tool_file, "tool file")
        cmds = canon_from_file(file, tool_file, mode)
    lines = canon.to_jsonl(cmds) if as_json else canon.write_text(cmds)
    for line in lines:
        click.echo(line)


@command.command("to-gcode")
@program_argument("file")
@tool_table_option("tool_file", STEPNC_TOOLS, ("--tool-file",), must_exist=False)
@click.option("--mode", type=MODES, default="default", show_default=True)
@click.option(
    "-d",
    "--dialect",
    default="rs274ngc",
    show_default=True,
    help="target dialect (as cnc convert --to: rs274ngc, fanuc, grbl, ...)",
)
@output_option(help="file (default stdout)")
@force_option(help="overwrite OUTPUT")
@guarded
@_interpreting
def to_gcode(
    file: str, tool_file: str | None, mode: str, dialect: str, output: str | None, force: bool
) -> None:
    """Write FILE as a G-code program (RS274/NGC by default)."""
    from stepnc.to_canon import canon_from_model

    if output is not None:
        _write_guard(output, force, (file, tool_file or ""))
    from gcode.write.writer import write as emit_write

    cmds = canon_from_model(_model(file), _tools(tool_file), mode)
    text = "".join(f"{line}\n" for line in emit_write(cmds, dialect))
    if output is None:
        click.echo(text, nl=False)
        return
    write_output(output, text)


@command.command("part")
@program_argument("file")
@output_option(required=True, help=".step/.stp or .stl")
@click.option("--raw", help="raw block x0,y0,z0,x1,y1,z1 when the workpiece has none")
@force_option(help="overwrite OUTPUT")
@guarded
@_interpreting
def part(file: str, output: str, raw: str | None, force: bool) -> None:
    """Write the finished part (workpiece minus features; a turning program's bar less its
    turned features) as STEP or STL."""
    from stepnc import geometry, turned

    if not output.lower().endswith((".step", ".stp", ".stl")):
        raise click.UsageError("OUTPUT must end in .step, .stp or .stl")
    _write_guard(output, force, (file,))
    model = _model(file)
    shape = (
        turned.turned_solid(turned.turned_profile(model))
        if turned.is_turning(model)
        else geometry.finished_part(model, _raw(raw))
    )
    with replacing(output) as tmp:
        geometry.export(shape, tmp)
    click.echo(f"{output}: finished part, volume {geometry.volume(shape):.3f} mm^3")


@command.command("gouge")
@program_argument("file")
@tool_table_option("tool_file", STEPNC_TOOLS, ("--tool-file",), must_exist=False)
@click.option("--mode", type=MODES, default="nist", show_default=True)
@click.option("--raw", help="raw block x0,y0,z0,x1,y1,z1 when the workpiece has none")
@guarded
@_interpreting
def gouge_cmd(file: str, tool_file: str | None, mode: str, raw: str | None) -> None:
    """Check every cutting move against the finished part, per workingstep."""
    from stepnc import gouge, turned
    from stepnc.to_canon import canon_from_model

    model = _model(file)
    tools = _tools(tool_file)
    commands = canon_from_model(model, tools, mode)
    if turned.is_turning(model):
        result = turned.turning_gouges(model, commands)
    else:
        result = gouge.check(model, commands, _raw(raw))
    bad = 0
    for ws, found in result.items():
        status = "ok" if not found else f"{len(found)} gouging move(s)"
        click.echo(f"#{ws} {model.entity(ws).its_id!r}: {status}")
        for g in found[:3]:
            click.echo(f"    command {g.command + 1} at {tuple(round(c, 4) for c in g.point)}")
        bad += len(found)
    if bad:
        raise SystemExit(EXIT_PROGRAM_ERROR)


__all__ = ["command", "EXIT_USAGE"]
