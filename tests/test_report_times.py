"""Time per tool and per operation (kernel.report.breakdown) and the clock format every
person-readable time uses (kernel.report.clock), issue 18.

The breakdown is checked against closed forms: on a machine whose acceleration is
effectively infinite, a constant-feed line of length L takes L / F, a traverse L / v_max
and a tool change the profile's change time, so each tool's share is a sum done by hand.
"""

from __future__ import annotations

import json
import math

import pytest

import kernel.ir.canon as canon
from kernel import simulate
from kernel.diagnostics import Location
from kernel.machine import AxisLimits, Controller, Machine
from kernel.report.breakdown import OUTSIDE, START, Stretches, breakdown
from kernel.report.clock import clock, fixed

# ------------------------------------------------------------------------------ clock


@pytest.mark.parametrize(
    ("seconds", "text"),
    [
        (2037, "33:57"),  # 33 * 60 + 57
        (2037.6, "33:58"),  # the 33:58
        (2037.5, "33:58"),  # halves round up
        (3723, "1:02:03"),
        (36000, "10:00:00"),
        (60, "1:00"),
        (59.96, "1:00"),  # rounds up across the minute: the longer form
        (59.94, "0:59.9"),
        (42.5, "0:42.5"),
        (0.04, "0:00.0"),
        (0, "0:00.0"),
        (-0.0, "0:00.0"),
        (-0.01, "0:00.0"),  # no "-0:00.0"
        (-75, "-1:15"),
        (3599.6, "1:00:00"),
        (math.inf, "-"),
        (math.nan, "-"),
    ],
)
def test_clock_closed_cases(seconds: float, text: str) -> None:
    assert clock(seconds) == text


@pytest.mark.parametrize(
    ("value", "digits", "text"),
    [
        (-0.0, 1, "0.0"),
        (-0.04, 1, "0.0"),
        (-0.05, 1, "-0.1"),
        (-1e-12, 3, "0.000"),
        (2.5, 2, "2.50"),
    ],
)
def test_fixed_never_prints_negative_zero(value: float, digits: int, text: str) -> None:
    assert fixed(value, digits) == text


# -------------------------------------------------------------------------- breakdown

V_RAPID = 100.0  # mm/s
CHANGE = 7.0  # s
STOP = 2.0  # s of M0


def _machine() -> Machine:
    """Acceleration and jerk so large that every move runs at its speed from end to end."""
    axes = tuple(
        AxisLimits(n, velocity=V_RAPID, acceleration=1e9, jerk=1e15) for n in ("x", "y", "z")
    )
    return Machine("stiff", axes, Controller(tool_change_time=CHANGE, program_stop_time=STOP))


def _program(ws: bool = False) -> list[canon.Command]:
    """T3: 30 mm at 600 mm/min and a 50 mm traverse; T5: a dwell, 20 mm at 1200 mm/min,
    a stop; T3 again: 10 mm at 600 mm/min. With ``ws`` the commands carry workingstep ids
    (11 for the first tool, 12 for the rest, none for the end) as STEP-NC commands do."""

    def at(cmd: canon.Command, w: int | None) -> canon.Command:
        if ws:
            object.__setattr__(cmd, "source", Location("p.stp", 1, 1, 100, w))
        return cmd

    return [
        at(canon.UseLengthUnits(canon.Units.MM), None),
        at(canon.ChangeTool(3), 11),
        at(canon.SetFeedRate(600.0), 11),
        at(canon.StraightFeed(30.0, 0.0, 0.0), 11),
        at(canon.StraightTraverse(30.0, 50.0, 0.0), 11),
        at(canon.ChangeTool(5), 12),
        at(canon.Dwell(1.5), 12),
        at(canon.SetFeedRate(1200.0), 12),
        at(canon.StraightFeed(30.0, 30.0, 0.0), 12),
        at(canon.ProgramStop(), 12),
        at(canon.ChangeTool(3), 12),
        at(canon.SetFeedRate(600.0), 12),
        at(canon.StraightFeed(40.0, 30.0, 0.0), 12),
        at(canon.ProgramEnd(), None),
    ]


def test_time_per_tool_is_the_hand_sum_of_its_moves() -> None:
    st = Stretches()
    result = simulate(st.watch(_program()), _machine())
    rows = breakdown(result.plan, st.tools)
    assert [r.label for r in rows] == ["T3", "T5", "T3"]
    first, second, third = (r.cycle for r in rows)
    tol = 1e-6
    assert first.cutting == pytest.approx(30 / 10, abs=tol)
    assert first.rapid == pytest.approx(50 / V_RAPID, abs=tol)
    assert first.tool_change == pytest.approx(CHANGE)
    assert first.total == pytest.approx(3 + 0.5 + CHANGE, abs=tol)
    assert second.dwell == pytest.approx(1.5)
    assert second.cutting == pytest.approx(20 / 20, abs=tol)
    assert second.other == pytest.approx(STOP)
    assert second.total == pytest.approx(CHANGE + 1.5 + 1 + STOP, abs=tol)
    assert third.cutting == pytest.approx(10 / 10, abs=tol)
    assert third.total == pytest.approx(CHANGE + 1, abs=tol)
    # the stretches follow each other and add up to the cycle time
    assert rows[1].start == pytest.approx(first.total, abs=tol)
    assert rows[2].start == pytest.approx(first.total + second.total, abs=tol)
    assert sum(r.cycle.total for r in rows) == pytest.approx(result.plan.total_time, rel=1e-12)
    assert [r.line for r in rows] == [0, 0, 0]  # canonical commands without source lines


