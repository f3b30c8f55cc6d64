"""Issue 15: round trips through every dialect pair, on every suite of programs we have.

Every program of the golden, corpus, hand-derived dialect and real-program suites
(``tests/realworld/**``, whatever is there: the suites join by folder, and an absent
folder is no case) is read by its own dialect's reader, with and without its tool table,
written in every target dialect as ``cnc convert`` writes it (register marks, kept cycles
and compensation where the target has them), and read back by the target's reader. Then:

* a refusal is a located ``CONV-`` error (the CLI writes nothing), and so is a loss the
  conversion report lists (the CLI exits 1 and writes nothing);
* otherwise the read-back is the original: the same motions, feeds and state by the rule of
  ``tests/canon_equiv.py`` (the corpus README's 1e-4, at six written decimals) where the
  writer replaced nothing, and where it replaced curves by pieces, every piece on the
  curve within the tolerance (``tests/chord_equiv.py``'s chord rule);
* and, at every motion, the tool length in force (its register and its length), the work
  offset (its number and values) and the spindle and coolant state are the original's.

The default run takes a fixed sample of the cases (every :data:`STRIDE`-th); the rest are
``slow``. ``rs274`` reads the LinuxCNC and Grbl outputs too (``reference``).
"""

from __future__ import annotations

import dataclasses
import functools
import shutil
from collections.abc import Iterable
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.core import linuxcnc as lc
from gcode.core.register_marks import ToolLengthRegister, WorkOffsetRegister
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read, read_text
from gcode.registry import NAMES, REGISTRY, SUFFIXES, get_dialect
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.ir.equivalence import first_difference
from kernel.tooltable import read_tool_table
from tests.convert_support import fine_text, rs274

HERE = Path(__file__).resolve().parent
#: one case in this many runs in the default run; the rest are slow
STRIDE = 23
SOURCE_SUFFIXES = (".ngc", ".nc", ".gcode", ".tap", ".mpf")


@dataclasses.dataclass(frozen=True)
class Program:
    """A program of a suite: its file, its dialect and the tool table beside it."""

    path: Path
    dialect: str
    table: Path | None

    @property
    def name(self) -> str:
        return self.path.relative_to(HERE).as_posix()


def _table_near(path: Path, top: Path) -> Path | None:
    """The tool table of a program: a ``*.tbl`` in its folder or the nearest above it."""
    folder = path.parent
    while True:
        found = sorted(folder.glob("*.tbl"))
        if found:
            return found[0]
        if folder == top or top not in folder.parents:
            return None
        folder = folder.parent


def _dialect_of(path: Path, top: Path) -> str | None:
    """A real program's dialect: the nearest folder named after a dialect (``ngc`` is
    RS274/NGC), else its suffix's (gcode.registry), else RS274/NGC."""
    for folder in path.relative_to(top).parents:
        name = folder.name
        if name == "ngc":
            return "rs274ngc"
        if name in {e.name for e in REGISTRY}:
            return name
    return SUFFIXES.get(path.suffix.lower(), "rs274ngc")


def suites() -> list[Program]:
    """Every program of every suite, by glob."""
    out: list[Program] = []
    golden = HERE / "golden" / "ngc"
    corpus = HERE / "data" / "corpus" / "ngc"
    for folder in (golden, corpus):
        table = folder / "sim.tbl"
        out += [Program(p, "rs274ngc", table) for p in sorted(folder.glob("*.ngc"))]
    fanuc = HERE / "dialects" / "fanuc"
    for p in sorted(fanuc.glob("*.nc")):
        if "_error_" in p.name or "book" in p.name:
            continue
        lathe = "lathe" in p.name or "turn" in p.name
        out.append(Program(p, "fanuc_lathe" if lathe else "fanuc", None))
    siemens = HERE / "dialects" / "siemens840d"
    out += [
        Program(p, "siemens840d", siemens / "tools.tbl")
        for p in sorted(siemens.glob("*.mpf"))
        if "_error_" not in p.name
    ]
    real = HERE / "realworld"
    if real.is_dir():
        for p in sorted(real.rglob("*")):
            if p.suffix.lower() not in SOURCE_SUFFIXES or not p.is_file():
                continue
            dialect = _dialect_of(p, real)
            if dialect is None or dialect not in {e.name for e in REGISTRY}:
                continue
            out.append(Program(p, dialect, _table_near(p, real)))
    return out


PROGRAMS = suites()
CASES = [
    (program, target, table)
    for program in PROGRAMS
    for target in NAMES
    for table in (True, False)
    if not table or program.table is not None
]


