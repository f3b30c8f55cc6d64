"""Streaming access to program files for the interpreter, with the seeks O-words need.

Programs are read line by line (a million-line file is never held in memory); loops and
subroutine calls jump back by byte offset, as LinuxCNC does. Parsed blocks are cached by
(file, offset) with a bounded size so loop bodies are parsed once.
"""

from __future__ import annotations

import os
import re
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from gcode.lexer import Block, parse_line
from kernel.diagnostics import Diagnostic, Location

_CACHE_SIZE = 4096
_OWORD_LINE_RE = re.compile(rb"^\s*/?\s*(?:[nN]\s*[\d.]+\s*)?[oO]")


@dataclass(frozen=True, slots=True)
class Position:
    """A place in a program: which file, the byte offset of a line start, its number."""

    file: str
    offset: int
    line: int


class ProgramFile:
    """One open program file with line numbers and seekable offsets."""

    def __init__(self, path: str) -> None:
        self.path = path
        try:
            self._fh: BinaryIO = open(path, "rb")  # noqa: SIM115 - closed by close()
        except OSError as exc:
            raise Diagnostic(
                "IO-OPEN", f"cannot open program: {exc.strerror or exc}", Location(path)
            ) from None
        self.line = 0
        self._cache: OrderedDict[int, Block] = OrderedDict()

    def close(self) -> None:
        self._fh.close()

    def tell(self) -> Position:
        return Position(self.path, self._fh.tell(), self.line)

    def seek(self, pos: Position) -> None:
        self._fh.seek(pos.offset)
        self.line = pos.line

    def next_raw(self) -> tuple[int, bytes] | None:
        """The next raw line with its offset, or None at end of file."""
        offset = self._fh.tell()
        data = self._fh.readline()
        if not data:
            return None
        self.line += 1
        return offset, data

    def next_block(self) -> Block | None:
        raw = self.next_raw()
        if raw is None:
            return None
        offset, data = raw
        cached = self._cache.get(offset)
        if cached is not None:
            return cached
        block = parse_line(_decode(data, self.path, self.line), self.line, self.path)
        if len(self._cache) >= _CACHE_SIZE:
            self._cache.popitem(last=False)
        self._cache[offset] = block
        return block

    def next_oword_block(self) -> Block | None:
        """Skip forward to the next line holding an O-word (used when skipping bodies)."""
        while True:
            raw = self.next_raw()
            if raw is None:
                return None
            offset, data = raw
            if _OWORD_LINE_RE.match(data):
                block = parse_line(_decode(data, self.path, self.line), self.line, self.path)
                if block.oword is not None:
                    return block


def _decode(data: bytes, path: str, line: int) -> str:
    try:
        return data.decode("utf-8").rstrip("\r\n")
    except UnicodeDecodeError:
        return data.decode("latin-1").rstrip("\r\n")


def find_subroutine_file(name: str, search_path: list[str], current_dir: str) -> str | None:
    """``o<name> call`` of a subroutine not defined in the program: ``name.ngc`` on the path."""
    for d in [*search_path, current_dir]:
        for candidate in (f"{name}.ngc", f"{name}.NGC"):
            p = os.path.join(d, candidate)
            if os.path.isfile(p):
                return str(Path(p))
    return None
