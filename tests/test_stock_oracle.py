"""Exact oracle for the height-field simulation: manifold3d's boolean subtraction of the
swept tool solids from the stock (issue 17). The tools are convex solids of revolution, so
a tool swept along a line is exactly the convex hull of its two end placements; the
removed volume is the stock's volume minus that of the stock less the union of the hulls.
The profiles are polygons of many segments (their inscribed error is about 1e-4 of the
volume), independent of kernel.stock's closed forms. The height field must agree within
0.5 % at a 0.1 mm grid.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel.ir import canon
from kernel.stock import HeightField, StockBox, ToolShape, simulate_removal
from kernel.stock.tools import make_tool

m3d = pytest.importorskip("manifold3d")

BOX = StockBox(0.0, 0.0, -10.0, 40.0, 30.0, 0.0)
SEGMENTS = 256
TALL = 40.0  # tool height above its tip in the oracle: past the stock's top from any move


def profile(tool: ToolShape) -> list[tuple[float, float]]:
    """(r, z) outline of the tool from the tip up, closed along the axis."""
    r = tool.radius
    pts: list[tuple[float, float]] = [(0.0, 0.0)]
    arc = np.linspace(0.0, math.pi / 2, 33)[1:]
    if tool.kind == "ball":
        pts += [(r * math.sin(p), r - r * math.cos(p)) for p in arc]
    elif tool.kind == "bull":
        a, rc = r - tool.corner_radius, tool.corner_radius
        pts += [(a, 0.0)] + [(a + rc * math.sin(p), rc - rc * math.cos(p)) for p in arc]
    elif tool.kind in ("drill", "chamfer"):
        tip = 0.5 * tool.tip_diameter
        if tip > 0:
            pts.append((tip, 0.0))
        pts.append((r, (r - tip) / math.tan(math.radians(tool.angle / 2))))
    else:
        pts.append((r, 0.0))
    return [*pts, (r, TALL), (0.0, TALL)]


def oracle_removed(tool: ToolShape, path: list[tuple[float, float, float]]) -> float:
    solid = m3d.Manifold.revolve(m3d.CrossSection([profile(tool)]), SEGMENTS)
    sweeps = [
        m3d.Manifold.batch_hull([solid.translate(p0), solid.translate(p1)])
        for p0, p1 in zip(path, path[1:], strict=False)
    ]
    size = (BOX.x1 - BOX.x0, BOX.y1 - BOX.y0, BOX.z1 - BOX.z0)
    stock = m3d.Manifold.cube(size).translate((BOX.x0, BOX.y0, BOX.z0))
    left = stock - m3d.Manifold.batch_boolean(sweeps, m3d.OpType.Add)
    return stock.volume() - left.volume()


PATH = [
    (6.0, 7.0, 3.0),
    (6.0, 7.0, -2.5),  # plunge
    (30.0, 9.0, -4.0),  # 3-D line, sloping down
    (33.0, 22.0, -1.0),  # 3-D line, sloping up
    (10.0, 24.5, -3.0),
    (10.0, 24.5, 3.0),
]
TOOLS = {
    "flat": ToolShape("flat", 6.0),
    "ball": ToolShape("ball", 6.0),
    "bull": make_tool("bull", 8.0, "t", corner_radius=1.5),
    "drill": make_tool("drill", 5.0, "t"),
    "chamfer": make_tool("chamfer", 8.0, "t", angle=90.0, tip_diameter=1.0),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(TOOLS))
def test_removed_volume_agrees_with_the_boolean_of_the_swept_solids(name: str) -> None:
    tool = TOOLS[name]
    exact = oracle_removed(tool, PATH)
    cmds: list[canon.Command] = [canon.StraightTraverse(*PATH[0])]
    cmds += [canon.StraightFeed(*p) for p in PATH[1:]]
    got = simulate_removal(cmds, HeightField(BOX, 0.1), {0: tool}).removed_volume
    assert abs(got - exact) / exact < 0.005, (name, got, exact)