#: cases that show a converter defect not fixed yet -> what differs (strict: a fix shows)
KNOWN: dict[str, str] = {}


def _params() -> list[object]:
    params = []
    for index, (program, target, table) in enumerate(CASES):
        marks = [] if index % STRIDE == 0 else [pytest.mark.slow]
        ident = f"{program.name}-{program.dialect}-to-{target}-{'table' if table else 'none'}"
        if ident in KNOWN:
            marks.append(pytest.mark.xfail(strict=True, reason=KNOWN[ident]))
        params.append(pytest.param(program, target, table, id=ident, marks=marks))
    return params


def reader_options(program: Program, table: bool, target: str | None = None) -> InterpreterOptions:
    """The options ``cnc convert`` reads with (target None: the source's reader)."""
    tools = None
    if table and program.table is not None:
        tools = read_tool_table(program.table.read_text().splitlines(), str(program.table))
    keep = get_dialect(target).has_cutter_comp if target else False
    return InterpreterOptions(
        tool_table=tools,
        search_path=(str(program.path.parent), str(program.path.parent / "subs")),
        cycle_marks=True,
        keep_cutter_comp=keep,
        register_marks=True,
    )


@functools.cache
def source_ir(program: Program, table: bool, keep_comp: bool) -> tuple[canon.Command, ...] | None:
    options = dataclasses.replace(reader_options(program, table), keep_cutter_comp=keep_comp)
    try:
        return tuple(read(program.path, program.dialect, options))
    except Diagnostic:
        return None


State = tuple[object, ...]


def states(commands: Iterable[canon.Command]) -> list[State]:
    """What each motion runs with, repeats collapsed (a writer may split or merge moves):
    the tool length register and length, the work offset's number and values (mm), the
    spindle's direction and speed, mist and flood."""
    register: tuple[str | None, int | None] = (None, None)
    length = 0.0
    work: tuple[object, ...] = (1,)
    number: int | None = None  # the next work offset's number (its mark)
    spindle = (canon.Direction.STOPPED, 0.0)
    mist = flood = False
    mm = 1.0
    out: list[State] = []
    for c in commands:
        if isinstance(c, canon.UseLengthUnits):
            mm = c.units.mm_per_unit
        elif isinstance(c, ToolLengthRegister):
            register = (None, None) if c.code == "G49" else (c.code, c.register)
        elif isinstance(c, canon.UseToolLengthOffset):
            length = c.length * mm
        elif isinstance(c, lc.ToolLengthOffsets):
            length = c.offset[2] * mm
        elif isinstance(c, WorkOffsetRegister):
            number = c.number
        elif isinstance(c, canon.SetG5xOffset):
            # its number (G54.1 P n and G510+ are marked: the IR's index holds nine); its
            # values are the machine's (see the module doc)
            work, number = (number or c.index,), None
        elif isinstance(c, canon.SetSpindleSpeed):
            spindle = (spindle[0], round(c.speed, 3))
        elif isinstance(c, canon.StartSpindleClockwise):
            spindle = (canon.Direction.CLOCKWISE, spindle[1])
        elif isinstance(c, canon.StartSpindleCounterclockwise):
            spindle = (canon.Direction.COUNTERCLOCKWISE, spindle[1])
        elif isinstance(c, canon.StopSpindleTurning):
            spindle = (canon.Direction.STOPPED, spindle[1])
        elif isinstance(c, canon.MistOn | canon.MistOff):
            mist = isinstance(c, canon.MistOn)
        elif isinstance(c, canon.FloodOn | canon.FloodOff):
            flood = isinstance(c, canon.FloodOn)
        elif isinstance(c, canon.MOTIONS):
            state = (*register, round(length, 3), *work, *spindle, mist, flood)
            if not out or out[-1] != state:
                out.append(state)
    return out


def convert(
    ir: Iterable[canon.Command], target: str
) -> tuple[str | None, ConversionReport, Diagnostic | None]:
    report = ConversionReport()
    options = WriterOptions(decimals=6, cycles="keep")
    try:
        return "\n".join(write(ir, target, options, report)) + "\n", report, None
    except Diagnostic as exc:
        return None, report, exc


