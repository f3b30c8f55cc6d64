"""Program memory: the O-number programs of a file and where their blocks are.

A Fanuc program file holds one or more programs between ``%`` marks, each opened by
``O<number>`` (Fanuc 0i-MF manual, "Program configuration"); the main program is the
first one (a file may also start without an O line). Blocks are parsed lazily, once per
line, and kept for lines run more than once (loops, subprograms). Subprograms not in the
file are looked up on the search path as ``O<n>``, ``O<n>.nc``, ``<n>.nc`` (and the same
with four/five digits).
"""

from __future__ import annotations

import bisect
import re
from array import array
from collections.abc import Iterator
from dataclasses import dataclass, field
from itertools import accumulate, repeat
from operator import add

import kernel.limits as limits
from gcode.core.search import find_in_dirs, search_dirs
from gcode.fanuc.lexer import FBlock, parse_line
from kernel.diagnostics import Diagnostic, Location

#: an O line (``:`` is the ISO program number address, read as O); a byte order mark may
#: open the file
_O_RE = re.compile(r"^\ufeff?[ \t]*/?[ \t]*[Oo:][ \t]*(\d+)", re.MULTILINE | re.ASCII)
_O_BYTES_RE = re.compile(rb"^(?:\xef\xbb\xbf)?[ \t]*/?[ \t]*[Oo:][ \t]*(\d+)", re.MULTILINE)
_N_RE = re.compile(r"[ \t]*/?[ \t]*[Nn][ \t]*(\d+)", re.ASCII)


class Lines:
    """The lines of a file held as its bytes and an array of line starts: a line is
    decoded when it is read (a 200,000-line program is one bytes object, not 200,000
    strings)."""

    def __init__(self, path: str, data: bytes) -> None:
        self.path = path
        self.data = data
        # the start of each line: 0, then one past each newline (the pieces' lengths plus
        # their newlines, summed in C)
        pieces = map(len, data.split(b"\n"))
        starts = array("q", accumulate(map(add, pieces, repeat(1)), initial=0))
        starts.pop()  # one past the end of the last line
        self.starts = starts

    def __len__(self) -> int:
        return len(self.starts)

    def __iter__(self) -> Iterator[str]:
        """The lines in order (as indexing them one by one would give)."""
        return (self[i] for i in range(len(self.starts)))

    def __getitem__(self, index: int) -> str:
        starts = self.starts
        begin = starts[index]
        end = starts[index + 1] - 1 if index + 1 < len(starts) else len(self.data)
        raw = self.data[begin:end]
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            where = Location(self.path, index + 1, exc.start + 1)
            raise Diagnostic("FANUC-ENCODING", f"not UTF-8 text: {exc.reason}", where) from None

    def line_of(self, offset: int) -> int:
        return bisect.bisect_right(self.starts, offset) - 1


def _o_lines(data: bytes) -> Iterator[re.Match[bytes]]:
    """The O lines of ``data`` in order, as ``_O_BYTES_RE.finditer`` finds them (a match
    starts a line and ends in it): the pattern is tried only at the start of the lines
    holding an ``O``, ``o`` or ``:``, when those bytes are rare (a CAM program's few O
    lines and comments); else the pattern scans the whole file."""
    letters = (b"O", b"o", b":")
    if sum(map(data.count, letters)) * 64 > len(data):
        yield from _O_BYTES_RE.finditer(data)
        return
    starts: set[int] = set()
    for letter in letters:
        pos = data.find(letter)
        while pos >= 0:
            starts.add(data.rfind(b"\n", 0, pos) + 1)
            pos = data.find(letter, pos + 1)
    for start in sorted(starts):
        m = _O_BYTES_RE.match(data, start)
        if m is not None:
            yield m


@dataclass
class Source:
    """One file's text: its lines and the programs it holds."""

    path: str
    lines: Lines
    #: O number -> index of its O line
    programs: dict[int, int] = field(default_factory=dict)
    #: (O line index) -> {sequence number: line index}
    sequences: dict[int, dict[int, int]] = field(default_factory=dict)
    cache: dict[int, FBlock] = field(default_factory=dict)

    @classmethod
    def from_bytes(cls, path: str, data: bytes) -> Source:
        src = cls(path, Lines(path, data))
        digits = limits.current().digits
        for m in _o_lines(data):
            index = src.lines.line_of(m.start())
            if len(m.group(1)) > digits:
                limits.check_digits(src.lines[index], path, index + 1)
            src.programs.setdefault(int(m.group(1)), index)
        return src

    @classmethod
    def from_text(cls, path: str, text: str) -> Source:
        return cls.from_bytes(path, text.encode("utf-8"))

    def block(self, index: int, keep: bool) -> FBlock:
        """The parsed block of line ``index`` (0-based)."""
        blk = self.cache.get(index)
        if blk is None:
            blk = parse_line(self.lines[index], index + 1, self.path)
            if keep:
                self.cache[index] = blk
        return blk

    def main_program_line(self) -> int:
        """Index of the main program's O line when the file opens with one, else -1."""
        for i, raw in enumerate(self.lines):
            text = raw.strip()
            if not text or text.startswith("%") or text.startswith("("):
                continue
            return i if _O_RE.match(raw) else -1
        return -1

    def find_sequence(self, start: int, number: int) -> int | None:
        """Line index of ``N<number>`` in the program whose O line is ``start``."""
        table = self.sequences.get(start)
        if table is None:
            table = {}
            first = start + 1 if start >= 0 else 0
            for i in range(first, len(self.lines)):
                raw = self.lines[i]
                if _O_RE.match(raw) or (i > 0 and raw.lstrip().startswith("%")):
                    break
                m = _N_RE.match(raw)
                if m is not None:
                    limits.check_digits(raw, self.path, i + 1)
                    table.setdefault(int(m.group(1)), i)
            self.sequences[start] = table
        return table.get(number)


def read_source(path: str) -> Source:
    with open(path, "rb") as fh:
        return Source.from_bytes(path, fh.read())


def find_program_file(number: int, search_path: tuple[str, ...], here: str) -> str | None:
    """A file holding program O<number> in one of the search directories (beside ``here``
    when there is none), never outside them (:func:`gcode.core.search.find_in_dirs`)."""
    names = []
    for digits in (f"{number}", f"{number:04d}", f"{number:05d}"):
        for stem in (f"O{digits}", f"o{digits}", digits):
            names += [stem, stem + ".nc", stem + ".NC", stem + ".txt"]
    return find_in_dirs(search_dirs(search_path, here), names)