def test_moves_before_the_first_tool_change_are_the_start_stretch() -> None:
    st = Stretches()
    cmds = [canon.SetFeedRate(600.0), canon.StraightFeed(10.0, 0.0, 0.0), *_program()[1:]]
    result = simulate(st.watch(cmds), _machine())
    rows = breakdown(result.plan, st.tools)
    assert rows[0].label == START and rows[0].cycle.cutting == pytest.approx(1.0, abs=1e-6)
    assert sum(r.cycle.total for r in rows) == pytest.approx(result.plan.total_time)


def test_time_per_workingstep_uses_the_ids_and_given_names() -> None:
    st = Stretches()
    result = simulate(st.watch(_program(ws=True)), _machine())
    rows = breakdown(result.plan, st.operations, {11: "WS FACE"}, st.tools)
    assert [r.label for r in rows] == ["WS FACE", "#12"]  # the end (no workingstep) takes 0 s
    assert [r.tool for r in rows] == ["T3", "T5"]
    assert rows[0].cycle.total == pytest.approx(CHANGE + 3 + 0.5, abs=1e-6)
    assert rows[1].cycle.total == pytest.approx(2 * CHANGE + 1.5 + 1 + STOP + 1, abs=1e-6)
    assert OUTSIDE not in [r.label for r in rows]


def test_gcode_has_no_operations() -> None:
    st = Stretches()
    list(st.watch(_program()))
    assert st.operations == []
    assert [m.label for m in st.tools] == [START, "T3", "T5", "T3"]


def test_share_json_keeps_seconds_and_adds_the_clock() -> None:
    st = Stretches()
    result = simulate(st.watch(_program()), _machine())
    row = breakdown(result.plan, st.tools)[0].to_dict()
    assert row["total"] == pytest.approx(10.5, abs=1e-6) and row["total_hms"] == "0:10.5"
    assert row["tool"] == row["label"] == "T3"


# ------------------------------------------------------------------------ cnc plan text


def test_plan_text_units_clock_no_negative_zero_and_unbroken_title(tmp_path) -> None:
    """``cnc plan``: every header has its unit, times read m:ss, no ``-0.0`` (a Z that never
    moves), the file name is never broken by a wrapped title at 80 columns, and samples and
    chord error only come with ``-v``."""
    from click.testing import CliRunner

    from cli.main import cli

    folder = tmp_path / ("a_rather_long_folder_name_for_a_shop_" * 2).rstrip("_")
    folder.mkdir()
    prog = folder / "two_tools_and_a_long_program_name.canon"
    prog.write_text("\n".join(c.to_text() for c in _program()) + "\n")
    res = CliRunner(env={"COLUMNS": "80"}).invoke(cli, ["plan", str(prog)])
    assert res.exit_code == 0, res.output
    out = res.output
    assert str(prog) in out.replace("\n", "") and any(str(prog) in ln for ln in out.splitlines())
    assert "-0.0" not in out
    for header in ("time [m:s]", "time [s]", "share [%]", "velocity [mm/s]"):
        assert header in out
    assert "acceleration [mm/s²]" in out and "jerk [mm/s³]" in out
    assert "total [m:s]" in out and "T5" in out  # the per-tool table
    assert "samples" not in out and "chord error" not in out
    verbose = CliRunner().invoke(cli, ["-v", "plan", str(prog)])
    assert verbose.exit_code == 0 and "chord error" in verbose.output
    assert "samples" in verbose.output


def test_plan_json_has_the_time_per_tool(tmp_path) -> None:
    """``cnc plan --format json`` keeps its keys and adds ``times``: seconds and m:ss."""
    from click.testing import CliRunner

    from cli.main import cli

    prog = tmp_path / "two_tools.canon"
    prog.write_text("\n".join(c.to_text() for c in _program()) + "\n")
    res = CliRunner().invoke(cli, ["plan", str(prog), "--format", "json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["cycle"]["total"] == pytest.approx(doc["times"]["cycle"])
    tools = doc["times"]["tools"]
    assert [t["label"] for t in tools] == ["T3", "T5", "T3"]
    assert sum(t["total"] for t in tools) == pytest.approx(doc["cycle"]["total"])
    assert doc["times"]["operations"] == [] and doc["times"]["cycle_hms"] == clock(
        doc["cycle"]["total"]
    )
