"""Interpreter speed on every program shape: ``cnc canon`` against LinuxCNC's ``rs274``.

Issue 22: the plain-line benchmark (bench/bench_interp.py) is one shape among many. This
suite generates the shapes users have (plain CAM lines, arcs every 5th and every 2nd block
in R and centre format, O-word subroutine calls, parameter- and expression-heavy code,
cutter compensation on a long contour, a canned-cycle drilling grid) and takes five real
public CAM programs from tests/realworld/ngc, runs ``cnc canon`` and ``rs274`` on each in the
same run, and prints one table.

Each figure is the CPU time (user + system) of the whole process, start-up included, best
of ``--repeat`` runs: CPU time rather than wall time because the machine may be shared, and
the best run because other load only ever adds time. The ratio is ours / rs274 (<= 1.0
means we are at least as fast). Both write their canonical text to a file. Run by hand::

    python bench/bench_shapes.py [--lines 200000] [--repeat 3] [--only arcs]
"""

from __future__ import annotations

import argparse
import math
import resource
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
REALWORLD = ROOT / "tests" / "realworld" / "ngc"
TOOL_TABLE = REALWORLD / "tools.tbl"
#: five real public CAM programs (tests/realworld/SOURCES.md), 50 KB to the suite's largest
REAL_PROGRAMS = (
    "camotics__tiny_cat_outline.ngc",
    "ugs__ShapeOko_Calibration_Pattern_01b.ngc",
    "ugs__enclosure.nc",
    "lcnc__3D_Chips.ngc",
    "ugs__communicator.nc",
)

HEADER = ("%", "G21 G90 G17 G94 G40 G49 G80", "T1 M6", "S12000 M3", "G0 X0 Y0 Z5", "G1 Z-1 F300")
FOOTER = ("G0 Z5", "M5", "M2", "%")


def plain(n: int) -> Iterator[str]:
    """``n`` feed lines of a zig-zag surfacing pass, ``X.. Y.. Z..`` only."""
    yield from HEADER
    x = 0.0
    for i in range(n):
        x += 0.5 + (i * 7919 % 1000) / 1000.0
        yield f"X{x:.4f} Y{20.0 * math.sin(i / 40.0):.4f} Z{-1.0 - (i % 5) * 0.04:.4f}"
    yield from FOOTER


