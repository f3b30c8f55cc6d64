"""The architecture of docs/architecture.md holds in the code: data flows one way.

The import graph is read from the source with ``ast`` (every ``import``, including those inside
functions and under ``TYPE_CHECKING``), so a cycle cannot hide behind a late import.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("gcode", "stepnc", "kernel", "cli")
FRONT_ENDS = ("gcode", "stepnc", "cli")


def modules() -> dict[str, Path]:
    """Dotted module name -> file, for every module of the project's packages."""
    found: dict[str, Path] = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join(parts)] = path
    return found


def imported(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The project modules ``name`` imports (``from a import b`` counts ``a.b`` when it is a
    module, else ``a``)."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    targets: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            targets.add(module)
            targets.update(f"{module}.{alias.name}" for alias in node.names)
    edges: set[str] = set()
    for target in targets:
        while target and target not in known:
            target = target.rpartition(".")[0]
        if target and target != name:
            edges.add(target)
    return edges


def graph() -> dict[str, set[str]]:
    known = modules()
    return {name: imported(name, path, known) for name, path in known.items()}


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected groups of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return groups


def test_the_cycle_finder_finds_a_cycle_through_a_late_import() -> None:
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycles(edges) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_the_graph_sees_imports_inside_functions(tmp_path: Path) -> None:
    path = tmp_path / "m.py"
    path.write_text("def f():\n    from kernel import canon\n    import gcode.lexer\n")
    known = {"kernel.canon": path, "gcode.lexer": path, "pkg.m": path}
    assert imported("pkg.m", path, known) == {"kernel.canon", "gcode.lexer"}


def test_no_module_imports_itself_back_through_others() -> None:
    assert cycles(graph()) == []


def test_the_kernel_imports_no_front_end() -> None:
    offending = {
        name: sorted(t for t in targets if t.split(".")[0] in FRONT_ENDS)
        for name, targets in graph().items()
        if name.split(".")[0] == "kernel"
    }
    assert {k: v for k, v in offending.items() if v} == {}


def test_front_ends_import_no_cli() -> None:
    offending = {
        name: sorted(t for t in targets if t.split(".")[0] == "cli")
        for name, targets in graph().items()
        if name.split(".")[0] in ("gcode", "stepnc")
    }
    assert {k: v for k, v in offending.items() if v} == {}


def test_every_package_has_its_paragraph_in_the_architecture_map() -> None:
    """docs/architecture.md names every package folder (as ``path/`` or, under a folder it
    describes, as ``name/``), so the map cannot fall behind the tree."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    missing = []
    for package in PACKAGES:
        for init in sorted((ROOT / package).rglob("__init__.py")):
            folder = init.parent.relative_to(ROOT)
            if f"`{folder.as_posix()}/`" not in text and f"`{folder.name}/`" not in text:
                missing.append(folder.as_posix())
    assert missing == []
