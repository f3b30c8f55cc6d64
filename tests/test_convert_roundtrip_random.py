"""Issue 15, "Done when": no round trip changes tool length, work offset or spindle and coolant
state, on random programs too.

Hypothesis writes random RS274/NGC programs of tool changes (``T n M6``), tool length
offsets (``G43 H n``, ``G43`` of the tool in the spindle, ``G49``), work offsets
(``G54``-``G59.3``), spindle (``S``, ``M3``/``M4``/``M5``), coolant (``M7``/``M8``/``M9``)
and moves; random Fanuc programs add the additional work offsets (``G54.1 P n``) and the
settings of work offsets (``G10 L2 P n``, ``G10 L20 P n``), whose number and values at every
motion must survive too. Each program is also stated in Fanuc and Siemens 840D by our
writers (where they can state it) and read by their readers: three source programs. Each
source is converted to every target dialect as ``cnc convert`` does (register marks), with
and without a tool table, and read back by the target's reader: the state at every motion is
the source's (the collapse of ``tests/test_convert_roundtrip_pairs.py``: register and tool
length, work offset number, spindle direction and speed, mist, flood), or the conversion is
refused at a located line (``CONV-``: the CLI writes nothing)."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gcode.core.register_marks import WorkOffsetRegister
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read_text
from gcode.registry import NAMES, get_dialect
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table
from tests.test_convert_roundtrip_pairs import states

TABLE = Path(__file__).resolve().parent / "golden" / "ngc" / "sim.tbl"
TOOLS = read_tool_table(TABLE.read_text().splitlines(), str(TABLE))
WORK = ["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"]
#: the sources: RS274/NGC as drawn, and as our Fanuc and Siemens writers state it
SOURCES = ("rs274ngc", "fanuc", "siemens840d")
#: targets that read lengths from the machine: the mill dialects (the lathes and Sandia
#: have their own refusals, checked by the pairs suite)
TARGETS = [t for t in NAMES if t not in ("sandia",)]

coord = st.integers(-500, 500).map(lambda v: v / 10)


@st.composite
def programs(draw: st.DrawFn) -> str:
    """A random RS274/NGC program of tool, offset, spindle and coolant changes and moves."""
    lines = ["G21 G90 G17 G94", "F200"]
    tool = 0
    for _ in range(draw(st.integers(1, 14))):
        kind = draw(
            st.sampled_from(["tool", "g43", "g49", "work", "speed", "spindle", "coolant", "move"])
        )
        if kind == "tool":
            tool = draw(st.integers(1, 3))
            lines.append(f"T{tool} M6")
        elif kind == "g43":
            register = draw(st.one_of(st.none(), st.integers(1, 3)))
            if register is None and tool == 0:
                continue
            lines.append("G43" if register is None else f"G43 H{register}")
        elif kind == "g49":
            lines.append("G49")
        elif kind == "work":
            lines.append(draw(st.sampled_from(WORK)))
        elif kind == "speed":
            lines.append(f"S{draw(st.integers(100, 12000))}")
        elif kind == "spindle":
            lines.append(draw(st.sampled_from(["M3", "M4", "M5"])))
        elif kind == "coolant":
            lines.append(draw(st.sampled_from(["M7", "M8", "M9"])))
        else:
            code = draw(st.sampled_from(["G0", "G1"]))
            lines.append(f"{code} X{draw(coord)} Y{draw(coord)} Z{draw(coord)}")
        if draw(st.booleans()):
            lines.append(f"G1 X{draw(coord)} Y{draw(coord)}")  # a motion sees the state
    lines.append("M2")
    return "\n".join(lines) + "\n"


#: the Fanuc program's work offsets: G54-G59 and additional offsets (G54.1 P n)
FANUC_WORK = ["G54", "G55", "G56", "G57", "G58", "G59", "G54.1 P1", "G54.1 P2", "G54.1 P48"]


@st.composite
def fanuc_programs(draw: st.DrawFn) -> str:
    """A random Fanuc program of the same kinds, with additional work offsets (G54.1 P n)
    and the settings of work offsets (G10 L2 P n, G10 L20 P n), which RS274/NGC lacks."""
    lines = ["%", "O0001", "G21 G90 G17 G94", "F200."]
    tool = 0
    for _ in range(draw(st.integers(1, 14))):
        kind = draw(
            st.sampled_from(["tool", "g43", "g49", "work", "set", "spindle", "coolant", "move"])
        )
        if kind == "tool":
            tool = draw(st.integers(1, 3))
            lines.append(f"T{tool} M06")
        elif kind == "g43":
            lines.append(f"G43 H{draw(st.integers(1, 3))}")
        elif kind == "g49":
            lines.append("G49")
        elif kind == "work":
            lines.append(draw(st.sampled_from(FANUC_WORK)))
        elif kind == "set":
            extended = draw(st.booleans())
            p = draw(st.sampled_from([1, 2, 48])) if extended else draw(st.integers(1, 6))
            axes = draw(st.lists(st.sampled_from("XYZ"), min_size=1, max_size=3, unique=True))
            words = " ".join(f"{a}{draw(coord)}" for a in sorted(axes))
            lines.append(f"G10 L{20 if extended else 2} P{p} {words}")
        elif kind == "spindle":
            lines.append(
                f"S{draw(st.integers(100, 12000))} {draw(st.sampled_from(['M03', 'M04', 'M05']))}"
            )
        elif kind == "coolant":
            lines.append(draw(st.sampled_from(["M07", "M08", "M09"])))
        else:
            code = draw(st.sampled_from(["G00", "G01"]))
            lines.append(f"{code} X{draw(coord)} Y{draw(coord)} Z{draw(coord)}")
        if draw(st.booleans()):
            lines.append(f"G01 X{draw(coord)} Y{draw(coord)}")  # a motion sees the state
    lines += ["M30", "%"]
    return "\n".join(lines) + "\n"


def offsets(commands: list[canon.Command]) -> list[tuple[object, ...]]:
    """The work offset at each motion, repeats collapsed: its number (the reader's mark)
    and its values in mm, as the reader's offset table holds them after the program's own
    G10 settings (every table starts at zero here, so a setting lost or misplaced shows)."""
    number: int | None = None
    work: tuple[object, ...] = (1, 0.0, 0.0, 0.0)
    mm = 1.0
    out: list[tuple[object, ...]] = []
    for c in commands:
        if isinstance(c, canon.UseLengthUnits):
            mm = c.units.mm_per_unit
        elif isinstance(c, WorkOffsetRegister):
            number = c.number
        elif isinstance(c, canon.SetG5xOffset):
            values = tuple(round(v * mm, 3) for v in (c.x, c.y, c.z))
            work, number = (number or c.index, *values), None
        elif isinstance(c, canon.MOTIONS) and (not out or out[-1] != work):
            out.append(work)
    return out


def _options(table: bool, target: str | None = None) -> InterpreterOptions:
    keep = get_dialect(target).has_cutter_comp if target else False
    return InterpreterOptions(
        tool_table=TOOLS if table else None,
        cycle_marks=True,
        keep_cutter_comp=keep,
        register_marks=True,
    )


def _write(ir: list[canon.Command], target: str) -> tuple[str | None, Diagnostic | None]:
    report = ConversionReport()
    try:
        text = "\n".join(write(ir, target, WriterOptions(decimals=6), report)) + "\n"
    except Diagnostic as exc:
        return None, exc
    refused = report.refused()
    if refused:
        first = refused[0]
        assert first.source is not None and first.source.line > 0
        return None, Diagnostic(str(first.loss_code), first.message, first.source)
    return text, None


def _source(program: str, dialect: str, table: bool) -> list[canon.Command] | None:
    """The program as ``dialect`` states it, read by that dialect's reader (None: our
    writer cannot state it)."""
    ir = list(read_text(program, "rs274ngc", "random.ngc", _options(table)))
    if dialect == "rs274ngc":
        return ir
    text, error = _write(ir, dialect)
    if error is not None:
        return None
    assert text is not None
    source = list(read_text(text, dialect, f"random.{dialect}", _options(table)))
    assert states(source) == states(ir), f"stating it in {dialect} changed it"
    return source


def _check(program: str, source: str, table: bool) -> None:
    """Every target's round trip of ``program`` stated in ``source`` keeps the state."""
    ir = _source(program, source, table)
    if ir is None:
        return
    want = states(ir)
    for target in TARGETS:
        text, error = _write(ir, target)
        if error is not None:
            assert error.code.startswith("CONV-") and error.location.line > 0, error
            continue
        assert text is not None
        back = list(read_text(text, target, f"back.{target}", _options(table, target)))
        assert states(back) == want, f"{source} -> {target}:\n{text}"


