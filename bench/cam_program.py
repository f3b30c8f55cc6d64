"""Generator of CAM-style RS274/NGC programs for benchmarks (issue 2, 3, 7).

The program looks like a CAM post's output: a header, then mostly ``X.. Y.. Z..`` feed
lines of a zig-zag surfacing pass, an arc every 50 lines and a feed change every 200, and
a footer. It is deterministic (seeded) so runs compare like with like.
"""

from __future__ import annotations

import argparse
import math
import random
from collections.abc import Iterator
from pathlib import Path


def cam_lines(n_lines: int, seed: int = 5970, stop_every: int = 0) -> Iterator[str]:
    """Yield ``n_lines`` lines (header and footer included) of a millimetre CAM program;
    ``stop_every``: a ``G4 P0`` (a stop: LinuxCNC's queue runs dry) instead of every
    ``stop_every``-th feed line (0: none)."""
    rng = random.Random(seed)
    yield "%"
    yield "(CAM-style benchmark program)"
    yield "G21 G90 G17 G94 G40 G49 G80"
    yield "T1 M6"
    yield "S12000 M3"
    yield "G0 X0 Y0 Z5"
    yield "G1 Z-1 F300"
    x = y = 0.0
    body = n_lines - 10
    for i in range(body):
        if stop_every and i % stop_every == stop_every - 1:
            yield "G4 P0"
        elif i % 200 == 199:
            yield f"F{rng.choice((600, 800, 1200, 1500))}"
        elif i % 50 == 49:
            r = 2.0 + rng.random()
            xe = x + 2 * r
            yield f"G3 X{xe:.4f} Y{y:.4f} I{r:.4f} J0"
            yield "G1"
            x = xe
        else:
            x += 0.5 + rng.random()
            y = 20.0 * math.sin(i / 40.0) + rng.random()
            z = -1.0 - 0.2 * rng.random()
            yield f"X{x:.4f} Y{y:.4f} Z{z:.4f}"
    yield "G0 Z5"
    yield "M5"
    yield "M2"
    yield "%"


def write_program(path: Path, n_lines: int, seed: int = 5970, stop_every: int = 0) -> Path:
    """Write the program to ``path`` and return it."""
    with path.open("w") as fh:
        for line in cam_lines(n_lines, seed, stop_every):
            fh.write(line + "\n")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("out", type=Path)
    parser.add_argument("--lines", type=int, default=200_000)
    args = parser.parse_args()
    write_program(args.out, args.lines)


if __name__ == "__main__":
    main()
