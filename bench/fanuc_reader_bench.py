"""Fanuc reader speed: lines/s on a 200,000-line program of G01/G02/G03 moves, and
``convert --from fanuc --to rs274ngc`` vs reading to canonical text (in-process).

The program is the mix of ``bench/convert_bench.py`` written the Fanuc way (two-digit
codes, decimal points, an O-number frame). Prints the best of three runs of each.

    python bench/fanuc_reader_bench.py [LINES]
"""

from __future__ import annotations

import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

from gcode.fanuc.reader import interpret
from gcode.ngc import interpreter
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.ir import canon


def program(lines: int) -> str:
    """G01 zig-zags with a G02/G03 R arc every fifth block, absolute mm."""
    out = ["%", "O1000", "G21 G90 G17 G94", "F600. S8000 M03", "G00 X0. Y0. Z1.", "G01 Z-0.5"]
    x = y = 0.0
    for i in range(lines - 8):
        if i % 5 == 4:
            r = 2.0 + (i % 7) * 0.1
            code = "G02" if i % 2 else "G03"
            out.append(f"{code} X{x + 2 * r:.3f} Y{y:.3f} R{r:.3f}")
            x += 2 * r
        else:
            x += 1.0 + 0.25 * math.sin(i * 0.01)
            y = 10.0 * math.sin(i * 0.003)
            out.append(f"G01 X{x:.3f} Y{y:.3f}")
    out += ["G00 Z5.", "M30", "%"]
    return "\n".join(out) + "\n"


def timed(func) -> float:  # noqa: ANN001
    start = time.perf_counter()
    func()
    return time.perf_counter() - start


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.nc"
        path.write_text(program(lines))
        sink = Path(tmp) / "out.txt"

        def canon_run() -> None:
            with open(sink, "w") as fh:
                for line in canon.write_text(interpret(path)):
                    fh.write(line + "\n")

        def convert_run() -> None:
            with open(sink, "w") as fh:
                for line in write(interpret(path), "rs274ngc", WriterOptions(), ConversionReport()):
                    fh.write(line + "\n")

        def read_only() -> None:
            for _ in interpret(path):
                pass

        ngc = Path(tmp) / "big.ngc"  # the same moves for the RS274/NGC reader, for scale
        ngc.write_text("%\n" + "\n".join(program(lines).splitlines()[2:-2]) + "\nM2\n%\n")
        options = interpreter.InterpreterOptions(fast_lane=False)

        def read_ngc() -> None:
            for _ in interpreter.interpret(ngc, options):
                pass

        read = min(timed(read_only) for _ in range(3))
        base = min(timed(read_ngc) for _ in range(3))
        pairs = [(timed(convert_run), timed(canon_run)) for _ in range(3)]
        ratio = statistics.median(c / b for c, b in pairs)
        print(f"{lines} lines: read {read:.2f} s = {lines / read:,.0f} lines/s")
        print(f"  RS274/NGC reader on the same moves (no fast lane): {lines / base:,.0f} lines/s")
        print(
            f"  canon text {min(b for _, b in pairs):.2f} s, convert to rs274ngc "
            f"{min(c for c, _ in pairs):.2f} s, ratio {ratio:.2f}"
        )


if __name__ == "__main__":
    main()
