"""The RS274/NGC interpreter's modules depend one way: the interpreter imports its parts,
the parts share state through :class:`gcode.ngc.context.NgcContext` and never import the
interpreter or each other in a circle (imports inside functions and under TYPE_CHECKING
count too)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from gcode.core.state import FeedCode, SavedModes, Setup
from kernel.ir.canon import Direction, FeedMode, Plane, Units

ROOT = Path(__file__).resolve().parents[1]
#: the interpreter and the modules it runs (the group that once formed one import cycle)
GROUP = (
    "gcode.ngc.interpreter",
    "gcode.ngc.context",
    "gcode.ngc.modes",
    "gcode.ngc.motion",
    "gcode.ngc.offsets",
    "gcode.ngc.cycles",
    "gcode.ngc.mcodes",
    "gcode.ngc.lane.lane",
    "gcode.ngc.oword",
    "gcode.ngc.predefined",
    "gcode.ngc.threading",
    "gcode.core.state",
    "gcode.ngc.comp.api",
)


def _imports(name: str) -> tuple[set[str], list[int]]:
    """The ``gcode`` modules (dotted names, ``from a import b`` counted as ``a.b`` too) that
    module ``name`` imports anywhere, and the lines of imports placed inside functions."""
    tree = ast.parse((ROOT / Path(*name.split("."))).with_suffix(".py").read_text())
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("gcode"):
            found.add(node.module)
            found.update(f"{node.module}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("gcode."))
    local = [
        inner.lineno
        for fn in ast.walk(tree)
        if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef)
        for inner in ast.walk(fn)
        if isinstance(inner, ast.Import | ast.ImportFrom)
    ]
    return found, local


@pytest.mark.parametrize(
    "name", [n for n in GROUP if n != "gcode.ngc.interpreter"], ids=lambda n: n.split(".")[-1]
)
def test_parts_do_not_import_the_interpreter(name: str) -> None:
    found, local = _imports(name)
    assert "gcode.ngc.interpreter" not in found
    assert local == [], f"{name} imports inside functions at lines {local}"


def test_the_group_has_no_import_cycle() -> None:
    edges = {n: {m for m in _imports(n)[0] if m in GROUP} for n in GROUP}
    done: set[str] = set()

    def visit(n: str, path: tuple[str, ...]) -> None:
        assert n not in path, "import cycle: " + " -> ".join((*path, n))
        if n in done:
            return
        for m in sorted(edges[n]):
            visit(m, (*path, n))
        done.add(n)

    for n in GROUP:
        visit(n, ())


def test_feed_codes_and_modes_map_both_ways() -> None:
    assert [c.mode for c in FeedCode] == [
        FeedMode.INVERSE_TIME,
        FeedMode.UNITS_PER_MINUTE,
        FeedMode.UNITS_PER_REVOLUTION,
    ]
    for code in FeedCode:
        assert FeedCode.of(code.mode) is code
    assert FeedCode(930) is FeedCode.G93


def test_saved_modes_copy_the_setup() -> None:
    s = Setup()
    s.units, s.plane, s.spindle, s.feed_rate = Units.INCHES, Plane.XZ, Direction.CLOCKWISE, 12.5
    saved = SavedModes.of(s)
    assert (saved.units, saved.plane, saved.spindle, saved.feed_rate) == (
        Units.INCHES,
        Plane.XZ,
        Direction.CLOCKWISE,
        12.5,
    )
    s.feed_rate = 3.0
    assert saved.feed_rate == 12.5
