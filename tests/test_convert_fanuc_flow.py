"""Fanuc reader behaviour checked against closed forms and the Fanuc rules directly:
transforms (hypothesis: G68 rotation and G51 scaling of random points), program frames
and subprogram files, M99 in a main program."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gcode.fanuc.reader import interpret, interpret_text
from kernel.ir import canon

HEAD = "%\nO0001\nG21 G90 G17\nG00 X0 Y0\n"
coord = st.floats(-200, 200, allow_nan=False).map(lambda v: round(v, 3))


def _feeds(text: str) -> list[tuple[float, float]]:
    return [(c.x, c.y) for c in interpret_text(text) if isinstance(c, canon.StraightFeed)]


@settings(max_examples=60, deadline=None)
@given(coord, coord, st.floats(-360, 360).map(lambda v: round(v, 3)), coord, coord)
def test_g68_rotates_every_point_about_its_centre(
    cx: float, cy: float, angle: float, x: float, y: float
) -> None:
    text = HEAD + f"G68 X{cx:.3f} Y{cy:.3f} R{angle:.3f}\nG01 X{x:.3f} Y{y:.3f} F100.\nM30\n"
    t = math.radians(angle)
    want = (
        cx + (x - cx) * math.cos(t) - (y - cy) * math.sin(t),
        cy + (x - cx) * math.sin(t) + (y - cy) * math.cos(t),
    )
    assert _feeds(text)[0] == pytest.approx(want, abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(coord, coord, st.integers(1, 400_000), coord, coord)
def test_g51_scales_about_its_centre_in_units_of_0_00001(
    cx: float, cy: float, p: int, x: float, y: float
) -> None:
    text = HEAD + f"G51 X{cx:.3f} Y{cy:.3f} P{p}\nG01 X{x:.3f} Y{y:.3f} F100.\nM30\n"
    f = p * 1e-5
    assert _feeds(text)[0] == pytest.approx((cx + f * (x - cx), cy + f * (y - cy)), abs=1e-9)


def test_m99_in_the_main_program_stops_reading() -> None:
    text = HEAD + "G01 X1. F100.\nM99\nG01 X2.\nM30\n%\n"
    assert _feeds(text) == [(1.0, 0.0)]


def test_subprogram_file_without_o_line_is_found_beside_the_program(tmp_path: Path) -> None:
    (tmp_path / "main.nc").write_text(HEAD + "M98 P77 L2\nM30\n%\n")
    (tmp_path / "O0077.nc").write_text("%\n(NO O LINE)\nG91 G01 X3. F100.\nG90\nM99\n%\n")
    feeds = [c.x for c in interpret(tmp_path / "main.nc") if isinstance(c, canon.StraightFeed)]
    assert feeds == pytest.approx([3.0, 6.0])


def test_lathe_u_is_a_diameter_increment_and_w_a_z_increment() -> None:
    text = "%\nO0001\nG21 G98\nG00 X20. Z0\nG01 U-4. W-10. F100.\nM30\n%\n"
    feeds = [c for c in interpret_text(text, lathe=True) if isinstance(c, canon.StraightFeed)]
    assert (feeds[0].x, feeds[0].z) == pytest.approx((8.0, -10.0))


def test_the_lathe_reader_module_reads_x_as_a_diameter() -> None:
    from gcode.fanuc_lathe import reader as fanuc_lathe_reader

    text = "%\nO0001\nG21 G98\nG00 X40. Z2.\nM30\n%\n"
    rapids = [
        c for c in fanuc_lathe_reader.interpret_text(text) if isinstance(c, canon.StraightTraverse)
    ]
    assert (rapids[0].x, rapids[0].z) == pytest.approx((20.0, 2.0))