@pytest.mark.parametrize("table", [True, False], ids=["tool-table", "no-table"])
@pytest.mark.parametrize("source", SOURCES)
@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program=programs())
def test_no_round_trip_changes_tool_length_offset_spindle_or_coolant(
    program: str, source: str, table: bool
) -> None:
    _check(program, source, table)


def _check_fanuc(program: str, table: bool) -> None:
    """A Fanuc program's round trip to every target keeps the state and the work offsets
    (number and values) at every motion, or is refused at a located line."""
    ir = list(read_text(program, "fanuc", "random.nc", _options(table)))
    want, work = states(ir), offsets(ir)
    for target in TARGETS:
        text, error = _write(ir, target)
        if error is not None:
            assert error.code.startswith("CONV-") and error.location.line > 0, error
            continue
        assert text is not None
        back = list(read_text(text, target, f"back.{target}", _options(table, target)))
        assert states(back) == want, f"fanuc -> {target}:\n{text}"
        assert offsets(back) == work, f"fanuc -> {target}:\n{text}"


@pytest.mark.parametrize("table", [True, False], ids=["tool-table", "no-table"])
@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program=fanuc_programs())
def test_no_round_trip_changes_a_fanuc_work_offset_or_its_setting(
    program: str, table: bool
) -> None:
    _check_fanuc(program, table)


