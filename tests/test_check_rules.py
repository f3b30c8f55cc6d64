"""``cnc check`` rules: each problem class has a program that triggers exactly it, a clean
program triggers none, and the LinuxCNC corpus gives only reviewed, real findings."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cli.check import Setup, check_file, load_context
from kernel.check import RULES, CheckContext, check_stream, config_from_dict
from kernel.check.geometry import arc_extremes, arc_of, segment_hits_box
from kernel.check.rules import TEXT_RULES
from kernel.check.state import CheckState, advance
from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, AxisLimits, Machine
from tests.data_paths import CORPUS_NGC

HERE = Path(__file__).parent / "check"
CORPUS = CORPUS_NGC
DOCS = Path(__file__).resolve().parents[1] / "docs" / "check-rules.md"
SHOP = load_context(str(HERE / "shop.toml"), str(HERE / "shop.toml"), None)
SIM = load_context(str(HERE / "sim.toml"), str(HERE / "sim.toml"), None)
TRIGGERS = sorted(p.stem for p in HERE.glob("CNC*.canon"))
#: rules judged on a program's text (kernel.check.rules.TEXT_RULES): their triggers are G-code
TEXT_TRIGGERS = sorted(p.stem for p in HERE.glob("CNC*.nc"))


def rules_fired(path: Path, ctx: CheckContext = SHOP) -> set[str]:
    with open(path) as fh:
        return {
            f.rule
            for f in check_stream(canon.read_commands(fh, str(path), keep_linuxcnc=True), ctx)
        }


def run(cmds: list[canon.Command], ctx: CheckContext = SHOP) -> list:
    return check_stream(cmds, ctx)


# --------------------------------------------------------------------------- one program per rule
@pytest.mark.parametrize("rule", TRIGGERS)
def test_trigger_program_fires_exactly_its_rule(rule: str) -> None:
    assert rules_fired(HERE / f"{rule}.canon") == {rule}


def test_clean_program_fires_no_rule() -> None:
    assert rules_fired(HERE / "clean.canon") == set()


def test_every_rule_has_a_trigger_program_and_a_doc_section() -> None:
    doc = DOCS.read_text()
    headings = set(re.findall(r"^## (CNC\d{3}) ", doc, re.M))
    assert set(RULES) == set(TRIGGERS) | set(TEXT_TRIGGERS) == headings
    assert set(TEXT_TRIGGERS) == TEXT_RULES and not set(TRIGGERS) & TEXT_RULES
    assert len(RULES) >= 25


def test_gcode_trigger_programs_match_their_canonical_twins() -> None:
    pytest.importorskip("gcode.ngc.interpreter")
    from cli.programs import program_commands

    for ngc in sorted(HERE.glob("*.ngc")):
        fired = {
            f.rule
            for f in check_stream(
                program_commands(str(ngc), SHOP.tools, SHOP.tool_mm_per_unit), SHOP
            )
        }
        want = set() if ngc.stem == "clean" else {ngc.stem}
        assert fired == want, ngc.name


@pytest.mark.parametrize("rule", TEXT_TRIGGERS)
def test_text_trigger_program_fires_exactly_its_rule(rule: str) -> None:
    result = check_file(str(HERE / f"{rule}.nc"), Setup(SHOP, verbosity=-1))
    assert {f.rule for f in result.findings} == {rule}


# --------------------------------------------------------------------------- corpus
#: Findings on the corpus with the sim profile: none (issue 6). The sim profile disables the
#: two rules that only make sense on a real mill (see its [check] table); with them on, the
#: splash screens and the engraving and puma demos cut with the spindle off (CNC504) and
#: examples.ngc starts with a G1 from wherever the machine stands (CNC030).
CORPUS_FINDINGS: set[tuple[str, str]] = set()
MILL_ONLY_FINDINGS = {
    ("axis__images__axis-lathe", "CNC504"),
    ("axis__remap__manual-toolchange-with-tool-length-switch__nc_files__tcdemo", "CNC504"),
    ("axis__vismach__puma__puma_cube", "CNC504"),
    ("axis__remap__extend-builtins__nc_files__examples", "CNC030"),
}


def test_corpus_has_no_findings_with_the_sim_profile() -> None:
    found = set()
    for path in sorted(CORPUS.glob("*.canon")):
        found |= {(path.stem, r) for r in rules_fired(path, SIM)}
    assert found == CORPUS_FINDINGS


def test_corpus_trips_the_mill_only_rules_when_they_are_on() -> None:
    on = {k: v for k, v in SIM.config.overrides.items() if k not in ("CNC504", "CNC030")}
    mill = replace(SIM, config=replace(SIM.config, overrides=on))
    found = set()
    for path in sorted(CORPUS.glob("*.canon")):
        found |= {(path.stem, r) for r in rules_fired(path, mill)}
    assert found == MILL_ONLY_FINDINGS


def test_corpus_gcode_has_no_findings_with_the_sim_profile() -> None:
    pytest.importorskip("gcode.ngc.interpreter")
    from cli.programs import program_commands

    found = set()
    for path in sorted(CORPUS.glob("*.ngc")):
        found |= {
            (path.stem, f.rule)
            for f in check_stream(program_commands(str(path), SIM.tools, SIM.tool_mm_per_unit), SIM)
        }
    assert found == CORPUS_FINDINGS


# --------------------------------------------------------------------------- rule semantics
def test_soft_limit_counts_origin_offset_and_tool_length() -> None:
    m = Machine("m", (AxisLimits("x", -10, 10), AxisLimits("y", -10, 10), AxisLimits("z", -50, 20)))
    ctx = CheckContext(m)
    base = [canon.SetOriginOffsets(0, 0, 5), canon.UseToolLengthOffset(10.0)]
    # program Z 4 -> machine 4 + 5 + 10 = 19 mm: inside; Z 6 -> 21 mm: outside
    assert not [f for f in run([*base, canon.StraightTraverse(0, 0, 4)], ctx) if f.rule == "CNC101"]
    hit = [f for f in run([*base, canon.StraightTraverse(0, 0, 6)], ctx) if f.rule == "CNC101"]
    assert len(hit) == 1 and "21 mm" in hit[0].message


def test_soft_limit_sees_the_bulge_of_an_arc() -> None:
    m = Machine("m", (AxisLimits("x", -100, 100), AxisLimits("y", -5, 100), AxisLimits("z", -9, 9)))
    ctx = CheckContext(m)
    # half circle from (10, 0) CW around (0, 0) to (-10, 0) dips to y = -10: beyond -5
    cw = [canon.StraightTraverse(10, 0, 0), canon.ArcFeed(-10, 0, 0, 0, -1, 0)]
    ccw = [canon.StraightTraverse(10, 0, 0), canon.ArcFeed(-10, 0, 0, 0, 1, 0)]
    assert "CNC101" in {f.rule for f in run(cw, ctx)}
    assert "CNC101" not in {f.rule for f in run(ccw, ctx)}


def test_inch_program_is_converted_before_limits() -> None:
    m = Machine("m", (AxisLimits("x", -30, 30), AxisLimits("y", -30, 30), AxisLimits("z", -30, 30)))
    ctx = CheckContext(m)
    inch = [canon.UseLengthUnits(canon.Units.INCHES)]
    assert "CNC101" not in {f.rule for f in run([*inch, canon.StraightTraverse(1.0, 0, 0)], ctx)}
    assert "CNC101" in {f.rule for f in run([*inch, canon.StraightTraverse(1.2, 0, 0)], ctx)}


def test_linuxcnc_g5x_and_g92_offsets_add_up() -> None:
    text = [
        "SET_G5X_OFFSET(1, 10.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "SET_G92_OFFSET(2.5000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    ]
    cmds = list(canon.read_commands(text, keep_linuxcnc=True))
    st_ = CheckState()
    for c in cmds:
        advance(st_, c)
    assert st_.origin_mm[0] == pytest.approx(12.5)


def test_rotated_work_offset_places_moves_as_rs274_does() -> None:
    """G92, then the XY rotation about the G5x origin, then the G5x offset (rs274's order):
    X10 under a 90° rotation with G54 at X100 is machine (100, 10)."""
    st_ = CheckState()
    for c in canon.read_commands(
        [
            "SET_G5X_OFFSET(1, 100.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
            "SET_G92_OFFSET(0.0000, 5.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
            "SET_XY_ROTATION(90.0000)",
        ],
        keep_linuxcnc=True,
    ):
        advance(st_, c)
    assert st_.machine_point((10, 0, 1, 0, 0, 0)) == pytest.approx((95, 10, 1, 0, 0, 0))


def test_soft_limit_under_rotation_boxes_arcs_in_machine_axes() -> None:
    """An arc of radius 10 about the origin from 30° to 60° reaches Y 8.66 at most; turned
    by a 45° XY rotation it runs from 75° to 105° in machine axes and passes 90°, Y 10,
    between its ends (Y 9.66). With Y travel to 9.8 only the rotated arc leaves it."""
    machine = replace(
        DEFAULT_MACHINE,
        axes=tuple(replace(a, max=9.8) if a.name == "y" else a for a in DEFAULT_MACHINE.axes),
    )
    ctx = CheckContext(machine)
    c30, s30 = 10 * math.cos(math.radians(30)), 10 * math.sin(math.radians(30))
    start = [canon.StraightTraverse(c30, s30, 0.0), canon.SetFeedRate(100.0)]
    arc = canon.ArcFeed(s30, c30, 0.0, 0.0, 1, 0.0)
    assert "CNC101" in {f.rule for f in run([canon.SetXYRotation(45.0), *start, arc], ctx)}
    assert "CNC101" not in {f.rule for f in run([*start, arc], ctx)}


def test_a_run_of_offending_moves_is_one_finding_with_a_count() -> None:
    cmds = [canon.StraightTraverse(0, 0, 5), canon.SetFeedRate(100)]
    cmds += [canon.StraightFeed(i, 0, 0) for i in range(1, 1001)] + [canon.ProgramEnd()]
    found = [f for f in run(cmds, CheckContext(DEFAULT_MACHINE)) if f.rule == "CNC504"]
    assert len(found) == 1 and "999 more" in found[0].message


def test_interpreter_error_keeps_earlier_findings_and_stops() -> None:
    def stream():
        yield canon.StraightFeed(1, 0, 0)  # first move is a feed: CNC030
        raise Diagnostic("NGC-ARC-RADIUS", "radius differs", Location("p.ngc", 7, 3))

    found = check_stream(stream(), CheckContext(DEFAULT_MACHINE))
    assert [f.rule for f in found][-1] == "CNC001"
    assert found[-1].code == "NGC-ARC-RADIUS" and found[-1].location.line == 7
    assert "CNC030" in {f.rule for f in found} and "CNC010" not in {f.rule for f in found}


def test_linuxcnc_arc_tolerance_is_absolute_and_relative() -> None:
    """research/anchors.md §1.1: fail when the radii differ by more than 2·0.01·√2 mm and
    by more than 0.1 % of the radius."""
    ctx = CheckContext(DEFAULT_MACHINE, config_from_dict({"arc_tolerance": "linuxcnc"}, set(RULES)))

    def fires(r_end: float, r: float) -> bool:
        cmds = [canon.StraightTraverse(r, 0, 0), canon.ArcFeed(-r_end, 0, 0, 0, 1, 0)]
        return "CNC301" in {f.rule for f in run(cmds, ctx)}

    t_abs = 2 * 0.01 * math.sqrt(2)
    assert not fires(10 + 0.9 * t_abs, 10)  # under the absolute threshold
    assert fires(10 + 1.1 * t_abs, 10)  # over both (0.1 % of 10 mm is 0.01 mm)
    assert not fires(100 + 1.1 * t_abs, 100)  # over absolute, under 0.1 % of 100 mm


# --------------------------------------------------------------------------- configuration
def test_config_disable_enable_and_severity_override() -> None:
    cfg = config_from_dict(
        {"disable": ["CNC504"], "enable": ["CNC601"], "rules": {"CNC030": "note"}}, set(RULES)
    )
    assert cfg.severity("CNC504", Severity.ERROR, True) is None
    assert cfg.severity("CNC601", Severity.WARNING, False) == Severity.WARNING
    assert cfg.severity("CNC030", Severity.WARNING, True) == Severity.NOTE
    assert cfg.severity("CNC202", Severity.WARNING, False) is None


@pytest.mark.parametrize(
    "table",
    [
        {"safe_height": 5},
        {"disable": ["CNC999"]},
        {"rules": {"CNC101": "fatal"}},
        {"stock": {"min": [0, 0, 0], "max": [1, 1]}},
        {"unsupported": ["X5"]},
        {"arc_tolerance": "haas"},
    ],
)
def test_config_mistakes_are_diagnostics(table: dict) -> None:
    with pytest.raises(Diagnostic) as err:
        config_from_dict(table, set(RULES), "m.toml")
    assert err.value.code == "CHECK-CONFIG"


# --------------------------------------------------------------------------- geometry properties
@given(
    st.floats(-math.pi, math.pi),
    st.floats(0.05, 6.0),
    st.sampled_from([-1, 1]),
    st.floats(0.5, 50.0),
)
def test_arc_box_contains_every_point_of_the_arc(
    theta0: float, sweep: float, sign: int, r: float
) -> None:
    sw = sign * sweep
    s = CheckState()
    s.position = (r * math.cos(theta0), r * math.sin(theta0), 0, 0, 0, 0)
    t1 = theta0 + sw
    cmd = canon.ArcFeed(r * math.cos(t1), r * math.sin(t1), 0, 0, sign, 0)
    pts = list(arc_extremes(arc_of(s, cmd)))
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    for k in range(65):
        t = theta0 + sw * k / 64
        x, y = r * math.cos(t), r * math.sin(t)
        assert min(xs) - 1e-9 <= x <= max(xs) + 1e-9
        assert min(ys) - 1e-9 <= y <= max(ys) + 1e-9


def test_segment_box_intersection() -> None:
    lo, hi = (0.0, 0.0, -10.0), (10.0, 10.0, 0.0)
    assert segment_hits_box((5, 5, 5), (5, 5, -1), lo, hi)  # plunge
    assert not segment_hits_box((5, 5, 5), (5, 5, 0), lo, hi)  # touches the top only
    assert segment_hits_box((-5, 5, -1), (15, 5, -1), lo, hi)  # crosses sideways
    assert not segment_hits_box((-5, -5, -1), (-1, 15, -1), lo, hi)  # passes beside


def test_straight_retract_with_spindle_stopped_is_not_cutting() -> None:
    """A reamer leaves its hole along +Z with the spindle stopped (STEP-NC REAMING)."""
    cmds = [
        canon.StraightTraverse(0, 0, 5),
        canon.SetSpindleSpeed(500),
        canon.StartSpindleClockwise(),
        canon.SetFeedRate(100),
        canon.StraightFeed(0, 0, -10),
        canon.StopSpindleTurning(),
        canon.StraightFeed(0, 0, 5),
        canon.ProgramEnd(),
    ]
    ctx = CheckContext(DEFAULT_MACHINE)
    assert "CNC504" not in {f.rule for f in run(cmds, ctx)}
    cmds[-2] = canon.StraightFeed(5, 0, 5)  # leaving sideways does cut
    assert "CNC504" in {f.rule for f in run(cmds, ctx)}


def test_a_tool_known_only_by_name_counts_as_loaded() -> None:
    cfg = config_from_dict({"enable": ["CNC202"]}, set(RULES))
    ctx = CheckContext(DEFAULT_MACHINE, cfg)
    cmds = [
        canon.StraightTraverse(0, 0, 5),
        canon.ChangeTool(0, "REAMER_22MM"),
        canon.UseToolLengthOffset(100.0),
        canon.SetSpindleSpeed(500),
        canon.StartSpindleClockwise(),
        canon.SetFeedRate(100),
        canon.StraightFeed(0, 0, -10),
        canon.ProgramEnd(),
    ]
    assert {f.rule for f in run(cmds, ctx)} == set()
    del cmds[2]  # no length offset after the change
    found = [f for f in run(cmds, ctx) if f.rule == "CNC203"]
    assert found and "REAMER_22MM" in found[0].message


@given(
    st.lists(
        st.tuples(st.floats(-150, 150), st.floats(-150, 150), st.floats(-150, 150)),
        min_size=1,
        max_size=8,
    )
)
def test_limit_verdict_does_not_depend_on_program_units(points: list) -> None:
    """The same moves written in mm and in inches hit the same travel limits."""
    m = Machine(
        "m", (AxisLimits("x", -100, 100), AxisLimits("y", -80, 80), AxisLimits("z", -60, 60))
    )
    ctx = CheckContext(m)

    def margin_ok(p: tuple) -> bool:  # keep clear of the limits, where rounding could decide
        return all(abs(abs(v) - lim) > 1e-6 for v, lim in zip(p, (100, 80, 60), strict=True))

    if not all(margin_ok(p) for p in points):
        return
    mm = [canon.UseLengthUnits(canon.Units.MM)] + [canon.StraightTraverse(*p) for p in points]
    inch = [canon.UseLengthUnits(canon.Units.INCHES)] + [
        canon.StraightTraverse(*(v / 25.4 for v in p)) for p in points
    ]
    hits_mm = [f.location for f in run(mm, ctx) if f.rule == "CNC101"]
    hits_inch = [f.location for f in run(inch, ctx) if f.rule == "CNC101"]
    outside = any(abs(p[0]) > 100 or abs(p[1]) > 80 or abs(p[2]) > 60 for p in points)
    assert bool(hits_mm) == bool(hits_inch) == outside


_num = st.floats(-500, 500, allow_nan=False, allow_infinity=False)
_commands = st.one_of(
    st.builds(canon.StraightTraverse, _num, _num, _num, _num, _num, _num),
    st.builds(canon.StraightFeed, _num, _num, _num, _num, _num, _num),
    st.builds(canon.ArcFeed, _num, _num, _num, _num, st.integers(-3, 3), _num),
    st.builds(canon.StraightProbe, _num, _num, _num),
    st.builds(canon.SetFeedRate, st.floats(0, 1e5)),
    st.builds(canon.SetSpindleSpeed, st.floats(0, 1e5)),
    st.builds(canon.Dwell, st.floats(0, 1e3)),
    st.builds(canon.SelectPlane, st.sampled_from(list(canon.Plane))),
    st.builds(canon.UseLengthUnits, st.sampled_from([canon.Units.MM, canon.Units.INCHES])),
    st.builds(canon.SetOriginOffsets, _num, _num, _num),
    st.builds(canon.UseToolLengthOffset, _num),
    st.builds(canon.ChangeTool, st.integers(0, 5)),
    st.builds(canon.SetFeedMode, st.sampled_from(list(canon.FeedMode))),
    st.builds(canon.SetCutterRadiusCompensation, st.floats(0, 20)),
    st.builds(canon.StartCutterRadiusCompensation, st.sampled_from(list(canon.CompSide))),
    st.builds(canon.SetMotionControlMode, st.sampled_from(list(canon.MotionMode)), st.floats(0, 5)),
    st.sampled_from(
        [
            canon.StartSpindleClockwise(),
            canon.StartSpindleCounterclockwise(),
            canon.StopSpindleTurning(),
            canon.FloodOn(),
            canon.MistOn(),
            canon.StopCutterRadiusCompensation(),
            canon.ProgramEnd(),
        ]
    ),
)


@example([canon.StraightFeed(0.0, 0.0, 1e-06)])  # found by this test: tiny move, no axis cap
@given(st.lists(_commands, max_size=40))
def test_any_canonical_stream_is_judged_without_crashing(cmds: list) -> None:
    found = check_stream(cmds, SHOP)
    assert all(f.rule in RULES for f in found)
    assert all(f.severity in Severity for f in found)


def test_interpreter_missing_end_is_the_program_end_rule() -> None:
    def stream():
        yield canon.StraightTraverse(0, 0, 5)
        raise Diagnostic(
            "NGC-NO-END", "file ended with no percent sign or program end", Location("p.ngc", 9, 1)
        )

    found = check_stream(stream(), CheckContext(DEFAULT_MACHINE))
    assert [(f.rule, f.code) for f in found] == [("CNC010", "NGC-NO-END")]


def test_constant_surface_speed_is_not_judged_as_rpm() -> None:
    """G96 S200 is 200 m/min, not 200 rpm; its rpm cap is D (SET_SPINDLE_MODE css_max)."""
    cmds = [
        canon.StraightTraverse(0, 0, 5),
        canon.SetSpindleMode(3000.0, True),
        canon.SetSpindleSpeed(200.0),  # below min_speed 500 if it were rpm
        canon.StartSpindleClockwise(),
        canon.SetFeedRate(100),
        canon.StraightFeed(10, 10, -1),
        canon.ProgramEnd(),
    ]
    fired = {f.rule for f in run(cmds)}
    assert not fired & {"CNC501", "CNC502"}
    cmds[1] = canon.SetSpindleMode(20000.0, True)  # D above the 12000 rpm spindle
    assert "CNC501" in {f.rule for f in run(cmds)}
