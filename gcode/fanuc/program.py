"""Program memory: the O-number programs of a file and where their blocks are.

A Fanuc program file holds one or more programs between ``%`` marks, each opened by
``O<number>`` (Fanuc 0i-MF manual, "Program configuration"); the main program is the
first one (a file may also start without an O line). Blocks are parsed lazily, once per
line, and kept for lines run more than once (loops, subprograms). Subprograms not in the
file are looked up on the search path as ``O<n>``, ``O<n>.nc``, ``<n>.nc`` (and the same
with four/five digits).
"""

from __future__ import annotations

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
    strings). The starts are found when first asked for, or handed in (:meth:`index`)
    by a fast lane that finds them faster in compiled code."""

    def __init__(self, path: str, data: bytes) -> None:
        self.path = path
        self.data = data
        self._count = data.count(b"\n") + 1
        self._starts: array[int] | None = None

    @property
    def starts(self) -> array[int]:
        """The offset where each line starts: 0, then one past each newline."""
        if self._starts is None:
            # the pieces' lengths plus their newlines, summed in C
            pieces = map(len, self.data.split(b"\n"))
            starts = array("q", accumulate(map(add, pieces, repeat(1)), initial=0))
            starts.pop()  # one past the end of the last line
            self._starts = starts
        return self._starts

    @property
    def indexed(self) -> bool:
        """The line starts are known."""
        return self._starts is not None

    def index(self, starts: array[int]) -> None:
        """Take ``starts`` as the line starts (:attr:`starts`' very values, found by the
        caller)."""
        if len(starts) != self._count:
            raise ValueError("line starts of another text")
        self._starts = starts

    def __len__(self) -> int:
        return self._count

    def __iter__(self) -> Iterator[str]:
        """The lines in order (as indexing them one by one would give), found as they are
        read: an early stop reads no further."""
        data = self.data
        begin = 0
        for index in range(self._count):
            end = data.find(b"\n", begin)
            yield self._decode(data[begin : len(data) if end < 0 else end], index)
            begin = end + 1

    def __getitem__(self, index: int) -> str:
        starts = self.starts
        begin = starts[index]
        end = starts[index + 1] - 1 if index + 1 < len(starts) else len(self.data)
        return self._decode(self.data[begin:end], index)

    def _decode(self, raw: bytes, index: int) -> str:
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            where = Location(self.path, index + 1, exc.start + 1)
            raise Diagnostic("FANUC-ENCODING", f"not UTF-8 text: {exc.reason}", where) from None


def _o_lines(data: bytes) -> Iterator[re.Match[bytes]]:
    """The O lines of ``data`` in order, as ``_O_BYTES_RE.finditer`` finds them (a match
    starts a line and ends in it): the pattern is tried only at the start of the lines
    holding an ``O``, ``o`` or ``:``, when those lines are rare (a CAM program's few O
    lines and comments: each found by ``bytes.find``); else the pattern scans the whole
    file."""
    most = len(data) // 64
    found = 0
    starts: set[int] = set()
    for letter in (b"O", b"o", b":"):
        pos = data.find(letter)
        while pos >= 0:
            found += 1
            if found > most:
                yield from _O_BYTES_RE.finditer(data)
                return
            starts.add(data.rfind(b"\n", 0, pos) + 1)
            end = data.find(b"\n", pos)  # the line's other such letters add nothing
            pos = -1 if end < 0 else data.find(letter, end + 1)
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
        limits.check_lines(data, path)
        src = cls(path, Lines(path, data))
        digits = limits.current().digits
        index = at = 0  # the line of offset ``at``: the newlines before it
        for m in _o_lines(data):
            index += data.count(b"\n", at, m.start())
            at = m.start()
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
