"""Convert speed: a 200,000-line program converted FROM one dialect TO another vs ``cnc canon``.

Issue 7 asks that converting a 200,000-line program between any two dialects take within
2x of ``cnc canon`` on the same file. For each FROM dialect with a reader installed
(:func:`gcode.registry.readable`; readers still being written are skipped) the generated
CAM-like program (G1 zig-zags with an R arc every fifth block) is written in FROM by our
writer; then, in this process and on that file:

* ``canon`` does what ``cnc canon FILE --dialect FROM -o OUT`` does, through the command's
  own functions (cli/canon.py ``file_chunks``: the RS274/NGC interpreter's chunks, arcs
  included, with the compiled fast-lane formatter for rs274ngc, the FROM reader's commands
  otherwise; canonical text written in large blocks);
* ``convert`` does what ``cnc convert FILE --from FROM --to TO -o OUT`` does (cli/convert.py:
  the FROM reader's IR through the TO writer's text chunks (``gcode.write.writer.write_text``), and
  one note formatted per conversion-report entry, as the CLI prints them).

Each pair is timed back to back, ``--repeat`` times (5), the two sides interleaved (canon,
convert, canon, convert, ...) so that a burst of load from other processes falls on both;
printed are the best wall seconds of each side, the median wall ratio, and the CPU-time
ratio: the best (smallest) CPU seconds of convert over the best of canon
(``time.process_time``: this process only). Load only ever adds time, so each side's
minimum is its figure least disturbed by other processes; a ratio of two ~0.1 s figures
is otherwise decided by the noise. With ``--cli`` the two sides are the installed commands
themselves, run as child processes (``cnc canon FILE --dialect FROM -o OUT`` and ``cnc
convert FILE --from FROM --to TO -o OUT --force``, notes to a file): start-up included, CPU
time of the child. ``--to`` and ``--from`` take a dialect, a comma-separated list, or
``all``.

    python bench/convert_bench.py [LINES] [--from D|all] [--to D|all] [--shape mill|lathe|cam]
                                  [--cli] [--no-verify] [--repeat N]
"""

from __future__ import annotations

import argparse
import math
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from cli.canon import _options as canon_options
from cli.canon import _write as canon_write
from cli.canon import file_chunks
from cli.verify import Recorder, Verification, reader_options, verified_output
from gcode import readers, registry
from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.registry import NAMES, get_dialect
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write, write_text
from kernel.diagnostics import Diagnostic, DiagnosticRecord, Location, Severity

REPEATS = 5
SUFFIX = {
    "fanuc": ".nc",
    "fanuc_lathe": ".nc",
    "haas": ".nc",
    "grbl": ".gcode",
    "siemens840d": ".mpf",
    "sandia": ".txt",
}


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


def lathe_program(lines: int) -> str:
    """Turning passes in the ZX plane (G18): feeds along Z and X with a G2/G3 radius every
    fifth block, absolute mm, per-minute feed (every target can state it)."""
    out = ["G21 G90 G18 G94", "F300 S1200 M3", "G0 X30 Z2", "G1 Z0"]
    x, z = 30.0, 0.0
    for i in range(lines - 6):
        if i % 5 == 4:
            r = 1.0 + (i % 7) * 0.1
            code = "G2" if i % 2 else "G3"
            out.append(f"{code} X{x:.4f} Z{z - 2 * r:.4f} R{1.2 * r:.4f}")
            z -= 2 * r
        else:
            z -= 0.5 + 0.1 * math.sin(i * 0.01)
            x = 20.0 + 5.0 * math.sin(i * 0.003)
            out.append(f"G1 X{x:.4f} Z{z:.4f}")
        if z < -400.0:
            out += ["G0 X35", "G0 Z0", f"G0 X{x:.4f}"]  # back to the start of the next pass
            z = 0.0
    out += ["G0 X40", "M2"]
    return "\n".join(out[: lines - 1] + ["M2"]) + "\n"


def source_file(folder: Path, lines: int, dialect: str, shape: str = "mill") -> Path:
    """The generated program written in ``dialect`` (by our writer unless RS274/NGC)."""
    ngc = folder / "big.ngc"
    if not ngc.exists():
        if shape == "cam":
            sys.path.insert(0, str(Path(__file__).resolve().parent))
            from cam_program import cam_lines

            ngc.write_text("\n".join(cam_lines(lines)) + "\n")
        else:
            ngc.write_text(program(lines) if shape == "mill" else lathe_program(lines))
    if dialect == "rs274ngc":
        return ngc
    path = folder / f"big_{dialect}{SUFFIX.get(dialect, '.ngc')}"
    with open(path, "w") as fh:
        for line in write(interpret(ngc), dialect, WriterOptions(), ConversionReport()):
            fh.write(line + "\n")
    return path


def canon_run(path: Path, dialect: str, sink: Path) -> None:
    """``cnc canon PATH --dialect DIALECT -o SINK``: the command's own options and reading
    (cli.canon.file_chunks: RS274/NGC's fast lane with arcs) and its text writer."""
    options = canon_options(None, None, (str(path.parent),), False)
    with open(sink, "w", encoding="utf-8") as fh:
        canon_write(file_chunks(str(path), dialect, options), str(path), "text", True, fh)


