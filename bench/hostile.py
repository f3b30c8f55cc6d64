"""Held-out hostile inputs campaign (issue 19): hand-made hostile programs, profiles, tool
tables and file names, run through the real ``cnc`` command as a user would.

tests/fuzzing.py mutates the corpus and generates grammar programs and runs them in a
worker through the readers and ``cnc check``; this campaign is the other half: every
command (``canon``, ``check``, ``plan`` with the three controller models, ``trace``,
``run``, ``sim``, ``convert --to`` each dialect, ``stepnc ...``), every input language, and
inputs no generator makes (huge values in each word, recursion through files, loops of
every kind, enormous moves and arcs of many turns, tiny pecks and tools, hostile machine
profiles, FIFOs, directories, /dev/zero, 100 MB lines, symlinked and ``..`` names).

Each run is one ``cnc`` process under ``nice -n 19``, 1 GB of address space
(``RLIMIT_AS``) and 20 s of wall time. A run fails when it prints a traceback, is killed,
passes the time, peaks over 1 GB, exits 0 on a clearly invalid input, exits non-zero
without a located, coded diagnostic (``file:line:col: error[CODE]``), or leaves a file
outside what it was told to write. Failures are sorted by kind, exception type and
innermost frame. ``python -m bench.hostile [--only SUBSTRING] [--jobs N] [--big]``
(``--big`` adds the 100 MB single-line files).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WALL_SECONDS = 20.0
MEMORY_BYTES = 1 << 30
LCNC_PROFILE = ROOT / "tests" / "data" / "lcnc_tp" / "machine.toml"
GRBL_PROFILE = ROOT / "tests" / "data" / "grbl_sim" / "machine.toml"
STEPNC = ROOT / "tests" / "stepnc"
TARGETS = (
    "rs274ngc", "nist_v3", "fanuc", "fanuc_lathe", "grbl", "haas", "haas_lathe",
    "siemens840d", "mach3", "sandia",
)  # fmt: skip
NGC_FAMILY = ("rs274ngc", "nist_v3", "mach3", "grbl")
FANUC_FAMILY = ("fanuc", "haas", "fanuc_lathe", "haas_lathe")
SUFFIX = {"siemens840d": ".mpf", "sandia": ".txt", "canon": ".canon", "stepnc": ".stp"}
SUFFIX |= {"ap238": ".stp", "fanuc": ".nc", "haas": ".nc", "fanuc_lathe": ".nc"}
SUFFIX |= {"haas_lathe": ".nc", "mach3": ".tap", "grbl": ".gcode"}
#: a located, coded diagnostic as the CLI prints it (cli/excerpt.py), or as a JSON report
LOCATED = re.compile(
    r"(?m)^.*?:(?:#\d+:)?\d+:\d+: (?:error|warning)\[[A-Z0-9][A-Z0-9/-]*\]"
    r"|\"code\": \"[A-Z0-9][A-Z0-9-]*\".*?\"line\": \d+"
)
#: a coded error not tied to a line (an I/O error naming its file, a usage error naming
#: the option): right for what is not a program's text
#: the file is named and the code says which key or option (a profile's MACH-*, SERVO-*)
CODED = re.compile(
    r"(?m)error\[(?:CNC001/)?(IO|MACH|SERVO|TOOL|LIMIT|CHECK-CONFIG|SIM-|STEPNC-PROJECT)"
    r"[A-Z0-9-]*\]|^Error: "
)


@dataclass
class Case:
    """One hostile input: its files (name to bytes; the program is ``prog<suffix>``),
    the dialect it is read as, which commands run it and whether it must be refused."""

    name: str
    dialect: str
    files: dict[str, bytes]
    invalid: bool | None = None  # None: invalid unless the case is a motion case
    commands: str = "read"  # read | motion | all | stepnc | profile
    program: str = ""  # the program's name when not prog<suffix> (a special path)
    extra: tuple[str, ...] = ()  # arguments added to each command
    setup: Callable[[Path], None] | None = None  # makes FIFOs, symlinks, directories

    def __post_init__(self) -> None:
        if self.invalid is None:
            self.invalid = self.commands not in ("motion", "stepnc", "profile", "outputs")

    @property
    def prog(self) -> str:
        return self.program or "prog" + SUFFIX.get(self.dialect, ".ngc")


@dataclass
class Result:
    case: str
    command: str
    kind: str  # ok, or the failure's kind
    where: str = ""
    rc: int = 0
    wall: float = 0.0
    cpu: float = 0.0
    rss_mb: float = 0.0
    excerpt: str = ""


# ----------------------------------------------------------------------------- programs

BIG = "9" * 99  # the largest number of digits the `digits` limit (100) lets through
OVER = "9" * 150  # over the digits limit
DEEP = 5_000


def _ngc(body: str) -> bytes:
    return f"G21 G90 G17 G94\nF100 S1000 M3\n{body}\nM2\n".encode()


def _fanuc(body: str, lathe: bool = False) -> bytes:
    head = "G21 G18 G99" if lathe else "G21 G90 G17 G94"
    return f"%\nO1000\n{head}\nF100. S1000 M03\n{body}\nM30\n%\n".encode()


def _siemens(body: str) -> bytes:
    return f"G710 G90 G17 G94\nF100 S1000 M3\n{body}\nM30\n".encode()


def _sandia(body: str) -> bytes:
    return f"SetUnits linear=mm angular=deg\nSetSpeed 100\n{body}\n".encode()


def _canon(body: list[str]) -> bytes:
    lines = ["USE_LENGTH_UNITS(CANON_UNITS_MM)", "SET_FEED_RATE(100.0000)", *body]
    return "".join(f"{i + 1:5d} N..... {c}\n" for i, c in enumerate(lines)).encode()


def ngc_cases(d: str) -> Iterator[Case]:
    """RS274/NGC and its subsets and Mach3: numbers, nesting, recursion, loops, motion."""
    lathe = ""
    yield Case("big-x", d, {"p": _ngc(f"G1 X{BIG} F100")}, commands="motion")
    yield Case("big-arc-centre", d, {"p": _ngc(f"G2 X0 Y0 I{BIG} J0")}, commands="motion")
    yield Case("over-digits-x", d, {"p": _ngc(f"G1 X{OVER}")})
    yield Case("over-digits-f", d, {"p": _ngc(f"G1 X1 F{OVER}")})
    yield Case("over-digits-g", d, {"p": _ngc(f"G{OVER} X1")})
    yield Case("over-digits-m", d, {"p": _ngc(f"M{OVER}")})
    yield Case("over-digits-n", d, {"p": _ngc(f"N{OVER} G1 X1")})
    yield Case("over-digits-param", d, {"p": _ngc(f"#{OVER}=1")})
    yield Case("big-param-number", d, {"p": _ngc("#99999999=1\nG1 X#99999999")})
    yield Case("over-digits-oword", d, {"p": _ngc(f"o{OVER} sub\no{OVER} endsub")})
    yield Case("decimal-200", d, {"p": _ngc("G1 X0." + "0" * 200 + "1")})
    yield Case("long-name-param", d, {"p": _ngc("#<" + "a" * 200_000 + ">=1")}, invalid=False)
    yield Case(
        "pow-overflow", d, {"p": _ngc("#1=[10**300]\n#2=[#1*#1]\nG1 X#2")}, commands="motion"
    )
    yield Case("exp-overflow", d, {"p": _ngc("G1 X[EXP[1000]]")}, commands="motion")
    yield Case("div-zero", d, {"p": _ngc("G1 X[1/0]")})
    yield Case("sqrt-neg", d, {"p": _ngc("G1 X[SQRT[-1]]")})
    yield Case("nan-param", d, {"p": _ngc("#1=[[10**300]*[10**300]-[10**300]*[10**300]]\nG1 X#1")})
    yield Case("deep-brackets", d, {"p": _ngc("G1 X" + "[" * DEEP + "1" + "]" * DEEP)})
    yield Case("deep-unary", d, {"p": _ngc("G1 X" + "-" * DEEP + "1")})
    yield Case("deep-funcs", d, {"p": _ngc("G1 X" + "ABS[" * DEEP + "1" + "]" * DEEP)})
    yield Case("long-chain", d, {"p": _ngc("G1 X[" + "1+" * 100_000 + "1]")})
    yield Case("deep-params", d, {"p": _ngc("#1=1\nG1 X" + "#" * DEEP + "1")})
    yield Case(
        "o-recursion", d, {"p": _ngc("o<r> sub\nG91 G1 X1\no<r> call\no<r> endsub\no<r> call")}
    )
    yield Case(
        "o-recursion-file",
        d,
        {"p": _ngc("o<r> call"), "r.ngc": b"o<r> sub\no<r> call\no<r> endsub\n"},
    )
    yield Case(
        "o-mutual-files",
        d,
        {"p": _ngc("o<a> call"), "a.ngc": b"o<a> sub\no<b> call\no<a> endsub\n",
         "b.ngc": b"o<b> sub\no<a> call\no<b> endsub\n"},
    )  # fmt: skip
    yield Case("while-moving", d, {"p": _ngc("G91\no1 while [1]\nG1 X1\no1 endwhile")})
    yield Case("while-still", d, {"p": _ngc("o1 while [1]\n#1=[#1+1]\no1 endwhile")})
    yield Case("repeat-huge", d, {"p": _ngc(f"G91\no1 repeat [{BIG}]\nG1 X0.001\no1 endrepeat")})
    yield Case("repeat-nested", d, {"p": _ngc(
        "G91\n" + "".join(f"o{i} repeat [1000]\n" for i in range(1, 9)) + "G1 X0.001\n"
        + "".join(f"o{i} endrepeat\n" for i in range(8, 0, -1)))})  # fmt: skip
    yield Case("sub-abs-name", d, {"p": _ngc("o</etc/passwd> call")})
    yield Case("sub-dotdot-name", d, {"p": _ngc("o<../outside/evil> call")})
    yield Case("sub-symlink-out", d, {"p": _ngc("o<evil> call")}, setup=_symlink_sub("evil.ngc"))
    yield Case("arc-turns-huge", d, {"p": _ngc(f"G2 X0 Y0 I10 J0 P{BIG}")}, commands="motion")
    yield Case(
        "arc-turns-1e6",
        d,
        {"p": _ngc("G2 X0 Y0 I10 J0 P1000000")},
        invalid=False,
        commands="motion",
    )
    yield Case("arc-r-zero", d, {"p": _ngc("G2 X10 Y0 R0")})
    yield Case("arc-r-tiny", d, {"p": _ngc("G2 X10 Y0 R0.000000001")})
    yield Case(
        "arc-units-mid",
        d,
        {"p": _ngc("G2 X10 Y0 I5 J0\nG20\nG3 X0 Y0 I-5 J0")},
        invalid=False,
        commands="motion",
    )
    yield Case(
        "move-1e9",
        d,
        {"p": _ngc("G0 X1000000000 Y-1000000000 Z1000000000")},
        invalid=False,
        commands="motion",
    )
    yield Case("helix-huge", d, {"p": _ngc(f"G2 X0 Y0 Z{BIG} I10 J0 P100")}, commands="motion")
    yield Case("feed-zero", d, {"p": _ngc("F0\nG1 X10")})
    yield Case("feed-negative", d, {"p": _ngc("G1 X10 F-100")})
    yield Case(
        "feed-tiny", d, {"p": _ngc("G1 X1000 F0.000000001")}, invalid=False, commands="motion"
    )
    yield Case("spindle-negative", d, {"p": _ngc("S-1000 M3\nG1 X1")})
    yield Case("dwell-huge", d, {"p": _ngc(f"G4 P{BIG}")}, commands="motion")
    yield Case("dwell-1e9", d, {"p": _ngc("G4 P1000000000")}, invalid=False, commands="motion")
    yield Case("dwell-negative", d, {"p": _ngc("G4 P-1")})
    yield Case(
        "peck-tiny", d, {"p": _ngc("G83 X0 Y0 Z-100 R1 Q0.0000001 F100\nG80")}, commands="motion"
    )
    yield Case(
        "cycle-l-huge", d, {"p": _ngc(f"G91 G81 X1 Y0 Z-1 R1 L{BIG}\nG80")}, commands="motion"
    )
    yield Case(
        "cycle-l-1e5",
        d,
        {"p": _ngc("G91 G81 X0.01 Y0 Z-1 R1 L99999\nG80")},
        invalid=False,
        commands="motion",
    )
    nurbs = "G5.2 X0 Y1 P1 L3\n" + "".join(f"X{i % 7} Y{(i * 3) % 11} P1\n" for i in range(150_000))
    yield Case("nurbs-150k", d, {"p": _ngc(nurbs + "G5.3")}, commands="motion")
    same = "G5.2 X0 Y0 P1 L3\n" + "X0 Y0 P1\n" * 50 + "G5.3"
    yield Case("nurbs-degenerate", d, {"p": _ngc(same)}, invalid=False, commands="motion")
    yield Case(
        "nurbs-zero-weight",
        d,
        {"p": _ngc("G5.2 X0 Y1 P0 L3\nX2 Y2 P0\nX2 Y0 P0\nG5.3")},
        invalid=False,
        commands="motion",
    )
    yield Case("nurbs-order-huge", d, {"p": _ngc(f"G5.2 X0 Y1 P1 L{BIG}\nX2 Y2 P1\nG5.3")})
    yield Case(
        "nurbs-units-mid", d, {"p": _ngc("G5.2 X0 Y1 P1 L3\nG20\nX2 Y2 P1\nG5.3")},
        commands="motion",
    )  # fmt: skip
    yield Case("spline-g5", d, {"p": _ngc(f"G5 X1 Y1 I{BIG} J0 P0 Q0")}, commands="motion")
    # accepted by design: with no tool table every tool number is a tool (rs274 refuses
    # one past its int as "Negative tool id")
    yield Case("tool-huge", d, {"p": _ngc(f"T{BIG} M6")}, invalid=False)
    yield Case(
        "tool-offset-huge",
        d,
        {"p": _ngc(f"G10 L1 P1 R{BIG} Z{BIG}\nT1 M6\nG43 H1\nG41 D1\nG1 X10 Y10\nG40")},
        commands="motion",
    )
    yield Case(
        "comp-radius-big",
        d,
        {"p": _ngc("G41.1 D1000\nG1 X10 Y0\nG1 X10 Y10\nG40")},
        commands="motion",
    )
    yield Case("g10-coords-huge", d, {"p": _ngc(f"G10 L2 P1 X{BIG}\nG54 G0 X0")}, commands="motion")
    yield Case("feed-inverse-zero", d, {"p": _ngc("G93 G1 X10 F0")}, commands="motion")
    yield Case("rpm-mode-zero", d, {"p": _ngc("G95 S0 M3\nG1 X10 F1")})
    yield Case(
        "lathe-cycle-tiny",
        d,
        {"p": _ngc("G7 G18\nG0 X20 Z1\nG76 P1 Z-1000 I-1 J0.0000001 K1 Q29")},
        commands="motion",
    )
    del lathe


def fanuc_cases(d: str) -> Iterator[Case]:
    """Fanuc and Haas, mill and lathe: macro B variables, loops, M98/G65 recursion."""
    lathe = "lathe" in d

    def f(body: str) -> dict[str, bytes]:
        return {"p": _fanuc(body, lathe)}

    yield Case("big-x", d, f(f"G01 X{BIG}."), commands="motion")
    yield Case("over-digits-x", d, f(f"G01 X{OVER}."))
    yield Case("over-digits-var", d, f(f"#{OVER}=1."))
    yield Case("big-var-number", d, f("#99999999=1."))
    yield Case("over-digits-o", d, {"p": f"%\nO{OVER}\nG0 X0\nM30\n%\n".encode()})
    yield Case("over-digits-n", d, f(f"N{OVER} G01 X1."))
    yield Case("over-digits-goto", d, f(f"GOTO{OVER}"))
    yield Case("goto-huge", d, f(f"GOTO{BIG}"))
    yield Case("deep-brackets", d, f("#1=" + "[" * DEEP + "1" + "]" * DEEP))
    yield Case("deep-indirect", d, f("#1=1\n#2=" + "#[" * DEEP + "1" + "]" * DEEP))
    yield Case("long-chain", d, f("#1=" + "1+" * 100_000 + "1"))
    yield Case(
        "var-overflow",
        d,
        f("#1=10.\nWHILE[#1 LT 1.E999]DO1\n#1=#1*#1\nEND1\nG01 X#1"),
        commands="motion",
    )
    yield Case(
        "var-square-chain", d, f("#1=1.E50\n#1=#1*#1*#1*#1*#1*#1*#1*#1\nG01 X#1"), commands="motion"
    )
    yield Case("while-moving", d, f("G91\nWHILE[1EQ1]DO1\nG01 X1.\nEND1"))
    yield Case("while-still", d, f("WHILE[1EQ1]DO1\n#1=#1+1\nEND1"))
    yield Case("goto-loop", d, f("N10 G91 G01 X1.\nGOTO10"))
    yield Case("goto-loop-still", d, f("N10 #1=#1+1\nGOTO10"))
    # M99 in a main program ends the reading (a production loop); cnc check says CNC010
    yield Case("m99-main", d, f("G91 G01 X1.\nM99"), invalid=False)
    yield Case("m98-self", d, {"p": b"%\nO1000\nG21 G91\nF100.\nG01 X1.\nM98 P1000\nM30\n%\n"})
    yield Case(
        "m98-file-recursion",
        d,
        {
            "p": _fanuc("M98 P2000", lathe),
            "O2000.nc": b"O2000\nG91 G01 X1. F100.\nM98 P2000\nM99\n",
        },
    )
    yield Case(
        "m98-repeat-huge",
        d,
        {
            "p": _fanuc(f"M98 P2000 L{BIG}", lathe),
            "O2000.nc": b"O2000\nG91 G01 X0.001 F100.\nM99\n",
        },
    )
    yield Case("m98-p-huge", d, f(f"M98 P{BIG}"))
    yield Case("g65-recursion", d, {"p": b"%\nO1000\nG21\nG65 P1000 A1.\nM30\n%\n"})
    yield Case(
        "g66-modal-recursion", d, {"p": b"%\nO1000\nG21 G91 F100.\nG66 P1000\nG01 X1.\nM30\n%\n"}
    )
    yield Case("m98-abs", d, f("M98 P/etc/passwd"))
    yield Case(
        "m98-symlink-out", d, {"p": _fanuc("M98 P3000", lathe)}, setup=_symlink_sub("O3000.nc")
    )
    yield Case("arc-huge-i", d, f(f"G02 X0 Y0 I{BIG}. J0"), commands="motion")
    yield Case("arc-r-zero", d, f("G02 X10. Y0 R0"))
    yield Case(
        "arc-units-mid",
        d,
        f("G02 X10. Y0 I5. J0\nG20\nG03 X0 Y0 I-5. J0"),
        invalid=False,
        commands="motion",
    )
    yield Case("feed-zero", d, f("F0\nG01 X10."))
    yield Case("feed-negative", d, f("G01 X10. F-100."))
    yield Case("spindle-negative", d, f("S-1000 M03\nG01 X1."))
    yield Case("dwell-huge", d, f(f"G04 X{BIG}."), commands="motion")
    yield Case("dwell-negative", d, f("G04 X-1."))
    yield Case("peck-tiny", d, f("G83 X0 Y0 Z-100. R1. Q0.0000001 F100.\nG80"), commands="motion")
    yield Case("cycle-k-huge", d, f(f"G91 G81 X1. Y0 Z-1. R1. K{BIG}\nG80"), commands="motion")
    yield Case(
        "nurbs-many",
        d,
        f(
            "G06.2 K0 X0 Y0 R1. P3\n"
            + "".join(f"K0 X{i % 7}. Y{i % 5}. R1.\n" for i in range(150_000))
            + "K1. \nK1. \nK1. \nG01 X0"
        ),
        commands="motion",
    )
    yield Case(
        "nurbs-degenerate",
        d,
        f(
            "G06.2 P4 K0 X0 Y0 R0\nK0 X0 Y0 R0\nK0 X0 Y0 R0\nK0 X0 Y0 R0\n"
            "K1.\nK1.\nK1.\nK1.\nG01 X1."
        ),
        commands="motion",
    )
    yield Case("rotation-huge", d, f(f"G68 X0 Y0 R{BIG}.\nG01 X10."), commands="motion")
    yield Case("scaling-zero", d, f("G51 X0 Y0 P0\nG01 X10."), commands="motion")
    yield Case("scaling-huge", d, f(f"G51 X0 Y0 P{BIG}\nG01 X10."), commands="motion")
    yield Case("polar-huge", d, f(f"G16\nG01 X{BIG}. Y{BIG}.\nG15"), commands="motion")
    yield Case("tool-huge", d, f(f"T{BIG} M06"), invalid=False)
    yield Case("h-huge", d, f(f"G43 H{BIG} Z1."), invalid=False)
    yield Case("alarm-var", d, f("#3000=1(BOOM)"))
    if lathe:
        yield Case(
            "g71-tiny-depth",
            d,
            f(
                "G00 X50. Z2.\nG71 U0.0000001 R0.5\nG71 P10 Q20 U0.2 W0.1 F0.2\n"
                "N10 G00 X20.\nG01 Z-30.\nN20 X50.\nG70 P10 Q20"
            ),
            commands="motion",
        )
        yield Case(
            "g73-repeat-huge",
            d,
            f(
                f"G00 X50. Z2.\nG73 U5. W0 R{BIG}\nG73 P10 Q20 U0.2 W0.1 F0.2\n"
                "N10 G00 X20.\nG01 Z-30.\nN20 X50."
            ),
            commands="motion",
        )
        yield Case("g70-missing-q", d, f("G70 P10 Q99999"))
        yield Case("g70-self", d, f("N10 G70 P10 Q10"))
        yield Case(
            "g76-tiny",
            d,
            f("G00 X30. Z5.\nG76 P010060 Q0.0000001 R0.01\nG76 X20. Z-1000. P1000 Q0.0000001 F1.5"),
            commands="motion",
        )
        yield Case(
            "g92-thread-huge", d, f(f"G00 X30. Z5.\nG92 X20. Z-{BIG}. F1.5"), commands="motion"
        )
        yield Case(
            "g74-peck-tiny", d, f("G00 X0 Z5.\nG74 R1.\nG74 Z-100. Q0.0001 F0.1"), commands="motion"
        )
        yield Case(
            "css-zero-x",
            d,
            f("G50 S999999\nG96 S200 M03\nG01 X0 Z-10. F0.1"),
            invalid=False,
            commands="motion",
        )


def siemens_cases(d: str) -> Iterator[Case]:
    """Siemens 840D: R parameters, arrays, CALL, REPEAT, labels, BSPLINE."""

    def s(body: str) -> dict[str, bytes]:
        return {"p": _siemens(body)}

    yield Case("big-x", d, s(f"G1 X={BIG}"), commands="motion")
    yield Case("over-digits-x", d, s(f"G1 X{OVER}"))
    yield Case("over-digits-r", d, s(f"R{OVER}=1"))
    yield Case("big-r-number", d, s("R99999999=1"))
    yield Case("r-value-over", d, s(f"R1={OVER}"))
    yield Case("array-huge", d, s("DEF REAL A[100000000]\nA[5]=1"))
    yield Case("array-3d-huge", d, s("DEF REAL A[10000,10000,10000]"))
    yield Case("array-index-huge", d, s(f"DEF REAL A[10]\nA[{BIG}]=1"))
    yield Case("array-neg", d, s("DEF REAL A[-5]"))
    yield Case("string-huge", d, s('DEF STRING[1000000000] S\nS="X"'))
    yield Case("deep-parens", d, s("R1=" + "(" * DEEP + "1" + ")" * DEEP))
    yield Case("long-chain", d, s("R1=" + "1+" * 100_000 + "1"))
    yield Case("deep-unary", d, s("R1=" + "-" * DEEP + "1"))
    yield Case("pow-overflow", d, s("R1=1E300*1E300\nG1 X=R1"), commands="motion")
    yield Case("loop-moving", d, s("G91\nLOOP\nG1 X1\nENDLOOP"))
    yield Case("while-still", d, s("WHILE 1\nR1=R1+1\nENDWHILE"))
    yield Case("gotob-loop", d, s("G91\nL1: G1 X1\nGOTOB L1"))
    yield Case("repeatb-huge", d, s(f"G91\nL1: G1 X0.001\nREPEATB L1 P={BIG}"))
    yield Case("repeat-self", d, s("G91\nL1: G1 X0.001\nREPEAT L1 P=1000000000"))
    yield Case(
        "repeat-nested",
        d,
        s(
            "G91\nA1: G1 X0.001\nREPEAT A1 P=10000\nB1: G1 Y0.001\n"
            "REPEAT A1 B1 P=10000\nREPEAT A1 B1 P=10000"
        ),
    )
    yield Case("for-huge", d, s(f"DEF INT I\nG91\nFOR I=1 TO {BIG}\nG1 X0.001\nENDFOR"))
    yield Case(
        "call-self", d, {"p": _siemens('CALL "SELF"'), "SELF.SPF": b'G91 G1 X1\nCALL "SELF"\nM17\n'}
    )
    yield Case("call-main-self", d, {"p": b"G91 G1 X1 F100\nPROG\nM30\n"}, program="PROG.MPF")
    yield Case(
        "l-repeat-huge", d, {"p": _siemens(f"L100 P{BIG}"), "L100.SPF": b"G91 G1 X0.001\nM17\n"}
    )
    yield Case("call-abs", d, s('CALL "/etc/passwd"'))
    yield Case("call-dotdot", d, s('CALL "../outside/evil"'))
    yield Case("call-symlink-out", d, s("EVIL"), setup=_symlink_sub("EVIL.SPF"))
    yield Case("arc-turn-huge", d, s(f"G2 X0 Y0 I10 J0 TURN={BIG}"), commands="motion")
    yield Case("arc-cr-zero", d, s("G2 X10 Y0 CR=0"))
    yield Case(
        "arc-units-mid",
        d,
        s("G2 X10 Y0 I5 J0\nG700\nG3 X0 Y0 I-5 J0"),
        invalid=False,
        commands="motion",
    )
    yield Case("feed-zero", d, s("F0\nG1 X10"))
    yield Case("feed-negative", d, s("G1 X10 F-100"))
    yield Case("dwell-huge", d, s(f"G4 F{BIG}"), commands="motion")
    bs = "BSPLINE SD=3\n" + "".join(f"X{i % 7} Y{i % 5} PW=1\n" for i in range(150_000)) + "G1 X0"
    yield Case("bspline-many", d, s(bs), commands="motion")
    yield Case(
        "bspline-degenerate",
        d,
        s("BSPLINE SD=3\nX0 Y0\nX0 Y0\nX0 Y0\nX0 Y0 PW=0\nG1 X1"),
        invalid=False,
        commands="motion",
    )
    yield Case("bspline-sd-huge", d, s(f"BSPLINE SD={BIG}\nX1 Y1\nX2 Y0\nG1 X0"))
    yield Case("peck-tiny", d, s("CYCLE83(10,0,1,-100,,,0.0000001,0,0,0,1,0)"), commands="motion")
    yield Case("trans-huge", d, s(f"TRANS X={BIG}\nG1 X1"), commands="motion")
    yield Case("rot-huge", d, s(f"ROT RPL={BIG}\nG1 X1"), commands="motion")
    yield Case("scale-zero", d, s("SCALE X=0 Y=0\nG1 X1 Y1"), commands="motion")
    yield Case(
        "case-goto-loop", d, s("L1: G91 G1 X1\nCASE R1 OF 0 GOTOB L1 DEFAULT GOTOF L2\nL2: G0 X0")
    )
    yield Case("label-huge", d, s("GOTOF " + "A" * 200_000))


def sandia_cases(d: str) -> Iterator[Case]:
    """The Sandia generic language: numbers and moves."""
    yield Case("big-x", d, {"p": _sandia(f"MoveTo X={BIG} Y=0 Z=0")}, commands="motion")
    yield Case("over-digits-x", d, {"p": _sandia(f"MoveTo X={OVER} Y=0 Z=0")})
    yield Case("speed-zero", d, {"p": _sandia("SetSpeed 0\nMoveTo X=1 Y=0 Z=0")})
    yield Case("speed-negative", d, {"p": _sandia("SetSpeed -5\nMoveTo X=1 Y=0 Z=0")})
    yield Case("speed-nan", d, {"p": _sandia("SetSpeed nan\nMoveTo X=1 Y=0 Z=0")})
    yield Case("x-inf", d, {"p": _sandia("MoveTo X=inf Y=0 Z=0")})
    yield Case("x-1e999", d, {"p": _sandia("MoveTo X=1e999 Y=0 Z=0")})
    yield Case("tool-huge", d, {"p": _sandia(f"GetTool {BIG}")}, invalid=False)
    yield Case("tool-length-nan", d, {"p": _sandia("GetTool 1\nSetToolLength nan")})
    yield Case(
        "attributes-huge", d, {"p": _sandia(f"point_to_point_positioning X=1 attributes={BIG}")}
    )
    yield Case(
        "units-mid",
        d,
        {"p": _sandia("MoveTo X=1 Y=0 Z=0\nSetUnits linear=inch angular=deg\nMoveTo X=1 Y=1 Z=0")},
        invalid=False,
        commands="motion",
    )
    yield Case("many-args", d, {"p": _sandia("MoveTo " + "X=1 " * 100_000)})


def canon_cases(d: str) -> Iterator[Case]:
    """Canonical text: values no reader makes."""
    yield Case(
        "feed-inf", d, {"p": _canon(["STRAIGHT_FEED(1e300, 0, 0, 0, 0, 0)"])}, commands="motion"
    )
    yield Case("feed-nan", d, {"p": _canon(["STRAIGHT_FEED(nan, 0, 0, 0, 0, 0)"])})
    yield Case(
        "rate-zero", d, {"p": _canon(["SET_FEED_RATE(0)", "STRAIGHT_FEED(10, 0, 0, 0, 0, 0)"])}
    )
    yield Case(
        "rate-negative", d, {"p": _canon(["SET_FEED_RATE(-5)", "STRAIGHT_FEED(10, 0, 0, 0, 0, 0)"])}
    )
    yield Case(
        "arc-turns-huge",
        d,
        {"p": _canon([f"ARC_FEED(0, 0, 10, 0, {BIG}, 0, 0, 0, 0)"])},
        commands="motion",
    )
    yield Case(
        "arc-turns-1e7",
        d,
        {"p": _canon(["ARC_FEED(0, 0, 10, 0, 10000000, 0, 0, 0, 0)"])},
        invalid=False,
        commands="motion",
    )
    yield Case(
        "arc-radius-huge",
        d,
        {"p": _canon(["ARC_FEED(0, 0, 1e90, 0, 1, 0, 0, 0, 0)"])},
        commands="motion",
    )
    yield Case("dwell-huge", d, {"p": _canon(["DWELL(1e300)"])}, commands="motion")
    yield Case(
        "dwell-1e9", d, {"p": _canon(["DWELL(1000000000)"])}, invalid=False, commands="motion"
    )
    yield Case("dwell-negative", d, {"p": _canon(["DWELL(-1)"])})
    yield Case("dwell-nan", d, {"p": _canon(["DWELL(nan)"])})
    yield Case(
        "nurbs-degenerate",
        d,
        {"p": _canon(["NURBS_FEED(3, 3, 0, 0, 1, 0, 0, 0, 0, 0, 0)"])},
        commands="motion",
    )
    yield Case("over-digits", d, {"p": _canon([f"STRAIGHT_FEED({OVER}, 0, 0, 0, 0, 0)"])})
    yield Case("many-args", d, {"p": _canon(["STRAIGHT_FEED(" + "1, " * 100_000 + "1)"])})
    yield Case("seq-huge", d, {"p": f"{OVER} N..... STRAIGHT_FEED(1, 0, 0, 0, 0, 0)\n".encode()})
    yield Case("tool-huge", d, {"p": _canon([f"CHANGE_TOOL({BIG})"])})
    yield Case(
        "units-mid-arcs",
        d,
        {
            "p": _canon(
                [
                    "ARC_FEED(10, 0, 5, 0, 1, 0, 0, 0, 0)",
                    "USE_LENGTH_UNITS(CANON_UNITS_INCHES)",
                    "ARC_FEED(0, 0, 5, 0, 1, 0, 0, 0, 0)",
                ]
            )
        },
        invalid=False,
        commands="motion",
    )
    yield Case(
        "spindle-nan", d, {"p": _canon(["SET_SPINDLE_SPEED(nan)", "START_SPINDLE_CLOCKWISE()"])}
    )
    yield Case("deep-parens", d, {"p": _canon(["STRAIGHT_FEED" + "(" * DEEP + "1" + ")" * DEEP])})


def _p21(data: list[str]) -> bytes:
    head = (
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\n"
        "FILE_NAME('','',(''),(''),'','','');\nFILE_SCHEMA(('MACHINING_SCHEMA'));\nENDSEC;\nDATA;\n"
    )
    return (head + "\n".join(data) + "\nENDSEC;\nEND-ISO-10303-21;\n").encode()


def _edit(name: str, old: str, new: str, count: int = 1) -> bytes:
    text = (STEPNC / name).read_text()
    if old not in text:
        raise SystemExit(f"campaign case out of date: {old!r} not in {name}")
    return text.replace(old, new, count).encode()


def stepnc_cases(d: str) -> Iterator[Case]:
    """ISO 14649 Part 21: ids, values, self-reference, cycles, tools, pockets, b-splines."""
    zig = "pocket_zigzag.stp"
    yield Case(
        "id-over-digits", d, {"p": _edit(zig, "#1=PROJECT", f"#{OVER}=PROJECT")}, commands="stepnc"
    )
    yield Case("id-big", d, {"p": _edit(zig, "#1=PROJECT", f"#{BIG}=PROJECT")}, commands="stepnc")
    yield Case(
        "ref-big",
        d,
        {
            "p": _edit(
                zig,
                "#1=PROJECT('POCKET ZIGZAG ENTRY',#2",
                f"#1=PROJECT('POCKET ZIGZAG ENTRY',#{BIG}",
            )
        },
        commands="stepnc",
    )
    yield Case(
        "value-over-digits",
        d,
        {"p": _edit(zig, "(50.0,40.0,0.0)", f"({OVER}.0,40.0,0.0)")},
        commands="stepnc",
    )
    yield Case(
        "value-1e999",
        d,
        {"p": _edit(zig, "(50.0,40.0,0.0)", "(1.0E999,40.0,0.0)")},
        commands="stepnc",
    )
    yield Case(
        "value-1e300",
        d,
        {"p": _edit(zig, "(50.0,40.0,0.0)", "(1.0E300,40.0,0.0)")},
        commands="stepnc",
    )
    yield Case(
        "self-ref-workplan",
        d,
        {"p": _edit(zig, "#2=WORKPLAN('MAIN',(#132)", "#2=WORKPLAN('MAIN',(#2)")},
        commands="stepnc",
    )
    yield Case(
        "self-ref-placement",
        d,
        {"p": _edit(zig, "#103=AXIS2_PLACEMENT_3D('',#100,", "#103=AXIS2_PLACEMENT_3D('',#103,")},
        commands="stepnc",
    )
    yield Case(
        "cycle-3",
        d,
        {
            "p": _edit(
                zig, "#104=PLANE('SECURITY PLANE',#103)", "#104=PLANE('SECURITY PLANE',#104)"
            ).replace(b"#4=SETUP('SETUP',$,#104", b"#4=SETUP('SETUP',$,#2")
        },
        commands="stepnc",
    )
    yield Case(
        "ws-cycle",
        d,
        {
            "p": _edit(
                zig,
                "#132=MACHINING_WORKINGSTEP('WS ROUGH',#104,#122,",
                "#132=MACHINING_WORKINGSTEP('WS ROUGH',#104,#132,",
            )
        },
        commands="stepnc",
    )
    yield Case(
        "deep-parens",
        d,
        {"p": _edit(zig, "(0.0,0.0,50.0)", "(" * DEEP + "0.0" + ")" * DEEP)},
        commands="stepnc",
    )
    yield Case(
        "tool-tiny",
        d,
        {"p": _edit(zig, "MILLING_TOOL_DIMENSION(10.0", "MILLING_TOOL_DIMENSION(0.0000001")},
        commands="stepnc",
    )
    yield Case(
        "tool-zero",
        d,
        {"p": _edit(zig, "MILLING_TOOL_DIMENSION(10.0", "MILLING_TOOL_DIMENSION(0.0")},
        commands="stepnc",
    )
    yield Case(
        "tool-negative",
        d,
        {"p": _edit(zig, "MILLING_TOOL_DIMENSION(10.0", "MILLING_TOOL_DIMENSION(-10.0")},
        commands="stepnc",
    )
    yield Case(
        "stepover-tiny",
        d,
        {"p": _edit(zig, "4.0,4.0,0.5,0.5);", "0.0000001,0.0000001,0.5,0.5);")},
        commands="stepnc",
    )
    yield Case(
        "depth-tiny",
        d,
        {"p": _edit(zig, "'POCKET OP',5.0", "'POCKET OP',0.0000001")},
        commands="stepnc",
    )
    yield Case(
        "pocket-huge",
        d,
        {"p": _edit(zig, "TOLERANCED_LENGTH_MEASURE(70.0", f"TOLERANCED_LENGTH_MEASURE({BIG}.0")},
        commands="stepnc",
    )
    yield Case(
        "feed-zero",
        d,
        {"p": _edit(zig, "MILLING_TECHNOLOGY(0.02", "MILLING_TECHNOLOGY(0.0")},
        commands="stepnc",
    )
    yield Case(
        "feed-negative",
        d,
        {"p": _edit(zig, "MILLING_TECHNOLOGY(0.02", "MILLING_TECHNOLOGY(-0.02")},
        commands="stepnc",
    )
    yield Case(
        "spindle-nan", d, {"p": _edit(zig, ".TCP.,$,-20.0", ".TCP.,$,1.0E999")}, commands="stepnc"
    )
    yield Case(
        "string-huge",
        d,
        {"p": _edit(zig, "'WS ROUGH'", "'" + "W" * 20_000_000 + "'")},
        commands="stepnc",
    )
    yield Case(
        "unterminated-string", d, {"p": _edit(zig, "'WS ROUGH'", "'WS ROUGH")}, commands="stepnc"
    )
    bsp = "explicit_bspline.stp"
    pts = ",".join(f"#{1000 + i}" for i in range(150_000))
    cps = "\n".join(
        f"#{1000 + i}=CARTESIAN_POINT('',({i % 7}.0,{i % 5}.0,0.0));" for i in range(150_000)
    )
    text = _edit(
        bsp,
        "(#105,#106,#107,#108),.UNSPECIFIED.,.F.,.F.,(4,4)",
        f"({pts}),.UNSPECIFIED.,.F.,.F.,(4,149992,4)",
    ).decode()
    text = text.replace("ENDSEC;\nEND-ISO", cps + "\nENDSEC;\nEND-ISO")
    yield Case("bspline-many", d, {"p": text.encode()}, commands="stepnc")
    yield Case(
        "bspline-degree-huge",
        d,
        {
            "p": _edit(
                bsp, "B_SPLINE_CURVE_WITH_KNOTS('',3,", f"B_SPLINE_CURVE_WITH_KNOTS('',{BIG},"
            )
        },
        commands="stepnc",
    )
    yield Case(
        "bspline-degree-zero",
        d,
        {"p": _edit(bsp, "B_SPLINE_CURVE_WITH_KNOTS('',3,", "B_SPLINE_CURVE_WITH_KNOTS('',0,")},
        commands="stepnc",
    )
    yield Case(
        "bspline-knots-bad",
        d,
        {"p": _edit(bsp, "(4,4),(0.0,1.0)", "(1000000000,4),(0.0,1.0)")},
        commands="stepnc",
    )
    yield Case(
        "bspline-knots-equal",
        d,
        {"p": _edit(bsp, "(4,4),(0.0,1.0)", "(4,4),(1.0,1.0)")},
        commands="stepnc",
    )
    yield Case(
        "bspline-one-point",
        d,
        {"p": _edit(bsp, "(#105,#106,#107,#108)", "(#105)")},
        commands="stepnc",
    )
    yield Case(
        "many-instances",
        d,
        {"p": _p21([f"#{i}=CARTESIAN_POINT('',(0.0,0.0,0.0));" for i in range(1, 300_001)])},
        commands="stepnc",
    )
    yield Case(
        "ref-chain",
        d,
        {
            "p": _p21(
                ["#1=PROJECT('P',#2,(),$,$,$);"]
                + [f"#{i}=WORKPLAN('W',(#{i + 1}),$,$,$);" for i in range(2, 20_000)]
                + ["#20000=WORKPLAN('W',(),$,$,$);"]
            )
        },
        commands="stepnc",
    )
    yield Case(
        "duplicate-ids",
        d,
        {
            "p": _p21(
                [
                    "#1=PROJECT('P',#2,(),$,$,$);",
                    "#2=WORKPLAN('W',(),$,$,$);",
                    "#2=WORKPLAN('W',(),$,$,$);",
                ]
            )
        },
        commands="stepnc",
    )
    yield Case(
        "multistep-tiny",
        d,
        {"p": _edit("multistep_drilling.stp", "1.0,5.0,4.0,0.2);", "1.0,5.0,0.0000001,0.2);")},
        commands="stepnc",
    )


def ap238_cases(d: str) -> Iterator[Case]:
    """AP238 conformance class 1: the same kinds of edits on an AIM file."""
    name = "ap238/cc1_two_tools.stp"
    yield Case(
        "feed-zero",
        d,
        {"p": _edit(name, "NUMERIC_MEASURE(500.)", "NUMERIC_MEASURE(0.)")},
        commands="stepnc",
    )
    yield Case(
        "feed-negative",
        d,
        {"p": _edit(name, "NUMERIC_MEASURE(500.)", "NUMERIC_MEASURE(-500.)")},
        commands="stepnc",
    )
    yield Case(
        "feed-1e999",
        d,
        {"p": _edit(name, "NUMERIC_MEASURE(500.)", "NUMERIC_MEASURE(1.E999)")},
        commands="stepnc",
    )
    yield Case(
        "unit-self",
        d,
        {
            "p": _edit(
                name,
                "#5=MEASURE_WITH_UNIT(TIME_MEASURE(60.),#2)",
                "#5=MEASURE_WITH_UNIT(TIME_MEASURE(60.),#5)",
            )
        },
        commands="stepnc",
    )
    yield Case(
        "unit-cycle",
        d,
        {
            "p": _edit(
                name,
                "#4=(CONVERSION_BASED_UNIT('minute',#5)",
                "#4=(CONVERSION_BASED_UNIT('minute',#4)",
            )
        },
        commands="stepnc",
    )
    yield Case(
        "time-zero",
        d,
        {"p": _edit(name, "TIME_MEASURE(60.)", "TIME_MEASURE(0.)")},
        commands="stepnc",
    )
    yield Case(
        "seq-cycle",
        d,
        {
            "p": _edit(
                name,
                "#33=MACHINING_PROCESS_SEQUENCE_RELATIONSHIP('',$,#30,#31,1.)",
                "#33=MACHINING_PROCESS_SEQUENCE_RELATIONSHIP('',$,#30,#30,1.)",
            )
        },
        commands="stepnc",
    )
    yield Case(
        "id-over-digits",
        d,
        {"p": _edit(name, "#30=MACHINING_WORKPLAN", f"#{OVER}=MACHINING_WORKPLAN")},
        commands="stepnc",
    )
    yield Case(
        "value-over-digits",
        d,
        {"p": _edit(name, "NUMERIC_MEASURE(500.)", f"NUMERIC_MEASURE({OVER}.)")},
        commands="stepnc",
    )


def file_cases() -> Iterator[Case]:
    """What is given as a program: empty, binary, odd line ends, non-files."""
    for d in ("rs274ngc", "fanuc", "siemens840d", "sandia", "canon", "stepnc"):
        yield Case("empty", d, {"p": b""}, invalid=False)
        yield Case("nul-bytes", d, {"p": b"G1 X1\x00\x00 Y2 F100\nM2\n"})
        yield Case("all-nul", d, {"p": b"\x00" * 100_000})
        yield Case("cr-only", d, {"p": b"G21 G90\rG1 X1 F100\rG1 Y1\rM2\r"}, invalid=False)
        yield Case("utf16", d, {"p": "G1 X1 F100\nM2\n".encode("utf-16")})
        yield Case("latin1", d, {"p": b"(caf\xe9)\nG1 X1 F100\nM2\n"}, invalid=False)
        yield Case("fullwidth-digits", d, {"p": "G1 X\uff11\uff10 F100\nM2\n".encode()})
        yield Case("arabic-digits", d, {"p": "G1 X\u0661\u0660 F100\nM2\n".encode()})
        yield Case("nbsp-zwsp", d, {"p": "G1\u00a0X1\u200bY2 F100\nM2\n".encode()})
        yield Case("bom", d, {"p": "\ufeffG21\nG1 X1 F100\nM2\n".encode()}, invalid=False)
        yield Case("rtl-override", d, {"p": "G1 X1\u202e2 F100\nM2\n".encode()})
        yield Case("binary", d, {"p": bytes(range(256)) * 400})
        yield Case("directory", d, {}, program="adir", setup=lambda t: (t / "adir").mkdir())
        yield Case("fifo", d, {}, program="afifo", setup=lambda t: os.mkfifo(t / "afifo"))
        yield Case("dev-zero", d, {}, program="/dev/zero")
        yield Case("dev-null", d, {}, program="/dev/null", invalid=False)
        yield Case("missing", d, {}, program="nothing-here.ngc")
        yield Case("symlink-loop", d, {}, program="loop.ngc", setup=_symlink_loop)
        yield Case("unreadable", d, {"p": b"G1 X1\nM2\n"}, setup=_unreadable)


def big_cases() -> Iterator[Case]:
    """100 MB on one line (with --big)."""
    line = b"G1 X1 Y2 F100 " * (100 * 1024 * 1024 // 14)
    comment = b"(" + b"a" * (100 * 1024 * 1024) + b")\nM2\n"
    for d in ("rs274ngc", "fanuc", "siemens840d", "sandia", "canon", "grbl", "mach3"):
        yield Case("100mb-line", d, {"p": line + b"\nM2\n"})
        yield Case("100mb-comment", d, {"p": comment}, invalid=False)
    yield Case(
        "100mb-line",
        "stepnc",
        {"p": _p21(["#1=CARTESIAN_POINT('',(" + "0.0," * (25 * 1024 * 1024) + "0.0));"])},
        commands="stepnc",
    )
    yield Case("100mb-digits", "rs274ngc", {"p": b"G1 X" + b"1" * (100 * 1024 * 1024) + b"\nM2\n"})


def _symlink_sub(name: str) -> Callable[[Path], None]:
    def make(tmp: Path) -> None:
        (tmp.parent / "outside").mkdir(exist_ok=True)
        (tmp.parent / "outside" / name).write_text("o<evil> sub\nG1 X1\no<evil> endsub\nM99\n")
        (tmp / name).symlink_to(tmp.parent / "outside" / name)

    return make


def _symlink_loop(tmp: Path) -> None:
    (tmp / "loop.ngc").symlink_to(tmp / "loop2.ngc")
    (tmp / "loop2.ngc").symlink_to(tmp / "loop.ngc")


def _unreadable(tmp: Path) -> None:
    for p in tmp.iterdir():
        p.chmod(0)


# ------------------------------------------------------------------ profiles and tools

MOTION = _ngc("G0 X10 Y10\nG1 X20 Y20\nG2 X30 Y20 I5 J0\nG4 P0.5\nT1 M6\nG1 X0 Y0")


def profile_cases() -> Iterator[Case]:
    """Hostile machine profiles and tool tables with a sane program."""
    axes = "\n".join(f"[axes.{a}]\nvelocity = 100.0\nacceleration = 1000.0\n" for a in "xyz")
    bad = {
        "nan-velocity": "[axes.x]\nvelocity = nan\n",
        "inf-velocity": "[axes.x]\nvelocity = inf\n",
        "zero-accel": "[axes.x]\nacceleration = 0.0\n",
        "negative-accel": "[axes.y]\nacceleration = -1000.0\n",
        "nan-limits": "[axes.x]\nmin = nan\nmax = nan\n",
        "min-over-max": "[axes.x]\nmin = 100.0\nmax = -100.0\n",
        "zero-jerk-scurve": '[axes.x]\njerk = 0.0\n[controller]\naccdec = "scurve"\n',
        "negative-period": "[controller]\ninterpolation_period = -0.001\n",
        "zero-period": "[controller]\ninterpolation_period = 0.0\n",
        "tiny-period": "[controller]\ninterpolation_period = 1e-12\n",
        "huge-period": "[controller]\ninterpolation_period = 1e300\n",
        "nan-period": "[controller]\ninterpolation_period = nan\n",
        "lookahead-zero": "[controller]\nlookahead = 0\n",
        "lookahead-huge": "[controller]\nlookahead = 9223372036854775807\n",
        "lookahead-negative": "[controller]\nlookahead = -5\n",
        "bad-model": '[controller]\nmodel = "../../etc/passwd"\n',
        "junction-nan": '[controller]\nmodel = "grbl"\njunction_deviation = nan\n',
        "junction-negative": '[controller]\nmodel = "grbl"\njunction_deviation = -1.0\n',
        "arc-tol-zero": '[controller]\nmodel = "grbl"\narc_tolerance = 0.0\n',
        "lcnc-tiny-period": '[controller]\nmodel = "linuxcnc"\ninterpolation_period = 1e-9\n',
        "servo-kp-nan": "[servo]\nkp = nan\n",
        "servo-kp-negative": "[servo]\nkp = -30.0\n",
        "servo-period-zero": "[servo]\nperiod = 0.0\n",
        "servo-settle-huge": "[servo]\nsettle = 1e12\n",
        "tool-change-nan": "[controller]\ntool_change_time = nan\n",
        "tool-change-huge": "[controller]\ntool_change_time = 1e300\n",
        "feed-override-zero": "[controller]\nfeed_override = 0.0\n",
        "chord-zero": "[controller]\nchord_tolerance = 0.0\n",
        "limits-digits-huge": "[limits]\ndigits = 100000000\n",
        "limits-negative": "[limits]\nloop_passes = -1\n",
        "limits-nan": "[limits]\nsamples_per_move = nan\n",
        "accdec-bad": '[accdec]\nkind = "fir"\ntime = -1.0\n',
        "accdec-huge": '[accdec]\nkind = "moving_average"\ntime = 1e9\n',
        "spindle-nan": "[spindle]\nmax_speed = nan\n",
        "not-toml": "this is = = not toml [[[\n",
        "wrong-types": '[axes]\nx = "fast"\n',
        "deep-tables": "[" + ".".join(["a"] * 5000) + "]\n",
        "kind-bad": 'kind = "submarine"\n',
    }
    for name, text in bad.items():
        body = text if "axes." in text else axes + text
        yield Case(
            f"profile-{name}",
            "rs274ngc",
            {"p": MOTION, "m.toml": body.encode()},
            commands="profile",
            extra=("-m", "m.toml"),
        )
    big_tools = "".join(f"T{i} P{i} Z1.0 D0.5\n" for i in range(1, 200_001))
    tables = {
        "tbl-huge": big_tools,
        "tbl-nan": "T1 P1 Z nan D nan\n",
        "tbl-inf": "T1 P1 Z1e999 D1e999\n",
        "tbl-negative": "T1 P1 Z-10 D-5\n",
        "tbl-over-digits": f"T{OVER} P1 Z1 D1\n",
        "tbl-pocket-huge": f"T1 P{BIG} Z1 D1\n",
        "tbl-binary": "\x00\xff\xfe" * 1000,
        "tbl-duplicate": "T1 P1 Z1 D1\nT1 P2 Z2 D2\n",
    }
    # a negative length offset or diameter is a LinuxCNC table's to give (not refused)
    for name, text in tables.items():
        yield Case(
            f"tools-{name}",
            "rs274ngc",
            {"p": MOTION, "t.tbl": text.encode("latin-1")},
            commands="profile",
            extra=("-t", "t.tbl"),
            invalid=name not in ("tbl-huge", "tbl-duplicate", "tbl-negative"),
        )
    yield Case(
        "tools-fifo",
        "rs274ngc",
        {"p": MOTION},
        commands="profile",
        extra=("-t", "tf"),
        setup=lambda t: os.mkfifo(t / "tf"),
    )
    yield Case("tools-dir", "rs274ngc", {"p": MOTION}, commands="profile", extra=("-t", "."))
    yield Case(
        "profile-dev-zero", "rs274ngc", {"p": MOTION}, commands="profile", extra=("-m", "/dev/zero")
    )
    yield Case(
        "profile-fifo",
        "rs274ngc",
        {"p": MOTION},
        commands="profile",
        extra=("-m", "mf"),
        setup=lambda t: os.mkfifo(t / "mf"),
    )


# ---------------------------------------------------------------------------- commands


def commands_for(case: Case, tmp: Path) -> list[tuple[str, list[str], list[str]]]:
    """(label, argv after ``cnc``, outputs the run may write) of each command run on
    ``case``: every command for motion cases, reading ones for the rest."""
    p, d, x = case.prog, case.dialect, list(case.extra)
    stock = "bar:25,-80,1" if "lathe" in d else "box:-50,-50,-20,50,50,0"
    dl = [] if d in ("canon", "stepnc", "ap238") else ["-d", d]
    runs: list[tuple[str, list[str], list[str]]] = [
        ("canon", ["canon", *dl, *x, p], []),
        ("check", ["check", *dl, *x, "-f", "json", p], []),
    ]
    if case.commands == "stepnc":
        runs = [
            ("stepnc-canon", ["stepnc", "canon", p], []),
            ("stepnc-check", ["stepnc", "check", p], []),
            ("stepnc-info", ["stepnc", "info", p], []),
            ("stepnc-to-gcode", ["stepnc", "to-gcode", p, "-o", "out.ngc"], ["out.ngc"]),
            ("canon", ["canon", p], []),
            ("plan", ["plan", p], []),
            ("convert-fanuc", ["convert", p, "--to", "fanuc", "-o", "out.nc"], ["out.nc"]),
        ]
        if not case.name.startswith(("many-", "100mb", "string-huge", "ref-chain")):
            runs.append(("stepnc-gouge", ["stepnc", "gouge", p, "--raw", "0,0,-45,100,120,5"], []))
        return runs
    if case.commands in ("motion", "profile", "all"):
        runs += [
            ("plan-book", ["plan", *dl, *x, p], []),
            ("plan-linuxcnc", ["plan", *dl, "-m", str(LCNC_PROFILE), p], []),
            ("plan-grbl", ["plan", *dl, "-m", str(GRBL_PROFILE), p], []),
            ("trace", ["trace", *dl, *x, p, "-o", "tr"], ["tr"]),
            ("run", ["run", *dl, *x, p, "-o", "rn"], ["rn"]),
            (
                "sim",
                ["sim", *dl, *x, p, "--stock", stock, "--resolution", "2"],
                [],
            ),
        ]
        if case.commands == "profile":
            runs = [r for r in runs if r[0] not in ("plan-linuxcnc", "plan-grbl")]
            runs.append(("plan-compare", ["plan", *x, "--compare", "book,linuxcnc,grbl", p], []))
    targets = TARGETS if case.commands in ("motion", "all") else ("rs274ngc",)
    if case.commands != "profile":
        for t in targets:
            out = f"out.{t}"
            runs.append((f"convert-{t}", ["convert", *dl, p, "--to", t, "-o", out], [out]))
    return runs


def output_cases() -> Iterator[Case]:
    """Outputs named through ``..``, absolute names and symlinks: only what was named
    is written, never through a link (the checks are in :func:`run_output_case`)."""
    yield Case("outputs", "rs274ngc", {"p": MOTION}, invalid=False, commands="outputs")


def run_output_case(tmp: Path, cnc: list[str]) -> list[Result]:
    """Each command asked to write through a symlink, into ``..`` and onto its input."""
    results = []
    outside = tmp.parent / "outside"
    outside.mkdir(exist_ok=True)
    victim = outside / "victim.txt"
    victim.write_text("keep me\n")
    (tmp / "link.ngc").symlink_to(victim)
    (tmp / "linkdir").symlink_to(outside)
    cases = [
        ("canon-o-symlink", ["canon", "prog.ngc", "-o", "link.ngc"], "refuse"),
        ("canon-o-symlink-force", ["canon", "prog.ngc", "-o", "link.ngc", "--force"], "replace"),
        ("canon-o-input", ["canon", "prog.ngc", "-o", "prog.ngc", "--force"], "refuse"),
        (
            "convert-o-input",
            ["convert", "prog.ngc", "--to", "rs274ngc", "-o", "prog.ngc", "--force"],
            "refuse",
        ),
        ("convert-o-symlink", ["convert", "prog.ngc", "--to", "fanuc", "-o", "link.ngc"], "refuse"),
        ("trace-o-symlink-dir", ["trace", "prog.ngc", "-o", "linkdir", "--force"], "any"),
        ("run-o-symlink-dir", ["run", "prog.ngc", "-o", "linkdir", "--force"], "any"),
        ("canon-o-dev-full", ["canon", "prog.ngc", "-o", "/dev/full", "--force"], "any"),
        ("check-o-symlink", ["check", "prog.ngc", "-o", "link.ngc", "-f", "json"], "refuse"),
        (
            "stepnc-o-symlink",
            ["stepnc", "to-gcode", str(STEPNC / "pocket_zigzag.stp"), "-o", "link.ngc"],
            "refuse",
        ),
    ]
    for label, argv, want in cases:
        res = run(cnc + argv, tmp)
        kind, where = classify(res, invalid=want == "refuse")
        if victim.read_text() != "keep me\n":
            kind, where = "write-outside", f"{victim} changed"
            victim.write_text("keep me\n")
        if want == "refuse" and res.rc == 0:
            kind, where = "accepted", "wrote through a link or onto the input"
        results.append(
            Result(
                "outputs",
                label,
                kind,
                where,
                res.rc,
                res.wall,
                res.cpu,
                res.rss_mb,
                res.stderr[-300:],
            )
        )
    return results


# ------------------------------------------------------------------------------ running


@dataclass
class Run:
    rc: int
    wall: float
    cpu: float
    rss_mb: float
    stdout: str
    stderr: str
    timed_out: bool = False


def _limits() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_BYTES, MEMORY_BYTES))
    os.setsid()


def run(argv: list[str], cwd: Path) -> Run:
    """One ``cnc`` process in ``cwd`` under the limits; its exit, times and peak RSS."""
    out, err, peak = cwd / ".stdout", cwd / ".stderr", cwd / ".peak"
    with open(out, "wb") as fo, open(err, "wb") as fe:
        start = time.monotonic()
        # the peak RSS from /usr/bin/time, which starts the command itself: a child forked
        # from this (large) process would count this process' pages in its ru_maxrss
        proc = subprocess.Popen(
            ["nice", "-n", "19", "/usr/bin/time", "-f", "%M", "-o", str(peak), *argv],
            cwd=cwd, stdout=fo, stderr=fe, stdin=subprocess.DEVNULL, preexec_fn=_limits,
        )  # fmt: skip
        timed_out = False
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - start > WALL_SECONDS:
                timed_out = True
                os.killpg(proc.pid, signal.SIGKILL)
                pid, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.05)
        proc.returncode = os.waitstatus_to_exitcode(status)
        wall = time.monotonic() - start
    text, etext = _ends(out), _ends(err)
    try:
        rss_kb = float(peak.read_text().split()[-1])
    except (OSError, ValueError, IndexError):  # killed before time wrote it
        rss_kb = usage.ru_maxrss
    for f in (out, err, peak):
        f.unlink(missing_ok=True)
    return Run(
        proc.returncode, wall, usage.ru_utime + usage.ru_stime, rss_kb / 1024,
        text, etext, timed_out,
    )  # fmt: skip


def _ends(path: Path) -> str:
    """The first and last 2 MB of an output (a message may quote a huge line)."""
    data = path.read_bytes()
    if len(data) > 4_000_000:
        data = data[:2_000_000] + b"\n...\n" + data[-2_000_000:]
    return data.decode("utf-8", "replace")


_FRAME = re.compile(r'File "([^"]+)", line (\d+), in (\S+)')


def classify(res: Run, invalid: bool) -> tuple[str, str]:
    """(kind, where) of one run: ``ok`` or the failure."""
    both = res.stderr + res.stdout
    if res.timed_out:
        # under nice -n 19 on a loaded machine the wall clock says little: a run stopped
        # with less than half its wall time in CPU is rerun alone (--rerun)
        if res.cpu < WALL_SECONDS / 2:
            return "slow-under-load", f"over {WALL_SECONDS:g} s wall, CPU {res.cpu:.1f} s"
        return "hang", f"over {WALL_SECONDS:g} s (CPU {res.cpu:.1f} s)"
    if "Traceback (most recent call last)" in both:
        frames = [
            f"{os.path.relpath(f, ROOT)}:{fn}:{ln}"
            for f, ln, fn in _FRAME.findall(both)
            if str(ROOT) in f
        ]
        last = [ln for ln in both.splitlines() if ln and not ln.startswith(" ")]
        exc = last[-1].split(":")[0] if last else "?"
        return f"traceback {exc}", frames[-1] if frames else "?"
    if res.rc < 0 or res.rc > 2 and res.rc != 141:
        return "killed", f"exit {res.rc}"
    if res.rss_mb > MEMORY_BYTES / 2**20:
        return "memory", f"{res.rss_mb:.0f} MB"
    if "MemoryError" in both:
        return "memory", "MemoryError"
    if "CHECK-INTERNAL" in both or "INTERNAL" in both:
        m = re.search(r"[A-Z]+-INTERNAL[^\n]{0,200}", both)
        return "internal", m.group(0) if m else "INTERNAL"
    if res.stdout.lstrip().startswith("{") and '"cnc-check-report"' in res.stdout:
        return _classify_check(res, invalid)
    if res.rc == 0:
        if invalid and not LOCATED.search(both):
            return "accepted", "exit 0 on an invalid input"
        return "ok", ""
    if LOCATED.search(both) or CODED.search(both):
        return "ok", ""
    return "unlocated", (res.stderr.strip().splitlines() or ["(no message)"])[-1][:200]


def _classify_check(res: Run, invalid: bool) -> tuple[str, str]:
    """``cnc check -f json``: each error finding has a code and a line; an I/O error a
    code; a program that is invalid has an error finding."""
    try:
        report = json.loads(res.stdout)
    except ValueError:
        return "bad-report", "cnc check -f json printed no JSON"
    errors = []
    for f in report.get("files", []):
        if f.get("io_error"):
            errors.append(("io", f["io_error"]))
        if f.get("status") not in ("clean", "findings", "io-error", None):
            return "check-status", str(f.get("status"))
        for x in f.get("findings", []):
            if x.get("severity") != "error":
                continue
            if not x.get("code") and not x.get("rule") or not x.get("line"):
                return "unlocated", f"{x.get('code') or x.get('rule')}: {x.get('message')}"[:200]
            errors.append((x.get("code"), x.get("line")))
    if res.rc == 0 and invalid and not errors:
        return "accepted", "exit 0 on an invalid input"
    if res.rc != 0 and not errors:
        return "unlocated", "exit non-zero with no error finding"
    return "ok", ""


def _snapshot(root: Path) -> set[str]:
    return {
        os.path.relpath(os.path.join(dp, f), root) for dp, dn, fn in os.walk(root) for f in fn + dn
    }


def run_case(case: Case, cnc: list[str], keep: Path, only: tuple[str, ...] = ()) -> list[Result]:
    """Every command of ``case`` in a fresh directory; what each left outside its outputs."""
    base = Path(tempfile.mkdtemp(prefix="hostile-", dir=keep))
    tmp = base / "work"
    tmp.mkdir()
    try:
        for name, data in case.files.items():
            (tmp / (case.prog if name == "p" else name)).write_bytes(data)
        if case.setup is not None:
            case.setup(tmp)
        if case.commands == "outputs":
            return run_output_case(tmp, cnc)
        results = []
        for label, argv, outputs in commands_for(case, tmp):
            if only and not label.startswith(only):
                continue
            before = _snapshot(base)
            res = run(cnc + argv, tmp)
            kind, where = classify(res, bool(case.invalid))
            new = _snapshot(base) - before
            stray = sorted(
                n for n in new
                if not any(n == f"work/{o}" or n.startswith(f"work/{o}/") for o in outputs)
                and not n.startswith(("work/.std", "work/.peak"))
            )  # fmt: skip
            if stray and kind == "ok":
                kind, where = "write-outside", ", ".join(stray[:5])
            for o in outputs:  # outputs are cleared between commands
                path = tmp / o
                if path.is_dir() and not path.is_symlink():
                    shutil.rmtree(path)
                elif path.exists() or path.is_symlink():
                    path.unlink()
            results.append(
                Result(
                    f"{case.dialect}/{case.name}",
                    label,
                    kind,
                    where,
                    res.rc,
                    res.wall,
                    res.cpu,
                    res.rss_mb,
                    (res.stderr or res.stdout)[-400:],
                )  # fmt: skip
            )
        return results
    finally:
        for p in base.rglob("*"):
            if not p.is_symlink():
                p.chmod(0o700)
        shutil.rmtree(base, ignore_errors=True)


def all_cases(big: bool) -> list[Case]:
    out: list[Case] = []
    for d in NGC_FAMILY:
        out += ngc_cases(d)
    for d in FANUC_FAMILY:
        out += fanuc_cases(d)
    out += siemens_cases("siemens840d")
    out += sandia_cases("sandia")
    out += canon_cases("canon")
    out += stepnc_cases("stepnc")
    out += ap238_cases("ap238")
    out += file_cases()
    out += profile_cases()
    out += output_cases()
    if big:
        out += big_cases()
    for c in out:
        if c.commands == "stepnc" and c.name in STEPNC_INVALID:
            c.invalid = True
    return out


#: STEP-NC and AP238 cases no reader may accept
STEPNC_INVALID = {
    "id-over-digits", "value-over-digits", "value-1e999", "self-ref-workplan",
    "self-ref-placement", "cycle-3", "ws-cycle", "deep-parens", "tool-zero", "tool-negative",
    "feed-negative", "unterminated-string", "bspline-degree-huge", "bspline-degree-zero",
    "bspline-knots-bad", "bspline-one-point", "duplicate-ids", "spindle-nan", "seq-cycle",
    "feed-1e999", "ref-big",
}  # fmt: skip
# the AP238 reader knows its units by name: a unit's own measure that refers to itself, or
# a minute of 0 s, is not read (not refused)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--only",
        default="",
        help="run the cases whose dialect/name contains one of these (comma list)",
    )
    ap.add_argument(
        "--commands", default="", help="comma list of command label prefixes run (default all)"
    )
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--big", action="store_true", help="add the 100 MB single-line files")
    ap.add_argument("--log", type=Path, help="append one line per run to this file")
    args = ap.parse_args(argv)
    cnc = [shutil.which("cnc") or "cnc"]
    env_root = str(ROOT)
    os.environ["PYTHONPATH"] = env_root + os.pathsep + os.environ.get("PYTHONPATH", "")
    wanted = args.only.split(",")
    cases = [c for c in all_cases(args.big) if any(w in f"{c.dialect}/{c.name}" for w in wanted)]
    keep = Path(tempfile.mkdtemp(prefix="cnc-hostile-"))
    lock = threading.Lock()
    only = tuple(c for c in args.commands.split(",") if c)
    results: list[Result] = []
    log = open(args.log, "a") if args.log else None  # noqa: SIM115 - closed below

    def one(case: Case) -> None:
        res = run_case(case, cnc, keep, only)
        with lock:
            results.extend(res)
            for r in res:
                line = (
                    f"{r.kind:22s} {r.case:40s} {r.command:18s} rc={r.rc} wall={r.wall:5.1f}"
                    f" cpu={r.cpu:5.1f} rss={r.rss_mb:5.0f}MB {r.where}"
                )
                if log:
                    log.write(line + "\n")
                    if r.kind != "ok":
                        log.write("    " + r.excerpt.replace("\n", "\n    ")[-400:] + "\n")
                    log.flush()

    with ThreadPoolExecutor(args.jobs) as pool:
        list(pool.map(one, cases))
    if log:
        log.close()
    shutil.rmtree(keep, ignore_errors=True)
    print(summary(results))
    return 1 if any(r.kind != "ok" for r in results) else 0


def summary(results: list[Result]) -> str:
    """Runs per dialect and command, then the failures by kind and innermost frame."""
    per: Counter[str] = Counter(r.case.split("/")[0] for r in results)
    cmds: Counter[str] = Counter(r.command for r in results)
    fails: Counter[tuple[str, str]] = Counter((r.kind, r.where) for r in results if r.kind != "ok")
    lines = [f"{len(results)} runs, {sum(fails.values())} failures"]
    lines.append("runs per input: " + ", ".join(f"{k} {v}" for k, v in sorted(per.items())))
    lines.append("runs per command: " + ", ".join(f"{k} {v}" for k, v in sorted(cmds.items())))
    worst = max(results, key=lambda r: r.rss_mb, default=None)
    slow = max(results, key=lambda r: r.wall, default=None)
    if worst and slow:
        lines.append(f"peak RSS {worst.rss_mb:.0f} MB ({worst.case} {worst.command}); "
                     f"longest {slow.wall:.1f} s ({slow.case} {slow.command})")  # fmt: skip
    for (kind, where), n in fails.most_common():
        ex = [f"{r.case} {r.command}" for r in results if (r.kind, r.where) == (kind, where)]
        lines.append(f"  {n:4d} {kind:22s} {where}\n       e.g. {', '.join(ex[:4])}")
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())
