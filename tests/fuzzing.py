"""The fuzzing harness (issue 19): structure-aware program generators per dialect, mutation
of every golden and real program, and a worker process that runs each case under CPU and
memory limits and sorts failures by exception type and innermost frame.

A case is ``(dialect, text)``; ``dialect`` is a G-code dialect of :mod:`gcode.registry`,
``"stepnc"`` (Part 21 text) or ``"canon"`` (canonical text). It passes when reading it (and,
for a sample, planning it) finishes or raises a :class:`kernel.diagnostics.Diagnostic` with a
code and a line inside the program; anything else (another exception, more than the CPU
limit, more than the memory limit, a dead worker) is a failure, keyed by
``(kind, innermost project frame)`` so that one bug found a thousand times is one entry.

Used by tests/test_fuzz.py (a fast sample by default, the full runs marked ``slow``) and by
hand: ``python -m tests.fuzzing rs274ngc 10000`` prints the failures found.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing as mp
import os
import random
import re
import resource
import signal
import sys
import tempfile
import time
import traceback
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from multiprocessing.connection import Connection
from pathlib import Path
from types import FrameType

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
#: per-case limits of the issue's done-when clause
CPU_SECONDS = 10.0
MEMORY_BYTES = 1 << 30
#: a generated loop may legitimately run long: reading stops after this many commands
MAX_COMMANDS = 20_000
#: loop passes in a row (kernel.limits loop_passes) in reader cases
LOOP_PASSES = 2_000
#: cnc check's CPU budget per program in CLI cases (--limit seconds)
CLI_SECONDS = 5.0

GCODE_DIALECTS = (
    "rs274ngc", "nist_v3", "grbl", "mach3", "fanuc", "fanuc_lathe", "haas", "haas_lathe",
)  # fmt: skip
DIALECTS = (*GCODE_DIALECTS, "siemens840d", "sandia", "stepnc", "canon")

# ------------------------------------------------------------------------------ corpus


def corpus(dialect: str) -> list[str]:
    """The golden and real programs of ``dialect`` (the mutation seeds)."""
    globs: dict[str, list[tuple[Path, str]]] = {
        "rs274ngc": [
            (HERE / "golden" / "ngc", "*.ngc"),
            (HERE / "golden" / "ngc_errors", "*.ngc"),
            (HERE / "data" / "corpus" / "ngc", "*.ngc"),
        ],
        "fanuc": [(HERE / "dialects" / "fanuc", "*.nc")],
        "mach3": [(HERE / "dialects" / "mach3", "*")],
        "siemens840d": [(HERE / "dialects" / "siemens840d", "*")],
        "sandia": [(HERE / "dialects" / "sandia", "*")],
        "stepnc": [(HERE / "stepnc", "*.stp")],
        "canon": [(HERE / "golden" / "ngc", "*.canon")],
    }
    family = {
        "nist_v3": "rs274ngc",
        "grbl": "rs274ngc",
        "fanuc_lathe": "fanuc",
        "haas": "fanuc",
        "haas_lathe": "fanuc",
    }
    out = []
    for folder, pattern in globs[family.get(dialect, dialect)]:
        for p in sorted(folder.glob(pattern)):
            if (
                p.is_file()
                and p.suffix not in (".canon", ".md", ".json", ".tbl", ".txt")
                or (dialect == "canon" and p.suffix == ".canon")
            ):
                try:
                    out.append(p.read_text(encoding="utf-8", errors="replace")[:200_000])
                except OSError:
                    continue
    return out


# -------------------------------------------------------------------------- generators

HOSTILE_NUMBERS = (
    "9" * 150,
    "1." + "0" * 120 + "1",
    "1e308",
    "0.0000001",
    "-0",
    "99999999",
    "1000000000",
    "nan",
    "inf",
    "-1",
    "0",
)


NGC_G = ("17", "18", "19", "20", "21", "90", "91", "40", "41", "42", "43", "49", "54", "92")
NGC_G += ("5.2", "5.3", "33", "76", "61", "64", "93", "94", "95")
NGC_M = ("3", "4", "5", "6", "0", "1", "2", "30", "98", "99", "66", "62")
FANUC_G = ("68", "69", "51", "50", "16", "15", "43", "41", "40")


def _num(r: random.Random) -> str:
    roll = r.random()
    if roll < 0.04:
        return r.choice(HOSTILE_NUMBERS)
    if roll < 0.3:
        return str(r.randint(-20, 100))
    return f"{r.uniform(-200, 200):.{r.randint(0, 5)}f}"


def _nested(r: random.Random, open_: str, close: str, inner: str) -> str:
    depth = r.choice((1, 2, 5, 30, 70, 300)) if r.random() < 0.1 else r.randint(1, 4)
    return open_ * depth + inner + close * depth


def _ngc_expr(r: random.Random, depth: int = 0) -> str:
    roll = r.random()
    if depth > 3 or roll < 0.3:
        return r.choice((_num(r), f"#{r.randint(1, 40)}", "#<a>", "#<_x>", "#5220"))
    if roll < 0.6:
        op = r.choice(("+", "-", "*", "/", "MOD", "**", "EQ", "LT", "AND", "OR"))
        return f"[{_ngc_expr(r, depth + 1)} {op} {_ngc_expr(r, depth + 1)}]"
    if roll < 0.8:
        fn = r.choice(("SIN", "COS", "SQRT", "ABS", "FIX", "ROUND", "LN", "EXP", "ACOS"))
        return f"{fn}[{_ngc_expr(r, depth + 1)}]"
    if roll < 0.9:
        return _nested(r, "[", "]", _ngc_expr(r, depth + 1))
    return f"ATAN[{_ngc_expr(r, depth + 1)}]/[{_ngc_expr(r, depth + 1)}]"


def _ngc_value(r: random.Random) -> str:
    return _num(r) if r.random() < 0.7 else _ngc_expr(r)


def _ngc_line(r: random.Random, labels: list[int]) -> str:
    roll = r.random()
    if roll < 0.35:
        g = r.choice(("G0", "G1", "G2", "G3", "G1", "G0"))
        words = [g] + [f"{a}{_ngc_value(r)}" for a in r.sample("XYZIJKR", r.randint(1, 3))]
        if r.random() < 0.5:
            words.append(f"F{abs(float(r.randint(1, 3000)))}")
        if g in ("G2", "G3") and r.random() < 0.1:
            words.append(f"P{r.choice(('2', '1000000000', '0'))}")
        return " ".join(words)
    if roll < 0.45:
        cyc = r.choice(("G81", "G82", "G83", "G73", "G85", "G89", "G84", "G86"))
        return (
            f"{cyc} X{_num(r)} Y{_num(r)} Z{_num(r)} R{_num(r)} Q{_num(r)} P{_num(r)} "
            f"L{r.choice(('1', '3', '1000000000', _num(r)))} F100"
        )
    if roll < 0.55:
        return f"#{r.randint(1, 40)} = {_ngc_expr(r)}"
    if roll < 0.65:
        n = r.randint(100, 105)
        labels.append(n)
        kind = r.choice(("while", "if", "repeat", "do"))
        if kind == "while":
            return f"o{n} while [{_ngc_expr(r)}]\nG1 X{_num(r)}\no{n} endwhile"
        if kind == "if":
            return f"o{n} if [{_ngc_expr(r)}]\nG0 X1\no{n} else\nG0 X2\no{n} endif"
        if kind == "repeat":
            return f"o{n} repeat [{r.choice(('3', '1000000', _num(r)))}]\nG1 X1\no{n} endrepeat"
        return f"o{n} do\n#1=[#1+1]\no{n} while [#1 LT {r.randint(0, 50)}]"
    if roll < 0.7:
        name = r.choice(("s", "../x", "/etc/passwd", "sub"))
        return f"o<{name}> call [{_num(r)}]"
    if roll < 0.75:
        return f"G{r.choice(NGC_G)} X{_num(r)}"
    if roll < 0.8:
        return f"M{r.choice(NGC_M)} S{_num(r)} T{r.randint(0, 5)}"
    if roll < 0.85:
        return f"({r.choice(('MSG', 'DEBUG', 'PRINT', 'comment'))},{_num(r)})"
    if roll < 0.9:
        return f"N{r.randint(0, 99999)} {_ngc_line(r, labels)}"
    return " ".join(f"{r.choice('GMXYZFSTPQRIJKLDH')}{_ngc_value(r)}" for _ in range(3))


def gen_ngc(r: random.Random) -> str:
    """A structured RS274/NGC program: units, moves, expressions, O-word flow, cycles."""
    labels: list[int] = []
    head = r.choice(("G21 G90 G17", "G20 G91", "G21 G90 G54 G64 P0.01", ""))
    body = [_ngc_line(r, labels) for _ in range(r.randint(1, 25))]
    if r.random() < 0.2:
        body.insert(0, "o<s> sub\nG1 X#1 F100\no<s> endsub")
    return "\n".join([head, "S1000 M3", *body, r.choice(("M2", "M30", "%", ""))]) + "\n"


def _fanuc_expr(r: random.Random, depth: int = 0) -> str:
    roll = r.random()
    if depth > 3 or roll < 0.3:
        return r.choice((_num(r), f"#{r.randint(1, 40)}", "#0", "#4001", "#5001"))
    if roll < 0.6:
        op = r.choice(("+", "-", "*", "/", "MOD", "EQ", "NE", "GT", "AND", "OR"))
        return f"{_fanuc_expr(r, depth + 1)}{op}{_fanuc_expr(r, depth + 1)}"
    if roll < 0.8:
        fn = r.choice(("SIN", "COS", "SQRT", "ABS", "FIX", "FUP", "ROUND", "LN", "EXP"))
        return f"{fn}[{_fanuc_expr(r, depth + 1)}]"
    return _nested(r, "[", "]", _fanuc_expr(r, depth + 1))


def gen_fanuc(r: random.Random) -> str:
    """A structured Fanuc program: O frame, macro B, WHILE/IF/GOTO, M98/G65, cycles."""
    lines = ["%", f"O{r.randint(1, 9999):04d}", r.choice(("G21 G90 G17", "G20 G91", "G21"))]
    for _ in range(r.randint(1, 25)):
        roll = r.random()
        if roll < 0.35:
            g = r.choice(("G00", "G01", "G02", "G03"))
            words = " ".join(f"{a}{_num(r)}" for a in r.sample("XYZIJKR", r.randint(1, 3)))
            lines.append(f"{g} {words} F{r.randint(1, 3000)}.")
        elif roll < 0.45:
            cyc = r.choice(("G81", "G82", "G83", "G73", "G76", "G84", "G85"))
            lines.append(
                f"{cyc} X{_num(r)} Y{_num(r)} Z{_num(r)} R{_num(r)} Q{_num(r)} "
                f"K{r.choice(('1', '9999', _num(r)))} F100."
            )
        elif roll < 0.6:
            lines.append(f"#{r.randint(1, 40)}={_fanuc_expr(r)}")
        elif roll < 0.7:
            m = r.randint(1, 9)
            lines += [f"WHILE[{_fanuc_expr(r)}]DO{m}", f"G01 X{_num(r)}", f"END{m}"]
        elif roll < 0.75:
            lines.append(f"IF[{_fanuc_expr(r)}]GOTO{r.randint(1, 200)}")
        elif roll < 0.8:
            lines.append(f"N{r.randint(1, 200)} G00 X{_num(r)}")
        elif roll < 0.85:
            lines.append(f"{r.choice(('M98', 'G65'))} P{r.randint(1, 9999)} L{_num(r)} A{_num(r)}")
        elif roll < 0.9:
            lines.append(f"G{r.choice(FANUC_G)} X{_num(r)} R{_num(r)} H1 D1")
        else:
            lines.append(" ".join(f"{r.choice('GMXYZFSTPQRIJKLDH#')}{_num(r)}" for _ in range(3)))
    lines += ["M30", "%"]
    return "\n".join(lines) + "\n"


def gen_siemens(r: random.Random) -> str:
    """A structured Siemens 840D program: R parameters, DEF, IF/WHILE/LOOP/FOR, GOTO."""
    lines = [r.choice(("G71 G90 G17", "G70 G91", "G710"))]
    for _ in range(r.randint(1, 25)):
        roll = r.random()
        if roll < 0.35:
            g = r.choice(("G0", "G1", "G2", "G3"))
            words = " ".join(f"{a}={_num(r)}" for a in r.sample(["X", "Y", "Z", "I", "J", "CR"], 2))
            lines.append(f"{g} {words} F{r.randint(1, 3000)}")
        elif roll < 0.5:
            inner = _nested(r, "(", ")", f"R{r.randint(1, 20)}+{_num(r)}")
            lines.append(f"R{r.randint(1, 20)}={inner}")
        elif roll < 0.6:
            lines += [f"WHILE R{r.randint(1, 5)}<{_num(r)}", f"G1 X={_num(r)}", "ENDWHILE"]
        elif roll < 0.65:
            lines += ["DEF INT I", f"FOR I=1 TO {r.choice(('3', '1000000000', _num(r)))}", "ENDFOR"]
        elif roll < 0.7:
            lines += [f"IF R1>{_num(r)}", "G0 X1", "ELSE", "G0 X2", "ENDIF"]
        elif roll < 0.75:
            lines.append(f"GOTO{r.choice('FB')} L{r.randint(1, 20)}")
        elif roll < 0.8:
            lines.append(f"L{r.randint(1, 20)}: G0 X{_num(r)}")
        elif roll < 0.85:
            lines.append(f"CYCLE81({_num(r)},{_num(r)},{_num(r)},{_num(r)})")
        elif roll < 0.9:
            lines.append(f"TRANS X={_num(r)}")
        else:
            lines.append(" ".join(f"{r.choice('GMXYZFST')}{_num(r)}" for _ in range(3)))
    lines.append(r.choice(("M30", "M2", "M17", "")))
    return "\n".join(lines) + "\n"


def gen_words(r: random.Random) -> str:
    """Word soup for the dialects without a grammar of their own (Sandia)."""
    return (
        "\n".join(
            " ".join(f"{r.choice('GMXYZFSTNIJK')}{_num(r)}" for _ in range(r.randint(1, 5)))
            for _ in range(r.randint(1, 20))
        )
        + "\n"
    )


def gen_canon(r: random.Random) -> str:
    """Canonical text with odd arguments."""
    names = (
        "STRAIGHT_FEED",
        "STRAIGHT_TRAVERSE",
        "ARC_FEED",
        "SET_FEED_RATE",
        "DWELL",
        "NURBS_FEED",
        "CHANGE_TOOL",
        "USE_LENGTH_UNITS",
        "SELECT_PLANE",
    )
    out = []
    for i in range(r.randint(1, 20)):
        args = ", ".join(_num(r) for _ in range(r.randint(0, 9)))
        out.append(f"{i + 1:5d} N..... {r.choice(names)}({args})")
    return "\n".join(out) + "\n"


def gen_stepnc(r: random.Random) -> str:
    """A real STEP-NC program with numbers, references and lists changed."""
    seeds = _corpus_cache("stepnc")
    text = r.choice(seeds)
    lines = text.splitlines()
    for _ in range(r.randint(1, 6)):
        i = r.randrange(len(lines))
        line = lines[i]
        roll = r.random()
        if roll < 0.4:  # a number
            nums = list(re.finditer(r"-?\d+\.\d*", line))
            if nums:
                m = r.choice(nums)
                line = (
                    line[: m.start()]
                    + r.choice((*HOSTILE_NUMBERS, "0.0001", "1E9", "-5.0"))
                    + line[m.end() :]
                )
        elif roll < 0.6:  # a reference
            refs = list(re.finditer(r"#\d+", line))
            if refs:
                m = r.choice(refs)
                line = (
                    line[: m.start()]
                    + f"#{r.choice((1, 2, 3, 99999, r.randint(1, 150)))}"
                    + line[m.end() :]
                )
        elif roll < 0.7:
            line = line.replace("(", "((", 1).replace(")", "))", 1)
        elif roll < 0.8:
            line = line.replace(",", ",$,", 1)
        else:
            lines.insert(i, lines[r.randrange(len(lines))])
        lines[i] = line
    return "\n".join(lines) + "\n"


_CORPUS: dict[str, list[str]] = {}


def _corpus_cache(dialect: str) -> list[str]:
    if dialect not in _CORPUS:
        _CORPUS[dialect] = corpus(dialect) or ["\n"]
    return _CORPUS[dialect]


GENERATORS: dict[str, Callable[[random.Random], str]] = {
    "rs274ngc": gen_ngc,
    "nist_v3": gen_ngc,
    "grbl": gen_ngc,
    "mach3": gen_ngc,
    "fanuc": gen_fanuc,
    "fanuc_lathe": gen_fanuc,
    "haas": gen_fanuc,
    "haas_lathe": gen_fanuc,
    "siemens840d": gen_siemens,
    "sandia": gen_words,
    "stepnc": gen_stepnc,
    "canon": gen_canon,
}

HOSTILE_INSERTS = (
    "[" * 200 + "1" + "]" * 200,
    "(" * 200,
    "9" * 5000,
    "#" * 300 + "1",
    "-" * 300 + "1",
    "\x00",
    "\r",
    "\t",
    "%",
    "/",
    ";",
    "(",
    ")",
    "[",
    "]",
    "#",
    "=",
    "\n",
    "\xff",
    "G5.2",
    "L1000000000",
    "Q0.000001",
    "P1000000000",
)


def mutate(r: random.Random, text: str) -> str:
    """Byte-level and token-level mutations: flips, inserts of hostile tokens, deletions,
    duplicated and truncated lines."""
    for _ in range(r.randint(1, 6)):
        roll = r.random()
        i = r.randrange(len(text) + 1)
        if roll < 0.3:
            text = text[:i] + r.choice(HOSTILE_INSERTS) + text[i:]
        elif roll < 0.5 and text:
            text = text[:i] + chr(r.randrange(32, 127)) + text[i + 1 :]
        elif roll < 0.65 and text:
            text = text[:i] + text[i + r.randint(1, 20) :]
        elif roll < 0.8:
            lines = text.splitlines(keepends=True)
            if lines:
                j = r.randrange(len(lines))
                lines.insert(j, lines[r.randrange(len(lines))] * r.randint(1, 3))
                text = "".join(lines)
        elif roll < 0.9:
            text = text[:i]
        else:
            text = text[:i] + _num(r) + text[i:]
    return text


def case(dialect: str, seed: int) -> str:
    """Case ``seed`` of ``dialect``: half generated, half mutated corpus (both mutated at
    times), reproducible from the seed alone."""
    r = random.Random(f"{dialect}:{seed}")
    seeds = _corpus_cache(dialect)
    if r.random() < 0.5 and seeds:
        text = r.choice(seeds)
        if len(text) > 20_000:
            text = text[: r.randint(0, 20_000)]
        return mutate(r, text)
    text = GENERATORS[dialect](r)
    return mutate(r, text) if r.random() < 0.3 else text


# ------------------------------------------------------------------------------ running


def run_reader(dialect: str, text: str) -> int:
    """Read ``text`` as ``dialect`` into canonical commands; their count (at most
    :data:`MAX_COMMANDS`). Only Diagnostics may escape. A loop ends after
    :data:`LOOP_PASSES` passes in a row (the default budget is exercised through the CLI
    cases and tests/test_loop_guard.py): a generated endless loop then costs milliseconds."""
    import kernel.limits as limits

    limits.configure(loop_passes=LOOP_PASSES)
    try:
        return _read(dialect, text)
    finally:
        limits.reset()


def _read(dialect: str, text: str) -> int:
    """:func:`run_reader` under the limits it sets."""
    from kernel.ir import canon as ir

    if dialect == "stepnc":
        from stepnc.to_canon import canon_from_file

        with tempfile.NamedTemporaryFile("w", suffix=".stp", delete=False) as fh:
            fh.write(text)
        try:
            return sum(1 for _ in canon_from_file(fh.name, mode="nist"))
        finally:
            os.unlink(fh.name)
    if dialect == "canon":
        n = 0
        for tc in ir.read_text(text.splitlines(), "fuzz.canon"):
            ir.parse_command(tc, "fuzz.canon")
            n += 1
        return n
    from gcode.readers import read_text

    n = 0
    for n, _ in enumerate(read_text(text, dialect, "fuzz"), 1):
        if n >= MAX_COMMANDS:
            break
    return n


def run_cli(dialect: str, text: str) -> int:
    """``cnc check`` on ``text`` written to a file (the whole CLI path: reading, checking,
    planning rules); the exit code. Tracebacks are failures."""
    from click.testing import CliRunner

    import kernel.limits as limits
    from cli.main import cli

    suffix = {"stepnc": ".stp", "canon": ".canon", "siemens840d": ".mpf"}.get(dialect, ".ngc")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"fuzz{suffix}"
        path.write_text(text, encoding="utf-8", errors="replace")
        args = ["check", "-f", "json", str(path)]
        if dialect in GCODE_DIALECTS or dialect in ("siemens840d", "sandia"):
            args[1:1] = ["--dialect", dialect]
        # an endless loop that moves runs until LOOP-LIMIT (loop_passes): the batch
        # budget per program ends it first, as it would in a user's batch
        args[0:0] = ["--limit", f"seconds={CLI_SECONDS:g}"]
        try:
            res = CliRunner().invoke(cli, args, catch_exceptions=True)
        finally:
            limits.reset()
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        exc = res.exception
        raise exc.with_traceback(exc.__traceback__)
    if "CHECK-INTERNAL" in res.output:
        raise RuntimeError(f"CHECK-INTERNAL: {res.output[:300]}")
    return res.exit_code


@dataclass
class Outcome:
    ok: bool
    key: tuple[str, str] = ("", "")  # (kind, innermost project frame)
    detail: str = ""


class _CpuOut(BaseException):
    pass


def _innermost(tb: traceback.StackSummary) -> str:
    frames = [f for f in tb if str(ROOT) in f.filename and "/tests/" not in f.filename]
    f = frames[-1] if frames else (tb[-1] if tb else None)
    if f is None:
        return "?"
    return f"{os.path.relpath(f.filename, ROOT)}:{f.name}:{f.lineno}"


def check_one(mode: str, dialect: str, text: str) -> Outcome:
    """Run one case in this process (the worker calls it under its limits)."""
    from kernel.diagnostics import Diagnostic

    try:
        if mode == "cli":
            run_cli(dialect, text)
        else:
            run_reader(dialect, text)
    except Diagnostic as diag:
        # a lone CR ends a line too (old Mac files): splitlines counts it
        lines = max(text.count("\n"), len(text.splitlines())) + 2
        if not diag.code or diag.code != diag.code.upper():
            return Outcome(False, ("bad-code", diag.code), str(diag))
        # STEP-NC locations are instance numbers, canonical text ones its sequence numbers
        if dialect not in ("stepnc", "canon") and not 0 <= (diag.location.line or 0) <= lines:
            return Outcome(False, ("bad-line", diag.code), str(diag))
        return Outcome(True)
    except _CpuOut:
        return Outcome(False, ("cpu", "over the CPU limit"), "")
    except MemoryError:
        return Outcome(False, ("memory", "over the memory limit"), "")
    except RecursionError as exc:
        tb = traceback.extract_tb(exc.__traceback__)
        return Outcome(False, ("RecursionError", _innermost(tb)), "")
    except Exception as exc:  # noqa: BLE001 - every other exception is what we look for
        tb = traceback.extract_tb(exc.__traceback__)
        return Outcome(False, (type(exc).__name__, _innermost(tb)), f"{exc}"[:300])
    return Outcome(True)


def _run_case(mode: str, dialect: str, text: str, cpu: float) -> Outcome:
    """One case under the per-case CPU timer."""
    signal.setitimer(signal.ITIMER_PROF, cpu)
    try:
        return check_one(mode, dialect, text)
    except _CpuOut:
        return Outcome(False, ("cpu", "over the CPU limit"))
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


def _worker(conn: Connection, progress: ctypes.c_int64, cpu: float, memory: int) -> None:
    """Run jobs from ``conn`` under ``memory`` bytes of address space and ``cpu`` seconds
    of CPU per case (a SIGPROF timer). A job is one text (``("text", mode, dialect, text)``,
    answered with its :class:`Outcome`) or a batch of seeds (``("seeds", mode, dialect,
    start, stop)``) generated here: each failure is sent as it is found (``("fail", seed,
    outcome)``), then ``("done", count)``; ``progress`` holds the seed being run, so that
    the parent knows which case killed or hung the worker."""
    # on top of what the fresh interpreter already maps (libraries, numpy): the cases' own
    # growth is what is limited
    with open("/proc/self/statm") as fh:
        mapped = int(fh.read().split()[0]) * resource.getpagesize()
    resource.setrlimit(resource.RLIMIT_AS, (mapped + memory, mapped + memory))

    def expire(signum: int, frame: FrameType | None) -> None:
        raise _CpuOut

    signal.signal(signal.SIGPROF, expire)
    sys.setrecursionlimit(1000)
    while True:
        try:
            job = conn.recv()
        except EOFError:
            return
        if job is None:
            return
        if job[0] == "text":
            _, mode, dialect, text = job
            conn.send(_run_case(mode, dialect, text, cpu))
            continue
        _, mode, dialect, first, stop = job
        for seed in range(first, stop):
            progress.value = seed
            out = _run_case(mode, dialect, case(dialect, seed), cpu)
            if not out.ok:
                conn.send(("fail", seed, out))
        conn.send(("done", stop - first))


@dataclass
class Report:
    """Failures of a campaign keyed by (kind, innermost frame), each with its smallest case
    and the seeds that found it (``case(dialect, seed)`` gives the case back)."""

    cases: int = 0
    failures: Counter[tuple[str, str]] = field(default_factory=Counter)
    examples: dict[tuple[str, str], tuple[str, str, str]] = field(default_factory=dict)
    seeds: dict[tuple[str, str], list[int]] = field(default_factory=dict)

    def add(
        self, key: tuple[str, str], dialect: str, text: str, detail: str, seed: int | None = None
    ) -> None:
        self.failures[key] += 1
        if key not in self.examples or len(text) < len(self.examples[key][1]):
            self.examples[key] = (dialect, text, detail)
        if seed is not None:
            self.seeds.setdefault(key, []).append(seed)

    def summary(self) -> str:
        lines = [f"{self.cases} cases, {sum(self.failures.values())} failures"]
        for key, n in self.failures.most_common():
            d, text, detail = self.examples[key]
            lines.append(f"  {n:6d}  {key[0]:16s} {key[1]}  [{d}] {detail[:120]!r}")
            seeds = self.seeds.get(key, [])
            if seeds:
                more = f" (+{len(seeds) - 10})" if len(seeds) > 10 else ""
                lines.append(f"          seeds: {', '.join(map(str, seeds[:10]))}{more}")
            lines.append(f"          smallest case: {text[:300]!r}")
        return "\n".join(lines)


#: seeds a worker runs per job (the pipe is crossed twice a batch, not twice a case)
BATCH = 500
#: cases after which a worker is replaced by a fresh one: the CLI's caches keep about 20 KB
#: a case, which the 1 GB limit would otherwise meet after some 40,000 cases
RECYCLE = 20_000
#: a worker that makes no progress for this long (wall clock) is blocked. CPU time, not wall
#: time, decides a hang: under ``nice -n 19`` on a loaded machine a case of 1 s of CPU can
#: take minutes of wall time
HANG_SECONDS = 900.0


def cpu_seconds(pid: int) -> float:
    """User plus system CPU seconds process ``pid`` has used (Linux /proc; 0 elsewhere)."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            fields = fh.read().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


