"""Siemens 840D reader speed on a 200,000-line program of G1/G2 blocks (issue 7, readers.md §5).

Prints lines per second of the reader alone (interpret -> IR objects), of ``cnc canon``'s
work (reader + canonical text) and of ``cnc convert``'s work to RS274/NGC (reader +
writer), the convert/canon ratio the issue bounds by 2, and for scale the RS274/NGC
interpreter (Python path, no compiled fast lane) on the same moves written with ``R``.
Best of three runs each; the machine's load moves all figures together.

    python bench/siemens_reader_bench.py [LINES]
"""

from __future__ import annotations

import math
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from gcode.ngc.interpreter import InterpreterOptions
from gcode.ngc.interpreter import interpret as interpret_ngc
from gcode.siemens.reader import interpret
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.ir import canon


def program(lines: int) -> str:
    """G1 zig-zags with a G2/G3 ``CR=`` arc every fifth block, absolute mm (CAM-like)."""
    out = ["G710 G90 G17 G94", "F600 S8000 M3", "G0 X0 Y0 Z1", "G1 Z-0.5"]
    x = y = 0.0
    for i in range(lines - 6):
        if i % 5 == 4:
            r = 2.0 + (i % 7) * 0.1
            code = "G2" if i % 2 else "G3"
            out.append(f"{code} X{x + 2 * r:.4f} Y{y:.4f} CR={r:.4f}")
            x += 2 * r
        else:
            x += 1.0 + 0.25 * math.sin(i * 0.01)
            y = 10.0 * math.sin(i * 0.003)
            out.append(f"G1 X{x:.4f} Y{y:.4f}")
    out += ["G0 Z5", "M30"]
    return "\n".join(out) + "\n"


def best(func: Callable[[], object], repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "BIG.MPF"
        path.write_text(program(lines))
        sink = Path(tmp) / "out.txt"

        def read() -> None:
            for _ in interpret(path):
                pass

        def canon_text() -> None:
            with sink.open("w") as fh:
                for line in canon.write_text(interpret(path)):
                    fh.write(line + "\n")

        def convert() -> None:
            with sink.open("w") as fh:
                text = write(interpret(path), "rs274ngc", WriterOptions(), ConversionReport())
                for line in text:
                    fh.write(line + "\n")

        ngc = Path(tmp) / "big.ngc"
        ngc.write_text(
            program(lines).replace("CR=", "R").replace("G710", "G21").replace("M30", "M2")
        )

        def read_ngc() -> None:
            for _ in interpret_ngc(ngc, InterpreterOptions(fast_lane=False)):
                pass

        t_read, t_canon, t_convert = best(read), best(canon_text), best(convert)
        t_ngc = best(read_ngc)
    print(f"{lines} lines of G1/G2 (CR=) blocks")
    print(f"reader alone     {t_read:7.2f} s  {lines / t_read:9.0f} lines/s")
    print(f"canon (+ text)   {t_canon:7.2f} s  {lines / t_canon:9.0f} lines/s")
    print(f"convert to ngc   {t_convert:7.2f} s  {lines / t_convert:9.0f} lines/s")
    print(f"convert / canon  {t_convert / t_canon:7.2f}")
    print(f"NGC interpreter  {t_ngc:7.2f} s  {lines / t_ngc:9.0f} lines/s (same moves)")


if __name__ == "__main__":
    main()
