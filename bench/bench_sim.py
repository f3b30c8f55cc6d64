"""``cnc sim`` speed: a generated 3-axis finishing program on a 300 x 300 mm stock (issue 17).

The program is a raster of short 3-D lines (1.5 mm each) over a wavy surface with a 6 mm
ball end mill, rapids between rows, fed to :func:`kernel.stock.simulate_removal` as canonical
commands (the reader's time is not counted). Prints CPU seconds (the machine may be shared),
moves per second and the peak memory for several move counts and grid sizes, so that time
against moves and against cells can be read off.
Usage: ``python bench/bench_sim.py [MOVES ...] [GRID_MM ...] [--tool=KIND ...]`` (a grid size
has a dot; KIND flat, ball (the default), bull (corner 1 mm), drill (118°) or chamfer (90°),
all 6 mm; with several tools each row's ``ratio`` is its time over the first tool's, measured
in the same run, since the machine may be shared). ``--turning`` times the turning profile
instead: roughing passes of 0.5 mm lines along a 150 mm bar, insert with a 0.8 mm nose
(default 10,000 moves at 0.01 mm).
"""

from __future__ import annotations

import math
import resource
import sys
import time

from kernel.ir import canon
from kernel.stock import HeightField, StockBox, ToolShape, simulate_removal
from kernel.stock.tools import make_tool
from kernel.stock.turning import Bar, TurnedProfile, simulate_turning

BOX = StockBox(0.0, 0.0, -30.0, 300.0, 300.0, 0.0)
SEG = 1.5  # mm of each feed move


def program(moves: int) -> list[canon.Command]:
    """About ``moves`` feed moves: rows along X, each of 200 short 3-D lines, rows spread
    over the stock in Y, one rapid up, across and down between rows."""
    per_row = int(BOX.x1 // SEG)
    rows = max(1, moves // per_row)
    step = BOX.y1 / rows
    cmds: list[canon.Command] = []
    for r in range(rows):
        y = (r + 0.5) * step
        cmds.append(canon.StraightTraverse(0.0, y, 5.0))
        for k in range(per_row + 1):
            x = k * SEG
            z = -2.0 - 1.5 * math.sin(x / 20.0) * math.cos(y / 25.0)
            cmds.append(canon.StraightFeed(x, y, z))
        cmds.append(canon.StraightTraverse(BOX.x1, y, 5.0))
    return cmds


def bench_tool(kind: str) -> ToolShape:
    """The 6 mm tool of the given kind."""
    extra = {"bull": {"corner_radius": 1.0}}.get(kind, {})
    return make_tool(kind, 6.0, f"--tool={kind}", **extra)


def run(moves: int, res: float, tool: ToolShape) -> tuple[float, int, int]:
    cmds = program(moves)
    hf = HeightField(BOX, res)
    t0 = time.process_time()
    result = simulate_removal(cmds, hf, {0: tool})
    return time.process_time() - t0, result.moves, hf.nx * hf.ny


BAR = Bar(30.0, -150.0, 0.0)


def turning_program(moves: int) -> list[canon.Command]:
    """About ``moves`` lathe feed moves: passes along -Z of 0.5 mm steps over the bar's
    150 mm, each 0.5 mm deeper than the last with a 0.2 mm wave in X, rapids back."""
    per_pass = int(-BAR.z0 / 0.5)
    passes = max(1, moves // per_pass)
    depth = min(0.5, 20.0 / passes)
    cmds: list[canon.Command] = []
    for p in range(passes):
        x0 = BAR.radius - (p + 1) * depth
        cmds.append(canon.StraightTraverse(BAR.radius + 2, 0.0, 2.0))
        cmds.append(canon.StraightTraverse(x0, 0.0, 2.0))
        for k in range(per_pass + 1):
            z = -0.5 * k
            cmds.append(canon.StraightFeed(x0 - 0.2 * math.sin(z / 7.0) ** 2, 0.0, z))
        cmds.append(canon.StraightTraverse(BAR.radius + 2, 0.0, BAR.z0))
    return cmds


def run_turning(moves: int, res: float) -> tuple[float, int, int]:
    cmds = turning_program(moves)
    prof = TurnedProfile(BAR, res)
    t0 = time.process_time()
    result = simulate_turning(cmds, prof, {0: make_tool("insert", 0.8, "insert")})
    return time.process_time() - t0, result.moves, prof.nz


def main(argv: list[str]) -> None:
    if "--turning" in argv:
        counts = [int(a) for a in argv if not a.startswith("--") and "." not in a] or [10_000]
        grids = [float(a) for a in argv if "." in a and not a.startswith("--")] or [0.01]
        print(f"{'moves':>8} {'grid mm':>8} {'cells':>10} {'seconds':>8} {'moves/s':>9}")
        for res in grids:
            for n in counts:
                secs, moves, cells = run_turning(n, res)
                print(f"{moves:>8} {res:>8g} {cells:>10} {secs:>8.2f} {moves / secs:>9.0f}")
        return
    counts = [int(a) for a in argv if not a.startswith("--") and "." not in a] or [
        5_000,
        10_000,
        20_000,
    ]
    grids = [float(a) for a in argv if "." in a and not a.startswith("--")] or [0.2, 0.1]
    kinds = [a.split("=", 1)[1] for a in argv if a.startswith("--tool=")] or ["ball"]
    first: dict[tuple[int, float], float] = {}
    print(
        f"{'tool':>8} {'moves':>8} {'grid mm':>8} {'cells':>10} {'seconds':>8} {'moves/s':>9}"
        f" {'ratio':>6}"
    )
    for kind in kinds:
        tool = bench_tool(kind)
        run(200, grids[0], tool)  # the compiled kernels load (or compile) outside the timing
        for res in grids:
            for n in counts:
                secs, moves, cells = run(n, res, tool)
                ratio = secs / first.setdefault((n, res), secs)
                print(
                    f"{kind:>8} {moves:>8} {res:>8g} {cells:>10} {secs:>8.2f} "
                    f"{moves / secs:>9.0f} {ratio:>6.2f}"
                )
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak memory {peak:.0f} MB")


if __name__ == "__main__":
    main(sys.argv[1:])
