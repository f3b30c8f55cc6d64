"""``cnc check`` judges runs of moves over arrays (kernel.check.batch); the findings must be
those of asking every rule command by command (``check_stream(..., batched=False)``, the
loop the rules were written for). Compared on every canonical program of the check tests,
the corpus and the RS274/NGC goldens, under the shop profile (every rule on, stock and safe
height set), the sim profile and the built-in default machine, with runs cut short so that
their boundaries fall everywhere; and on a generated CAM program with an XY rotation, a
work offset and a tool length offset.
"""

from __future__ import annotations

import contextlib
import math
import random
from collections.abc import Iterator
from pathlib import Path

import pytest

import kernel.check as check
from bench.cam_program import cam_lines
from cli.check import load_context
from kernel.check import CheckContext, check_stream
from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE
from tests.data_paths import CORPUS_NGC

HERE = Path(__file__).parent
CHECK = HERE / "check"
CONTEXTS = {
    "shop": load_context(str(CHECK / "shop.toml"), str(CHECK / "shop.toml"), None),
    "sim": load_context(str(CHECK / "sim.toml"), str(CHECK / "sim.toml"), None),
    "default": CheckContext(DEFAULT_MACHINE, default_machine=True),
}
TRIGGERS = sorted(CHECK.glob("*.canon"))
PROGRAMS = sorted([*CORPUS_NGC.glob("*.canon"), *(HERE / "golden" / "ngc").glob("*.canon")])


def _commands(path: Path) -> list[canon.Command]:
    with open(path) as fh:
        out: list[canon.Command] = []
        # an unreadable golden is judged up to its error
        with contextlib.suppress(Exception):
            out.extend(canon.read_commands(fh, str(path), keep_linuxcnc=True))
        return out


