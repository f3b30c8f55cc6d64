"""Convert speed: a 200,000-line program converted to each dialect vs ``cnc canon`` on it.

Issue 7 asks that converting a 200,000-line program between dialects take within 2x of
``cnc canon`` on the same file. Both sides run in this process on the same generated
program (lines and arcs, the mix of CAM output): ``canon`` = interpret + canonical text;
``convert`` = interpret + write in the dialect. Prints the best seconds of each and the
median ratio of back-to-back pairs (robust to load from other processes).

    python bench/convert_bench.py [LINES]
"""

from __future__ import annotations

import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

from gcode.convert_report import ConversionReport
from gcode.dialects import NAMES
from gcode.emit import WriterOptions, write
from gcode.interpreter import interpret
from kernel import canon


def program(lines: int) -> str:
    """G1 zig-zags with a G2/G3 arc every fifth block, all in absolute mm."""
    out = ["G21 G90 G17 G94", "F600 S8000 M3", "G0 X0 Y0 Z1", "G1 Z-0.5"]
    x = y = 0.0
    for i in range(lines - 6):
        if i % 5 == 4:
            r = 2.0 + (i % 7) * 0.1
            code = "G2" if i % 2 else "G3"
            out.append(f"{code} X{x + 2 * r:.4f} Y{y:.4f} R{r:.4f}")
            x += 2 * r
        else:
            x += 1.0 + 0.25 * math.sin(i * 0.01)
            y = 10.0 * math.sin(i * 0.003)
            out.append(f"G1 X{x:.4f} Y{y:.4f}")
    out += ["G0 Z5", "M2"]
    return "\n".join(out) + "\n"


REPEATS = 3


def timed(func) -> float:  # noqa: ANN001
    start = time.perf_counter()
    func()
    return time.perf_counter() - start


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.ngc"
        path.write_text(program(lines))
        sink = Path(tmp) / "out.txt"

        def canon_run() -> None:
            with open(sink, "w") as fh:
                for line in canon.write_text(interpret(path)):
                    fh.write(line + "\n")

        def convert_run(name: str) -> None:
            with open(sink, "w") as fh:
                for line in write(interpret(path), name, WriterOptions(), ConversionReport()):
                    fh.write(line + "\n")

        ir = list(interpret(path))
        print(f"{lines} lines, {len(ir)} commands; {REPEATS} side-by-side pairs per dialect")
        print("  ratio = median over pairs of convert time / canon time measured back to back")
        for name in NAMES:
            pairs = []
            for _ in range(REPEATS):
                base = timed(canon_run)
                pairs.append((timed(lambda name=name: convert_run(name)), base))

            def alone(name: str = name) -> None:
                for _ in write(ir, name, WriterOptions(), ConversionReport()):
                    pass

            w = min(timed(alone) for _ in range(2))
            ratio = statistics.median(t / b for t, b in pairs)
            t, base = min(p[0] for p in pairs), min(p[1] for p in pairs)
            print(
                f"  {name:12s} convert {t:6.2f} s  canon {base:6.2f} s  ratio {ratio:4.2f}"
                f"  (writer alone {w:5.2f} s)"
            )


if __name__ == "__main__":
    main()