def convert_run(
    path: Path, src: str, dst: str, sink: Path, notes: Path, verify: bool = True
) -> None:
    """``cnc convert PATH --from SRC --to DST -o SINK`` (notes: the CLI's stderr), with the
    CLI's defaults: cycles kept, cutter compensation kept where the target has it, register
    marks, and the output read back and compared with the source (``verify``, as the CLI
    does without ``--no-verify``: cli.verify)."""
    target = get_dialect(dst)
    keep_comp = target.has_cutter_comp
    options = InterpreterOptions(
        search_path=(str(path.parent),),
        cycle_marks=True,
        keep_cutter_comp=keep_comp,
        register_marks=True,
    )
    report = ConversionReport(source_dialect=src, target_dialect=dst)
    ir = readers.read_chunks(path, src, options, arcs=src == "rs274ngc")
    writer = WriterOptions(cycles="keep")
    if verify:
        recorder = Recorder(ir, str(path))
        chunks = write_text(recorder, target, writer, report, source=str(path))
        back = reader_options(str(path), None, True, keep_comp)
        chunks = verified_output(chunks, recorder, target, back, writer, report, Verification())
    else:
        chunks = write_text(ir, target, writer, report, source=str(path))
    with open(sink, "w", encoding="utf-8", newline="\n") as fh:
        fh.writelines(chunks)
    with open(notes, "w") as err:
        for change in report.changes:
            rec = DiagnosticRecord(
                change.code,
                f"{change.kind}: {change.message}",
                change.source or Location(str(path)),
                Severity.NOTE,
            )
            err.write(rec.format() + "\n")


def timed(func: Callable[[], None]) -> tuple[float, float]:
    """(wall seconds, CPU seconds of this process)."""
    wall, cpu = time.perf_counter(), time.process_time()
    func()
    return time.perf_counter() - wall, time.process_time() - cpu


def command_timed(args: list[str], notes: Path) -> tuple[float, float]:
    """(wall seconds, CPU seconds) of the command ``args`` run as a child process; its
    standard error goes to ``notes``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter()
    with open(notes, "w") as err:
        subprocess.run(args, stdout=subprocess.DEVNULL, stderr=err, check=True)
    wall = time.perf_counter() - wall
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def cli_pair(
    path: Path, src: str, dst: str, sink: Path, notes: Path
) -> tuple[Callable[[], tuple[float, float]], Callable[[], tuple[float, float]]]:
    """(canon, convert) as the commands a user types, each timed as a child process."""
    canon = ["cnc", "canon", str(path), "--dialect", src, "-o", str(sink), "--force"]
    convert = ["cnc", "convert", str(path), "--from", src, "--to", dst, "-o", str(sink)]
    return (
        lambda: command_timed(canon, notes),
        lambda: command_timed([*convert, "--force"], notes),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("lines", nargs="?", type=int, default=200_000)
    parser.add_argument("--from", dest="src", default="rs274ngc", help="dialect or 'all'")
    parser.add_argument("--to", dest="dst", default="all", help="dialect or 'all'")
    parser.add_argument(
        "--shape",
        choices=("mill", "lathe", "cam"),
        default="mill",
        help="the generated program: XY milling with an R arc every fifth block, ZX turning "
        "(for the lathe dialect), or bench/cam_program.py's plain CAM lines (an arc every 50)",
    )
    parser.add_argument(
        "--cli", action="store_true", help="time the cnc commands as child processes instead"
    )
    parser.add_argument(
        "--no-verify",
        action="store_true",
        help="convert without reading the output back (cnc convert --no-verify)",
    )
    parser.add_argument(
        "--repeat",
        type=int,
        default=REPEATS,
        help=f"interleaved (canon, convert) pairs per target; each side's best counts "
        f"(default {REPEATS})",
    )
    args = parser.parse_args()
    verify = not args.no_verify
    repeats = max(args.repeat, 1)
    readable = registry.readable()
    sources = readable if args.src == "all" else tuple(args.src.split(","))
    targets = NAMES if args.dst == "all" else tuple(args.dst.split(","))
    print(f"{args.lines} lines; readers installed: {', '.join(readable)}")
    print(f"  wall: best s of {repeats} interleaved pairs, ratio = median of convert/canon")
    print(
        "  cpu: CPU seconds of "
        + ("the cnc commands (child processes)" if args.cli else "this process")
        + ", ratio = best convert / best canon (each side's least disturbed run)"
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        sink, notes = folder / "out.txt", folder / "notes.txt"
        for src in sources:
            if src not in readable:
                print(f"  from {src}: no reader installed, skipped")
                continue
            try:
                path = source_file(folder, args.lines, src, args.shape)
            except Diagnostic as exc:  # a lathe has no Y axis for this milling program
                print(f"from {src}: cannot state the program ({exc.code}), skipped")
                continue
            with open(path, "rb") as fh:
                count = sum(1 for _ in fh)
            print(f"from {src}: {path.name}, {count} lines")
            for dst in targets:
                try:
                    convert_run(path, src, dst, sink, notes, verify)  # warm-up, and refusals
                except Diagnostic as exc:
                    print(f"  to {dst:12s} refused ({exc.code}), skipped")
                    continue
                pairs = []
                for _ in range(repeats):
                    if args.cli:
                        run_canon, run_convert = cli_pair(path, src, dst, sink, notes)
                        base, conv = run_canon(), run_convert()
                    else:
                        base = timed(lambda p=path, s=src: canon_run(p, s, sink))
                        conv = timed(
                            lambda p=path, s=src, d=dst: convert_run(p, s, d, sink, notes, verify)
                        )
                    pairs.append((conv, base))
                wall = statistics.median(c[0] / b[0] for c, b in pairs)
                best_c = min(c[0] for c, _ in pairs)
                best_b = min(b[0] for _, b in pairs)
                cpu_c = min(c[1] for c, _ in pairs)
                cpu_b = min(b[1] for _, b in pairs)
                cpu = cpu_c / cpu_b
                print(
                    f"  to {dst:12s} convert {best_c:6.2f} s  canon {best_b:6.2f} s  "
                    f"wall ratio {wall:4.2f}  cpu ratio {cpu:4.2f} ({cpu_c:.3f} / {cpu_b:.3f} s)"
                )


if __name__ == "__main__":
    main()
