"""The Mach3 dialect (gcode/mach3; docs/readers/mach3.md).

* Each feature program ``tests/dialects/mach3/NNN.tap`` has a hand translation into
  RS274/NGC (``NNN.ngc``: G70 -> G20, the scale factors multiplied out by hand, the macro M
  codes left out, G31 -> G38.2) whose output by LinuxCNC's ``rs274`` is ``NNN.canon``; the
  Mach3 reading of the ``.tap`` must be equivalent to it (tests/canon_equiv.py) once its
  MACHINE_FUNCTION events are set aside.
* Closed forms: G51 factors on end points, centres and radii; G50; refused elliptical and
  mirrored arcs, a zero factor, M47; macro M codes as MACHINE_FUNCTION with P/Q, before
  the block's motion; the arc tolerance (5 % of the radius accepted, past it refused,
  where RS274/NGC refuses both); ``.tap`` names the dialect; no program end needed.
* The writer: the corpus written with ``--to mach3`` reads back equivalent.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from click.testing import CliRunner

import tests.canon_equiv as canon_equiv
from cli.main import cli
from gcode import registry
from gcode.mach3 import reader as mach3
from gcode.ngc.interpreter import interpret_text as ngc_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import fine_text, ir_of, options, programs

FEATURES = sorted((Path(__file__).parent / "dialects" / "mach3").glob("*.tap"))


def _read(text: str) -> list[canon.Command]:
    return list(mach3.interpret_text(text, "t.tap"))


def _motions(text: str) -> list[canon.Command]:
    return [c for c in _read(text) if isinstance(c, canon.MOTIONS)]


def _refused(text: str) -> Diagnostic:
    with pytest.raises(Diagnostic) as err:
        _read(text)
    return err.value


@pytest.mark.parametrize("program", FEATURES, ids=lambda p: p.stem)
def test_feature_is_rs274_on_its_translation(program: Path) -> None:
    ours = [c for c in mach3.interpret(program) if not isinstance(c, canon.MachineFunction)]
    ref = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(list(canon.write_text(ours)), ref) == []


def test_features_are_there() -> None:
    assert len(FEATURES) >= 5
    assert all(
        p.with_suffix(".ngc").exists() and p.with_suffix(".canon").exists() for p in FEATURES
    )


@pytest.mark.parametrize(("fx", "fy", "fz"), [(2.0, 0.5, 1.0), (-1.0, 3.0, 0.25), (1.5, 1.5, -2)])
def test_g51_multiplies_each_axis_word_by_its_factor(fx: float, fy: float, fz: float) -> None:
    text = f"G21 F100\nG51 X{fx} Y{fy} Z{fz}\nG1 X3 Y-4 Z7\nG50\nG1 X3 Y-4 Z7\nM30\n"
    first, second = _motions(text)
    assert (first.x, first.y, first.z) == pytest.approx((3 * fx, -4 * fy, 7 * fz))
    assert (second.x, second.y, second.z) == pytest.approx((3, -4, 7))


def test_g51_keeps_the_factors_of_axes_it_does_not_name() -> None:
    (m,) = _motions("G21 F100\nG51 X2 Y3\nG51 Y5\nG1 X1 Y1 Z1\nM30\n")
    assert (m.x, m.y, m.z) == pytest.approx((2, 5, 1))


def test_scaled_arcs_scale_centre_and_radius() -> None:
    k = 2.5
    text = f"G21 F100\nG51 X{k} Y{k}\nG0 X4 Y0\nG3 X0 Y4 I-4 J0\nG2 X-4 Y0 R4\nM30\n"
    _, ccw, cw = _motions(text)
    assert isinstance(ccw, canon.ArcFeed) and isinstance(cw, canon.ArcFeed)
    # a quarter circle of radius 4 about the origin becomes one of radius 4k
    assert (ccw.first_end, ccw.second_end) == pytest.approx((0, 4 * k))
    assert (ccw.first_axis, ccw.second_axis) == pytest.approx((0, 0))
    # R4 from (0, 4k) to (-4k, 0) clockwise: radius 4k, centre (-4k, 4k) (the short way)
    assert (cw.first_end, cw.second_end) == pytest.approx((-4 * k, 0))
    assert (cw.first_axis, cw.second_axis) == pytest.approx((-4 * k, 4 * k))
    assert math.hypot(cw.first_end - cw.first_axis, cw.second_end - cw.second_axis) == (
        pytest.approx(4 * k)
    )


@pytest.mark.parametrize(
    ("factors", "what"), [("X2 Y3", "differ"), ("X-1 Y1", "mirror the arc (one is negative)")]
)
def test_arcs_under_unequal_or_mirroring_factors_are_refused(factors: str, what: str) -> None:
    err = _refused(f"G21 F100\nG51 {factors}\n G2 X1 Y1 I1 J0\nM30\n")
    assert err.code == "MACH3-SCALE-ARC" and what in err.message
    assert (err.location.line, err.location.column) == (3, 2)


def test_a_zero_factor_and_m47_are_refused_where_written() -> None:
    err = _refused("G21\nG51 X1 Y0\n")
    assert (err.code, err.location.line, err.location.column) == ("MACH3-SCALE-ZERO", 2, 8)
    err = _refused("G21\nG0 X1\nG0 X2 M47\n")
    assert (err.code, err.location.line, err.location.column) == ("MACH3-M47", 3, 7)


def test_g70_g71_set_inch_and_millimetre_units() -> None:
    units = [c.units for c in _read("G70\nG71\nG70\nM30\n") if isinstance(c, canon.UseLengthUnits)]
    assert units[-3:] == [canon.Units.INCHES, canon.Units.MM, canon.Units.INCHES]


def test_macro_m_codes_are_machine_functions_before_the_motion() -> None:
    cmds = _read("G21 F100\nG1 X1 M10\nM11 P4 Q2.5\nG4 P1 M12\nM3 S100\nM30\n")
    names = [c.NAME for c in cmds if c.NAME in ("MACHINE_FUNCTION", "STRAIGHT_FEED", "DWELL")]
    assert names == ["MACHINE_FUNCTION", "STRAIGHT_FEED", "MACHINE_FUNCTION"] + [
        "MACHINE_FUNCTION",
        "DWELL",
    ]
    functions = [c for c in cmds if isinstance(c, canon.MachineFunction)]
    assert [(f.code, f.p, f.q) for f in functions] == [
        (10, None, None),
        (11, 4, 2.5),
        (12, None, None),
    ]
    assert [(f.source.line, f.source.column) for f in functions] == [(2, 7), (3, 1), (4, 7)]
    # Mach3's own M codes stay what they are
    assert any(isinstance(c, canon.StartSpindleClockwise) for c in cmds)


def _arc(mismatch: float) -> str:
    """An arc about (0, 0) from (10, 0) to a point at radius 10 * (1 + mismatch)."""
    r = 10 * (1 + mismatch)
    return f"G21 F100\nG0 X10 Y0\nG3 X0 Y{r:.4f} I-10 J0\nM30\n"


def test_arc_end_radius_mismatch_mach3_accepts_rs274ngc_refuses() -> None:
    (_, arc) = _motions(_arc(0.02))
    assert isinstance(arc, canon.ArcFeed)
    assert (arc.first_end, arc.second_end, arc.first_axis, arc.second_axis) == pytest.approx(
        (0, 10.2, 0, 0)
    )
    with pytest.raises(Diagnostic) as err:
        list(ngc_text(_arc(0.02)))
    assert err.value.code == "NGC-ARC-RADIUS"
    assert _refused(_arc(0.06)).code == "NGC-ARC-RADIUS"


def test_tap_suffix_names_mach3_and_a_program_needs_no_end() -> None:
    assert registry.dialect_for_suffix(".tap") == "mach3"
    assert registry.dialect_for_suffix(".TAP") == "mach3"
    assert "mach3" in registry.NAMES and "mach3" in registry.INPUTS
    assert registry.get_dialect("mach3").machine_function == "M{code}"
    assert [c.NAME for c in _motions("G21\nG0 X1\n")] == ["STRAIGHT_TRAVERSE"]


@pytest.mark.parametrize("program", programs()[:40], ids=lambda p: p.stem)
def test_corpus_written_for_mach3_reads_back_equivalent(program: Path) -> None:
    ir = ir_of(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    try:
        text = "\n".join(write(ir, "mach3", WriterOptions("ijk", decimals=5), report))
    except Diagnostic as exc:
        assert exc.code.startswith("CONV-") and exc.location.line > 0
        return
    if report.changes:
        assert all(c.source is not None and c.source.line > 0 for c in report.changes)
        return
    back = list(mach3.interpret_text(text + "\n", program.name, options(program)))
    assert canon_equiv.compare(fine_text(back), fine_text(ir)) == []


def test_cnc_canon_reads_a_tap_file_as_mach3_by_its_suffix() -> None:
    program = FEATURES[[p.stem for p in FEATURES].index("004_macro_m_codes")]
    result = CliRunner().invoke(cli, ["canon", str(program)], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    assert "MACHINE_FUNCTION(10)" in result.output
    refused = CliRunner().invoke(cli, ["canon", "--dialect", "rs274ngc", str(program)])
    assert refused.exit_code != 0 and "NGC-UNKNOWN-M" in refused.output


def test_rs274ngc_errors_keep_their_codes_and_columns() -> None:
    err = _refused("G21\nG1 X1 F-5\n")
    assert (err.code, err.location.line, err.location.column) == ("NGC-NEGATIVE-F", 2, 7)
    err = _refused("G21 F100\nG51 X2 Y2\nG1 X1 F-5\n")
    assert (err.code, err.location.line, err.location.column) == ("NGC-NEGATIVE-F", 3, 7)
