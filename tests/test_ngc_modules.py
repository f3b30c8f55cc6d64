"""The RS274/NGC interpreter's modules depend one way: the interpreter imports its parts,
the parts share state through :class:`gcode.ngc_context.NgcContext` and never import the
interpreter or each other in a circle (imports inside functions and under TYPE_CHECKING
count too)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from gcode.state import FeedCode, SavedModes, Setup
from kernel.canon import Direction, FeedMode, Plane, Units

GCODE = Path(__file__).resolve().parents[1] / "gcode"
#: the interpreter and the modules it runs (the group that once formed one import cycle)
GROUP = (
    "interpreter",
    "ngc_context",
    "modes",
    "motion",
    "offsets",
    "cycles",
    "mcodes",
    "lane",
    "oword",
    "predefined",
    "threading",
    "state",
    "comp_api",
)


def _imports(name: str) -> tuple[set[str], list[int]]:
    """The ``gcode`` modules ``gcode/<name>.py`` imports anywhere, and the lines of imports
    placed inside functions."""
    tree = ast.parse((GCODE / f"{name}.py").read_text())
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("gcode"):
            if node.module == "gcode":
                found.update(a.name for a in node.names)
            else:
                found.add(node.module.split(".")[1])
        elif isinstance(node, ast.Import):
            found.update(a.name.split(".")[1] for a in node.names if a.name.startswith("gcode."))
    local = [
        inner.lineno
        for fn in ast.walk(tree)
        if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef)
        for inner in ast.walk(fn)
        if isinstance(inner, ast.Import | ast.ImportFrom)
    ]
    return found, local


@pytest.mark.parametrize("name", [n for n in GROUP if n != "interpreter"])
def test_parts_do_not_import_the_interpreter(name: str) -> None:
    found, local = _imports(name)
    assert "interpreter" not in found
    assert local == [], f"gcode/{name}.py imports inside functions at lines {local}"


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
