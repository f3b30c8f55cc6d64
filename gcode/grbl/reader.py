"""Reader of Grbl 1.1 programs: the RS274/NGC interpreter within Grbl's vocabulary and limits.

Grbl's supported list (gnea/grbl README, "List of Supported G-Codes in Grbl v1.1"):
non-modal G4, G10 L2, G10 L20, G28, G30, G28.1, G30.1, G53, G92, G92.1; motion G0, G1, G2,
G3, G38.2-G38.5, G80; G93, G94; G20, G21; G90, G91; G91.1; G17-G19; G43.1, G49; G40;
G54-G59; G61; M0, M1, M2, M30; M7, M8, M9; M3, M4, M5; words F I J K L N P R S T X Y Z.
Everything else is refused with ``GRBL-UNSUPPORTED`` at its column: other G and M codes
(canned cycles, G41/G42, G43 H, M6, ...), A/B/C and the other letters, O-words,
``#`` parameters and ``[...]`` expressions. A line holds at most 79 characters once
blanks and comments are removed (Grbl's ``LINE_BUFFER_SIZE`` 80 with its terminator,
protocol.c): ``GRBL-LINE-LENGTH``.

Program frame: Grbl streams lines and has no program end, so a program needs neither M2
nor ``%`` (a ``%`` line is accepted as a delimiter, as senders strip it).
``$`` lines are Grbl system commands, not G-code: queries and settings (``$$``, ``$#``,
``$G``, ``$I``, ``$N``, ``$X``, ``$<n>=<value>``) do not move the machine and are skipped;
``$H`` (homing), ``$J=`` (jogging), ``$C`` (check mode), ``$SLP``, ``$RST=`` and startup
lines ``$N<n>=`` change what runs or move by the machine's switches, and are refused
(``GRBL-SYSTEM``).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import replace

from gcode.core.codes import Words
from gcode.core.lexer import Block
from gcode.core.subset_reader import (
    Vocabulary,
    code_of,
    constant_word,
    read_chunks,
    read_path,
    read_text,
)
from gcode.ngc.interpreter import InterpreterOptions
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

G_CODES = frozenset(
    {0, 10, 20, 30, 40, 100, 170, 180, 190, 200, 210, 280, 281, 300, 301}
    | {382, 383, 384, 385, 400, 431, 490, 530, 540, 550, 560, 570, 580, 590}
    | {610, 800, 900, 910, 911, 920, 921, 930, 940}
)
M_CODES = frozenset({0, 10, 20, 300, 30, 40, 50, 70, 80, 90})
LETTERS = frozenset("fijklnprstxyzgm")
#: characters of a line Grbl keeps (LINE_BUFFER_SIZE 80 minus the terminator)
MAX_LINE = 79
#: ``$`` system commands that neither move nor change what runs: help, settings, parameters,
#: parser state, build info, startup lines (listing), alarm unlock; and ``$<n>=<value>``
_QUERIES = frozenset({b"", b"$", b"#", b"G", b"I", b"N", b"X"})
_SETTING = re.compile(rb"[0-9]+=[-+0-9.]*")
_NOT_BLANK = re.compile(r"\([^)]*\)?|;.*|[\s/]")
_LONG = re.compile(rb"[^\n]{80,}")


class Grbl(Vocabulary):
    prefix = "GRBL"
    title = "Grbl 1.1"
    lenient_end = frozenset({"NGC-NO-END", "NGC-NO-PERCENT"})

    def raw_line(self, data: bytes, file: str, line: int) -> bytes:
        stripped = data.lstrip()
        if not stripped.startswith(b"$"):
            return data
        body = stripped[1:].strip().upper()
        if body in _QUERIES or _SETTING.fullmatch(body):
            return b"\n"  # a query or a setting: no motion, no IR
        what = "$" + body.split(b"=")[0].decode("latin-1")
        raise Diagnostic(
            "GRBL-SYSTEM",
            f"system command {what} is not part of a program (homing, jogging, check mode, "
            "sleep, reset and startup lines are the operator's)",
            Location(file, line, len(data) - len(stripped) + 1),
        )

    def options(self, options: InterpreterOptions) -> InterpreterOptions:
        """Grbl refuses no arc for its small radius (gcode.c, the G2/G3 checks: the end
        radius must agree with the start's, to 0.005 mm or 0.1 %; motion_control.c
        ``mc_arc`` makes an arc of radius below half ``$12`` one line), and it stops before
        it stores offsets, G10 L2/L20 and G28.1/G30.1 (gcode.c step 19 calls settings.c
        ``settings_write_coord_data``, which empties the planner buffer first): marked
        for the planner (``OFFSETS_STORED``)."""
        return replace(options, arc_min_radius=0.0, store_marks=True)

    def check(self, block: Block, file: str) -> None:
        text, line = block.text, block.line
        if len(_NOT_BLANK.sub("", text)) > MAX_LINE:
            raise Diagnostic(
                "GRBL-LINE-LENGTH",
                f"line longer than Grbl's {MAX_LINE} characters (blanks and comments aside)",
                Location(file, line, 1),
            )
        if block.oword is not None:
            raise self.refuse("O-words (subroutines and flow control)", file, line, block.col0)
        if block.assignments:
            raise self.refuse("parameters (#)", file, line, block.assignments[0][2])
        cached = block.cached_words
        if isinstance(cached, Words) and cached.plain:  # a plain line, read at lexing
            for letter in cached.values:
                if letter not in LETTERS:
                    col = text.lower().find(letter) + 1
                    raise self.refuse(f"{letter.upper()} axis", file, line, col)
            return
        for w in block.words:
            if w.letter not in LETTERS:
                raise self.refuse(f"{w.letter.upper()} word", file, line, w.column)
            if type(w.value) is not float:
                raise self.refuse("parameters or expressions", file, line, w.column)
            if w.letter == "g":
                self.check_g(block, code_of(w), w.column, file)
            elif w.letter == "m" and code_of(w) not in M_CODES:
                raise self.refuse(f"M{w.value:g}", file, line, w.column)

    def check_g(self, block: Block, code: int | None, column: int, file: str) -> None:
        if code not in G_CODES:
            name = f"G{code / 10:g}" if code is not None else "G code"
            raise self.refuse(name, file, block.line, column)
        if code == 100 and constant_word(block, "l") not in (2.0, 20.0):
            raise self.refuse("G10 other than G10 L2 and G10 L20", file, block.line, column)

    def check_plain(self, data: bytes, file: str, first_line: int) -> None:
        # the first rotary letter, found by bytes.find (a regex search of the class is slower)
        hits = [at for letter in b"AaBbCc" if (at := data.find(letter)) >= 0]
        if hits:
            at = min(hits)
            start = data.rfind(b"\n", 0, at) + 1
            line = first_line + data.count(b"\n", 0, at)
            letter = chr(data[at]).upper()
            raise self.refuse(f"{letter} axis", file, line, at - start + 1)
        if _longest_line(data) < 80:
            return  # no line _LONG matches (its scan costs more than finding the line ends)
        for long in _LONG.finditer(data):
            if len(long.group().split()) and len(b"".join(long.group().split())) > MAX_LINE:
                line = first_line + data.count(b"\n", 0, long.start())
                raise Diagnostic(
                    "GRBL-LINE-LENGTH",
                    f"line longer than Grbl's {MAX_LINE} characters (blanks and comments aside)",
                    Location(file, line, 1),
                )


def _longest_line(data: bytes) -> int:
    """The length of the longest line of ``data`` (line ends aside), from the offsets of its
    line ends found by numpy in one pass (imported here: only the fast lane, which has
    loaded it, checks its runs' bytes this way)."""
    import numpy as np

    ends = np.flatnonzero(np.frombuffer(data, dtype=np.uint8) == ord("\n"))
    if not len(ends):
        return len(data)
    gaps = np.diff(ends)
    inner = int(gaps.max()) - 1 if len(gaps) else 0
    return max(int(ends[0]), inner, len(data) - int(ends[-1]) - 1)


GRBL = Grbl()


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the Grbl program at ``path`` (streaming)."""
    return read_path(path, GRBL, options)


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret`, with the fast lane's runs of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays; ``arcs``: runs may hold arcs."""
    return read_chunks(path, GRBL, options, arcs)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a Grbl program given as text."""
    return read_text(text, name, GRBL, options)