#: the failure of a worker that died under a case (killed, out of memory in native code)
DEAD = ("dead", "worker killed or out of memory")


class Pool:
    """One worker process under the limits; restarted when a case kills or hangs it."""

    def __init__(self, cpu: float = CPU_SECONDS, memory: int = MEMORY_BYTES) -> None:
        self.cpu, self.memory = cpu, memory
        # a fresh interpreter, not a fork: a fork of a test runner's thread inherits its
        # mappings and its (small) stack
        self.ctx = mp.get_context("spawn")
        self.progress = self.ctx.RawValue(ctypes.c_int64, -1)
        self._start()

    def _start(self) -> None:
        self.ran = 0  # cases the worker has run
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(
            target=_worker, args=(child, self.progress, self.cpu, self.memory)
        )
        self.proc.daemon = True
        self.proc.start()
        child.close()

    def _stuck(self, since: float, cpu0: float) -> tuple[str, str] | None:
        """Why the worker, on the same case since wall time ``since`` and its CPU time
        ``cpu0``, is hung, if it is: over 1.5 times the CPU limit (stuck in native code,
        a regular expression or a huge integer, where the timer cannot stop it), or no
        progress for :data:`HANG_SECONDS` (blocked)."""
        if cpu_seconds(self.proc.pid or 0) - cpu0 > 1.5 * self.cpu + 2.0:
            return ("hang", "over the CPU limit where the timer cannot stop it")
        if time.monotonic() - since > max(HANG_SECONDS, 6 * self.cpu):
            return ("hang", "no progress (blocked)")
        return None

    def run(self, mode: str, dialect: str, text: str) -> Outcome:
        """One given text."""
        self.conn.send(("text", mode, dialect, text))
        since, cpu0 = time.monotonic(), cpu_seconds(self.proc.pid or 0)
        key = DEAD
        while True:
            if self.conn.poll(1.0):
                try:
                    out: Outcome = self.conn.recv()
                    return out
                except (EOFError, OSError):
                    break
            if not self.proc.is_alive():
                break
            stuck = self._stuck(since, cpu0)
            if stuck is not None:
                key = stuck
                break
        self.restart()
        return Outcome(False, key)

    def run_seeds(self, mode: str, dialect: str, first: int, stop: int, report: Report) -> int:
        """Cases ``first .. stop`` of ``dialect`` generated and run in the worker, their
        failures added to ``report``; returns the seed to go on from (``stop``, or the seed
        after one that killed or hung the worker, which is then restarted)."""
        self.progress.value = first - 1
        self.conn.send(("seeds", mode, dialect, first, stop))
        pid = self.proc.pid or 0
        seen, since, cpu0 = self.progress.value, time.monotonic(), cpu_seconds(pid)
        key = DEAD
        while True:
            if self.conn.poll(1.0):
                try:
                    msg = self.conn.recv()
                except (EOFError, OSError):
                    break
                if msg[0] == "done":
                    report.cases += msg[1]
                    self.ran += msg[1]
                    if self.ran >= RECYCLE:
                        self.restart()
                    return stop
                _, seed, out = msg
                report.add(out.key, dialect, case(dialect, seed), out.detail, seed)
                continue
            if not self.proc.is_alive():
                break
            if self.progress.value != seen:
                seen, since, cpu0 = self.progress.value, time.monotonic(), cpu_seconds(pid)
            else:
                stuck = self._stuck(since, cpu0)
                if stuck is not None:
                    key = stuck
                    break
        bad = max(self.progress.value, first)
        self.restart()
        report.cases += bad + 1 - first
        report.add(key, dialect, case(dialect, bad), "", bad)
        return bad + 1

    def restart(self) -> None:
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join()
        self._start()

    def close(self) -> None:
        with contextlib.suppress(BrokenPipeError, OSError):
            self.conn.send(None)
        self.proc.join(5)
        if self.proc.is_alive():
            self.proc.kill()


def campaign(
    dialect: str, count: int, mode: str = "reader", start: int = 0, pool: Pool | None = None
) -> Report:
    """Run cases ``start .. start+count`` of ``dialect`` (generated in the worker, in
    batches) and sort the failures."""
    own = pool is None
    pool = pool or Pool()
    report = Report()
    try:
        seed, stop = start, start + count
        while seed < stop:
            seed = pool.run_seeds(mode, dialect, seed, min(stop, seed + BATCH), report)
    finally:
        if own:
            pool.close()
    return report


def cases(dialect: str, count: int, start: int = 0) -> Iterator[str]:
    for seed in range(start, start + count):
        yield case(dialect, seed)


def main(argv: list[str]) -> int:
    dialect, count = argv[0], int(argv[1])
    mode = argv[2] if len(argv) > 2 else "reader"
    start = int(argv[3]) if len(argv) > 3 else 0
    report = campaign(dialect, count, mode, start)
    print(report.summary())
    return 1 if report.failures else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

__all__ = ["DIALECTS", "Pool", "Report", "campaign", "case", "check_one"]