@pytest.mark.slow
@pytest.mark.parametrize("table", [True, False], ids=["tool-table", "no-table"])
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program=fanuc_programs())
def test_many_random_fanuc_round_trips(program: str, table: bool) -> None:
    _check_fanuc(program, table)


def test_a_lost_work_offset_setting_is_seen() -> None:
    """The offset check can fail: G54.1 P1 after its G10 L20 differs from G54.1 P1 alone,
    and from G54.1 P2 set the same way."""
    head = "%\nG21 G90\n"
    set_p1 = list(read_text(f"{head}G10 L20 P1 X5.\nG54.1 P1\nG0 X1.\nM30\n%\n", "fanuc", "a"))
    alone = list(read_text(f"{head}G54.1 P1\nG0 X1.\nM30\n%\n", "fanuc", "b"))
    set_p2 = list(read_text(f"{head}G10 L20 P2 X5.\nG54.1 P2\nG0 X1.\nM30\n%\n", "fanuc", "c"))
    assert offsets(set_p1) != offsets(alone)
    marked = [
        list(
            read_text(
                f"{head}G10 L20 P{n} X5.\nG54.1 P{n}\nG0 X1.\nM30\n%\n",
                "fanuc",
                "d",
                _options(False),
            )
        )
        for n in (1, 2)
    ]
    assert offsets(marked[0]) != offsets(marked[1])
    assert set_p2


@pytest.mark.slow
@pytest.mark.parametrize("table", [True, False], ids=["tool-table", "no-table"])
@pytest.mark.parametrize("source", SOURCES)
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program=programs())
def test_many_random_round_trips(program: str, source: str, table: bool) -> None:
    _check(program, source, table)


def test_a_lost_tool_length_is_seen() -> None:
    """The state check can fail: G43 H1 read as G49 differs."""
    with_g43 = list(
        read_text("G21\nT1 M6\nG43 H1\nG1 X1 F100\nM2\n", "rs274ngc", "a.ngc", _options(True))
    )
    without = list(
        read_text("G21\nT1 M6\nG49\nG1 X1 F100\nM2\n", "rs274ngc", "b.ngc", _options(True))
    )
    assert states(with_g43) != states(without)