@pytest.mark.parametrize(("program", "target", "table"), _params())
def test_round_trip_keeps_the_program(program: Program, target: str, table: bool) -> None:
    if table and program.table is None:
        pytest.skip("no tool table beside this program")
    keep = get_dialect(target).has_cutter_comp
    ir = source_ir(program, table, keep)
    if ir is None:
        pytest.skip("the source reader refuses this program")
    text, report, error = convert(ir, target)
    must = must_refuse(ir, target)
    if error is not None:
        assert error.code.startswith("CONV-") and error.location.line > 0, error
        if must is not None and error.location.line >= must[1]:  # the loss came first
            listed = {c.loss_code for c in report.refused()}
            assert error.code == must[0] or must[0] in listed, (error, must)
        return
    assert text is not None
    refused = report.refused()
    if must is not None:
        assert must[0] in {c.loss_code for c in refused}, (must, refused)
    if refused:  # the CLI refuses it: exit 1, no file
        assert all(c.source is not None and c.source.line > 0 for c in refused)
        return
    try:
        back = list(
            read_text(text, target, program.path.name, reader_options(program, table, target))
        )
    except Diagnostic as exc:  # the CLI's read-back refuses it (CONV-VERIFY): no file
        pytest.skip(f"the {target} reader refuses the output ({exc.code}); CONV-VERIFY")
    assert states(back) == states(ir)
    if any(
        c.kind in ("dropped", "substituted") and c.code != "CONV-ARC-FORMAT" for c in report.changes
    ):
        return  # a note that changes no motion (an operator message as a comment): the
        # CLI writes it "not verified"; the state above is what must hold
    pieces = any(c.kind in ("approximated", "expanded") for c in report.changes)
    if pieces:
        diff = first_difference(ir, back, 0.001)
        assert diff is None, diff
    else:
        found = canon_equiv.compare(fine_text(_plain(back)), fine_text(_plain(ir)))
        if get_dialect(target).structure == "commands":
            # a language without planes (Sandia: world-space MoveTo) reads every move back
            # in XY; a straight move goes to the same point in any plane (kernel.ir.equivalence)
            found = [f for f in found if not (" STRAIGHT_" in f and " sees plane " in f)]
            diff = first_difference(ir, back, 0.001)  # the rest of what those moves see
            assert diff is None, diff
        assert found == []


def must_refuse(ir: Iterable[canon.Command], target: str) -> tuple[str, int] | None:
    """(code, source line) where a conversion to ``target`` must stop (an error at or after
    that line has this code, or the loss was listed before it) or list this loss, else None:
    the program writes the machine's tool table (G10 L1/L10/L11), which is written only with
    --write-tool-table (and Sandia cannot write at all); a tool length by register (G43 H n,
    G43.2 H n: the length the machine measured), which Sandia's SetToolLength (a value)
    cannot say."""
    for c in ir:
        line = c.source.line if c.source else 0
        if isinstance(c, canon.SetToolTableEntry):
            return ("CONV-TOOL-LENGTH" if target == "sandia" else "CONV-TOOL-TABLE", line)
        if target == "sandia" and isinstance(c, ToolLengthRegister) and c.register is not None:
            return ("CONV-TOOL-LENGTH", line)
    return None


def _plain(commands: Iterable[canon.Command]) -> list[canon.Command]:
    """The canonical commands, without the readers' marks for writers."""
    return [c for c in commands if type(c).__module__ == canon.__name__]


LINUXCNC_TARGETS = ("rs274ngc", "grbl")
REFERENCE = [p for p in PROGRAMS if p.dialect == "rs274ngc" and p.table is not None]


@pytest.mark.reference
@pytest.mark.parametrize("target", LINUXCNC_TARGETS)
@pytest.mark.parametrize(
    "program",
    [
        pytest.param(p, marks=[] if i % STRIDE == 0 else [pytest.mark.slow], id=p.name)
        for i, p in enumerate(REFERENCE)
    ],
)
def test_rs274_reads_the_linuxcnc_and_grbl_output_as_the_original(
    program: Program, target: str, tmp_path: Path
) -> None:
    if shutil.which("rs274") is None:
        pytest.skip("rs274 is not installed")
    ir = source_ir(program, True, get_dialect(target).has_cutter_comp)
    if ir is None:
        pytest.skip("the source reader refuses this program")
    text, report, error = convert(ir, target)
    if error is not None or report.refused() or report.changes:
        pytest.skip("refused or changed: the round trip above checks it")
    assert text is not None
    if not text.startswith("%"):
        text = f"%\n{text}%\n"  # Grbl has no end marker; rs274 needs one
    assert program.table is not None
    theirs = rs274(text, program.table, tmp_path)
    compensated = source_ir(program, True, False)  # rs274 applies G41/G42 itself
    assert compensated is not None
    assert canon_equiv.compare(theirs, fine_text(_plain(compensated))) == []


def test_the_suites_are_collected_by_glob() -> None:
    dialects = {p.dialect for p in PROGRAMS}
    assert {"rs274ngc", "fanuc", "siemens840d"} <= dialects
    assert len(PROGRAMS) > 300