@pytest.fixture
def short_runs(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    monkeypatch.setattr(check, "BATCH", 7)
    yield


def _differ(paths: list[Path], ctx: CheckContext) -> list[str]:
    out = []
    for path in paths:
        cmds = _commands(path)
        if check_stream(cmds, ctx, str(path)) != check_stream(cmds, ctx, str(path), batched=False):
            out.append(path.name)
    return out


@pytest.mark.parametrize("ctx_name", sorted(CONTEXTS))
def test_runs_judge_as_command_by_command_on_the_rule_triggers(
    short_runs: None, ctx_name: str
) -> None:
    assert not _differ(TRIGGERS, CONTEXTS[ctx_name])


@pytest.mark.slow
@pytest.mark.parametrize("ctx_name", sorted(CONTEXTS))
def test_runs_judge_as_command_by_command_on_the_corpus_and_goldens(
    short_runs: None, ctx_name: str
) -> None:
    assert not _differ(PROGRAMS, CONTEXTS[ctx_name])


def test_runs_judge_as_command_by_command_on_a_cam_program() -> None:
    from gcode.readers import read_text

    head = "G10 L2 P1 X3 Y-2 R30\nG54\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\nG1 Z-1 F9000\n"
    text = head + "\n".join(list(cam_lines(600))[7:]) + "\n"
    cmds = list(read_text(text, "rs274ngc", "cam.ngc"))
    for ctx in CONTEXTS.values():
        batched = check_stream(cmds, ctx, "cam.ngc")
        assert batched == check_stream(cmds, ctx, "cam.ngc", batched=False)
    assert batched  # the default machine's travel is left, the feed is too fast


@pytest.mark.parametrize(
    "ctx_name",
    [
        "default",
        pytest.param("shop", marks=pytest.mark.slow),
        pytest.param("sim", marks=pytest.mark.slow),
    ],
)
def test_the_fast_lanes_arrays_judge_as_its_commands(
    tmp_path: Path, ctx_name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    import gcode.ngc.interpreter as interp
    from cli.programs import check_input_bulk
    from gcode.readers import read

    # the lane forced on (its break-even would leave a program this small to the general
    # path; this test is about what cnc check does with the lane's arrays)
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    prog = tmp_path / "cam.ngc"
    head = "G10 L2 P1 X3 Y-2 R30\nG54\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\nG1 Z-1 F9000\n"
    prog.write_text(head + "\n".join(list(cam_lines(9500))[7:]) + "\n")
    ctx = CONTEXTS[ctx_name]
    items, _ = check_input_bulk(str(prog), "rs274ngc", -1, bulk=True)
    items = list(items)
    assert any(isinstance(i, check.Moves) for i in items)
    bulk = check_stream(items, ctx, str(prog))
    assert bulk == check_stream(read(prog, "rs274ngc"), ctx, str(prog), batched=False)
    assert bulk


def _mixed_program(n: int) -> str:
    """Plain lines the fast lane takes, with a feed change, an arc either way (some a
    little off their radius) or an A move every few lines."""
    lines = ["G21 G17", "T1 M6", "S9000 M3", "G0 X0 Y0 Z5", "G1 Z-1 F300"]
    x = y = 0.0
    for i in range(n):
        if i % 7 == 3:
            lines.append(f"F{(300, 900, 2500, 40000)[i % 4]}")
        elif i % 11 == 5:
            r = 2.0 + (i % 3)
            off = (0.0, 0.001, 0.01)[i % 3]
            lines.append(f"{('G2', 'G3')[i % 2]} X{x + 2 * r + off:.4f} Y{y:.4f} I{r:.4f} J0")
            lines.append("G1")
            x += 2 * r + off
        elif i % 13 == 6:
            lines.append(f"A{i % 40}")
        else:
            x, y = x + 0.5 + (i % 5) / 10, (i % 9) / 10
            lines.append(f"X{x:.4f} Y{y:.4f} Z{-1 - (i % 4) / 10:.4f}")
    return "\n".join([*lines, "G0 Z5", "M5", "M2"]) + "\n"


def test_the_fast_lanes_runs_with_feed_changes_and_arcs_judge_as_their_commands(
    tmp_path: Path, short_runs: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Runs span SET_FEED_RATEs (the feed is judged per row) and arcs (screened from their
    arrays); cut short so that runs start and end everywhere."""
    import gcode.ngc.interpreter as interp
    from cli.programs import check_input_bulk
    from gcode.readers import read
    from kernel.check import config_from_dict

    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    prog = tmp_path / "mixed.ngc"
    prog.write_text(_mixed_program(300))
    table = {"unsupported": ["G2"], "arc_tolerance": "mach3", "max_feed": 30000.0}
    strict = config_from_dict(table, set(check.RULES))
    contexts = [CONTEXTS["default"], CheckContext(DEFAULT_MACHINE, strict, default_machine=True)]
    for ctx in contexts:
        items, _ = check_input_bulk(str(prog), "rs274ngc", -1, bulk=True)
        bulk = check_stream(items, ctx, str(prog))
        assert bulk == check_stream(read(prog, "rs274ngc"), ctx, str(prog), batched=False)
        rules = {f.rule for f in bulk}
        assert {"CNC102", "CNC103"} <= rules  # the A moves, the fast feed
    assert {"CNC301", "CNC701"} <= rules  # the arcs off their radius, the G2s


_NUMBERS = (0.0, -1.0, 399.9999999, 400.0, 400.000001, 1e308, -1e308, math.inf, math.nan, 1e-7)


def _random_stream(rng: random.Random, n: int) -> list[canon.Command]:
    """Moves, arcs (either way, several turns, none), feed rates (zero, negative, NaN) and
    the state changes between them, with now and then a number at a limit or beyond."""

    def num() -> float:
        return rng.choice(_NUMBERS) if rng.random() < 0.1 else rng.uniform(-50.0, 450.0)

    def at(i: int) -> Location:
        return Location("r.canon", i + 2, 1)

    out: list[canon.Command] = [canon.ChangeTool(1, "", source=at(-1))]
    for i in range(n):
        r = rng.random()
        if r < 0.35:
            out.append(canon.StraightFeed(num(), num(), num(), 0.0, 0.0, 0.0, source=at(i)))
        elif r < 0.5:
            a = rng.choice((0.0, 0.0, 5.0))
            out.append(canon.StraightTraverse(num(), num(), num(), a, 0.0, 0.0, source=at(i)))
        elif r < 0.65:
            turns = rng.choice((-2, -1, 0, 1, 1, 2))
            arc = (num(), num(), num(), num(), turns, num(), 0.0, 0.0, 0.0)
            out.append(canon.ArcFeed(*arc, source=at(i)))
        elif r < 0.77:
            rate = rng.choice((0.0, 100.0, 5000.0, 1e6, math.nan, -5.0, 300.0))
            out.append(canon.SetFeedRate(rate, source=at(i)))
        else:
            out.append(
                rng.choice(
                    (
                        canon.SelectPlane(rng.choice(list(canon.Plane)), source=at(i)),
                        canon.UseLengthUnits(rng.choice(list(canon.Units)), source=at(i)),
                        canon.StartSpindleClockwise(source=at(i)),
                        canon.StopSpindleTurning(source=at(i)),
                        canon.SetSpindleSpeed(rng.choice((0.0, 9000.0)), source=at(i)),
                        canon.SetCutterRadiusCompensation(rng.choice((2.0, 50.0)), source=at(i)),
                        canon.StartCutterRadiusCompensation(
                            rng.choice(list(canon.CompSide)), source=at(i)
                        ),
                        canon.StopCutterRadiusCompensation(source=at(i)),
                        canon.SetFeedMode(rng.choice(list(canon.FeedMode)), source=at(i)),
                        canon.UseToolLengthOffset(rng.choice((0.0, 10.0)), source=at(i)),
                    )
                )
            )
    return [*out, canon.ProgramEnd(source=at(n))]


def test_random_streams_judge_as_command_by_command(short_runs: None) -> None:
    """Runs of moves, arcs and feed changes with limits, non-finite numbers, zero feeds and
    compensation: the arrays (and the arcs' screens) give the rules' own findings."""
    from kernel.check import config_from_dict

    table = {
        "unsupported": ["G2"],
        "arc_tolerance": "grbl",
        "max_feed": 3000.0,
        "safe_z": 2.0,
        "stock": {"min": [0.0, 0.0, -10.0], "max": [50.0, 50.0, 0.0]},
    }
    strict = config_from_dict(table, set(check.RULES))
    contexts = [CONTEXTS["default"], CheckContext(DEFAULT_MACHINE, strict, default_machine=True)]
    found = set()
    for seed in range(6):
        cmds = _random_stream(random.Random(seed), 120)
        for ctx in contexts:
            batched = check_stream(cmds, ctx, "r.canon")
            assert batched == check_stream(cmds, ctx, "r.canon", batched=False), seed
            found |= {f.rule for f in batched}
    assert {"CNC101", "CNC104", "CNC301", "CNC701"} <= found