def arcs(n: int, every: int, radius_format: bool) -> Iterator[str]:
    """``n`` blocks with an arc every ``every``-th block: a quarter circle in R format or a
    half circle in centre (I J) format, alternating G2 and G3; lines between them."""
    yield from HEADER
    x = y = 0.0
    for i in range(n):
        if i % every == every - 1:
            r = 2.0 + (i % 7) * 0.25
            g = "G2" if (i // every) % 2 else "G3"
            if radius_format:
                sign = -1.0 if g == "G2" else 1.0
                x, y = x + r, y + sign * r
                yield f"{g} X{x:.4f} Y{y:.4f} R{r:.4f}"
            else:
                x += 2 * r
                yield f"{g} X{x:.4f} Y{y:.4f} I{r:.4f} J0"
        else:
            x += 0.5 + (i * 7919 % 1000) / 1000.0
            y = 20.0 * math.sin(i / 40.0)
            yield f"G1 X{x:.4f} Y{y:.4f}"
    yield from FOOTER


def subroutines(n: int) -> Iterator[str]:
    """A four-line O-word subroutine called ``n`` times with two arguments each."""
    yield from HEADER[:-1]
    yield "o100 sub"
    yield "G1 X#1 Y#2 F300"
    yield "G1 X[#1 + 1] Y#2"
    yield "G1 X[#1 + 1] Y[#2 + 1]"
    yield "o100 endsub"
    for i in range(n):
        yield f"o100 call [{i % 100 * 2}] [{i // 100 * 2}]"
    yield from FOOTER


def expressions(n: int) -> Iterator[str]:
    """Macro-style code: assignments with arithmetic and functions feeding the moves."""
    yield from HEADER
    yield "#1 = 0"
    yield "#2 = 0.5"
    for i in range(n // 3):
        yield f"#1 = [#1 + #2 * {1 + i % 3}]"
        yield "#3 = [SIN[#1 * 10] * 20 + ABS[COS[#1]] / 2]"
        yield "G1 X[#1] Y[#3] Z[-1 - [#3 MOD 1] / 10]"
    yield from FOOTER


def cutter_comp(n: int) -> Iterator[str]:
    """G42 around a 200-sided polygon (inches, tool 1), lap after lap: ``n`` moves."""
    yield "%"
    yield "G20 G90 G17 G94 G40 G49 G80"
    yield "T1 M6"
    yield "S12000 M3"
    yield "G0 X3 Y0 Z0.2"
    yield "G1 Z-0.1 F30"
    yield "G42 G1 X2 Y0"
    sides = 200
    for i in range(1, n + 1):
        a = 2 * math.pi * (i % sides) / sides
        yield f"X{2 * math.cos(a):.4f} Y{2 * math.sin(a):.4f}"
    yield "G40 G1 X3 Y0"
    yield from FOOTER


def drilling(n: int) -> Iterator[str]:
    """A grid of ``n`` holes: G81 and G83 peck drilling in alternate rows."""
    yield from HEADER[:-1]
    per_row = 100
    for i in range(n):
        row, col = divmod(i, per_row)
        if col == 0:
            cycle = "G81" if row % 2 == 0 else "G83 Q0.5"
            yield f"{cycle} X0 Y{row * 5} Z-3 R1 F200"
        else:
            yield f"X{col * 5} Y{row * 5}"
    yield "G80"
    yield from FOOTER


def shapes(lines: int) -> list[tuple[str, Callable[[], Iterator[str]]]]:
    """The generated shapes at the requested size (O-word calls and drill holes are fixed
    counts: 2,000 calls, 10,000 holes)."""
    return [
        (f"plain lines ({lines // 1000}k)", lambda: plain(lines)),
        (f"arc every 5th, R ({lines // 1000}k)", lambda: arcs(lines, 5, True)),
        (f"arc every 5th, IJ ({lines // 1000}k)", lambda: arcs(lines, 5, False)),
        (f"arc every 2nd, R ({lines // 1000}k)", lambda: arcs(lines, 2, True)),
        (f"arc every 2nd, IJ ({lines // 1000}k)", lambda: arcs(lines, 2, False)),
        ("2,000 O-word calls", lambda: subroutines(2000)),
        (f"expressions ({lines // 10000}k)", lambda: expressions(lines // 10)),
        (f"cutter comp G42 ({lines // 10000}k)", lambda: cutter_comp(lines // 10)),
        ("drilling grid (10k holes)", lambda: drilling(10000)),
    ]


def cpu_of(repeat: int, cmd: list[str], cwd: Path) -> float:
    """Best CPU time (user + system, seconds) of ``repeat`` runs of ``cmd``.

    rs274 occasionally dies with SIGBUS when other copies share its tool table: a failed
    run is retried up to three times."""
    best = math.inf
    for _ in range(repeat):
        for attempt in range(3):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            proc = subprocess.run(cmd, cwd=cwd, capture_output=True)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            if proc.returncode == 0:
                break
            if attempt == 2:
                raise RuntimeError(f"{cmd[0]} failed: {proc.stderr.decode()[-300:]}")
        used = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        best = min(best, used)
    return best


def measure(name: str, program: Path, tmp: Path, repeat: int) -> tuple[str, int, float, float]:
    """(name, size in bytes, our CPU seconds, rs274's) for one program."""
    ours = [sys.executable, "-m", "cli.main", "canon", str(program)]
    ours += ["-o", str(tmp / "ours.canon"), "--force", "--tool-table", str(TOOL_TABLE)]
    rs = ["rs274", "-t", str(TOOL_TABLE), "-g", str(program), str(tmp / "rs.canon")]
    t_ours = cpu_of(repeat, ours, ROOT)
    t_rs = cpu_of(repeat, rs, tmp) if shutil.which("rs274") else math.nan
    return name, program.stat().st_size, t_ours, t_rs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=200_000, help="size of the line shapes")
    parser.add_argument("--repeat", type=int, default=3, help="runs per program (best kept)")
    parser.add_argument("--only", default="", help="only the rows whose name contains this")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        two = tmp / "two.ngc"
        two.write_text("G1 X1 Y2 F100\nM2\n")
        programs: list[tuple[str, Path]] = [("2-line program (start-up)", two)]
        for name, lines in shapes(args.lines):
            path = tmp / f"shape{len(programs)}.ngc"
            path.write_text("\n".join(lines()) + "\n")
            programs.append((name, path))
        programs += [(f"real: {p}", REALWORLD / p) for p in REAL_PROGRAMS]
        rows = [
            measure(name, path, tmp, args.repeat) for name, path in programs if args.only in name
        ]
    print("| program | size | `cnc canon` CPU s | `rs274` CPU s | ratio |")
    print("| --- | --- | --- | --- | --- |")
    for name, size, ours, rs in rows:
        size_text = f"{size / 1e6:.2f} MB" if size >= 1e6 else f"{size / 1e3:.0f} KB"
        print(f"| {name} | {size_text} | {ours:.2f} | {rs:.2f} | {ours / rs:.2f} |")


if __name__ == "__main__":
    main()
